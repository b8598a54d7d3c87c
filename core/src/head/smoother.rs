//! Pose smoother: a causal one-pole low-pass on the generated pose, before the speed governor.
//!
//! The argmax follows every syllable's f0 and level, so its motion is busy: many small, fast
//! moves. The governor then scales the whole motion down until its mean speed is a real head's,
//! and the amplitude (SD) ends at about half of real. Smoothing first removes the busy part,
//! which carries much speed but little amplitude, so the governor scales down less and the SD
//! comes closer to real at the same mean speed. The cost is lag: a time constant τ delays slow
//! motion by about τ, so training only considers τ up to [`MAX_TIME_S`] and picks it on the
//! training clips (see [`super::train::calibrate_motion`]). τ = 0 passes the pose unchanged.
//! A held pose (the same input as the frame before, e.g. the unvoiced `hold` behaviour) holds the
//! output too, where the smoothing has brought it, as the governor does. Allocation-free.

use glam::DVec3;

/// Longest time constant training may choose, seconds: beyond it the head visibly trails the
/// voice.
pub const MAX_TIME_S: f64 = 0.25;

/// The smoother's state for one stream.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseSmoother {
    time_s: f64,
    /// (last input, last output).
    state: Option<(DVec3, DVec3)>,
}

impl PoseSmoother {
    /// A smoother with time constant `time_s` seconds (0 = off).
    pub fn new(time_s: f64) -> PoseSmoother {
        PoseSmoother {
            time_s,
            state: None,
        }
    }

    /// Back to the start (the next pose passes unchanged).
    pub fn reset(&mut self) {
        self.state = None;
    }

    /// The smoothed pose for the next frame's `pose` at `frame_rate_hz`.
    pub fn apply(&mut self, pose: DVec3, frame_rate_hz: f64) -> DVec3 {
        if self.time_s <= 0.0 || !pose.is_finite() {
            return pose;
        }
        let a = (-1.0 / (frame_rate_hz * self.time_s)).exp();
        let next = match self.state {
            Some((input, out)) if input == pose => out,
            Some((_, out)) => out * a + pose * (1.0 - a),
            None => pose,
        };
        self.state = Some((pose, next));
        next
    }
}

/// Runs a fresh smoother over a whole pose track (roll, pitch, yaw per frame).
pub fn smooth_track(pose: &[[f64; 3]], frame_rate_hz: f64, time_s: f64) -> Vec<[f64; 3]> {
    let mut s = PoseSmoother::new(time_s);
    pose.iter()
        .map(|p| s.apply(DVec3::from_array(*p), frame_rate_hz).to_array())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::head::metrics::motion_stats;

    /// A slow sway (0.3 Hz, 4°) plus a busy wobble (6 Hz, 1°) on every axis, 30 s at 120 fps.
    fn busy_sway() -> Vec<[f64; 3]> {
        (0..3600)
            .map(|i| {
                let t = i as f64 / 120.0;
                let v = 4.0 * (std::f64::consts::TAU * 0.3 * t).sin()
                    + (std::f64::consts::TAU * 6.0 * t).sin();
                [v, v, v]
            })
            .collect()
    }

    #[test]
    fn smoothing_cuts_speed_far_more_than_amplitude() {
        let raw = busy_sway();
        let smooth = smooth_track(&raw, 120.0, 0.1);
        let (r, s) = (motion_stats(&raw, 120.0), motion_stats(&smooth, 120.0));
        let speed_kept = s.mean_speed_deg_s / r.mean_speed_deg_s;
        let sd_kept = s.sd_deg[0] / r.sd_deg[0];
        // The 6 Hz wobble dominates the speed and is cut; the 0.3 Hz sway carries the SD.
        assert!(speed_kept < 0.6, "speed kept ×{speed_kept:.2}");
        assert!(sd_kept > 0.9, "SD kept ×{sd_kept:.2}");
    }

    #[test]
    fn a_held_pose_holds_the_output() {
        let mut s = PoseSmoother::new(0.1);
        let a = s.apply(DVec3::ZERO, 120.0);
        let b = s.apply(DVec3::ONE, 120.0);
        assert!(b != a && b != DVec3::ONE);
        assert_eq!(s.apply(DVec3::ONE, 120.0), b);
        assert!(s.apply(DVec3::splat(2.0), 120.0) != b);
    }

    #[test]
    fn zero_time_passes_the_pose_and_reset_restarts() {
        let raw = busy_sway();
        assert_eq!(smooth_track(&raw, 120.0, 0.0), raw);
        let mut s = PoseSmoother::new(0.2);
        let first: Vec<DVec3> = raw[..50]
            .iter()
            .map(|p| s.apply(DVec3::from_array(*p), 120.0))
            .collect();
        s.reset();
        let again: Vec<DVec3> = raw[..50]
            .iter()
            .map(|p| s.apply(DVec3::from_array(*p), 120.0))
            .collect();
        assert_eq!(first, again);
        assert_eq!(first[0], DVec3::from_array(raw[0]));
        assert_ne!(first[10], DVec3::from_array(raw[10]));
    }
}
