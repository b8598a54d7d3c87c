//! The voicing decision in one place. [`VoicingEvidence`] gathers the cues one frame offers
//! (periodicity of the long window, of a short centred window and of short windows at either
//! end, their agreement, the low band's share of the energy, the level against the running
//! speech level and the noise floor, continuity with the previous frame's period, and the
//! period itself), all computed causally from the audio alone, never from earlier decisions,
//! so the same cues can be gathered once and any model fitted on them. [`VoicingModel`] is a
//! logistic regression over those cues ([`VOICING_FEATURES`]) with two thresholds on its score
//! (hysteresis: a higher score to start voicing than to keep it), read from a versioned text
//! file (`assets/models/voicing.txt`, embedded) that `cargo xtask train-voicing` fits
//! leave-one-speaker-out and regenerates bit for bit. [`VoicingRule`] applies the model with
//! its hysteresis state and a fixed silence gate.

use std::sync::OnceLock;

use thiserror::Error;

/// The shipped model, embedded.
const SHIPPED_MODEL: &str = include_str!("../../../assets/models/voicing.txt");
/// First line of a model file (after comments): format name and version.
const FORMAT_LINE: &str = "pneuma-voicing-model 1";
/// Width of the fade of the voicing confidence below the silence gate, dB.
const SILENCE_FADE_DB: f32 = 10.0;

/// Number of cues the model weighs.
pub const N_VOICING_FEATURES: usize = 15;
/// Index of `level_vs_gate` among the cues: a frame under the level gate is never voiced.
pub(crate) const LEVEL_VS_GATE: usize = 14;
/// The level gate: frames more than this many dB under the running speech level are never
/// voiced, nor frames less than [`NOISE_MARGIN_DB`] above the noise floor, though the noise
/// gate never rises closer than [`NOISE_HEADROOM_DB`] under the speech level (a stream without
/// pauses has its "floor" at the voice itself).
const SPEECH_GATE_DB: f32 = 30.0;
const NOISE_MARGIN_DB: f32 = 6.0;
const NOISE_HEADROOM_DB: f32 = 2.0;

/// The cues, in the order of a feature vector and of the model file's `feature` lines.
pub const VOICING_FEATURES: [&str; N_VOICING_FEATURES] = [
    "long_clarity",
    "chosen_clarity",
    "short_clarity",
    "short_agrees",
    "edge_newest",
    "edge_oldest",
    "best_clarity",
    "log_unclarity",
    "level_vs_speech",
    "level_vs_floor",
    "low_band",
    "period_jump",
    "previous_clarity",
    "log_f0",
    "level_vs_gate",
];

/// One frame's cues as a vector, in [`VOICING_FEATURES`] order.
pub type VoicingFeatures = [f32; N_VOICING_FEATURES];

/// What one frame offers the voicing decision, before the transforms of
/// [`VoicingEvidence::features`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct VoicingEvidence {
    /// The long window's highest key maximum, 0–1.
    pub long_clarity: f32,
    /// The chosen period's clarity, 0–1.
    pub chosen_clarity: f32,
    /// The centred short window's pick's clarity (0 when it did not run).
    pub short_clarity: f32,
    /// Whether that pick is the chosen period.
    pub short_agrees: bool,
    /// Clarity of the chosen period on a short window at the newest / oldest end of the long
    /// one (0 when that window's own choice differs or the period is beyond its reach).
    pub edge_newest: f32,
    pub edge_oldest: f32,
    /// Frame level, dBFS.
    pub rms_db: f32,
    /// The running level of clearly periodic frames, dBFS.
    pub speech_db: f32,
    /// The running noise floor, dBFS (+∞ before it is known).
    pub floor_db: f32,
    /// Share of the voice band's energy in its low band (80 Hz–1 kHz of 80 Hz–4 kHz).
    pub low_band: f32,
    /// The chosen f0 of this and of the previous frame, Hz (0 = none).
    pub f0_hz: f32,
    pub previous_f0_hz: f32,
    /// The previous frame's long-window clarity.
    pub previous_clarity: f32,
}

