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
}

/// The number the `i`-th breath (0-based) goes by in labels and in the plot: from 1.
pub fn number(i: usize) -> usize {
    i + 1
}

/// The label of the `i`-th breath (0-based).
pub fn label(i: usize, b: &BreathEvent) -> String {
    format!(
        "breath {} ({}, {:.1} dBFS)",
        number(i),
        b.kind.as_str(),
        b.peak_db
    )
}

/// An Audacity label track.
pub fn audacity(breaths: &[BreathEvent]) -> String {
    let mut s = String::new();
    for (i, b) in breaths.iter().enumerate() {
        s.push_str(&format!(
            "{:.6}\t{:.6}\t{}\n",
            b.start_s,
            b.end_s,
            label(i, b)
        ));
    }
    s
}

/// `M:SS.mmm`, REAPER's default time display.
fn minutes(s: f64) -> String {
    let ms = (s.max(0.0) * 1000.0).round() as u64;
    format!("{}:{:02}.{:03}", ms / 60_000, ms / 1000 % 60, ms % 1000)
}

/// A REAPER region/marker list.
pub fn reaper(breaths: &[BreathEvent]) -> String {
    let mut s = String::from("#,Name,Start,End,Length\n");
    for (i, b) in breaths.iter().enumerate() {
        s.push_str(&format!(
            "R{},{},{},{},{}\n",
            i + 1,
            label(i, b).replace(',', ";"),
            minutes(b.start_s),
            minutes(b.end_s),
            minutes(b.end_s - b.start_s)
        ));
    }
    s
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
