//! The pitch estimator: McLeod's normalised square difference function (NSDF) on `realfft`.
//!
//! For a window `x` of `W` samples the NSDF is `n(τ) = 2·r(τ) / m(τ)` with
//! `r(τ) = Σ x[j]·x[j+τ]` (computed by FFT, zero-padded so it is a linear, not circular,
//! correlation) and `m(τ) = Σ (x[j]² + x[j+τ]²)` over the same `W − τ` overlapping samples: the
//! true normalisation, which makes `n` lie in −1..1 and reach 1 for a perfectly periodic window
//! at every lag that is a multiple of the period. Key maxima are the highest points of each
//! positive lobe after the first negative-going zero crossing; the period is the first key
//! maximum at least `key_max_ratio` × the highest one (this rule prefers the true period over
//! its multiples, against octave-down errors, while a lobe at half the period only wins when it
//! is nearly as periodic as the true one). Parabolic interpolation refines the lag and the peak
//! height, which is the clarity.
//!
//! Plans and buffers are made in [`NsdfPitch::new`]; [`NsdfPitch::analyse`] never allocates.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

/// Most key maxima kept per frame.
pub const MAX_CANDIDATES: usize = 16;

/// One period candidate: a key maximum of the NSDF.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PitchEstimate {
    /// Frequency in Hz (0 when there is no candidate).
    pub f0_hz: f32,
    /// Interpolated NSDF peak height, 0..1 (periodicity).
    pub clarity: f32,
}

/// NSDF pitch estimator for windows of a fixed length at a fixed rate.
pub struct NsdfPitch {
    rate_hz: f64,
    window_len: usize,
    lag_min: usize,
    lag_max: usize,
    key_max_ratio: f32,
    r2c: Arc<dyn RealToComplex<f32>>,
    c2r: Arc<dyn ComplexToReal<f32>>,
    time: Vec<f32>,
    spectrum: Vec<Complex<f32>>,
    scratch: Vec<Complex<f32>>,
    acf: Vec<f32>,
    nsdf: Vec<f32>,
    candidates: [PitchEstimate; MAX_CANDIDATES],
    n_candidates: usize,
    periodicity: f32,
}

impl std::fmt::Debug for NsdfPitch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NsdfPitch")
            .field("rate_hz", &self.rate_hz)
            .field("window_len", &self.window_len)
            .field("lag_min", &self.lag_min)
            .field("lag_max", &self.lag_max)
            .field("fft_len", &self.time.len())
            .finish()
    }
}

/// Smallest 5-smooth number (2^a·3^b·5^c) not below `n`: sizes the FFT is fast at.
fn fft_len_for(n: usize) -> usize {
    let mut m = n.max(2);
    loop {
        let mut k = m;
        for p in [2, 3, 5] {
            while k.is_multiple_of(p) {
                k /= p;
            }
        }
        if k == 1 {
            return m;
        }
        m += 1;
    }
}

impl NsdfPitch {
    /// An estimator for windows of `window_len` samples at `rate_hz`, searching
    /// `f0_min_hz..=f0_max_hz`. Allocates and plans the FFTs.
    pub fn new(
        rate_hz: f64,
        window_len: usize,
        f0_min_hz: f32,
        f0_max_hz: f32,
        key_max_ratio: f32,
    ) -> Self {
        let lag_min = ((rate_hz / f0_max_hz as f64).floor() as usize).max(2);
        let lag_max = ((rate_hz / f0_min_hz as f64).ceil() as usize)
            .min(window_len.saturating_sub(2))
            .max(lag_min + 2);
        let fft_len = fft_len_for(window_len + lag_max + 2);
        let mut planner = RealFftPlanner::<f32>::new();
        let r2c = planner.plan_fft_forward(fft_len);
        let c2r = planner.plan_fft_inverse(fft_len);
        let scratch_len = r2c.get_scratch_len().max(c2r.get_scratch_len());
        Self {
            rate_hz,
            window_len,
            lag_min,
            lag_max,
            key_max_ratio,
            time: r2c.make_input_vec(),
            spectrum: r2c.make_output_vec(),
            scratch: vec![Complex::default(); scratch_len],
            acf: c2r.make_output_vec(),
            nsdf: vec![0.0; lag_max + 2],
            r2c,
            c2r,
            candidates: [PitchEstimate::default(); MAX_CANDIDATES],
            n_candidates: 0,
            periodicity: 0.0,
        }
    }

    /// Window length in samples.
    pub fn window_len(&self) -> usize {
        self.window_len
    }

