//! Speed governor: keeps the generated head motion's mean angular speed near a target.
//!
//! The argmax synthesis moves as much as the voice's f0 and level make its densities' modes move,
//! so an expressive voice (wide f0 swings) gets a head that moves two to three times faster than
//! real speakers' heads, a flat voice a slower one; real speakers' mean speeds lie much closer
//! together (14–22 °/s on the styletalk clips). The governor scales the pose by
//! `target / running mean speed` (clamped to [`MIN_SCALE`]..[`MAX_SCALE`]), so each voice's
//! motion keeps its shape and timing (and so its correlation with f0) at a believable speed.
//!
//! The running mean is a one-pole average of the ungoverned speed with time constant `time_s`,
//! started from the target with the weight of [`PRIOR_S`] seconds of motion (so the first
//! seconds neither jump nor stall); frames whose pose did not change (a held head) leave it and
//! the scale unchanged, so a hold stays a hold. So do frames more than [`PAUSE_HOLD_S`] into an
//! unvoiced stretch: a pause's slow motion (a damped return to neutral, the loudness model
//! settling) would pull the mean down and the scale up to [`MAX_SCALE`], and the head would
//! move two to three times too fast for the first seconds after the pause. Training calibrates
//! the target and chooses the time constant on the training clips only (see
//! [`super::train::calibrate_motion`]). Allocation-free; a target of 0 turns the governor off.

use glam::DVec3;

/// Smallest scale the governor applies.
pub const MIN_SCALE: f64 = 0.25;
/// Largest scale the governor applies (kept low so a long still pause cannot make the first
/// motion after it jump).
pub const MAX_SCALE: f64 = 2.0;
/// Weight of the target in the running mean at the start, seconds of motion.
pub const PRIOR_S: f64 = 1.0;
/// Unvoiced time after which the running mean (and so the scale) holds until the voice is
/// back, seconds: longer than the gaps of consonants and short breaks inside a phrase.
pub const PAUSE_HOLD_S: f64 = 0.25;

/// The governor's state for one stream.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedGovernor {
    target_deg_s: f64,
    time_s: f64,
    mean_speed_deg_s: f64,
    frames: f64,
    prev: Option<DVec3>,
    unvoiced_s: f64,
}

impl SpeedGovernor {
    /// A governor toward `target_deg_s` (°/s; 0 = off) averaging over `time_s` seconds.
    pub fn new(target_deg_s: f64, time_s: f64) -> SpeedGovernor {
        SpeedGovernor {
            target_deg_s,
            time_s,
            mean_speed_deg_s: target_deg_s,
            frames: 0.0,
            prev: None,
            unvoiced_s: 0.0,
        }
    }

    /// Back to the start (no motion seen yet).
    pub fn reset(&mut self) {
        *self = SpeedGovernor::new(self.target_deg_s, self.time_s);
    }

    /// The governed pose for the ungoverned `pose` of the next frame at `frame_rate_hz`,
    /// `voiced` when the frame is.
    pub fn apply(&mut self, pose: DVec3, voiced: bool, frame_rate_hz: f64) -> DVec3 {
        if self.target_deg_s <= 0.0 || !pose.is_finite() {
            return pose;
        }
        // Counted up to just past the hold (no growth without end in a long silence).
        self.unvoiced_s = if voiced {
            0.0
        } else {
            (self.unvoiced_s + 1.0 / frame_rate_hz).min(2.0 * PAUSE_HOLD_S)
        };
        let paused = self.unvoiced_s > PAUSE_HOLD_S;
        // A held pose stays held exactly, and a pause leaves the mean as speech left it: no
        // update, the same scale.
        if let Some(prev) = self.prev.filter(|p| *p != pose && !paused) {
            let speed = (pose - prev).length() * frame_rate_hz;
            let prior = PRIOR_S * frame_rate_hz;
            let a = (-1.0 / (frame_rate_hz * self.time_s))
                .exp()
                .min((self.frames + prior) / (self.frames + prior + 1.0));
            self.mean_speed_deg_s = a * self.mean_speed_deg_s + (1.0 - a) * speed;
            self.frames += 1.0;
        }
        self.prev = Some(pose);
        pose * self.scale()
    }

    /// The scale applied to the latest pose.
    pub fn scale(&self) -> f64 {
        if self.target_deg_s <= 0.0 {
            return 1.0;
        }
        (self.target_deg_s / self.mean_speed_deg_s.max(1e-9)).clamp(MIN_SCALE, MAX_SCALE)
    }
}

