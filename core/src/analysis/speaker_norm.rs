//! Running speaker normalisation: f0 in semitones around the speaker's running median f0, and
//! level in dB around the speaker's running speech level, so later models serve any voice.
//!
//! The median comes from a histogram of voiced-frame f0 in 0.1-semitone bins whose weights
//! decay with a half-life counted in seconds of voiced speech (old speech is forgotten slowly,
//! silence forgets nothing). The speech level is the equally weighted running mean of `rms_db`
//! over voiced frames. Both start from a prior worth `prior_weight_s` seconds of speech, so the
//! first frames of a stream are not normalised against themselves alone.

use super::error::AnalysisError;
use crate::settings::analysis::{
    SPEAKER_HALF_LIFE_S, SPEAKER_PRIOR_F0_HZ, SPEAKER_PRIOR_LEVEL_DB, SPEAKER_PRIOR_WEIGHT_S,
};
use crate::settings::setting::{check_fields, field, Field};

/// Running speech level (full band, dBFS) at or over which the absolute levels set for speech
/// hold as set: the analysis's voicing silence (`silence_db`), the phrase tracker's silence
/// level (`phrase_silence_db`) and a cut's ceiling; under it they move down with the speech,
/// so a quiet take's soft syllables stay voice and its soft sounds stay over its silence.
/// Every recording in `../shared/data` speaks at −20 to −30 dBFS (median of the voiced
/// frames), so the rule changes nothing there.
pub const QUIET_SPEECH_DB: f32 = -30.0;

/// How far levels set for speech at [`QUIET_SPEECH_DB`] move for a speaker whose running
/// speech level is `speech_level_db` (dBFS): 0 at or over it, the speech's shortfall under it
/// (negative), 0 before any level is known.
pub fn quiet_shift_db(speech_level_db: f32) -> f32 {
    if speech_level_db.is_finite() {
        (speech_level_db - QUIET_SPEECH_DB).min(0.0)
    } else {
        0.0
    }
}

/// Lowest f0 the histogram covers, Hz.
const HIST_MIN_HZ: f64 = 30.0;
/// Bin width in semitones.
const BIN_ST: f64 = 0.1;
/// Number of bins (30 Hz .. about 1 kHz).
const BINS: usize = 608;

/// Settings of the speaker normalisation; each field's setting (unit, range, default, why) is
/// in [`crate::settings::analysis`].
#[derive(Debug, Clone, PartialEq)]
pub struct SpeakerNormConfig {
    /// Half-life of the running statistics in seconds of voiced speech
    /// ([`SPEAKER_HALF_LIFE_S`]).
    pub half_life_s: f32,
    /// Prior median f0 in Hz before the speaker is heard ([`SPEAKER_PRIOR_F0_HZ`]).
    pub prior_f0_hz: f32,
    /// Prior speech level in dBFS ([`SPEAKER_PRIOR_LEVEL_DB`]).
    pub prior_level_db: f32,
    /// Weight of the priors, in seconds of voiced speech ([`SPEAKER_PRIOR_WEIGHT_S`]).
    pub prior_weight_s: f32,
}

/// The settings of [`SpeakerNormConfig`] and the fields holding them.
static FIELDS: [Field<SpeakerNormConfig>; 4] = [
    field!(SPEAKER_HALF_LIFE_S, half_life_s),
    field!(SPEAKER_PRIOR_F0_HZ, prior_f0_hz),
    field!(SPEAKER_PRIOR_LEVEL_DB, prior_level_db),
    field!(SPEAKER_PRIOR_WEIGHT_S, prior_weight_s),
];

impl Default for SpeakerNormConfig {
    /// The table's defaults.
    fn default() -> Self {
        Self {
            half_life_s: SPEAKER_HALF_LIFE_S.default,
            prior_f0_hz: SPEAKER_PRIOR_F0_HZ.default,
            prior_level_db: SPEAKER_PRIOR_LEVEL_DB.default,
            prior_weight_s: SPEAKER_PRIOR_WEIGHT_S.default,
        }
    }
}

impl SpeakerNormConfig {
    /// The settings of this struct and the fields holding them.
    pub fn fields() -> &'static [Field<SpeakerNormConfig>] {
        &FIELDS
    }

    /// Checks every setting.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        Ok(check_fields(self, &FIELDS)?)
    }
}

/// Running per-speaker statistics.
#[derive(Debug, Clone)]
pub struct SpeakerNorm {
    config: SpeakerNormConfig,
    decay: f64,
    hist: Vec<f64>,
    /// Weight given to the next frame; grows instead of decaying every bin (lazy decay).
    increment: f64,
    total: f64,
    level_sum: f64,
    prior_frames: f64,
}

