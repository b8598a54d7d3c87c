//! One clip's generated head motion against its real motion ([`ClipEval`]): the canonical
//! correlation of the head angles with f0 (semitones, voiced frames) for the generated motion,
//! the clip's real motion and, as the chance level, other clips' real motion against the same
//! f0; mean angle (posture), SD and mean angular speed of generated and real motion; frozen
//! frames; the share of angular-velocity power above 3 Hz; and the peak speed when the clip's
//! speech starts after a silence (a jump shows there). Also the frames of a digital silence and
//! the posture over it after a clip's speech. [`super::targets`] judges the figures, [`super::evaluate`] gathers them
//! leave-one-clip-out.

use super::features::TrainingClip;
use super::metrics::{cca_pose_signal, f0_semitones, motion_stats, MotionStats};
use super::model_file::HeadModel;
use super::synth::HeadConfig;
use super::train::synthesize;
use crate::analysis::{AnalysisConfig, Analyzer, FeatureFrame};

/// Silence before each clip in the onset check, seconds: longer than any pause inside speech,
/// so every part of the synthesis has settled to its rest.
pub const ONSET_SILENCE_S: f64 = 3.0;
/// The onset check reads the peak speed over this much of the clip after its first voiced
/// frame, seconds.
pub const ONSET_WINDOW_S: f64 = 0.5;
/// Length of the silence whose posture the cross-validation checks, seconds (the CLI's
/// evaluation checks ten minutes through the engine).
pub const SILENCE_CHECK_S: f64 = 60.0;

/// Comparison of one clip's generated motion with its real motion.
#[derive(Debug, Clone, PartialEq)]
pub struct ClipEval {
    /// Clip name.
    pub name: String,
    /// Frames compared.
    pub frames: usize,
    /// CCA of the head angles with f0 ([`f0_semitones`]) over voiced frames: generated, real,
    /// and chance (the mean over other clips of their real motion against this clip's f0).
    pub cca: [f64; 3],
    /// Statistics of the generated motion.
    pub generated: MotionStats,
    /// Statistics of the real motion.
    pub real: MotionStats,
    /// Peak angular speed of the generated head over the first [`ONSET_WINDOW_S`] of the clip's
    /// speech after [`ONSET_SILENCE_S`] of silence, °/s.
    pub onset_peak_deg_s: f64,
    /// The generated pose per frame (roll, pitch, yaw), degrees.
    pub pose_deg: Vec<[f64; 3]>,
}

impl ClipEval {
    /// Generated / real mean angular speed (0 when the real head does not move).
    pub fn speed_ratio(&self) -> f64 {
        ratio(self.generated.mean_speed_deg_s, self.real.mean_speed_deg_s)
    }

    /// Generated / real SD per axis (roll, pitch, yaw); 0 where the real axis does not move.
    pub fn sd_ratio(&self) -> [f64; 3] {
        [0, 1, 2].map(|k| ratio(self.generated.sd_deg[k], self.real.sd_deg[k]))
    }
}

fn ratio(generated: f64, real: f64) -> f64 {
    if real > 0.0 {
        generated / real
    } else {
        0.0
    }
}

/// f0 per frame for the CCA ([`f0_semitones`], 0 when unvoiced) and the voiced mask.
fn f0_signal(frames: &[FeatureFrame]) -> (Vec<f64>, Vec<bool>) {
    let voiced: Vec<bool> = frames.iter().map(|f| f.voiced && f.f0_hz > 0.0).collect();
    let f0 = frames
        .iter()
        .zip(&voiced)
        .map(|(f, v)| {
            if *v {
                f0_semitones(f.f0_hz as f64)
            } else {
                0.0
            }
        })
        .collect();
    (f0, voiced)
}

