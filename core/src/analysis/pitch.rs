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
//! Two window lengths (the second optional): the long window must hold two periods of the lowest
//! f0, but a voice whose pitch glides fast (a falling phrase end, an accent, a short syllable of
//! a low voice) is not periodic over 40 ms: its harmonics drift apart in phase across the window
//! and the NSDF peak sinks although every single period is clean, and the key-maximum rule may
//! then take a lobe at half the period. A short window centred in the long one sees less of the
//! glide; the same key-maximum rule runs on it over the lags it holds twice. When it agrees with
//! the long window's choice, its clarity counts for the periodicity (the higher of the two);
//! when it prefers a longer period that the long window also has as a key maximum, that longer
//! period is taken (the long window's choice was a fraction of the period); otherwise it is
//! ignored, so the short window never introduces a period the long window did not see.
//! [`NsdfPitch::edge_clarity`] runs the same short window at either end of the long one for the
//! voicing decision at phrase edges (for periods too long for it, the NSDF at the chosen period
//! over the two periods at that end).
//!
//! [`NsdfPitch::low_pass`] makes every NSDF hear its window through a low-pass (the analyzer
//! sets one at 1.8 kHz): white noise and hiss spread up to the Nyquist frequency, the voice's
//! periodicity lives in its lower harmonics.
//!
//! Plans and buffers are made in [`NsdfPitch::new`]; [`NsdfPitch::analyse`] never allocates.

use std::sync::Arc;

use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};

use super::biquad::Biquad;
use super::breath_band::{BandLevels, BandSpectrum};

/// Most key maxima kept per frame.
pub const MAX_CANDIDATES: usize = 16;

/// The low band (Hz) whose share of the voice band's energy ([`NsdfPitch::low_band`]) tells
/// voiced sounds (energy in the first formant region) from fricatives and hiss.
const LOW_BAND_HZ: (f64, f64) = (80.0, 1000.0);
/// Top of the voice band for that share: the lowest internal rate's Nyquist frequency, so the
/// share means the same at every host rate.
const VOICE_BAND_TOP_HZ: f64 = 4000.0;

/// Behind the low-pass, r(τ) holds the filter's ringing past the window's end and m(τ) does
/// not, so a periodic window's NSDF peaks reach about 1.015: the curve is clamped here, not at
/// 1, so the parabolic refinement still sees the peak's shape (the clarity is clamped to 1).
const HEARD_NSDF_MAX: f64 = 1.1;

/// Key maxima of the two windows closer than this lag ratio are the same lobe.
const SAME_LOBE_RATIO: f64 = 1.04;

/// One period candidate: a key maximum of the NSDF.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PitchEstimate {
    /// Frequency in Hz (0 when there is no candidate).
    pub f0_hz: f32,
    /// Interpolated NSDF peak height, 0..1 (periodicity).
    pub clarity: f32,
}

/// Everything [`NsdfPitch::analyse_frame`] finds in one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrameAnalysis {
    /// As [`NsdfPitch::analyse`] returns it.
    pub chosen: PitchEstimate,
    /// [`NsdfPitch::edge_clarity`] of `chosen` at the newest and at the oldest end.
    pub edge_newest: Option<f32>,
    pub edge_oldest: Option<f32>,
    /// Σ x² of the window (summed in f64 in [`Lanes`]).
    pub square_sum: f64,
    /// The long window's energy about its mean as the NSDF hears it (behind
    /// [`NsdfPitch::low_pass`], when set; 0 for a window of the wrong length).
    pub heard_energy: f64,
}

/// The NSDF of one window length, with its FFT plans and buffers.
struct Nsdf {
    window_len: usize,
    r2c: Arc<dyn RealToComplex<f32>>,
    c2r: Arc<dyn ComplexToReal<f32>>,
    time: Vec<f32>,
    spectrum: Vec<Complex<f32>>,
    scratch: Vec<Complex<f32>>,
    acf: Vec<f32>,
    /// n(τ) for τ = 0..=lag_max+1.
    curve: Vec<f32>,
    /// Spectrum bins of the low band and of the whole voice band (see `low_band`).
    low_bins: (usize, usize),
    band_bins: (usize, usize),
    /// Share of the last window's voice-band energy in the low band, 0..1 (kept up to date
    /// only when `measure_low_band`: the short windows' share is never asked for).
    low_band: f32,
    measure_low_band: bool,
    /// The breath bands read from the spectrum, when asked for ([`NsdfPitch::measure_bands`]),
    /// and their levels in the last window.
    bands: Option<BandSpectrum>,
    band_levels: BandLevels,
    /// The low-pass the NSDF hears the window through (see [`NsdfPitch::low_pass`]), its
    /// power gain per spectrum bin, and the window through it (from rest).
    filter: Option<Biquad>,
    weights: Vec<f32>,
    heard: Vec<f32>,
    /// Energy of the last window as the NSDF hears it (about the mean, after the low-pass).
    heard_energy: f64,
}

/// The mean of one window and its energy about the mean.
#[derive(Debug, Clone, Copy)]
struct WindowStats {
    /// Mean of the samples (summed in f64 in [`Lanes`], then rounded to f32).
    mean: f32,
    /// Σ (x − mean)², each difference rounded to f32 first, summed in f64 in [`Lanes`].
    energy: f64,
}

