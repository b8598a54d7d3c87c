//! Band levels of each frame for telling breath noise from other unvoiced sound in a pause.
//!
//! An inhalation is broadband noise, flat-ish from 0.5 to 5 kHz with some formant colouring;
//! /s/ and /sh/ put most of their energy above 2.5–4 kHz; a reverberant tail and room rumble
//! carry most of theirs under 500 Hz. Three band levels tell these apart:
//!
//! | band   | pass band                     |
//! |--------|-------------------------------|
//! | low    | 100–400 Hz                    |
//! | mid    | 500–2500 Hz                   |
//! | high   | 2500–6000 Hz (2500–3600 Hz at an 8 kHz host rate) |
//!
//! Each band is a fourth-order Linkwitz–Riley high-pass and low-pass (each two second-order
//! Butterworth sections, RBJ biquads with f64 state; −6 dB at the edges, so adjacent bands sum
//! flat). They run on the host signal decimated by an integer factor to 16–32 kHz (the
//! analysis decimator's low-pass, cut-off 0.4 × that rate ≥ 6.4 kHz; no decimation at 8–32 kHz),
//! so the bands are the same at any host rate from 8 kHz (where the high band ends at 3.6 kHz)
//! to 768 kHz and cost about the same per second. The squared outputs, each standing for the
//! host samples it replaces, are summed per analysis slot into a ring the analyzer indexes
//! exactly like its RMS bins, so a frame's band levels cover the same window as its `rms_db`
//! (late by the decimation filter's delay, under 0.5 ms). Samples go in
//! one by one: the levels are bit-identical for any block partition. Allocation happens only
//! in [`BandMeter::new`].

use super::amplitude_to_db;
/// Re-exported for the test-noise shaping in `crate::test_signals`.
pub(crate) use super::biquad::Biquad;
use super::decimator::Decimator;

/// Lower edge of the low band, Hz.
const LOW_FROM_HZ: f64 = 100.0;
/// Upper edge of the low band, Hz.
const LOW_TO_HZ: f64 = 400.0;
/// Lower edge of the mid band, Hz.
const MID_FROM_HZ: f64 = 500.0;
/// Edge between the mid and the high band, Hz.
const MID_TO_HZ: f64 = 2500.0;
/// Upper edge of the high band, Hz (lowered to 0.45 × the band filters' rate when that is lower).
const HIGH_TO_HZ: f64 = 6000.0;
/// The band filters run at the host rate divided by the largest integer keeping it at least
/// this, Hz.
const BAND_MIN_RATE_HZ: f64 = 16_000.0;

/// The levels of one frame in three bands, dBFS (floor −120 dBFS), over the frame's RMS window
/// (see [`crate::analysis::FeatureFrame::rms_db`]). The default (all 0) only fills test frames.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BandLevels {
    /// Level of 100–400 Hz, dBFS: voice fundamentals, vowel tails, rumble.
    pub low_db: f32,
    /// Level of 500–2500 Hz, dBFS: where breath noise carries its formant colouring.
    pub mid_db: f32,
    /// Level of 2500–6000 Hz (at most 3.6 kHz at an 8 kHz host rate), dBFS: sibilants.
    pub high_db: f32,
}

impl BandLevels {
    /// The high band over the mid band, dB: about 0 or below for breath noise, well above 0
    /// for /s/.
    pub fn high_over_mid_db(&self) -> f32 {
        self.high_db - self.mid_db
    }

    /// The low band over the mid band, dB: high for vowel tails, hum and rumble.
    pub fn low_over_mid_db(&self) -> f32 {
        self.low_db - self.mid_db
    }
}

/// Lanes of [`BandBank`]: the three bands and an idle fourth, so the lanes fill whole SIMD
/// registers.
const LANES: usize = 4;

/// The three bands' chains of four [`Biquad`] sections, stored lane by lane (one lane per
/// band) so each step of a section runs on all bands at once and vectorises. Every lane does
/// exactly the operations of [`Biquad::process`] in the same order, so the output is
/// bit-identical to running each band's sections one after the other.
#[derive(Debug, Clone)]
struct BandBank {
    /// Per section: the coefficients `b0 b1 b2 a1 a2` (as in [`Biquad`]), per lane.
    coef: [[[f64; LANES]; 5]; 4],
    /// Per section: the inputs and outputs one and two samples back, per lane.
    state: [[[f64; LANES]; 4]; 4],
}

