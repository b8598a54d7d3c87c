//! `pneuma eval`: the evaluations of head motion ([`crate::eval_head`]) and breathing
//! ([`crate::eval_breaths`], [`crate::eval_breath_sounds`]).

use std::process::ExitCode;

/// Command-line arguments of `pneuma eval`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// What to evaluate.
    #[command(subcommand)]
    pub what: What,
}

/// The evaluations.
#[derive(Debug, clap::Subcommand)]
pub enum What {
    /// Head motion against real head motion (styletalk format data).
    Head(crate::eval_head::HeadArgs),
    /// Breathing of offline renders: empty lung during speech, breath durations and levels.
    Breaths(crate::eval_breaths::BreathArgs),
    /// Inserted breaths against real ones labelled by hand: spectrum, level, duration, and the
    /// engine's detection of the real ones.
    BreathSounds(crate::eval_breath_sounds::BreathSoundArgs),
}

/// Runs `pneuma eval`.
pub fn main(args: Args) -> ExitCode {
    match args.what {
        What::Breaths(b) => crate::eval_breaths::main(&b),
        What::BreathSounds(b) => crate::eval_breath_sounds::main(&b),
        What::Head(h) => exit_code(
            crate::eval_head::run(&h).map(|all| all || !h.check),
            "a head-motion",
        ),
    }
}

/// The exit code of an evaluation: success when `result` is `Ok(true)`; otherwise the error,
/// or "`what` target was missed", on stderr.
pub fn exit_code(result: Result<bool, String>, what: &str) -> ExitCode {
    match result {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => {
            eprintln!("error: {what} target was missed (see above)");
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
