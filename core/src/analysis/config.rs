//! Settings of the analysis front end: [`AnalysisConfig`] bound to the table's analysis
//! settings ([`crate::settings::analysis`]: units, ranges, defaults and why), its validation
//! and string setter, and the supported host sample rates.

use super::error::AnalysisError;
use super::speaker_norm::SpeakerNormConfig;
use super::voicing::VoicingModel;
use crate::settings::analysis::{
    F0_MAX_HZ, F0_MIN_HZ, FRAME_RATE_HZ, HIGHPASS_HZ, KEY_MAX_RATIO, LOWPASS_HZ, NOISE_WINDOW_S,
    RMS_WINDOW_S, SHORT_WINDOW_S, SILENCE_DB, WINDOW_S,
};
use crate::settings::setting::{check_fields, field, find_field, Field, Relation, SettingError};

/// Lowest supported host sample rate in Hz.
pub const MIN_SAMPLE_RATE_HZ: f64 = 8_000.0;
/// Highest supported host sample rate in Hz.
pub const MAX_SAMPLE_RATE_HZ: f64 = 768_000.0;

/// Settings of the analysis front end; each numeric field's setting (unit, range, default,
/// why) is in [`crate::settings::analysis`].
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisConfig {
    /// Frame rate of the frame clock, Hz ([`FRAME_RATE_HZ`]).
    pub frame_rate_hz: f64,
    /// Lowest f0 searched, Hz ([`F0_MIN_HZ`]).
    pub f0_min_hz: f32,
    /// Highest f0 searched, Hz, at least 1.5 × `f0_min_hz` ([`F0_MAX_HZ`]). A voice above it
    /// has no pitch (unvoiced frames), not the subharmonic that lies in range.
    pub f0_max_hz: f32,
    /// Pitch analysis window, seconds, at least two periods of `f0_min_hz` ([`WINDOW_S`]).
    pub window_s: f32,
    /// Short pitch window, seconds, centred in the long one, for the periods it holds twice
    /// (f0 ≥ 2 / `short_window_s`); 0 = off, else at most `window_s` ([`SHORT_WINDOW_S`]). A
    /// voice gliding fast is periodic over a short window when it is not over the long one; the
    /// short window confirms or corrects the long window's period (see the pitch module). At
    /// phrase edges the voicing decision also hears a short window at the newest (onset) or
    /// oldest (offset) end of the long one.
    pub short_window_s: f32,
    /// RMS window, seconds, centred on the frame time ([`RMS_WINDOW_S`]).
    pub rms_window_s: f32,
    /// Key-maximum rule: the first NSDF key maximum at least this fraction of the highest one is
    /// the period ([`KEY_MAX_RATIO`]).
    pub key_max_ratio: f32,
    /// The voicing decision: a logistic regression over the frame's periodicity, level and
    /// spectral cues with hysteresis (default: the shipped model, `assets/models/voicing.txt`,
    /// fitted leave-one-speaker-out by `cargo xtask train-voicing`).
    pub voicing_model: VoicingModel,
    /// Frames below this RMS level are never voiced, dBFS ([`SILENCE_DB`]).
    pub silence_db: f32,
    /// Window of the noise-floor tracker, seconds ([`NOISE_WINDOW_S`]): the floor is the
    /// lowest level of the not clearly periodic frames over that window, one of the voicing
    /// cues.
    pub noise_window_s: f32,
    /// High-pass corner applied before the pitch analysis, Hz; 0 = off ([`HIGHPASS_HZ`]). It
    /// takes rumble (traffic, car, handling noise) out of the periodicity measure.
    pub highpass_hz: f32,
    /// Corner of the second-order Butterworth low-pass the periodicity measure (the NSDF)
    /// hears its windows through, Hz; 0 = off ([`LOWPASS_HZ`]). A voice's periodicity lives in
    /// its lower harmonics, while white noise, hiss and fan noise spread evenly up to the
    /// internal Nyquist frequency (4–8 kHz): with the band above the corner damped (−12 dB per
    /// octave) the NSDF hears the voice over less of that noise (held-out Keele FFE in white
    /// noise at 10 dB: 11.31 % without, 9.04 % with; docs/measurements.md). It is applied to each window's
    /// power spectrum ([`crate::analysis::NsdfPitch`]), so the breath bands, the band level the
    /// phrase tracker reads (`FeatureFrame::band_db`), the level and the two-period edge cue
    /// still read the signal without it; the voicing cues' band level and its noise floor are
    /// read behind it.
    pub lowpass_hz: f32,
    /// Speaker normalisation settings.
    pub speaker: SpeakerNormConfig,
}

