//! Third-octave spectra of short sounds (breaths): the power in each band from 250 Hz to
//! 6.3 kHz, the shape (dB relative to the bands' own mean) and the log-spectral distance
//! between two shapes. The breath voice learns its envelope in these bands
//! ([`super::learned`]) and the breath evaluations measure in them.
//!
//! The room's noise floor per band is the mean over a recording's quietest 5 % of frames
//! ([`FloorEstimate`], bounded memory); a breath's band powers have it subtracted
//! ([`without_floor`]).
//!
//! A breath's **level** is its mean square in these bands ([`band_level_db`]), with the floor
//! taken out per band for a real breath: the learned voice learns it and the evaluations score
//! inserted against real breaths with it, so both mean the same thing. (A full-band mean square
//! would count the rumble and DC drift under 250 Hz that a recording's quiet frames hold and a
//! breath does not.)
//!
//! Band powers: Hann frames of [`frame_len`] samples (at least 25 ms, a power of two: 512 at
//! 16 and 20 kHz) every half frame, powers averaged over the sound and summed per band (edges
//! at the centre × 2^(±1/6)). [`BandAnalyzer::new`] allocates (an FFT plan): not for the audio
//! thread.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{RealFftPlanner, RealToComplex};

/// Third-octave band centres, Hz (250 Hz to 6.3 kHz: where breath noise lies, above mains hum
/// and below the Nyquist frequency of 16 kHz recordings).
pub const BAND_CENTRES_HZ: [f64; 15] = [
    250.0, 315.0, 400.0, 500.0, 630.0, 800.0, 1000.0, 1250.0, 1600.0, 2000.0, 2500.0, 3150.0,
    4000.0, 5000.0, 6300.0,
];

/// Number of bands.
pub const BANDS: usize = BAND_CENTRES_HZ.len();

/// Powers or levels per band.
pub type Bands = [f64; BANDS];

/// Shortest analysis frame, seconds.
const MIN_FRAME_S: f64 = 0.025;

/// The analysis frame at `rate_hz`: the power of two of at least 25 ms (512 at 16–20 kHz).
pub fn frame_len(rate_hz: f64) -> usize {
    ((MIN_FRAME_S * rate_hz).ceil().max(16.0) as usize).next_power_of_two()
}

/// The ratio of a band's upper (lower) edge to its centre: 2^(1/6).
pub fn band_edge_ratio() -> f64 {
    2f64.powf(1.0 / 6.0)
}

/// The band holding `hz`: edges at the centre × 2^(±1/6).
pub fn band_of(hz: f64) -> Option<usize> {
    let edge = band_edge_ratio();
    BAND_CENTRES_HZ
        .iter()
        .position(|&c| hz >= c / edge && hz < c * edge)
}

/// Third-octave band powers at one rate: the FFT plan and buffers, made once.
pub struct BandAnalyzer {
    fft: Arc<dyn RealToComplex<f64>>,
    window: Vec<f64>,
    bins: Vec<Option<usize>>,
    input: Vec<f64>,
    spectrum: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl std::fmt::Debug for BandAnalyzer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BandAnalyzer")
            .field("frame", &self.window.len())
            .finish()
    }
}

impl BandAnalyzer {
    /// An analyzer for sounds at `rate_hz`. Allocates.
    pub fn new(rate_hz: f64) -> Self {
        let frame = frame_len(rate_hz);
        let fft = RealFftPlanner::<f64>::new().plan_fft_forward(frame);
        Self {
            window: (0..frame)
                .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / frame as f64).cos())
                .collect(),
            bins: (0..=frame / 2)
                .map(|k| band_of(k as f64 * rate_hz / frame as f64))
                .collect(),
            input: fft.make_input_vec(),
            spectrum: fft.make_output_vec(),
            scratch: fft.make_scratch_vec(),
            fft,
        }
    }

    /// The analysis frame, samples.
    pub fn frame(&self) -> usize {
        self.window.len()
    }

    /// Mean power per band of `x` (one zero-padded frame when `x` is shorter than a frame).
    /// Allocation-free.
    pub fn powers(&mut self, x: &[f32]) -> Bands {
        let frame = self.frame();
        let hop = frame / 2;
        let mut bands = [0.0; BANDS];
        let mut frames = 0usize;
        let mut start = 0;
        loop {
            for (i, v) in self.input.iter_mut().enumerate() {
                *v = x.get(start + i).map_or(0.0, |s| f64::from(*s)) * self.window[i];
            }
            self.fft
                .process_with_scratch(&mut self.input, &mut self.spectrum, &mut self.scratch)
                .expect("buffers made by the plan");
            for (c, b) in self.spectrum.iter().zip(&self.bins) {
                if let Some(b) = b {
                    bands[*b] += c.norm_sqr();
                }
            }
            frames += 1;
            start += hop;
            if start + frame > x.len() {
                break;
            }
        }
        bands.map(|p| p / frames as f64)
    }

    /// The power of every FFT bin (0 to half the frame, bin `k` at `k · rate / frame`) of the
    /// last frame [`BandAnalyzer::powers`] took: the whole spectrum, the bands' and beyond.
    pub fn last_bin_powers(&self) -> impl Iterator<Item = f64> + '_ {
        self.spectrum.iter().map(|c| c.norm_sqr())
    }
}