impl SpeakerNorm {
    /// Running statistics for frames at `frame_rate_hz`. Allocates.
    pub fn new(config: SpeakerNormConfig, frame_rate_hz: f64) -> Self {
        let frames_per_half_life = (config.half_life_s as f64 * frame_rate_hz).max(1.0);
        let mut s = Self {
            decay: 0.5f64.powf(1.0 / frames_per_half_life),
            prior_frames: config.prior_weight_s as f64 * frame_rate_hz,
            config,
            hist: vec![0.0; BINS],
            increment: 1.0,
            total: 0.0,
            level_sum: 0.0,
        };
        s.reset();
        s
    }

    /// Forgets the speaker and returns to the priors.
    pub fn reset(&mut self) {
        self.hist.fill(0.0);
        self.increment = 1.0;
        let w = self.prior_frames.max(1e-3);
        self.hist[bin_of(self.config.prior_f0_hz as f64)] = w;
        self.total = w;
        self.level_sum = w * self.config.prior_level_db as f64;
    }

    /// Adds one frame; only voiced frames with a finite f0 teach the statistics.
    pub fn update(&mut self, voiced: bool, f0_hz: f32, rms_db: f32) {
        if !(voiced && f0_hz > 0.0 && f0_hz.is_finite() && rms_db.is_finite()) {
            return;
        }
        self.increment /= self.decay;
        if self.increment > 1e200 {
            let k = 1.0 / self.increment;
            self.hist.iter_mut().for_each(|h| *h *= k);
            self.total *= k;
            self.level_sum *= k;
            self.increment = 1.0;
        }
        self.hist[bin_of(f0_hz as f64)] += self.increment;
        self.total += self.increment;
        self.level_sum += self.increment * rms_db as f64;
    }

    /// The running median f0 in Hz.
    pub fn median_f0_hz(&self) -> f32 {
        let half = self.total / 2.0;
        let mut acc = 0.0;
        for (i, &h) in self.hist.iter().enumerate() {
            if acc + h >= half && h > 0.0 {
                let frac = ((half - acc) / h).clamp(0.0, 1.0);
                let st = (i as f64 + frac) * BIN_ST;
                return (HIST_MIN_HZ * (st / 12.0).exp2()) as f32;
            }
            acc += h;
        }
        self.config.prior_f0_hz
    }

    /// The running speech level in dBFS.
    pub fn speech_level_db(&self) -> f32 {
        (self.level_sum / self.total) as f32
    }

    /// `f0_hz` in semitones around the running median (0 for unvoiced frames).
    pub fn f0_st(&self, f0_hz: f32) -> f32 {
        if f0_hz > 0.0 && f0_hz.is_finite() {
            12.0 * (f0_hz / self.median_f0_hz()).log2()
        } else {
            0.0
        }
    }
}

fn bin_of(f0_hz: f64) -> usize {
    let st = 12.0 * (f0_hz.max(HIST_MIN_HZ) / HIST_MIN_HZ).log2();
    ((st / BIN_ST) as usize).min(BINS - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_follows_the_speaker() {
        let mut n = SpeakerNorm::new(SpeakerNormConfig::default(), 100.0);
        assert!((n.median_f0_hz() - 150.0).abs() < 2.0);
        // Ten seconds of a 220 Hz speaker with occasional outliers.
        for i in 0..1000 {
            let f0 = if i % 10 == 0 {
                440.0
            } else {
                215.0 + (i % 7) as f32 * 2.0
            };
            n.update(true, f0, -20.0);
            n.update(false, 0.0, -70.0);
        }
        let m = n.median_f0_hz();
        assert!((m - 221.0).abs() < 3.0, "median {m}");
        assert!(
            (n.speech_level_db() - -20.5).abs() < 0.6,
            "{}",
            n.speech_level_db()
        );
        assert!((n.f0_st(2.0 * m) - 12.0).abs() < 1e-3);
        assert_eq!(n.f0_st(0.0), 0.0);
        n.reset();
        assert!((n.median_f0_hz() - 150.0).abs() < 2.0);
    }

    #[test]
    fn old_speech_is_forgotten() {
        let cfg = SpeakerNormConfig {
            half_life_s: 2.0,
            ..Default::default()
        };
        let mut n = SpeakerNorm::new(cfg, 100.0);
        for _ in 0..2000 {
            n.update(true, 120.0, -30.0);
        }
        for _ in 0..2000 {
            n.update(true, 240.0, -10.0);
        }
        assert!((n.median_f0_hz() - 240.0).abs() < 5.0);
        assert!(n.speech_level_db() > -11.0);
    }
}
