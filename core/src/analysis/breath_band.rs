//! Band levels of each frame for telling breath noise from other unvoiced sound in a pause.
//!
//! An inhalation is broadband noise, flat-ish from 0.5 to 5 kHz with some formant colouring;
//! /s/ and /sh/ put most of their energy above 2.5 kHz; a reverberant tail and room rumble
//! carry most of theirs under 500 Hz. Three band levels tell these apart:
//!
//! | band   | pass band        |
//! |--------|------------------|
//! | low    | 100–400 Hz       |
//! | mid    | 500–2500 Hz      |
//! | high   | 2500–3500 Hz     |
//!
//! They cost no work per sample: [`BandSpectrum`] sums the power spectrum that the pitch
//! analysis already takes of its long window (about 40 ms centred on the frame, at the internal
//! rate of 8–16 kHz, see [`crate::analysis::NsdfPitch`]) over each band's bins. Each bin's power
//! is divided by the power gain of the chain in front of that window (the decimation low-pass
//! and the 120 Hz high-pass), so a band reads what the host signal holds there. The high band
//! ends at 3.5 kHz because that is inside every internal rate's reach: at the lowest (8 kHz)
//! the decimation filter is 13 dB down there and 60 dB down at 4.5 kHz, whose alias would
//! land there, so the compensated band is clean at every host rate from 8 kHz to 768 kHz
//! and means the same everywhere. The band edges are the bins' edges (no filter skirts:
//! adjacent bands do not overlap); the window is rectangular, so a strong tone leaks into
//! the next band about 20 dB down. A frame's levels depend only on its window, so they are
//! bit-identical for any block partition. Allocation happens only in [`BandSpectrum::new`].

use realfft::num_complex::Complex;

use super::level::{amplitude_to_db, band_power, LEVEL_FLOOR_DB};

/// The three bands' edges, Hz: low, mid, high.
const BANDS_HZ: [(f64, f64); 3] = [(100.0, 400.0), (500.0, 2500.0), (2500.0, 3500.0)];
/// The front chain's power gain is compensated down to this (−20 dB); bins weaker than that
/// count with this gain. With the default 120 Hz high-pass they do not occur inside the bands
/// at any supported rate; with `highpass_hz` above about 316 Hz the low band's lowest bins
/// fall under it and read low.
const MIN_POWER_GAIN: f64 = 0.01;

/// The levels of one frame in three bands, dBFS (floor −120 dBFS), over the pitch analysis's
/// long window (see [`crate::analysis::FeatureFrame::bands`]), and how flat the mid band's
/// spectrum is. The default (levels 0, a flat spectrum) only fills test frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandLevels {
    /// Level of 100–400 Hz, dBFS: voice fundamentals, vowel tails, rumble.
    pub low_db: f32,
    /// Level of 500–2500 Hz, dBFS: where breath noise carries its formant colouring.
    pub mid_db: f32,
    /// Level of 2500–3500 Hz, dBFS: sibilants.
    pub high_db: f32,
    /// Spectral flatness of 500–2500 Hz: the geometric over the arithmetic mean of its bins'
    /// power, 0 to 1. Noise through this rectangular window reads about 0.56 (white noise;
    /// real inhalations 0.28–0.57 as runs), tones that stand out in the band (an instrument, a
    /// sung note, a chord) far less (a string bed's swells 0.06–0.12 as runs, a steady chord
    /// under 0.15 per frame).
    pub mid_flatness: f32,
}

impl Default for BandLevels {
    fn default() -> Self {
        Self {
            low_db: 0.0,
            mid_db: 0.0,
            high_db: 0.0,
            mid_flatness: 1.0,
        }
    }
}

impl BandLevels {
    /// All three bands at the −120 dBFS floor (a silent window, [`LEVEL_FLOOR_DB`]; its
    /// spectrum counts as flat).
    pub const FLOOR: Self = Self {
        low_db: LEVEL_FLOOR_DB,
        mid_db: LEVEL_FLOOR_DB,
        high_db: LEVEL_FLOOR_DB,
        mid_flatness: 1.0,
    };

    /// The high band over the mid band, dB: about 0 or below for breath noise, well above 0
    /// for /s/.
    pub fn high_over_mid_db(&self) -> f32 {
        self.high_db - self.mid_db
    }

    /// The low band over the mid band, dB: high for vowel tails, hum and rumble.
    pub fn low_over_mid_db(&self) -> f32 {
        self.low_db - self.mid_db
    }

