//! The `pneuma` command: a thin door onto `pneuma-core`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pneuma_core::AnalysisConfig;

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
    /// Analyse a WAV file: f0, voicing and RMS level per frame, as CSV
    /// (time_s,f0_hz,voiced,voicing,rms_db).
    Analyze {
        /// Input WAV (8/16/24/32-bit integer or 32-bit float PCM, any channels, 8–192 kHz).
        input: PathBuf,
        /// Output CSV path, or `-` for standard output.
        #[arg(short, long)]
        output: PathBuf,
        /// Frames per second.
        #[arg(long, default_value_t = 120.0)]
        frame_rate: f64,
        /// Lowest f0 searched, Hz.
        #[arg(long, default_value_t = 50.0)]
        f0_min: f32,
        /// Highest f0 searched, Hz.
        #[arg(long, default_value_t = 600.0)]
        f0_max: f32,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Analyze {
            input,
            output,
            frame_rate,
            f0_min,
            f0_max,
        } => {
            let config = AnalysisConfig {
                frame_rate_hz: frame_rate,
                f0_min_hz: f0_min,
                f0_max_hz: f0_max,
                // Two periods of the lowest f0, at least the default 40 ms.
                window_s: AnalysisConfig::default().window_s.max(2.0 / f0_min),
                ..Default::default()
            };
            match pneuma_cli::analyze::run(&input, &output, config) {
                Ok(s) => {
                    if output.as_os_str() != "-" {
                        eprintln!(
                            "analysed {} ({} Hz, {} ch, {}-bit{}): {} frames, {} voiced -> {}",
                            input.display(),
                            s.info.sample_rate_hz,
                            s.info.channels,
                            s.info.bits,
                            if s.info.float { " float" } else { "" },
                            s.frames,
                            s.voiced_frames,
                            output.display()
                        );
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
    }
}