impl WindowStats {
    fn of(window: &[f32]) -> Self {
        let mut sum = Lanes::default();
        sum.add(window, |x| x as f64);
        let mean = (sum.total() / window.len().max(1) as f64) as f32;
        Self {
            mean,
            energy: energy_about(window, mean),
        }
    }
}

/// Σ (x − mean)² over `window`, each difference rounded to f32, summed in [`Lanes`].
#[inline]
fn energy_about(window: &[f32], mean: f32) -> f64 {
    let mut e = Lanes::default();
    e.add(window, |x| {
        let t = (x - mean) as f64;
        t * t
    });
    e.total()
}

/// Σ x² of `window` in [`Lanes`].
fn square_sum(window: &[f32]) -> f64 {
    let mut s = Lanes::default();
    s.add(window, |x| (x as f64) * (x as f64));
    s.total()
}

/// Lanes of [`Lanes`].
const LANES: usize = 8;

/// A sum in f64 over a run of samples kept as [`LANES`] partial sums (sample `i` of the run
/// into lane `i % LANES`, each lane in sample order) and added up at the end in a fixed tree:
/// independent chains that vectorise and overlap, where one serial sum waits on every
/// addition. The same run always gives the same bits.
#[derive(Debug, Clone, Copy, Default)]
struct Lanes([f64; LANES]);

impl Lanes {
    /// Adds `f(x)` for every sample of `xs` (the whole run, or its continuation when the run
    /// so far was a whole number of [`LANES`] long).
    #[inline(always)]
    fn add<T: Copy>(&mut self, xs: &[T], f: impl Fn(T) -> f64) {
        let mut l = self.0;
        let chunks = xs.chunks_exact(LANES);
        let tail = chunks.remainder();
        for c in chunks {
            for k in 0..LANES {
                l[k] += f(c[k]);
            }
        }
        for (k, &x) in tail.iter().enumerate() {
            l[k] += f(x);
        }
        self.0 = l;
    }

    /// The sum: the lanes added pairwise.
    #[inline]
    fn total(&self) -> f64 {
        let l = self.0;
        ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]))
    }
}

/// The statistics of the long window and of the three short windows inside it (oldest end,
/// centre, newest end), and the long window's plain sum of squares: each window's sums are
/// exactly its [`WindowStats::of`] sums (the same lanes in the same order, so the results are
/// bit-identical), but the oldest short window's sum is shared with the long window's.
#[derive(Debug, Clone, Copy)]
struct FrameStats {
    long: WindowStats,
    /// Oldest end, centre, newest end.
    short: [WindowStats; 3],
    /// Σ x² of the long window, summed in [`Lanes`] (for [`FrameAnalysis::square_sum`]).
    square_sum: f64,
}

impl FrameStats {
    /// The short windows start at `0`, `(w − short_len) / 2` and `w − short_len`; requires
    /// `short_len <= window.len()`.
    fn of(window: &[f32], short_len: usize) -> Self {
        let (w, len) = (window.len(), short_len);
        let starts = [0, (w - len) / 2, w - len];
        let shorts = starts.map(|a| &window[a..a + len]);
        let plain = |x: f32| x as f64;
        let mut sums = [Lanes::default(); 3];
        for (s, part) in sums.iter_mut().zip(shorts) {
            s.add(part, plain);
        }
        let mut long = Lanes::default();
        if len.is_multiple_of(LANES) {
            // The long window's run so far is the oldest short window's.
            long = sums[0];
            long.add(&window[len..], plain);
        } else {
            long.add(window, plain);
        }
        let mean_long = (long.total() / w.max(1) as f64) as f32;
        let means = sums.map(|s| (s.total() / len.max(1) as f64) as f32);
        Self {
            long: WindowStats {
                mean: mean_long,
                energy: energy_about(window, mean_long),
            },
            short: [0, 1, 2].map(|k| WindowStats {
                mean: means[k],
                energy: energy_about(shorts[k], means[k]),
            }),
            square_sum: square_sum(window),
        }
    }
}

