//! The `pneuma` command's library: WAV input with clear errors, safe output files, and the
//! subcommands. The binary in `main.rs` only parses arguments and reports errors.

pub mod analyze;
pub mod eval;
pub mod eval_breaths;
pub mod options;
pub mod output;
pub mod plot;
pub mod render;
pub mod speak;
pub mod train;
pub mod wav;
pub mod wav_out;
