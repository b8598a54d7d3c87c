//! [`Nsdf`]: the normalised square difference function of one window length, with its FFT
//! plans and buffers, the low-pass it may hear the window through, and what its spectrum also
//! gives (the low band's share of the voice band, the breath bands).

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

use super::super::biquad::{Biquad, BiquadLanes};
use super::super::breath_band::{BandLevels, BandSpectrum};
use super::sums::{
    frame_means, short_starts, square_sum, FrameStats, Lanes, LanesX4, WindowStats, LANES,
};

/// The low band (Hz) whose share of the voice band's energy ([`super::NsdfPitch::low_band`]) tells
/// voiced sounds (energy in the first formant region) from fricatives and hiss.
const LOW_BAND_HZ: (f64, f64) = (80.0, 1000.0);
/// Top of the voice band for that share: the lowest internal rate's Nyquist frequency, so the
/// share means the same at every host rate.
const VOICE_BAND_TOP_HZ: f64 = 4000.0;

/// Behind the low-pass, r(τ) holds the filter's ringing past the window's end and m(τ) does
/// not, so a periodic window's NSDF peaks reach about 1.015: the curve is clamped here, not at
/// 1, so the parabolic refinement still sees the peak's shape (the clarity is clamped to 1).
pub(super) const HEARD_NSDF_MAX: f64 = 1.1;

/// The NSDF of one window length, with its FFT plans and buffers.
pub(super) struct Nsdf {
    pub(super) window_len: usize,
    pub(super) r2c: Arc<dyn RealToComplex<f32>>,
    pub(super) c2r: Arc<dyn ComplexToReal<f32>>,
    pub(super) time: Vec<f32>,
    pub(super) spectrum: Vec<Complex<f32>>,
    pub(super) scratch: Vec<Complex<f32>>,
    pub(super) acf: Vec<f32>,
    /// n(τ) for τ = 0..=lag_max+1.
    pub(super) curve: Vec<f32>,
    /// m(τ) for the same lags.
    norm: Vec<f64>,
    /// Spectrum bins of the low band and of the whole voice band (see `low_band`).
    pub(super) low_bins: (usize, usize),
    pub(super) band_bins: (usize, usize),
    /// Share of the last window's voice-band energy in the low band, 0..1 (kept up to date
    /// only when `measure_low_band`: the short windows' share is never asked for).
    pub(super) low_band: f32,
    pub(super) measure_low_band: bool,
    /// The breath bands read from the spectrum, when asked for ([`super::NsdfPitch::measure_bands`]),
    /// and their levels in the last window.
    pub(super) bands: Option<BandSpectrum>,
    pub(super) band_levels: BandLevels,
    /// The low-pass the NSDF hears the window through (see [`super::NsdfPitch::low_pass`]), its
    /// power gain per spectrum bin, and the window through it (from rest).
    pub(super) filter: Option<Biquad>,
    pub(super) weights: Vec<f32>,
    pub(super) heard: Vec<f32>,
    /// Energy of the last window as the NSDF hears it (about the mean, after the low-pass).
    pub(super) heard_energy: f64,
}

/// A window's statistics, and the window as the NSDF hears it with its energy (Σ h², in
/// [`Lanes`]) when those are known already ([`hear_frame`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Known<'a> {
    pub(super) stats: WindowStats,
    pub(super) heard: Option<(&'a [f32], f64)>,
}

/// One step of the NSDF's hearing: the centred sample `t` through `filter` (from its state).
#[inline(always)]
fn hear_one(filter: &mut Biquad, t: f32) -> f32 {
    filter.process(t as f64) as f32
}

/// The centred window `time` filtered from rest through `filter`, into `heard`.
fn hear(mut filter: Biquad, time: &[f32], heard: &mut [f32]) {
    for (h, &t) in heard.iter_mut().zip(time) {
        *h = hear_one(&mut filter, t);
    }
}

/// `x²` in f64.
#[inline(always)]
fn square(x: f32) -> f64 {
    (x as f64) * (x as f64)
}

