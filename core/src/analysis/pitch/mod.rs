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
//!
//! The rooms: [`nsdf`] computes one window length's curve (FFT plans, buffers, the low-pass
//! weights, the low-band share and the breath bands read from its spectrum); [`sums`] the
//! window statistics in f64 lanes; [`key_maxima`] the peak picking on a curve; [`edge_cues`]
//! the voicing cues at the window's ends; this file the period choice over both windows.

mod edge_cues;
mod key_maxima;
mod nsdf;
mod sums;
#[cfg(test)]
mod tests;

use realfft::RealFftPlanner;

use super::biquad::Biquad;
use super::breath_band::{BandLevels, BandSpectrum};
pub use key_maxima::PitchEstimate;

use key_maxima::key_maxima;
use nsdf::{hear_frame, Known, Nsdf};
use sums::{square_sum, FrameStats};

/// Most key maxima kept per frame.
pub const MAX_CANDIDATES: usize = 16;

/// Key maxima of the two windows closer than this lag ratio are the same lobe.
const SAME_LOBE_RATIO: f64 = 1.04;

/// Everything [`NsdfPitch::analyse_frame`] finds in one window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrameAnalysis {
    /// As [`NsdfPitch::analyse`] returns it.
    pub chosen: PitchEstimate,
    /// [`NsdfPitch::edge_clarity`] of `chosen` at the newest and at the oldest end.
    pub edge_newest: Option<f32>,
    pub edge_oldest: Option<f32>,
    /// Σ x² of the window (summed in f64 in [`sums::Lanes`]).
    pub square_sum: f64,
    /// The long window's energy about its mean as the NSDF hears it (behind
    /// [`NsdfPitch::low_pass`], when set; 0 for a window of the wrong length).
    pub heard_energy: f64,
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
    /// The four windows of a frame as the NSDF hears them, behind the low-pass (long, oldest
    /// end, centre, newest end; empty without a low-pass or a short window).
    frame_heard: [Vec<f32>; 4],
}

/// What the fused frame analysis knows of its four windows before their NSDFs: their
/// statistics and, behind a low-pass, the windows as the NSDF hears them.
#[derive(Debug, Clone, Copy)]
struct FrameKnown<'a> {
    stats: &'a FrameStats,
    /// The four windows as heard and their energies.
    heard: Option<(&'a [Vec<f32>; 4], [f64; 4])>,
}

impl<'a> FrameKnown<'a> {
    /// Window `k`: 0 the long one, 1–3 the short ones (oldest end, centre, newest end).
    fn window(&self, k: usize) -> Known<'a> {
        let stats = if k == 0 {
            self.stats.long
        } else {
            self.stats.short[k - 1]
        };
        Known {
            stats,
            heard: self.heard.map(|(h, e)| (&h[k][..], e[k])),
        }
    }
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
            frame_heard: Default::default(),
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
            let (long, short) = (self.long.window_len, short.window_len);
            self.frame_heard = [long, short, short, short].map(|n| vec![0.0; n]);
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
    /// all four windows come from one [`FrameStats`] (the oldest short window's sum shared),
    /// behind the low-pass taken on the way while `hear_frame` hears the four windows.
    /// Also gives the window's plain sum of squares and its energy as the NSDF heard it.
    pub(crate) fn analyse_frame(&mut self, window: &[f32]) -> FrameAnalysis {
        let short_len = match self.short.as_ref().map(|(s, _)| s.window_len) {
            Some(len) if window.len() == self.long.window_len => len,
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
        // Behind the low-pass, the four windows are heard at once, their statistics taken on
        // the way (see `hear_frame`).
        let mut heard = std::mem::take(&mut self.frame_heard);
        let filter = self.long.filter.filter(|_| heard[0].len() == window.len());
        let (stats, energies) = match filter {
            Some(filter) => {
                let (stats, energies) = hear_frame(filter, window, short_len, &mut heard);
                (stats, Some(energies))
            }
            None => (FrameStats::of(window, short_len), None),
        };
        let frame = FrameKnown {
            stats: &stats,
            heard: energies.map(|e| (&heard, e)),
        };
        let chosen = self.analyse_with(window, Some(&frame));
        let analysis = FrameAnalysis {
            chosen,
            edge_newest: self.edge_clarity_with(window, chosen, true, Some(&frame)),
            edge_oldest: self.edge_clarity_with(window, chosen, false, Some(&frame)),
            square_sum: stats.square_sum,
            heard_energy: self.long.heard_energy,
        };
        self.frame_heard = heard;
        analysis
    }

    fn analyse_with(&mut self, window: &[f32], frame: Option<&FrameKnown>) -> PitchEstimate {
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
        let computed = match frame {
            Some(fr) => self.long.compute_with(window, fr.window(0)),
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
            if let Some(short_pick) = self.short_pick(window, frame) {
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

    /// The key-maximum choice on the short window (periods it holds twice), if there is one.
    fn short_pick(&mut self, window: &[f32], frame: Option<&FrameKnown>) -> Option<PitchEstimate> {
        let len = self.short.as_ref()?.0.window_len;
        self.short_pick_at(
            window,
            (window.len() - len) / 2,
            frame.map(|fr| fr.window(2)),
        )
    }

    /// The short window's pick at `start`; `known` is what is known of that window already.
    fn short_pick_at(
        &mut self,
        window: &[f32],
        start: usize,
        known: Option<Known>,
    ) -> Option<PitchEstimate> {
        let (short, short_last) = self.short.as_mut()?;
        let part = &window[start..start + short.window_len];
        let computed = match known {
            Some(k) => short.compute_with(part, k),
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
