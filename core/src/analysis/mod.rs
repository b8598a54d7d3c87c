//! The analysis front end: Framer → PitchTracker + Energy → [`FeatureFrame`] → SpeakerNorm.
//!
//! [`Analyzer`] takes mono blocks of any size at any sample rate from 8 kHz to 768 kHz and emits
//! one [`FeatureFrame`] per tick of a fixed frame clock (default 120 Hz). Internally the signal is
//! decimated by an integer factor to a rate between 8 and 16 kHz, so the pitch analysis costs the
//! same per second of audio whatever the host rate; the level is measured on the full-rate signal.

mod analyzer;
pub(crate) mod biquad;
pub(crate) mod breath_band;
mod clock;
mod config;
pub(crate) mod decimator;
mod error;
mod frame;
mod level;
pub(crate) mod noise_floor;
mod pitch;
mod speaker_norm;
mod tracking;
mod voicing;

pub use analyzer::Analyzer;
pub use biquad::Biquad;
pub use breath_band::BandLevels;
pub use clock::FrameClock;
pub use config::{AnalysisConfig, MAX_SAMPLE_RATE_HZ, MIN_SAMPLE_RATE_HZ};
pub use error::AnalysisError;
pub use frame::FeatureFrame;
pub(crate) use level::band_power;
pub use level::{
    amplitude_to_db, no_signal_peak_db, quiet_peak_db, rms, LEVEL_FLOOR_DB, SPEECH_CREST_DB,
};
pub use pitch::{NsdfPitch, PitchEstimate};
pub use speaker_norm::{quiet_shift_db, SpeakerNorm, SpeakerNormConfig, QUIET_SPEECH_DB};
pub use voicing::{
    InvalidVoicingModel, VoicingFeatures, VoicingModel, VoicingModelError, N_VOICING_FEATURES,
    VOICING_FEATURES,
};
// The training of the voicing model (`cargo xtask train-voicing`) reads this cue too.
pub use voicing::LEVEL_VS_GATE;
