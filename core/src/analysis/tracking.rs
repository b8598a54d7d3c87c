//! Causal decisions on top of the per-window pitch estimates: the voiced decision with
//! hysteresis and a silence gate, continuity against octave jumps, and a short outlier filter.
//! Nothing here looks ahead: each frame uses only itself and the two frames before it.

use super::pitch::PitchEstimate;

/// A candidate this close (ratio) to the previous f0 counts as continuing the track.
const CONTINUITY_RATIO: f32 = 1.18;
/// A continuing candidate replaces the key-maximum choice if its clarity is at least this
/// fraction of the chosen one.
const CONTINUITY_CLARITY: f32 = 0.85;
/// The current f0 is an outlier when it differs from the median of the last three by more than
/// this fraction.
const OUTLIER_FRACTION: f32 = 0.15;
/// Width of the fade of the voicing confidence below the silence gate, dB.
const SILENCE_FADE_DB: f32 = 10.0;

/// What the tracker says about one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TrackedPitch {
    pub f0_hz: f32,
    pub voiced: bool,
    pub voicing: f32,
}

/// Causal voicing and f0 tracker.
#[derive(Debug, Clone)]
pub(crate) struct Tracker {
    voicing_on: f32,
    voicing_off: f32,
    silence_db: f32,
    /// Raw f0 of the previous two frames (0 = unvoiced), newest first.
    history: [f32; 2],
    voiced: bool,
}

impl Tracker {
    pub(crate) fn new(voicing_on: f32, voicing_off: f32, silence_db: f32) -> Self {
        Self {
            voicing_on,
            voicing_off,
            silence_db,
            history: [0.0; 2],
            voiced: false,
        }
    }

    /// Whether the frame is voiced now (the last decision).
    pub(crate) fn is_voiced(&self) -> bool {
        self.voiced
    }

    /// Whether the periodicity alone leaves a frame that passes the level gates on the unvoiced
    /// side of the current threshold: only then can more evidence (the edge windows) change the
    /// decision, so only then is it worth computing.
    pub(crate) fn wants_more_evidence(
        &self,
        periodicity: f32,
        rms_db: f32,
        gate_db: f32,
        level_bonus: f32,
    ) -> bool {
        let threshold = if self.voiced {
            self.voicing_off
        } else {
            self.voicing_on
        };
        rms_db >= gate_db.max(self.silence_db) && periodicity + level_bonus < threshold
    }

    pub(crate) fn reset(&mut self) {
        self.history = [0.0; 2];
        self.voiced = false;
    }