/// The statistics of a frame's four windows ([`FrameStats::of`]) and the windows as the NSDF
/// hears them: the long window and its three short windows (oldest end, centre, newest end, of
/// `short_len` samples), each centred on its mean and filtered from rest through `filter`, into
/// `heard` (long, oldest, centre, newest), with their energies Σ h² (in that order). The same
/// bits as [`FrameStats::of`], [`hear`] and the [`Lanes`] sums one window after another, but in
/// one loop: the four recursions run side by side in [`BiquadLanes`] over the short windows'
/// length, and the long window's recursion alone after that; each output waits on the one
/// before it in its own window only, and the sums of squares (in the same lanes in the same
/// order) fill the time the recursions wait.
pub(super) fn hear_frame(
    filter: Biquad,
    window: &[f32],
    short_len: usize,
    heard: &mut [Vec<f32>; 4],
) -> (FrameStats, [f64; 4]) {
    let (w, len) = (window.len(), short_len);
    let means = frame_means(window, len);
    let [a, b, c] = short_starts(w, len);
    let (head, tail) = window.split_at(len);
    let (oldest_in, centre_in, newest_in) = (
        &window[a..a + len],
        &window[b..b + len],
        &window[c..c + len],
    );
    let [long, oldest, centre, newest] = heard;
    let (long_head, long_rest) = long[..w].split_at_mut(len);
    let (oldest, centre, newest) = (&mut oldest[..len], &mut centre[..len], &mut newest[..len]);
    let mut lanes = BiquadLanes::<4>::new(filter);
    let (mut energy, mut heard_energy) = (LanesX4::default(), LanesX4::default());
    for i in 0..len {
        let x = head[i];
        let t = [
            x - means[0],
            oldest_in[i] - means[1],
            centre_in[i] - means[2],
            newest_in[i] - means[3],
        ];
        let y = lanes.process(t.map(|t| t as f64));
        let h = y.map(|y| y as f32);
        long_head[i] = h[0];
        oldest[i] = h[1];
        centre[i] = h[2];
        newest[i] = h[3];
        let lane = i % LANES;
        energy.add_at(lane, t.map(square));
        heard_energy.add_at(lane, h.map(square));
    }
    let mut f = lanes.lane(0);
    let (mut long_energy, mut long_heard) = (energy.run(0), heard_energy.run(0));
    for (i, (h, &x)) in long_rest.iter_mut().zip(tail).enumerate() {
        let t = x - means[0];
        *h = hear_one(&mut f, t);
        let lane = (len + i) % LANES;
        long_energy.add_at(lane, square(t));
        long_heard.add_at(lane, square(*h));
    }
    let stats = FrameStats {
        long: WindowStats {
            mean: means[0],
            energy: long_energy.total(),
        },
        short: [1, 2, 3].map(|k| WindowStats {
            mean: means[k],
            energy: energy.run(k).total(),
        }),
        square_sum: square_sum(window),
    };
    let energies = [
        long_heard.total(),
        heard_energy.run(1).total(),
        heard_energy.run(2).total(),
        heard_energy.run(3).total(),
    ];
    (stats, energies)
}

/// m(τ) into `norm` for τ = 0, 1, ...: `m0` at lag 0, then at each lag the squares of the
/// window's two end samples (`end(i)` is sample `i` of the `w`-sample window as the NSDF hears
/// it) taken off, one running sum in f64.
#[inline(always)]
fn norms(norm: &mut [f64], m0: f64, w: usize, end: impl Fn(usize) -> f32) {
    let mut m = m0;
    for (tau, n) in norm.iter_mut().enumerate() {
        if tau > 0 {
            let (a, b) = (end(tau - 1) as f64, end(w - tau) as f64);
            m -= a * a + b * b;
        }
        *n = m;
    }
}

/// Smallest even 5-smooth number (2^a·3^b·5^c, a ≥ 1) not below `n`: sizes the real FFT is
/// fast at (an odd length would cost a full-length complex FFT).
pub(super) fn fft_len_for(n: usize) -> usize {
    let mut m = n.max(2).next_multiple_of(2);
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
        m += 2;
    }
}

impl Nsdf {
    pub(super) fn new(
        planner: &mut RealFftPlanner<f32>,
        rate_hz: f64,
        window_len: usize,
        lag_max: usize,
        measure_low_band: bool,
    ) -> Self {
        let fft_len = fft_len_for(window_len + lag_max + 2);
        let bin = |hz: f64| ((hz * fft_len as f64 / rate_hz).round() as usize).min(fft_len / 2);
        let r2c = planner.plan_fft_forward(fft_len);
        let c2r = planner.plan_fft_inverse(fft_len);
        let scratch_len = r2c.get_scratch_len().max(c2r.get_scratch_len());
        Self {
            window_len,
            time: r2c.make_input_vec(),
            spectrum: r2c.make_output_vec(),
            scratch: vec![Complex::default(); scratch_len],
            acf: c2r.make_output_vec(),
            curve: vec![0.0; lag_max + 2],
            norm: vec![0.0; lag_max + 2],
            low_bins: (bin(LOW_BAND_HZ.0), bin(LOW_BAND_HZ.1)),
            band_bins: (bin(LOW_BAND_HZ.0), bin(VOICE_BAND_TOP_HZ)),
            low_band: 0.0,
            measure_low_band,
            bands: None,
            band_levels: BandLevels::FLOOR,
            filter: None,
            weights: Vec::new(),
            heard: Vec::new(),
            heard_energy: 0.0,
            r2c,
            c2r,
        }
    }

