//! The voicing model: a score over the cues (a logistic regression, regression trees, or
//! both added) with two thresholds on it, and its parts ([`Linear`], [`Ensemble`]).

use std::sync::Arc;

use thiserror::Error;

use super::cues::{VoicingFeatures, N_VOICING_FEATURES, VOICING_FEATURES};

/// A malformed voicing model file. The message names the line and what to do.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum VoicingModelError {
    /// A line that does not say what the format requires there.
    #[error("voicing model, line {line}: {message}; regenerate the file with `cargo xtask train-voicing` (format documented in core/src/analysis/voicing/model_file.rs)")]
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
    /// Parts given to a constructor ([`VoicingModel::new`], [`VoicingModel::trees`],
    /// [`VoicingModel::plus_trees`], [`VoicingModel::with_thresholds`]) that make no model.
    #[error(transparent)]
    Invalid(#[from] InvalidVoicingModel),
}

/// What is wrong with the parts of a voicing model (the message names the part).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum InvalidVoicingModel {
    /// A tree depth outside 1..=[`MAX_TREE_DEPTH`].
    #[error("depth {0} is outside 1..={MAX_TREE_DEPTH}")]
    Depth(usize),
    /// Split and leaf arrays whose lengths make no whole number of trees.
    #[error("{splits} splits and {leaves} leaves do not make whole trees of depth {depth}")]
    PartialTrees {
        /// Splits given.
        splits: usize,
        /// Leaves given.
        leaves: usize,
        /// Depth given.
        depth: usize,
    },
    /// A split on an unknown cue or at a threshold that is not finite.
    #[error("split on cue {feature} at {threshold}: the cue must be one of the {N_VOICING_FEATURES} and the threshold finite")]
    Split {
        /// Index of the cue given.
        feature: usize,
        /// Threshold given.
        threshold: f32,
    },
    /// A leaf value that is not finite.
    #[error("leaf values must be finite")]
    Leaf,
    /// A threshold that is not finite.
    #[error("thresholds must be finite")]
    ThresholdNotFinite,
    /// `threshold_off` above `threshold_on`.
    #[error("threshold_off {off} lies above threshold_on {on}")]
    ThresholdOrder {
        /// `threshold_on` given.
        on: f32,
        /// `threshold_off` given.
        off: f32,
    },
    /// A logistic regression's mean or weight of a cue that is not finite.
    #[error("feature {0}: mean and weight must be finite")]
    MeanOrWeight(&'static str),
    /// A scale that is not positive and finite.
    #[error("feature {0}: scale must be positive and finite")]
    Scale(&'static str),
    /// A bias that is not finite.
    #[error("bias must be finite")]
    Bias,
    /// A trees model's base score that is not finite.
    #[error("base must be finite")]
    Base,
    /// Trees added to a model that is not a logistic regression.
    #[error("trees are added to a logistic regression only")]
    NotLogistic,
}

/// The most splits on a tree's path from its root to a leaf (a tree has `2^depth` leaves).
pub(super) const MAX_TREE_DEPTH: usize = 4;

/// One split of a tree: frames whose cue `feature` is at most `threshold` go to the lower child.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct TreeSplit {
    /// Index of the cue in [`VOICING_FEATURES`].
    pub(super) feature: usize,
    /// The split value (finite).
    pub(super) threshold: f32,
}

/// A logistic regression's score: bias + Σ weight·(feature − mean)/scale.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Linear {
    pub(super) mean: VoicingFeatures,
    pub(super) scale: VoicingFeatures,
    pub(super) weight: VoicingFeatures,
    pub(super) bias: f32,
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
pub(super) struct Ensemble {
    pub(super) depth: usize,
    pub(super) splits: Arc<[TreeSplit]>,
    pub(super) leaves: Arc<[f32]>,
}

impl Ensemble {
    /// Checks the parts (see [`VoicingModel::trees`]).
    pub(super) fn new(
        depth: usize,
        splits: Vec<(usize, f32)>,
        leaves: Vec<f32>,
    ) -> Result<Self, InvalidVoicingModel> {
        let splits: Vec<TreeSplit> = splits
            .into_iter()
            .map(|(feature, threshold)| TreeSplit { feature, threshold })
            .collect();
        if !(1..=MAX_TREE_DEPTH).contains(&depth) {
            return Err(InvalidVoicingModel::Depth(depth));
        }
        let n_leaves = 1 << depth;
        let n_trees = leaves.len() / n_leaves;
        if leaves.len() != n_trees * n_leaves || splits.len() != n_trees * (n_leaves - 1) {
            return Err(InvalidVoicingModel::PartialTrees {
                splits: splits.len(),
                leaves: leaves.len(),
                depth,
            });
        }
        if let Some(s) = splits
            .iter()
            .find(|s| s.feature >= N_VOICING_FEATURES || !s.threshold.is_finite())
        {
            return Err(InvalidVoicingModel::Split {
                feature: s.feature,
                threshold: s.threshold,
            });
        }
        if !leaves.iter().all(|v| v.is_finite()) {
            return Err(InvalidVoicingModel::Leaf);
        }
        Ok(Self {
            depth,
            splits: splits.into(),
            leaves: leaves.into(),
        })
    }

    pub(super) fn n_leaves(&self) -> usize {
        1 << self.depth
    }

