//! Motion statistics for evaluating head motion against real motion: canonical correlation of
//! the three head angles with f0, per-axis standard deviation, mean angular speed and the share
//! of frozen frames.

use glam::{DMat3, DVec3};

/// A frame counts as frozen when the head's angular speed is below this, degrees per second.
pub const FROZEN_SPEED_DEG_S: f64 = 1.0;

/// The smoothness figure counts angular-velocity power above this frequency, Hz.
pub const JERKY_ABOVE_HZ: f64 = 3.0;

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

/// Summary of a motion: per-axis mean and SD (roll, pitch, yaw), degrees; mean angular speed,
/// °/s; share of frozen frames (speed below [`FROZEN_SPEED_DEG_S`]), 0..1.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotionStats {
    /// Mean per axis (roll, pitch, yaw), degrees: the posture.
    pub mean_deg: [f64; 3],
    /// Standard deviation per axis (roll, pitch, yaw), degrees.
    pub sd_deg: [f64; 3],
    /// Mean angular speed |Δθ|·rate, degrees per second.
    pub mean_speed_deg_s: f64,
    /// Share of frames whose speed is below [`FROZEN_SPEED_DEG_S`], 0..1.
    pub frozen_share: f64,
    /// Share of the angular-velocity power above [`JERKY_ABOVE_HZ`], 0..1 (see
    /// [`power_share_above`]); lower is smoother.
    pub power_above_3hz: f64,
}

/// f0 as semitones above 100 Hz, the f0 signal the evaluation correlates head motion with: a
/// fixed reference, so the canonical correlation (which ignores offset and scale) measures the
/// coupling with log f0 itself. The running speaker median the synthesis reads (`f0_st`) moves
/// while it learns a new voice, and a slow drift like that correlates by chance with any slow
/// head motion (on a 10 s clip of a high voice, the real motion's CCA read 0.77 against 0.35).
pub fn f0_semitones(f0_hz: f64) -> f64 {
    12.0 * (f0_hz / 100.0).log2()
}

/// The median of `v` (0 when empty).
pub fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Mean angular speed |Δθ|·rate of `pose` sampled at `frame_rate_hz`, degrees per second (0
/// for fewer than two frames).
pub fn mean_speed(pose: &[[f64; 3]], frame_rate_hz: f64) -> f64 {
    if pose.len() < 2 {
        return 0.0;
    }
    let sum: f64 = pose
        .windows(2)
        .map(|w| (DVec3::from_array(w[1]) - DVec3::from_array(w[0])).length())
        .sum();
    sum * frame_rate_hz / (pose.len() - 1) as f64
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
        mean_deg: mean,
        sd_deg: sd.map(f64::sqrt),
        mean_speed_deg_s: speed_sum / (n - 1) as f64,
        frozen_share: frozen as f64 / (n - 1) as f64,
        power_above_3hz: power_share_above(pose, frame_rate_hz, JERKY_ABOVE_HZ),
    }
}

/// The share of angular-motion power above `cutoff_hz`: the angular velocity of each axis
/// (first differences × rate, mean removed) is transformed over the whole track, and the power
/// of the bins above the cutoff, summed over the three axes, is divided by the power of all
/// bins above 0 Hz. 0..1; 0 for tracks shorter than 4 frames or without motion.
pub fn power_share_above(pose: &[[f64; 3]], frame_rate_hz: f64, cutoff_hz: f64) -> f64 {
    let n = pose.len().saturating_sub(1);
    if n < 3 {
        return 0.0;
    }
    let fft = realfft::RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut input = fft.make_input_vec();
    let mut spectrum = fft.make_output_vec();
    let (mut above, mut all) = (0.0, 0.0);
    for k in 0..3 {
        for (x, w) in input.iter_mut().zip(pose.windows(2)) {
            *x = (w[1][k] - w[0][k]) * frame_rate_hz;
        }
        let mean = input.iter().sum::<f64>() / n as f64;
        input.iter_mut().for_each(|x| *x -= mean);
        fft.process(&mut input, &mut spectrum)
            .expect("buffers made by the plan");
        for (bin, c) in spectrum.iter().enumerate().skip(1) {
            let p = c.norm_sqr();
            all += p;
            if bin as f64 * frame_rate_hz / n as f64 > cutoff_hz {
                above += p;
            }
        }
    }
    if all > 0.0 {
        above / all
    } else {
        0.0
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
        assert!((s.mean_deg[1] - 5.0).abs() < 1e-9, "{:?}", s.mean_deg);
        let still = vec![[1.0, 2.0, 3.0]; 50];
        assert_eq!(motion_stats(&still, 30.0).frozen_share, 1.0);
    }

    #[test]
    fn power_share_splits_slow_and_fast_sways() {
        // 1 Hz sway of 4° on roll and a 6 Hz tremor of 0.5° on yaw, 10 s at 120 Hz. Velocity
        // amplitudes 2π·1·4 and 2π·6·0.5, so the power above 3 Hz is 3² / (4² + 3²) = 0.36.
        let pose: Vec<[f64; 3]> = (0..1201)
            .map(|i| {
                let t = i as f64 / 120.0;
                let w = std::f64::consts::TAU * t;
                [4.0 * w.sin(), 0.0, 0.5 * (6.0 * w).sin()]
            })
            .collect();
        let share = power_share_above(&pose, 120.0, 3.0);
        assert!((share - 0.36).abs() < 0.01, "{share}");
        let slow: Vec<[f64; 3]> = pose.iter().map(|p| [p[0], 0.0, 0.0]).collect();
        assert!(power_share_above(&slow, 120.0, 3.0) < 0.01);
        assert_eq!(power_share_above(&pose[..3], 120.0, 3.0), 0.0);
    }
}
