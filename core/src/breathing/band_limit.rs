//! The recording's bandwidth and the limit it puts on inserted breaths.
//!
//! A voice recorded or sent at a lower rate and converted up (a guest's 16 kHz call in a
//! 48 kHz episode, a telephone line) holds nothing above its band edge, while a breath voice
//! reaches up to [`LOWPASS_HZ`]: beside the dull voice the breath sounds airier, another
//! microphone. [`upper_edge_hz`] reads the edge from the long-term power spectrum of the voiced
//! speech: the highest frequency whose power lies within [`EDGE_DROP_DB`] of the spectrum's
//! peak in the breath bands (223 Hz–7.1 kHz), where the spectrum falls off a cliff (the third
//! octave under the edge within [`CUT_WITHIN_DB`] of the peak). [`BandLimit`] is the
//! 8th-order Butterworth low-pass at that edge that every inserted breath then passes through,
//! when the edge lies under the breath's own top, under [`OWN_BAND_SHARE`] of the Nyquist
//! frequency (a recording at its own rate keeps its anti-alias roll-off, which is no cut) and
//! over [`MIN_EDGE_HZ`].
//!
//! Measured in Python on `../shared/data` speech (its loudest 40 % of frames, the same rule):
//! PTDB's 48 kHz microphones reach 21.8–22.9 kHz and fall 40–43 dB from the peak to 9–11 kHz;
//! a 16 kHz styletalk clip converted to 44.1 kHz (`sox`) or 48 kHz (`ffmpeg`) ends at 7.6 kHz
//! and lies 93–99 dB under its peak at 9–11 kHz; Keele's f1 through a 300–3400 Hz telephone
//! band ends at 3.5 kHz. The third octave under the edge lies 24–44 dB under the peak on the
//! converted and telephone clips and on three Keele and three styletalk clips as they are. The
//! drop and the share were set from these before any breath was rendered with them;
//! [`MIN_EDGE_HZ`] after the tests' synthetic speaker (glottal vowels with no breath noise in
//! them, over noise 60 dB down, at 16 kHz) read as a chain that ends at 2.7 kHz, and
//! [`CUT_WITHIN_DB`] after a review asked what a noise-free studio voice would read.

use super::filters::{Biquad, LOWPASS_HZ};
use super::third_octave::{band_edge_ratio, BAND_CENTRES_HZ};

/// How far under the speech spectrum's peak (in the breath bands) its upper edge lies, dB.
pub const EDGE_DROP_DB: f64 = 60.0;
/// How close to the peak the third octave under the edge lies when the edge is a chain's cut,
/// dB: a converter's, codec's or telephone line's filter falls its last 10 dB or more within a
/// third octave; a clean voice's own roll-off (12 dB per octave) does not.
pub const CUT_WITHIN_DB: f64 = 50.0;
/// Lowest edge taken for a recording chain's, Hz: the narrowest chain in use, a telephone
/// line, passes up to 3.4 kHz; a spectrum that ends lower is a voice's own (a synthetic vowel
/// with no breath noise in it), not a cut.
pub const MIN_EDGE_HZ: f64 = 3_000.0;
/// Share of the Nyquist frequency an edge must lie under to count as a band limit.
pub const OWN_BAND_SHARE: f64 = 0.8;
/// Voiced speech heard before the edge is read, seconds (a few words: the spectrum's top is
/// the fricatives' and the breathy vowels').
pub const MIN_EDGE_SPEECH_S: f64 = 1.0;
/// Q of the four sections of an 8th-order Butterworth low-pass: 1 / (2 cos θ), θ = (2k − 1)
/// π / 16.
const BUTTER8_Q: [f64; 4] = [0.509_795_6, 0.601_344_9, 0.899_976_2, 2.562_915_4];

/// The upper edge of a long-term power spectrum `bin_powers` (bin `k` at `k · bin_hz`, any
/// scale), Hz: the top of the highest bin within [`EDGE_DROP_DB`] of the peak over the breath
/// bands, when the third octave under it lies within [`CUT_WITHIN_DB`] of the peak (a cut);
/// `None` when those bins hold no power or the spectrum rolls off gradually. Allocation-free;
/// its cost is the bins of the breath bands and those above the edge.
pub fn upper_edge_hz(bin_powers: &[f64], bin_hz: f64) -> Option<f64> {
    let edge = band_edge_ratio();
    let bin = |hz: f64| ((hz / bin_hz).round() as usize).min(bin_powers.len());
    let bands =
        bin(BAND_CENTRES_HZ[0] / edge)..bin(BAND_CENTRES_HZ[BAND_CENTRES_HZ.len() - 1] * edge);
    let peak = bin_powers[bands].iter().copied().fold(0.0, f64::max);
    if peak <= 0.0 || !peak.is_finite() {
        return None;
    }
    let floor = peak * 10f64.powf(-EDGE_DROP_DB / 10.0);
    let top = bin_powers.iter().rposition(|&p| p >= floor)?;
    let edge_hz = (top as f64 + 0.5) * bin_hz;
    let under = &bin_powers[bin(edge_hz / 2f64.powf(1.0 / 3.0)).min(top)..=top];
    let mean = under.iter().sum::<f64>() / under.len() as f64;
    (mean >= peak * 10f64.powf(-CUT_WITHIN_DB / 10.0)).then_some(edge_hz)
}

