//! The voicing decision in one place: [`VoicingEvidence`] gathers what one frame offers (its
//! periodicity, the edge window's, the level against the gates and the speech level), and
//! [`VoicingRule`] decides voiced or unvoiced from it with hysteresis (a higher threshold to
//! start voicing than to keep it). The rule also says when a frame is undecided enough that
//! more evidence (the edge windows) is worth computing.

/// Width of the fade of the voicing confidence below the level gate, dB.
const SILENCE_FADE_DB: f32 = 10.0;

/// What one frame offers the voicing decision.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct VoicingEvidence {
    /// The long window's periodicity (its best NSDF key maximum), 0–1.
    pub periodicity: f32,
    /// The short window's clarity at the chosen period at the phrase edge (0 when not
    /// computed: it only helps the decision, never the reported voicing).
    pub edge_periodicity: f32,
    /// Frame level, dBFS.
    pub rms_db: f32,
    /// The level gate from the speech level and the noise floor, dBFS.
    pub gate_db: f32,
    /// Added to the periodicity: louder than the speech level helps, quieter hurts.
    pub level_bonus: f32,
}

/// Thresholds on the periodicity with hysteresis, and a fixed silence gate.
#[derive(Debug, Clone)]
pub(crate) struct VoicingRule {
    voicing_on: f32,
    voicing_off: f32,
    silence_db: f32,
    /// The last decision.
    voiced: bool,
}

impl VoicingRule {
    pub(crate) fn new(voicing_on: f32, voicing_off: f32, silence_db: f32) -> Self {
        Self {
            voicing_on,
            voicing_off,
            silence_db,
            voiced: false,
        }
    }

    pub(crate) fn reset(&mut self) {
        self.voiced = false;
    }

    /// The last decision.
    pub(crate) fn is_voiced(&self) -> bool {
        self.voiced
    }

    /// The periodicity (plus level bonus) a frame needs now: hysteresis.
    fn threshold(&self) -> f32 {
        if self.voiced {
            self.voicing_off
        } else {
            self.voicing_on
        }
    }

    /// The level a frame must reach: the evidence's gate, never below the silence gate.
    fn gate_db(&self, e: &VoicingEvidence) -> f32 {
        e.gate_db.max(self.silence_db)
    }

    /// Whether the periodicity alone leaves a frame that passes the level gate on the unvoiced
    /// side of the threshold: only then can the edge windows change the decision.
    pub(crate) fn wants_more_evidence(&self, e: &VoicingEvidence) -> bool {
        e.rms_db >= self.gate_db(e) && e.periodicity + e.level_bonus < self.threshold()
    }

    /// The reported voicing confidence: the periodicity, faded out below the level gate.
    pub(crate) fn confidence(&self, e: &VoicingEvidence) -> f32 {
        let gate_db = self.gate_db(e);
        let gate = ((e.rms_db - (gate_db - SILENCE_FADE_DB)) / SILENCE_FADE_DB).clamp(0.0, 1.0);
        (e.periodicity * gate).clamp(0.0, 1.0)
    }

    /// Decides one frame with a period found (`has_period`) and remembers the decision.
    pub(crate) fn decide(&mut self, has_period: bool, e: &VoicingEvidence) -> bool {
        let evidence = e.periodicity.max(e.edge_periodicity);
        let voiced = has_period
            && evidence + e.level_bonus >= self.threshold()
            && e.rms_db >= self.gate_db(e);
        self.voiced = voiced;
        voiced
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(periodicity: f32, edge_periodicity: f32, rms_db: f32) -> VoicingEvidence {
        VoicingEvidence {
            periodicity,
            edge_periodicity,
            rms_db,
            gate_db: -50.0,
            level_bonus: 0.0,
        }
    }

    #[test]
    fn the_edge_window_is_asked_only_when_it_can_change_the_decision() {
        let mut rule = VoicingRule::new(0.7, 0.5, -60.0);
        // Loud enough, not periodic enough: the edge window may help, and does.
        assert!(rule.wants_more_evidence(&frame(0.6, 0.0, -20.0)));
        assert!(rule.decide(true, &frame(0.6, 0.8, -20.0)));
        // Now voiced: 0.6 keeps voicing (hysteresis), so no more evidence is wanted.
        assert!(!rule.wants_more_evidence(&frame(0.6, 0.0, -20.0)));
        // Under the level gate nothing helps.
        assert!(!rule.wants_more_evidence(&frame(0.3, 0.0, -55.0)));
        assert!(!rule.decide(true, &frame(0.3, 0.99, -55.0)));
        // No period found: unvoiced whatever the periodicity.
        assert!(!rule.decide(false, &frame(0.99, 0.99, -20.0)));
    }
}