    /// The key maxima of the last analysed window, shortest period (highest f0) first.
    pub fn candidates(&self) -> &[PitchEstimate] {
        &self.candidates[..self.n_candidates]
    }

    /// Periodicity of the last analysed window, 0..1: the height of its highest key maximum,
    /// which the key-maximum rule may pass over for a slightly lower peak at the true period.
    pub fn periodicity(&self) -> f32 {
        self.periodicity
    }

    /// The NSDF of the last analysed window, lags 0..=lag_max+1.
    pub fn nsdf(&self) -> &[f32] {
        &self.nsdf
    }

    /// Analyses one window of exactly [`Self::window_len`] samples (any other length gives a
    /// zero estimate). The mean is removed first, so DC offsets do not
    /// matter. Returns the period chosen by the key-maximum rule, or a zero estimate when the
    /// window has no periodic structure in range.
    pub fn analyse(&mut self, window: &[f32]) -> PitchEstimate {
        self.n_candidates = 0;
        self.periodicity = 0.0;
        if window.len() != self.window_len {
            return PitchEstimate::default();
        }
        let w = self.window_len;
        let mean = window[..w].iter().map(|&x| x as f64).sum::<f64>() / w.max(1) as f64;
        let mean = mean as f32;
        let mut energy = 0.0f64;
        for (t, &x) in self.time.iter_mut().zip(&window[..w]) {
            *t = x - mean;
            energy += (*t as f64) * (*t as f64);
        }
        self.time[w..].fill(0.0);
        if energy < 1e-12 * w as f64 {
            self.nsdf.fill(0.0);
            return PitchEstimate::default();
        }
        // r(τ) by FFT: |X|² then inverse. Plans and buffers are sized in new(), so the only
        // failure is impossible here; fall back to "no pitch" rather than panic.
        if self
            .r2c
            .process_with_scratch(&mut self.time, &mut self.spectrum, &mut self.scratch)
            .is_err()
        {
            return PitchEstimate::default();
        }
        for c in self.spectrum.iter_mut() {
            *c = Complex::new(c.norm_sqr(), 0.0);
        }
        if self
            .c2r
            .process_with_scratch(&mut self.spectrum, &mut self.acf, &mut self.scratch)
            .is_err()
        {
            return PitchEstimate::default();
        }
        // m(0) = 2·Σx²; later lags drop one sample from each end (the forward pass overwrote
        // `time`, so the ends are read from the window itself).
        let mut m = 2.0 * energy;
        let scale = 1.0 / self.time.len() as f64;
        for tau in 0..self.nsdf.len() {
            if tau > 0 {
                let a = (window[tau - 1] - mean) as f64;
                let b = (window[w - tau] - mean) as f64;
                m -= a * a + b * b;
            }
            let r = self.acf[tau] as f64 * scale;
            self.nsdf[tau] = if m > 1e-12 {
                (2.0 * r / m).clamp(-1.0, 1.0) as f32
            } else {
                0.0
            };
        }
        self.pick()
    }