/// The numeric settings of [`AnalysisConfig`] and the fields holding them (the voicing model
/// and the speaker normalisation have their own).
static FIELDS: [Field<AnalysisConfig>; 11] = [
    field!(FRAME_RATE_HZ, frame_rate_hz),
    field!(F0_MIN_HZ, f0_min_hz),
    field!(F0_MAX_HZ, f0_max_hz),
    field!(WINDOW_S, window_s),
    field!(SHORT_WINDOW_S, short_window_s),
    field!(RMS_WINDOW_S, rms_window_s),
    field!(KEY_MAX_RATIO, key_max_ratio),
    field!(SILENCE_DB, silence_db),
    field!(NOISE_WINDOW_S, noise_window_s),
    field!(HIGHPASS_HZ, highpass_hz),
    field!(LOWPASS_HZ, lowpass_hz),
];

/// The voicing model's thresholds, set by [`AnalysisConfig::set`] (the model's own numbers,
/// not settings of the table).
pub const VOICING_THRESHOLD_IDS: [&str; 2] = ["voicing_threshold_on", "voicing_threshold_off"];

impl Default for AnalysisConfig {
    /// The table's defaults and the shipped voicing model.
    fn default() -> Self {
        Self {
            frame_rate_hz: f64::from(FRAME_RATE_HZ.default),
            f0_min_hz: F0_MIN_HZ.default,
            f0_max_hz: F0_MAX_HZ.default,
            window_s: WINDOW_S.default,
            short_window_s: SHORT_WINDOW_S.default,
            rms_window_s: RMS_WINDOW_S.default,
            key_max_ratio: KEY_MAX_RATIO.default,
            voicing_model: VoicingModel::default(),
            silence_db: SILENCE_DB.default,
            noise_window_s: NOISE_WINDOW_S.default,
            highpass_hz: HIGHPASS_HZ.default,
            lowpass_hz: LOWPASS_HZ.default,
            speaker: SpeakerNormConfig::default(),
        }
    }
}

impl AnalysisConfig {
    /// The numeric settings of this struct and the fields holding them.
    pub fn fields() -> &'static [Field<AnalysisConfig>] {
        &FIELDS
    }

    /// Sets one setting from its id and a text value (for command-line overrides such as
    /// `frame_rate_hz=200`): an analysis or speaker setting of the table, or a voicing
    /// threshold ([`VOICING_THRESHOLD_IDS`]).
    pub fn set(&mut self, id: &str, text: &str) -> Result<(), AnalysisError> {
        if let Some(which) = VOICING_THRESHOLD_IDS.iter().position(|t| *t == id) {
            let v: f32 = text.trim().replace('\u{2212}', "-").parse().map_err(|_| {
                AnalysisError::NotANumber {
                    name: id.to_string(),
                    value: text.to_string(),
                }
            })?;
            let (mut on, mut off) = (
                self.voicing_model.threshold(false),
                self.voicing_model.threshold(true),
            );
            if which == 0 {
                on = v;
            } else {
                off = v;
            }
            self.voicing_model = self.voicing_model.with_thresholds(on, off)?;
            return Ok(());
        }
        if let Some(f) = find_field(&FIELDS, id) {
            let value = f.setting.parse(text)?;
            (f.set)(self, value);
            return Ok(());
        }
        let f = find_field(SpeakerNormConfig::fields(), id)
            .ok_or_else(|| SettingError::Unknown(id.to_owned()))?;
        let value = f.setting.parse(text)?;
        (f.set)(&mut self.speaker, value);
        Ok(())
    }

    /// Checks every setting against its range, the f0 range and the windows against each
    /// other, and says what to change.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        check_fields(self, &FIELDS)?;
        let f0_min = f64::from(self.f0_min_hz);
        F0_MAX_HZ.check_within(
            f64::from(self.f0_max_hz),
            (1.5 * f0_min).max(F0_MAX_HZ.min()),
            F0_MAX_HZ.max(),
            Some(Relation {
                words: "at least 1.5 times",
                other: &F0_MIN_HZ,
            }),
        )?;
        // Two periods of the lowest f0 (a thousandth of slack for the rounding of `2 / f0`).
        WINDOW_S.check_within(
            f64::from(self.window_s),
            (2.0 / f0_min * 0.999).max(WINDOW_S.min()),
            WINDOW_S.max(),
            Some(Relation {
                words: "at least 2 periods of",
                other: &F0_MIN_HZ,
            }),
        )?;
        if self.short_window_s != 0.0 {
            SHORT_WINDOW_S.check_within(
                f64::from(self.short_window_s),
                SHORT_WINDOW_S.min(),
                f64::from(self.window_s).min(SHORT_WINDOW_S.max()),
                Some(Relation {
                    words: "at most",
                    other: &WINDOW_S,
                }),
            )?;
        }
        self.speaker.validate()
    }
}

