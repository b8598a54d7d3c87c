//! Causal decisions on top of the per-window pitch estimates: the voiced decision (the
//! [`VoicingRule`] of `voicing/rule.rs`), continuity against octave jumps and a short outlier filter
//! ([`F0Smoother`]).
//! Nothing here looks ahead: each frame uses only itself and the two frames before it.

use super::pitch::PitchEstimate;
use super::voicing::{VoicingFeatures, VoicingRule};

/// A candidate this close (ratio) to the previous f0 counts as continuing the track.
const CONTINUITY_RATIO: f32 = 1.18;
/// A continuing candidate replaces the key-maximum choice if its clarity is at least this
/// fraction of the chosen one (one an octave under the choice only if it is the clearer).
const CONTINUITY_CLARITY: f32 = 0.85;
/// The current f0 is an outlier when it differs from the median of the last three by more than
/// this fraction.
const OUTLIER_FRACTION: f32 = 0.15;
/// A jump is no outlier when the newest end of the window, analysed on its own, picks the same
/// period with at least this clarity (see [`F0Smoother::smooth`]).
pub(crate) const JUMP_CONFIRM_CLARITY: f32 = 0.8;
/// What the tracker says about one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrackedPitch {
    pub f0_hz: f32,
    pub voiced: bool,
    pub voicing: f32,
}

/// The f0 track's smoothing: continuity against octave jumps (a candidate near the previous
/// f0 replaces a not much clearer jump, or a clearer one an octave under the jump) and a
/// median-of-three outlier filter.
#[derive(Debug, Clone, Default)]
pub(crate) struct F0Smoother {
    /// Raw f0 of the previous two frames (0 = unvoiced), newest first.
    history: [f32; 2],
}

impl F0Smoother {
    pub(crate) fn reset(&mut self) {
        self.history = [0.0; 2];
    }

    /// The estimate that continues the track: `chosen`, or a candidate near the previous f0
    /// whose clarity is close to the chosen one's (or above it, for a candidate an octave under
    /// the choice).
    pub(crate) fn continue_track(
        &self,
        chosen: PitchEstimate,
        candidates: &[PitchEstimate],
    ) -> PitchEstimate {
        let prev = self.history[0];
        if prev <= 0.0 || chosen.f0_hz <= 0.0 || within(chosen.f0_hz, prev, CONTINUITY_RATIO) {
            return chosen;
        }
        let mut best: Option<PitchEstimate> = None;
        for c in candidates {
            // A voice periodic at the chosen period is as periodic over two of them: a track an
            // octave under the choice holds only while it is the clearer (period doubling), or
            // an octave-down lock would never let go.
            let needed = if within(chosen.f0_hz, 2.0 * c.f0_hz, CONTINUITY_RATIO) {
                chosen.clarity.next_up()
            } else {
                CONTINUITY_CLARITY * chosen.clarity
            };
            if within(c.f0_hz, prev, CONTINUITY_RATIO)
                && c.clarity >= needed
                && best.is_none_or(|b| c.clarity > b.clarity)
            {
                best = Some(*c);
            }
        }
        best.unwrap_or(chosen)
    }

    /// The reported f0 of a frame whose raw f0 is `raw_hz` (0 = unvoiced): a single outlier
    /// against the last two voiced frames is replaced by their median, unless the newest end of
    /// the window confirms it (`confirmed`). A real pitch change fills the newest samples
    /// first, so it passes at once instead of one frame late (the latency limit); an octave
    /// error of the long window is not the newest end's own pick, so it is still filtered.
    pub(crate) fn smooth(&mut self, raw_hz: f32, confirmed: bool) -> f32 {
        let mut f0_hz = raw_hz;
        if raw_hz > 0.0 && !confirmed && self.history[0] > 0.0 && self.history[1] > 0.0 {
            let med = median3(raw_hz, self.history[0], self.history[1]);
            if (raw_hz / med - 1.0).abs() > OUTLIER_FRACTION {
                f0_hz = med;
            }
        }
        self.history = [raw_hz, self.history[0]];
        f0_hz
    }
}

/// Causal voicing and f0 tracker: the voicing rule and the f0 smoothing.
#[derive(Debug, Clone)]
pub(crate) struct Tracker {
    rule: VoicingRule,
    smoother: F0Smoother,
}

impl Tracker {
    pub(crate) fn new(rule: VoicingRule) -> Self {
        Self {
            rule,
            smoother: F0Smoother::default(),
        }
    }

    pub(crate) fn reset(&mut self) {
        self.rule.reset();
        self.smoother.reset();
    }

    /// One frame: the chosen period and all key maxima, the frame's level (as judged against
    /// the silence gate: the analyzer raises a quiet speaker's, see `quiet_shift_db`), voicing
    /// features,
    /// periodicity (for the reported confidence) and the clarity of `chosen` on the newest end
    /// of the window alone (`newest_clarity`, 0 when that end picks another period).
    pub(crate) fn update(
        &mut self,
        chosen: PitchEstimate,
        candidates: &[PitchEstimate],
        rms_db: f32,
        features: &VoicingFeatures,
        periodicity: f32,
        newest_clarity: f32,
    ) -> TrackedPitch {
        let est = self.smoother.continue_track(chosen, candidates);
        let voiced = self.rule.decide(est.f0_hz > 0.0, rms_db, features);
        // Only the long window's own choice was judged on the newest end.
        let confirmed = est == chosen && newest_clarity >= JUMP_CONFIRM_CLARITY;
        let f0_hz = self
            .smoother
            .smooth(if voiced { est.f0_hz } else { 0.0 }, confirmed);
        TrackedPitch {
            f0_hz,
            voiced,
            voicing: self.rule.confidence(periodicity, rms_db),
        }
    }
}