/// Runs a fresh governor over a whole pose track (roll, pitch, yaw per frame) whose frames
/// are voiced where `voiced` says (as long as `pose`).
pub fn govern_track(
    pose: &[[f64; 3]],
    voiced: &[bool],
    frame_rate_hz: f64,
    target_deg_s: f64,
    time_s: f64,
) -> Vec<[f64; 3]> {
    assert_eq!(pose.len(), voiced.len(), "one voiced flag per pose");
    let mut g = SpeedGovernor::new(target_deg_s, time_s);
    pose.iter()
        .zip(voiced)
        .map(|(p, v)| g.apply(DVec3::from_array(*p), *v, frame_rate_hz).to_array())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::head::metrics::motion_stats;

    /// A sway of `amp_deg` at `f_hz` on two axes, 60 s at 120 frames per second.
    fn sway(amp_deg: f64, f_hz: f64) -> Vec<[f64; 3]> {
        (0..7200)
            .map(|i| {
                let t = i as f64 / 120.0;
                let w = std::f64::consts::TAU * f_hz * t;
                [amp_deg * w.sin(), 0.5 * amp_deg * (1.3 * w).cos(), 0.0]
            })
            .collect()
    }

    #[test]
    fn fast_and_slow_motion_both_end_near_the_target_speed() {
        for (amp, f) in [(6.0, 1.5), (1.0, 0.7), (3.0, 1.0)] {
            let raw = sway(amp, f);
            let raw_speed = motion_stats(&raw, 120.0).mean_speed_deg_s;
            let out = govern_track(&raw, &[true; 7200], 120.0, 18.0, 2.0);
            // Judge the last 50 s, after the running mean has settled.
            let got = motion_stats(&out[1200..], 120.0).mean_speed_deg_s;
            let expected = (raw_speed * (18.0 / raw_speed).clamp(MIN_SCALE, MAX_SCALE)).max(0.0);
            assert!(
                (got / expected - 1.0).abs() < 0.1,
                "amp {amp} f {f}: raw {raw_speed:.1} °/s, governed {got:.1} °/s, expected {expected:.1}"
            );
        }
    }

    #[test]
    fn a_pause_holds_the_scale_and_a_short_gap_does_not() {
        let raw = sway(4.0, 1.0);
        let mut g = SpeedGovernor::new(18.0, 2.0);
        for p in &raw[..1200] {
            g.apply(DVec3::from_array(*p), true, 120.0);
        }
        // Then 5 s unvoiced: a slow glide toward neutral (1 s time constant).
        let last = DVec3::from_array(raw[1199]);
        let glide = |k: usize| last * (-(k as f64) / 120.0).exp();
        let scales: Vec<f64> = (1..=600)
            .map(|k| {
                g.apply(glide(k), false, 120.0);
                g.scale()
            })
            .collect();
        // Frames 1–25 (under 0.25 s) still count; from frame 35 on the scale holds.
        assert!(
            scales[..25].windows(2).all(|w| w[1] > w[0]),
            "a short unvoiced gap counts: {:?}",
            &scales[..25]
        );
        assert!(
            scales[34..].iter().all(|s| *s == scales[34]),
            "the scale holds in a pause: {} … {}",
            scales[34],
            scales[599]
        );
        // A reset in the pause starts the unvoiced time again: the next frames count.
        g.reset();
        let fresh = g.scale();
        g.apply(glide(601), false, 120.0);
        g.apply(glide(602), false, 120.0);
        assert!(
            g.scale() > fresh,
            "after a reset, {} against {fresh}",
            g.scale()
        );
    }

    #[test]
    fn off_keeps_the_pose_and_reset_restarts() {
        let raw = sway(4.0, 1.0);
        assert_eq!(govern_track(&raw, &[true; 7200], 120.0, 0.0, 2.0), raw);
        let mut g = SpeedGovernor::new(18.0, 2.0);
        let first: Vec<DVec3> = raw[..300]
            .iter()
            .map(|p| g.apply(DVec3::from_array(*p), true, 120.0))
            .collect();
        g.reset();
        let again: Vec<DVec3> = raw[..300]
            .iter()
            .map(|p| g.apply(DVec3::from_array(*p), true, 120.0))
            .collect();
        assert_eq!(first, again);
    }
}
