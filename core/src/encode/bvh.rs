//! BVH (Biovision hierarchy) encoder: head motion as a small skeleton that animation tools
//! (Blender, MotionBuilder, Maya) import.
//!
//! Skeleton, in metres (1.8 m to the top of the head, so Blender's importer, which takes BVH
//! units as metres, shows a person-sized figure at its default scale 1.0), Y up, the character
//! facing +Z (so +X is the character's left; right-handed): `Hips` (root, at 1 m height) →
//! `Chest` → `Neck` → `Head` → end site at the top of the head. From control frames
//! ([`push_control`]):
//! - `Chest`: the breathing reaches the chest as a small extension of the upper trunk with the
//!   thorax expansion, [`CHEST_PITCH_DEG_PER_THORAX`] degrees at full expansion (as the VMC
//!   rig's default `chest_pitch_deg` in `osc.rs`; a chosen
//!   visible amount, not a measured one; scale it in the rig if needed);
//! - `Neck`: the breathing neck pitch;
//! - `Head`: the head pose;
//! - `Hips` stay still: breathing hardly moves the pelvis, and a root motion would move the
//!   whole character.
//!
//! The root's `OFFSET` is 0 and its position channels hold the hips' place, (0, 1, 0) m, in
//! every frame: importers read a root's position channels either as its absolute position
//! (Blender: hips written as 0 with a 1 m offset sank the figure 1 m into the floor) or as
//! added to its offset, and both read this one the same.
//!
//! Sign conventions: every joint's rotation channels are `Zrotation Yrotation Xrotation`, in
//! degrees, meaning the joint rotation `R = Rz(z)·Ry(y)·Rx(x)` (the BVH convention: channels
//! compose left to right). The angles of the controls CSV and OSC (pitch > 0 lifts the chin,
//! yaw > 0 turns to the character's left, roll > 0 tilts the head to its left) become
//! `z = −roll_deg`, `y = yaw_deg`, `x = −pitch_deg`: pitch and roll change sign in the file,
//! because in this skeleton a positive X rotation tips +Y (up) towards +Z (forward, chin down)
//! and a positive Z rotation tips +Y towards −X (the character's right). This is the same
//! rotation as [`crate::head::angles_to_quat`]; importers show the CSV's signs again.

use std::fmt::Write;

use crate::control::{ControlFrame, HeadAngles};

/// Chest extension at full thorax expansion (thorax = 1), degrees (positive = chest up and
/// back, written as a negative X rotation like the head's pitch).
pub const CHEST_PITCH_DEG_PER_THORAX: f32 = 3.0;

/// Names of the joints, root first.
pub const JOINTS: [&str; 4] = ["Hips", "Chest", "Neck", "Head"];

/// Height of the hips (the root's Y position in every frame), metres.
pub const HIPS_HEIGHT_M: f32 = 1.0;

/// The HIERARCHY section and the MOTION header for `frames` frames at `frame_rate_hz`.
pub fn header(frames: usize, frame_rate_hz: f64) -> String {
    let mut s = String::with_capacity(1024);
    s.push_str("HIERARCHY\n");
    s.push_str("ROOT Hips\n{\n  OFFSET 0.0 0.0 0.0\n");
    s.push_str("  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n");
    s.push_str("  JOINT Chest\n  {\n    OFFSET 0.0 0.25 0.0\n");
    s.push_str("    CHANNELS 3 Zrotation Yrotation Xrotation\n");
    s.push_str("    JOINT Neck\n    {\n      OFFSET 0.0 0.25 0.0\n");
    s.push_str("      CHANNELS 3 Zrotation Yrotation Xrotation\n");
    s.push_str("      JOINT Head\n      {\n        OFFSET 0.0 0.1 0.0\n");
    s.push_str("        CHANNELS 3 Zrotation Yrotation Xrotation\n");
    s.push_str("        End Site\n        {\n          OFFSET 0.0 0.2 0.0\n        }\n");
    s.push_str("      }\n    }\n  }\n}\n");
    let frame_time_s = if frame_rate_hz.is_finite() && frame_rate_hz > 0.0 {
        1.0 / frame_rate_hz
    } else {
        1.0 / 120.0
    };
    let _ = write!(
        s,
        "MOTION\nFrames: {frames}\nFrame Time: {frame_time_s:.8}\n"
    );
    s
}

