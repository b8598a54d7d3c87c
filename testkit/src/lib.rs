//! Pneuma's test scaffolding, shared by the tests and benches of every crate. A dev-dependency
//! only (`publish = false`): nothing here reaches a shipped binary.
//!
//! - [`signals`]: generated signals with known f0 (harmonic tones, glottal vowels) and seeded
//!   noise, exact without data files;
//! - [`voice`]: the shipped example voice (`assets/examples/voice.wav`) and WAV files read back
//!   (through hound, not Pneuma's own reader), at its rate or resampled;
//! - [`resample`]: resampling through rubato (tests present the example voice at host rates);
//! - [`osc`]: an OSC decoder independent of Pneuma's encoder (rosc), so the encoder's tests do
//!   not check it against itself;
//! - [`python`]: a Python with the third-party modules a test checks output with, or a visible
//!   skip (a failure when the run requires it);
//! - [`vmc`]: the third-party VMC receiver (python-osc + vmcp) the OSC tests send to.
//!
//! The level helper is core's own [`pneuma_core::analysis::rms`] (the CLI uses it too).
//!
//! Everything here takes and returns plain samples and its own types, never pneuma-core's, so
//! core's own unit tests can use it: core dev-depends on this crate, which depends on core, and
//! cargo builds the copy of core this crate links apart from the one under test; no type of that
//! copy reaches core's tests.

pub mod osc;
pub mod python;
pub mod resample;
pub mod signals;
pub mod vmc;
pub mod voice;