impl BandBank {
    /// The bank of three bands, each four sections applied in order.
    fn new(bands: [[Biquad; 4]; 3]) -> Self {
        let mut coef = [[[0.0; LANES]; 5]; 4];
        for (lane, band) in bands.iter().enumerate() {
            for (section, biquad) in band.iter().enumerate() {
                let (b, a) = biquad.coefficients();
                for (k, v) in b.into_iter().chain(a).enumerate() {
                    coef[section][k][lane] = v;
                }
            }
        }
        Self {
            coef,
            state: [[[0.0; LANES]; 4]; 4],
        }
    }

    fn reset(&mut self) {
        self.state = [[[0.0; LANES]; 4]; 4];
    }

    /// Filters one sample through every band; the band outputs in lanes 0..3.
    #[inline]
    fn process(&mut self, x: f64) -> [f64; LANES] {
        let mut v = [x; LANES];
        for (c, st) in self.coef.iter().zip(&mut self.state) {
            let [x1, x2, y1, y2] = *st;
            let mut y = [0.0; LANES];
            for l in 0..LANES {
                y[l] = c[0][l] * v[l] + c[1][l] * x1[l] + c[2][l] * x2[l]
                    - c[3][l] * y1[l]
                    - c[4][l] * y2[l];
            }
            *st = [v, x1, y, y1];
            v = y;
        }
        v
    }
}

/// One band's sections in order: a fourth-order Linkwitz–Riley high-pass at `from_hz` (two
/// Butterworth sections) and low-pass at `to_hz`, at `rate_hz`.
fn linkwitz_riley_band(from_hz: f64, to_hz: f64, rate_hz: f64) -> [Biquad; 4] {
    let hp = Biquad::butterworth(from_hz, rate_hz, true);
    let lp = Biquad::butterworth(to_hz, rate_hz, false);
    [hp, hp, lp, lp]
}

/// Decimator, band filters and a ring of per-slot band energies. See the module docs.
#[derive(Debug, Clone)]
pub(crate) struct BandMeter {
    /// Host rate to band filters' rate.
    decimator: Decimator,
    /// Host samples per band-filter sample.
    factor: usize,
    /// The three bands' filters, run side by side.
    filters: BandBank,
    /// Energy of each band accumulated since the last closed slot.
    acc: [f64; 3],
    /// Per decimated slot (indexed like the analyzer's RMS bins): each band's energy.
    ring: Vec<[f64; 3]>,
}

impl BandMeter {
    /// A meter for a stream at `rate_hz` with a ring of `slots` (a power of two, the analyzer's
    /// ring length). Allocates.
    pub(crate) fn new(host_rate_hz: f64, slots: usize) -> Self {
        let factor = ((host_rate_hz / BAND_MIN_RATE_HZ).floor() as usize).max(1);
        let rate_hz = host_rate_hz / factor as f64;
        let high_to = HIGH_TO_HZ.min(0.45 * rate_hz);
        Self {
            decimator: Decimator::new(factor),
            factor,
            filters: BandBank::new([
                linkwitz_riley_band(LOW_FROM_HZ, LOW_TO_HZ, rate_hz),
                linkwitz_riley_band(MID_FROM_HZ, MID_TO_HZ, rate_hz),
                linkwitz_riley_band(MID_TO_HZ, high_to, rate_hz),
            ]),
            acc: [0.0; 3],
            ring: vec![[0.0; 3]; slots.max(1)],
        }
    }

    /// Clears all state (keeps the allocation).
    pub(crate) fn reset(&mut self) {
        self.decimator.reset();
        self.filters.reset();
        self.acc = [0.0; 3];
        self.ring.fill([0.0; 3]);
    }

    /// Takes one host-rate sample (finite, already clamped).
    #[inline]
    pub(crate) fn push(&mut self, x: f32) {
        let Some(x) = self.decimator.push(x) else {
            return;
        };
        let weight = self.factor as f64;
        let y = self.filters.process(x as f64);
        for (acc, y) in self.acc.iter_mut().zip(y) {
            *acc += weight * y * y;
        }
    }

    /// Stores the energy accumulated since the last call as decimated slot `slot` (the
    /// analyzer's ring index) and starts the next slot.
    #[inline]
    pub(crate) fn close_slot(&mut self, slot: usize) {
        let n = self.ring.len();
        self.ring[slot % n] = self.acc;
        self.acc = [0.0; 3];
    }

