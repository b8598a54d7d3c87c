//! The head model and its JSON file (DESIGN.md contract): format name and version, the feature
//! normalisation it expects, the five voiced GMMs over (motion feature, f0, level), the five
//! unvoiced GMMs over (motion feature, level) with the chosen unvoiced behaviour, the synthesis
//! weights, and provenance. Loading validates every number and names what is wrong.
//!
//! File layout (version 1):
//! ```text
//! { "format": "pneuma-head-model", "version": 1,
//!   "normalisation": { "f0": "st_re_speaker_median", "level": "db_re_speech_level",
//!                      "angles": "deg_re_speaker_mean_pose", "velocity": "deg_per_s",
//!                      "acceleration": "deg_per_s2", "f0_st_range": [lo, hi],
//!                      "level_db_range": [lo, hi] },
//!   "voiced":   { "roll": GMM, "pitch": GMM, "yaw": GMM, "velocity": GMM, "acceleration": GMM },
//!   "unvoiced": { "behaviour": "hold" | "return" | "loudness_model", "return_time_s": t,
//!                 "roll": GMM, ... },
//!   "synthesis": { "pose_weight": 0.2, "velocity_weight": 0.25, "acceleration_weight": 0.0625,
//!                  "bound_deg": 90, "output_gain": [roll, pitch, yaw],
//!                  "speed_target_deg_s": 17.7, "speed_time_s": 1, "smoothing_s": 0.1 },
//!   "provenance": { ... } }
//! GMM = { "weights": [..], "means": [[..], ..], "covariances": [[[..]..], ..] }
//! ```
//! Voiced GMM coordinates are (feature, f0_st, level_db); unvoiced ones (feature, level_db).
//! Angles are in degrees around the speaker's mean pose, velocity |Δθ| in °/s and acceleration
//! |Δ²θ| in °/s², so a model serves any frame rate.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use super::gmm::{Gaussian, Gmm, GmmError, MAX_DIM};
use super::inputs::{InputKind, InputTracker, SPEAKER_MEAN_NAMES, SPEAKER_MEDIAN_NAMES};
use crate::settings::analysis::FRAME_RATE_HZ;

/// The `format` name of a head model file.
pub const FORMAT_NAME: &str = "pneuma-head-model";
/// The file version this code reads and writes.
pub const FORMAT_VERSION: u32 = 1;

/// The shipped model, trained by `cargo xtask train-default` on the styletalk clips.
const DEFAULT_MODEL_JSON: &str = include_str!("../../../assets/models/head-default.json");

/// Largest per-axis output gain a model may have.
pub const MAX_OUTPUT_GAIN: f64 = 20.0;

/// The names of the five motion features, in model order.
pub const FEATURE_NAMES: [&str; 5] = ["roll", "pitch", "yaw", "velocity", "acceleration"];

/// Errors of head models and their settings; each message says what to change.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum HeadModelError {
    /// The text is not JSON of the model layout.
    #[error("the head model file is not valid: {0} (expected the JSON layout written by `pneuma train`)")]
    Json(String),
    /// The `format` field is wrong.
    #[error("format `{0}` is not a head model: expected \"{FORMAT_NAME}\"")]
    Format(String),
    /// The `version` is not supported.
    #[error("head model version {0} is not supported: this build reads version {FORMAT_VERSION}; retrain with `pneuma train`")]
    Version(u32),
    /// A normalisation field names units this code does not produce.
    #[error("normalisation `{field}` is `{got}` but this build computes `{want}`: retrain the model with `pneuma train`")]
    Normalisation {
        /// Field name.
        field: &'static str,
        /// Value in the file.
        got: String,
        /// Value expected.
        want: &'static str,
    },
    /// A GMM has the wrong dimension.
    #[error("{group} GMM `{feature}` has dimension {got}, expected {want}")]
    Dimension {
        /// `voiced` or `unvoiced`.
        group: &'static str,
        /// Feature name.
        feature: &'static str,
        /// Dimension found.
        got: usize,
        /// Dimension needed.
        want: usize,
    },
    /// A GMM's parameters are invalid.
    #[error("{group} GMM `{feature}`: {source}")]
    Gmm {
        /// `voiced` or `unvoiced`.
        group: &'static str,
        /// Feature name.
        feature: &'static str,
        /// What is wrong.
        source: GmmError,
    },
    /// A number of the model or the settings is outside its range.
    #[error("{name} = {value} is out of range: it must lie in {range}")]
    OutOfRange {
        /// Name of the field.
        name: &'static str,
        /// Value given.
        value: f64,
        /// Allowed range, in words.
        range: &'static str,
    },
    /// A head-pose setting is out of its range.
    #[error(transparent)]
    Setting(#[from] crate::settings::SettingError),
    /// The model's training frame rate is not one the analysis runs at.
    #[error("provenance.frame_rate_hz, the frame rate the model was trained at and its head steps at: {0}; retrain the model with `pneuma train`")]
    TrainingRate(crate::settings::SettingError),
    /// The unvoiced behaviour name is unknown.
    #[error("unvoiced behaviour `{0}` is unknown: use `hold`, `return` or `loudness_model`")]
    Behaviour(String),
}