fn within(f: f32, reference: f32, ratio: f32) -> bool {
    f > 0.0 && f < reference * ratio && f * ratio > reference
}

fn median3(a: f32, b: f32, c: f32) -> f32 {
    a.max(b).min(a.min(b).max(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn est(f0_hz: f32, clarity: f32) -> PitchEstimate {
        PitchEstimate { f0_hz, clarity }
    }

    /// A tracker whose model voices frames whose first feature (the long clarity) reaches
    /// 0.7, and keeps voicing down to 0.5.
    fn tracker() -> Tracker {
        use crate::analysis::voicing::{VoicingModel, N_VOICING_FEATURES};
        let mut w = [0.0; N_VOICING_FEATURES];
        w[0] = 1.0;
        let zero = [0.0; N_VOICING_FEATURES];
        let model = VoicingModel::new(zero, [1.0; N_VOICING_FEATURES], w, 0.0, 0.7, 0.5).unwrap();
        Tracker::new(VoicingRule::new(model, -60.0))
    }

    /// `update` with the periodicity the pitch estimator would report: the best clarity.
    fn upd(
        t: &mut Tracker,
        chosen: PitchEstimate,
        candidates: &[PitchEstimate],
        rms_db: f32,
    ) -> TrackedPitch {
        let periodicity = candidates
            .iter()
            .map(|c| c.clarity)
            .fold(chosen.clarity, f32::max);
        let mut features = [0.0; crate::analysis::voicing::N_VOICING_FEATURES];
        features[0] = periodicity;
        t.update(chosen, candidates, rms_db, &features, periodicity, 0.0)
    }

    #[test]
    fn median_of_three() {
        assert_eq!(median3(1.0, 2.0, 3.0), 2.0);
        assert_eq!(median3(3.0, 1.0, 2.0), 2.0);
        assert_eq!(median3(2.0, 3.0, 1.0), 2.0);
    }

    #[test]
    fn continuity_prefers_the_candidate_near_the_track() {
        let mut t = tracker();
        upd(&mut t, est(150.0, 0.9), &[est(150.0, 0.9)], -20.0);
        // The key-maximum rule jumped an octave down, but a nearly as clear candidate
        // continues.
        let cands = [est(75.5, 0.9), est(151.0, 0.88)];
        let r = upd(&mut t, cands[0], &cands, -20.0);
        assert_eq!(r.f0_hz, 151.0);
        // Against a jump an octave up, the track holds while it is the clearer.
        let cands = [est(301.0, 0.9), est(151.0, 0.92)];
        assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 151.0);
        // A clearly better new candidate is kept: a real jump, which the outlier filter lets
        // through one frame later.
        let cands = [est(200.0, 0.95), est(151.0, 0.5)];
        assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 151.0);
        assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 200.0);
    }

    #[test]
    fn a_track_an_octave_down_holds_only_while_it_is_the_clearer() {
        // Locked an octave under a 240 Hz voice (the choice at the voice's onset): the voice's
        // own period, as clear as its double, takes over (one frame late: the outlier filter).
        let mut t = tracker();
        upd(&mut t, est(120.0, 0.95), &[est(120.0, 0.95)], -20.0);
        upd(&mut t, est(120.0, 0.95), &[est(120.0, 0.95)], -20.0);
        let cands = [est(240.0, 0.95), est(120.0, 0.94)];
        assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 120.0);
        assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 240.0);
        assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 240.0);
        // Period doubling (every other pulse alike): the double period is the clearer, and the
        // track stays on it.
        let mut t = tracker();
        upd(&mut t, est(120.0, 0.95), &[est(120.0, 0.95)], -20.0);
        let cands = [est(240.0, 0.9), est(120.0, 0.97)];
        for _ in 0..3 {
            assert_eq!(upd(&mut t, cands[0], &cands, -20.0).f0_hz, 120.0);
        }
    }

    #[test]
    fn single_outliers_are_replaced_by_the_median() {
        let mut t = tracker();
        upd(&mut t, est(150.0, 0.9), &[], -20.0);
        upd(&mut t, est(152.0, 0.9), &[], -20.0);
        assert_eq!(upd(&mut t, est(300.0, 0.9), &[], -20.0).f0_hz, 152.0);
        // A lasting jump comes through one frame later.
        assert_eq!(upd(&mut t, est(300.0, 0.9), &[], -20.0).f0_hz, 300.0);
    }

    #[test]
    fn a_jump_the_newest_samples_confirm_passes_at_once() {
        let mut t = tracker();
        let features = [0.9; crate::analysis::voicing::N_VOICING_FEATURES];
        for f0_hz in [150.0, 151.0] {
            t.update(est(f0_hz, 0.9), &[], -20.0, &features, 0.9, 0.9);
        }
        // The newest end picks the new period clearly: a pitch change, reported now.
        let r = t.update(est(250.0, 0.9), &[], -20.0, &features, 0.9, 0.95);
        assert_eq!(r.f0_hz, 250.0);
        // A jump the newest end does not pick (an octave error) is still an outlier.
        let mut t = tracker();
        for f0_hz in [150.0, 151.0] {
            t.update(est(f0_hz, 0.9), &[], -20.0, &features, 0.9, 0.9);
        }
        let r = t.update(est(300.0, 0.9), &[], -20.0, &features, 0.9, 0.0);
        assert_eq!(r.f0_hz, 151.0);
    }
}
