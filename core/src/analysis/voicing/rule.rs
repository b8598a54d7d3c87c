//! [`VoicingRule`]: the model's decision with its hysteresis state and a fixed silence gate,
//! and the reported voicing confidence.

use super::cues::{VoicingFeatures, LEVEL_VS_GATE};
use super::model::VoicingModel;

/// Width of the fade of the voicing confidence below the silence gate, dB.
const SILENCE_FADE_DB: f32 = 10.0;

/// The model's decision with hysteresis, and a fixed silence gate.
#[derive(Debug, Clone)]
pub(crate) struct VoicingRule {
    model: VoicingModel,
    silence_db: f32,
    /// The last decision.
    voiced: bool,
}

impl VoicingRule {
    pub(crate) fn new(model: VoicingModel, silence_db: f32) -> Self {
        Self {
            model,
            silence_db,
            voiced: false,
        }
    }

    pub(crate) fn reset(&mut self) {
        self.voiced = false;
    }

    /// The reported voicing confidence: `periodicity`, faded out below the silence gate.
    pub(crate) fn confidence(&self, periodicity: f32, rms_db: f32) -> f32 {
        let gate =
            ((rms_db - (self.silence_db - SILENCE_FADE_DB)) / SILENCE_FADE_DB).clamp(0.0, 1.0);
        (periodicity * gate).clamp(0.0, 1.0)
    }

    /// Decides one frame from its features (`has_period`: a period was found) and remembers
    /// the decision. Frames under the silence gate or the level gate are never voiced.
    pub(crate) fn decide(&mut self, has_period: bool, rms_db: f32, f: &VoicingFeatures) -> bool {
        let voiced = has_period
            && rms_db >= self.silence_db
            && f[LEVEL_VS_GATE] >= 0.0
            && self.model.score(f) >= self.model.threshold(self.voiced);
        self.voiced = voiced;
        voiced
    }
}

#[cfg(test)]
mod tests {
    use super::super::cues::N_VOICING_FEATURES;
    use super::*;

    #[test]
    fn hysteresis_and_silence_gate() {
        let zero = [0.0; N_VOICING_FEATURES];
        let mut w = [0.0; N_VOICING_FEATURES];
        w[0] = 1.0;
        let model = VoicingModel::new(zero, [1.0; N_VOICING_FEATURES], w, 0.0, 0.7, 0.5).unwrap();
        let mut rule = VoicingRule::new(model, -60.0);
        let f = |c: f32| {
            let mut f = zero;
            f[0] = c;
            f
        };
        assert!(!rule.decide(true, -20.0, &f(0.6)));
        assert!(rule.decide(true, -20.0, &f(0.8)));
        assert!(rule.decide(true, -20.0, &f(0.6)));
        assert!(!rule.decide(true, -20.0, &f(0.4)));
        assert!(!rule.decide(true, -65.0, &f(0.99)));
        assert!(!rule.decide(false, -20.0, &f(0.99)));
        assert!((rule.confidence(0.99, -65.0) - 0.99 * 0.5).abs() < 1e-6);
    }
}
