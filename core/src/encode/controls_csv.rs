//! The controls CSV contract (DESIGN.md): header
//! `time_s,f0_hz,voiced,rms_db,speaking,phase,lung,thorax,abdomen,neck_pitch_deg,nostril_flare,mouth_open,head_pitch_deg,head_yaw_deg,head_roll_deg`,
//! one row per [`ControlFrame`]: `f0_hz` 0 when unvoiced, `voiced` and `speaking` 0/1, `phase`
//! `rest`/`inspiration`/`expiration`, 0..1 fields with 4 decimals, angles in degrees with 3.
//! Pure: writes to a `String` or any `std::io::Write`.

use crate::control::ControlFrame;
use std::fmt::Write as _;

/// The header line, without a line ending.
pub const HEADER: &str = "time_s,f0_hz,voiced,rms_db,speaking,phase,lung,thorax,abdomen,neck_pitch_deg,nostril_flare,mouth_open,head_pitch_deg,head_yaw_deg,head_roll_deg";

/// Appends one row (with `\n`) for `frame` to `out`.
pub fn write_row(out: &mut String, frame: &ControlFrame) {
    let f0 = if frame.voiced { frame.f0_hz } else { 0.0 };
    let b = &frame.breathing;
    let h = &frame.head;
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        "{:.6},{:.2},{},{:.2},{},{},{:.4},{:.4},{:.4},{:.3},{:.4},{:.4},{:.3},{:.3},{:.3}",
        frame.time_s,
        f0,
        u8::from(frame.voiced),
        frame.rms_db,
        u8::from(frame.speaking),
        b.phase.as_str(),
        b.lung,
        b.thorax,
        b.abdomen,
        b.neck_pitch_deg,
        b.nostril_flare,
        b.mouth_open,
        h.pitch_deg,
        h.yaw_deg,
        h.roll_deg
    );
}

/// Writes the header and one row per frame to `w`.
pub fn write_all(w: &mut impl std::io::Write, frames: &[ControlFrame]) -> std::io::Result<()> {
    let mut line = String::with_capacity(160);
    writeln!(w, "{HEADER}")?;
    for f in frames {
        line.clear();
        write_row(&mut line, f);
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{BreathingState, HeadAngles, Phase};

    #[test]
    fn rows_follow_the_contract() {
        let frame = ControlFrame {
            index: 2,
            time_s: 0.0125,
            f0_hz: 123.456,
            voiced: false,
            rms_db: -30.5,
            speaking: true,
            breathing: BreathingState {
                phase: Phase::Inspiration,
                lung: 0.5,
                thorax: 0.25,
                abdomen: 0.125,
                neck_pitch_deg: 1.5,
                nostril_flare: 0.1,
                mouth_open: 0.2,
            },
            head: HeadAngles {
                pitch_deg: -2.0,
                yaw_deg: 3.25,
                roll_deg: 0.5,
            },
            ..Default::default()
        };
        let mut buf = Vec::new();
        write_all(&mut buf, &[frame]).unwrap();
        let s = String::from_utf8(buf).unwrap();
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines[0], HEADER);
        assert_eq!(
            lines[1],
            "0.012500,0.00,0,-30.50,1,inspiration,0.5000,0.2500,0.1250,1.500,0.1000,0.2000,-2.000,3.250,0.500"
        );
        assert_eq!(HEADER.split(',').count(), lines[1].split(',').count());
    }
}