impl VoicingEvidence {
    /// The model's inputs: the cues, bounded, in [`VOICING_FEATURES`] order.
    pub(crate) fn features(&self) -> VoicingFeatures {
        let best = self
            .long_clarity
            .max(if self.short_agrees {
                self.short_clarity
            } else {
                0.0
            })
            .max(self.edge_newest)
            .max(self.edge_oldest)
            .clamp(0.0, 1.0);
        let level_vs_floor = if self.floor_db.is_finite() {
            ((self.rms_db - self.floor_db) / 10.0).clamp(0.0, 6.0)
        } else {
            0.0
        };
        let period_jump = if self.f0_hz > 0.0 && self.previous_f0_hz > 0.0 {
            (self.f0_hz / self.previous_f0_hz).log2().abs().min(1.0)
        } else {
            1.0
        };
        let log_f0 = if self.f0_hz > 0.0 {
            (self.f0_hz / 150.0).log2().clamp(-2.0, 2.0)
        } else {
            0.0
        };
        let noise_gate_db = if self.floor_db.is_finite() {
            (self.floor_db + NOISE_MARGIN_DB).min(self.speech_db - NOISE_HEADROOM_DB)
        } else {
            f32::NEG_INFINITY
        };
        let gate_db = (self.speech_db - SPEECH_GATE_DB).max(noise_gate_db);
        [
            self.long_clarity,
            self.chosen_clarity,
            self.short_clarity,
            f32::from(u8::from(self.short_agrees)),
            self.edge_newest,
            self.edge_oldest,
            best,
            -(1.001 - best).ln(),
            ((self.rms_db - self.speech_db) / 10.0).clamp(-4.0, 2.0),
            level_vs_floor,
            self.low_band,
            period_jump,
            self.previous_clarity,
            log_f0,
            ((self.rms_db - gate_db) / 10.0).clamp(-3.0, 3.0),
        ]
    }
}

/// A malformed voicing model file. The message names the line and what to do.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum VoicingModelError {
    /// A line that does not say what the format requires there.
    #[error("voicing model, line {line}: {message}; regenerate the file with `cargo xtask train-voicing` (format documented in core/src/analysis/voicing.rs)")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The file ended before a required line.
    #[error("voicing model: the file ends before {missing}; regenerate the file with `cargo xtask train-voicing`")]
    Truncated {
        /// The line that was expected.
        missing: String,
    },
}

/// A logistic-regression voicing model: score = bias + Σ weight·(feature − mean)/scale; a
/// frame starts voicing at `threshold_on` and keeps voicing down to `threshold_off`.
///
/// File format (text, UTF-8; `#` lines and blank lines are comments):
///
/// ```text
/// pneuma-voicing-model 1
/// feature <name> mean <m> scale <s> weight <w>     (one per cue, in VOICING_FEATURES order)
/// bias <b>
/// threshold_on <on>
/// threshold_off <off>                               (off ≤ on)
/// ```
///
/// Every number is a finite decimal (written as the shortest text that reads back as the same
/// `f32`), every scale positive.
#[derive(Debug, Clone, PartialEq)]
pub struct VoicingModel {
    mean: VoicingFeatures,
    scale: VoicingFeatures,
    weight: VoicingFeatures,
    bias: f32,
    threshold_on: f32,
    threshold_off: f32,
}

impl Default for VoicingModel {
    fn default() -> Self {
        Self::shipped().clone()
    }
}

