//! OSC 1.0 encoder: one bundle per [`ControlFrame`], written into a caller-provided buffer
//! without allocating (DESIGN.md, "Contracts", OSC). The tests read the bytes back with rosc, a
//! decoder written apart from this encoder (`pneuma_testkit::osc`).
//!
//! # Wire format
//! OSC 1.0: strings NUL-terminated and padded to 4 bytes, `i` = big-endian i32, `f` = big-endian
//! IEEE 754 f32, `s` = string. Every frame leaves as one bundle (`#bundle`, an NTP time tag, then
//! size-prefixed messages). Only the four required OSC 1.0 types `i`, `f`, `s` (no blobs) are used,
//! so every OSC 1.0 receiver can read them.
//!
//! # `pneuma` address space (format [`OscFormat::Pneuma`])
//! One bundle per frame with these messages, in this order:
//!
//! | address | types | value |
//! |---|---|---|
//! | `/pneuma/frame` | `if` | frame index (wraps at 2³¹), frame time in s from the stream start |
//! | `/pneuma/f0` | `f` | fundamental frequency, Hz; 0 when unvoiced |
//! | `/pneuma/voiced` | `i` | 1 voiced, 0 unvoiced |
//! | `/pneuma/rms` | `f` | RMS level, dBFS (floor −120) |
//! | `/pneuma/level` | `f` | level around the speaker's running speech level, dB |
//! | `/pneuma/speaking` | `i` | 1 inside a phrase, 0 in a pause |
//! | `/pneuma/breath/phase` | `s` | `rest`, `inspiration` or `expiration` |
//! | `/pneuma/breath/lung` | `f` | lung volume, 0..1 |
//! | `/pneuma/breath/thorax` | `f` | thorax expansion, 0..1 |
//! | `/pneuma/breath/abdomen` | `f` | abdomen expansion, 0..1 |
//! | `/pneuma/breath/nostril_flare` | `f` | nostril flare, 0..1 |
//! | `/pneuma/breath/mouth_open` | `f` | mouth opening from breathing, 0..1 |
//! | `/pneuma/breath/neck_pitch` | `f` | neck pitch from breathing, degrees, + = chin up |
//! | `/pneuma/head` | `fff` | head pitch, yaw, roll in degrees (DESIGN.md convention: right-handed, pitch + = chin up, yaw + = to the character's left, roll + = tilted to its left) |
//!
//! # VMC (format [`OscFormat::Vmc`])
//! The Virtual Motion Capture protocol (performer → marionette), one bundle per frame:
//!
//! | address | types | value |
//! |---|---|---|
//! | `/VMC/Ext/OK` | `i` | 1: the model is loaded (the protocol's availability message) |
//! | `/VMC/Ext/T` | `f` | the frame's time, seconds from the stream start |
//! | `/VMC/Ext/Bone/Pos` | `sfffffff` | bone `Chest`, then `Neck`, then `Head`: name, local position x, y, z (m), local rotation quaternion x, y, z, w |
//! | `/VMC/Ext/Blend/Val` | `sf` | blendshape `A` (VRM preset, = mouth open), `Breath` (= lung volume), `NostrilFlare` (= nostril flare), each 0..1 |
//! | `/VMC/Ext/Blend/Apply` | (none) | once per frame, after the values |
//!
//! No `/VMC/Ext/Root/Pos`: Pneuma does not know where the avatar stands, and a root at the
//! origin would pull an avatar that another performer (a face or body tracker) places back to
//! it; receivers keep the root where it is.
//!
//! Rotations: `Head` carries the head angles, `Neck` the breathing neck pitch, `Chest` a pitch of
//! `thorax × `[`VmcRig::chest_pitch_deg`] (the chest lifts on inspiration). Positions are the rig's
//! constant rest offsets ([`VmcRig`]); receivers that apply only rotations ignore them.
//!
//! ## From our angles to Unity's frame
//! VMC speaks Unity's frame: left-handed, Y up, the avatar facing +Z, X to the avatar's right.
//! Unity's rotation matrices are numerically the usual ones, so a positive rotation about +X turns
//! the forward vector (+Z) down, about +Y turns it to +X (the avatar's right), and about +Z turns
//! the up vector to −X (the avatar's left). Hence, for our right-handed angles:
//!
//! - Unity X angle = −pitch (our pitch + = chin up),
//! - Unity Y angle = −yaw (our yaw + = looking to the character's left),
//! - Unity Z angle = +roll (our roll + = top of the head to the character's left),
//!
//! composed in Unity's `Quaternion.Euler` order, `q = q_y · q_x · q_z` (roll first, then pitch,
//! then yaw, about fixed axes), so a receiver's `q.eulerAngles` returns (−pitch, −yaw, roll).
//!
//! # Modules
//! - [`wire`]: the OSC 1.0 writer (messages, bundles, time tags).
//! - [`pneuma`]: the `/pneuma` mapping.
//! - [`vmc`]: the VMC mapping and Unity-frame maths.

