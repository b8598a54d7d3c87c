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
//! the scale unchanged, so a hold stays a hold.
//!
//! That feed-forward scale alone lands the output's mean speed some way off the target, by as
//! much as the voice's motion is bursty and by how often the scale sits at its clamp (on the
//! styletalk clips, 0.84 to 1.0 of the target: a different figure for each voice and for each
//! version of the pitch front end). So the governor also measures its own output's speed (a
//! one-pole mean over [`OUT_TIME_S`]) and integrates the relative error `1 − mean / target` into
//! a correction factor (integration time [`CORRECTION_TIME_S`], at most [`MAX_CORRECTION`]
//! either way), which drives the output's mean speed, not the log of it, to the target.
//!
//! Training sets the target and chooses the time constant on the training clips only (see
//! [`super::train::calibrate_motion`]). Allocation-free; a target of 0 turns the governor off.

use glam::DVec3;

/// Smallest scale the governor applies.
pub const MIN_SCALE: f64 = 0.25;
/// Largest scale the governor applies (kept low so a long still pause cannot make the first
/// motion after it jump).
pub const MAX_SCALE: f64 = 2.0;
/// Weight of the target in the running mean at the start, seconds of motion.
pub const PRIOR_S: f64 = 1.0;

/// The governor's state for one stream.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedGovernor {
    target_deg_s: f64,
    time_s: f64,
    mean_speed_deg_s: f64,
    frames: f64,
    prev: Option<DVec3>,
    mean_out_deg_s: f64,
    log_correction: f64,
    prev_out: Option<DVec3>,
}

/// Time constant of the running mean of the governed output's speed, seconds.
pub const OUT_TIME_S: f64 = 1.0;
/// Integration time of the correction toward the target, seconds: a relative error held for
/// this long moves the log of the correction by that error. Four times [`OUT_TIME_S`], which
/// damps the loop (the measured speed lags the correction by about `OUT_TIME_S`).
pub const CORRECTION_TIME_S: f64 = 4.0;
/// Largest correction either way (a factor).
pub const MAX_CORRECTION: f64 = 2.0;

impl SpeedGovernor {
    /// A governor toward `target_deg_s` (°/s; 0 = off) averaging over `time_s` seconds.
    pub fn new(target_deg_s: f64, time_s: f64) -> SpeedGovernor {
        SpeedGovernor {
            target_deg_s,
            time_s,
            mean_speed_deg_s: target_deg_s,
            frames: 0.0,
            prev: None,
            mean_out_deg_s: target_deg_s,
            log_correction: 0.0,
            prev_out: None,
        }
    }

    /// Back to the start (no motion seen yet).
    pub fn reset(&mut self) {
        *self = SpeedGovernor::new(self.target_deg_s, self.time_s);
    }

    /// The governed pose for the ungoverned `pose` of the next frame at `frame_rate_hz`.
    pub fn apply(&mut self, pose: DVec3, frame_rate_hz: f64) -> DVec3 {
        if self.target_deg_s <= 0.0 || !pose.is_finite() {
            return pose;
        }
        // A held pose stays held exactly: the same output, no update.
        if self.prev == Some(pose) {
            if let Some(out) = self.prev_out {
                return out;
            }
        }
        if let Some(prev) = self.prev {
            let speed = (pose - prev).length() * frame_rate_hz;
            let prior = PRIOR_S * frame_rate_hz;
            let a = (-1.0 / (frame_rate_hz * self.time_s))
                .exp()
                .min((self.frames + prior) / (self.frames + prior + 1.0));
            self.mean_speed_deg_s = a * self.mean_speed_deg_s + (1.0 - a) * speed;
            self.frames += 1.0;
        }
        self.prev = Some(pose);
        let out = pose * self.scale();
        if let Some(prev_out) = self.prev_out {
            self.correct((out - prev_out).length() * frame_rate_hz, frame_rate_hz);
        }
        self.prev_out = Some(out);
        out
    }

