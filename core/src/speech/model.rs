//! The stacked speech model: one logistic regression over Silero's logit and the decision's own
//! cues ([`SPEECH_FEATURES`]), read from a versioned text file (`assets/models/speech.txt`,
//! embedded) that `cargo xtask train-speech` fits on the podcast recipe and regenerates bit for
//! bit.
//!
//! ## Format, version 1
//! Comment lines (`#`, provenance and held-out figures) and blank lines anywhere; then, in this
//! order:
//! ```text
//! pneuma-speech-model 1
//! feature silero_logit mean <m> scale <s> weight <w>
//! feature voiced_near mean <m> scale <s> weight <w>
//! feature level_dips mean <m> scale <s> weight <w>
//! bias <b>
//! threshold <t>
//! ```
//! The probability is `σ(bias + Σ weight · (feature − mean) / scale)`; a frame is speech when it
//! reaches `threshold` (0 < t < 1). Every number must be finite and every scale positive.

use std::sync::OnceLock;

use thiserror::Error;

/// The shipped model, embedded.
const SHIPPED_MODEL: &str = include_str!("../../../assets/models/speech.txt");
/// First line of a model file (after comments).
const FORMAT_LINE: &str = "pneuma-speech-model 1";
/// Number of inputs.
pub const N_SPEECH_FEATURES: usize = 3;
/// The inputs, in the order of a feature vector and of the file's `feature` lines: Silero's
/// logit (its probability clipped to [`LOGIT_CLIP`] .. 1 − [`LOGIT_CLIP`]) and the cues of
/// [`cues`](super::cues).
pub const SPEECH_FEATURES: [&str; N_SPEECH_FEATURES] =
    ["silero_logit", "voiced_near", "level_dips"];
/// Silero's probability is clipped this far from 0 and 1 before its logit is taken.
pub const LOGIT_CLIP: f32 = 1e-4;

/// One frame's inputs, in [`SPEECH_FEATURES`] order.
pub type SpeechFeatures = [f32; N_SPEECH_FEATURES];

/// Silero's probability as the model's first input.
pub fn silero_logit(p: f32) -> f32 {
    let p = p.clamp(LOGIT_CLIP, 1.0 - LOGIT_CLIP);
    (p / (1.0 - p)).ln()
}

/// A malformed speech model file. The message names the line and what to do.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SpeechModelError {
    /// A line that does not say what the format requires there.
    #[error("speech model, line {line}: {message}; regenerate the file with `cargo xtask train-speech` (format documented in core/src/speech/model.rs)")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A number that is not allowed where it stands.
    #[error("speech model: {0}; regenerate the file with `cargo xtask train-speech`")]
    Invalid(String),
    /// The file ended before a required line.
    #[error("speech model: the file ends before {missing}; regenerate the file with `cargo xtask train-speech`")]
    Truncated {
        /// The line that was expected.
        missing: String,
    },
}

/// The stacked model. See the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeechModel {
    mean: SpeechFeatures,
    scale: SpeechFeatures,
    weight: SpeechFeatures,
    bias: f32,
    threshold: f32,
}

impl Default for SpeechModel {
    fn default() -> Self {
        Self::shipped().clone()
    }
}

impl SpeechModel {
    /// A model from its parts; fails (naming the part) on a non-finite number, a scale that is
    /// not positive or a threshold outside (0, 1).
    pub fn new(
        mean: SpeechFeatures,
        scale: SpeechFeatures,
        weight: SpeechFeatures,
        bias: f32,
        threshold: f32,
    ) -> Result<Self, SpeechModelError> {
        let invalid = |m: String| Err(SpeechModelError::Invalid(m));
        for (k, name) in SPEECH_FEATURES.iter().enumerate() {
            if !(mean[k].is_finite() && scale[k].is_finite() && weight[k].is_finite()) {
                return invalid(format!("feature {name}: every number must be finite"));
            }
            if scale[k] <= 0.0 {
                return invalid(format!(
                    "feature {name}: scale {} must be positive",
                    scale[k]
                ));
            }
        }
        if !bias.is_finite() {
            return invalid(format!("bias {bias} must be finite"));
        }
        if !(threshold > 0.0 && threshold < 1.0) {
            return invalid(format!("threshold {threshold} must lie between 0 and 1"));
        }
        Ok(Self {
            mean,
            scale,
            weight,
            bias,
            threshold,
        })
    }