impl Nsdf {
    fn new(
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
    fn compute(&mut self, window: &[f32]) -> bool {
        self.compute_with(window, WindowStats::of(window))
    }

    /// [`Nsdf::compute`] with the window's statistics already known.
    fn compute_with(&mut self, window: &[f32], stats: WindowStats) -> bool {
        let w = self.window_len;
        let WindowStats { mean, energy } = stats;
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
        if let Some(mut filter) = self.filter {
            let mut e = Lanes::default();
            for (h, &t) in self.heard.iter_mut().zip(&self.time[..w]) {
                *h = filter.process(t as f64) as f32;
            }
            e.add(&self.heard, |h| (h as f64) * (h as f64));
            self.heard_energy = e.total();
        }
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
        let mut m = 2.0 * self.heard_energy;
        let scale = 1.0 / self.time.len() as f64;
        let top = if self.filter.is_some() {
            HEARD_NSDF_MAX
        } else {
            1.0
        };
        for tau in 0..self.curve.len() {
            if tau > 0 {
                let (a, b) = if self.filter.is_some() {
                    (self.heard[tau - 1] as f64, self.heard[w - tau] as f64)
                } else {
                    (
                        (window[tau - 1] - mean) as f64,
                        (window[w - tau] - mean) as f64,
                    )
                };
                m -= a * a + b * b;
            }
            let r = self.acf[tau] as f64 * scale;
            self.curve[tau] = if m > 1e-12 {
                (2.0 * r / m).clamp(-1.0, top) as f32
            } else {
                0.0
            };
        }
        true
    }
}

/// NSDF pitch estimator for windows of a fixed length at a fixed rate.
pub struct NsdfPitch {
    rate_hz: f64,
    lag_min: usize,
    /// Shortest and longest period in range, in samples (`rate / f0_max`, `rate / f0_min`): a
    /// refined key maximum outside them is no candidate.
    lag_range: (f64, f64),
    lag_max: usize,
    key_max_ratio: f32,
    long: Nsdf,
    /// The short centred window and the longest lag it serves.
    short: Option<(Nsdf, usize)>,
    candidates: [PitchEstimate; MAX_CANDIDATES],
    n_candidates: usize,
    short_candidates: [PitchEstimate; MAX_CANDIDATES],
    periodicity: f32,
    /// The long window's own periodicity (before the short window's say).
    long_periodicity: f32,
    /// The centred short window's pick, when it ran, and whether it agreed with the choice.
    short_pick: PitchEstimate,
    short_agrees: bool,
}

impl std::fmt::Debug for NsdfPitch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NsdfPitch")
            .field("rate_hz", &self.rate_hz)
            .field("window_len", &self.long.window_len)
            .field(
                "short_window_len",
                &self.short.as_ref().map(|s| s.0.window_len),
            )
            .field("lag_min", &self.lag_min)
            .field("lag_max", &self.lag_max)
            .finish()
    }
}