/// Compares `generated` (per frame of `clip`) with the clip's real motion and with the real
/// motion of `others` (each tiled or cut to the clip's length) as the chance level;
/// `onset_peak_deg_s` comes from [`onset_peak_speed`].
pub fn evaluate_clip(
    generated: &[[f64; 3]],
    clip: &TrainingClip,
    others: &[&TrainingClip],
    onset_peak_deg_s: f64,
) -> ClipEval {
    let n = clip.frames.len().min(generated.len());
    let (f0, voiced) = f0_signal(&clip.frames[..n]);
    let chance = others
        .iter()
        .map(|o| {
            let tiled: Vec<[f64; 3]> = (0..n).map(|i| o.pose_deg[i % o.pose_deg.len()]).collect();
            cca_pose_signal(&tiled, &f0, Some(&voiced))
        })
        .sum::<f64>()
        / others.len().max(1) as f64;
    ClipEval {
        name: clip.name.clone(),
        frames: n,
        cca: [
            cca_pose_signal(&generated[..n], &f0, Some(&voiced)),
            cca_pose_signal(&clip.pose_deg[..n], &f0, Some(&voiced)),
            chance,
        ],
        generated: motion_stats(&generated[..n], clip.frame_rate_hz),
        real: motion_stats(&clip.pose_deg[..n], clip.frame_rate_hz),
        onset_peak_deg_s,
        pose_deg: generated[..n].to_vec(),
    }
}

/// Feature frames of `seconds` of digital silence at `frame_rate_hz` (the analyzer run on
/// zeros, so they are the frames a silent input gives).
pub fn silence_frames(seconds: f64, frame_rate_hz: f64) -> Vec<FeatureFrame> {
    const RATE_HZ: f64 = 16_000.0;
    const BLOCK: usize = 4096;
    let config = AnalysisConfig {
        frame_rate_hz,
        ..AnalysisConfig::default()
    };
    let mut analyzer = Analyzer::new(config).expect("the default analysis settings are valid");
    analyzer
        .prepare(RATE_HZ, BLOCK)
        .expect("16 kHz is a supported rate");
    let zeros = vec![0.0f32; BLOCK];
    let mut frames = Vec::new();
    let mut left = (seconds * RATE_HZ) as usize;
    while left > 0 {
        let n = left.min(BLOCK);
        analyzer
            .process(&zeros[..n], |f| frames.push(*f))
            .expect("blocks within the prepared size");
        left -= n;
    }
    analyzer
        .finish(|f| frames.push(*f))
        .expect("a prepared analyzer finishes");
    frames
}

/// The peak angular speed of the generated head (°/s) over the first [`ONSET_WINDOW_S`] of
/// `clip`'s speech when the clip follows `silence` (frames of [`silence_frames`]): a jump from
/// the rest pose shows here. 0 when the clip has no voiced frame.
pub fn onset_peak_speed(
    model: &HeadModel,
    config: &HeadConfig,
    clip: &TrainingClip,
    silence: &[FeatureFrame],
) -> f64 {
    let Some(first) = clip.frames.iter().position(|f| f.voiced) else {
        return 0.0;
    };
    let rate = clip.frame_rate_hz;
    let mut frames = silence.to_vec();
    frames.extend_from_slice(&clip.frames);
    let pose = synthesize(model, config, &frames, rate);
    peak_speed_from(&pose, silence.len() + first, rate)
}

/// The peak angular speed (°/s) of `pose` at `frame_rate_hz` over [`ONSET_WINDOW_S`] from
/// frame `start` (the speed of frame i is the step from frame i − 1).
pub fn peak_speed_from(pose: &[[f64; 3]], start: usize, frame_rate_hz: f64) -> f64 {
    let end = (start + (ONSET_WINDOW_S * frame_rate_hz) as usize).min(pose.len());
    (start.max(1)..end)
        .map(|i| {
            let d: f64 = (0..3).map(|k| (pose[i][k] - pose[i - 1][k]).powi(2)).sum();
            d.sqrt() * frame_rate_hz
        })
        .fold(0.0, f64::max)
}

/// The mean angles (roll, pitch, yaw) of the head over `silence` when it follows `speech`
/// (frames of a clip; empty for a silence from the start of a stream), degrees. After speech
/// the silence starts from wherever the speech left the head and with the speaker's pause
/// level, which a silence from the start of a stream (at rest from its first frame) never
/// tests.
pub fn silence_posture(
    model: &HeadModel,
    config: &HeadConfig,
    speech: &[FeatureFrame],
    silence: &[FeatureFrame],
    frame_rate_hz: f64,
) -> [f64; 3] {
    let mut frames = speech.to_vec();
    frames.extend_from_slice(silence);
    let pose = synthesize(model, config, &frames, frame_rate_hz);
    motion_stats(&pose[speech.len()..], frame_rate_hz).mean_deg
}
