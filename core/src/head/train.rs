//! Training of head models on clips of speech with real head motion: fits the five voiced GMMs
//! and the five unvoiced ones and calibrates a [`Variant`]'s output gain, smoother and speed
//! governor on the training clips ([`super::select`] trains the shipped model).

use thiserror::Error;

use super::em::{EmConfig, EmError};
use super::features::{FeatureRows, TrainingClip};
use super::gmm::Gmm;
use super::governor::govern_track;
use super::inputs::counts_as_voiced;
use super::metrics::{mean_speed, median, motion_stats};
use super::model_file::MAX_OUTPUT_GAIN;
use super::model_file::{
    HeadModel, HeadModelError, Normalisation, Provenance, SynthesisWeights, FEATURE_NAMES,
};
use super::smoother::smooth_track;
use super::synth::{HeadConfig, HeadSynth};
use super::variant::Variant;
use crate::analysis::FeatureFrame;

/// Errors of training; each message says what to change.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum TrainError {
    /// No clips given.
    #[error("no training clips: give at least one clip (two for leave-one-clip-out figures)")]
    NoClips,
    /// EM failed on one GMM.
    #[error("training the {group} `{feature}` GMM failed: {source}")]
    Em {
        /// `voiced` or `unvoiced`.
        group: &'static str,
        /// Feature name.
        feature: &'static str,
        /// What went wrong.
        source: EmError,
    },
    /// The fitted parts do not form a valid model.
    #[error("the trained model is invalid: {0}")]
    Model(#[from] HeadModelError),
}

/// Settings of training.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainConfig {
    /// Components of the voiced velocity and acceleration GMMs (the paper: 11).
    pub components: usize,
    /// Components of the pose GMMs (roll, pitch, yaw given f0 and level when voiced, given
    /// level when not; default 1): one Gaussian makes the pose a linear function of the inputs
    /// whose value at the mean input is the mean pose, so the head sits at the speaker's mean
    /// pose on average. With
    /// several components the argmax climbs to the highest conditional mode, and a narrow
    /// component (one speaker's habitual pose) then holds the head degrees off the mean on
    /// every voice (issue 32); held out on the seven styletalk clips, one component met more
    /// of the targets than three or eleven.
    pub pose_components: usize,
    /// Components of each unvoiced velocity and acceleration GMM (default 4).
    pub unvoiced_components: usize,
    /// EM restarts per GMM (default 3).
    pub restarts: usize,
    /// Most EM iterations (default 200).
    pub max_iterations: usize,
    /// EM seed (default 2015).
    pub seed: u64,
    /// Time constant of the damped return toward neutral stored in the model, seconds
    /// (default 0.8).
    pub return_time_s: f64,
    /// SD of the Gaussian smoothing of the training motion, seconds (default 0.025): removes
    /// the tracking jitter of video-based head tracking from velocity and acceleration.
    pub motion_smoothing_s: f64,
    /// Description of the data for the provenance.
    pub data_description: String,
}

impl Default for TrainConfig {
    fn default() -> Self {
        Self {
            components: 11,
            pose_components: 1,
            unvoiced_components: 4,
            restarts: 3,
            max_iterations: 200,
            seed: 2015,
            return_time_s: 0.8,
            motion_smoothing_s: 0.025,
            data_description: String::new(),
        }
    }
}

fn em(cfg: &TrainConfig, dim: usize, k: usize, seed_offset: u64) -> EmConfig {
    EmConfig {
        max_iterations: cfg.max_iterations,
        ..EmConfig::new(dim, k)
            .seed(cfg.seed.wrapping_add(seed_offset))
            .restarts(cfg.restarts)
    }
}

