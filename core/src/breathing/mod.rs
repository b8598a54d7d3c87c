//! The speech-breathing model of Bernardet et al. ("A Dynamic Speech Breathing System for
//! Virtual Characters", and its IEEE VR version): parameters (Table 1, Equation 1), presets, the
//! event-driven breath cycle (lung sawtooth, thorax, abdomen, neck, nostrils, mouth), procedural
//! and sampled inhalation sounds, and the text chunker with its English syllable counter.
//!
//! The same [`BreathCycle`] serves the text-driven path (`pneuma speak`: utterance lengths are
//! measured from the TTS audio) and the audio-driven path (the engine: utterance lengths known
//! offline, estimated live).

pub mod band_limit;
mod banks;
mod chunker;
mod cycle;
mod filters;
pub mod learned;
mod params;
mod presets;
pub mod reference;
mod sample;
mod syllables;
pub mod third_octave;
mod voice;

pub use chunker::{chunk_text, Chunk, ChunkBreak, Chunker};
pub use cycle::{BreathCycle, MIN_LUNG_VOLUME, RESERVE_DECAY_S, RESERVE_LUNG};
pub use params::{
    BreathingParams, LowLevelParams, BASE_SYLLABLE_RATE_HZ, BREATH_RMS_RE_SPEECH_AT_FULL,
    MIN_INSPIRATION_S,
};
pub use presets::Preset;
pub use sample::{BreathSample, SampleSlot, MAX_SAMPLE_S, MIN_SAMPLE_S};
pub use syllables::{count_syllables, count_syllables_text};
pub use voice::BreathVoice;

use thiserror::Error;

/// Errors of the breathing model.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BreathingError {
    /// A parameter is outside its range.
    #[error(transparent)]
    Setting(#[from] crate::settings::SettingError),
    /// No preset has this name.
    #[error("unknown breathing preset `{0}`; use one of {names}", names = Preset::NAMES.join(", "))]
    UnknownPreset(String),
    /// A breath sample is unusable.
    #[error("breath sample rejected: {0}")]
    BadSample(String),
}