    /// The mid and high bands together (0.5–3.5 kHz, where breath noise lies), dBFS: a
    /// breath's level apart from the hum and rumble that can carry a room's full-band level.
    pub fn breath_bands_db(&self) -> f32 {
        (10.0 * (band_power(self.mid_db) + band_power(self.high_db)).log10()) as f32
    }
}

/// The share of the band's mean power a bin counts with at least in the flatness (−30 dB).
const EMPTY_BIN_SHARE: f64 = 1e-3;

/// The bins of each band in a power spectrum of a fixed FFT length, with each bin's weight.
#[derive(Debug, Clone)]
pub(crate) struct BandSpectrum {
    /// Per band: its first bin and one past its last.
    bins: [(usize, usize); 3],
    /// Per bin (index = bin): 1 / the front chain's power gain there, times the scale that
    /// turns a sum of |X|² into a mean square of the window (2 / (fft_len · window_len)).
    weights: Vec<f64>,
}

impl BandSpectrum {
    /// The bands for an FFT of `fft_len` points over a zero-padded window of `window_len`
    /// samples at `rate_hz`; `power_gain(f_hz)` is the power gain of everything in front of
    /// the window at `f_hz`. Allocates.
    pub(crate) fn new(
        rate_hz: f64,
        fft_len: usize,
        window_len: usize,
        power_gain: impl Fn(f64) -> f64,
    ) -> Self {
        let bin_hz = rate_hz / fft_len as f64;
        let last = fft_len / 2;
        // Bin k (centre k · bin_hz) belongs to a band when from ≤ k · bin_hz < to.
        let bin_at = |hz: f64| ((hz / bin_hz).ceil() as usize).min(last);
        let bins = BANDS_HZ.map(|(from, to)| (bin_at(from).max(1), bin_at(to)));
        let scale = 2.0 / (fft_len as f64 * window_len.max(1) as f64);
        let weights = (0..bins[2].1)
            .map(|k| scale / power_gain(k as f64 * bin_hz).max(MIN_POWER_GAIN))
            .collect();
        Self { bins, weights }
    }

    /// The band levels of `power` (|X|² in the real parts, bins 0..=fft_len/2).
    pub(crate) fn levels(&self, power: &[Complex<f32>]) -> BandLevels {
        let [low, mid, high] = self.bins.map(|(a, b)| {
            power[a..b]
                .iter()
                .zip(&self.weights[a..b])
                .fold(0.0f64, |s, (p, w)| s + p.re as f64 * w)
        });
        BandLevels {
            low_db: amplitude_to_db(low.sqrt()),
            mid_db: amplitude_to_db(mid.sqrt()),
            high_db: amplitude_to_db(high.sqrt()),
            mid_flatness: self.flatness(power, self.bins[1], mid),
        }
    }

