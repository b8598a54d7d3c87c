//! The voicing decision in one place. [`VoicingEvidence`] gathers the cues one frame offers
//! (periodicity of the long window, of a short centred window and of short windows at either
//! end, their agreement, the low band's share of the energy, the level against the running
//! speech level and the noise floors, how noisy the recording is and the long window's clarity
//! with the background's share taken out, continuity with the previous frame's period and how
//! long the period has moved smoothly, and the period itself), all computed causally from the
//! audio alone, never from earlier decisions, so the same cues can be gathered once and any
//! model fitted on them. [`VoicingModel`] is a
//! score over those cues ([`VOICING_FEATURES`]: a logistic regression, regression trees, or
//! both added) with two thresholds on its score
//! (hysteresis: a higher score to start voicing than to keep it), read from a versioned text
//! file (`assets/models/voicing.txt`, embedded) that `cargo xtask train-voicing` fits
//! leave-one-speaker-out and regenerates bit for bit. [`VoicingRule`] applies the model with
//! its hysteresis state and a fixed silence gate.

use std::sync::{Arc, OnceLock};

use thiserror::Error;

/// The shipped model, embedded.
const SHIPPED_MODEL: &str = include_str!("../../../assets/models/voicing.txt");
/// First line of a model file (after comments): format name and version (3: a logistic
/// regression plus trees).
const FORMAT_LINE: &str = "pneuma-voicing-model 3";
/// The first line of a version 1 file (logistic regression), still read and written.
const FORMAT_LINE_V1: &str = "pneuma-voicing-model 1";
/// The first line of a version 2 file (trees alone), still read and written.
const FORMAT_LINE_V2: &str = "pneuma-voicing-model 2";
/// Width of the fade of the voicing confidence below the silence gate, dB.
const SILENCE_FADE_DB: f32 = 10.0;

/// Number of cues the model weighs.
pub const N_VOICING_FEATURES: usize = 19;
/// Index of `level_vs_gate` among the cues: a frame under the level gate is never voiced.
pub const LEVEL_VS_GATE: usize = 14;
/// The level gate: frames more than this many dB under the running speech level are never
/// voiced, nor frames whose band level (what the NSDF hears) lies under the band's noise floor
/// (plus [`NOISE_MARGIN_DB`]), unless their level is within [`NOISE_HEADROOM_DB`] of the
/// speech level (a stream without pauses has its "floor" at the voice itself). The margin was
/// 6 dB until stop 28, though the model has level cues of its own; at 0 dB the model judges the
/// frames between, and held out, Keele's white noise at 0 dB went from 17.67 % to 12.34 % FFE
/// with that change alone (README, pitch section).
const SPEECH_GATE_DB: f32 = 30.0;
const NOISE_MARGIN_DB: f32 = 0.0;
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
    "speech_vs_floor",
    "unclarity_by_snr",
    "denoised_clarity",
    "pitch_track",
];
/// The longest pitch-track continuity the `pitch_track` cue counts, s (it reads 0–1 of this).
pub(crate) const TRACK_CAP_S: f32 = 0.1;