/// What the head does on unvoiced frames.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UnvoicedBehaviour {
    /// The paper's behaviour: the head keeps its last pose.
    Hold,
    /// A damped return toward the speaker's neutral pose (0°), with the model's time constant.
    Return,
    /// The same argmax synthesis with GMMs of (motion feature, loudness) trained on unvoiced
    /// frames.
    LoudnessModel,
}

impl UnvoicedBehaviour {
    /// The name used in files and on the command line.
    pub fn as_str(self) -> &'static str {
        match self {
            UnvoicedBehaviour::Hold => "hold",
            UnvoicedBehaviour::Return => "return",
            UnvoicedBehaviour::LoudnessModel => "loudness_model",
        }
    }

    /// Parses a name written by [`UnvoicedBehaviour::as_str`].
    pub fn parse(name: &str) -> Result<Self, HeadModelError> {
        match name {
            "hold" => Ok(Self::Hold),
            "return" => Ok(Self::Return),
            "loudness_model" => Ok(Self::LoudnessModel),
            other => Err(HeadModelError::Behaviour(other.to_string())),
        }
    }

    /// All behaviours, for comparisons.
    pub const ALL: [UnvoicedBehaviour; 3] = [Self::Hold, Self::Return, Self::LoudnessModel];
}

/// The weights of the synthesis objective
/// `J(θ) = −pose·Σ log p(θ_axis|f0,E) − velocity·log p(v|f0,E) − acceleration·log p(a|f0,E)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SynthesisWeights {
    /// Weight of each pose term (reference implementation: 0.2).
    pub pose_weight: f64,
    /// Weight of the velocity term (reference: w_v/8 = 0.25).
    pub velocity_weight: f64,
    /// Weight of the acceleration term (reference: w_a/16 = 0.0625).
    pub acceleration_weight: f64,
    /// Box bound of each angle during the search, degrees (reference: 90).
    pub bound_deg: f64,
    /// Output gain per axis (roll, pitch, yaw), 1..[`MAX_OUTPUT_GAIN`]: the argmax follows the densities' modes
    /// and so shrinks the motion; training calibrates this gain on the training clips so the
    /// generated per-axis SD matches the real one (1 = the paper's raw argmax).
    #[serde(default = "unit_gain")]
    pub output_gain: [f64; 3],
    /// Mean angular speed the speed governor scales the output toward, °/s, 0..500 (0 = no
    /// governor, as in files written before it existed); training sets it to the geometric
    /// centre of the slowest and the fastest training clip's real mean speed (see
    /// [`super::governor`] and [`super::train::calibrate_motion`]).
    #[serde(default)]
    pub speed_target_deg_s: f64,
    /// Time constant of the governor's running mean of the ungoverned speed, seconds, 0.1..60;
    /// chosen on the training clips (the one whose output lands closest to the target).
    #[serde(default = "default_speed_time")]
    pub speed_time_s: f64,
    /// Time constant of the pose smoother before the governor, seconds, 0..0.25 (0 = none, as
    /// in files written before it existed); chosen on the training clips (see
    /// [`super::smoother`]).
    #[serde(default)]
    pub smoothing_s: f64,
    /// How the pose terms read the pose densities (`mixture`, the paper's, in files written
    /// before this field existed; see [`PoseTerm`]).
    #[serde(default)]
    pub pose_term: PoseTerm,
}