    /// The spectral flatness of bins `a..b` of `power`, whose weighted power sums to `sum` (the
    /// band's level, already taken; a silent band is flat). A bin counts with at least [`EMPTY_BIN_SHARE`] of the band's mean power:
    /// a band left partly empty by a codec's low-pass or a denoiser would otherwise read as
    /// tonal, its empty bins ruling the geometric mean.
    fn flatness(&self, power: &[Complex<f32>], (a, b): (usize, usize), sum: f64) -> f32 {
        let n = (b - a) as f64;
        let mean = sum / n;
        if b <= a || mean <= 0.0 {
            return 1.0;
        }
        let floor = mean * EMPTY_BIN_SHARE;
        let (log_sum, floored_sum) = power[a..b]
            .iter()
            .zip(&self.weights[a..b])
            .map(|(p, w)| (p.re as f64 * w).max(floor))
            .fold((0.0f64, 0.0f64), |(l, s), q| (l + q.ln(), s + q));
        ((log_sum / n).exp() / (floored_sum / n)).clamp(0.0, 1.0) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{AnalysisConfig, Analyzer};

    /// The median band levels of the frames of a steady sine at `hz` of amplitude 0.5
    /// (−9.03 dBFS RMS) at host rate `rate_hz`, after a settling half second.
    fn levels_of_tone(hz: f64, rate_hz: f64) -> BandLevels {
        let x: Vec<f32> = (0..(rate_hz * 1.5) as usize)
            .map(|i| 0.5 * (2.0 * std::f64::consts::PI * hz * i as f64 / rate_hz).sin() as f32)
            .collect();
        let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
        a.prepare(rate_hz, 512).expect("rate");
        let mut frames = Vec::new();
        a.process(&x, |f| frames.push(f.bands)).expect("prepared");
        let steady = &mut frames[60..];
        let median = |get: fn(&BandLevels) -> f32| {
            let mut v: Vec<f32> = steady.iter().map(get).collect();
            v.sort_by(f32::total_cmp);
            v[v.len() / 2]
        };
        BandLevels {
            low_db: median(|b| b.low_db),
            mid_db: median(|b| b.mid_db),
            high_db: median(|b| b.high_db),
            mid_flatness: median(|b| b.mid_flatness),
        }
    }

    #[test]
    fn a_tone_lands_in_its_band_at_any_rate() {
        // 44.1 kHz and 22.05 kHz analyse at 8.82 and 11.025 kHz, the others at 8 kHz (where
        // the decimation filter is 6 to 13 dB down at 3.2 to 3.5 kHz: compensated).
        for rate in [8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 192_000.0] {
            let low = levels_of_tone(200.0, rate);
            let mid = levels_of_tone(1200.0, rate);
            let high = levels_of_tone(3300.0, rate);
            // Its own band reads the tone's level; the others are at least 20 dB under it (the
            // rectangular window's leakage).
            let own = |db: f32| (db + 9.03).abs() < 1.0;
            let leak = |db: f32| db < -29.0;
            assert!(own(low.low_db), "{rate}: {low:?}");
            assert!(leak(low.mid_db) && leak(low.high_db), "{rate}: {low:?}");
            assert!(own(mid.mid_db), "{rate}: {mid:?}");
            assert!(leak(mid.low_db) && leak(mid.high_db), "{rate}: {mid:?}");
            assert!(own(high.high_db), "{rate}: {high:?}");
            assert!(leak(high.low_db) && leak(high.mid_db), "{rate}: {high:?}");
        }
    }

    /// The median mid-band flatness of the frames of `x` at `rate_hz`, after a settling
    /// half second.
    fn median_flatness(x: &[f32], rate_hz: f64) -> f32 {
        let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
        a.prepare(rate_hz, 512).expect("rate");
        let mut v = Vec::new();
        a.process(x, |f| v.push(f.bands.mid_flatness))
            .expect("prepared");
        let mut steady = v[60..].to_vec();
        steady.sort_by(f32::total_cmp);
        steady[steady.len() / 2]
    }

    #[test]
    fn noise_is_flat_and_a_chord_is_not_at_any_rate() {
        for rate in [8_000.0, 22_050.0, 44_100.0, 96_000.0] {
            let n = (rate * 1.5) as usize;
            let mut rng = crate::rng::SeededRng::new(7);
            let noise: Vec<f32> = (0..n).map(|_| 0.1 * rng.normal() as f32).collect();
            // A major chord on A4 with its first harmonics, as a bed under a voice plays.
            let chord: Vec<f32> = (0..n)
                .map(|i| {
                    let t = i as f64 / rate;
                    [440.0, 554.37, 659.25]
                        .iter()
                        .flat_map(|f| (1..=4).map(move |h| (f * h as f64, 0.05 / h as f64)))
                        .map(|(f, a)| a * (2.0 * std::f64::consts::PI * f * t).sin())
                        .sum::<f64>() as f32
                })
                .collect();
            let (flat_noise, flat_chord) =
                (median_flatness(&noise, rate), median_flatness(&chord, rate));
            assert!(
                (0.4..0.7).contains(&flat_noise),
                "{rate}: noise {flat_noise}"
            );
            assert!(flat_chord < 0.15, "{rate}: chord {flat_chord}");
        }
    }

    #[test]
    fn noise_with_part_of_the_band_emptied_is_still_noise() {
        // A noise periodogram over the mid band whose top fifth a codec's low-pass emptied
        // (160 dB down): its empty bins must not rule the geometric mean.
        let b = BandSpectrum::new(8_000.0, 512, 320, |_| 1.0);
        let (lo, hi) = b.bins[1];
        let mut rng = crate::rng::SeededRng::new(3);
        let mut power = vec![Complex::default(); 257];
        for (k, p) in power.iter_mut().enumerate().take(hi).skip(lo) {
            // |X|² of white noise: exponentially distributed.
            let full = -(1.0 - rng.uniform()).ln() as f32;
            p.re = if k < lo + (hi - lo) * 4 / 5 {
                full
            } else {
                full * 1e-16
            };
        }
        let flatness = b.levels(&power).mid_flatness;
        assert!(flatness > 0.2, "{flatness}");
    }

    #[test]
    fn silence_is_the_floor() {
        let b = BandSpectrum::new(8_000.0, 486, 320, |_| 1.0);
        assert_eq!(b.levels(&[Complex::default(); 244]), BandLevels::FLOOR);
    }
}