    /// Computes the curve of `window` (exactly `window_len` samples, mean removed here); returns
    /// false (curve all zero) for a silent window.
    pub(super) fn compute(&mut self, window: &[f32]) -> bool {
        let stats = WindowStats::of(window);
        self.compute_with(window, Known { stats, heard: None })
    }

    /// [`Nsdf::compute`] with what is `known` of the window already.
    pub(super) fn compute_with(&mut self, window: &[f32], known: Known) -> bool {
        let w = self.window_len;
        let WindowStats { mean, energy } = known.stats;
        for (t, &x) in self.time.iter_mut().zip(window) {
            *t = x - mean;
        }
        self.time[w..].fill(0.0);
        self.low_band = 0.0;
        self.band_levels = BandLevels::FLOOR;
        self.heard_energy = energy;
        if energy < 1e-12 * w as f64 {
            self.curve.fill(0.0);
            return false;
        }
        // The window as the NSDF hears it (behind the low-pass), from `known` or heard here.
        let heard: Option<&[f32]> = match (self.filter, known.heard) {
            (None, _) => None,
            (Some(_), Some((heard, e))) => {
                self.heard_energy = e;
                Some(heard)
            }
            (Some(filter), None) => {
                hear(filter, &self.time[..w], &mut self.heard);
                let mut e = Lanes::default();
                e.add(&self.heard, square);
                self.heard_energy = e.total();
                Some(&self.heard)
            }
        };
        // r(τ) by FFT: |X|² then inverse. Plans and buffers are sized in new(), so the only
        // failure is impossible here; fall back to "no pitch" rather than panic.
        if self
            .r2c
            .process_with_scratch(&mut self.time, &mut self.spectrum, &mut self.scratch)
            .is_err()
        {
            self.curve.fill(0.0);
            return false;
        }
        for c in self.spectrum.iter_mut() {
            *c = Complex::new(c.norm_sqr(), 0.0);
        }
        if self.measure_low_band {
            if let Some(bands) = &self.bands {
                self.band_levels = bands.levels(&self.spectrum);
            }
        }
        // The breath bands are read before the low-pass, the low-band share after it. The
        // low-pass, applied to the power spectrum: r(τ) becomes the autocorrelation of the
        // filtered window (its ringing past the window's end included).
        for (c, &g) in self.spectrum.iter_mut().zip(&self.weights) {
            c.re *= g;
        }
        if self.measure_low_band {
            let ((la, lb), (ba, bb)) = (self.low_bins, self.band_bins);
            let power = |c: Complex<f32>| c.re as f64;
            let (mut low, mut band) = (Lanes::default(), Lanes::default());
            low.add(&self.spectrum[la..lb], power);
            band.add(&self.spectrum[ba..bb], power);
            let (low, band) = (low.total(), band.total());
            if band > 0.0 {
                self.low_band = (low / band) as f32;
            }
        }
        if self
            .c2r
            .process_with_scratch(&mut self.spectrum, &mut self.acf, &mut self.scratch)
            .is_err()
        {
            self.curve.fill(0.0);
            return false;
        }
        // m(0) = 2·Σx²; later lags drop one sample from each end (the forward pass overwrote
        // `time`, so the ends are read from the window itself, or from the filtered window).
        // The running sum first, then the lags' divisions, which do not wait on each other.
        let m0 = 2.0 * self.heard_energy;
        let top = if let Some(heard) = heard {
            norms(&mut self.norm, m0, w, |i| heard[i]);
            HEARD_NSDF_MAX
        } else {
            norms(&mut self.norm, m0, w, |i| window[i] - mean);
            1.0
        };
        let scale = 1.0 / self.time.len() as f64;
        let n = self.curve.len();
        let (curve, norm, acf) = (&mut self.curve[..n], &self.norm[..n], &self.acf[..n]);
        for i in 0..n {
            let (m, r) = (norm[i], acf[i] as f64 * scale);
            // As `clamp(-1.0, top)` does it, without its check that the bounds are ordered.
            let v = 2.0 * r / m;
            let v = if v < -1.0 { -1.0 } else { v };
            let v = if v > top { top } else { v };
            curve[i] = if m > 1e-12 { v as f32 } else { 0.0 };
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fft_sizes_are_5_smooth() {
        assert_eq!(fft_len_for(483), 486);
        assert_eq!(fft_len_for(512), 512);
        assert_eq!(fft_len_for(532), 540);
        // The short window at 8 kHz: 243 = 3^5 is 5-smooth but odd.
        assert_eq!(fft_len_for(242), 250);
    }
}
