//! The room's band levels: an exponential average of the breath bands' powers over frames at
//! the noise floor (never silence, under the tracker's `silence_db`), and the shape of a frame's
//! band powers above them (what tells a breath from a sibilant, a vowel's tail or rumble).

use crate::analysis::BandLevels;

/// A frame within this of the noise floor teaches the room's band levels, dB.
pub(super) const FLOOR_BAND_WITHIN_DB: f32 = 3.0;
/// ... and at least this far under the running speech level, dB (at the start of a stream the
/// floor still sits at the voice).
pub(super) const FLOOR_BAND_UNDER_SPEECH_DB: f32 = 20.0;
/// Time constant of the room's band levels, seconds.
pub(super) const FLOOR_BAND_TAU_S: f64 = 1.0;

/// The room's band powers (an exponential average over frames at the noise floor) and the shape
/// of a frame's band powers above them.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct FloorBands {
    /// Mean power of the low, mid and high band at the floor (linear, full scale = 1).
    power: [f64; 3],
    /// Frames learnt so far (the first ones set the mean directly).
    learnt: u32,
}

impl FloorBands {
    fn powers(b: &BandLevels) -> [f64; 3] {
        [b.low_db, b.mid_db, b.high_db].map(|db| {
            if db.is_finite() {
                crate::analysis::band_power(db)
            } else {
                0.0
            }
        })
    }

    pub(super) fn learn(&mut self, b: &BandLevels, weight: f64) {
        let p = Self::powers(b);
        self.learnt = self.learnt.saturating_add(1);
        let w = weight.max(1.0 / f64::from(self.learnt));
        for (m, v) in self.power.iter_mut().zip(p) {
            *m += w * (v - *m);
        }
    }

    /// How far the frame's breath bands (mid and high together, 0.5–3.5 kHz) stand over the
    /// room's, dB (−∞ before the room is learnt).
    pub(super) fn breath_bands_over_room_db(&self, b: &BandLevels) -> f32 {
        let room = self.power[1] + self.power[2];
        if self.learnt == 0 || room <= 0.0 {
            return f32::NEG_INFINITY;
        }
        b.breath_bands_db() - (10.0 * room.log10()) as f32
    }

    /// (high over mid, low over mid) of the frame's band powers with the room's taken out
    /// (never below a tenth of the frame's own power), dB, within ±40 dB so one odd frame
    /// cannot swing a run's mean.
    pub(super) fn excess_shape_db(&self, b: &BandLevels) -> (f32, f32) {
        let p = Self::powers(b);
        let e: [f64; 3] = std::array::from_fn(|k| (p[k] - self.power[k]).max(0.1 * p[k]));
        let ratio = |a: f64, m: f64| {
            if a > 0.0 && m > 0.0 {
                (10.0 * (a / m).log10()).clamp(-40.0, 40.0) as f32
            } else {
                0.0
            }
        };
        (ratio(e[2], e[1]), ratio(e[0], e[1]))
    }
}
