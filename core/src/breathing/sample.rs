//! User breath samples (mouth and nose inhalations from WAV files) and how they are fitted to an
//! inspiration.
//!
//! # The fitting rule
//! 1. On [`super::BreathVoice::set_sample`] (or `prepare`), the sample is resampled to the
//!    stream rate (windowed-sinc, band-limited when going down) and scaled to unit RMS over its
//!    whole length, so `gain` means the same for samples and procedural sounds.
//! 2. When a breath of `n` samples starts: a sample at least `n` long plays its **first `n`
//!    samples** (the natural onset is kept); a shorter one is **looped with a 50 ms equal-power
//!    crossfade** (at most a quarter of the sample) until `n` samples are filled.
//! 3. The breath's smooth trapezoid envelope (zero at both ends) is applied on top, so no fitting
//!    can click.

use super::BreathingError;

/// Which breath sound a sample replaces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SampleSlot {
    /// The mouth inhalation.
    Mouth,
    /// The nose inhalation.
    Nose,
}

/// A mono breath recording, checked and scaled to unit RMS.
#[derive(Debug, Clone, PartialEq)]
pub struct BreathSample {
    samples: Vec<f32>,
    sample_rate_hz: f64,
}

/// The shortest usable sample, seconds.
pub const MIN_SAMPLE_S: f64 = 0.05;
/// The longest usable sample, seconds: a breath sample is one inhalation (real ones last
/// 0.1–1 s; with the room before and after it a recording of one stays under this). A longer
/// file is something else (a take, a song): only its first breath-length would play, scaled by
/// the whole file's level.
pub const MAX_SAMPLE_S: f64 = 3.0;
/// A sample quieter than this is silence or dither, not an inhalation, dBFS RMS (a quiet
/// inhalation lies 40–60 dB under full scale; 16-bit dither about 100 dB).
pub const SILENT_SAMPLE_DB: f64 = -80.0;

impl BreathSample {
    /// A sample from mono samples (full scale ±1) at `sample_rate_hz` (8–192 kHz). Rejects
    /// empty, too short ([`MIN_SAMPLE_S`]), too long ([`MAX_SAMPLE_S`]), non-finite or silent
    /// ([`SILENT_SAMPLE_DB`]) recordings.
    pub fn from_mono(samples: Vec<f32>, sample_rate_hz: f64) -> Result<Self, BreathingError> {
        if !(8_000.0..=192_000.0).contains(&sample_rate_hz) {
            return Err(BreathingError::BadSample(format!(
                "sample rate {sample_rate_hz} Hz is outside 8000–192000 Hz; resample the file"
            )));
        }
        if (samples.len() as f64) < MIN_SAMPLE_S * sample_rate_hz {
            return Err(BreathingError::BadSample(format!(
                "{} samples is shorter than {} ms; use a recording of a whole inhalation",
                samples.len(),
                MIN_SAMPLE_S * 1000.0
            )));
        }
        let length_s = samples.len() as f64 / sample_rate_hz;
        if length_s > MAX_SAMPLE_S {
            return Err(BreathingError::BadSample(format!(
                "it is {length_s:.2} s long, and a breath sample is one inhalation (at most \
                 {MAX_SAMPLE_S} s); cut the breath out of it"
            )));
        }
        if samples.iter().any(|v| !v.is_finite()) {
            return Err(BreathingError::BadSample(
                "it contains NaN or infinite values; re-export the file".into(),
            ));
        }
        let mean = samples.iter().map(|&v| v as f64).sum::<f64>() / samples.len() as f64;
        let rms = (samples
            .iter()
            .map(|&v| (v as f64 - mean).powi(2))
            .sum::<f64>()
            / samples.len() as f64)
            .sqrt();
        let rms_db = 20.0 * rms.max(1e-12).log10();
        if rms_db < SILENT_SAMPLE_DB {
            return Err(BreathingError::BadSample(format!(
                "it is silent or dither only (RMS {rms_db:.0} dBFS, under {SILENT_SAMPLE_DB} \
                 dBFS); record an audible inhalation"
            )));
        }
        let scale = 1.0 / rms;
        let samples = samples
            .iter()
            .map(|&v| ((v as f64 - mean) * scale) as f32)
            .collect();
        Ok(Self {
            samples,
            sample_rate_hz,
        })
    }

    /// The samples, unit RMS, DC removed.
    pub fn samples(&self) -> &[f32] {
        &self.samples
    }

    /// The sample rate, Hz.
    pub fn sample_rate_hz(&self) -> f64 {
        self.sample_rate_hz
    }

    /// Length in seconds.
    pub fn length_s(&self) -> f64 {
        self.samples.len() as f64 / self.sample_rate_hz
    }

    /// The sample at `rate_hz` (allocates; windowed-sinc interpolation, low-passed below the
    /// lower of the two Nyquist frequencies), rescaled to unit RMS.
    pub fn resampled(&self, rate_hz: f64) -> Vec<f32> {
        if (rate_hz - self.sample_rate_hz).abs() < 1e-9 {
            return self.samples.clone();
        }
        let ratio = rate_hz / self.sample_rate_hz;
        let n_out = ((self.samples.len() as f64) * ratio).round().max(1.0) as usize;
        let cutoff = ratio.min(1.0) * 0.95; // fraction of the source Nyquist
        let half = (16.0 / cutoff).ceil() as i64;
        let src = &self.samples;
        let mut out: Vec<f32> = (0..n_out)
            .map(|j| {
                let x = j as f64 / ratio;
                let centre = x.floor() as i64;
                let mut acc = 0.0;
                for k in (centre - half + 1)..=(centre + half) {
                    if k < 0 || k as usize >= src.len() {
                        continue;
                    }
                    let d = x - k as f64;
                    let w = if d.abs() >= half as f64 {
                        0.0
                    } else {
                        // Hann window over ±half.
                        0.5 + 0.5 * (std::f64::consts::PI * d / half as f64).cos()
                    };
                    let arg = std::f64::consts::PI * d * cutoff;
                    let sinc = if arg.abs() < 1e-12 {
                        1.0
                    } else {
                        arg.sin() / arg
                    };
                    acc += src[k as usize] as f64 * cutoff * sinc * w;
                }
                acc as f32
            })
            .collect();
        let rms = (out.iter().map(|&v| (v as f64).powi(2)).sum::<f64>() / out.len() as f64).sqrt();
        if rms > 1e-9 {
            let s = (1.0 / rms) as f32;
            out.iter_mut().for_each(|v| *v *= s);
        }
        out
    }
}

/// Reads a fitted sample at output position `i` (see the module docs): straight for a sample at
/// least as long as the breath, looped with an equal-power crossfade of `xfade` samples otherwise.
pub(crate) fn fitted_at(samples: &[f32], i: usize, breath_len: usize, xfade: usize) -> f32 {
    let len = samples.len();
    if len == 0 {
        return 0.0;
    }
    if breath_len <= len {
        return samples[i.min(len - 1)];
    }
    let xfade = xfade.min(len / 4).max(1);
    let period = len - xfade;
    let k = i / period;
    let j = i % period;
    if k == 0 || j >= xfade {
        return samples[j];
    }
    // Head of repetition k overlaps the tail of repetition k − 1.
    let x = (j as f32 + 0.5) / xfade as f32;
    let (fade_in, fade_out) = (
        (0.5 * std::f32::consts::PI * x).sin(),
        (0.5 * std::f32::consts::PI * x).cos(),
    );
    samples[j] * fade_in + samples[period + j] * fade_out
}