/// The corner a breath at `rate_hz` is limited to for a recording whose spectrum ends at
/// `edge_hz`: the edge when it lies under the breath's own top ([`LOWPASS_HZ`]), under
/// [`OWN_BAND_SHARE`] of the Nyquist frequency and at least [`MIN_EDGE_HZ`], else `None` (no
/// limit).
pub fn corner_hz(edge_hz: Option<f64>, rate_hz: f64) -> Option<f64> {
    edge_hz.filter(|&e| e >= MIN_EDGE_HZ && e < LOWPASS_HZ.min(OWN_BAND_SHARE * 0.5 * rate_hz))
}

/// The low-pass an inserted breath passes through (see the module docs); passes the sound
/// unchanged, bit for bit, without a corner. Allocation-free.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct BandLimit {
    sections: [Biquad; 4],
    corner_hz: Option<f64>,
    rate_hz: f64,
}

impl BandLimit {
    /// Limits to `corner_hz` at `rate_hz` (`None`: no limit). A new corner starts from a
    /// cleared state; the same one keeps its state (a breath that replaces a playing one
    /// follows on without a click).
    pub(super) fn set(&mut self, corner_hz: Option<f64>, rate_hz: f64) {
        if (corner_hz, rate_hz) == (self.corner_hz, self.rate_hz) {
            return;
        }
        (self.corner_hz, self.rate_hz) = (corner_hz, rate_hz);
        if let Some(c) = corner_hz {
            for (s, q) in self.sections.iter_mut().zip(BUTTER8_Q) {
                s.lowpass(c, q, rate_hz);
                s.clear();
            }
        }
    }

    /// The next sample through the limit.
    #[inline]
    pub(super) fn tick(&mut self, x: f64) -> f64 {
        if self.corner_hz.is_none() {
            return x;
        }
        self.sections.iter_mut().fold(x, |v, s| s.tick(v))
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    #[test]
    fn the_butterworth_sections_are_the_eighth_order_poles() {
        for (k, q) in BUTTER8_Q.iter().enumerate() {
            let theta = (2 * k + 1) as f64 * PI / 16.0;
            assert!((q - 1.0 / (2.0 * theta.cos())).abs() < 1e-6, "section {k}");
        }
    }

    #[test]
    fn the_edge_is_where_the_spectrum_falls_60_db_under_its_peak() {
        // 44.1 kHz, 2048-point frames: a spectrum flat at 1 up to 7.6 kHz, 1e-9 (90 dB down)
        // above: the edge lies at 7.6 kHz; with 1e-4 (40 dB down) above, at the top bin.
        let bin_hz = 44_100.0 / 2048.0;
        let cliff = (7_600.0 / bin_hz) as usize;
        let spectrum = |above: f64| {
            (0..=1024)
                .map(|k| if k <= cliff { 1.0 } else { above })
                .collect::<Vec<_>>()
        };
        let edge = upper_edge_hz(&spectrum(1e-9), bin_hz).unwrap();
        assert!((edge - 7_600.0).abs() < bin_hz, "{edge}");
        let full = upper_edge_hz(&spectrum(1e-4), bin_hz).unwrap();
        assert!(full > 22_000.0, "{full}");
        assert_eq!(upper_edge_hz(&vec![0.0; 1025], bin_hz), None);
        // A clean voice's gradual roll-off, 12 dB per octave from 500 Hz, with no floor: no
        // cut, though it falls 60 dB under its peak by 16 kHz.
        let dark: Vec<f64> = (0..=1024)
            .map(|k| (k as f64 * bin_hz / 500.0).max(1.0).powi(-4))
            .collect();
        assert_eq!(upper_edge_hz(&dark, bin_hz), None);
    }

    #[test]
    fn only_an_edge_under_the_breaths_top_and_the_rates_own_band_limits() {
        assert_eq!(corner_hz(Some(7_600.0), 44_100.0), Some(7_600.0));
        assert_eq!(corner_hz(Some(3_500.0), 16_000.0), Some(3_500.0));
        // A 16 kHz recording's own anti-alias roll-off, a full-band one, none heard.
        assert_eq!(corner_hz(Some(7_600.0), 16_000.0), None);
        assert_eq!(corner_hz(Some(21_800.0), 48_000.0), None);
        assert_eq!(corner_hz(None, 48_000.0), None);
        // Narrower than a telephone line: a voice's own spectrum, not a chain's.
        assert_eq!(corner_hz(Some(2_700.0), 44_100.0), None);
    }

    #[test]
    fn the_limit_passes_the_band_and_stops_above_the_corner() {
        let fs = 48_000.0;
        let mut limit = BandLimit::default();
        assert_eq!(limit.tick(0.25).to_bits(), 0.25f64.to_bits());
        limit.set(Some(7_600.0), fs);
        let gain_db = |limit: &mut BandLimit, hz: f64| {
            limit.set(None, fs);
            limit.set(Some(7_600.0), fs);
            let n = 48_000;
            let (mut e_in, mut e_out) = (0.0, 0.0);
            for i in 0..n {
                let x = (2.0 * PI * hz * i as f64 / fs).sin();
                let y = limit.tick(x);
                if i > n / 2 {
                    e_in += x * x;
                    e_out += y * y;
                }
            }
            10.0 * (e_out / e_in).log10()
        };
        assert!(gain_db(&mut limit, 2_000.0).abs() < 0.1);
        assert!(gain_db(&mut limit, 10_000.0) < -15.0);
        assert!(gain_db(&mut limit, 12_000.0) < -25.0);
    }
}