/// Smallest even 5-smooth number (2^a·3^b·5^c, a ≥ 1) not below `n`: sizes the real FFT is
/// fast at (an odd length would cost a full-length complex FFT).
fn fft_len_for(n: usize) -> usize {
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
        Self::with_short_window(rate_hz, window_len, 0, f0_min_hz, f0_max_hz, key_max_ratio)
    }

    /// Like [`NsdfPitch::new`], plus a short window of `short_len` samples centred in the long
    /// one (see the module docs) serving the lags it holds twice; 0, or a short window too
    /// short for two periods of `f0_max_hz` or not shorter than the long one, means none.
    pub fn with_short_window(
        rate_hz: f64,
        window_len: usize,
        short_len: usize,
        f0_min_hz: f32,
        f0_max_hz: f32,
        key_max_ratio: f32,
    ) -> Self {
        let lag_min = ((rate_hz / f0_max_hz as f64).floor() as usize).max(2);
        let lag_max = ((rate_hz / f0_min_hz as f64).ceil() as usize)
            .min(window_len.saturating_sub(2))
            .max(lag_min + 2);
        let mut planner = RealFftPlanner::<f32>::new();
        let long = Nsdf::new(&mut planner, rate_hz, window_len, lag_max, true);
        let short_lag_max = (short_len / 2).min(lag_max);
        let short = (short_len < window_len && short_lag_max >= lag_min + 2).then(|| {
            (
                Nsdf::new(&mut planner, rate_hz, short_len, short_lag_max, false),
                short_lag_max,
            )
        });
        Self {
            rate_hz,
            lag_min,
            lag_range: (rate_hz / f0_max_hz as f64, rate_hz / f0_min_hz as f64),
            lag_max,
            key_max_ratio,
            long,
            short,
            candidates: [PitchEstimate::default(); MAX_CANDIDATES],
            n_candidates: 0,
            short_candidates: [PitchEstimate::default(); MAX_CANDIDATES],
            periodicity: 0.0,
            long_periodicity: 0.0,
            short_pick: PitchEstimate::default(),
            short_agrees: false,
        }
    }

    /// Window length in samples.
    pub fn window_len(&self) -> usize {
        self.long.window_len
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

    /// The long window's own periodicity in the last analysed window (its highest key
    /// maximum, without the short window's confirmation), 0..1.
    pub fn long_periodicity(&self) -> f32 {
        self.long_periodicity
    }

    /// The centred short window's key-maximum pick in the last analysed window (zero when it
    /// did not run: no pitch, or the period beyond its reach), and whether it is the same lobe
    /// as the chosen period.
    pub fn short_window_pick(&self) -> (PitchEstimate, bool) {
        (self.short_pick, self.short_agrees)
    }

    /// Share of the last long window's energy between 80 Hz and 1 kHz in its energy between
    /// 80 Hz and 4 kHz, 0..1 (0 for a silent window), behind the low-pass when one is set:
    /// high for vowels, low for fricatives.
    pub fn low_band(&self) -> f32 {
        self.long.low_band
    }

    /// Makes every NSDF (long and short windows) hear its window through `filter` (the
    /// analyzer's low-pass, see [`crate::AnalysisConfig::lowpass_hz`]) without a second FFT:
    /// r(τ) comes from the window's power spectrum times the filter's power gain (the
    /// autocorrelation of the window filtered from rest, its ringing past the window's end
    /// included), m(τ) from the window filtered from rest in the time domain. The low-band
    /// share is read behind the filter too; the breath bands and the two-period edge cue
    /// read the window itself. Allocates.
    pub(crate) fn low_pass(&mut self, filter: Biquad) {
        let rate_hz = self.rate_hz;
        let weigh = |nsdf: &mut Nsdf| {
            let fft_len = nsdf.time.len() as f64;
            nsdf.weights = (0..nsdf.spectrum.len())
                .map(|k| filter.power_gain(k as f64 * rate_hz / fft_len, rate_hz) as f32)
                .collect();
            nsdf.heard = vec![0.0; nsdf.window_len];
            nsdf.filter = Some(filter);
        };
        weigh(&mut self.long);
        if let Some((short, _)) = &mut self.short {
            weigh(short);
        }
    }

    /// Makes the analysis also measure the breath bands on the long window's spectrum
    /// ([`NsdfPitch::band_levels`]); `power_gain(f_hz)` is the power gain of whatever filtered
    /// the signal before the window. Allocates.
    pub(crate) fn measure_bands(&mut self, power_gain: impl Fn(f64) -> f64) {
        let long = &mut self.long;
        long.bands = Some(BandSpectrum::new(
            self.rate_hz,
            long.time.len(),
            long.window_len,
            power_gain,
        ));
    }

    /// The breath-band levels of the last long window (the −120 dBFS floor when silent or
    /// when [`NsdfPitch::measure_bands`] was not called).
    pub(crate) fn band_levels(&self) -> BandLevels {
        self.long.band_levels
    }

    /// The last long window's NSDF at half the period of `chosen` (linear interpolation),
    /// clamped to 0..1; 0 without a period. Near the chosen clarity when the chosen period is
    /// twice the true one (an octave-down pick), low (the curve is negative there) for a true
    /// period.
    pub fn half_period_clarity(&self, chosen: PitchEstimate) -> f32 {
        if chosen.f0_hz <= 0.0 {
            return 0.0;
        }
        let lag = self.rate_hz / chosen.f0_hz as f64 / 2.0;
        let curve = &self.long.curve;
        let i = lag.floor() as usize;
        if i + 1 >= curve.len() {
            return 0.0;
        }
        let frac = (lag - i as f64) as f32;
        (curve[i] + (curve[i + 1] - curve[i]) * frac).clamp(0.0, 1.0)
    }

    /// The NSDF of the last analysed (long) window, lags 0..=lag_max+1.
    pub fn nsdf(&self) -> &[f32] {
        &self.long.curve
    }

    /// Analyses one window of exactly [`Self::window_len`] samples (any other length gives a
    /// zero estimate). The mean is removed first, so DC offsets do not
    /// matter. Returns the period chosen by the key-maximum rule, or a zero estimate when the
    /// window has no periodic structure in range.
    pub fn analyse(&mut self, window: &[f32]) -> PitchEstimate {
        self.analyse_with(window, None)
    }

    /// [`NsdfPitch::analyse`] and both [`NsdfPitch::edge_clarity`] calls on one window at once,
    /// bit-identical to making those calls one after the other, but faster: the statistics of
    /// all four windows come from one [`FrameStats`] (the oldest short window's sum shared).
    /// Also gives the window's plain sum of squares and its energy as the NSDF heard it.
    pub(crate) fn analyse_frame(&mut self, window: &[f32]) -> FrameAnalysis {
        let short_len = self.short.as_ref().map(|(s, _)| s.window_len);
        let stats = match short_len {
            Some(len) if window.len() == self.long.window_len => FrameStats::of(window, len),
            _ => {
                let chosen = self.analyse(window);
                return FrameAnalysis {
                    chosen,
                    edge_newest: self.edge_clarity(window, chosen, true),
                    edge_oldest: self.edge_clarity(window, chosen, false),
                    square_sum: square_sum(window),
                    heard_energy: self.long.heard_energy,
                };
            }
        };
        let chosen = self.analyse_with(window, Some(&stats));
        FrameAnalysis {
            chosen,
            edge_newest: self.edge_clarity_with(window, chosen, true, Some(&stats)),
            edge_oldest: self.edge_clarity_with(window, chosen, false, Some(&stats)),
            square_sum: stats.square_sum,
            heard_energy: self.long.heard_energy,
        }
    }

    fn analyse_with(&mut self, window: &[f32], stats: Option<&FrameStats>) -> PitchEstimate {
        self.n_candidates = 0;
        self.periodicity = 0.0;
        self.long_periodicity = 0.0;
        self.short_pick = PitchEstimate::default();
        self.short_agrees = false;
        if window.len() != self.long.window_len {
            self.long.band_levels = BandLevels::FLOOR;
            self.long.heard_energy = 0.0;
            return PitchEstimate::default();
        }
        let computed = match stats {
            Some(st) => self.long.compute_with(window, st.long),
            None => self.long.compute(window),
        };
        if !computed {
            if let Some((short, _)) = &mut self.short {
                short.curve.fill(0.0);
            }
            return PitchEstimate::default();
        }
        let last = self.lag_max.min(self.long.curve.len() - 2);
        let mut n = 0;
        let above_range = key_maxima(
            &self.long.curve,
            self.rate_hz,
            self.lag_range,
            last,
            &mut self.candidates,
            &mut n,
        );
        self.n_candidates = n;
        let best = self.candidates[..n]
            .iter()
            .fold(0.0f32, |m, c| m.max(c.clarity));
        self.periodicity = best;
        self.long_periodicity = best;
        let threshold = self.key_max_ratio * best.max(above_range);
        if above_range > 0.0 && above_range >= threshold {
            // The key-maximum rule would take a period shorter than the range allows: the
            // voice is above `f0_max_hz`. No pitch, rather than its subharmonic.
            return PitchEstimate::default();
        }
        let mut chosen = self.candidates[..n]
            .iter()
            .copied()
            .find(|c| c.clarity >= threshold && c.clarity > 0.0)
            .unwrap_or_default();
        // The short window can only confirm the chosen period or prefer a longer one, so it
        // has nothing to say when the chosen period is beyond its reach.
        let in_reach = self.short.as_ref().is_some_and(|(_, last)| {
            chosen.f0_hz > 0.0
                && self.rate_hz / (chosen.f0_hz as f64) <= *last as f64 * SAME_LOBE_RATIO
        });
        if in_reach {
            if let Some(short_pick) = self.short_pick(window, stats) {
                let ratio = SAME_LOBE_RATIO as f32;
                let same = |a: f32, b: f32| a < b * ratio && a * ratio > b;
                if !same(short_pick.f0_hz, chosen.f0_hz) && short_pick.f0_hz < chosen.f0_hz {
                    // The short window, free of the glide, prefers a longer period: the long
                    // window's pick was a fraction of the period. Take the long window's lobe
                    // at the short window's period, if it has one.
                    if let Some(c) = self.candidates[..n]
                        .iter()
                        .find(|c| same(c.f0_hz, short_pick.f0_hz))
                    {
                        chosen = *c;
                    }
                }
                self.short_pick = short_pick;
                if same(short_pick.f0_hz, chosen.f0_hz) {
                    self.short_agrees = true;
                    self.periodicity = self.periodicity.max(short_pick.clarity);
                }
            }
        }
        chosen
    }

    /// Clarity of `chosen` on a short window at one end of `window` (the newest samples when
    /// `newest`, else the oldest), if that window's own key-maximum choice is the same lobe;
    /// `None` without a short window. A period beyond the short window's reach (f0 under about
    /// 100 Hz) is judged on the last (first) two periods instead ([`two_period_clarity`]),
    /// scaled down by the NSDF at half the period (an octave-down pick), so low voices have
    /// edge cues too. For the voicing decision at phrase edges, where the voice
    /// fills only one end of the window.
    pub fn edge_clarity(
        &mut self,
        window: &[f32],
        chosen: PitchEstimate,
        newest: bool,
    ) -> Option<f32> {
        self.edge_clarity_with(window, chosen, newest, None)
    }

    fn edge_clarity_with(
        &mut self,
        window: &[f32],
        chosen: PitchEstimate,
        newest: bool,
        stats: Option<&FrameStats>,
    ) -> Option<f32> {
        let (short, last) = self.short.as_ref()?;
        let (len, reach) = (short.window_len, *last as f64 * SAME_LOBE_RATIO);
        if window.len() != self.long.window_len || chosen.f0_hz <= 0.0 {
            return None;
        }
        let period = self.rate_hz / chosen.f0_hz as f64;
        if period > reach {
            // An octave-down pick of a higher voice is periodic over two of its periods too:
            // the NSDF at half the period tells it from a true low voice.
            let octave_down = self.half_period_clarity(chosen);
            return Some(two_period_clarity(window, period, newest) * (1.0 - octave_down));
        }
        let start = if newest { window.len() - len } else { 0 };
        let p = self.short_pick_at(window, start, stats.map(|st| st.short[2 * newest as usize]))?;
        let ratio = SAME_LOBE_RATIO as f32;
        (p.f0_hz < chosen.f0_hz * ratio && p.f0_hz * ratio > chosen.f0_hz).then_some(p.clarity)
    }

    /// The key-maximum choice on the short window (periods it holds twice), if there is one.
    fn short_pick(&mut self, window: &[f32], stats: Option<&FrameStats>) -> Option<PitchEstimate> {
        let len = self.short.as_ref()?.0.window_len;
        self.short_pick_at(
            window,
            (window.len() - len) / 2,
            stats.map(|st| st.short[1]),
        )
    }

    /// The short window's pick at `start`; `stats` are that window's, when known.
    fn short_pick_at(
        &mut self,
        window: &[f32],
        start: usize,
        stats: Option<WindowStats>,
    ) -> Option<PitchEstimate> {
        let (short, short_last) = self.short.as_mut()?;
        let part = &window[start..start + short.window_len];
        let computed = match stats {
            Some(st) => short.compute_with(part, st),
            None => short.compute(part),
        };
        if !computed {
            return None;
        }
        let mut k = 0;
        key_maxima(
            &short.curve,
            self.rate_hz,
            self.lag_range,
            *short_last,
            &mut self.short_candidates,
            &mut k,
        );
        let cands = &self.short_candidates[..k];
        let best = cands.iter().fold(0.0f32, |m, c| m.max(c.clarity));
        let threshold = self.key_max_ratio * best;
        cands
            .iter()
            .copied()
            .find(|c| c.clarity >= threshold && c.clarity > 0.0)
    }
}