    /// Key maxima and the key-maximum rule.
    fn pick(&mut self) -> PitchEstimate {
        let n = &self.nsdf;
        let last = self.lag_max.min(n.len() - 2);
        // Skip the lobe around lag 0: start after the first negative-going zero crossing.
        let mut tau = 1;
        while tau <= last && n[tau] > 0.0 {
            tau += 1;
        }
        let mut best = 0.0f32;
        while tau <= last {
            // Skip the negative region.
            while tau <= last && n[tau] <= 0.0 {
                tau += 1;
            }
            // Highest point of this positive lobe.
            let mut peak_tau = 0;
            let mut peak = f32::MIN;
            while tau <= last && n[tau] > 0.0 {
                if n[tau] > peak {
                    peak = n[tau];
                    peak_tau = tau;
                }
                tau += 1;
            }
            if peak_tau == 0 || peak_tau < self.lag_min {
                continue;
            }
            // A lobe cut off by the end of the search range is only a candidate if its highest
            // point is a true local maximum.
            if n[peak_tau + 1] > n[peak_tau] {
                continue;
            }
            let (a, b, c) = (n[peak_tau - 1], n[peak_tau], n[peak_tau + 1]);
            let denom = a - 2.0 * b + c;
            let (delta, height) = if denom < 0.0 {
                let d = (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
                (d, b - 0.25 * (a - c) * d)
            } else {
                (0.0, b)
            };
            let lag = peak_tau as f64 + delta as f64;
            let clarity = height.clamp(0.0, 1.0);
            let candidate = PitchEstimate {
                f0_hz: (self.rate_hz / lag) as f32,
                clarity,
            };
            best = best.max(clarity);
            if self.n_candidates == MAX_CANDIDATES {
                // Full (very low f0 with a bright spectrum has many lobes): drop the weakest
                // kept lobe if this one is stronger, keeping the lag order.
                let (weakest, w) =
                    self.candidates
                        .iter()
                        .enumerate()
                        .fold((0, f32::MAX), |m, (i, c)| {
                            if c.clarity < m.1 {
                                (i, c.clarity)
                            } else {
                                m
                            }
                        });
                if clarity <= w {
                    continue;
                }
                self.candidates.copy_within(weakest + 1.., weakest);
                self.n_candidates -= 1;
            }
            self.candidates[self.n_candidates] = candidate;
            self.n_candidates += 1;
        }
        self.periodicity = best;
        let threshold = self.key_max_ratio * best;
        self.candidates[..self.n_candidates]
            .iter()
            .copied()
            .find(|c| c.clarity >= threshold && c.clarity > 0.0)
            .unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tone(f0: f64, rate: f64, n: usize, harmonics: &[f64]) -> Vec<f32> {
        (0..n)
            .map(|i| {
                let t = i as f64 / rate;
                harmonics
                    .iter()
                    .enumerate()
                    .map(|(h, a)| a * (2.0 * std::f64::consts::PI * f0 * (h + 1) as f64 * t).sin())
                    .sum::<f64>() as f32
                    * 0.3
            })
            .collect()
    }

    #[test]
    fn many_lobes_do_not_hide_the_period() {
        // 52 Hz with all energy near 1 kHz: about 19 lobes before the true period.
        let rate = 8_000.0;
        let mut p = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
        let mut h = vec![0.0; 22];
        h[17] = 0.6;
        h[18] = 1.0;
        h[19] = 0.8;
        h[20] = 0.5;
        let x = tone(52.0, rate, 320, &h);
        let e = p.analyse(&x);
        // The true period stays among the candidates, as the strongest lobe, and the choice
        // lands near it rather than at a short lag (a narrow-band signal has near-equal lobes
        // around the period, so the key-maximum rule may take one a lobe or two early).
        let best = p
            .candidates()
            .iter()
            .copied()
            .fold(PitchEstimate::default(), |m, c| {
                if c.clarity > m.clarity {
                    c
                } else {
                    m
                }
            });
        assert!((best.f0_hz - 52.0).abs() < 1.0, "{:?}", p.candidates());
        assert!(e.f0_hz < 65.0, "{}", e.f0_hz);
        assert_eq!(p.analyse(&x[..100]), PitchEstimate::default());
    }

    #[test]
    fn fft_sizes_are_5_smooth() {
        assert_eq!(fft_len_for(483), 486);
        assert_eq!(fft_len_for(512), 512);
        assert_eq!(fft_len_for(532), 540);
    }

    #[test]
    fn finds_pure_and_rich_tones_across_the_range() {
        let rate = 8_000.0;
        let mut p = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
        for f0 in [55.0, 80.0, 110.0, 220.0, 330.0, 440.0, 550.0] {
            for h in [&[1.0][..], &[1.0, 0.6, 0.4, 0.3, 0.2]] {
                let x = tone(f0, rate, 320, h);
                let e = p.analyse(&x);
                let cents = 1200.0 * (e.f0_hz as f64 / f0).log2();
                assert!(
                    cents.abs() < 10.0,
                    "f0 {f0}: got {} ({cents} cents)",
                    e.f0_hz
                );
                assert!(e.clarity > 0.95, "f0 {f0}: clarity {}", e.clarity);
            }
        }
    }

    #[test]
    fn true_normalisation_ignores_amplitude_and_dc() {
        let rate = 8_000.0;
        let mut p = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
        let x = tone(200.0, rate, 320, &[1.0, 0.5]);
        let a = p.analyse(&x);
        let quiet: Vec<f32> = x.iter().map(|v| v * 1e-3 + 0.4).collect();
        let b = p.analyse(&quiet);
        assert!((a.f0_hz - b.f0_hz).abs() < 0.05);
        assert!((a.clarity - b.clarity).abs() < 1e-3);
    }

    #[test]
    fn noise_and_silence_have_low_clarity() {
        let mut p = NsdfPitch::new(8_000.0, 320, 50.0, 600.0, 0.88);
        assert_eq!(p.analyse(&[0.0; 320]), PitchEstimate::default());
        let mut s = 12345u32;
        let noise: Vec<f32> = (0..320)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 8) as f32 / (1u32 << 24) as f32 - 0.5
            })
            .collect();
        assert!(p.analyse(&noise).clarity < 0.5);
    }
}
