//! The procedural breath sounds' resonator banks (`(centre Hz, Q, gain)` per band-pass, see
//! [`super::voice`]: the mouth bright, the nose dark) and what the learned voice takes from
//! them: the tilt of the mouth's third-octave shape over the nose's.

use std::f64::consts::PI;

use super::filters::{Biquad, Phasor};
use super::third_octave::{band_edge_ratio, shape_db, Bands, BANDS, BAND_CENTRES_HZ};

/// The mouth's resonances (open vocal tract, an [h]/[ɑ] inhalation).
pub(super) const MOUTH_BANK: [(f64, f64, f64); 6] = [
    (750.0, 4.0, 0.35),
    (1350.0, 5.0, 0.55),
    (2500.0, 6.0, 0.6),
    (3600.0, 6.0, 0.45),
    (4800.0, 4.0, 0.35),
    (3000.0, 0.6, 0.35),
];
/// The nose's resonances (the nasal cavity).
pub(super) const NOSE_BANK: [(f64, f64, f64); 4] = [
    (290.0, 2.5, 1.0),
    (1050.0, 4.0, 0.45),
    (2300.0, 5.0, 0.3),
    (1500.0, 0.7, 0.12),
];
/// Rate the banks' third-octave shapes are computed at ([`mouth_over_nose_tilt_db`]), Hz: every
/// resonance and band lies under its 0.45 × rate.
const SHAPE_RATE_HZ: f64 = 48_000.0;
/// Frequencies per band averaged in [`mouth_over_nose_tilt_db`].
const SHAPE_POINTS_PER_BAND: usize = 16;

/// How a breath taken through the mouth differs in colour from one taken through the nose, dB
/// per third-octave band: the least-squares line (a tilt, dB per band around the middle band)
/// through the procedural mouth sound's shape over the nose sound's (each bank's band powers,
/// white noise in, as dB around their own mean; the band limits common to both left out). The
/// banks' single resonances are this model's detail, not a speaker's; their tilt (the nose
/// dark, the mouth bright) is what the learned voice takes from the mouth share of
/// [`super::BreathVoice::start`].
pub(super) fn mouth_over_nose_tilt_db() -> Bands {
    let shape = |table: &[(f64, f64, f64)]| {
        let mut bank = [Biquad::default(); 6];
        for (b, &(f, q, _)) in bank.iter_mut().zip(table) {
            b.bandpass(f, q, SHAPE_RATE_HZ);
        }
        let edge = band_edge_ratio();
        let powers = BAND_CENTRES_HZ.map(|centre| {
            (0..SHAPE_POINTS_PER_BAND)
                .map(|i| {
                    let share = (i as f64 + 0.5) / SHAPE_POINTS_PER_BAND as f64;
                    let hz = centre / edge * (edge * edge).powf(share);
                    let p = Phasor::at(2.0 * PI * hz / SHAPE_RATE_HZ);
                    let (re, im) = table.iter().zip(&bank).fold((0.0, 0.0), |(r, i), (t, b)| {
                        let (hr, hi) = b.response_at(&p);
                        (r + t.2 * hr, i + t.2 * hi)
                    });
                    re * re + im * im
                })
                .sum::<f64>()
        });
        shape_db(&powers)
    };
    let (mouth, nose) = (shape(&MOUTH_BANK), shape(&NOSE_BANK));
    let middle = (BANDS - 1) as f64 / 2.0;
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..BANDS {
        // Both shapes are around their own mean: the difference is too.
        num += (k as f64 - middle) * (mouth[k] - nose[k]);
        den += (k as f64 - middle).powi(2);
    }
    let slope_db = num / den;
    std::array::from_fn(|k| slope_db * (k as f64 - middle))
}