    /// The model shipped in `assets/models/speech.txt` (embedded; a unit test checks that it
    /// parses).
    pub fn shipped() -> &'static SpeechModel {
        static MODEL: OnceLock<SpeechModel> = OnceLock::new();
        MODEL.get_or_init(|| {
            SpeechModel::parse(SHIPPED_MODEL).expect("the embedded speech model parses")
        })
    }

    /// The probability that a frame with these inputs is speech.
    pub fn probability(&self, f: &SpeechFeatures) -> f32 {
        let z = (0..N_SPEECH_FEATURES).fold(self.bias, |z, k| {
            z + self.weight[k] * (f[k] - self.mean[k]) / self.scale[k]
        });
        1.0 / (1.0 + (-z).exp())
    }

    /// The probability at which a frame counts as speech.
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// Reads a model file (see the module docs); errors name the line.
    pub fn parse(text: &str) -> Result<Self, SpeechModelError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let mut next = |what: &str| {
            lines.next().ok_or_else(|| SpeechModelError::Truncated {
                missing: what.to_string(),
            })
        };
        let bad = |line: usize, message: String| SpeechModelError::Line { line, message };
        let number = |line: usize, key: &str, text: &str| {
            text.parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(line, format!("{key} {text:?} is not a finite number")))
        };
        let (line, first) = next(&format!("the format line `{FORMAT_LINE}`"))?;
        if first != FORMAT_LINE {
            return Err(bad(
                line,
                format!("expected `{FORMAT_LINE}`, found `{first}` (not a speech model, or another version)"),
            ));
        }
        let (mut mean, mut scale, mut weight) = ([0.0; 3], [1.0; 3], [0.0; 3]);
        for (k, name) in SPEECH_FEATURES.iter().enumerate() {
            let (line, l) = next(&format!("the line of feature {name}"))?;
            let t: Vec<&str> = l.split_whitespace().collect();
            let ["feature", found, "mean", m, "scale", s, "weight", w] = t[..] else {
                return Err(bad(
                    line,
                    format!("expected `feature {name} mean <m> scale <s> weight <w>`, found `{l}`"),
                ));
            };
            if found != *name {
                return Err(bad(
                    line,
                    format!("expected feature {name} here (features come in a fixed order), found {found}"),
                ));
            }
            mean[k] = number(line, "mean", m)?;
            scale[k] = number(line, "scale", s)?;
            weight[k] = number(line, "weight", w)?;
            if scale[k] <= 0.0 {
                return Err(bad(line, format!("scale {s} must be positive")));
            }
        }
        let mut keyed = |key: &str| -> Result<(usize, f32), SpeechModelError> {
            let (line, l) = next(&format!("the `{key}` line"))?;
            match l.split_whitespace().collect::<Vec<_>>()[..] {
                [k, v] if k == key => number(line, key, v).map(|v| (line, v)),
                _ => Err(bad(line, format!("expected `{key} <number>`, found `{l}`"))),
            }
        };
        let (_, bias) = keyed("bias")?;
        let (line, threshold) = keyed("threshold")?;
        let model = Self::new(mean, scale, weight, bias, threshold).map_err(|e| match e {
            SpeechModelError::Invalid(m) => bad(line, m),
            other => other,
        })?;
        if let Some((line, l)) = lines.next() {
            return Err(bad(line, format!("unexpected line after threshold: `{l}`")));
        }
        Ok(model)
    }

    /// The model as a file: `notes` (provenance) as leading comment lines, then the format.
    /// [`SpeechModel::parse`] reads it back to the same model, bit for bit.
    pub fn to_text(&self, notes: &[String]) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        for n in notes {
            let _ = writeln!(s, "# {n}");
        }
        let _ = writeln!(s, "{FORMAT_LINE}");
        for (k, name) in SPEECH_FEATURES.iter().enumerate() {
            let _ = writeln!(
                s,
                "feature {name} mean {} scale {} weight {}",
                self.mean[k], self.scale[k], self.weight[k]
            );
        }
        let _ = writeln!(s, "bias {}", self.bias);
        let _ = writeln!(s, "threshold {}", self.threshold);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_model_parses_and_reads_back_bit_for_bit() {
        let m = SpeechModel::parse(SHIPPED_MODEL).expect("shipped model");
        let notes: Vec<String> = SHIPPED_MODEL
            .lines()
            .take_while(|l| l.starts_with('#'))
            .map(|l| l.trim_start_matches('#').trim_start().to_string())
            .collect();
        assert_eq!(m.to_text(&notes), SHIPPED_MODEL);
        assert_eq!(SpeechModel::parse(&m.to_text(&[])), Ok(m));
    }

    fn text() -> String {
        SpeechModel::new(
            [1.0, 0.5, 0.25],
            [6.0, 0.5, 0.25],
            [3.5, 0.3, 0.5],
            -1.0,
            0.5,
        )
        .expect("valid")
        .to_text(&["a note".into()])
    }

    /// `text()` with content line `i` (0-based among the non-comment lines) replaced.
    fn with(i: usize, line: &str) -> String {
        let mut k = 0;
        text()
            .lines()
            .map(|l| {
                if l.starts_with('#') {
                    return l.to_string();
                }
                k += 1;
                if k - 1 == i {
                    line.to_string()
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    }

    fn line_error(text: &str) -> (usize, String) {
        match SpeechModel::parse(text) {
            Err(SpeechModelError::Line { line, message }) => (line, message),
            other => panic!("expected a line error, got {other:?}"),
        }
    }

    #[test]
    fn malformed_files_are_rejected_naming_the_line_and_the_fix() {
        assert!(SpeechModel::parse(&text()).is_ok());
        assert_eq!(line_error(&with(0, "pneuma-speech-model 2")).0, 2);
        let (line, m) = line_error(&with(2, "feature level_dips mean 0 scale 1 weight 1"));
        assert_eq!(line, 4);
        assert!(m.contains("expected feature voiced_near"), "{m}");
        let (_, m) = line_error(&with(1, "feature silero_logit mean x scale 1 weight 1"));
        assert!(m.contains("not a finite number"), "{m}");
        let (_, m) = line_error(&with(1, "feature silero_logit mean 0 scale 0 weight 1"));
        assert!(m.contains("must be positive"), "{m}");
        let (_, m) = line_error(&with(1, "feature silero_logit mean 0 scale 1"));
        assert!(m.contains("expected `feature silero_logit"), "{m}");
        let (_, m) = line_error(&with(5, "threshold 1.5"));
        assert!(m.contains("between 0 and 1"), "{m}");
        let (_, m) = line_error(&with(4, "bias inf"));
        assert!(m.contains("bias"), "{m}");
        let (_, m) = line_error(&format!("{}\nextra 1\n", text()));
        assert!(m.contains("unexpected line"), "{m}");
        let cut: String = text().lines().take(4).collect::<Vec<_>>().join("\n");
        let e = SpeechModel::parse(&cut).unwrap_err();
        assert!(matches!(e, SpeechModelError::Truncated { .. }), "{e}");
        assert!(e.to_string().contains("cargo xtask train-speech"), "{e}");
    }

    #[test]
    fn the_probability_is_the_logistic_of_the_standardised_sum() {
        let m = SpeechModel::new(
            [1.0, 0.5, 0.25],
            [2.0, 0.5, 0.25],
            [3.0, 1.0, -2.0],
            -0.5,
            0.5,
        )
        .expect("valid");
        let z: f32 =
            -0.5 + 3.0 * (2.0 - 1.0) / 2.0 + 1.0 * (1.0 - 0.5) / 0.5 - 2.0 * (0.5 - 0.25) / 0.25;
        let p = m.probability(&[2.0, 1.0, 0.5]);
        assert!((p - 1.0 / (1.0 + (-z).exp())).abs() < 1e-6, "{p}");
        assert!((silero_logit(0.5)).abs() < 1e-7);
        assert!((silero_logit(1.0) - silero_logit(1.0 - LOGIT_CLIP)).abs() < 1e-6);
    }
}