/// Fits a model on `clips` and calibrates it for `variant` on them.
pub fn fit_model(
    clips: &[&TrainingClip],
    cfg: &TrainConfig,
    variant: Variant,
) -> Result<HeadModel, TrainError> {
    if clips.is_empty() {
        return Err(TrainError::NoClips);
    }
    // The inputs as they come (ranges wide open), then the model's ranges from them.
    let mut norm = Normalisation {
        f0_st_range: [-48.0, 48.0],
        level_db_range: [-120.0, 60.0],
        ..Normalisation::default()
    };
    let mut rows = FeatureRows::default();
    for c in clips {
        rows.add_clip(c, &norm, cfg.motion_smoothing_s);
    }
    norm.f0_st_range = rows.input_range(|r, voiced| voiced.then_some(r[1]));
    norm.level_db_range = rows.input_range(|r, voiced| Some(if voiced { r[2] } else { r[1] }));
    rows.clamp_inputs(&norm);
    let fit = |group: &'static str, k: usize, dim: usize, comps: usize, data: &[[f64; 3]]| {
        em(cfg, dim, comps, (k as u64) * 1000 + dim as u64)
            .fit(data)
            .map(|f| f.gmm)
            .map_err(|source| TrainError::Em {
                group,
                feature: FEATURE_NAMES[k],
                source,
            })
    };
    let mut voiced: Vec<Gmm> = Vec::with_capacity(5);
    let mut unvoiced: Vec<Gmm> = Vec::with_capacity(5);
    for k in 0..5 {
        // The pose densities (roll, pitch, yaw), voiced and unvoiced, with their own
        // component count.
        let (voiced_k, unvoiced_k) = if k < 3 {
            (cfg.pose_components, cfg.pose_components)
        } else {
            (cfg.components, cfg.unvoiced_components)
        };
        voiced.push(fit("voiced", k, 3, voiced_k, &rows.voiced[k])?);
        unvoiced.push(fit("unvoiced", k, 2, unvoiced_k, &rows.unvoiced[k])?);
    }
    let provenance = Provenance {
        data: cfg.data_description.clone(),
        clips: clips.iter().map(|c| c.name.clone()).collect(),
        voiced_frames: rows.voiced[0].len() as u64,
        unvoiced_frames: rows.unvoiced[0].len() as u64,
        frame_rate_hz: clips[0].frame_rate_hz,
        components: cfg.components,
        pose_components: Some(cfg.pose_components),
        seed: cfg.seed,
        motion_smoothing_s: cfg.motion_smoothing_s,
        trainer: format!("pneuma-core {} head::train", env!("CARGO_PKG_VERSION")),
        held_out_log_likelihood: Vec::new(),
        notes: String::new(),
    };
    let to5 = |v: Vec<Gmm>| -> [Gmm; 5] { v.try_into().expect("five GMMs") };
    let mut model = HeadModel::new(
        to5(voiced),
        to5(unvoiced),
        variant.unvoiced,
        cfg.return_time_s,
        norm,
        SynthesisWeights::default(),
        provenance,
    )?;
    calibrate_motion(&mut model, clips, variant)?;
    Ok(model)
}

/// One pose track (roll, pitch, yaw per frame, degrees) per clip.
type Tracks = Vec<Vec<[f64; 3]>>;

/// Time constants the speed governor may use, seconds; training keeps the one whose governed
/// output lands closest to the target on the training clips.
pub const SPEED_TIME_CANDIDATES_S: [f64; 4] = [0.5, 1.0, 2.0, 4.0];

/// Time constants the pose smoother may use, seconds (up to [`super::smoother::MAX_TIME_S`]);
/// training keeps the one whose output, at the gain that matches the real SD, moves at the real
/// speed on the training clips (see [`calibrate_motion`]).
pub const SMOOTHING_CANDIDATES_S: [f64; 5] = [0.05, 0.1, 0.15, 0.2, 0.25];

