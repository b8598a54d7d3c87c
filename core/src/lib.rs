//! # pneuma-core
//!
//! The engine behind every Pneuma door (plugin, CLI): it turns a stream of speech samples into
//! timestamped feature frames (f0, voicing, RMS level, speaker-normalised prosody), finds phrases
//! and pauses, inserts breaths into the audio ([`engine::Engine`]) and produces breathing and
//! head-pose control frames, with pure encoders for every output format ([`encode`]). It knows
//! nothing about plugin formats, threads, sockets or files (encoders write into buffers or any
//! `Write`). The architecture and every contract are in `docs/DESIGN.md`.
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
pub mod speech;

pub use analysis::{
    AnalysisConfig, AnalysisError, Analyzer, FeatureFrame, VoicingFeatures, VoicingModel,
    VoicingModelError, N_VOICING_FEATURES, VOICING_FEATURES,
};
pub use control::{BreathEvent, BreathKind, BreathingState, ControlFrame, HeadAngles, Phase};