/// Finite value or 0.
fn f(v: f32) -> f32 {
    if v.is_finite() {
        v
    } else {
        0.0
    }
}

/// Appends one MOTION line: static Hips and Chest, `neck_pitch_deg` on the Neck, `head` on the
/// Head. Non-finite angles are written as 0.
pub fn push_frame(out: &mut String, head: &HeadAngles, neck_pitch_deg: f32) {
    push_pose(out, 0.0, neck_pitch_deg, head);
}

/// Appends one MOTION line of a control frame: the breathing on the Chest (from the thorax)
/// and the Neck, the head pose on the Head.
pub fn push_control(out: &mut String, frame: &ControlFrame) {
    let chest = CHEST_PITCH_DEG_PER_THORAX * f(frame.breathing.thorax).clamp(0.0, 1.0);
    push_pose(out, chest, frame.breathing.neck_pitch_deg, &frame.head);
}

fn push_pose(out: &mut String, chest_pitch_deg: f32, neck_pitch_deg: f32, head: &HeadAngles) {
    let _ = writeln!(
        out,
        "0.0000 {:.4} 0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 {:.4} 0.0000 0.0000 {:.4} {:.4} {:.4} {:.4}",
        HIPS_HEIGHT_M,
        shown(-f(chest_pitch_deg)),
        shown(-f(neck_pitch_deg)),
        shown(-f(head.roll_deg)),
        shown(f(head.yaw_deg)),
        shown(-f(head.pitch_deg))
    );
}

/// `v` as the four decimals show it, with no negative zero: an angle that rounds to 0 is
/// written `0.0000`, never `-0.0000`.
fn shown(v: f32) -> f32 {
    // Adding +0.0 turns −0.0 into +0.0 and leaves every other value as it is.
    (v * 1e4).round() / 1e4 + 0.0
}

/// A whole BVH file of head angles at `frame_rate_hz` (neck static).
pub fn encode_head(frames: &[HeadAngles], frame_rate_hz: f64) -> String {
    let mut s = header(frames.len(), frame_rate_hz);
    s.reserve(frames.len() * 96);
    for a in frames {
        push_frame(&mut s, a, 0.0);
    }
    s
}

