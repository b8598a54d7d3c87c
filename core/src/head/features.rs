//! Training features: head motion resampled to the feature frame clock, poses taken around the
//! speaker's mean pose, velocity |Δθ| in °/s and acceleration |Δ²θ| in °/s², paired with the
//! speaker-normalised f0 (semitones) and level (dB) of each frame.

use super::gmm::MAX_DIM;
use super::inputs::ModelInput;
use super::model_file::Normalisation;
use crate::analysis::FeatureFrame;

/// One clip of training or evaluation data: feature frames and the real head pose on the same
/// frame clock.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainingClip {
    /// Clip name (file stem).
    pub name: String,
    /// Frame rate of `frames` and `pose_deg`, Hz.
    pub frame_rate_hz: f64,
    /// Analysis frames of the clip's audio.
    pub frames: Vec<FeatureFrame>,
    /// Real head pose per frame as (roll, pitch, yaw) degrees around the clip's mean pose;
    /// as long as `frames` (frames past the end of the motion are dropped from `frames`).
    pub pose_deg: Vec<[f64; 3]>,
}

/// Head motion as recorded: times and angles (degrees) at any rate.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MotionTrack {
    /// Sample times, seconds, increasing.
    pub time_s: Vec<f64>,
    /// (roll, pitch, yaw) in degrees per sample.
    pub pose_deg: Vec<[f64; 3]>,
}

impl MotionTrack {
    /// The pose at time `t_s` by Catmull–Rom interpolation (smooth velocity and finite
    /// acceleration, unlike linear interpolation); `None` outside the recorded span.
    pub fn at(&self, t_s: f64) -> Option<[f64; 3]> {
        let n = self.time_s.len();
        if n < 2 || !(t_s >= self.time_s[0] && t_s <= self.time_s[n - 1]) {
            return None;
        }
        let i = match self.time_s.partition_point(|&x| x <= t_s) {
            0 => 0,
            p => (p - 1).min(n - 2),
        };
        let (t1, t2) = (self.time_s[i], self.time_s[i + 1]);
        let u = if t2 > t1 { (t_s - t1) / (t2 - t1) } else { 0.0 };
        let p0 = self.pose_deg[i.saturating_sub(1)];
        let p1 = self.pose_deg[i];
        let p2 = self.pose_deg[i + 1];
        let p3 = self.pose_deg[(i + 2).min(n - 1)];
        let mut out = [0.0; 3];
        for k in 0..3 {
            let (a, b, c, d) = (p0[k], p1[k], p2[k], p3[k]);
            out[k] = 0.5
                * (2.0 * b
                    + (-a + c) * u
                    + (2.0 * a - 5.0 * b + 4.0 * c - d) * u * u
                    + (-a + 3.0 * b - 3.0 * c + d) * u * u * u);
        }
        Some(out)
    }
}

impl TrainingClip {
    /// Pairs analysis frames with a motion track: keeps the frames inside the motion's span,
    /// resamples the pose to them and removes the clip's mean pose.
    pub fn from_motion(
        name: &str,
        frame_rate_hz: f64,
        frames: &[FeatureFrame],
        motion: &MotionTrack,
    ) -> TrainingClip {
        let mut kept = Vec::with_capacity(frames.len());
        let mut pose = Vec::with_capacity(frames.len());
        for f in frames {
            if let Some(p) = motion.at(f.time_s) {
                kept.push(*f);
                pose.push(p);
            }
        }
        let n = pose.len().max(1) as f64;
        let mut mean = [0.0; 3];
        for p in &pose {
            for k in 0..3 {
                mean[k] += p[k] / n;
            }
        }
        for p in &mut pose {
            for k in 0..3 {
                p[k] -= mean[k];
            }
        }
        TrainingClip {
            name: name.to_string(),
            frame_rate_hz,
            frames: kept,
            pose_deg: pose,
        }
    }
}

/// Training rows of one clip: for each motion feature (roll, pitch, yaw, velocity,
/// acceleration) the voiced rows (feature, f0, level) and unvoiced rows (feature, level), with
/// f0 and level the model's inputs ([`super::inputs`]). The first two frames (no acceleration
/// yet) are skipped.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FeatureRows {
    /// Voiced rows per motion feature.
    pub voiced: [Vec<[f64; MAX_DIM]>; 5],
    /// Unvoiced rows per motion feature.
    pub unvoiced: [Vec<[f64; MAX_DIM]>; 5],
}

