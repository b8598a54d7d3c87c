//! # pneuma-eval
//!
//! Pneuma's evaluations against data, each in a module of its own: head motion against real
//! motion ([`head`]), the breathing of offline renders ([`breaths`]), inserted breaths against
//! real ones labelled by hand and the detection of the real ones ([`breath_sounds`]), pitch and
//! voicing against laryngograph references ([`pitch`]) and pause detection ([`pauses`]).
//! Beneath them the rooms they share: reading the corpora ([`data`]), seeded noise
//! ([`noise`]), figures such as medians and rank correlations ([`stats`]) and the hand labels
//! of real breaths ([`labels`]). An evaluation uses the rooms and never another evaluation's
//! insides (the breath sounds use the breathing's offline render).
//!
//! The doors: `pneuma eval head|breaths|breath-sounds|restore|podcast` ([`Args`], [`main`]) and `cargo xtask
//! eval-pitch|eval-pauses` ([`pitch::main`], [`pauses::main`]). The data lives beside the
//! checkout (`../shared/data`), never in it.

use std::process::ExitCode;

pub mod breath_sounds;
pub mod breaths;
pub mod data;
pub mod head;
pub mod labels;
pub mod noise;
pub mod pauses;
pub mod pitch;
pub mod podcast;
pub mod python_worker;
pub mod restore;
pub mod stats;

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
    Head(head::HeadArgs),
    /// Breathing of offline renders: empty lung during speech, breath durations and levels.
    Breaths(breaths::BreathArgs),
    /// Inserted breaths against real ones labelled by hand: spectrum, level, duration, and the
    /// engine's detection of the real ones.
    BreathSounds(breath_sounds::BreathSoundArgs),
    /// Real breaths cut out as an editor does, then rendered: how they are put back (count,
    /// level, duration, spectral shape against the real ones), per speaker.
    Restore(restore::RestoreArgs),
    /// Podcast-like episodes (real speech, music, singing, noise): breaths outside speech
    /// pauses, pauses with a breath, and the speech decision beside Silero VAD.
    Podcast(podcast::evaluate::PodcastArgs),
}

/// Runs `pneuma eval`.
pub fn main(args: Args) -> ExitCode {
    match args.what {
        What::Breaths(b) => exit_code(breaths::run(&b), "a checked breathing"),
        What::BreathSounds(b) => exit_code(
            breath_sounds::run(&b).map(|ok| ok || !b.check),
            "a breath-detection",
        ),
        What::Restore(r) => exit_code(restore::run(&r), "a breath-restoration"),
        What::Podcast(p) => exit_code(
            podcast::evaluate::run(&p).map(|ok| ok || !p.check),
            "a podcast",
        ),
        What::Head(h) => exit_code(head::run(&h).map(|all| all || !h.check), "a head-motion"),
    }
}

/// The exit code of an evaluation: success when `result` is `Ok(true)`; otherwise the error,
/// or "`what` target was missed", on stderr.
fn exit_code(result: Result<bool, String>, what: &str) -> ExitCode {
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