/// Validates a host sample rate.
pub(crate) fn check_sample_rate(sample_rate_hz: f64) -> Result<(), AnalysisError> {
    if sample_rate_hz.is_finite()
        && (MIN_SAMPLE_RATE_HZ..=MAX_SAMPLE_RATE_HZ).contains(&sample_rate_hz)
    {
        Ok(())
    } else {
        Err(AnalysisError::SampleRate(sample_rate_hz))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        assert_eq!(AnalysisConfig::default().validate(), Ok(()));
    }

    #[test]
    fn bad_settings_are_named() {
        let named = |c: &AnalysisConfig| match c.validate() {
            Err(AnalysisError::Setting(e)) => e.setting().map(|s| s.id),
            other => panic!("{other:?}"),
        };
        let mut c = AnalysisConfig {
            frame_rate_hz: 0.0,
            ..Default::default()
        };
        assert_eq!(named(&c), Some("frame_rate_hz"));
        c = AnalysisConfig {
            f0_min_hz: 300.0,
            f0_max_hz: 400.0,
            ..Default::default()
        };
        assert_eq!(named(&c), Some("f0_max_hz"));
        let err = c.validate().unwrap_err().to_string();
        assert!(
            err.contains("use 450 to 1000 Hz (at least 1.5 times f0_min_hz)"),
            "{err}"
        );
        c = AnalysisConfig {
            window_s: 0.02,
            ..Default::default()
        };
        let err = c.validate().unwrap_err();
        assert!(
            err.to_string().contains("at least 2 periods of f0_min_hz"),
            "{err}"
        );
        c = AnalysisConfig {
            highpass_hz: 6000.0,
            ..Default::default()
        };
        assert_eq!(named(&c), Some("highpass_hz"));
        // A low-pass at or over the lowest internal Nyquist frequency, or in the voice's
        // fundamentals, is refused; 0 turns it off.
        for lowpass_hz in [100.0, 4000.0, f32::NAN] {
            c = AnalysisConfig {
                lowpass_hz,
                ..Default::default()
            };
            assert_eq!(named(&c), Some("lowpass_hz"), "{lowpass_hz}");
        }
        c.lowpass_hz = 0.0;
        assert_eq!(c.validate(), Ok(()));
        c = AnalysisConfig {
            short_window_s: 0.05,
            ..Default::default()
        };
        assert_eq!(named(&c), Some("short_window_s"));
        c.short_window_s = 0.0;
        assert_eq!(c.validate(), Ok(()));
        c = AnalysisConfig {
            noise_window_s: 1e9,
            ..Default::default()
        };
        assert!(c.validate().is_err());
        assert!(check_sample_rate(7999.0).is_err());
        assert!(check_sample_rate(f64::NAN).is_err());
        assert!(check_sample_rate(192_000.0).is_ok());
        assert!(check_sample_rate(768_000.0).is_ok());
        assert!(check_sample_rate(768_001.0).is_err());
    }

    #[test]
    fn the_string_setter_names_what_is_wrong() {
        use crate::analysis::{InvalidVoicingModel, VoicingModelError};
        let mut c = AnalysisConfig::default();
        assert_eq!(c.set("f0_min_hz", "60"), Ok(()));
        assert_eq!(c.f0_min_hz, 60.0);
        // The table's ids, of the analysis and of the speaker normalisation, in their units.
        c.set("frame_rate_hz", "200").unwrap();
        assert_eq!(c.frame_rate_hz, 200.0);
        c.set("speaker_prior_f0_hz", "210").unwrap();
        assert_eq!(c.speaker.prior_f0_hz, 210.0);
        c.set("silence_db", "\u{2212}50").unwrap();
        assert_eq!(c.silence_db, -50.0);
        let e = c.set("f0_min_hz", "sixty").unwrap_err();
        assert_eq!(
            e.to_string(),
            "f0_min_hz: `sixty` is not a number: use 30 to 600 Hz"
        );
        let e = c.set("frame_rate_hz", "1000").unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame_rate_hz 1000 Hz is out of range: use 30 to 240 Hz"
        );
        assert_eq!(c.frame_rate_hz, 200.0, "a refused value changes nothing");
        let e = c.set("f0_minimum", "60").unwrap_err();
        assert!(matches!(
            e,
            AnalysisError::Setting(SettingError::Unknown(_))
        ));
        // A phrase setting is not the analysis's.
        assert!(c.set("hangover_s", "0.2").is_err());
        let e = c.set("voicing_threshold_on", "high").unwrap_err();
        assert_eq!(
            e,
            AnalysisError::NotANumber {
                name: "voicing_threshold_on".into(),
                value: "high".into()
            }
        );
        // The thresholds go through the model, which refuses `off` above `on`.
        c.set("voicing_threshold_on", "1").unwrap();
        c.set("voicing_threshold_off", "0.5").unwrap();
        assert_eq!(
            (
                c.voicing_model.threshold(false),
                c.voicing_model.threshold(true)
            ),
            (1.0, 0.5)
        );
        let e = c.set("voicing_threshold_off", "2").unwrap_err();
        assert_eq!(
            e,
            AnalysisError::VoicingModel(VoicingModelError::Invalid(
                InvalidVoicingModel::ThresholdOrder { on: 1.0, off: 2.0 }
            ))
        );
        assert_eq!(e.to_string(), "threshold_off 2 lies above threshold_on 1");
        assert_eq!(
            c.voicing_model.threshold(true),
            0.5,
            "a refused value changes nothing"
        );
    }
}