/// Sets the model's synthesis to `variant` and calibrates its output on `clips` (training clips
/// only, so held-out figures stay honest):
/// - the pose term, the unvoiced behaviour and the paper's velocity and acceleration weights
///   (0 when the variant leaves those terms out);
/// - the per-axis output gain = the median over the clips of real SD / generated SD (clamped to
///   1..[`MAX_OUTPUT_GAIN`]; the median, as the targets judge the median ratio): the argmax
///   follows the densities' centres and so generates less motion than the data it was trained
///   on;
/// - the pose smoother's time constant (when the variant has the smoother): of
///   [`SMOOTHING_CANDIDATES_S`], the one whose output at its own calibrated gain has the median
///   speed ratio (generated / real) closest to 1. The argmax's motion is busier than real
///   motion (more speed per degree of amplitude); the smoother takes out the busy part, so a
///   head with the real amplitude also moves at the real speed;
/// - the speed governor (when the variant has one): the target speed is the geometric centre
///   of the slowest and the fastest clip's real mean speed (the speed every voice should move
///   at, as far from the slowest as from the fastest real speaker); the time constant is the
///   one of [`SPEED_TIME_CANDIDATES_S`] whose governed output lands closest to that target on
///   its worst clip.
///
/// The motion is generated once per clip without smoother, gain, limits or governor (none of
/// them feeds back into the argmax), and each candidate is applied to it.
pub fn calibrate_motion(
    model: &mut HeadModel,
    clips: &[&TrainingClip],
    variant: Variant,
) -> Result<(), TrainError> {
    let behaviour = variant.unvoiced;
    model.unvoiced_behaviour = behaviour;
    let paper = SynthesisWeights::default();
    let mut weights = model.synthesis;
    weights.pose_term = variant.pose_term;
    let motion = if variant.motion_terms { 1.0 } else { 0.0 };
    weights.velocity_weight = paper.velocity_weight * motion;
    weights.acceleration_weight = paper.acceleration_weight * motion;
    weights.output_gain = [1.0; 3];
    weights.speed_target_deg_s = 0.0;
    weights.smoothing_s = 0.0;
    model.set_synthesis(weights)?;
    let free = HeadConfig {
        max_pitch_deg: 90.0,
        max_yaw_deg: 90.0,
        max_roll_deg: 90.0,
        max_speed_deg_s: 2000.0,
        unvoiced: Some(behaviour),
        ..HeadConfig::default()
    };
    let raw: Vec<Vec<[f64; 3]>> = clips
        .iter()
        .map(|c| synthesize_clip(model, &free, c))
        .collect();
    let real: Vec<_> = clips
        .iter()
        .map(|c| motion_stats(&c.pose_deg, c.frame_rate_hz))
        .collect();
    let candidates: &[f64] = if variant.smoother {
        &SMOOTHING_CANDIDATES_S
    } else {
        &[0.0]
    };
    // (time constant, |ln median speed ratio|, gain, the clips' motion at it)
    let mut best: Option<(f64, f64, [f64; 3], Tracks)> = None;
    for &time_s in candidates {
        let mut smoothed: Vec<Vec<[f64; 3]>> = raw
            .iter()
            .zip(clips)
            .map(|(g, c)| smooth_track(g, c.frame_rate_hz, time_s))
            .collect();
        let stats: Vec<_> = smoothed
            .iter()
            .zip(clips)
            .map(|(g, c)| motion_stats(g, c.frame_rate_hz))
            .collect();
        let gain = [0, 1, 2].map(|k| {
            let ratios: Vec<f64> = stats
                .iter()
                .zip(&real)
                .filter(|(g, _)| g.sd_deg[k] > 0.0)
                .map(|(g, r)| r.sd_deg[k] / g.sd_deg[k])
                .collect();
            if ratios.is_empty() {
                1.0
            } else {
                median(ratios).clamp(1.0, MAX_OUTPUT_GAIN)
            }
        });
        for p in smoothed.iter_mut().flatten() {
            for k in 0..3 {
                p[k] *= gain[k];
            }
        }
        let speed_ratio = median(
            smoothed
                .iter()
                .zip(clips)
                .zip(&real)
                .map(|((g, c), r)| mean_speed(g, c.frame_rate_hz) / r.mean_speed_deg_s.max(1e-9))
                .collect(),
        );
        let miss = speed_ratio.max(1e-9).ln().abs();
        if best.as_ref().is_none_or(|b| miss < b.1) {
            best = Some((time_s, miss, gain, smoothed));
        }
    }
    let (time_s, _, gain, generated) = best.expect("at least one smoothing candidate");
    weights.smoothing_s = time_s;
    weights.output_gain = gain;
    let real_speed: Vec<f64> = real.iter().map(|r| r.mean_speed_deg_s).collect();
    if let Some(governor) =
        best_governor(&generated, clips, &real_speed).filter(|_| variant.governor)
    {
        weights.speed_time_s = governor.time_s;
        weights.speed_target_deg_s = governor.target_deg_s;
    }
    model.set_synthesis(weights)?;
    Ok(())
}