pub mod pneuma;
pub mod vmc;
pub mod wire;

pub use pneuma::encode_pneuma;
pub use vmc::{encode_vmc, unity_quaternion, VmcRig, VMC_BLENDSHAPES};
pub use wire::{write_message, BundleWriter, OscArg, OscError, TimeTag};

use crate::control::ControlFrame;

/// Which address space a frame is encoded in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum OscFormat {
    /// The `/pneuma/...` address space.
    #[default]
    Pneuma,
    /// The VMC protocol (`/VMC/Ext/...`).
    Vmc,
}

/// Largest packet either format produces for one frame, bytes (a buffer this big always fits).
pub const MAX_FRAME_PACKET_BYTES: usize = 1024;

/// Addresses of the `pneuma` format (see the module docs for types and units).
pub mod address {
    /// `if`: frame index, frame time (s).
    pub const FRAME: &str = "/pneuma/frame";
    /// `f`: f0 in Hz, 0 when unvoiced.
    pub const F0: &str = "/pneuma/f0";
    /// `i`: voiced 0/1.
    pub const VOICED: &str = "/pneuma/voiced";
    /// `f`: RMS level, dBFS.
    pub const RMS: &str = "/pneuma/rms";
    /// `f`: level around the speaker's speech level, dB.
    pub const LEVEL: &str = "/pneuma/level";
    /// `i`: speaking 0/1.
    pub const SPEAKING: &str = "/pneuma/speaking";
    /// `s`: breathing phase.
    pub const PHASE: &str = "/pneuma/breath/phase";
    /// `f`: lung volume 0..1.
    pub const LUNG: &str = "/pneuma/breath/lung";
    /// `f`: thorax 0..1.
    pub const THORAX: &str = "/pneuma/breath/thorax";
    /// `f`: abdomen 0..1.
    pub const ABDOMEN: &str = "/pneuma/breath/abdomen";
    /// `f`: nostril flare 0..1.
    pub const NOSTRIL_FLARE: &str = "/pneuma/breath/nostril_flare";
    /// `f`: mouth open 0..1.
    pub const MOUTH_OPEN: &str = "/pneuma/breath/mouth_open";
    /// `f`: neck pitch, degrees.
    pub const NECK_PITCH: &str = "/pneuma/breath/neck_pitch";
    /// `fff`: head pitch, yaw, roll, degrees.
    pub const HEAD: &str = "/pneuma/head";
    /// VMC availability, `i` (1: loaded).
    pub const VMC_OK: &str = "/VMC/Ext/OK";
    /// VMC time, `f`: the frame's time in seconds from the stream start.
    pub const VMC_TIME: &str = "/VMC/Ext/T";
    /// VMC bone pose, `sfffffff`.
    pub const VMC_BONE_POS: &str = "/VMC/Ext/Bone/Pos";
    /// VMC blendshape value, `sf`.
    pub const VMC_BLEND_VAL: &str = "/VMC/Ext/Blend/Val";
    /// VMC blendshape apply, no arguments.
    pub const VMC_BLEND_APPLY: &str = "/VMC/Ext/Blend/Apply";
}