/// The jump from the previous frame's chosen period to this one's, octaves, at most 1 (1 when
/// either frame has none): the `period_jump` cue, and what breaks the pitch track.
pub(crate) fn period_jump_octaves(f0_hz: f32, previous_f0_hz: f32) -> f32 {
    if f0_hz > 0.0 && previous_f0_hz > 0.0 {
        (f0_hz / previous_f0_hz).log2().abs().min(1.0)
    } else {
        1.0
    }
}

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
    /// The pitch window's level as the NSDF hears it (mean removed, behind the low-pass), dB.
    pub band_db: f32,
    /// The running noise floor of that band level, dB (+∞ before it is known).
    pub band_floor_db: f32,
    /// The long-window clarity the background alone gives (running mean at the band floor).
    pub noise_clarity: f32,
    /// Share of the voice band's energy in its low band (80 Hz–1 kHz of 80 Hz–4 kHz), behind
    /// the low-pass.
    pub low_band: f32,
    /// The chosen f0 of this and of the previous frame, Hz (0 = none).
    pub f0_hz: f32,
    pub previous_f0_hz: f32,
    /// The previous frame's long-window clarity.
    pub previous_clarity: f32,
    /// How long the chosen period has moved smoothly from frame to frame up to this one, s
    /// (0 when it jumped; at most [`TRACK_CAP_S`]).
    pub track_s: f32,
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
        // While no background has been heard, the floor cues read 0 (the cautious reading, as
        // deep in noise), and nothing is taken out of the clarity.
        let level_vs_floor = if self.band_floor_db.is_finite() {
            ((self.band_db - self.band_floor_db) / 10.0).clamp(0.0, 6.0)
        } else {
            0.0
        };
        let period_jump = period_jump_octaves(self.f0_hz, self.previous_f0_hz);
        let log_f0 = if self.f0_hz > 0.0 {
            (self.f0_hz / 150.0).log2().clamp(-2.0, 2.0)
        } else {
            0.0
        };
        // The gate: at most SPEECH_GATE_DB under the speech level, and either at or above the
        // noise floor in the pitch window's band (what the NSDF hears: a rumble under the
        // high-pass does not hide the voice) or near the speech level itself.
        let over_speech_gate = (self.rms_db - (self.speech_db - SPEECH_GATE_DB)) / 10.0;
        let over_noise_gate = if self.band_floor_db.is_finite() {
            ((self.band_db - (self.band_floor_db + NOISE_MARGIN_DB)) / 10.0)
                .max((self.rms_db - (self.speech_db - NOISE_HEADROOM_DB)) / 10.0)
        } else {
            f32::INFINITY
        };
        // How far the running speech level stands above the noise floor, 0–6 (tens of dB; 0
        // while the floor is unknown): lets the model trust a middling clarity in a clean
        // recording that it must doubt in noise, and its product with the unclarity lets the
        // clarity it asks for move with the noise.
        let speech_vs_floor = if self.floor_db.is_finite() {
            ((self.speech_db - self.floor_db) / 10.0).clamp(0.0, 6.0)
        } else {
            0.0
        };
        let log_unclarity = -(1.001 - best).ln();
        // The share of the window's band energy the background is taken to make up, and the
        // long-window clarity with the background's part taken out: noise adds energy to the
        // NSDF's norm, not to its periodic peak, so a voice in steady noise reads less clear
        // by about that share. The division at most doubles the clarity left, so a noise
        // frame's chance peak at the floor does not read as a clear voice.
        let noise_share = if self.band_floor_db.is_finite() {
            10f32.powf(-(self.band_db - self.band_floor_db).max(0.0) / 10.0)
        } else {
            0.0
        };
        let denoised_clarity = ((self.long_clarity - noise_share * self.noise_clarity)
            / (1.0 - noise_share).max(0.5))
        .clamp(0.0, 1.0);
        [
            self.long_clarity,
            self.chosen_clarity,
            self.short_clarity,
            f32::from(u8::from(self.short_agrees)),
            self.edge_newest,
            self.edge_oldest,
            best,
            log_unclarity,
            ((self.rms_db - self.speech_db) / 10.0).clamp(-4.0, 2.0),
            level_vs_floor,
            self.low_band,
            period_jump,
            self.previous_clarity,
            log_f0,
            over_speech_gate.min(over_noise_gate).clamp(-3.0, 3.0),
            speech_vs_floor,
            log_unclarity * speech_vs_floor / 6.0,
            denoised_clarity,
            (self.track_s / TRACK_CAP_S).clamp(0.0, 1.0),
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

/// The most splits on a tree's path from its root to a leaf (a tree has `2^depth` leaves).
const MAX_TREE_DEPTH: usize = 4;

/// One split of a tree: frames whose cue `feature` is at most `threshold` go to the lower child.
#[derive(Debug, Clone, Copy, PartialEq)]
struct TreeSplit {
    /// Index of the cue in [`VOICING_FEATURES`].
    feature: usize,
    /// The split value (finite).
    threshold: f32,
}

/// A logistic regression's score: bias + Σ weight·(feature − mean)/scale.
#[derive(Debug, Clone, PartialEq)]
struct Linear {
    mean: VoicingFeatures,
    scale: VoicingFeatures,
    weight: VoicingFeatures,
    bias: f32,
}

impl Linear {
    fn score(&self, features: &VoicingFeatures) -> f32 {
        let mut z = self.bias;
        let terms = features.iter().zip(&self.mean).zip(&self.scale);
        for (((x, m), s), w) in terms.zip(&self.weight) {
            z += w * ((x - m) / s);
        }
        z
    }
}

/// Regression trees of one `depth`: splits stored breadth first (`2^depth − 1` per tree),
/// leaves left to right (`2^depth` per tree), all trees in one flat array each (allocated
/// once, at load, and shared: a clone of a model, as a host's thread makes when it builds an
/// analyzer from a copied configuration, never allocates).
#[derive(Debug, Clone, PartialEq)]
struct Ensemble {
    depth: usize,
    splits: Arc<[TreeSplit]>,
    leaves: Arc<[f32]>,
}

impl Ensemble {
    /// Checks the parts (see [`VoicingModel::trees`]).
    fn new(depth: usize, splits: Vec<(usize, f32)>, leaves: Vec<f32>) -> Result<Self, String> {
        let splits: Vec<TreeSplit> = splits
            .into_iter()
            .map(|(feature, threshold)| TreeSplit { feature, threshold })
            .collect();
        if !(1..=MAX_TREE_DEPTH).contains(&depth) {
            return Err(format!("depth {depth} is outside 1..={MAX_TREE_DEPTH}"));
        }
        let n_leaves = 1 << depth;
        let n_trees = leaves.len() / n_leaves;
        if leaves.len() != n_trees * n_leaves || splits.len() != n_trees * (n_leaves - 1) {
            return Err(format!(
                "{} splits and {} leaves do not make whole trees of depth {depth}",
                splits.len(),
                leaves.len()
            ));
        }
        if let Some(s) = splits
            .iter()
            .find(|s| s.feature >= N_VOICING_FEATURES || !s.threshold.is_finite())
        {
            return Err(format!(
                "split on cue {} at {}: the cue must be one of the {N_VOICING_FEATURES} and the threshold finite",
                s.feature, s.threshold
            ));
        }
        if !leaves.iter().all(|v| v.is_finite()) {
            return Err("leaf values must be finite".into());
        }
        Ok(Self {
            depth,
            splits: splits.into(),
            leaves: leaves.into(),
        })
    }

    fn n_leaves(&self) -> usize {
        1 << self.depth
    }

    fn count(&self) -> usize {
        self.leaves.len() / self.n_leaves()
    }

    /// Keeps the first `count` trees.
    fn truncate(&mut self, count: usize) {
        let n_leaves = self.n_leaves();
        let count = count.min(self.count());
        self.leaves = self.leaves[..count * n_leaves].into();
        self.splits = self.splits[..count * (n_leaves - 1)].into();
    }

    /// The sum of the leaf each tree reaches.
    fn score(&self, features: &VoicingFeatures) -> f32 {
        let n_leaves = self.n_leaves();
        let mut z = 0.0;
        for (tree_splits, tree_leaves) in self
            .splits
            .chunks_exact(n_leaves - 1)
            .zip(self.leaves.chunks_exact(n_leaves))
        {
            let mut node = 0;
            for _ in 0..self.depth {
                let s = tree_splits[node];
                node = 2 * node + 1 + usize::from(features[s.feature] > s.threshold);
            }
            z += tree_leaves[node - (n_leaves - 1)];
        }
        z
    }

    /// The `tree` lines of the file format.
    fn write(&self, s: &mut String) {
        use std::fmt::Write as _;
        let n_leaves = self.n_leaves();
        for (tree_splits, tree_leaves) in self
            .splits
            .chunks_exact(n_leaves - 1)
            .zip(self.leaves.chunks_exact(n_leaves))
        {
            s.push_str("tree");
            for sp in tree_splits {
                let _ = write!(s, " {} {}", VOICING_FEATURES[sp.feature], sp.threshold);
            }
            s.push_str(" leaves");
            for v in tree_leaves {
                let _ = write!(s, " {v}");
            }
            s.push('\n');
        }
    }
}

/// How a model turns the cues into a score (log-odds of voiced).
#[derive(Debug, Clone, PartialEq)]
enum Scorer {
    /// A logistic regression (version 1).
    Logistic(Linear),
    /// `base` + the trees (version 2).
    Trees { base: f32, trees: Ensemble },
    /// The logistic regression's score + the trees (version 3: trees boosted from the
    /// logistic score, which keeps the score rising with clarity where the trees are flat).
    Hybrid { linear: Linear, trees: Ensemble },
}

/// A voicing model: a score (log-odds of voiced) from the cues, and two thresholds on it; a
/// frame starts voicing at `threshold_on` and keeps voicing down to `threshold_off`. The score
/// is a logistic regression (format version 1), a sum of small regression trees (gradient
/// boosting, version 2), or the logistic score plus such trees (version 3).
///
/// File format (text, UTF-8; `#` lines and blank lines are comments). Version 1:
///
/// ```text
/// pneuma-voicing-model 1
/// feature <name> mean <m> scale <s> weight <w>     (one per cue, in VOICING_FEATURES order)
/// bias <b>
/// threshold_on <on>
/// threshold_off <off>                               (off ≤ on)
/// ```
///
/// Version 2 (trees):
///
/// ```text
/// pneuma-voicing-model 2
/// trees <count> depth <d> base <b>                  (1 ≤ d ≤ 4)
/// tree <name> <t> ... <name> <t> leaves <v> ...     (count lines: 2^d − 1 splits breadth
///                                                    first, then 2^d leaf values)
/// threshold_on <on>
/// threshold_off <off>
/// ```
///
/// Version 3 (hybrid: the logistic regression's score plus trees):
///
/// ```text
/// pneuma-voicing-model 3
/// feature ... / bias <b>                            (as in version 1)
/// trees <count> depth <d>                           (then the tree lines of version 2)
/// tree ...
/// threshold_on <on>
/// threshold_off <off>
/// ```
///
/// A split sends a frame whose cue `<name>` is at most `<t>` to its first child. The score is
/// `base` (version 2) or the logistic score (version 3) plus the leaf each tree reaches. Every number is a finite decimal (written as the
/// shortest text that reads back as the same `f32`), every scale positive.
#[derive(Debug, Clone, PartialEq)]
pub struct VoicingModel {
    scorer: Scorer,
    threshold_on: f32,
    threshold_off: f32,
}

impl Default for VoicingModel {
    fn default() -> Self {
        Self::shipped().clone()
    }
}

impl VoicingModel {
    /// A model from a checked scorer; fails on non-finite thresholds or `off > on`.
    fn from_scorer(scorer: Scorer, threshold_on: f32, threshold_off: f32) -> Result<Self, String> {
        if !(threshold_on.is_finite() && threshold_off.is_finite()) {
            return Err("thresholds must be finite".into());
        }
        if threshold_off > threshold_on {
            return Err(format!(
                "threshold_off {threshold_off} lies above threshold_on {threshold_on}"
            ));
        }
        Ok(Self {
            scorer,
            threshold_on,
            threshold_off,
        })
    }

    /// The model shipped in `assets/models/voicing.txt` (embedded; a unit test checks that it
    /// parses).
    pub fn shipped() -> &'static VoicingModel {
        static MODEL: OnceLock<VoicingModel> = OnceLock::new();
        MODEL.get_or_init(|| {
            VoicingModel::parse(SHIPPED_MODEL).expect("the embedded voicing model parses")
        })
    }

    /// A logistic-regression model from its parts; fails (naming the part) on a non-finite
    /// number, a scale that is not positive or `threshold_off > threshold_on`.
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
        if !bias.is_finite() {
            return Err("bias must be finite".into());
        }
        let scorer = Scorer::Logistic(Linear {
            mean,
            scale,
            weight,
            bias,
        });
        Self::from_scorer(scorer, threshold_on, threshold_off)
    }

    /// A tree-ensemble model: `splits` holds `2^depth − 1` splits per tree (breadth first),
    /// each (cue index in [`VOICING_FEATURES`], threshold: a frame whose cue is at most the
    /// threshold goes to the first child), `leaves` `2^depth` values per tree; fails (naming
    /// the part) on a depth outside 1..=4, arrays of the wrong length, an unknown cue, a
    /// non-finite number or `threshold_off > threshold_on`.
    pub fn trees(
        depth: usize,
        base: f32,
        splits: Vec<(usize, f32)>,
        leaves: Vec<f32>,
        threshold_on: f32,
        threshold_off: f32,
    ) -> Result<Self, String> {
        if !base.is_finite() {
            return Err("base must be finite".into());
        }
        let trees = Ensemble::new(depth, splits, leaves)?;
        Self::from_scorer(Scorer::Trees { base, trees }, threshold_on, threshold_off)
    }

    /// This logistic-regression model's score plus trees (a hybrid, format version 3):
    /// `depth`, `splits` and `leaves` as for [`VoicingModel::trees`], the thresholds given.
    /// Fails on a model that is not a logistic regression, or as [`VoicingModel::trees`] does.
    pub fn plus_trees(
        &self,
        depth: usize,
        splits: Vec<(usize, f32)>,
        leaves: Vec<f32>,
        threshold_on: f32,
        threshold_off: f32,
    ) -> Result<Self, String> {
        let Scorer::Logistic(linear) = &self.scorer else {
            return Err("trees are added to a logistic regression only".into());
        };
        let trees = Ensemble::new(depth, splits, leaves)?;
        let scorer = Scorer::Hybrid {
            linear: linear.clone(),
            trees,
        };
        Self::from_scorer(scorer, threshold_on, threshold_off)
    }

    /// The same scorer with other thresholds (`off ≤ on`).
    pub fn with_thresholds(&self, threshold_on: f32, threshold_off: f32) -> Result<Self, String> {
        Self::from_scorer(self.scorer.clone(), threshold_on, threshold_off)
    }

    /// The same model with only the first `count` of its trees (an earlier stage of
    /// boosting); a logistic model is returned as it is.
    pub fn first_trees(&self, count: usize) -> Self {
        let mut m = self.clone();
        if let Scorer::Trees { trees, .. } | Scorer::Hybrid { trees, .. } = &mut m.scorer {
            trees.truncate(count);
        }
        m
    }

    /// The score of one frame's features (log-odds of voiced). Never allocates.
    pub fn score(&self, features: &VoicingFeatures) -> f32 {
        match &self.scorer {
            Scorer::Logistic(linear) => linear.score(features),
            Scorer::Trees { base, trees } => base + trees.score(features),
            Scorer::Hybrid { linear, trees } => linear.score(features) + trees.score(features),
        }
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

    /// Reads a model file of any version (see the type's docs); errors name the line.
    pub fn parse(text: &str) -> Result<Self, VoicingModelError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (line, first) = keyed_line(&mut lines, &format!("the format line `{FORMAT_LINE}`"))?;
        let version = match first {
            FORMAT_LINE_V1 => 1,
            FORMAT_LINE_V2 => 2,
            FORMAT_LINE => 3,
            _ => {
                return Err(bad(
                    line,
                    format!("expected `{FORMAT_LINE}` (or version 1 or 2), found `{first}` (not a voicing model, or another version)"),
                ))
            }
        };
        let scorer = match version {
            1 => Scorer::Logistic(parse_linear(&mut lines)?),
            2 => {
                let (line, l) = keyed_line(&mut lines, "the `trees` line")?;
                let t: Vec<&str> = l.split_whitespace().collect();
                let ["trees", n, "depth", d, "base", b] = t[..] else {
                    return Err(bad(
                        line,
                        format!("expected `trees <count> depth <d> base <b>`, found `{l}`"),
                    ));
                };
                let base = number(line, "base", b)?;
                let trees = parse_trees(&mut lines, line, n, d)?;
                Scorer::Trees { base, trees }
            }
            _ => {
                let linear = parse_linear(&mut lines)?;
                let (line, l) = keyed_line(&mut lines, "the `trees` line")?;
                let t: Vec<&str> = l.split_whitespace().collect();
                let ["trees", n, "depth", d] = t[..] else {
                    return Err(bad(
                        line,
                        format!("expected `trees <count> depth <d>`, found `{l}`"),
                    ));
                };
                let trees = parse_trees(&mut lines, line, n, d)?;
                Scorer::Hybrid { linear, trees }
            }
        };
        let (_, on) = keyed_number(&mut lines, "threshold_on")?;
        let (line_off, off) = keyed_number(&mut lines, "threshold_off")?;
        let model = Self::from_scorer(scorer, on, off).map_err(|m| bad(line_off, m))?;
        if let Some((line, l)) = lines.next() {
            return Err(bad(
                line,
                format!("unexpected line after threshold_off: `{l}`"),
            ));
        }
        Ok(model)
    }

    /// The model as a file: `notes` (provenance) as leading comment lines, then the format.
    /// [`VoicingModel::parse`] reads it back to the same model, bit for bit.
    pub fn to_text(&self, notes: &[String]) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        for n in notes {
            let _ = writeln!(s, "# {n}");
        }
        let write_linear = |s: &mut String, l: &Linear| {
            for (i, name) in VOICING_FEATURES.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "feature {name} mean {} scale {} weight {}",
                    l.mean[i], l.scale[i], l.weight[i]
                );
            }
            let _ = writeln!(s, "bias {}", l.bias);
        };
        match &self.scorer {
            Scorer::Logistic(linear) => {
                let _ = writeln!(s, "{FORMAT_LINE_V1}");
                write_linear(&mut s, linear);
            }
            Scorer::Trees { base, trees } => {
                let _ = writeln!(s, "{FORMAT_LINE_V2}");
                let _ = writeln!(
                    s,
                    "trees {} depth {} base {base}",
                    trees.count(),
                    trees.depth
                );
                trees.write(&mut s);
            }
            Scorer::Hybrid { linear, trees } => {
                let _ = writeln!(s, "{FORMAT_LINE}");
                write_linear(&mut s, linear);
                let _ = writeln!(s, "trees {} depth {}", trees.count(), trees.depth);
                trees.write(&mut s);
            }
        }
        let _ = writeln!(s, "threshold_on {}", self.threshold_on);
        let _ = writeln!(s, "threshold_off {}", self.threshold_off);
        s
    }
}

