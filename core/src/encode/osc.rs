//! OSC 1.0 encoder (and a small decoder for tests and tools): one bundle per [`ControlFrame`],
//! written into a caller-provided buffer without allocating (DESIGN.md, "Contracts", OSC).
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
//! | `/VMC/Ext/Bone/Pos` | `sfffffff` | bone `Chest`, then `Neck`, then `Head`: name, local position x, y, z (m), local rotation quaternion x, y, z, w |
//! | `/VMC/Ext/Blend/Val` | `sf` | blendshape `A` (VRM preset, = mouth open), `Breath` (= lung volume), `NostrilFlare` (= nostril flare), each 0..1 |
//! | `/VMC/Ext/Blend/Apply` | (none) | once per frame, after the values |
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

use crate::control::ControlFrame;
use glam::Quat;
use thiserror::Error;

/// A bad OSC buffer or packet.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum OscError {
    /// The caller's buffer is too small for the packet.
    #[error("the OSC buffer ({capacity} bytes) is too small: give at least {needed} bytes")]
    BufferFull {
        /// Bytes needed at least (so far).
        needed: usize,
        /// Bytes available.
        capacity: usize,
    },
    /// An address does not start with `/` or contains a NUL.
    #[error("OSC address {0:?} is invalid: it must start with '/' and contain no NUL")]
    Address(String),
    /// A packet could not be decoded.
    #[error("malformed OSC packet: {0}")]
    Malformed(&'static str),
}

/// One OSC argument.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OscArg<'a> {
    /// `i`: 32-bit signed integer.
    Int(i32),
    /// `f`: 32-bit float.
    Float(f32),
    /// `s`: string (must not contain NUL).
    Str(&'a str),
}

impl OscArg<'_> {
    fn tag(&self) -> u8 {
        match self {
            OscArg::Int(_) => b'i',
            OscArg::Float(_) => b'f',
            OscArg::Str(_) => b's',
        }
    }
}

/// An NTP time tag: seconds since 1900-01-01 in the high 32 bits, fraction in the low 32 bits.
/// The value 1 means "immediately".
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TimeTag(pub u64);

impl TimeTag {
    /// "Process immediately".
    pub const IMMEDIATELY: TimeTag = TimeTag(1);
    /// Seconds from 1900-01-01 (NTP era 0) to 1970-01-01 (Unix epoch).
    pub const UNIX_OFFSET_S: u64 = 2_208_988_800;

    /// The tag for `unix_s` seconds since the Unix epoch (negative values clamp to the epoch).
    pub fn from_unix_seconds(unix_s: f64) -> TimeTag {
        let s = unix_s.max(0.0);
        let whole = s.floor();
        let frac = ((s - whole) * 4_294_967_296.0).min(4_294_967_295.0) as u64;
        TimeTag(((whole as u64 + Self::UNIX_OFFSET_S) << 32) | frac)
    }

    /// Seconds since the Unix epoch.
    pub fn to_unix_seconds(self) -> f64 {
        let secs = (self.0 >> 32) as f64 - Self::UNIX_OFFSET_S as f64;
        secs + (self.0 & 0xFFFF_FFFF) as f64 / 4_294_967_296.0
    }
}

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

/// Sequential writer over a caller's byte buffer.
struct Cursor<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl<'a> Cursor<'a> {
    fn reserve(&mut self, n: usize) -> Result<&mut [u8], OscError> {
        let end = self.len + n;
        if end > self.buf.len() {
            return Err(OscError::BufferFull {
                needed: end,
                capacity: self.buf.len(),
            });
        }
        let slot = &mut self.buf[self.len..end];
        self.len = end;
        Ok(slot)
    }

    fn bytes(&mut self, b: &[u8]) -> Result<(), OscError> {
        self.reserve(b.len())?.copy_from_slice(b);
        Ok(())
    }

    /// A NUL-terminated string padded to a multiple of 4 bytes.
    fn padded(&mut self, parts: &[&[u8]]) -> Result<(), OscError> {
        let n: usize = parts.iter().map(|p| p.len()).sum();
        let total = (n + 4) & !3;
        let slot = self.reserve(total)?;
        let mut i = 0;
        for p in parts {
            slot[i..i + p.len()].copy_from_slice(p);
            i += p.len();
        }
        slot[i..].fill(0);
        Ok(())
    }
}

fn check_address(address: &str) -> Result<(), OscError> {
    if !address.starts_with('/') || address.contains('\0') {
        return Err(OscError::Address(address.to_owned()));
    }
    Ok(())
}