    /// The band levels over the slots `first..first + slots` (slots before the stream are
    /// silence), which hold `samples` host-rate samples in all.
    #[cfg(test)]
    pub(crate) fn levels(&self, first: i64, slots: usize, samples: usize) -> BandLevels {
        let mut sum = [0.0f64; 3];
        for b in (first..first + slots as i64).filter(|&b| b >= 0) {
            self.add_slot(&mut sum, b as usize);
        }
        Self::levels_of(sum, samples)
    }

    /// Adds the band energies of slot `slot` (the analyzer's ring index, ≥ 0) to `sum`.
    #[inline]
    pub(crate) fn add_slot(&self, sum: &mut [f64; 3], slot: usize) {
        let e = self.ring[slot % self.ring.len()];
        sum.iter_mut().zip(e).for_each(|(s, e)| *s += e);
    }

    /// The band levels of the band energies `sum` of `samples` host-rate samples.
    pub(crate) fn levels_of(sum: [f64; 3], samples: usize) -> BandLevels {
        let db = |e: f64| amplitude_to_db((e / samples.max(1) as f64).sqrt());
        BandLevels {
            low_db: db(sum[0]),
            mid_db: db(sum[1]),
            high_db: db(sum[2]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Band levels of a steady sine at `hz`, measured after a settling second.
    fn levels_of_tone(hz: f64, rate_hz: f64) -> BandLevels {
        let slot = 4usize;
        let mut m = BandMeter::new(rate_hz, 1024);
        let mut k = 0usize;
        for i in 0..(rate_hz as usize * 2) {
            let x = (2.0 * std::f64::consts::PI * hz * i as f64 / rate_hz).sin() as f32;
            m.push(0.5 * x);
            if (i + 1) % slot == 0 {
                m.close_slot(k);
                k += 1;
            }
        }
        m.levels(k as i64 - 200, 200, 200 * slot)
    }

    #[test]
    fn a_tone_lands_in_its_band_at_any_rate() {
        // 0.5 amplitude: −9.0 dBFS RMS in its own band.
        for rate in [8_000.0, 16_000.0, 48_000.0, 192_000.0] {
            let low = levels_of_tone(200.0, rate);
            let mid = levels_of_tone(1200.0, rate);
            let high = levels_of_tone(3200.0, rate);
            assert!((low.low_db + 9.0).abs() < 1.5, "{rate}: {low:?}");
            assert!(low.mid_db < -30.0 && low.high_db < -50.0, "{rate}: {low:?}");
            assert!((mid.mid_db + 9.0).abs() < 1.5, "{rate}: {mid:?}");
            assert!(mid.low_db < -30.0 && mid.high_db < -20.0, "{rate}: {mid:?}");
            assert!((high.high_db + 9.0).abs() < 3.5, "{rate}: {high:?}");
            assert!(
                high.low_db < -40.0 && high.mid_db < -15.0,
                "{rate}: {high:?}"
            );
            let (h, m) = (high.high_over_mid_db(), mid.high_over_mid_db());
            assert!(h > 6.0 && m < -8.0, "{rate}: {h} {m}");
        }
    }

    #[test]
    fn the_bank_is_bit_identical_to_the_sections_one_by_one() {
        let rate = 22_050.0;
        let mut bands = [
            linkwitz_riley_band(100.0, 400.0, rate),
            linkwitz_riley_band(500.0, 2500.0, rate),
            linkwitz_riley_band(2500.0, 6000.0, rate),
        ];
        let mut bank = BandBank::new(bands);
        let mut rng = crate::rng::SeededRng::new(7);
        for i in 0..5000 {
            let x = rng.uniform() - 0.5 + (i as f64 * 0.01).sin();
            let y = bank.process(x);
            for (band, y) in bands.iter_mut().zip(y) {
                let want = band.iter_mut().fold(x, |v, s| s.process(v));
                assert_eq!(y.to_bits(), want.to_bits(), "sample {i}");
            }
        }
    }

    #[test]
    fn silence_and_slots_before_the_stream_are_the_floor() {
        let m = BandMeter::new(16_000.0, 64);
        let l = m.levels(-10, 5, 20);
        assert_eq!((l.low_db, l.mid_db, l.high_db), (-120.0, -120.0, -120.0));
    }
}
