//! The voicing cues the pitch analysis gives besides the period: the clarity of the chosen
//! period on a short window at either end of the long one (the phrase edges, where the voice
//! fills only one end), the two-period cue for periods too long for that window, and the NSDF
//! at half the period (an octave-down pick).

use super::key_maxima::PitchEstimate;
use super::{FrameKnown, NsdfPitch, SAME_LOBE_RATIO};

impl NsdfPitch {
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

    pub(super) fn edge_clarity_with(
        &mut self,
        window: &[f32],
        chosen: PitchEstimate,
        newest: bool,
        frame: Option<&FrameKnown>,
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
        let known = frame.map(|fr| fr.window(if newest { 3 } else { 1 }));
        let p = self.short_pick_at(window, start, known)?;
        let ratio = SAME_LOBE_RATIO as f32;
        (p.f0_hz < chosen.f0_hz * ratio && p.f0_hz * ratio > chosen.f0_hz).then_some(p.clarity)
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
