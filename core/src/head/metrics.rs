//! Motion statistics for evaluating head motion against real motion: canonical correlation of
//! the three head angles with f0, per-axis standard deviation, mean angular speed and the share
//! of frozen frames.

use glam::{DMat3, DVec3};

/// A frame counts as frozen when the head's angular speed is below this, degrees per second.
pub const FROZEN_SPEED_DEG_S: f64 = 1.0;

/// The canonical correlation between the 3-D head pose and a 1-D signal, which is the multiple
/// correlation of the signal regressed on the three angles, 0..1. `mask` selects frames (e.g.
/// voiced ones); 0 when fewer than 10 frames or a constant input.
pub fn cca_pose_signal(pose: &[[f64; 3]], signal: &[f64], mask: Option<&[bool]>) -> f64 {
    let n = pose.len().min(signal.len());
    let take = |i: usize| mask.is_none_or(|m| m.get(i).copied().unwrap_or(false));
    let mut cnt = 0.0;
    let mut mx = DVec3::ZERO;
    let mut my = 0.0;
    for i in (0..n).filter(|&i| take(i)) {
        cnt += 1.0;
        mx += DVec3::from_array(pose[i]);
        my += signal[i];
    }
    if cnt < 10.0 {
        return 0.0;
    }
    mx /= cnt;
    my /= cnt;
    let mut cxx = DMat3::ZERO;
    let mut cxy = DVec3::ZERO;
    let mut vy = 0.0;
    for i in (0..n).filter(|&i| take(i)) {
        let x = DVec3::from_array(pose[i]) - mx;
        let y = signal[i] - my;
        cxx += DMat3::from_cols(x * x.x, x * x.y, x * x.z);
        cxy += x * y;
        vy += y * y;
    }
    if vy <= 0.0 {
        return 0.0;
    }
    // A tiny ridge keeps a frozen axis from making the matrix singular.
    let ridge = 1e-9 * (cxx.x_axis.x + cxx.y_axis.y + cxx.z_axis.z) + 1e-300;
    let cxx = cxx + DMat3::from_diagonal(DVec3::splat(ridge));
    if cxx.determinant().abs() < 1e-300 {
        return 0.0;
    }
    let r2 = cxy.dot(cxx.inverse() * cxy) / vy;
    r2.clamp(0.0, 1.0).sqrt()
}

/// Summary of a motion: per-axis SD (roll, pitch, yaw), degrees; mean angular speed, °/s;
/// share of frozen frames (speed below [`FROZEN_SPEED_DEG_S`]), 0..1.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotionStats {
    /// Standard deviation per axis (roll, pitch, yaw), degrees.
    pub sd_deg: [f64; 3],
    /// Mean angular speed |Δθ|·rate, degrees per second.
    pub mean_speed_deg_s: f64,
    /// Share of frames whose speed is below [`FROZEN_SPEED_DEG_S`], 0..1.
    pub frozen_share: f64,
}

/// Statistics of `pose` sampled at `frame_rate_hz`.
pub fn motion_stats(pose: &[[f64; 3]], frame_rate_hz: f64) -> MotionStats {
    let n = pose.len();
    if n < 2 {
        return MotionStats::default();
    }
    let mut mean = [0.0; 3];
    for p in pose {
        for k in 0..3 {
            mean[k] += p[k] / n as f64;
        }
    }
    let mut sd = [0.0; 3];
    for p in pose {
        for k in 0..3 {
            sd[k] += (p[k] - mean[k]).powi(2) / n as f64;
        }
    }
    let mut speed_sum = 0.0;
    let mut frozen = 0usize;
    for w in pose.windows(2) {
        let d = DVec3::from_array(w[1]) - DVec3::from_array(w[0]);
        let s = d.length() * frame_rate_hz;
        speed_sum += s;
        if s < FROZEN_SPEED_DEG_S {
            frozen += 1;
        }
    }
    MotionStats {
        sd_deg: sd.map(f64::sqrt),
        mean_speed_deg_s: speed_sum / (n - 1) as f64,
        frozen_share: frozen as f64 / (n - 1) as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cca_is_one_for_a_linear_combination_and_small_for_noise() {
        let mut rng = crate::rng::SeededRng::new(3);
        let pose: Vec<[f64; 3]> = (0..2000)
            .map(|_| [rng.normal(), rng.normal(), rng.normal()])
            .collect();
        let y: Vec<f64> = pose.iter().map(|p| 2.0 * p[0] - p[2]).collect();
        assert!((cca_pose_signal(&pose, &y, None) - 1.0).abs() < 1e-6);
        let noise: Vec<f64> = (0..2000).map(|_| rng.normal()).collect();
        assert!(cca_pose_signal(&pose, &noise, None) < 0.1);
        // Half signal, half noise: R = 1/√2 for the multiple correlation.
        let mixed: Vec<f64> = pose.iter().zip(&noise).map(|(p, e)| p[1] + e).collect();
        let r = cca_pose_signal(&pose, &mixed, None);
        assert!((r - 0.5f64.sqrt()).abs() < 0.05, "{r}");
    }

    #[test]
    fn stats_of_a_constant_speed_ramp() {
        let pose: Vec<[f64; 3]> = (0..101).map(|i| [0.0, i as f64 * 0.1, 0.0]).collect();
        let s = motion_stats(&pose, 100.0);
        assert!((s.mean_speed_deg_s - 10.0).abs() < 1e-9);
        assert_eq!(s.frozen_share, 0.0);
        assert_eq!(s.sd_deg[0], 0.0);
        let still = vec![[1.0, 2.0, 3.0]; 50];
        assert_eq!(motion_stats(&still, 30.0).frozen_share, 1.0);
    }
}