/// Writes one OSC message into `buf` and returns its length in bytes. Never allocates (except
/// for the error message of an invalid address).
pub fn write_message(buf: &mut [u8], address: &str, args: &[OscArg]) -> Result<usize, OscError> {
    check_address(address)?;
    let mut c = Cursor { buf, len: 0 };
    c.padded(&[address.as_bytes()])?;
    // Type tag string: ',' + one tag per argument (at most 15 on the stack).
    let mut tags = [0u8; 16];
    tags[0] = b',';
    if args.len() >= tags.len() {
        return Err(OscError::Malformed("more than 15 arguments in one message"));
    }
    for (t, a) in tags[1..].iter_mut().zip(args) {
        *t = a.tag();
    }
    c.padded(&[&tags[..=args.len()]])?;
    for a in args {
        match *a {
            OscArg::Int(v) => c.bytes(&v.to_be_bytes())?,
            OscArg::Float(v) => c.bytes(&v.to_be_bytes())?,
            OscArg::Str(s) => {
                if s.contains('\0') {
                    return Err(OscError::Malformed("string argument contains NUL"));
                }
                c.padded(&[s.as_bytes()])?
            }
        }
    }
    Ok(c.len)
}

/// Writes an OSC bundle into a caller's buffer, one message at a time.
pub struct BundleWriter<'a> {
    cursor: Cursor<'a>,
}

impl<'a> BundleWriter<'a> {
    /// Starts a bundle with time tag `time_tag`.
    pub fn new(buf: &'a mut [u8], time_tag: TimeTag) -> Result<Self, OscError> {
        let mut cursor = Cursor { buf, len: 0 };
        cursor.bytes(b"#bundle\0")?;
        cursor.bytes(&time_tag.0.to_be_bytes())?;
        Ok(Self { cursor })
    }

    /// Appends one message (size-prefixed).
    pub fn message(&mut self, address: &str, args: &[OscArg]) -> Result<(), OscError> {
        let start = self.cursor.len;
        self.cursor.reserve(4)?;
        let capacity = self.cursor.buf.len();
        let n = write_message(&mut self.cursor.buf[start + 4..], address, args).map_err(
            |e| match e {
                OscError::BufferFull { needed, .. } => OscError::BufferFull {
                    needed: needed + start + 4,
                    capacity,
                },
                e => e,
            },
        )?;
        self.cursor.buf[start..start + 4].copy_from_slice(&(n as i32).to_be_bytes());
        self.cursor.len += n;
        Ok(())
    }

    /// The bundle's length in bytes.
    pub fn finish(self) -> usize {
        self.cursor.len
    }
}

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
    /// VMC bone pose, `sfffffff`.
    pub const VMC_BONE_POS: &str = "/VMC/Ext/Bone/Pos";
    /// VMC blendshape value, `sf`.
    pub const VMC_BLEND_VAL: &str = "/VMC/Ext/Blend/Val";
    /// VMC blendshape apply, no arguments.
    pub const VMC_BLEND_APPLY: &str = "/VMC/Ext/Blend/Apply";
}

/// Writes `frame` as one `pneuma` bundle; returns its length in bytes.
pub fn encode_pneuma(
    frame: &ControlFrame,
    time_tag: TimeTag,
    buf: &mut [u8],
) -> Result<usize, OscError> {
    use address::*;
    use OscArg::{Float as F, Int as I};
    let b = &frame.breathing;
    let mut w = BundleWriter::new(buf, time_tag)?;
    w.message(
        FRAME,
        &[
            I(frame.index as u32 as i32 & i32::MAX),
            F(frame.time_s as f32),
        ],
    )?;
    w.message(F0, &[F(if frame.voiced { frame.f0_hz } else { 0.0 })])?;
    w.message(VOICED, &[I(i32::from(frame.voiced))])?;
    w.message(RMS, &[F(frame.rms_db)])?;
    w.message(LEVEL, &[F(frame.level_db)])?;
    w.message(SPEAKING, &[I(i32::from(frame.speaking))])?;
    w.message(PHASE, &[OscArg::Str(b.phase.as_str())])?;
    w.message(LUNG, &[F(b.lung)])?;
    w.message(THORAX, &[F(b.thorax)])?;
    w.message(ABDOMEN, &[F(b.abdomen)])?;
    w.message(NOSTRIL_FLARE, &[F(b.nostril_flare)])?;
    w.message(MOUTH_OPEN, &[F(b.mouth_open)])?;
    w.message(NECK_PITCH, &[F(b.neck_pitch_deg)])?;
    let h = &frame.head;
    w.message(HEAD, &[F(h.pitch_deg), F(h.yaw_deg), F(h.roll_deg)])?;
    Ok(w.finish())
}

/// The avatar rig assumed by the VMC output: rest positions of the bones (local to their parent,
/// metres, Unity frame) and how far the chest pitches with the thorax.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VmcRig {
    /// `Chest` local position, metres (x, y, z).
    pub chest_pos_m: [f32; 3],
    /// `Neck` local position, metres.
    pub neck_pos_m: [f32; 3],
    /// `Head` local position, metres.
    pub head_pos_m: [f32; 3],
    /// Chest pitch (chest lift) at full thorax expansion, degrees, + = chest up.
    pub chest_pitch_deg: f32,
}