/// A line error.
fn bad(line: usize, message: String) -> VoicingModelError {
    VoicingModelError::Line { line, message }
}

/// `text` as a finite number, or the error naming `key` and the line.
fn number(line: usize, key: &str, text: &str) -> Result<f32, VoicingModelError> {
    text.parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| bad(line, format!("{key} {text:?} is not a finite number")))
}

/// The `feature` lines and the `bias` line of a logistic regression.
fn parse_linear<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Result<Linear, VoicingModelError> {
    let (mut mean, mut scale, mut weight) = (
        [0.0; N_VOICING_FEATURES],
        [0.0; N_VOICING_FEATURES],
        [0.0; N_VOICING_FEATURES],
    );
    for (i, name) in VOICING_FEATURES.iter().enumerate() {
        let (line, l) = keyed_line(lines, &format!("the line of feature {name}"))?;
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
    let (_, bias) = keyed_number(lines, "bias")?;
    Ok(Linear {
        mean,
        scale,
        weight,
        bias,
    })
}

/// The `count` `tree` lines of depth `depth` (both as written on the `trees` line, `line`).
fn parse_trees<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    line: usize,
    count: &str,
    depth: &str,
) -> Result<Ensemble, VoicingModelError> {
    let count = count
        .parse::<usize>()
        .map_err(|_| bad(line, format!("tree count {count:?} is not a whole number")))?;
    let depth = depth
        .parse::<usize>()
        .ok()
        .filter(|d| (1..=MAX_TREE_DEPTH).contains(d))
        .ok_or_else(|| {
            bad(
                line,
                format!("depth {depth:?} is not a whole number in 1..={MAX_TREE_DEPTH}"),
            )
        })?;
    let n_leaves = 1usize << depth;
    let mut splits = Vec::with_capacity(count * (n_leaves - 1));
    let mut leaves = Vec::with_capacity(count * n_leaves);
    let mut last = line;
    for k in 0..count {
        let (line, l) = keyed_line(lines, &format!("tree {} of {count}", k + 1))?;
        last = line;
        let t: Vec<&str> = l.split_whitespace().collect();
        let expected = 1 + 2 * (n_leaves - 1) + 1 + n_leaves;
        if t.len() != expected || t[0] != "tree" || t[2 * n_leaves - 1] != "leaves" {
            return Err(bad(
                line,
                format!(
                    "tree {} of {count}: expected `tree` then {} pairs `<cue> <threshold>`, `leaves` and {n_leaves} numbers (depth {depth}), found `{l}`",
                    k + 1,
                    n_leaves - 1
                ),
            ));
        }
        for pair in t[1..2 * n_leaves - 1].chunks_exact(2) {
            let feature = VOICING_FEATURES
                .iter()
                .position(|n| *n == pair[0])
                .ok_or_else(|| {
                    bad(
                        line,
                        format!(
                            "unknown cue {:?} (the cues are {})",
                            pair[0],
                            VOICING_FEATURES.join(", ")
                        ),
                    )
                })?;
            splits.push((feature, number(line, "threshold", pair[1])?));
        }
        for v in &t[2 * n_leaves..] {
            leaves.push(number(line, "leaf", v)?);
        }
    }
    Ensemble::new(depth, splits, leaves).map_err(|m| bad(last, m))
}