/// The NSDF at the lag nearest `period` (samples; the best of that lag and its two
/// neighbours) over the last two periods of `window` (`newest`) or its first two: the edge cue
/// of a period too long for the short window (a low voice, 60–100 Hz, whose onsets and creaky
/// endings fill only one end of the long window). Time domain, O(period); 0 when the window
/// holds no two periods or the segment is silent.
fn two_period_clarity(window: &[f32], period: f64, newest: bool) -> f32 {
    let centre = period.round() as usize;
    let mut best = 0.0f32;
    for lag in centre.saturating_sub(1)..=centre + 1 {
        if lag < 2 || 2 * lag > window.len() {
            continue;
        }
        let start = if newest { window.len() - 2 * lag } else { 0 };
        let (older, newer) = window[start..start + 2 * lag].split_at(lag);
        let (mut cross, mut energy) = (0.0f64, 0.0f64);
        for (&a, &b) in older.iter().zip(newer) {
            cross += f64::from(a) * f64::from(b);
            energy += f64::from(a) * f64::from(a) + f64::from(b) * f64::from(b);
        }
        if energy > 0.0 {
            best = best.max((2.0 * cross / energy) as f32);
        }
    }
    best.clamp(0.0, 1.0)
}

/// Key maxima of one NSDF curve up to lag `last`, shortest lag first, into `out`
/// (count in `n`); a maximum whose refined lag lies outside `lag_range` (the f0 range) is no
/// candidate, and the returned value is the highest clarity among those above the range
/// (shorter than its shortest period; 0 if none); when `out` is full the weakest kept lobe
/// gives way to a stronger one.
fn key_maxima(
    n: &[f32],
    rate_hz: f64,
    lag_range: (f64, f64),
    last: usize,
    out: &mut [PitchEstimate],
    count: &mut usize,
) -> f32 {
    let mut above_range = 0.0f32;
    // Skip the lobe around lag 0: start after the first negative-going zero crossing.
    let mut tau = 1;
    while tau <= last && n[tau] > 0.0 {
        tau += 1;
    }
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
        // Lobes before the shortest period searched still tell of a voice above the range.
        if peak_tau == 0 {
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
        if lag < lag_range.0 {
            above_range = above_range.max(clarity);
            continue;
        }
        if lag > lag_range.1 {
            continue;
        }
        let candidate = PitchEstimate {
            f0_hz: (rate_hz / lag) as f32,
            clarity,
        };
        if *count == out.len() {
            // Full (very low f0 with a bright spectrum has many lobes): drop the weakest
            // kept lobe if this one is stronger, keeping the lag order.
            let (weakest, w) = out.iter().enumerate().fold((0, f32::MAX), |m, (i, c)| {
                if c.clarity < m.1 {
                    (i, c.clarity)
                } else {
                    m
                }
            });
            if clarity <= w {
                continue;
            }
            out.copy_within(weakest + 1.., weakest);
            *count -= 1;
        }
        out[*count] = candidate;
        *count += 1;
    }
    above_range
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SeededRng;

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

    /// Seeded uniform noise in −0.5..0.5.
    fn uniform(rng: &mut SeededRng) -> f32 {
        (rng.uniform() - 0.5) as f32
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

    /// A harmonic-rich tone whose f0 falls exponentially at `octaves_per_s`, `f0_mid` at the
    /// centre of the `n` samples.
    fn glide(f0_mid: f64, octaves_per_s: f64, rate: f64, n: usize) -> Vec<f32> {
        let mut phase = 0.0f64;
        (0..n)
            .map(|i| {
                let t = (i as f64 - n as f64 / 2.0) / rate;
                let f0 = f0_mid * (-octaves_per_s * t).exp2();
                phase += 2.0 * std::f64::consts::PI * f0 / rate;
                (1..=12)
                    .map(|h| (h as f64 * phase).sin() / h as f64)
                    .sum::<f64>() as f32
                    * 0.2
            })
            .collect()
    }

    #[test]
    fn the_short_window_keeps_a_fast_glide_periodic() {
        // 125 Hz falling 6 octaves per second (a fast phrase-final fall): over the 40 ms
        // window the period changes by 16 %.
        let rate = 8_000.0;
        let x = glide(125.0, 6.0, rate, 320);
        let mut long_only = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
        let mut both = NsdfPitch::with_short_window(rate, 320, 160, 50.0, 600.0, 0.88);
        let a = long_only.analyse(&x);
        let b = both.analyse(&x);
        let cents = |f: f32| 1200.0 * (f as f64 / 125.0).log2();
        assert!(cents(b.f0_hz).abs() < 100.0, "short: {} Hz", b.f0_hz);
        assert!(
            both.periodicity() > long_only.periodicity() + 0.05,
            "long {} ({} Hz), with short {} ({} Hz)",
            long_only.periodicity(),
            a.f0_hz,
            both.periodicity(),
            b.f0_hz
        );
        // A steady tone gains nothing: both windows see the same period.
        let steady = tone(125.0, rate, 320, &[1.0, 0.5, 0.3]);
        long_only.analyse(&steady);
        let e = both.analyse(&steady);
        assert!(cents(e.f0_hz).abs() < 10.0);
        assert!((both.periodicity() - long_only.periodicity()).abs() < 0.02);
        // The short window never brings a period the long window did not see: for a 60 Hz
        // tone (beyond its reach) the choice is the long window's.
        let low = tone(60.0, rate, 320, &[1.0, 0.8, 0.6, 0.4]);
        let a = long_only.analyse(&low);
        let b = both.analyse(&low);
        assert_eq!(a, b);
    }

    #[test]
    fn no_candidate_lies_outside_the_f0_range() {
        // Just above the top of the range the period falls between two lags, and parabolic
        // refinement of the peak at the shortest searched lag would land above 600 Hz; just
        // below the bottom, past the longest lag. Rates 8 kHz, 8.82 kHz (44.1 kHz / 5) and
        // 12 kHz (48 kHz / 4, 96 kHz / 8).
        for rate in [8_000.0, 8_820.0, 12_000.0] {
            let len = (0.04 * rate) as usize;
            let mut p = NsdfPitch::with_short_window(rate, len, len / 2, 50.0, 600.0, 0.88);
            for f0 in [601.0, 605.0, 615.0, 630.0, 645.0, 48.0, 49.5] {
                let x = tone(f0, rate, len, &[1.0, 0.5, 0.3]);
                let e = p.analyse(&x);
                for c in p.candidates().iter().chain([&e]) {
                    assert!(
                        c.f0_hz == 0.0 || (50.0..=600.0).contains(&c.f0_hz),
                        "rate {rate}, tone {f0} Hz: candidate {} Hz",
                        c.f0_hz
                    );
                }
            }
            // A voice above the range has no pitch, rather than its subharmonic.
            for f0 in [605.0, 630.0, 700.0] {
                let e = p.analyse(&tone(f0, rate, len, &[1.0, 0.5, 0.3]));
                assert_eq!(
                    e.f0_hz, 0.0,
                    "rate {rate}, tone {f0} Hz reported at {}",
                    e.f0_hz
                );
            }
            // Inside the range, next to its ends, the tones are still found.
            for f0 in [52.0, 590.0] {
                let e = p.analyse(&tone(f0, rate, len, &[1.0, 0.5, 0.3]));
                assert!(
                    (e.f0_hz / f0 as f32 - 1.0).abs() < 0.01,
                    "{rate}: {f0} → {}",
                    e.f0_hz
                );
            }
        }
    }

    #[test]
    fn fft_sizes_are_5_smooth() {
        assert_eq!(fft_len_for(483), 486);
        assert_eq!(fft_len_for(512), 512);
        assert_eq!(fft_len_for(532), 540);
        // The short window at 8 kHz: 243 = 3^5 is 5-smooth but odd.
        assert_eq!(fft_len_for(242), 250);
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
    fn a_low_voice_has_edge_cues_at_its_onset() {
        // A 70 Hz voice (period 14.3 ms, beyond the 20 ms short window's reach) filling only
        // the newest 29 ms of a 40 ms window: the newest end is clearly periodic, the oldest
        // (mostly silence with a little noise) much less.
        let (rate, n) = (8_000.0, 320);
        let mut p = NsdfPitch::with_short_window(rate, n, 160, 50.0, 600.0, 0.88);
        let voice = tone(70.0, rate, n, &[1.0, 0.6, 0.4, 0.3]);
        let mut s = SeededRng::new(99);
        let window: Vec<f32> = voice
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let noise = uniform(&mut s) * 0.01;
                if i >= 88 {
                    v + noise
                } else {
                    noise
                }
            })
            .collect();
        let chosen = p.analyse(&window);
        assert!((chosen.f0_hz - 70.0).abs() < 2.0, "{chosen:?}");
        let newest = p.edge_clarity(&window, chosen, true).unwrap();
        let oldest = p.edge_clarity(&window, chosen, false).unwrap();
        assert!(newest > 0.95, "newest end {newest}");
        // The oldest two periods hold 3 ms of the voice's 14 ms period in the older one.
        assert!(
            oldest < newest - 0.25,
            "oldest end {oldest}, newest {newest}"
        );
    }

    #[test]
    fn the_fused_frame_analysis_is_bit_identical_to_the_calls_one_by_one() {
        // Voices from 60 to 400 Hz (beyond and within the short window's reach), with onsets,
        // offsets, noise, a DC offset and silence, at the internal rates of 8, 44.1 and 48 kHz,
        // with and without the low-pass.
        for (rate, n, short, low_pass) in [
            (8_000.0, 320, 160, false),
            (8_820.0, 353, 176, false),
            (12_000.0, 480, 240, false),
            (8_000.0, 320, 160, true),
            (8_820.0, 353, 176, true),
        ] {
            let mut fused = NsdfPitch::with_short_window(rate, n, short, 50.0, 600.0, 0.88);
            let mut plain = NsdfPitch::with_short_window(rate, n, short, 50.0, 600.0, 0.88);
            if low_pass {
                fused.low_pass(Biquad::butterworth(1800.0, rate, false));
                plain.low_pass(Biquad::butterworth(1800.0, rate, false));
            }
            let mut s = SeededRng::new(5);
            for (k, f0) in [60.0f64, 70.0, 95.0, 130.0, 210.0, 400.0, 0.0]
                .into_iter()
                .enumerate()
            {
                let voice = tone(f0.max(1.0), rate, n, &[1.0, 0.6, 0.4, 0.3]);
                let window: Vec<f32> = voice
                    .iter()
                    .enumerate()
                    .map(|(i, &v)| {
                        let noise = uniform(&mut s) * 0.02;
                        let on = match k % 3 {
                            0 => i >= n / 3,
                            1 => i < 2 * n / 3,
                            _ => true,
                        };
                        let v = if on && f0 > 0.0 { v } else { 0.0 };
                        v + noise + 0.01 * k as f32
                    })
                    .collect();
                for w in [&window[..], &vec![0.0; n][..]] {
                    let got = fused.analyse_frame(w);
                    let chosen = plain.analyse(w);
                    let want = FrameAnalysis {
                        chosen,
                        edge_newest: plain.edge_clarity(w, chosen, true),
                        edge_oldest: plain.edge_clarity(w, chosen, false),
                        square_sum: square_sum(w),
                        heard_energy: plain.long.heard_energy,
                    };
                    let bits = |a: &FrameAnalysis| {
                        (
                            a.chosen.f0_hz.to_bits(),
                            a.chosen.clarity.to_bits(),
                            a.edge_newest.map(f32::to_bits),
                            a.edge_oldest.map(f32::to_bits),
                            a.square_sum.to_bits(),
                            a.heard_energy.to_bits(),
                        )
                    };
                    assert_eq!(bits(&got), bits(&want), "{rate} Hz, f0 {f0}");
                    assert_eq!(fused.candidates(), plain.candidates());
                    assert_eq!(fused.short_window_pick(), plain.short_window_pick());
                    assert_eq!(fused.low_band().to_bits(), plain.low_band().to_bits());
                    assert_eq!(fused.periodicity().to_bits(), plain.periodicity().to_bits());
                }
            }
        }
    }

    #[test]
    fn the_low_pass_hears_a_voice_through_white_noise() {
        // A 150 Hz voice (harmonics falling 6 dB per octave) in white noise of equal power at
        // 8 kHz: through the low-pass the NSDF finds the voice clearer, and on the voice alone
        // its peaks stay within a few thousandths of 1 (the filter's ringing past the window's
        // end is in r(τ), not in m(τ)), under the clamp at HEARD_NSDF_MAX.
        let (rate, n) = (8_000.0, 320);
        let voice = tone(
            150.0,
            rate,
            n,
            &[1.0, 0.5, 0.33, 0.25, 0.2, 0.17, 0.14, 0.12],
        );
        let power = |x: &[f32]| x.iter().map(|&v| (v as f64).powi(2)).sum::<f64>();
        let mut s = SeededRng::new(7);
        let mut noise: Vec<f32> = (0..n).map(|_| uniform(&mut s)).collect();
        let gain = (power(&voice) / power(&noise)).sqrt() as f32;
        noise.iter_mut().for_each(|v| *v *= gain);
        let noisy: Vec<f32> = voice.iter().zip(&noise).map(|(a, b)| a + b).collect();
        let mut plain = NsdfPitch::with_short_window(rate, n, 160, 50.0, 600.0, 0.88);
        let mut heard = NsdfPitch::with_short_window(rate, n, 160, 50.0, 600.0, 0.88);
        heard.low_pass(Biquad::butterworth(1800.0, rate, false));
        let (a, b) = (plain.analyse(&noisy), heard.analyse(&noisy));
        assert!((b.f0_hz - 150.0).abs() < 3.0, "{b:?}");
        assert!(b.clarity > a.clarity + 0.1, "plain {a:?}, low-passed {b:?}");
        let clean = heard.analyse(&voice);
        assert!(clean.clarity > 0.95, "{clean:?}");
        let top = heard.nsdf().iter().fold(f32::MIN, |m, &v| m.max(v));
        assert!(top < 1.03 && top < HEARD_NSDF_MAX as f32, "NSDF peak {top}");
        assert!((clean.f0_hz - 150.0).abs() < 0.5, "{clean:?}");
    }

    #[test]
    fn noise_and_silence_have_low_clarity() {
        let mut p = NsdfPitch::new(8_000.0, 320, 50.0, 600.0, 0.88);
        assert_eq!(p.analyse(&[0.0; 320]), PitchEstimate::default());
        let mut s = SeededRng::new(12345);
        let noise: Vec<f32> = (0..320).map(|_| uniform(&mut s)).collect();
        assert!(p.analyse(&noise).clarity < 0.5);
    }
}
