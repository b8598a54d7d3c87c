//! Settings of the analysis front end: [`AnalysisConfig`], its validation and its string
//! setter, and the supported host sample rates.

use super::error::{check_range, AnalysisError};
use super::speaker_norm::SpeakerNormConfig;
use super::voicing::VoicingModel;

/// Lowest supported host sample rate in Hz.
pub const MIN_SAMPLE_RATE_HZ: f64 = 8_000.0;
/// Highest supported host sample rate in Hz.
pub const MAX_SAMPLE_RATE_HZ: f64 = 768_000.0;

/// Settings of the analysis front end. Defaults are the product's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisConfig {
    /// Frame rate of the frame clock in Hz, 10..1000 (default 120).
    pub frame_rate_hz: f64,
    /// Lowest f0 searched, Hz (default 50).
    pub f0_min_hz: f32,
    /// Highest f0 searched, Hz (default 600). A voice above it has no pitch (unvoiced frames),
    /// not the subharmonic that lies in range.
    pub f0_max_hz: f32,
    /// Pitch analysis window in seconds, at least two periods of `f0_min_hz` (default 0.04).
    pub window_s: f32,
    /// Short pitch window in seconds, centred in the long one, for the periods it holds twice
    /// (f0 ≥ 2 / `short_window_s`); 0 = off, else 0.005..`window_s` (default 0.02). A voice
    /// gliding fast is periodic over a short window when it is not over the long one; the short
    /// window confirms or corrects the long window's period (see the pitch module). At phrase
    /// edges the voicing decision also hears a short window at the newest (onset) or oldest
    /// (offset) end of the long one.
    pub short_window_s: f32,
    /// RMS window in seconds, centred on the frame time (default 0.02).
    pub rms_window_s: f32,
    /// Key-maximum rule: the first NSDF key maximum at least this fraction of the highest one is
    /// the period, 0.5..1 (default 0.88).
    pub key_max_ratio: f32,
    /// The voicing decision: a logistic regression over the frame's periodicity, level and
    /// spectral cues with hysteresis (default: the shipped model, `assets/models/voicing.txt`,
    /// fitted leave-one-speaker-out by `cargo xtask train-voicing`).
    pub voicing_model: VoicingModel,
    /// Frames below this RMS level (dBFS) are never voiced (default −60).
    pub silence_db: f32,
    /// Window of the noise-floor tracker, seconds (default 3): the floor is the lowest level
    /// of the not clearly periodic frames over that window, one of the voicing cues.
    pub noise_window_s: f32,
    /// High-pass corner applied before the pitch analysis, Hz; 0 = off (default 120). It takes
    /// rumble (traffic, car, handling noise) out of the periodicity measure.
    pub highpass_hz: f32,
    /// Corner of the second-order Butterworth low-pass the periodicity measure (the NSDF)
    /// hears its windows through, Hz; 0 = off (default 1 800). A voice's periodicity lives in
    /// its lower harmonics, while white noise, hiss and fan noise spread evenly up to the
    /// internal Nyquist frequency (4–8 kHz): with the band above the corner damped (−12 dB per
    /// octave) the NSDF hears the voice over less of that noise (held-out Keele FFE in white
    /// noise at 10 dB: 11.31 % without, 9.04 % with; README). It is applied to each window's
    /// power spectrum ([`crate::analysis::NsdfPitch`]), so the breath bands, the band level the
    /// phrase tracker reads (`FeatureFrame::band_db`), the level and the two-period edge cue
    /// still read the signal without it; the voicing cues' band level and its noise floor are
    /// read behind it.
    pub lowpass_hz: f32,
    /// Speaker normalisation settings.
    pub speaker: SpeakerNormConfig,
}

impl Default for AnalysisConfig {
    fn default() -> Self {
        Self {
            frame_rate_hz: 120.0,
            f0_min_hz: 50.0,
            f0_max_hz: 600.0,
            window_s: 0.04,
            short_window_s: 0.02,
            rms_window_s: 0.02,
            key_max_ratio: 0.88,
            voicing_model: VoicingModel::default(),
            silence_db: -60.0,
            noise_window_s: 3.0,
            highpass_hz: 120.0,
            lowpass_hz: 1800.0,
            speaker: SpeakerNormConfig::default(),
        }
    }
}

