//! The breaths CSV contract (DESIGN.md): header `start_s,end_s,kind,peak_db`, one row per
//! inserted [`BreathEvent`] (`kind` one of `mouth`, `nose`, `mixed`, `sample`; `peak_db` dBFS).
//! The span is rounded outward to the microsecond (start down, end up), so `[start_s, end_s)`
//! holds every sample the breath changed at any rate: a row is an edit list's entry.
//! Pure: writes to a `String` or any `std::io::Write`.

use crate::control::BreathEvent;
use std::fmt::Write as _;

/// The header line, without a line ending.
pub const HEADER: &str = "start_s,end_s,kind,peak_db";

/// Microseconds per second: the rows' resolution.
const US_PER_S: f64 = 1e6;

/// How near a whole microsecond a time counts as on it, microseconds: far above the binary
/// fraction's error for spans of up to about 2.4 hours, far below a sample at any rate (past
/// that the fraction's step is larger, and a span can come out a microsecond wider, never
/// narrower).
const ON_THE_MICROSECOND: f64 = 1e-6;

/// Appends one row (with `\n`) for `event` to `out`.
pub fn write_row(out: &mut String, event: &BreathEvent) {
    let (start, end) = span_text(event.start_s, event.end_s);
    // Writing to a String cannot fail.
    let _ = writeln!(
        out,
        "{start},{end},{},{:.2}",
        event.kind.as_str(),
        event.peak_db
    );
}

/// A breath's span `[start_s, end_s)` as the rows write it (and the Audacity labels): seconds
/// with six decimals, rounded outward to whole microseconds (a time on the microsecond
/// already, give or take the binary fraction's last bits, stays as it is), printed from the
/// integers, so no decimal rounding moves them back inward.
pub fn span_text(start_s: f64, end_s: f64) -> (impl std::fmt::Display, impl std::fmt::Display) {
    let start_us = (start_s * US_PER_S + ON_THE_MICROSECOND).floor() as i64;
    let end_us = (end_s * US_PER_S - ON_THE_MICROSECOND).ceil() as i64;
    (Micros(start_us), Micros(end_us))
}

/// Whole microseconds shown as seconds with six decimals.
struct Micros(i64);

impl std::fmt::Display for Micros {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sign = if self.0 < 0 { "-" } else { "" };
        let us = self.0.unsigned_abs();
        write!(f, "{sign}{}.{:06}", us / 1_000_000, us % 1_000_000)
    }
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
        // A row of a mouth breath over `[start_s, end_s)`.
        let row = |start_s: f64, end_s: f64| {
            let mut s = String::new();
            let kind = BreathKind::Mouth;
            write_row(
                &mut s,
                &BreathEvent {
                    start_s,
                    end_s,
                    kind,
                    peak_db: -40.0,
                },
            );
            s
        };
        // At 48 kHz a breath over samples 165_600..165_681 ends at 3.4516875 s: written
        // 3.451688, so reading `[start, end)` back in samples keeps sample 165_680.
        let (rate, first, past) = (48_000.0, 165_600u64, 165_681u64);
        let s = row(first as f64 / rate, past as f64 / rate);
        assert_eq!(s, "3.450000,3.451688,mouth,-40.00\n");
        let end_s: f64 = s.split(',').nth(1).unwrap().parse().unwrap();
        assert!((end_s * rate) as u64 >= past, "{s}");
        // Outward at both ends, wherever the binary fraction lies.
        for k in 0..2000u64 {
            let (a, b) = (k * 7 + 3, k * 7 + 3 + 441);
            for rate in [44_100.0, 48_000.0, 96_000.0, 22_050.0] {
                let s = row(a as f64 / rate, b as f64 / rate);
                let v: Vec<f64> = s.split(',').take(2).map(|x| x.parse().unwrap()).collect();
                assert!(v[0] * rate <= a as f64 + 1e-6, "{s} at {rate}");
                assert!(v[1] * rate >= b as f64 - 1e-6, "{s} at {rate}");
                assert!(v[1] - v[0] <= (b - a) as f64 / rate + 2.0 / US_PER_S, "{s}");
            }
        }
        let mut buf = Vec::new();
        write_all(&mut buf, &[]).unwrap();
        assert_eq!(
            String::from_utf8(buf).unwrap(),
            "start_s,end_s,kind,peak_db\n"
        );
    }
}