/// Mean power per band of `x` at `rate_hz` ([`BandAnalyzer::powers`]).
pub fn band_powers(x: &[f32], rate_hz: f64) -> Bands {
    BandAnalyzer::new(rate_hz).powers(x)
}

/// The mean square in the bands of a sound whose band powers ([`BandAnalyzer::powers`] at
/// `rate_hz`) are `powers`, dB re full scale: the level of a breath (see the module docs).
pub fn band_level_db(powers: &Bands, rate_hz: f64) -> f64 {
    let n = frame_len(rate_hz) as f64;
    // Parseval with the periodic Hann window (sum of squares 3N/8): a one-sided bin's power
    // |X|² is a mean square of 2 |X|² / (N · 3N/8).
    let mean_square = powers.iter().sum::<f64>() * 16.0 / (3.0 * n * n);
    10.0 * mean_square.max(1e-20).log10()
}

/// Band levels as dB relative to their own mean (the shape of the spectrum).
pub fn shape_db(powers: &Bands) -> Bands {
    let db = powers.map(|p| 10.0 * p.max(1e-20).log10());
    let mean = db.iter().sum::<f64>() / db.len() as f64;
    db.map(|d| d - mean)
}

/// Log-spectral distance between two shapes: the RMS of their difference over the bands, dB.
pub fn distance_db(a: &Bands, b: &Bands) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    (sum / a.len() as f64).sqrt()
}

/// The mean of several shapes (NaN bands when there are none).
pub fn mean_shape(shapes: &[Bands]) -> Bands {
    if shapes.is_empty() {
        return [f64::NAN; BANDS];
    }
    let mut m = [0.0; BANDS];
    for s in shapes {
        for (a, b) in m.iter_mut().zip(s) {
            *a += b / shapes.len() as f64;
        }
    }
    m
}

/// Width of a bin of [`FloorEstimate`]'s level histogram, dB.
const FLOOR_BIN_DB: f64 = 0.5;
/// Bins of [`FloorEstimate`]: −150 dB to +10 dB (total band power of a frame).
const FLOOR_BINS: usize = 320;
/// Lowest level [`FloorEstimate`] bins, dB.
const FLOOR_LOWEST_DB: f64 = -150.0;
/// Share of the quietest frames that make the floor.
const FLOOR_SHARE: f64 = 0.05;

/// The room's noise floor per band, learned frame by frame in bounded memory: the mean band
/// powers of the quietest 5 % of the frames (by total band power, to within
/// a 0.5 dB histogram bin; digitally silent frames are left out).
#[derive(Debug, Clone)]
pub struct FloorEstimate {
    count: Vec<u64>,
    sums: Vec<Bands>,
    frames: u64,
}

impl Default for FloorEstimate {
    fn default() -> Self {
        Self {
            count: vec![0; FLOOR_BINS],
            sums: vec![[0.0; BANDS]; FLOOR_BINS],
            frames: 0,
        }
    }
}

impl FloorEstimate {
    /// Forgets every frame (allocation-free).
    pub fn clear(&mut self) {
        self.count.fill(0);
        self.sums.fill([0.0; BANDS]);
        self.frames = 0;
    }

    /// Adds one frame's band powers.
    pub fn add(&mut self, bands: &Bands) {
        let total: f64 = bands.iter().sum();
        if total <= 1e-15 {
            return;
        }
        let db = 10.0 * total.log10();
        let bin = (((db - FLOOR_LOWEST_DB) / FLOOR_BIN_DB).max(0.0) as usize).min(FLOOR_BINS - 1);
        self.count[bin] += 1;
        for (s, p) in self.sums[bin].iter_mut().zip(bands) {
            *s += p;
        }
        self.frames += 1;
    }

