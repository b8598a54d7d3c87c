//! The breaths CSV contract (DESIGN.md): header `start_s,end_s,kind,peak_db`, one row per
//! inserted [`BreathEvent`] (`kind` one of `mouth`, `nose`, `mixed`, `sample`; `peak_db` dBFS).
//! Pure: writes to a `String` or any `std::io::Write`.

use crate::control::BreathEvent;
use std::fmt::Write as _;

/// The header line, without a line ending.
pub const HEADER: &str = "start_s,end_s,kind,peak_db";

/// Appends one row (with `\n`) for `event` to `out`.
pub fn write_row(out: &mut String, event: &BreathEvent) {
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        "{:.6},{:.6},{},{:.2}",
        event.start_s,
        event.end_s,
        event.kind.as_str(),
        event.peak_db
    );
}

/// Writes the header and one row per event to `w`.
pub fn write_all(w: &mut impl std::io::Write, events: &[BreathEvent]) -> std::io::Result<()> {
    let mut s = String::with_capacity(64 * (events.len() + 1));
    s.push_str(HEADER);
    s.push('\n');
    for e in events {
        write_row(&mut s, e);
    }
    w.write_all(s.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::BreathKind;

    #[test]
    fn rows_follow_the_contract() {
        let mut s = String::new();
        write_row(
            &mut s,
            &BreathEvent {
                start_s: 1.5,
                end_s: 2.125,
                kind: BreathKind::Nose,
                peak_db: -31.234,
            },
        );
        assert_eq!(s, "1.500000,2.125000,nose,-31.23\n");
        let mut buf = Vec::new();
        write_all(&mut buf, &[]).unwrap();
        assert_eq!(
            String::from_utf8(buf).unwrap(),
            "start_s,end_s,kind,peak_db\n"
        );
    }
}