    /// Feeds the governed output's latest speed to the correction: its running mean's relative
    /// error from the target, integrated over [`CORRECTION_TIME_S`], is the log of the
    /// correction factor.
    fn correct(&mut self, out_speed_deg_s: f64, frame_rate_hz: f64) {
        let a = (-1.0 / (frame_rate_hz * OUT_TIME_S)).exp();
        self.mean_out_deg_s = a * self.mean_out_deg_s + (1.0 - a) * out_speed_deg_s;
        let error = 1.0 - self.mean_out_deg_s / self.target_deg_s;
        let limit = MAX_CORRECTION.ln();
        self.log_correction = (self.log_correction + error / (frame_rate_hz * CORRECTION_TIME_S))
            .clamp(-limit, limit);
    }

    /// The scale applied to the latest pose.
    pub fn scale(&self) -> f64 {
        if self.target_deg_s <= 0.0 {
            return 1.0;
        }
        (self.log_correction.exp() * self.target_deg_s / self.mean_speed_deg_s.max(1e-9))
            .clamp(MIN_SCALE, MAX_SCALE)
    }
}

/// Runs a fresh governor over a whole pose track (roll, pitch, yaw per frame).
pub fn govern_track(
    pose: &[[f64; 3]],
    frame_rate_hz: f64,
    target_deg_s: f64,
    time_s: f64,
) -> Vec<[f64; 3]> {
    let mut g = SpeedGovernor::new(target_deg_s, time_s);
    pose.iter()
        .map(|p| g.apply(DVec3::from_array(*p), frame_rate_hz).to_array())
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
            let out = govern_track(&raw, 120.0, 18.0, 2.0);
            // Judge the last 50 s, after the running mean has settled.
            let got = motion_stats(&out[1200..], 120.0).mean_speed_deg_s;
            let expected = (raw_speed * (18.0 / raw_speed).clamp(MIN_SCALE, MAX_SCALE)).max(0.0);
            assert!(
                (got / expected - 1.0).abs() < 0.1,
                "amp {amp} f {f}: raw {raw_speed:.1} °/s, governed {got:.1} °/s, expected {expected:.1}"
            );
        }
    }

    /// Phrases of a wide sway (`loud_deg`, `phrase_s` long) between pauses of a faint one
    /// (`quiet_deg`, `pause_s`), 60 s at 120 frames per second.
    fn phrases(loud_deg: f64, quiet_deg: f64, phrase_s: f64, pause_s: f64) -> Vec<[f64; 3]> {
        (0..7200)
            .map(|i| {
                let t = i as f64 / 120.0;
                let amp = if t % (phrase_s + pause_s) < phrase_s {
                    loud_deg
                } else {
                    quiet_deg
                };
                let w = std::f64::consts::TAU * 1.1 * t;
                [amp * w.sin(), 0.5 * amp * (1.3 * w).cos(), 0.0]
            })
            .collect()
    }

    #[test]
    fn bursty_motion_ends_on_the_target_speed_too() {
        // The feed-forward scale alone lands these at ×0.81–×0.95 of the target (the scale
        // climbs to its clamp in each pause and the next phrase starts too slow); the
        // correction brings every one within 4 %.
        for (loud, quiet, phrase_s, pause_s) in [(6.0, 0.1, 2.0, 2.0), (5.0, 0.5, 4.0, 3.0)] {
            let raw = phrases(loud, quiet, phrase_s, pause_s);
            for time_s in [0.5, 1.0] {
                let out = govern_track(&raw, 120.0, 18.0, time_s);
                let got = motion_stats(&out, 120.0).mean_speed_deg_s / 18.0;
                assert!(
                    (got - 1.0).abs() < 0.04,
                    "{loud}°/{quiet}° phrases {phrase_s} s, pauses {pause_s} s, time {time_s} s: \
                     ×{got:.3} of the target"
                );
            }
        }
    }

    #[test]
    fn off_keeps_the_pose_and_reset_restarts() {
        let raw = sway(4.0, 1.0);
        assert_eq!(govern_track(&raw, 120.0, 0.0, 2.0), raw);
        let mut g = SpeedGovernor::new(18.0, 2.0);
        let first: Vec<DVec3> = raw[..300]
            .iter()
            .map(|p| g.apply(DVec3::from_array(*p), 120.0))
            .collect();
        g.reset();
        let again: Vec<DVec3> = raw[..300]
            .iter()
            .map(|p| g.apply(DVec3::from_array(*p), 120.0))
            .collect();
        assert_eq!(first, again);
    }
}
