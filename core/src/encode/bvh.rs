//! BVH (Biovision hierarchy) encoder: head motion as a small skeleton that animation tools
//! (Blender, MotionBuilder, Maya) import.
//!
//! Skeleton, in centimetres, Y up, the character facing +Z (so +X is the character's left;
//! right-handed): `Hips` (root, at 100 cm height, static: 6 channels, all zero motion) →
//! `Chest` (static) → `Neck` (breathing neck pitch when encoded from control frames) → `Head`
//! (the head pose) → end site at the top of the head.
//!
//! Every joint's rotation channels are `Zrotation Yrotation Xrotation`, in degrees, meaning the
//! joint rotation `R = Rz(z)·Ry(y)·Rx(x)` (the BVH convention: channels compose left to right).
//! From the DESIGN.md angles: `z = −roll_deg`, `y = yaw_deg`, `x = −pitch_deg`; this is the
//! same rotation as [`crate::head::angles_to_quat`]. Pitch > 0 lifts the chin, yaw > 0 turns
//! to the character's left, roll > 0 tilts the head to its left.

use std::fmt::Write;

use crate::control::{ControlFrame, HeadAngles};

/// Names of the joints, root first.
pub const JOINTS: [&str; 4] = ["Hips", "Chest", "Neck", "Head"];

/// The HIERARCHY section and the MOTION header for `frames` frames at `frame_rate_hz`.
pub fn header(frames: usize, frame_rate_hz: f64) -> String {
    let mut s = String::with_capacity(1024);
    s.push_str("HIERARCHY\n");
    s.push_str("ROOT Hips\n{\n  OFFSET 0.0 100.0 0.0\n");
    s.push_str("  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n");
    s.push_str("  JOINT Chest\n  {\n    OFFSET 0.0 25.0 0.0\n");
    s.push_str("    CHANNELS 3 Zrotation Yrotation Xrotation\n");
    s.push_str("    JOINT Neck\n    {\n      OFFSET 0.0 25.0 0.0\n");
    s.push_str("      CHANNELS 3 Zrotation Yrotation Xrotation\n");
    s.push_str("      JOINT Head\n      {\n        OFFSET 0.0 10.0 0.0\n");
    s.push_str("        CHANNELS 3 Zrotation Yrotation Xrotation\n");
    s.push_str("        End Site\n        {\n          OFFSET 0.0 20.0 0.0\n        }\n");
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
    let _ = writeln!(
        out,
        "0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 0.0000 {:.4} {:.4} {:.4} {:.4}",
        -f(neck_pitch_deg),
        -f(head.roll_deg),
        f(head.yaw_deg),
        -f(head.pitch_deg)
    );
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

/// A whole BVH file of control frames: the head pose on `Head` and the breathing neck pitch
/// on `Neck`.
pub fn encode_controls(frames: &[ControlFrame], frame_rate_hz: f64) -> String {
    let mut s = header(frames.len(), frame_rate_hz);
    s.reserve(frames.len() * 96);
    for c in frames {
        push_frame(&mut s, &c.head, c.breathing.neck_pitch_deg);
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
            // The static joints do not move.
            assert!(row[..head_start].iter().all(|v| *v == 0.0));
        }
    }

    #[test]
    fn controls_put_breathing_on_the_neck() {
        let mut c = ControlFrame::default();
        c.breathing.neck_pitch_deg = 2.0;
        c.head.yaw_deg = 4.0;
        let text = encode_controls(&[c], 60.0);
        let (_, _, rows) = parse(&text);
        // Hips 6 + Chest 3, then Neck Z Y X.
        assert_eq!(rows[0][11], -2.0);
        assert_eq!(rows[0][13], 4.0);
    }
}