/// A whole BVH file of control frames ([`push_control`]).
pub fn encode_controls(frames: &[ControlFrame], frame_rate_hz: f64) -> String {
    let mut s = header(frames.len(), frame_rate_hz);
    s.reserve(frames.len() * 96);
    for c in frames {
        push_control(&mut s, c);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{EulerRot, Quat};

    /// Joint names with their channel lists.
    type Joints = Vec<(String, Vec<String>)>;

    /// A minimal BVH reader: joints, frame time, motion rows.
    fn parse(text: &str) -> (Joints, f64, Vec<Vec<f64>>) {
        let mut joints: Joints = Vec::new();
        let mut lines = text.lines().map(str::trim);
        let mut frames = 0;
        let mut frame_time = 0.0;
        for line in lines.by_ref() {
            let w: Vec<&str> = line.split_whitespace().collect();
            match w.first().copied() {
                Some("ROOT") | Some("JOINT") => joints.push((w[1].to_string(), Vec::new())),
                Some("CHANNELS") => {
                    let n: usize = w[1].parse().unwrap();
                    assert_eq!(w.len(), n + 2);
                    joints.last_mut().unwrap().1 = w[2..].iter().map(|s| s.to_string()).collect();
                }
                Some("Frames:") => frames = w[1].parse().unwrap(),
                Some("Frame") => {
                    frame_time = w[2].parse().unwrap();
                    break;
                }
                _ => {}
            }
        }
        let rows: Vec<Vec<f64>> = lines
            .filter(|l| !l.is_empty())
            .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), frames);
        (joints, frame_time, rows)
    }

    #[test]
    fn parses_back_to_the_angles_and_the_same_rotation() {
        let angles = [
            HeadAngles {
                pitch_deg: 5.0,
                yaw_deg: -12.5,
                roll_deg: 3.25,
            },
            HeadAngles {
                pitch_deg: -7.75,
                yaw_deg: 14.0,
                roll_deg: -11.0,
            },
            HeadAngles {
                pitch_deg: f32::NAN,
                yaw_deg: 1.0,
                roll_deg: 0.0,
            },
        ];
        let text = encode_head(&angles, 120.0);
        let (joints, frame_time, rows) = parse(&text);
        let names: Vec<&str> = joints.iter().map(|j| j.0.as_str()).collect();
        assert_eq!(names, JOINTS);
        assert!((frame_time - 1.0 / 120.0).abs() < 1e-8);
        let total: usize = joints.iter().map(|j| j.1.len()).sum();
        // Column of the Head's channels.
        let head_start: usize = joints[..3].iter().map(|j| j.1.len()).sum();
        assert_eq!(joints[3].1, ["Zrotation", "Yrotation", "Xrotation"]);
        for (row, a) in rows.iter().zip(&angles) {
            assert_eq!(row.len(), total);
            let (z, y, x) = (row[head_start], row[head_start + 1], row[head_start + 2]);
            let pitch = if a.pitch_deg.is_finite() {
                a.pitch_deg
            } else {
                0.0
            };
            assert!((-x - pitch as f64).abs() < 1e-3, "pitch");
            assert!((y - a.yaw_deg as f64).abs() < 1e-3, "yaw");
            assert!((-z - a.roll_deg as f64).abs() < 1e-3, "roll");
            // Z Y X channels compose as Rz·Ry·Rx: the rotation angles_to_quat gives.
            let q = Quat::from_euler(
                EulerRot::ZYX,
                (z as f32).to_radians(),
                (y as f32).to_radians(),
                (x as f32).to_radians(),
            );
            let clean = HeadAngles {
                pitch_deg: pitch,
                ..*a
            };
            let want = crate::head::angles_to_quat(&clean);
            assert!(q.dot(want).abs() > 1.0 - 1e-6, "{q:?} vs {want:?}");
            // The static joints do not move; the hips stand at their height.
            assert_eq!(row[..3], [0.0, f64::from(HIPS_HEIGHT_M), 0.0]);
            assert!(row[3..head_start].iter().all(|v| *v == 0.0));
        }
    }

    #[test]
    fn an_angle_that_rounds_to_zero_is_written_without_a_sign() {
        let tiny = HeadAngles {
            pitch_deg: 0.00002,
            yaw_deg: -0.00003,
            roll_deg: 0.00001,
        };
        let text = encode_head(&[tiny], 60.0);
        let motion = text.lines().last().unwrap();
        assert!(!motion.contains("-0.0000"), "{motion}");
        assert!(motion.ends_with("0.0000 0.0000 0.0000"), "{motion}");
        // Other values keep their sign and digits.
        let tilted = HeadAngles {
            pitch_deg: 1.23456,
            yaw_deg: -2.5,
            roll_deg: 0.00006,
        };
        let text = encode_head(&[tilted], 60.0);
        let motion = text.lines().last().unwrap();
        assert!(motion.ends_with("-0.0001 -2.5000 -1.2346"), "{motion}");
    }

    #[test]
    fn controls_put_breathing_on_the_neck() {
        let mut c = ControlFrame::default();
        c.breathing.neck_pitch_deg = 2.0;
        c.head.yaw_deg = 4.0;
        let mut full = c;
        full.breathing.thorax = 1.0;
        let text = encode_controls(&[c, full], 60.0);
        let (_, _, rows) = parse(&text);
        // Hips 6, Chest Z Y X, Neck Z Y X, Head Z Y X.
        assert_eq!(rows[0][11], -2.0);
        assert_eq!(rows[0][13], 4.0);
        // The chest follows the thorax: still at rest, extended (chin-up sign) when full.
        assert_eq!(rows[0][8], 0.0);
        assert!(rows[1][8] < -1.0, "chest X rotation {}", rows[1][8]);
        // The hips never move.
        assert!(rows
            .iter()
            .all(|r| r[..6] == [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]));
    }

    #[test]
    fn the_hips_stand_at_their_height_whether_a_reader_adds_the_offset_or_not() {
        let text = encode_head(&[HeadAngles::default(); 2], 24.0);
        let offset: Vec<f64> = text
            .lines()
            .skip_while(|l| !l.starts_with("ROOT"))
            .find_map(|l| l.trim().strip_prefix("OFFSET "))
            .expect("root offset")
            .split_whitespace()
            .map(|v| v.parse().expect("number"))
            .collect();
        let (_, _, rows) = parse(&text);
        let h = f64::from(HIPS_HEIGHT_M);
        for row in rows {
            // Read as the absolute position (Blender), and as added to the offset.
            assert_eq!(row[1], h, "absolute");
            assert_eq!(offset[1] + row[1], h, "added to the offset");
        }
    }
}
