//! Breath markers for editors (`pneuma render --markers audacity|reaper|cue`), so each inserted
//! breath can be reviewed where it sits:
//!
//! - `audacity`: `<stem>.breaths.txt`, an Audacity label track (File ▸ Import ▸ Labels): one
//!   line per breath, `start<TAB>end<TAB>label`, seconds with six decimals;
//! - `reaper`: `<stem>.breaths.reaper.csv`, REAPER's region/marker list (Region/Marker Manager ▸
//!   Import): `#,Name,Start,End,Length`, one region `R1`, `R2`, … per breath, times as
//!   `M:SS.mmm`;
//! - `cue`: cue points inside the output WAV (a `cue ` chunk at each breath's first sample, with
//!   a `LIST`/`adtl` chunk of labels and region lengths), shown by WaveLab, Adobe Audition, Sound
//!   Forge, ocenaudio and others. Only WAV holds them.
//!
//! Every label reads `breath N (kind, peak dBFS)`.

use pneuma_core::BreathEvent;

use crate::audio_out::Cue;

/// A marker format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum MarkerKind {
    /// Audacity label track (`<stem>.breaths.txt`).
    Audacity,
    /// REAPER region/marker CSV (`<stem>.breaths.reaper.csv`).
    Reaper,
    /// Cue points with labels inside the output WAV.
    Cue,
}

impl MarkerKind {
    /// The file name ending of the marker file (none for cue points, which live in the WAV).
    pub fn suffix(self) -> Option<&'static str> {
        match self {
            Self::Audacity => Some("breaths.txt"),
            Self::Reaper => Some("breaths.reaper.csv"),
            Self::Cue => None,
        }
    }

    /// The text of the marker file for `breaths`.
    pub fn file_text(self, breaths: &[BreathEvent]) -> String {
        match self {
            Self::Audacity => audacity(breaths),
            Self::Reaper => reaper(breaths),
            Self::Cue => String::new(),
        }
    }

    /// `lines`, a file's first whole lines, read as [`MarkerKind::file_text`] writes them and
    /// name at least one breath: Pneuma's mark on its marker files, which hold nothing else
    /// (every line exactly as Pneuma writes it, the breaths numbered from 1 in order). A file
    /// of no breaths has no line to tell it by.
    pub fn wrote(self, lines: &str) -> bool {
        let mut lines = lines.split_terminator('\n');
        let row: fn(usize, &str) -> bool = match self {
            Self::Audacity => is_audacity_line,
            Self::Reaper if lines.next() == Some(REAPER_HEADER) => is_reaper_row,
            Self::Reaper | Self::Cue => return false,
        };
        let mut rows = 0;
        for (i, line) in lines.enumerate() {
            if !row(i, line) {
                return false;
            }
            rows += 1;
        }
        rows > 0
    }
}

/// The number the `i`-th breath (0-based) goes by in labels and in the plot: from 1.
pub fn number(i: usize) -> usize {
    i + 1
}

/// The label of the `i`-th breath (0-based).
pub fn label(i: usize, b: &BreathEvent) -> String {
    label_text(number(i), b.kind.as_str(), b.peak_db)
}

/// The label of breath number `n` of kind `kind` (its name) peaking at `peak_db`.
fn label_text(n: usize, kind: &str, peak_db: f32) -> String {
    format!("breath {n} ({kind}, {peak_db:.1} dBFS)")
}

/// `text` is the label [`label`] gives the `i`-th breath (of a kind named in lower-case
/// letters; the kinds are core's to name).
fn is_label(i: usize, text: &str) -> bool {
    let parts = || {
        let (_, rest) = text.split_once(" (")?;
        let (kind, peak) = rest.strip_suffix(" dBFS)")?.split_once(", ")?;
        Some((kind, peak.parse::<f32>().ok()?))
    };
    parts().is_some_and(|(kind, peak)| {
        !kind.is_empty()
            && kind.bytes().all(|b| b.is_ascii_lowercase())
            && label_text(number(i), kind, peak) == text
    })
}

/// A span in an Audacity label track: as the breaths CSV writes it (seconds with six
/// decimals, rounded outward to the microsecond, so the label holds every changed sample).
fn seconds(start_s: f64, end_s: f64) -> (String, String) {
    let (start, end) = pneuma_core::encode::breaths_csv::span_text(start_s, end_s);
    (start.to_string(), end.to_string())
}

/// An Audacity label track.
pub fn audacity(breaths: &[BreathEvent]) -> String {
    let mut s = String::new();
    for (i, b) in breaths.iter().enumerate() {
        let (start, end) = seconds(b.start_s, b.end_s);
        s.push_str(&format!("{start}\t{end}\t{}\n", label(i, b)));
    }
    s
}

/// `line` is the line [`audacity`] writes for the `i`-th breath.
fn is_audacity_line(i: usize, line: &str) -> bool {
    let fields: Vec<&str> = line.split('\t').collect();
    let [start, end, text] = fields[..] else {
        return false;
    };
    let written = |t: &str| t.parse::<f64>().ok().map(|s| seconds(s, s));
    written(start).is_some_and(|(s, _)| s == start)
        && written(end).is_some_and(|(_, e)| e == end)
        && is_label(i, text)
}

/// `M:SS.mmm`, REAPER's default time display.
fn minutes(s: f64) -> String {
    minutes_of_ms((s.max(0.0) * 1000.0).round() as u64)
}

/// `M:SS.mmm` of `ms` milliseconds.
fn minutes_of_ms(ms: u64) -> String {
    format!("{}:{:02}.{:03}", ms / 60_000, ms / 1000 % 60, ms % 1000)
}