impl FeatureRows {
    /// Appends the rows of `clip` (inputs as a model with `norm` reads them). The pose is first
    /// smoothed by a Gaussian of SD `smoothing_s` seconds (0 = none), which removes the tracking
    /// jitter that would otherwise dominate the acceleration; the pose rows are taken around the
    /// mean pose of their voicing class.
    pub fn add_clip(&mut self, clip: &TrainingClip, norm: &Normalisation, smoothing_s: f64) {
        let r = clip.frame_rate_hz;
        let pose = smooth_pose(&clip.pose_deg, smoothing_s * r);
        // The model's inputs, as the synthesis computes them over the stream.
        let mut tracker = norm.input_tracker();
        let inputs: Vec<ModelInput> = clip.frames.iter().map(|f| tracker.next(f, r)).collect();
        let n = pose.len().min(inputs.len());
        // The mean pose of voiced and of unvoiced frames, each taken out of its own rows: every
        // pose density then has the mean pose at its centre (the voiced model's output at the
        // mean input is the mean pose), whatever share of a clip is voiced.
        let mut class_mean = [[0.0; 3]; 2];
        let mut class_count = [0.0; 2];
        for t in 2..n {
            let c = usize::from(!inputs[t].voiced);
            for k in 0..3 {
                class_mean[c][k] += pose[t][k];
            }
            class_count[c] += 1.0;
        }
        for c in 0..2 {
            for k in 0..3 {
                class_mean[c][k] /= f64::max(class_count[c], 1.0);
            }
        }
        for t in 2..n {
            let x = inputs[t];
            let (p, p1, p2) = (pose[t], pose[t - 1], pose[t - 2]);
            let mut v2 = 0.0;
            let mut a2 = 0.0;
            for k in 0..3 {
                v2 += (p[k] - p1[k]).powi(2);
                a2 += (p[k] - 2.0 * p1[k] + p2[k]).powi(2);
            }
            let m = class_mean[usize::from(!x.voiced)];
            let feats = [
                p[0] - m[0],
                p[1] - m[1],
                p[2] - m[2],
                r * v2.sqrt(),
                r * r * a2.sqrt(),
            ];
            if x.voiced {
                for (rows, v) in self.voiced.iter_mut().zip(feats) {
                    rows.push([v, x.f0_st, x.level_db]);
                }
            } else {
                for (rows, v) in self.unvoiced.iter_mut().zip(feats) {
                    rows.push([v, x.level_db, 0.0]);
                }
            }
        }
    }
}

/// Share of the training inputs left outside the model's input range at each end.
pub const INPUT_TAIL_SHARE: f64 = 0.01;

impl FeatureRows {
    /// The range of an input over the rows (`pick` reads it from a row of the first motion
    /// feature, voiced or not, or skips the row): from the [`INPUT_TAIL_SHARE`] quantile to the
    /// 1 − [`INPUT_TAIL_SHARE`] one, widened to include 0 (the mean input). The model clamps its
    /// inputs to it, so it is never asked beyond its data (a linear density extrapolated to a
    /// deep silence gave poses of several degrees).
    pub fn input_range(&self, pick: impl Fn(&[f64; MAX_DIM], bool) -> Option<f64>) -> [f64; 2] {
        let mut v: Vec<f64> = self.voiced[0]
            .iter()
            .filter_map(|r| pick(r, true))
            .chain(self.unvoiced[0].iter().filter_map(|r| pick(r, false)))
            .collect();
        if v.is_empty() {
            return [0.0, 0.0];
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        [
            at(INPUT_TAIL_SHARE).min(0.0),
            at(1.0 - INPUT_TAIL_SHARE).max(0.0),
        ]
    }

    /// Clamps every row's inputs to `norm`'s ranges, as the synthesis clamps its inputs.
    pub fn clamp_inputs(&mut self, norm: &Normalisation) {
        let [f_lo, f_hi] = norm.f0_st_range;
        let [l_lo, l_hi] = norm.level_db_range;
        for r in self.voiced.iter_mut().flatten() {
            r[1] = r[1].clamp(f_lo, f_hi);
            r[2] = r[2].clamp(l_lo, l_hi);
        }
        for r in self.unvoiced.iter_mut().flatten() {
            r[1] = r[1].clamp(l_lo, l_hi);
        }
    }
}

/// Zero-phase Gaussian smoothing of a pose track (SD `sigma_frames` frames, kernel ±3 SD,
/// edges held); returns a copy when `sigma_frames` < 0.1.
pub fn smooth_pose(pose: &[[f64; 3]], sigma_frames: f64) -> Vec<[f64; 3]> {
    if sigma_frames.is_nan() || sigma_frames < 0.1 || pose.is_empty() {
        return pose.to_vec();
    }
    let half = (3.0 * sigma_frames).ceil() as isize;
    let kernel: Vec<f64> = (-half..=half)
        .map(|j| (-0.5 * (j as f64 / sigma_frames).powi(2)).exp())
        .collect();
    let sum: f64 = kernel.iter().sum();
    let n = pose.len() as isize;
    (0..n)
        .map(|i| {
            let mut acc = [0.0; 3];
            for (w, j) in kernel.iter().zip(-half..=half) {
                let p = pose[(i + j).clamp(0, n - 1) as usize];
                for k in 0..3 {
                    acc[k] += w / sum * p[k];
                }
            }
            acc
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catmull_rom_passes_through_samples_and_is_exact_on_lines() {
        let m = MotionTrack {
            time_s: (0..10).map(|i| i as f64 * 0.1).collect(),
            pose_deg: (0..10)
                .map(|i| [i as f64, 2.0 * i as f64, -(i as f64)])
                .collect(),
        };
        let p = m.at(0.3).unwrap();
        assert!((p[0] - 3.0).abs() < 1e-12);
        let q = m.at(0.45).unwrap();
        assert!(
            (q[1] - 9.0).abs() < 1e-9 && (q[2] + 4.5).abs() < 1e-9,
            "{q:?}"
        );
        assert!(m.at(1.0).is_none() && m.at(-0.01).is_none());
    }
}
