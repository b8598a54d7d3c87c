//! The `pneuma` command end to end, one module per subject, in one test binary (one build and
//! one link instead of nine; `cargo test -p pneuma-cli --test integration podcast::` runs one
//! subject). [`support`] runs the built binary, encodes inputs with ffmpeg, writes test WAV files
//! and reads outputs back; `support::episode` also serves `examples/episode.rs`.

mod support;

mod analyze_cli;
mod animator_tryout;
mod carry_over;
mod formats;
mod long_render;
mod mp3_output;
mod osc;
mod podcast;
mod render_cli;
mod robustness;
mod speak_cli;
mod special_outputs;
mod train_eval_cli;
mod tryout;
mod user_reports;
mod wav_input;