/// The next content line of a model file, or the error naming what is missing.
fn keyed_line<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    what: &str,
) -> Result<(usize, &'a str), VoicingModelError> {
    lines.next().ok_or_else(|| VoicingModelError::Truncated {
        missing: what.to_string(),
    })
}

/// The next content line, which must read `<key> <number>`.
fn keyed_number<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    key: &str,
) -> Result<(usize, f32), VoicingModelError> {
    let (line, l) = keyed_line(lines, &format!("the `{key}` line"))?;
    match l.split_whitespace().collect::<Vec<_>>()[..] {
        [k, v] if k == key => number(line, key, v).map(|v| (line, v)),
        _ => Err(bad(line, format!("expected `{key} <number>`, found `{l}`"))),
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

    /// A logistic model with distinct numbers (a version 1 file).
    fn logistic() -> VoicingModel {
        let mut mean = [0.0; N_VOICING_FEATURES];
        let mut weight = [0.0; N_VOICING_FEATURES];
        for i in 0..N_VOICING_FEATURES {
            mean[i] = 0.1 * i as f32;
            weight[i] = 1.0 - 0.05 * i as f32;
        }
        VoicingModel::new(mean, [0.5; N_VOICING_FEATURES], weight, -0.25, 0.5, -0.5).unwrap()
    }

    /// Two trees of depth 2: the first splits on long_clarity at 0.5, then on level_vs_gate
    /// at 0 (lower child) and period_jump at 0.25 (upper child); the second only on
    /// low_band at 0.8, the second level's splits sending everything to the first child.
    fn two_trees() -> VoicingModel {
        let (splits, leaves) = two_trees_parts();
        VoicingModel::trees(2, 0.5, splits, leaves, 1.0, 0.0).unwrap()
    }

    /// The splits and leaves of [`two_trees`].
    fn two_trees_parts() -> (Vec<(usize, f32)>, Vec<f32>) {
        let splits = vec![
            (0, 0.5),
            (14, 0.0),
            (11, 0.25),
            (10, 0.8),
            (0, f32::MAX),
            (0, f32::MAX),
        ];
        (splits, vec![-2.0, -1.0, 3.0, 1.0, 0.25, 0.0, -0.75, 0.0])
    }

    /// [`logistic`] plus the trees of [`two_trees`] (a version 3 file).
    fn hybrid() -> VoicingModel {
        let (splits, leaves) = two_trees_parts();
        logistic().plus_trees(2, splits, leaves, 1.5, -0.5).unwrap()
    }

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
        // Both versions read back bit for bit.
        for m in [logistic(), two_trees(), hybrid()] {
            assert_eq!(VoicingModel::parse(&m.to_text(&["n".into()])).unwrap(), m);
        }
        assert!(hybrid().to_text(&[]).starts_with(FORMAT_LINE));
        assert!(logistic().to_text(&[]).starts_with(FORMAT_LINE_V1));
        assert!(two_trees().to_text(&[]).starts_with(FORMAT_LINE_V2));
    }

    #[test]
    fn trees_score_the_leaf_each_tree_reaches() {
        let m = two_trees();
        let f = |clarity: f32, gate: f32, jump: f32, low: f32| {
            let mut f = [0.0; N_VOICING_FEATURES];
            f[0] = clarity;
            f[14] = gate;
            f[11] = jump;
            f[10] = low;
            f
        };
        // base 0.5 + first tree's leaf + second tree's leaf (0.25 at low_band ≤ 0.8, else
        // -0.75); a value equal to a threshold goes to the first child.
        assert_eq!(m.score(&f(0.5, 0.0, 0.0, 0.8)), 0.5 - 2.0 + 0.25);
        assert_eq!(m.score(&f(0.2, 0.1, 0.0, 0.9)), 0.5 - 1.0 - 0.75);
        assert_eq!(m.score(&f(0.9, -1.0, 0.25, 0.0)), 0.5 + 3.0 + 0.25);
        assert_eq!(m.score(&f(0.9, -1.0, 0.5, 1.0)), 0.5 + 1.0 - 0.75);
        assert_eq!(m.first_trees(1).score(&f(0.9, -1.0, 0.5, 1.0)), 0.5 + 1.0);
        assert_eq!(m.threshold(false), 1.0);
        assert_eq!(m.threshold(true), 0.0);
    }

    #[test]
    fn a_hybrid_scores_the_logistic_score_plus_the_trees() {
        let (l, t, h) = (logistic(), two_trees(), hybrid());
        for k in 0..50 {
            let mut f = [0.0; N_VOICING_FEATURES];
            for (i, v) in f.iter_mut().enumerate() {
                *v = ((k * 7 + i * 3) % 11) as f32 / 10.0 - 0.2;
            }
            // The trees' part is the tree model's score without its base (0.5).
            assert_eq!(h.score(&f), l.score(&f) + (t.score(&f) - 0.5), "{f:?}");
        }
        assert_eq!(
            h.first_trees(0).score(&[0.3; N_VOICING_FEATURES]),
            l.score(&[0.3; N_VOICING_FEATURES])
        );
        assert!(t
            .plus_trees(1, vec![(0, 0.5)], vec![0.0, 1.0], 0.0, 0.0)
            .is_err());
    }

    #[test]
    fn malformed_version_3_files_are_rejected_naming_the_line() {
        let good = hybrid().to_text(&["a note".into()]);
        let n = good.lines().count();
        // From 0: line 0 the note, 1 the format, then the features, then (at `b`) the bias,
        // the `trees` line and the two trees, then the thresholds.
        let b = 2 + N_VOICING_FEATURES;
        assert_eq!(
            line_of(&with(&good, b + 1, "trees 2 depth 2 base 0.5")),
            b + 2
        );
        assert_eq!(line_of(&with(&good, b + 1, "trees 2 depth 5")), b + 2);
        assert_eq!(line_of(&with(&good, b, "bias x")), b + 1);
        let tree = good.lines().nth(b + 2).unwrap();
        assert_eq!(
            line_of(&with(&good, b + 3, &tree.replace("leaves", "leafs"))),
            b + 4
        );
        assert_eq!(line_of(&with(&good, n - 1, "threshold_off 2")), n);
        // A version 3 file without its trees: the thresholds come where the `trees` line must.
        let no_trees: Vec<&str> = good.lines().filter(|l| !l.starts_with("tree")).collect();
        assert_eq!(line_of(&no_trees.join("\n")), b + 2);
    }

    /// The 1-based line of a parse error (panics on anything else).
    fn line_of(text: &str) -> usize {
        match VoicingModel::parse(text) {
            Err(VoicingModelError::Line { line, .. }) => line,
            other => panic!("expected a line error, got {other:?}"),
        }
    }

    /// `text` with its line `i` (from 0) replaced by `l`.
    fn with(text: &str, i: usize, l: &str) -> String {
        let mut v: Vec<&str> = text.lines().collect();
        v[i] = l;
        v.join("\n")
    }

    #[test]
    fn malformed_version_1_files_are_rejected_naming_the_line() {
        let good = logistic().to_text(&["a note".into()]);
        let n = good.lines().count();
        // `with` counts from 0, the messages from 1: line 1 is the note, line 2 the format,
        // 3.. the features.
        assert_eq!(line_of(&with(&good, 1, "pneuma-voicing-model 4")), 2);
        assert_eq!(
            line_of(&with(
                &good,
                2,
                "feature long_clarity mean x scale 1 weight 1"
            )),
            3
        );
        // The second feature line naming the first feature: out of order.
        assert_eq!(
            line_of(&with(
                &good,
                3,
                "feature long_clarity mean 0 scale 1 weight 1"
            )),
            4
        );
        assert_eq!(
            line_of(&with(
                &good,
                4,
                "feature short_clarity mean 0 scale 0 weight 1"
            )),
            5
        );
        assert_eq!(line_of(&with(&good, n - 1, "threshold_off 99")), n);
        let e = VoicingModel::parse(&with(
            &good,
            2,
            "feature long_clarity mean NaN scale 1 weight 1",
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("line 3") && e.contains("cargo xtask train-voicing"),
            "{e}"
        );
        let cut: Vec<&str> = good.lines().take(n - 2).collect();
        assert!(matches!(
            VoicingModel::parse(&cut.join("\n")),
            Err(VoicingModelError::Truncated { .. })
        ));
    }

    #[test]
    fn malformed_version_2_files_are_rejected_naming_the_line() {
        let good = two_trees().to_text(&["a note".into()]);
        let n = good.lines().count();
        // Line 2 the format, 3 the `trees` line, 4 and 5 the trees, then the thresholds.
        assert_eq!(line_of(&with(&good, 2, "trees 2 depth 9 base 0")), 3);
        assert_eq!(line_of(&with(&good, 2, "trees 2 base 0 depth 2")), 3);
        let tree = good.lines().nth(3).unwrap();
        assert_eq!(
            line_of(&with(&good, 3, &tree.replace("long_clarity", "loudness"))),
            4
        );
        assert_eq!(line_of(&with(&good, 4, &format!("{tree} 1"))), 5);
        assert_eq!(
            line_of(&with(&good, 4, &tree.replace("leaves", "leafs"))),
            5
        );
        assert_eq!(line_of(&with(&good, 3, &tree.replace("-2", "inf"))), 4);
        assert_eq!(line_of(&with(&good, n - 1, "threshold_off 2")), n);
        // A third tree announced but missing: the file ends early.
        let e = VoicingModel::parse(&with(&good, 2, "trees 3 depth 2 base 0.5")).unwrap_err();
        assert_eq!(line_of(&with(&good, 2, "trees 3 depth 2 base 0.5")), n - 1);
        assert!(e.to_string().contains("tree 3 of 3"), "{e}");
        let cut: Vec<&str> = good.lines().take(4).collect();
        let e = VoicingModel::parse(&cut.join("\n")).unwrap_err();
        assert!(
            matches!(e, VoicingModelError::Truncated { .. })
                && e.to_string().contains("tree 2 of 2"),
            "{e}"
        );
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

    /// Evidence of a frame at `band_over_floor_db` over the band's noise floor, whose long
    /// window reads `long_clarity` where the background alone reads `noise_clarity`.
    fn in_noise(long_clarity: f32, band_over_floor_db: f32, noise_clarity: f32) -> VoicingFeatures {
        VoicingEvidence {
            long_clarity,
            chosen_clarity: long_clarity,
            rms_db: -20.0,
            speech_db: -20.0,
            floor_db: -20.0 - band_over_floor_db,
            band_db: -20.0,
            band_floor_db: -20.0 - band_over_floor_db,
            noise_clarity,
            ..Default::default()
        }
        .features()
    }

    #[test]
    fn the_background_is_taken_out_of_the_clarity() {
        let denoised = VOICING_FEATURES
            .iter()
            .position(|&n| n == "denoised_clarity")
            .unwrap();
        // A perfectly periodic voice (clarity 1) mixed with as much noise (its own clarity
        // 0.2): the NSDF peak of the mix is the power-weighted mean of the two, 0.6, and the
        // band level is 3 dB over the floor. Taking the background out finds the voice's 1.
        let half = 10.0 * 2f32.log10();
        let f = in_noise(0.5 * 1.0 + 0.5 * 0.2, half, 0.2);
        assert!((f[denoised] - 1.0).abs() < 1e-3, "{}", f[denoised]);
        // A voice of clarity 0.8 with a third of the band's power noise of clarity 0.3.
        let third = 10.0 * 3f32.log10();
        let f = in_noise(2.0 / 3.0 * 0.8 + 1.0 / 3.0 * 0.3, third, 0.3);
        assert!((f[denoised] - 0.8).abs() < 1e-3, "{}", f[denoised]);
        // The background alone (at the floor, as clear as the background) has no voice left,
        // and far over the floor nothing is taken out.
        let f = in_noise(0.3, 0.0, 0.3);
        assert!(f[denoised].abs() < 1e-3, "{}", f[denoised]);
        let f = in_noise(0.7, 60.0, 0.3);
        assert!((f[denoised] - 0.7).abs() < 1e-3, "{}", f[denoised]);
    }
}