/// How the synthesis objective's three pose terms use the conditional pose densities
/// p(angle | f0, level).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PoseTerm {
    /// The paper's: the log of the whole conditional mixture. The argmax climbs to the
    /// mixture's highest mode, and a narrow component (one speaker's habitual pose) makes a
    /// high, narrow mode away from the mean: the pose then sits off the mean pose.
    #[default]
    Mixture,
    /// A Gaussian with the conditional mixture's mean and variance: the pose is pulled toward
    /// E[angle | f0, level], which averages to the mean pose over the training frames.
    ConditionalMean,
}

fn unit_gain() -> [f64; 3] {
    [1.0; 3]
}

fn default_speed_time() -> f64 {
    2.0
}

impl Default for SynthesisWeights {
    fn default() -> Self {
        Self {
            pose_weight: 0.2,
            velocity_weight: 0.25,
            acceleration_weight: 0.0625,
            bound_deg: 90.0,
            output_gain: unit_gain(),
            speed_target_deg_s: 0.0,
            speed_time_s: default_speed_time(),
            smoothing_s: 0.0,
            pose_term: PoseTerm::Mixture,
        }
    }
}

/// Where a model came from.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Provenance {
    /// What data, in words (e.g. the data set name and licence).
    pub data: String,
    /// Clip names used.
    pub clips: Vec<String>,
    /// Voiced training frames.
    pub voiced_frames: u64,
    /// Unvoiced training frames.
    pub unvoiced_frames: u64,
    /// Frame rate of the training features, Hz.
    pub frame_rate_hz: f64,
    /// Components of each voiced velocity and acceleration GMM (and, in files without
    /// `pose_components`, of every voiced GMM).
    pub components: usize,
    /// Components of each pose GMM (roll, pitch, yaw; voiced and unvoiced); absent in older
    /// files, whose voiced pose GMMs have `components`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose_components: Option<usize>,
    /// EM seed.
    pub seed: u64,
    /// SD of the Gaussian smoothing applied to the training motion, seconds (tracking jitter
    /// removal); 0 = none.
    #[serde(default)]
    pub motion_smoothing_s: f64,
    /// The program that trained it.
    pub trainer: String,
    /// Leave-one-clip-out held-out mean log-likelihood per voiced GMM (nats per frame), in
    /// feature order; empty when not measured.
    #[serde(default)]
    pub held_out_log_likelihood: Vec<f64>,
    /// Free notes (e.g. the comparison that chose the unvoiced behaviour).
    #[serde(default)]
    pub notes: String,
}

/// The feature normalisation a model expects (checked against what this build computes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Normalisation {
    /// f0 units: `st_re_speaker_mean` (semitones around the speaker's running mean) or, in
    /// older files, `st_re_speaker_median` (see [`super::inputs`]).
    pub f0: String,
    /// Level units: `db_re_speaker_mean` (dB around the running mean of its voicing class) or,
    /// in older files, `db_re_speech_level`.
    pub level: String,
    /// Angle units: `deg_re_speaker_mean_pose`.
    pub angles: String,
    /// Velocity units: `deg_per_s`.
    pub velocity: String,
    /// Acceleration units: `deg_per_s2`.
    pub acceleration: String,
    /// f0 inputs are clamped to this range, semitones.
    pub f0_st_range: [f64; 2],
    /// Level inputs are clamped to this range, dB.
    pub level_db_range: [f64; 2],
}

impl Normalisation {
    /// The inputs the model reads (of a validated model; an unknown pair of names reads as the
    /// current kind).
    pub fn input_kind(&self) -> InputKind {
        InputKind::of_names(&self.f0, &self.level).unwrap_or(InputKind::SpeakerMean)
    }

    /// A fresh tracker of the inputs this normalisation names, clamped to its ranges.
    pub fn input_tracker(&self) -> InputTracker {
        InputTracker::new(self.input_kind(), self.f0_st_range, self.level_db_range)
    }
}

