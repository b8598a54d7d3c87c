//! The `pneuma analyze` CSV contract: header `time_s,f0_hz,voiced,voicing,rms_db`, one row per
//! feature frame (`f0_hz` 0 when unvoiced, `voiced` 0/1, `voicing` 0..1, `rms_db` dBFS).

use crate::analysis::FeatureFrame;
use std::fmt::Write;

/// The header line, without a line ending.
pub const HEADER: &str = "time_s,f0_hz,voiced,voicing,rms_db";

/// Appends one row (with `\n`) for `frame` to `out`.
pub fn write_row(out: &mut String, frame: &FeatureFrame) {
    let f0 = if frame.voiced { frame.f0_hz } else { 0.0 };
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        "{:.6},{:.2},{},{:.3},{:.2}",
        frame.time_s,
        f0,
        u8::from(frame.voiced),
        frame.voicing,
        frame.rms_db
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_follow_the_contract() {
        let mut s = String::new();
        write_row(
            &mut s,
            &FeatureFrame {
                index: 3,
                time_s: 0.025,
                f0_hz: 201.234,
                voiced: true,
                voicing: 0.91234,
                rms_db: -23.456,
                ..Default::default()
            },
        );
        write_row(
            &mut s,
            &FeatureFrame {
                time_s: 1.0 / 120.0,
                f0_hz: 180.0,
                voiced: false,
                rms_db: -120.0,
                ..Default::default()
            },
        );
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines[0], "0.025000,201.23,1,0.912,-23.46");
        assert_eq!(lines[1], "0.008333,0.00,0,0.000,-120.00");
        assert_eq!(HEADER.split(',').count(), lines[0].split(',').count());
    }
}