/// Writes `frame` in `format` (VMC with the default rig); returns the length in bytes.
pub fn encode_frame(
    format: OscFormat,
    frame: &ControlFrame,
    time_tag: TimeTag,
    buf: &mut [u8],
) -> Result<usize, OscError> {
    match format {
        OscFormat::Pneuma => encode_pneuma(frame, time_tag, buf),
        OscFormat::Vmc => encode_vmc(frame, &VmcRig::default(), time_tag, buf),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{BreathingState, HeadAngles, Phase};
    use glam::{Quat, Vec3};
    use pneuma_testkit::osc::{decode, OscType};

    fn sample_frame() -> ControlFrame {
        ControlFrame {
            index: 42,
            time_s: 0.35,
            f0_hz: 180.5,
            voiced: true,
            rms_db: -23.0,
            level_db: -1.5,
            speaking: true,
            breathing: BreathingState {
                phase: Phase::Expiration,
                lung: 0.6,
                thorax: 0.5,
                abdomen: 0.4,
                neck_pitch_deg: 1.25,
                nostril_flare: 0.1,
                mouth_open: 0.2,
            },
            head: HeadAngles {
                pitch_deg: 5.0,
                yaw_deg: -3.0,
                roll_deg: 2.0,
            },
        }
    }

    #[test]
    fn a_message_is_byte_exact_osc_1_0() {
        let mut buf = [0u8; 64];
        let n = write_message(
            &mut buf,
            "/a",
            &[OscArg::Int(1), OscArg::Float(0.5), OscArg::Str("hi")],
        )
        .unwrap();
        let want: &[u8] = &[
            b'/', b'a', 0, 0, // address padded to 4
            b',', b'i', b'f', b's', 0, 0, 0, 0, // ",ifs" + NUL, padded to 8
            0, 0, 0, 1, // int 1
            0x3F, 0, 0, 0, // 0.5f32
            b'h', b'i', 0, 0, // "hi"
        ];
        assert_eq!(&buf[..n], want);
        // An address of exactly 4 bytes needs a full 4 bytes of padding.
        let n = write_message(&mut buf, "/abc", &[]).unwrap();
        assert_eq!(&buf[..n], b"/abc\0\0\0\0,\0\0\0");
    }

    #[test]
    fn small_buffers_and_bad_addresses_are_refused() {
        let mut buf = [0u8; 10];
        assert!(matches!(
            write_message(&mut buf, "/pneuma/f0", &[OscArg::Float(1.0)]),
            Err(OscError::BufferFull { capacity: 10, .. })
        ));
        assert!(matches!(
            write_message(&mut [0u8; 64], "pneuma", &[]),
            Err(OscError::Address(_))
        ));
        let mut small = [0u8; 100];
        assert!(matches!(
            encode_pneuma(&sample_frame(), TimeTag::IMMEDIATELY, &mut small),
            Err(OscError::BufferFull { .. })
        ));
    }

    #[test]
    fn pneuma_bundle_carries_every_documented_address_with_its_values() {
        let mut buf = [0u8; MAX_FRAME_PACKET_BYTES];
        let tag = TimeTag::from_unix_seconds(1_700_000_000.25);
        let n = encode_pneuma(&sample_frame(), tag, &mut buf).unwrap();
        assert_eq!(&buf[..8], b"#bundle\0");
        let msgs = decode(&buf[..n]).unwrap();
        assert!(msgs.iter().all(|m| m.time_tag == Some(tag.0)));
        let get = |a: &str| {
            msgs.iter()
                .find(|m| m.address == a)
                .unwrap_or_else(|| panic!("{a} missing"))
                .args
                .clone()
        };
        use OscType::{Float as F, Int as I};
        assert_eq!(get("/pneuma/frame"), vec![I(42), F(0.35)]);
        assert_eq!(get("/pneuma/f0"), vec![F(180.5)]);
        assert_eq!(get("/pneuma/voiced"), vec![I(1)]);
        assert_eq!(get("/pneuma/rms"), vec![F(-23.0)]);
        assert_eq!(get("/pneuma/level"), vec![F(-1.5)]);
        assert_eq!(get("/pneuma/speaking"), vec![I(1)]);
        assert_eq!(
            get("/pneuma/breath/phase"),
            vec![OscType::String("expiration".into())]
        );
        assert_eq!(get("/pneuma/breath/lung"), vec![F(0.6)]);
        assert_eq!(get("/pneuma/breath/thorax"), vec![F(0.5)]);
        assert_eq!(get("/pneuma/breath/abdomen"), vec![F(0.4)]);
        assert_eq!(get("/pneuma/breath/nostril_flare"), vec![F(0.1)]);
        assert_eq!(get("/pneuma/breath/mouth_open"), vec![F(0.2)]);
        assert_eq!(get("/pneuma/breath/neck_pitch"), vec![F(1.25)]);
        assert_eq!(get("/pneuma/head"), vec![F(5.0), F(-3.0), F(2.0)]);
        assert_eq!(msgs.len(), 14);
        assert!((tag.to_unix_seconds() - 1_700_000_000.25).abs() < 1e-6);
        assert!(n <= MAX_FRAME_PACKET_BYTES);
    }

    #[test]
    fn unvoiced_frames_send_zero_f0() {
        let mut f = sample_frame();
        f.voiced = false;
        let mut buf = [0u8; MAX_FRAME_PACKET_BYTES];
        let n = encode_pneuma(&f, TimeTag::IMMEDIATELY, &mut buf).unwrap();
        let msgs = decode(&buf[..n]).unwrap();
        assert_eq!(msgs[1].args, vec![OscType::Float(0.0)]);
    }

    /// Rotates a vector by a Unity quaternion (numerically the usual formula).
    fn rotate(q: [f32; 4], v: Vec3) -> Vec3 {
        Quat::from_array(q) * v
    }

    #[test]
    fn unity_conversion_moves_the_face_the_documented_way() {
        let forward = Vec3::Z; // the avatar faces +Z; +X is its right, +Y up
                               // Chin up: the face turns up.
        let f = rotate(unity_quaternion(30.0, 0.0, 0.0), forward);
        assert!(f.y > 0.49 && f.y < 0.51, "{f}");
        // Yaw + looks to the avatar's left (−X).
        let f = rotate(unity_quaternion(0.0, 30.0, 0.0), forward);
        assert!(f.x < -0.49 && f.x > -0.51, "{f}");
        // Roll + tilts the top of the head to the avatar's left (−X).
        let up = rotate(unity_quaternion(0.0, 0.0, 30.0), Vec3::Y);
        assert!(up.x < -0.49 && up.x > -0.51, "{up}");
        // Composition order: roll is applied first (about the head's own forward axis), yaw last.
        let q = Quat::from_array(unity_quaternion(10.0, 20.0, 5.0));
        let (y, x, z) = q.to_euler(glam::EulerRot::YXZ);
        assert!((x.to_degrees() + 10.0).abs() < 1e-3);
        assert!((y.to_degrees() + 20.0).abs() < 1e-3);
        assert!((z.to_degrees() - 5.0).abs() < 1e-3);
        // Non-finite angles are neutral.
        assert_eq!(unity_quaternion(f32::NAN, 0.0, 0.0), [0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn vmc_bundle_has_bones_blendshapes_and_one_apply() {
        let mut buf = [0u8; MAX_FRAME_PACKET_BYTES];
        let frame = sample_frame();
        let n = encode_frame(OscFormat::Vmc, &frame, TimeTag::IMMEDIATELY, &mut buf).unwrap();
        assert!(n <= MAX_FRAME_PACKET_BYTES);
        let msgs = decode(&buf[..n]).unwrap();
        // The availability and the time come first, once each.
        assert_eq!(msgs[0].address, "/VMC/Ext/OK");
        assert_eq!(msgs[0].args, vec![OscType::Int(1)]);
        assert_eq!(msgs[1].address, "/VMC/Ext/T");
        assert_eq!(msgs[1].args, vec![OscType::Float(frame.time_s as f32)]);
        for a in ["/VMC/Ext/OK", "/VMC/Ext/T"] {
            assert_eq!(msgs.iter().filter(|m| m.address == a).count(), 1, "{a}");
        }
        let bones: Vec<_> = msgs
            .iter()
            .filter(|m| m.address == "/VMC/Ext/Bone/Pos")
            .collect();
        let names: Vec<_> = bones
            .iter()
            .map(|m| match &m.args[0] {
                OscType::String(s) => s.as_str(),
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(names, ["Chest", "Neck", "Head"]);
        for m in &bones {
            assert_eq!(m.args.len(), 8);
            assert!(m.args[1..].iter().all(|a| matches!(a, OscType::Float(_))));
        }
        let head: Vec<f32> = bones[2].args[4..]
            .iter()
            .map(|a| match a {
                OscType::Float(v) => *v,
                _ => unreachable!(),
            })
            .collect();
        assert_eq!(head, unity_quaternion(5.0, -3.0, 2.0));
        let norm: f32 = head.iter().map(|v| v * v).sum();
        assert!((norm - 1.0).abs() < 1e-5);
        let blends: Vec<_> = msgs
            .iter()
            .filter(|m| m.address == "/VMC/Ext/Blend/Val")
            .map(|m| m.args.clone())
            .collect();
        assert_eq!(
            blends,
            vec![
                vec![OscType::String("A".into()), OscType::Float(0.2)],
                vec![OscType::String("Breath".into()), OscType::Float(0.6)],
                vec![OscType::String("NostrilFlare".into()), OscType::Float(0.1)],
            ]
        );
        let applies: Vec<_> = msgs
            .iter()
            .enumerate()
            .filter(|(_, m)| m.address == "/VMC/Ext/Blend/Apply")
            .collect();
        assert_eq!(applies.len(), 1);
        assert_eq!(applies[0].0, msgs.len() - 1, "Apply comes last");
        assert!(applies[0].1.args.is_empty());
    }
}