impl Default for VmcRig {
    /// Offsets of a typical 1.6 m VRM humanoid.
    fn default() -> Self {
        Self {
            chest_pos_m: [0.0, 0.12, 0.0],
            neck_pos_m: [0.0, 0.22, 0.0],
            head_pos_m: [0.0, 0.09, 0.0],
            chest_pitch_deg: 3.0,
        }
    }
}

/// VMC blendshape names, in the order they are sent.
pub const VMC_BLENDSHAPES: [&str; 3] = ["A", "Breath", "NostrilFlare"];

/// Our right-handed (pitch, yaw, roll) in degrees as a Unity (left-handed, Y up, +Z forward)
/// local rotation quaternion `[x, y, z, w]`; see the module docs for the derivation.
pub fn unity_quaternion(pitch_deg: f32, yaw_deg: f32, roll_deg: f32) -> [f32; 4] {
    let finite = |a: f32| if a.is_finite() { a } else { 0.0 };
    let x = (-finite(pitch_deg)).to_radians();
    let y = (-finite(yaw_deg)).to_radians();
    let z = finite(roll_deg).to_radians();
    let q = Quat::from_rotation_y(y) * Quat::from_rotation_x(x) * Quat::from_rotation_z(z);
    q.to_array()
}

/// Writes `frame` as one VMC bundle; returns its length in bytes.
pub fn encode_vmc(
    frame: &ControlFrame,
    rig: &VmcRig,
    time_tag: TimeTag,
    buf: &mut [u8],
) -> Result<usize, OscError> {
    use OscArg::{Float as F, Str as S};
    let b = &frame.breathing;
    let h = &frame.head;
    let clamp01 = |v: f32| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    let mut w = BundleWriter::new(buf, time_tag)?;
    let bones = [
        (
            "Chest",
            rig.chest_pos_m,
            unity_quaternion(clamp01(b.thorax) * rig.chest_pitch_deg, 0.0, 0.0),
        ),
        (
            "Neck",
            rig.neck_pos_m,
            unity_quaternion(b.neck_pitch_deg, 0.0, 0.0),
        ),
        (
            "Head",
            rig.head_pos_m,
            unity_quaternion(h.pitch_deg, h.yaw_deg, h.roll_deg),
        ),
    ];
    for (name, p, q) in bones {
        w.message(
            address::VMC_BONE_POS,
            &[
                S(name),
                F(p[0]),
                F(p[1]),
                F(p[2]),
                F(q[0]),
                F(q[1]),
                F(q[2]),
                F(q[3]),
            ],
        )?;
    }
    let values = [b.mouth_open, b.lung, b.nostril_flare];
    for (name, v) in VMC_BLENDSHAPES.iter().zip(values) {
        w.message(address::VMC_BLEND_VAL, &[S(name), F(clamp01(v))])?;
    }
    w.message(address::VMC_BLEND_APPLY, &[])?;
    Ok(w.finish())
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

/// A decoded argument (owned), for tests and tools.
#[derive(Debug, Clone, PartialEq)]
pub enum OscValue {
    /// `i`
    Int(i32),
    /// `f`
    Float(f32),
    /// `s`
    Str(String),
}

/// A decoded message with the time tag of the bundle it came in (`None` for a bare message).
#[derive(Debug, Clone, PartialEq)]
pub struct OscMessage {
    /// Time tag of the enclosing bundle.
    pub time_tag: Option<TimeTag>,
    /// Address pattern.
    pub address: String,
    /// Arguments.
    pub args: Vec<OscValue>,
}

/// Decodes a packet (message or bundle, nested bundles flattened) into messages. Allocates: for
/// tests and tools, not for the audio thread.
pub fn decode_packet(packet: &[u8]) -> Result<Vec<OscMessage>, OscError> {
    let mut out = Vec::new();
    decode_into(packet, None, &mut out)?;
    Ok(out)
}

fn read_str(b: &[u8], pos: &mut usize) -> Result<String, OscError> {
    let rest = b
        .get(*pos..)
        .ok_or(OscError::Malformed("string past the end"))?;
    let nul = rest
        .iter()
        .position(|&c| c == 0)
        .ok_or(OscError::Malformed("string without NUL"))?;
    let s = std::str::from_utf8(&rest[..nul])
        .map_err(|_| OscError::Malformed("string is not UTF-8"))?
        .to_owned();
    let padded = (nul + 4) & !3;
    if padded > rest.len() {
        return Err(OscError::Malformed("string padding past the end"));
    }
    *pos += padded;
    Ok(s)
}

fn read4(b: &[u8], pos: &mut usize) -> Result<[u8; 4], OscError> {
    let v = b
        .get(*pos..*pos + 4)
        .ok_or(OscError::Malformed("argument past the end"))?;
    *pos += 4;
    Ok([v[0], v[1], v[2], v[3]])
}

fn decode_into(
    b: &[u8],
    time_tag: Option<TimeTag>,
    out: &mut Vec<OscMessage>,
) -> Result<(), OscError> {
    if !b.len().is_multiple_of(4) {
        return Err(OscError::Malformed("size is not a multiple of 4"));
    }
    if b.starts_with(b"#bundle\0") {
        let tag = b
            .get(8..16)
            .ok_or(OscError::Malformed("bundle without time tag"))?;
        let tag = TimeTag(u64::from_be_bytes(tag.try_into().expect("8 bytes")));
        let mut pos = 16;
        while pos < b.len() {
            let n = i32::from_be_bytes(read4(b, &mut pos)?);
            let n = usize::try_from(n).map_err(|_| OscError::Malformed("negative size"))?;
            let element = b
                .get(pos..pos + n)
                .ok_or(OscError::Malformed("bundle element past the end"))?;
            decode_into(element, Some(tag), out)?;
            pos += n;
        }
        return Ok(());
    }
    let mut pos = 0;
    let address = read_str(b, &mut pos)?;
    if !address.starts_with('/') {
        return Err(OscError::Malformed("address does not start with '/'"));
    }
    let tags = if pos < b.len() {
        read_str(b, &mut pos)?
    } else {
        ",".to_owned()
    };
    let tags = tags
        .strip_prefix(',')
        .ok_or(OscError::Malformed("type tags do not start with ','"))?;
    let mut args = Vec::with_capacity(tags.len());
    for t in tags.bytes() {
        args.push(match t {
            b'i' => OscValue::Int(i32::from_be_bytes(read4(b, &mut pos)?)),
            b'f' => OscValue::Float(f32::from_be_bytes(read4(b, &mut pos)?)),
            b's' => OscValue::Str(read_str(b, &mut pos)?),
            _ => return Err(OscError::Malformed("unsupported type tag")),
        });
    }
    out.push(OscMessage {
        time_tag,
        address,
        args,
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{BreathingState, HeadAngles, Phase};
    use glam::Vec3;

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
        let msgs = decode_packet(&buf[..n]).unwrap();
        assert!(msgs.iter().all(|m| m.time_tag == Some(tag)));
        let get = |a: &str| {
            msgs.iter()
                .find(|m| m.address == a)
                .unwrap_or_else(|| panic!("{a} missing"))
                .args
                .clone()
        };
        use OscValue::{Float as F, Int as I};
        assert_eq!(get("/pneuma/frame"), vec![I(42), F(0.35)]);
        assert_eq!(get("/pneuma/f0"), vec![F(180.5)]);
        assert_eq!(get("/pneuma/voiced"), vec![I(1)]);
        assert_eq!(get("/pneuma/rms"), vec![F(-23.0)]);
        assert_eq!(get("/pneuma/level"), vec![F(-1.5)]);
        assert_eq!(get("/pneuma/speaking"), vec![I(1)]);
        assert_eq!(
            get("/pneuma/breath/phase"),
            vec![OscValue::Str("expiration".into())]
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
        let msgs = decode_packet(&buf[..n]).unwrap();
        assert_eq!(msgs[1].args, vec![OscValue::Float(0.0)]);
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
        let msgs = decode_packet(&buf[..n]).unwrap();
        let bones: Vec<_> = msgs
            .iter()
            .filter(|m| m.address == "/VMC/Ext/Bone/Pos")
            .collect();
        let names: Vec<_> = bones
            .iter()
            .map(|m| match &m.args[0] {
                OscValue::Str(s) => s.as_str(),
                other => panic!("{other:?}"),
            })
            .collect();
        assert_eq!(names, ["Chest", "Neck", "Head"]);
        for m in &bones {
            assert_eq!(m.args.len(), 8);
            assert!(m.args[1..].iter().all(|a| matches!(a, OscValue::Float(_))));
        }
        let head: Vec<f32> = bones[2].args[4..]
            .iter()
            .map(|a| match a {
                OscValue::Float(v) => *v,
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
                vec![OscValue::Str("A".into()), OscValue::Float(0.2)],
                vec![OscValue::Str("Breath".into()), OscValue::Float(0.6)],
                vec![OscValue::Str("NostrilFlare".into()), OscValue::Float(0.1)],
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

    #[test]
    fn decoder_rejects_garbage() {
        assert!(decode_packet(b"abc").is_err());
        assert!(decode_packet(b"noslash\0").is_err());
        assert!(decode_packet(b"#bundle\0\0\0\0\0\0\0\0\x01\0\0\0\x40").is_err());
    }
}