impl VoicingModel {
    /// The model shipped in `assets/models/voicing.txt` (embedded; a unit test checks that it
    /// parses).
    pub fn shipped() -> &'static VoicingModel {
        static MODEL: OnceLock<VoicingModel> = OnceLock::new();
        MODEL.get_or_init(|| {
            VoicingModel::parse(SHIPPED_MODEL).expect("the embedded voicing model parses")
        })
    }

    /// A model from its parts; fails (naming the part) on a non-finite number, a scale that is
    /// not positive or `threshold_off > threshold_on`.
    pub fn new(
        mean: VoicingFeatures,
        scale: VoicingFeatures,
        weight: VoicingFeatures,
        bias: f32,
        threshold_on: f32,
        threshold_off: f32,
    ) -> Result<Self, String> {
        for (i, name) in VOICING_FEATURES.iter().enumerate() {
            if !(mean[i].is_finite() && weight[i].is_finite()) {
                return Err(format!("feature {name}: mean and weight must be finite"));
            }
            if !(scale[i].is_finite() && scale[i] > 0.0) {
                return Err(format!("feature {name}: scale must be positive and finite"));
            }
        }
        if !(bias.is_finite() && threshold_on.is_finite() && threshold_off.is_finite()) {
            return Err("bias and thresholds must be finite".into());
        }
        if threshold_off > threshold_on {
            return Err(format!(
                "threshold_off {threshold_off} lies above threshold_on {threshold_on}"
            ));
        }
        Ok(Self {
            mean,
            scale,
            weight,
            bias,
            threshold_on,
            threshold_off,
        })
    }

    /// The same weights with other thresholds (`off ≤ on`).
    pub fn with_thresholds(&self, threshold_on: f32, threshold_off: f32) -> Result<Self, String> {
        Self::new(
            self.mean,
            self.scale,
            self.weight,
            self.bias,
            threshold_on,
            threshold_off,
        )
    }

    /// The score of one frame's features (log-odds of voiced).
    pub fn score(&self, features: &VoicingFeatures) -> f32 {
        let mut z = self.bias;
        let terms = features.iter().zip(&self.mean).zip(&self.scale);
        for (((x, m), s), w) in terms.zip(&self.weight) {
            z += w * ((x - m) / s);
        }
        z
    }

    /// The score a frame needs: `threshold_on` after an unvoiced frame, `threshold_off` after
    /// a voiced one.
    pub fn threshold(&self, was_voiced: bool) -> f32 {
        if was_voiced {
            self.threshold_off
        } else {
            self.threshold_on
        }
    }

    /// Reads a model file (see the type's docs); errors name the line.
    pub fn parse(text: &str) -> Result<Self, VoicingModelError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let mut next = |what: &str| {
            lines.next().ok_or_else(|| VoicingModelError::Truncated {
                missing: what.to_string(),
            })
        };
        let bad = |line: usize, message: String| VoicingModelError::Line { line, message };
        let (line, first) = next(&format!("the format line `{FORMAT_LINE}`"))?;
        if first != FORMAT_LINE {
            return Err(bad(
                line,
                format!("expected `{FORMAT_LINE}`, found `{first}` (not a voicing model, or another version)"),
            ));
        }
        let number = |line: usize, key: &str, text: &str| -> Result<f32, VoicingModelError> {
            text.parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(line, format!("{key} {text:?} is not a finite number")))
        };
        let (mut mean, mut scale, mut weight) = (
            [0.0; N_VOICING_FEATURES],
            [0.0; N_VOICING_FEATURES],
            [0.0; N_VOICING_FEATURES],
        );
        for (i, name) in VOICING_FEATURES.iter().enumerate() {
            let (line, l) = next(&format!("the line of feature {name}"))?;
            let t: Vec<&str> = l.split_whitespace().collect();
            let shape = t.len() == 8
                && t[0] == "feature"
                && t[2] == "mean"
                && t[4] == "scale"
                && t[6] == "weight";
            if !shape {
                return Err(bad(
                    line,
                    format!("expected `feature {name} mean <m> scale <s> weight <w>`, found `{l}`"),
                ));
            }
            if t[1] != *name {
                return Err(bad(
                    line,
                    format!(
                        "expected feature {name} here (features come in a fixed order), found {}",
                        t[1]
                    ),
                ));
            }
            mean[i] = number(line, "mean", t[3])?;
            scale[i] = number(line, "scale", t[5])?;
            weight[i] = number(line, "weight", t[7])?;
            if scale[i] <= 0.0 {
                return Err(bad(line, format!("scale {} must be positive", t[5])));
            }
        }
        let mut keyed = |key: &str| -> Result<(usize, f32), VoicingModelError> {
            let (line, l) = next(&format!("the `{key}` line"))?;
            match l.split_whitespace().collect::<Vec<_>>()[..] {
                [k, v] if k == key => Ok((line, number(line, key, v)?)),
                _ => Err(bad(line, format!("expected `{key} <number>`, found `{l}`"))),
            }
        };
        let (_, bias) = keyed("bias")?;
        let (_, on) = keyed("threshold_on")?;
        let (line, off) = keyed("threshold_off")?;
        if let Some((line, l)) = lines.next() {
            return Err(bad(
                line,
                format!("unexpected line after threshold_off: `{l}`"),
            ));
        }
        Self::new(mean, scale, weight, bias, on, off).map_err(|m| bad(line, m))
    }

    /// The model as a file: `notes` (provenance) as leading comment lines, then the format.
    /// [`VoicingModel::parse`] reads it back to the same model, bit for bit.
    pub fn to_text(&self, notes: &[String]) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        for n in notes {
            let _ = writeln!(s, "# {n}");
        }
        let _ = writeln!(s, "{FORMAT_LINE}");
        for (i, name) in VOICING_FEATURES.iter().enumerate() {
            let _ = writeln!(
                s,
                "feature {name} mean {} scale {} weight {}",
                self.mean[i], self.scale[i], self.weight[i]
            );
        }
        let _ = writeln!(s, "bias {}", self.bias);
        let _ = writeln!(s, "threshold_on {}", self.threshold_on);
        let _ = writeln!(s, "threshold_off {}", self.threshold_off);
        s
    }
}

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
    use super::*;

    #[test]
    fn the_shipped_model_parses_and_reads_back_bit_for_bit() {
        let m = VoicingModel::parse(SHIPPED_MODEL).unwrap();
        let text = m.to_text(&[]);
        assert_eq!(VoicingModel::parse(&text).unwrap(), m);
        // The shipped file is exactly what the writer makes of it, apart from its notes.
        let body: String = SHIPPED_MODEL
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(body, text);
    }

    #[test]
    fn malformed_files_are_rejected_naming_the_line() {
        let good = VoicingModel::shipped().to_text(&["a note".into()]);
        let lines: Vec<&str> = good.lines().collect();
        let with = |i: usize, l: &str| {
            let mut v = lines.clone();
            v[i] = l;
            v.join("\n")
        };
        let line_of = |text: &str| match VoicingModel::parse(text) {
            Err(VoicingModelError::Line { line, .. }) => line,
            other => panic!("expected a line error, got {other:?}"),
        };
        // `with` counts from 0, the messages from 1: line 1 is the note, line 2 the format,
        // 3.. the features.
        assert_eq!(line_of(&with(1, "pneuma-voicing-model 2")), 2);
        assert_eq!(
            line_of(&with(2, "feature long_clarity mean x scale 1 weight 1")),
            3
        );
        // The second feature line naming the first feature: out of order.
        assert_eq!(
            line_of(&with(3, "feature long_clarity mean 0 scale 1 weight 1")),
            4
        );
        assert_eq!(
            line_of(&with(4, "feature short_clarity mean 0 scale 0 weight 1")),
            5
        );
        let n = lines.len();
        assert_eq!(line_of(&with(n - 1, "threshold_off 99")), n);
        let e = VoicingModel::parse(&with(2, "feature long_clarity mean NaN scale 1 weight 1"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 3") && e.contains("cargo xtask train-voicing"),
            "{e}"
        );
        let cut = lines[..n - 2].join("\n");
        assert!(matches!(
            VoicingModel::parse(&cut),
            Err(VoicingModelError::Truncated { .. })
        ));
    }

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
