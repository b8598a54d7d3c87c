//! How far real heads miss the per-clip targets against one another: the scale beside two of
//! [`super::targets`]' limits, measured on the clips' real motion alone (no model involved).
//!
//! - SD: another clip's real motion, taken as if it were generated for this clip, gives an SD
//!   ratio per axis (other / this); [`sd_ratios_within`] counts those inside
//!   [`CLIP_RATIO`](super::targets::CLIP_RATIO), per axis and per clip pair (all three axes).
//! - Posture: every real clip's angles average 0 over the whole clip (each is taken around
//!   its own mean pose), but not over a stretch as long as a shorter clip.
//!   [`window_means_within`] counts the windows of other clips' real motion, each as long as
//!   the clip judged, whose mean lies within
//!   [`MAX_MEAN_ANGLE_DEG`](super::targets::MAX_MEAN_ANGLE_DEG) on every axis.
//!
//! A generated head cannot know from the voice which axis a speaker favours or where they
//! happen to look for the few seconds of a short clip; when real heads miss a limit against one
//! another this often, a miss there says little about the model.

use super::features::TrainingClip;
use super::metrics::motion_stats;
use super::targets::{CLIP_RATIO, MAX_MEAN_ANGLE_DEG};

/// A count out of a total.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Share {
    /// Items meeting the limit.
    pub within: usize,
    /// Items judged.
    pub total: usize,
}

impl Share {
    /// `within / total` (0 when nothing was judged).
    pub fn fraction(&self) -> f64 {
        self.within as f64 / self.total.max(1) as f64
    }
}

/// Over every ordered pair of different clips (other, this): (axes whose SD ratio other / this
/// lies in `CLIP_RATIO`, pairs whose three axes all do).
pub fn sd_ratios_within(clips: &[TrainingClip]) -> (Share, Share) {
    let sds: Vec<[f64; 3]> = clips
        .iter()
        .map(|c| motion_stats(&c.pose_deg, c.frame_rate_hz).sd_deg)
        .collect();
    let (mut axes, mut pairs) = (Share::default(), Share::default());
    for (i, this) in sds.iter().enumerate() {
        for (j, other) in sds.iter().enumerate() {
            if i == j {
                continue;
            }
            let within = (0..3)
                .filter(|&k| this[k] > 0.0 && CLIP_RATIO.contains(&(other[k] / this[k])))
                .count();
            axes.within += within;
            axes.total += 3;
            pairs.within += usize::from(within == 3);
            pairs.total += 1;
        }
    }
    (axes, pairs)
}

/// For each clip, the windows of every other clip's real motion as long as it (one window per
/// second of the other clip, at its frame rate): those whose mean angle lies within
/// `MAX_MEAN_ANGLE_DEG` on every axis. Other clips shorter than the clip give no window.
pub fn window_means_within(clips: &[TrainingClip]) -> Share {
    let mut share = Share::default();
    for (i, this) in clips.iter().enumerate() {
        let n = this.pose_deg.len();
        for (j, other) in clips.iter().enumerate() {
            if i == j || n == 0 || other.pose_deg.len() < n {
                continue;
            }
            let step = (other.frame_rate_hz.round() as usize).max(1);
            for start in (0..=other.pose_deg.len() - n).step_by(step) {
                let window = &other.pose_deg[start..start + n];
                let within = (0..3).all(|k| {
                    (window.iter().map(|p| p[k]).sum::<f64>() / n as f64).abs()
                        <= MAX_MEAN_ANGLE_DEG
                });
                share.within += usize::from(within);
                share.total += 1;
            }
        }
    }
    share
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clip(name: &str, pose_deg: Vec<[f64; 3]>) -> TrainingClip {
        TrainingClip {
            name: name.into(),
            frame_rate_hz: 2.0,
            frames: Vec::new(),
            pose_deg,
        }
    }

    /// A clip alternating ±`amp_deg` per axis (SD = amp), `n` frames.
    fn square(name: &str, amp_deg: [f64; 3], n: usize) -> TrainingClip {
        let pose = (0..n)
            .map(|i| {
                let s = if i % 2 == 0 { 1.0 } else { -1.0 };
                amp_deg.map(|a| s * a)
            })
            .collect();
        clip(name, pose)
    }

    #[test]
    fn sd_ratios_count_axes_and_whole_pairs_inside_the_clip_band() {
        // a against b: ratios 1.5 and 1/1.5 on roll (inside ×0.6–×1.6), 2 and 0.5 on pitch
        // (outside), 1 on yaw (inside).
        let a = square("a", [3.0, 4.0, 2.0], 8);
        let b = square("b", [2.0, 2.0, 2.0], 8);
        let (axes, pairs) = sd_ratios_within(&[a.clone(), b.clone()]);
        assert_eq!(
            axes,
            Share {
                within: 4,
                total: 6
            }
        );
        assert_eq!(
            pairs,
            Share {
                within: 0,
                total: 2
            }
        );
        let c = square("c", [2.5, 3.0, 2.0], 8);
        let (_, pairs) = sd_ratios_within(&[a, c]);
        assert_eq!(
            pairs,
            Share {
                within: 2,
                total: 2
            }
        );
    }

    #[test]
    fn window_means_see_a_head_that_looks_one_way_then_the_other() {
        // Six frames at 2 Hz: +2° for three, −2° for three (mean 0 over the clip). Windows two
        // frames long start every 2 frames: [+2, +2], [+2, −2], [−2, −2]: only the middle one
        // averages within 1°.
        let long = clip(
            "long",
            (0..6)
                .map(|i| if i < 3 { [2.0; 3] } else { [-2.0; 3] })
                .collect(),
        );
        let short = clip("short", vec![[0.0; 3]; 2]);
        let share = window_means_within(&[short, long]);
        assert_eq!(
            share,
            Share {
                within: 1,
                total: 3
            }
        );
        assert!((share.fraction() - 1.0 / 3.0).abs() < 1e-12);
    }
}
