//! `pneuma render`: breaths into recorded speech, controls, plot. (Being built: issue 4.)

use std::process::ExitCode;

/// Command-line arguments of `pneuma render`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Remaining arguments (the full interface is being built).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `pneuma render`.
pub fn main(_args: Args) -> ExitCode {
    eprintln!("error: `pneuma render` is not built yet (issue 4)");
    ExitCode::FAILURE
}
