//! End-to-end test support (the tests themselves are in `tests/tests/`):
//!
//! - [`bundle`]: finds the built `Pneuma.clap`, building it first (see there for the policy);
//! - [`host`]: a small CLAP host on `clack-host`: loads the bundle, sets parameters, activates at
//!   any rate and block size, processes audio, collects the plugin's MIDI CC output with sample
//!   offsets, reads the reported latency, saves and restores state;
//! - [`wav`]: reading the shipped example voice.

pub mod bundle;
pub mod host;
pub mod wav;
