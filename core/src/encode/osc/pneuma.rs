//! The `/pneuma` address space: one bundle per control frame (table in [`super`]).

use super::address;
use super::wire::{BundleWriter, OscArg, OscError, TimeTag};
use crate::control::ControlFrame;

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