/// A speed governor's settings and how far its worst training clip lands from the target.
#[derive(Debug, Clone, Copy)]
struct Governor {
    time_s: f64,
    target_deg_s: f64,
    /// Largest |ln(generated mean speed / target)| over the clips.
    worst_target_error: f64,
}

/// The target is the geometric centre of the slowest and the fastest real speed (from real
/// motion alone, so it cannot follow chance agreements between the generated and the real
/// speeds of a few clips); the time constant is the one whose governed output lands closest to
/// that target on its worst training clip. `None` (no governor) when there are no clips or one
/// of them does not move at all (no speed can be centred on a still head).
fn best_governor(
    generated: &[Vec<[f64; 3]>],
    clips: &[&TrainingClip],
    real_speed: &[f64],
) -> Option<Governor> {
    let slowest = real_speed.iter().copied().fold(f64::INFINITY, f64::min);
    let fastest = real_speed.iter().copied().fold(0.0, f64::max);
    if !(slowest > 0.0 && slowest.is_finite() && fastest.is_finite()) {
        return None;
    }
    let target_deg_s = (slowest * fastest).sqrt().min(500.0);
    let voiced: Vec<Vec<bool>> = clips
        .iter()
        .map(|c| c.frames.iter().map(counts_as_voiced).collect())
        .collect();
    let mut best: Option<Governor> = None;
    for time_s in SPEED_TIME_CANDIDATES_S {
        let worst_target_error = generated
            .iter()
            .zip(clips)
            .zip(&voiced)
            .map(|((gen, c), voiced)| {
                let r = c.frame_rate_hz;
                let g = mean_speed(&govern_track(gen, voiced, r, target_deg_s, time_s), r);
                (g.max(1e-6) / target_deg_s).ln().abs()
            })
            .fold(0.0, f64::max);
        if best.is_none_or(|b| worst_target_error < b.worst_target_error) {
            best = Some(Governor {
                time_s,
                target_deg_s,
                worst_target_error,
            });
        }
    }
    best
}

/// Mean log-likelihood (nats per frame) of each voiced GMM on the voiced frames of `clip`.
pub fn held_out_log_likelihood(model: &HeadModel, clip: &TrainingClip) -> [f64; 5] {
    let mut rows = FeatureRows::default();
    rows.add_clip(
        clip,
        &model.normalisation,
        model.provenance.motion_smoothing_s,
    );
    let mut out = [f64::NAN; 5];
    for k in 0..5 {
        let r = &rows.voiced[k];
        if !r.is_empty() {
            out[k] = r.iter().map(|x| model.voiced()[k].log_pdf(x)).sum::<f64>() / r.len() as f64;
        }
    }
    out
}

/// Runs the synthesis over a clip's frames; returns (roll, pitch, yaw) per frame, degrees.
pub fn synthesize_clip(
    model: &HeadModel,
    config: &HeadConfig,
    clip: &TrainingClip,
) -> Vec<[f64; 3]> {
    synthesize(model, config, &clip.frames, clip.frame_rate_hz)
}

/// Runs a fresh synthesis over `frames` at `frame_rate_hz`; returns (roll, pitch, yaw) per
/// frame, degrees.
pub fn synthesize(
    model: &HeadModel,
    config: &HeadConfig,
    frames: &[FeatureFrame],
    frame_rate_hz: f64,
) -> Vec<[f64; 3]> {
    let mut synth = HeadSynth::new(model.clone(), config.clone()).expect("valid head config");
    frames
        .iter()
        .map(|f| {
            let a = synth.process(f, frame_rate_hz);
            [a.roll_deg as f64, a.pitch_deg as f64, a.yaw_deg as f64]
        })
        .collect()
}
