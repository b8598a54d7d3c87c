//! The `pneuma` command's library: audio input (the shared `pneuma-io` crate, its WAV reader
//! re-exported as [`wav`]), safe output files, and the
//! subcommands. The binary in `main.rs` only parses arguments and reports errors.

pub mod analyze;
pub mod ascii_text;
pub mod audio_out;
pub mod bvh_out;
pub mod channel;
pub mod markers;
pub mod midi_out;
pub mod mp3_out;
pub mod options;
pub mod osc_out;
pub mod output;
pub mod plot;
pub mod png_mark;
pub mod render;
pub mod speak;
pub mod train;
pub mod wav_out;

pub use pneuma_io::wav;
