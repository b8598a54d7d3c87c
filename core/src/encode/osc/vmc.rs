//! VMC (performer → marionette): the bones, blendshapes and the conversion of Pneuma's angles
//! to Unity's left-handed frame (see [`super`] for the table and the derivation).

use glam::Quat;

use super::address;
use super::wire::{BundleWriter, OscArg, OscError, TimeTag};
use crate::control::ControlFrame;

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

/// The `/VMC/Ext/OK` state sent with every frame: 1, the model is loaded (the protocol's
/// one-argument form, which every version reads).
pub const VMC_MODEL_LOADED: i32 = 1;

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
    use OscArg::{Float as F, Int as I, Str as S};
    let b = &frame.breathing;
    let h = &frame.head;
    let clamp01 = |v: f32| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
    let mut w = BundleWriter::new(buf, time_tag)?;
    w.message(address::VMC_OK, &[I(VMC_MODEL_LOADED)])?;
    let time_s = if frame.time_s.is_finite() {
        frame.time_s as f32
    } else {
        0.0
    };
    w.message(address::VMC_TIME, &[F(time_s)])?;
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
