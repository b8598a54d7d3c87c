//! [`AnalysisError`], the errors of the analysis area.

use thiserror::Error;

use crate::settings::setting::SettingError;

/// Errors of the analysis area; each message says what to change.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AnalysisError {
    /// The host sample rate is outside 8–768 kHz or not finite.
    #[error(
        "sample rate {0} Hz is not supported: use a rate between 8000 and 768000 Hz (resample the input)"
    )]
    SampleRate(f64),
    /// A setting is out of its range (or of the range another setting leaves it).
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// The voicing thresholds cannot be used.
    #[error("voicing thresholds on {on} / off {off} are not usable: give finite numbers with off at most on")]
    VoicingThresholds {
        /// Threshold to start voicing.
        on: f32,
        /// Threshold to keep voicing.
        off: f32,
    },
    /// `process` was called before `prepare`.
    #[error("the analyzer is not prepared: call prepare(sample_rate, max_block) first")]
    NotPrepared,
}
