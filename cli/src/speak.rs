//! `pneuma speak`: text to speech with breaths. (Being built: issue 3.)

use std::process::ExitCode;

/// Command-line arguments of `pneuma speak`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Remaining arguments (the full interface is being built).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `pneuma speak`.
pub fn main(_args: Args) -> ExitCode {
    eprintln!("error: `pneuma speak` is not built yet (issue 3)");
    ExitCode::FAILURE
}
