//! The `pneuma` command: a thin door onto `pneuma-core`. Each subcommand lives in its own module
//! of the `pneuma_cli` library with its own `Args` and `main`; `eval` is the evaluation crate's
//! (`pneuma-eval`).

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pneuma_cli::{analyze, render, speak, train};

#[derive(Parser)]
#[command(
    name = "pneuma",
    version,
    about = "Pneuma: speech gives a body (f0, RMS, breaths, head pose)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Analyse an audio file: f0, voicing and RMS level per frame, as CSV
    /// (time_s,f0_hz,voiced,voicing,rms_db).
    Analyze(analyze::Args),
    /// Put breaths into recorded speech and compute breathing and head-pose controls.
    Render(render::Args),
    /// Speak text with a TTS program, with breaths between breath groups.
    Speak(speak::Args),
    /// Train a head-pose model from audio files with head-motion CSVs.
    Train(train::Args),
    /// Evaluate a model against data.
    Eval(pneuma_eval::Args),
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::Analyze(args) => analyze::main(args),
        Command::Render(args) => render::main(args),
        Command::Speak(args) => speak::main(args),
        Command::Train(args) => train::main(args),
        Command::Eval(args) => pneuma_eval::main(args),
    }
}
