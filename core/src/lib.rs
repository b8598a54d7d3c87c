//! # pneuma-core
//!
//! The engine behind every Pneuma door (plugin, CLI): it turns a stream of speech samples into
//! timestamped feature frames (f0, voicing, RMS level, speaker-normalised prosody) and, in later
//! stages, into breathing and head-pose control frames. It knows nothing about plugin formats,
//! threads, sockets or files.
//!
//! Every stateful object follows the same life: `new(config)` validates and allocates,
//! `prepare(sample_rate, max_block)` allocates for a stream, `reset()` clears, and `process(...)`
//! never allocates, locks, blocks, logs or does I/O.

pub mod analysis;
pub mod breathing;
pub mod control;
pub mod encode;
pub mod engine;
pub mod head;
pub mod phrase;
pub mod rng;
pub mod synth;

pub use analysis::{
    AnalysisConfig, AnalysisError, Analyzer, FeatureFrame, VoicingFeatures, VoicingModel,
    VoicingModelError, N_VOICING_FEATURES, VOICING_FEATURES,
};
pub use control::{BreathEvent, BreathKind, BreathingState, ControlFrame, HeadAngles, Phase};