/// `t` is a time as [`minutes`] writes it.
fn is_minutes(t: &str) -> bool {
    let ms = || {
        let (m, rest) = t.split_once(':')?;
        let (s, ms) = rest.split_once('.')?;
        let [m, s, ms] = [m, s, ms].map(|x| x.parse::<u64>().ok());
        m?.checked_mul(60_000)?
            .checked_add(s?.checked_mul(1000)?)?
            .checked_add(ms?)
    };
    ms().is_some_and(|ms| minutes_of_ms(ms) == t)
}

/// The first line of a REAPER region/marker list.
const REAPER_HEADER: &str = "#,Name,Start,End,Length";

/// A label as a REAPER region's name (commas separate the list's fields).
fn region_name(label: &str) -> String {
    label.replace(',', ";")
}

/// A REAPER region/marker list.
pub fn reaper(breaths: &[BreathEvent]) -> String {
    let mut s = format!("{REAPER_HEADER}\n");
    for (i, b) in breaths.iter().enumerate() {
        s.push_str(&format!(
            "R{},{},{},{},{}\n",
            number(i),
            region_name(&label(i, b)),
            minutes(b.start_s),
            minutes(b.end_s),
            minutes(b.end_s - b.start_s)
        ));
    }
    s
}

/// `row` is the row [`reaper`] writes for the `i`-th breath.
fn is_reaper_row(i: usize, row: &str) -> bool {
    let fields: Vec<&str> = row.split(',').collect();
    let [region, name, start, end, length] = fields[..] else {
        return false;
    };
    let label = name.replace(';', ",");
    region == format!("R{}", number(i))
        && is_label(i, &label)
        && region_name(&label) == name
        && [start, end, length].into_iter().all(is_minutes)
}

/// Cue points at `rate_hz` for the output WAV.
pub fn cues(breaths: &[BreathEvent], rate_hz: u32) -> Vec<Cue> {
    let frame = |s: f64| (s.max(0.0) * f64::from(rate_hz)).round() as u64;
    breaths
        .iter()
        .enumerate()
        .map(|(i, b)| Cue {
            start_frame: frame(b.start_s),
            length_frames: frame(b.end_s).saturating_sub(frame(b.start_s)),
            label: label(i, b),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::BreathKind;

    fn breaths() -> Vec<BreathEvent> {
        let b = |start_s: f64, kind, peak_db| BreathEvent {
            start_s,
            end_s: start_s + 0.4321,
            kind,
            peak_db,
        };
        vec![
            b(1.25, BreathKind::Mouth, -30.04),
            b(61.0004, BreathKind::Nose, -0.04),
            b(3725.5, BreathKind::Sample, -41.5),
        ]
    }

    #[test]
    fn an_audacity_label_holds_every_sample_its_breath_changed() {
        // Samples 165_600..165_681 at 48 kHz: the end, 3.4516875 s, was written 3.451687.
        let b = BreathEvent {
            start_s: 165_600.0 / 48_000.0,
            end_s: 165_681.0 / 48_000.0,
            kind: BreathKind::Mouth,
            peak_db: -40.0,
        };
        let text = audacity(&[b]);
        assert!(text.starts_with("3.450000\t3.451688\t"), "{text}");
        assert!(MarkerKind::Audacity.wrote(&text), "{text}");
    }

    #[test]
    fn the_marker_files_pneuma_writes_carry_its_mark_and_others_do_not() {
        for kind in [MarkerKind::Audacity, MarkerKind::Reaper] {
            let text = kind.file_text(&breaths());
            assert!(kind.wrote(&text), "{kind:?}: {text}");
            // The first line alone (a file's head cut after a whole line) still reads as Pneuma's.
            let first_rows = text
                .lines()
                .take(2)
                .map(|l| format!("{l}\n"))
                .collect::<String>();
            assert!(kind.wrote(&first_rows), "{kind:?}: {first_rows}");
            // No breaths: nothing to tell it by.
            assert!(!kind.wrote(&kind.file_text(&[])), "{kind:?}");
            // A user's edits: another label, a renumbered breath, a time of another format, a
            // comma or a tab more, Windows line ends, another kind of file.
            for (from, to) in [
                ("breath 2", "take 2"),
                ("breath 2", "breath 3"),
                ("(nose", "(Nose"),
                ("-0.0 dBFS", "-0 dBFS"),
                ("1.250000", "1.25"),
                ("1:01.000", "1:1.000"),
                ("\n", "\r\n"),
                ("dBFS)", "dBFS),"),
                ("dBFS)", "dBFS)\t"),
            ] {
                let edited = text.replacen(from, to, 1);
                if edited != text {
                    assert!(!kind.wrote(&edited), "{kind:?}: {from} -> {to}: {edited}");
                }
            }
            assert!(!MarkerKind::Audacity.wrote(&MarkerKind::Reaper.file_text(&breaths())));
            assert!(!MarkerKind::Reaper.wrote(&MarkerKind::Audacity.file_text(&breaths())));
        }
        assert!(!MarkerKind::Cue.wrote(""));
        // REAPER's own export of a user's regions.
        let users = "#,Name,Start,End,Length\nR1,Intro,0:00.000,0:12.500,0:12.500\n";
        assert!(!MarkerKind::Reaper.wrote(users));
        // An Audacity label track of the user's.
        assert!(!MarkerKind::Audacity.wrote("1.000000\t2.000000\tchorus\n"));
    }
}
