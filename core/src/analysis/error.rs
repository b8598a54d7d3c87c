//! [`AnalysisError`], the errors of the analysis area.

use thiserror::Error;

use super::voicing::VoicingModelError;
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
    /// A voicing threshold given to [`super::AnalysisConfig::set`] that is not a number (the
    /// table's settings answer with [`SettingError::NotAValue`]).
    #[error("{name}: {value:?} is not a number")]
    NotANumber {
        /// Name of the setting.
        name: String,
        /// Text given.
        value: String,
    },
    /// Voicing thresholds set that make no model (`voicing_threshold_off` above
    /// `voicing_threshold_on`, or not finite).
    #[error(transparent)]
    VoicingModel(#[from] VoicingModelError),
    /// `process` was called before `prepare`.
    #[error("the analyzer is not prepared: call prepare(sample_rate, max_block) first")]
    NotPrepared,
}