    /// The floor's band powers (0 before any frame).
    pub fn floor(&self) -> Bands {
        let want = ((self.frames as f64 * FLOOR_SHARE).ceil() as u64).max(1);
        let (mut n, mut bands) = (0u64, [0.0; BANDS]);
        for bin in 0..FLOOR_BINS {
            if n >= want {
                break;
            }
            n += self.count[bin];
            for (b, s) in bands.iter_mut().zip(&self.sums[bin]) {
                *b += s;
            }
        }
        let n = n.max(1) as f64;
        bands.map(|b| b / n)
    }
}

/// The room's noise floor per band in `x` (frames of [`frame_len`], back to back, through a
/// [`FloorEstimate`]).
pub fn noise_floor(x: &[f32], rate_hz: f64) -> Bands {
    let mut a = BandAnalyzer::new(rate_hz);
    let mut est = FloorEstimate::default();
    for c in x.chunks_exact(a.frame()) {
        est.add(&a.powers(c));
    }
    est.floor()
}

/// Band powers of a sound in a room with `floor` band powers: the floor subtracted in power,
/// never below a tenth of the measured power.
pub fn without_floor(powers: &Bands, floor: &Bands) -> Bands {
    std::array::from_fn(|b| (powers[b] - floor[b]).max(0.1 * powers[b]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tone_lands_in_its_band_and_the_shape_is_relative_to_the_mean() {
        for rate in [16_000.0, 48_000.0] {
            let x: Vec<f32> = (0..rate as usize / 2)
                .map(|i| (2.0 * std::f64::consts::PI * 1000.0 * i as f64 / rate).sin() as f32)
                .collect();
            let p = band_powers(&x, rate);
            let loudest = (0..p.len()).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
            assert_eq!(BAND_CENTRES_HZ[loudest], 1000.0);
            // Two bands away the Hann window's leakage is at least 40 dB down.
            assert!(10.0 * (p[loudest] / p[loudest + 2]).log10() > 40.0, "{p:?}");
            let s = shape_db(&p);
            assert!(s.iter().sum::<f64>().abs() < 1e-9);
        }
    }

    #[test]
    fn every_band_holds_a_bin_at_every_rate_and_the_frame_is_25_ms_or_more() {
        for rate in [8_000.0, 16_000.0, 20_000.0, 44_100.0, 48_000.0, 96_000.0] {
            let frame = frame_len(rate);
            assert!(frame as f64 >= 0.025 * rate && frame.is_power_of_two());
            let highest = BAND_CENTRES_HZ
                .iter()
                .filter(|&&c| c * 2f64.powf(1.0 / 6.0) < rate / 2.0)
                .count();
            for b in 0..highest {
                let has =
                    (0..=frame / 2).any(|k| band_of(k as f64 * rate / frame as f64) == Some(b));
                assert!(has, "band {b} has no bin at {rate} Hz");
            }
        }
        assert_eq!(frame_len(16_000.0), 512);
    }

    #[test]
    fn the_band_level_of_white_noise_is_its_mean_square_in_the_bands() {
        let mut rng = crate::rng::SeededRng::new(5);
        for rate in [16_000.0, 48_000.0] {
            // Unit-variance white noise: its share of the band 222.7 Hz–7.07 kHz of rate / 2.
            let x: Vec<f32> = (0..rate as usize)
                .map(|_| ((rng.uniform() * 2.0 - 1.0) * 3f64.sqrt()) as f32)
                .collect();
            let edge = band_edge_ratio();
            let share =
                (BAND_CENTRES_HZ[BANDS - 1] * edge - BAND_CENTRES_HZ[0] / edge) / (rate / 2.0);
            let got = band_level_db(&band_powers(&x, rate), rate);
            assert!((got - 10.0 * share.log10()).abs() < 0.2, "{rate}: {got}");
        }
    }

    #[test]
    fn the_distance_is_zero_for_one_shape_and_grows_with_a_tilt() {
        let flat = [0.0; BANDS];
        assert_eq!(distance_db(&flat, &flat), 0.0);
        let tilt: Bands = std::array::from_fn(|b| b as f64 - 7.0);
        // RMS of -7..=7: sqrt(280 / 15).
        assert!((distance_db(&tilt, &flat) - (280.0f64 / 15.0).sqrt()).abs() < 1e-12);
    }
}