    pub(super) fn count(&self) -> usize {
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
}

/// How a model turns the cues into a score (log-odds of voiced).
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Scorer {
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
/// The file format is described at [`VoicingModel::parse`].
#[derive(Debug, Clone, PartialEq)]
pub struct VoicingModel {
    pub(super) scorer: Scorer,
    pub(super) threshold_on: f32,
    pub(super) threshold_off: f32,
}

impl Default for VoicingModel {
    fn default() -> Self {
        Self::shipped().clone()
    }
}

impl VoicingModel {
    /// A model from a checked scorer; fails on non-finite thresholds or `off > on`.
    pub(super) fn from_scorer(
        scorer: Scorer,
        threshold_on: f32,
        threshold_off: f32,
    ) -> Result<Self, InvalidVoicingModel> {
        if !(threshold_on.is_finite() && threshold_off.is_finite()) {
            return Err(InvalidVoicingModel::ThresholdNotFinite);
        }
        if threshold_off > threshold_on {
            return Err(InvalidVoicingModel::ThresholdOrder {
                on: threshold_on,
                off: threshold_off,
            });
        }
        Ok(Self {
            scorer,
            threshold_on,
            threshold_off,
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
    ) -> Result<Self, VoicingModelError> {
        for (i, name) in VOICING_FEATURES.iter().enumerate() {
            if !(mean[i].is_finite() && weight[i].is_finite()) {
                return Err(InvalidVoicingModel::MeanOrWeight(name).into());
            }
            if !(scale[i].is_finite() && scale[i] > 0.0) {
                return Err(InvalidVoicingModel::Scale(name).into());
            }
        }
        if !bias.is_finite() {
            return Err(InvalidVoicingModel::Bias.into());
        }
        let scorer = Scorer::Logistic(Linear {
            mean,
            scale,
            weight,
            bias,
        });
        Ok(Self::from_scorer(scorer, threshold_on, threshold_off)?)
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
    ) -> Result<Self, VoicingModelError> {
        if !base.is_finite() {
            return Err(InvalidVoicingModel::Base.into());
        }
        let trees = Ensemble::new(depth, splits, leaves)?;
        Ok(Self::from_scorer(
            Scorer::Trees { base, trees },
            threshold_on,
            threshold_off,
        )?)
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
    ) -> Result<Self, VoicingModelError> {
        let Scorer::Logistic(linear) = &self.scorer else {
            return Err(InvalidVoicingModel::NotLogistic.into());
        };
        let trees = Ensemble::new(depth, splits, leaves)?;
        let scorer = Scorer::Hybrid {
            linear: linear.clone(),
            trees,
        };
        Ok(Self::from_scorer(scorer, threshold_on, threshold_off)?)
    }

    /// The same scorer with other thresholds (`off ≤ on`).
    pub fn with_thresholds(
        &self,
        threshold_on: f32,
        threshold_off: f32,
    ) -> Result<Self, VoicingModelError> {
        Ok(Self::from_scorer(
            self.scorer.clone(),
            threshold_on,
            threshold_off,
        )?)
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
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A logistic model with distinct numbers (a version 1 file).
    pub(crate) fn logistic() -> VoicingModel {
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
    pub(crate) fn two_trees() -> VoicingModel {
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
    pub(crate) fn hybrid() -> VoicingModel {
        let (splits, leaves) = two_trees_parts();
        logistic().plus_trees(2, splits, leaves, 1.5, -0.5).unwrap()
    }

    #[test]
    fn the_constructors_name_the_part_that_is_wrong() {
        let invalid = |r: Result<VoicingModel, VoicingModelError>| match r {
            Err(VoicingModelError::Invalid(e)) => e,
            other => panic!("expected an invalid model, got {other:?}"),
        };
        let e = invalid(VoicingModel::trees(5, 0.0, vec![], vec![], 0.0, 0.0));
        assert_eq!(e, InvalidVoicingModel::Depth(5));
        assert_eq!(e.to_string(), "depth 5 is outside 1..=4");
        let (splits, leaves) = two_trees_parts();
        let e = invalid(VoicingModel::trees(
            2,
            0.0,
            splits,
            leaves[1..].to_vec(),
            0.0,
            0.0,
        ));
        assert_eq!(
            e.to_string(),
            "6 splits and 7 leaves do not make whole trees of depth 2"
        );
        let e = invalid(logistic().with_thresholds(0.0, 1.0));
        assert_eq!(e, InvalidVoicingModel::ThresholdOrder { on: 0.0, off: 1.0 });
        assert_eq!(e.to_string(), "threshold_off 1 lies above threshold_on 0");
        let mut scale = [1.0; N_VOICING_FEATURES];
        scale[1] = 0.0;
        let zero = [0.0; N_VOICING_FEATURES];
        let e = invalid(VoicingModel::new(zero, scale, zero, 0.0, 0.0, 0.0));
        assert_eq!(e, InvalidVoicingModel::Scale("chosen_clarity"));
        assert_eq!(
            e.to_string(),
            "feature chosen_clarity: scale must be positive and finite"
        );
        let e = invalid(two_trees().plus_trees(1, vec![(0, 0.5)], vec![0.0, 1.0], 0.0, 0.0));
        assert_eq!(e, InvalidVoicingModel::NotLogistic);
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
}
