//! `pneuma eval`: model evaluations. (Being built: issue 5.)

use std::process::ExitCode;

/// Command-line arguments of `pneuma eval`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Remaining arguments (the full interface is being built).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    pub rest: Vec<String>,
}

/// Runs `pneuma eval`.
pub fn main(_args: Args) -> ExitCode {
    eprintln!("error: `pneuma eval` is not built yet (issue 5)");
    ExitCode::FAILURE
}