    /// One frame: the chosen period and all key maxima, the window's periodicity (reported as
    /// the voicing field) and the edge window's (0 when not computed; it only helps the
    /// decision), the frame level, the level gate and the loudness bonus.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn update(
        &mut self,
        chosen: PitchEstimate,
        candidates: &[PitchEstimate],
        periodicity: f32,
        edge_periodicity: f32,
        rms_db: f32,
        gate_db: f32,
        level_bonus: f32,
    ) -> TrackedPitch {
        let mut est = chosen;
        let prev = self.history[0];
        if prev > 0.0 && est.f0_hz > 0.0 && !within(est.f0_hz, prev, CONTINUITY_RATIO) {
            let mut best: Option<PitchEstimate> = None;
            for c in candidates {
                if within(c.f0_hz, prev, CONTINUITY_RATIO)
                    && c.clarity >= CONTINUITY_CLARITY * est.clarity
                    && best.is_none_or(|b| c.clarity > b.clarity)
                {
                    best = Some(*c);
                }
            }
            if let Some(b) = best {
                est = b;
            }
        }
        let gate_db = gate_db.max(self.silence_db);
        let gate = ((rms_db - (gate_db - SILENCE_FADE_DB)) / SILENCE_FADE_DB).clamp(0.0, 1.0);
        let voicing = (periodicity * gate).clamp(0.0, 1.0);
        let threshold = if self.voiced {
            self.voicing_off
        } else {
            self.voicing_on
        };
        // The voicing field is the window's own periodicity; the decision also hears the
        // short window at the phrase edge (see the analyzer).
        let evidence = periodicity.max(edge_periodicity);
        let voiced = est.f0_hz > 0.0 && evidence + level_bonus >= threshold && rms_db >= gate_db;
        let raw = if voiced { est.f0_hz } else { 0.0 };
        let mut f0_hz = raw;
        if voiced && self.history[0] > 0.0 && self.history[1] > 0.0 {
            let med = median3(raw, self.history[0], self.history[1]);
            if (raw / med - 1.0).abs() > OUTLIER_FRACTION {
                f0_hz = med;
            }
        }
        self.history = [raw, self.history[0]];
        self.voiced = voiced;
        TrackedPitch {
            f0_hz,
            voiced,
            voicing,
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

    /// `update` with the periodicity the pitch estimator would report: the best clarity.
    fn upd(
        t: &mut Tracker,
        chosen: PitchEstimate,
        candidates: &[PitchEstimate],
        rms_db: f32,
        gate_db: f32,
        level_bonus: f32,
    ) -> TrackedPitch {
        let periodicity = candidates
            .iter()
            .map(|c| c.clarity)
            .fold(chosen.clarity, f32::max);
        t.update(
            chosen,
            candidates,
            periodicity,
            0.0,
            rms_db,
            gate_db,
            level_bonus,
        )
    }

    #[test]
    fn median_of_three() {
        assert_eq!(median3(1.0, 2.0, 3.0), 2.0);
        assert_eq!(median3(3.0, 1.0, 2.0), 2.0);
        assert_eq!(median3(2.0, 3.0, 1.0), 2.0);
    }

    #[test]
    fn hysteresis_and_silence_gate() {
        let mut t = Tracker::new(0.7, 0.5, -60.0);
        assert!(!upd(&mut t, est(200.0, 0.6), &[], -20.0, -120.0, 0.0).voiced);
        assert!(upd(&mut t, est(200.0, 0.8), &[], -20.0, -120.0, 0.0).voiced);
        assert!(upd(&mut t, est(200.0, 0.6), &[], -20.0, -120.0, 0.0).voiced);
        assert!(!upd(&mut t, est(200.0, 0.4), &[], -20.0, -120.0, 0.0).voiced);
        let quiet = upd(&mut t, est(200.0, 0.99), &[], -65.0, -120.0, 0.0);
        assert!(!quiet.voiced);
        assert!((quiet.voicing - 0.99 * 0.5).abs() < 1e-6);
    }

    #[test]
    fn continuity_prefers_the_candidate_near_the_track() {
        let mut t = Tracker::new(0.7, 0.5, -60.0);
        upd(
            &mut t,
            est(150.0, 0.9),
            &[est(150.0, 0.9)],
            -20.0,
            -120.0,
            0.0,
        );
        // The key-maximum rule jumped an octave up, but a nearly as clear candidate continues.
        let cands = [est(301.0, 0.9), est(151.0, 0.88)];
        let r = upd(&mut t, cands[0], &cands, -20.0, -120.0, 0.0);
        assert_eq!(r.f0_hz, 151.0);
        // A clearly better new candidate is kept: a real jump, which the outlier filter lets
        // through one frame later.
        let cands = [est(200.0, 0.95), est(151.0, 0.5)];
        assert_eq!(
            upd(&mut t, cands[0], &cands, -20.0, -120.0, 0.0).f0_hz,
            151.0
        );
        assert_eq!(
            upd(&mut t, cands[0], &cands, -20.0, -120.0, 0.0).f0_hz,
            200.0
        );
    }

    #[test]
    fn single_outliers_are_replaced_by_the_median() {
        let mut t = Tracker::new(0.7, 0.5, -60.0);
        upd(&mut t, est(150.0, 0.9), &[], -20.0, -120.0, 0.0);
        upd(&mut t, est(152.0, 0.9), &[], -20.0, -120.0, 0.0);
        assert_eq!(
            upd(&mut t, est(300.0, 0.9), &[], -20.0, -120.0, 0.0).f0_hz,
            152.0
        );
        // A lasting jump comes through one frame later.
        assert_eq!(
            upd(&mut t, est(300.0, 0.9), &[], -20.0, -120.0, 0.0).f0_hz,
            300.0
        );
    }
}