impl AnalysisConfig {
    /// Sets one setting from its name and a text value (for command-line overrides such as
    /// `voicing_on=0.8`).
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), AnalysisError> {
        let v: f64 = value.parse().map_err(|_| AnalysisError::NotANumber {
            name: name.to_string(),
            value: value.to_string(),
        })?;
        match name {
            "frame_rate_hz" => self.frame_rate_hz = v,
            "f0_min_hz" => self.f0_min_hz = v as f32,
            "f0_max_hz" => self.f0_max_hz = v as f32,
            "window_s" => self.window_s = v as f32,
            "short_window_s" => self.short_window_s = v as f32,
            "rms_window_s" => self.rms_window_s = v as f32,
            "key_max_ratio" => self.key_max_ratio = v as f32,
            "silence_db" => self.silence_db = v as f32,
            "noise_window_s" => self.noise_window_s = v as f32,
            "highpass_hz" => self.highpass_hz = v as f32,
            "lowpass_hz" => self.lowpass_hz = v as f32,
            "voicing_threshold_on" | "voicing_threshold_off" => {
                let (mut on, mut off) = (
                    self.voicing_model.threshold(false),
                    self.voicing_model.threshold(true),
                );
                if name == "voicing_threshold_on" {
                    on = v as f32;
                } else {
                    off = v as f32;
                }
                self.voicing_model = self.voicing_model.with_thresholds(on, off)?;
            }
            _ => return Err(AnalysisError::UnknownSetting(name.to_string())),
        }
        Ok(())
    }

    /// Checks every setting and says what to change.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        if !(self.frame_rate_hz.is_finite() && (10.0..=1000.0).contains(&self.frame_rate_hz)) {
            return Err(AnalysisError::FrameRate(self.frame_rate_hz));
        }
        let (lo, hi) = (self.f0_min_hz, self.f0_max_hz);
        if !(lo.is_finite() && hi.is_finite() && lo >= 30.0 && hi <= 1000.0 && hi >= 1.5 * lo) {
            return Err(AnalysisError::F0Range {
                min_hz: lo,
                max_hz: hi,
            });
        }
        let needed_s = 2.0 / lo;
        if !(self.window_s.is_finite() && self.window_s >= needed_s * 0.999 && self.window_s <= 0.1)
        {
            return Err(AnalysisError::Window {
                window_s: self.window_s,
                f0_min_hz: lo,
                needed_s,
            });
        }
        if self.short_window_s != 0.0 {
            check_range(
                "short_window_s",
                self.short_window_s,
                0.005,
                self.window_s,
                "0 (off) or 0.005 s..window_s",
            )?;
        }
        check_range(
            "rms_window_s",
            self.rms_window_s,
            0.005,
            0.1,
            "0.005..0.1 s",
        )?;
        check_range("key_max_ratio", self.key_max_ratio, 0.5, 1.0, "0.5..1")?;
        check_range(
            "noise_window_s",
            self.noise_window_s,
            0.5,
            30.0,
            "0.5..30 s",
        )?;
        check_range("highpass_hz", self.highpass_hz, 0.0, 400.0, "0..400 Hz")?;
        // Under the lowest internal rate's Nyquist frequency (4 kHz), and above the voice's
        // fundamentals (or off).
        if self.lowpass_hz != 0.0 {
            check_range(
                "lowpass_hz",
                self.lowpass_hz,
                500.0,
                3500.0,
                "0 (off) or 500..3500 Hz",
            )?;
        }
        check_range("silence_db", self.silence_db, -120.0, 0.0, "-120..0 dBFS")?;
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
        let mut c = AnalysisConfig {
            frame_rate_hz: 0.0,
            ..Default::default()
        };
        assert!(matches!(c.validate(), Err(AnalysisError::FrameRate(_))));
        c = AnalysisConfig {
            f0_min_hz: 300.0,
            f0_max_hz: 200.0,
            ..Default::default()
        };
        assert!(matches!(c.validate(), Err(AnalysisError::F0Range { .. })));
        c = AnalysisConfig {
            window_s: 0.02,
            ..Default::default()
        };
        let err = c.validate().unwrap_err();
        assert!(err.to_string().contains("at least 2 periods"), "{err}");
        c = AnalysisConfig {
            highpass_hz: 6000.0,
            ..Default::default()
        };
        assert!(matches!(
            c.validate(),
            Err(AnalysisError::OutOfRange {
                name: "highpass_hz",
                ..
            })
        ));
        // A low-pass at or over the lowest internal Nyquist frequency, or in the voice's
        // fundamentals, is refused; 0 turns it off.
        for lowpass_hz in [100.0, 4000.0, f32::NAN] {
            c = AnalysisConfig {
                lowpass_hz,
                ..Default::default()
            };
            assert!(
                matches!(
                    c.validate(),
                    Err(AnalysisError::OutOfRange {
                        name: "lowpass_hz",
                        ..
                    })
                ),
                "{lowpass_hz}"
            );
        }
        c.lowpass_hz = 0.0;
        assert_eq!(c.validate(), Ok(()));
        c = AnalysisConfig {
            short_window_s: 0.05,
            ..Default::default()
        };
        assert!(matches!(
            c.validate(),
            Err(AnalysisError::OutOfRange {
                name: "short_window_s",
                ..
            })
        ));
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
        let e = c.set("f0_min_hz", "sixty").unwrap_err();
        assert_eq!(
            e,
            AnalysisError::NotANumber {
                name: "f0_min_hz".into(),
                value: "sixty".into()
            }
        );
        assert_eq!(e.to_string(), "f0_min_hz: \"sixty\" is not a number");
        let e = c.set("f0_minimum", "60").unwrap_err();
        assert_eq!(e, AnalysisError::UnknownSetting("f0_minimum".into()));
        assert_eq!(e.to_string(), "unknown analysis setting \"f0_minimum\"");
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
