//! End-to-end test support (the tests themselves are in `tests/tests/`):
//!
//! - [`bundle`]: which plugin library the tests load: the one `cargo test` built beside them
//!   (this crate dev-depends on the plugin), or the file `PNEUMA_CLAP` names (`.ci/run`: the
//!   shipped bundle);
//! - [`host`]: a small CLAP host on `clack-host`: loads the bundle, sets parameters, selects the
//!   mono or stereo layout, activates at any rate and block size, processes audio with or without
//!   a transport, collects the plugin's MIDI CC output with sample offsets, reads the reported
//!   latency, saves and restores state.
//!
//! The example voice, its resampling to the host rates and the OSC decoder come from
//! `pneuma-testkit`.
//!
//! Test modules (one binary, `tests/integration/`): `plugin_clap.rs` (parameters, block partitions at 44.1/48 kHz, CC rules, breaths
//! in the audio, 14-bit/channel settings, state, NaN/silence, latency and restart, transport
//! jumps, and equality with the CLI render), `osc_udp.rs` (both
//! OSC formats received on 127.0.0.1, target and format changed while playing, an unresolvable
//! target), `example_voice.rs` (the shipped voice). `tests/vst3/check_vst3.py` is the VST3 check
//! in a real host (pedalboard), run by `.ci/run`. `benches/plugin_cpu.rs` measures CPU per
//! instance at 48 kHz in 64-sample blocks.

pub mod bundle;
pub mod host;
