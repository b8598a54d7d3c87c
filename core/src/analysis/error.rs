//! [`AnalysisError`], the errors of the analysis area, and the range check the settings of
//! the analysis and of the speaker normalisation share.

use thiserror::Error;

use super::voicing::VoicingModelError;

/// Errors of the analysis area; each message says what to change.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AnalysisError {
    /// The host sample rate is outside 8–768 kHz or not finite.
    #[error(
        "sample rate {0} Hz is not supported: use a rate between 8000 and 768000 Hz (resample the input)"
    )]
    SampleRate(f64),
    /// The frame rate is outside 10–1000 Hz.
    #[error(
        "frame rate {0} Hz is not supported: use a frame rate between 10 and 1000 Hz (default 120)"
    )]
    FrameRate(f64),
    /// The f0 range is empty or outside 30–1000 Hz.
    #[error("f0 range {min_hz}–{max_hz} Hz is not usable: choose 30 ≤ min < max ≤ 1000 Hz with max ≥ 1.5 × min (default 50–600)")]
    F0Range {
        /// Lower bound given.
        min_hz: f32,
        /// Upper bound given.
        max_hz: f32,
    },
    /// The analysis window cannot hold two periods of the lowest f0.
    #[error("analysis window {window_s} s does not fit f0_min {f0_min_hz} Hz: it must be at least 2 periods ({needed_s} s) and at most 0.1 s")]
    Window {
        /// Window given, seconds.
        window_s: f32,
        /// Lowest f0 given, Hz.
        f0_min_hz: f32,
        /// Shortest window that works, seconds.
        needed_s: f32,
    },
    /// A threshold or ratio is outside 0..1.
    #[error("{name} = {value} is out of range: it must lie in {range}")]
    OutOfRange {
        /// Name of the setting.
        name: &'static str,
        /// Value given.
        value: f32,
        /// Allowed range, in words.
        range: &'static str,
    },
    /// A text value given to [`super::AnalysisConfig::set`] that is not a number.
    #[error("{name}: {value:?} is not a number")]
    NotANumber {
        /// Name of the setting.
        name: String,
        /// Text given.
        value: String,
    },
    /// A name given to [`super::AnalysisConfig::set`] that is no analysis setting.
    #[error("unknown analysis setting {0:?}")]
    UnknownSetting(String),
    /// Voicing thresholds set that make no model (`voicing_threshold_off` above
    /// `voicing_threshold_on`, or not finite).
    #[error(transparent)]
    VoicingModel(#[from] VoicingModelError),
    /// `process` was called before `prepare`.
    #[error("the analyzer is not prepared: call prepare(sample_rate, max_block) first")]
    NotPrepared,
}

/// `Ok` when `value` is finite and within `lo..=hi`, else the error naming the setting and
/// its `range` in words.
pub(crate) fn check_range(
    name: &'static str,
    value: f32,
    lo: f32,
    hi: f32,
    range: &'static str,
) -> Result<(), AnalysisError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(AnalysisError::OutOfRange { name, value, range })
    }
}