impl Default for Normalisation {
    fn default() -> Self {
        Self {
            f0: SPEAKER_MEAN_NAMES.0.into(),
            level: SPEAKER_MEAN_NAMES.1.into(),
            angles: "deg_re_speaker_mean_pose".into(),
            velocity: "deg_per_s".into(),
            acceleration: "deg_per_s2".into(),
            f0_st_range: [-12.0, 12.0],
            level_db_range: [-40.0, 15.0],
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct GmmFile {
    weights: Vec<f64>,
    means: Vec<Vec<f64>>,
    covariances: Vec<Vec<Vec<f64>>>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FiveFile {
    roll: GmmFile,
    pitch: GmmFile,
    yaw: GmmFile,
    velocity: GmmFile,
    acceleration: GmmFile,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct UnvoicedFile {
    behaviour: String,
    return_time_s: f64,
    roll: GmmFile,
    pitch: GmmFile,
    yaw: GmmFile,
    velocity: GmmFile,
    acceleration: GmmFile,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelFile {
    format: String,
    version: u32,
    normalisation: Normalisation,
    voiced: FiveFile,
    unvoiced: UnvoicedFile,
    synthesis: SynthesisWeights,
    provenance: Provenance,
}

/// The head-pose model: five voiced GMMs, the unvoiced behaviour and its five GMMs, the
/// normalisation, the synthesis weights and provenance. Always valid once constructed.
#[derive(Debug, Clone, PartialEq)]
pub struct HeadModel {
    voiced: [Gmm; 5],
    unvoiced: [Gmm; 5],
    /// The unvoiced behaviour that matched real motion best when the model was trained.
    pub unvoiced_behaviour: UnvoicedBehaviour,
    /// Time constant of the damped return toward neutral, seconds (0.05..10).
    pub return_time_s: f64,
    /// Feature normalisation.
    pub normalisation: Normalisation,
    /// Synthesis objective weights.
    pub synthesis: SynthesisWeights,
    /// Where the model came from.
    pub provenance: Provenance,
}

impl HeadModel {
    /// Replaces the synthesis weights (validated).
    pub fn set_synthesis(&mut self, synthesis: SynthesisWeights) -> Result<(), HeadModelError> {
        let mut probe = self.clone();
        probe.synthesis = synthesis;
        let checked = HeadModel::new(
            probe.voiced,
            probe.unvoiced,
            probe.unvoiced_behaviour,
            probe.return_time_s,
            probe.normalisation,
            probe.synthesis,
            probe.provenance,
        )?;
        self.synthesis = checked.synthesis;
        Ok(())
    }
}

pub(super) fn check(
    name: &'static str,
    v: f64,
    lo: f64,
    hi: f64,
    range: &'static str,
) -> Result<(), HeadModelError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(HeadModelError::OutOfRange {
            name,
            value: v,
            range,
        })
    }
}

fn gmm_from_file(
    f: &GmmFile,
    group: &'static str,
    feature: &'static str,
    want: usize,
) -> Result<Gmm, HeadModelError> {
    let err = |source| HeadModelError::Gmm {
        group,
        feature,
        source,
    };
    let n = f.weights.len();
    if n == 0 || f.means.len() != n || f.covariances.len() != n {
        return Err(HeadModelError::Json(format!(
            "{group} GMM `{feature}` has {n} weights, {} means and {} covariances: they must be equally many and at least one",
            f.means.len(),
            f.covariances.len()
        )));
    }
    let mut comps = Vec::with_capacity(n);
    for k in 0..n {
        let got = f.means[k].len();
        if got != want {
            return Err(HeadModelError::Dimension {
                group,
                feature,
                got,
                want,
            });
        }
        let cov = &f.covariances[k];
        if cov.len() != want || cov.iter().any(|r| r.len() != want) {
            return Err(err(GmmError::Shape {
                component: k,
                what: "covariance",
                dim: want,
                got: cov.iter().map(Vec::len).sum(),
                want: want * want,
            }));
        }
        let mut g = Gaussian {
            weight: f.weights[k],
            mean: [0.0; MAX_DIM],
            cov: [[0.0; MAX_DIM]; MAX_DIM],
        };
        for i in 0..want {
            g.mean[i] = f.means[k][i];
            for j in 0..want {
                g.cov[i][j] = cov[i][j];
            }
        }
        comps.push(g);
    }
    Gmm::new(want, &comps).map_err(err)
}

fn gmm_to_file(g: &Gmm) -> GmmFile {
    let d = g.dim();
    GmmFile {
        weights: g.components().map(|c| c.weight).collect(),
        means: g.components().map(|c| c.mean[..d].to_vec()).collect(),
        covariances: g
            .components()
            .map(|c| c.cov[..d].iter().map(|r| r[..d].to_vec()).collect())
            .collect(),
    }
}

fn check_norm(field: &'static str, got: &str, want: &'static str) -> Result<(), HeadModelError> {
    if got == want {
        Ok(())
    } else {
        Err(HeadModelError::Normalisation {
            field,
            got: got.to_string(),
            want,
        })
    }
}

impl HeadModel {
    /// Builds a model from its parts, validating dimensions and settings. `voiced` GMMs are 3-D
    /// (feature, f0_st, level_db), `unvoiced` ones 2-D (feature, level_db), in the order of
    /// [`FEATURE_NAMES`].
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        voiced: [Gmm; 5],
        unvoiced: [Gmm; 5],
        unvoiced_behaviour: UnvoicedBehaviour,
        return_time_s: f64,
        normalisation: Normalisation,
        synthesis: SynthesisWeights,
        provenance: Provenance,
    ) -> Result<Self, HeadModelError> {
        for (k, g) in voiced.iter().enumerate() {
            if g.dim() != 3 {
                return Err(HeadModelError::Dimension {
                    group: "voiced",
                    feature: FEATURE_NAMES[k],
                    got: g.dim(),
                    want: 3,
                });
            }
        }
        for (k, g) in unvoiced.iter().enumerate() {
            if g.dim() != 2 {
                return Err(HeadModelError::Dimension {
                    group: "unvoiced",
                    feature: FEATURE_NAMES[k],
                    got: g.dim(),
                    want: 2,
                });
            }
        }
        if InputKind::of_names(&normalisation.f0, &normalisation.level).is_none() {
            let field = if [SPEAKER_MEAN_NAMES.0, SPEAKER_MEDIAN_NAMES.0]
                .contains(&normalisation.f0.as_str())
            {
                ("level", normalisation.level.clone())
            } else {
                ("f0", normalisation.f0.clone())
            };
            return Err(HeadModelError::Normalisation {
                field: field.0,
                got: field.1,
                want: "the pairs st_re_speaker_mean + db_re_speaker_mean or st_re_speaker_median + db_re_speech_level",
            });
        }
        check_norm("angles", &normalisation.angles, "deg_re_speaker_mean_pose")?;
        check_norm("velocity", &normalisation.velocity, "deg_per_s")?;
        check_norm("acceleration", &normalisation.acceleration, "deg_per_s2")?;
        let [f_lo, f_hi] = normalisation.f0_st_range;
        check(
            "normalisation.f0_st_range[0]",
            f_lo,
            -48.0,
            0.0,
            "-48..0 st",
        )?;
        check("normalisation.f0_st_range[1]", f_hi, 0.0, 48.0, "0..48 st")?;
        let [l_lo, l_hi] = normalisation.level_db_range;
        check(
            "normalisation.level_db_range[0]",
            l_lo,
            -120.0,
            0.0,
            "-120..0 dB",
        )?;
        check(
            "normalisation.level_db_range[1]",
            l_hi,
            0.0,
            60.0,
            "0..60 dB",
        )?;
        check("return_time_s", return_time_s, 0.05, 10.0, "0.05..10 s")?;
        FRAME_RATE_HZ
            .check(provenance.frame_rate_hz)
            .map_err(HeadModelError::TrainingRate)?;
        let s = &synthesis;
        check("synthesis.pose_weight", s.pose_weight, 0.0, 100.0, "0..100")?;
        check(
            "synthesis.velocity_weight",
            s.velocity_weight,
            0.0,
            100.0,
            "0..100",
        )?;
        check(
            "synthesis.acceleration_weight",
            s.acceleration_weight,
            0.0,
            100.0,
            "0..100",
        )?;
        check(
            "synthesis.bound_deg",
            s.bound_deg,
            1.0,
            180.0,
            "1..180 degrees",
        )?;
        for g in s.output_gain {
            check("synthesis.output_gain", g, 1.0, MAX_OUTPUT_GAIN, "1..20")?;
        }
        check(
            "synthesis.speed_target_deg_s",
            s.speed_target_deg_s,
            0.0,
            500.0,
            "0..500 degrees per second (0 = no speed governor)",
        )?;
        check(
            "synthesis.speed_time_s",
            s.speed_time_s,
            0.1,
            60.0,
            "0.1..60 s",
        )?;
        check(
            "synthesis.smoothing_s",
            s.smoothing_s,
            0.0,
            super::smoother::MAX_TIME_S,
            "0..0.25 s (0 = no smoothing)",
        )?;
        Ok(Self {
            voiced,
            unvoiced,
            unvoiced_behaviour,
            return_time_s,
            normalisation,
            synthesis,
            provenance,
        })
    }

    /// The embedded shipped model (parsed once).
    pub fn default_model() -> &'static HeadModel {
        static MODEL: OnceLock<HeadModel> = OnceLock::new();
        MODEL.get_or_init(|| {
            HeadModel::from_json(DEFAULT_MODEL_JSON)
                .expect("the embedded head model is valid (checked by a unit test)")
        })
    }

    /// The embedded default model file's text.
    pub fn default_model_json() -> &'static str {
        DEFAULT_MODEL_JSON
    }

    /// Parses and validates a model file.
    pub fn from_json(text: &str) -> Result<HeadModel, HeadModelError> {
        // Read format and version first, so an unknown version is named as such.
        let head: serde_json::Value =
            serde_json::from_str(text).map_err(|e| HeadModelError::Json(e.to_string()))?;
        match head.get("format").and_then(|v| v.as_str()) {
            Some(FORMAT_NAME) => {}
            Some(other) => return Err(HeadModelError::Format(other.to_string())),
            None => return Err(HeadModelError::Format("(missing)".into())),
        }
        match head.get("version").and_then(|v| v.as_u64()) {
            Some(v) if v == FORMAT_VERSION as u64 => {}
            Some(v) => return Err(HeadModelError::Version(v.min(u32::MAX as u64) as u32)),
            None => {
                return Err(HeadModelError::Json(
                    "field `version` is missing or not a whole number".into(),
                ))
            }
        }
        let f: ModelFile =
            serde_json::from_value(head).map_err(|e| HeadModelError::Json(e.to_string()))?;
        let v = &f.voiced;
        let voiced = [
            gmm_from_file(&v.roll, "voiced", "roll", 3)?,
            gmm_from_file(&v.pitch, "voiced", "pitch", 3)?,
            gmm_from_file(&v.yaw, "voiced", "yaw", 3)?,
            gmm_from_file(&v.velocity, "voiced", "velocity", 3)?,
            gmm_from_file(&v.acceleration, "voiced", "acceleration", 3)?,
        ];
        let u = &f.unvoiced;
        let unvoiced = [
            gmm_from_file(&u.roll, "unvoiced", "roll", 2)?,
            gmm_from_file(&u.pitch, "unvoiced", "pitch", 2)?,
            gmm_from_file(&u.yaw, "unvoiced", "yaw", 2)?,
            gmm_from_file(&u.velocity, "unvoiced", "velocity", 2)?,
            gmm_from_file(&u.acceleration, "unvoiced", "acceleration", 2)?,
        ];
        let behaviour = UnvoicedBehaviour::parse(&u.behaviour)?;
        HeadModel::new(
            voiced,
            unvoiced,
            behaviour,
            u.return_time_s,
            f.normalisation,
            f.synthesis,
            f.provenance,
        )
    }

    /// Writes the model file (pretty JSON, stable field order, ending with a newline).
    pub fn to_json(&self) -> String {
        let v = &self.voiced;
        let u = &self.unvoiced;
        let f = ModelFile {
            format: FORMAT_NAME.into(),
            version: FORMAT_VERSION,
            normalisation: self.normalisation.clone(),
            voiced: FiveFile {
                roll: gmm_to_file(&v[0]),
                pitch: gmm_to_file(&v[1]),
                yaw: gmm_to_file(&v[2]),
                velocity: gmm_to_file(&v[3]),
                acceleration: gmm_to_file(&v[4]),
            },
            unvoiced: UnvoicedFile {
                behaviour: self.unvoiced_behaviour.as_str().into(),
                return_time_s: self.return_time_s,
                roll: gmm_to_file(&u[0]),
                pitch: gmm_to_file(&u[1]),
                yaw: gmm_to_file(&u[2]),
                velocity: gmm_to_file(&u[3]),
                acceleration: gmm_to_file(&u[4]),
            },
            synthesis: self.synthesis,
            provenance: self.provenance.clone(),
        };
        let mut s = serde_json::to_string_pretty(&f).expect("a model always serialises");
        s.push('\n');
        s
    }

    /// The voiced GMMs over (feature, f0_st, level_db), in [`FEATURE_NAMES`] order.
    pub fn voiced(&self) -> &[Gmm; 5] {
        &self.voiced
    }

    /// The unvoiced GMMs over (feature, level_db), in [`FEATURE_NAMES`] order.
    pub fn unvoiced(&self) -> &[Gmm; 5] {
        &self.unvoiced
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_default_model_is_valid_and_round_trips() {
        let m = HeadModel::from_json(DEFAULT_MODEL_JSON).unwrap();
        assert_eq!(m.voiced().len(), 5);
        assert!(!m.provenance.clips.is_empty());
        let again = HeadModel::from_json(&m.to_json()).unwrap();
        assert_eq!(m, again);
        assert!(
            m.to_json() == DEFAULT_MODEL_JSON,
            "the asset is not in canonical form: regenerate it with `cargo xtask train-default`"
        );
        assert!(std::ptr::eq(
            HeadModel::default_model(),
            HeadModel::default_model()
        ));
    }

    #[test]
    fn smoothing_is_off_in_older_files_and_checked_in_new_ones() {
        let text = HeadModel::default_model_json();
        let shipped = HeadModel::default_model().synthesis.smoothing_s;
        assert!(shipped > 0.0, "the shipped model smooths ({shipped})");
        let key = text
            .find("\"smoothing_s\":")
            .expect("the shipped model has smoothing_s");
        let line_start = text[..key].rfind('\n').unwrap();
        let line_end = key + text[key..].find('\n').unwrap();
        // An older file: the field's line dropped (a field followed by another, with its comma).
        assert!(
            text[..line_end].ends_with(','),
            "smoothing_s is not the last field"
        );
        let older = format!("{}{}", &text[..line_start], &text[line_end..]);
        let m = HeadModel::from_json(&older).unwrap();
        assert_eq!(m.synthesis.smoothing_s, 0.0);
        // Out of range: a clear message naming the field and its range.
        let wrong = format!("{}\"smoothing_s\": 2.5,{}", &text[..key], &text[line_end..]);
        let err = HeadModel::from_json(&wrong).unwrap_err();
        let msg = err.to_string();
        assert!(
            msg.contains("synthesis.smoothing_s") && msg.contains("0..0.25"),
            "{msg}"
        );
    }

    #[test]
    fn a_model_trained_at_a_rate_the_analysis_never_runs_at_is_refused() {
        let text = HeadModel::default_model_json();
        let key = "\"frame_rate_hz\": 120.0";
        assert_eq!(text.matches(key).count(), 1, "one training frame rate");
        let err = HeadModel::from_json(&text.replace(key, "\"frame_rate_hz\": 25.0"))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("provenance.frame_rate_hz") && err.contains("30") && err.contains("240"),
            "{err}"
        );
        assert!(HeadModel::from_json(&text.replace(key, "\"frame_rate_hz\": 30.0")).is_ok());
    }
}
