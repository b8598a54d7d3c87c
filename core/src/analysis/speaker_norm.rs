//! Running speaker normalisation: f0 in semitones around the speaker's running median f0, and
//! level in dB around the speaker's running speech level, so later models serve any voice.
//!
//! The median comes from a histogram of voiced-frame f0 in 0.1-semitone bins whose weights
//! decay with a half-life counted in seconds of voiced speech (old speech is forgotten slowly,
//! silence forgets nothing). The speech level is the equally weighted running mean of `rms_db`
//! over voiced frames. Both start from a prior worth `prior_weight_s` seconds of speech, so the
//! first frames of a stream are not normalised against themselves alone.

use super::error::{check_range, AnalysisError};

/// Lowest f0 the histogram covers, Hz.
const HIST_MIN_HZ: f64 = 30.0;
/// Bin width in semitones.
const BIN_ST: f64 = 0.1;
/// Number of bins (30 Hz .. about 1 kHz).
const BINS: usize = 608;

/// Settings of the speaker normalisation.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeakerNormConfig {
    /// Half-life of the running statistics in seconds of voiced speech (default 30).
    pub half_life_s: f32,
    /// Prior median f0 in Hz before the speaker is heard (default 150).
    pub prior_f0_hz: f32,
    /// Prior speech level in dBFS (default −26).
    pub prior_level_db: f32,
    /// Weight of the priors, in seconds of voiced speech (default 1).
    pub prior_weight_s: f32,
}

impl Default for SpeakerNormConfig {
    fn default() -> Self {
        Self {
            half_life_s: 30.0,
            prior_f0_hz: 150.0,
            prior_level_db: -26.0,
            prior_weight_s: 1.0,
        }
    }
}

impl SpeakerNormConfig {
    /// Checks every setting.
    pub fn validate(&self) -> Result<(), AnalysisError> {
        check_range(
            "speaker.half_life_s",
            self.half_life_s,
            1.0,
            36_000.0,
            "1..36000 s",
        )?;
        check_range(
            "speaker.prior_f0_hz",
            self.prior_f0_hz,
            40.0,
            900.0,
            "40..900 Hz",
        )?;
        check_range(
            "speaker.prior_level_db",
            self.prior_level_db,
            -100.0,
            0.0,
            "-100..0 dBFS",
        )?;
        check_range(
            "speaker.prior_weight_s",
            self.prior_weight_s,
            0.0,
            60.0,
            "0..60 s",
        )
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
