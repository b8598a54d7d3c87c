//! Pneuma's mark on each optional file of a render: what tells a file of that name as one
//! Pneuma wrote, so that only such a file is ever removed as an earlier render's leftover
//! ([`super::leftovers`]); a file of the same name without the mark is the user's (episode
//! artwork `ep.png`, a motion capture `take1.bvh`, a song's `song.mid`). Each mark is defined
//! beside its writer and only read here, from the first [`HEAD_BYTES`] of a file:
//!
//! - the plot: the PNG text chunk `Software` = `pneuma <version>` ([`crate::png_mark`]);
//! - the BVH: the whole hierarchy Pneuma writes, joints, offsets and channels, up to the frame
//!   count ([`pneuma_core::encode::bvh::header`]; BVH has no comments);
//! - the MIDI file: its file header (format 0, one track, Pneuma's division) and the track's
//!   name event `Pneuma controls` ([`pneuma_core::encode::midi_file::TRACK_NAME`]);
//! - the marker files: every line as Pneuma writes it ([`crate::markers::MarkerKind::wrote`]);
//!   a file of no breaths only when it is exactly what Pneuma writes for none (nothing, or
//!   REAPER's header alone), which holds nothing of the user's.
//!
//! Only a regular file is read: a link is never followed (its target may be anything of the
//! user's), so a link of such a name carries no mark.

use std::io::Read;
use std::path::Path;

use pneuma_core::encode::{bvh, midi_file};

use crate::markers::MarkerKind;

/// Bytes of a file read to find its mark.
pub const HEAD_BYTES: usize = 4096;

/// Bytes of a MIDI track searched for its name event: it follows the tempo and time signature
/// events (15 bytes).
const TRACK_NAME_WITHIN: usize = 64;

/// An optional file of a render: one its options may leave out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Optional {
    /// The plot, `<stem>.png`.
    Plot,
    /// `<stem>.bvh`.
    Bvh,
    /// `<stem>.mid`.
    Midi,
    /// A marker file.
    Markers(MarkerKind),
}

impl Optional {
    /// What leaves it out of a render, in the user's terms: `--no-plot`, `no --bvh`,
    /// `no --markers reaper`.
    pub fn left_out_by(self) -> String {
        let without = |option: &str| format!("no {option}");
        match self {
            Self::Plot => "--no-plot".to_owned(),
            Self::Bvh => without("--bvh"),
            Self::Midi => without("--midi"),
            Self::Markers(k) => {
                let name = clap::ValueEnum::to_possible_value(&k)
                    .map(|v| v.get_name().to_owned())
                    .unwrap_or_default();
                without(&format!("--markers {name}"))
            }
        }
    }
}

/// `path` is a regular file (not a link) that carries Pneuma's mark for `file`.
pub fn is_pneumas(path: &Path, file: Optional) -> bool {
    let regular = std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_file());
    regular && head(path).is_some_and(|(head, whole)| carries_mark(file, &head, whole))
}

/// The first [`HEAD_BYTES`] of `path`, and whether they are the whole file.
fn head(path: &Path) -> Option<(Vec<u8>, bool)> {
    let mut head = Vec::with_capacity(HEAD_BYTES + 1);
    std::fs::File::open(path)
        .ok()?
        .take(HEAD_BYTES as u64 + 1)
        .read_to_end(&mut head)
        .ok()?;
    let whole = head.len() <= HEAD_BYTES;
    head.truncate(HEAD_BYTES);
    Some((head, whole))
}

/// `head`, a file's first bytes (`whole`: all of it), carries Pneuma's mark for `file`.
fn carries_mark(file: Optional, head: &[u8], whole: bool) -> bool {
    match file {
        Optional::Plot => crate::png_mark::is_marked(head),
        Optional::Bvh => is_bvh(head),
        Optional::Midi => is_midi(head),
        Optional::Markers(kind) => {
            // A marker file of no breaths (empty, or REAPER's header alone) has no line to tell
            // it by, but holds nothing to lose either: it goes too, as a stale one would tell
            // an editor the new audio has no breaths.
            let no_breaths = kind.suffix().is_some() && head == kind.file_text(&[]).as_bytes();
            (whole && no_breaths) || whole_lines(head, whole).is_some_and(|t| kind.wrote(t))
        }
    }
}

/// The head of a BVH Pneuma writes: everything before the frame count, the same in every file
/// (where the headers of two different lengths part), or the head Pneuma wrote before the
/// hips' height moved from the root's offset into its position channels
/// ([`BVH_HEAD_BEFORE_ROOT_POSITION`]).
fn is_bvh(head: &[u8]) -> bool {
    let (a, b) = (bvh::header(0, 1.0), bvh::header(1, 2.0));
    let same = a.bytes().zip(b.bytes()).take_while(|(x, y)| x == y).count();
    (same > 0 && head.starts_with(&a.as_bytes()[..same]))
        || head.starts_with(BVH_HEAD_BEFORE_ROOT_POSITION.as_bytes())
}

/// The head of the BVH files Pneuma wrote until December 2026, up to the frame count, as they
/// are on disk (fixed text: what later versions write does not move it).
const BVH_HEAD_BEFORE_ROOT_POSITION: &str = "HIERARCHY
ROOT Hips
{
  OFFSET 0.0 1.0 0.0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation
  JOINT Chest
  {
    OFFSET 0.0 0.25 0.0
    CHANNELS 3 Zrotation Yrotation Xrotation
    JOINT Neck
    {
      OFFSET 0.0 0.25 0.0
      CHANNELS 3 Zrotation Yrotation Xrotation
      JOINT Head
      {
        OFFSET 0.0 0.1 0.0
        CHANNELS 3 Zrotation Yrotation Xrotation
        End Site
        {
          OFFSET 0.0 0.2 0.0
        }
      }
    }
  }
}
MOTION
Frames: ";

/// The head of a MIDI file Pneuma writes: its file header up to the track's length (which
/// varies), and the track's name event among the track's first events.
fn is_midi(head: &[u8]) -> bool {
    let fixed = &midi_file::header(0)[..midi_file::HEADER_BYTES - 4];
    let name = midi_file::TRACK_NAME.as_bytes();
    // A sequence/track name meta event: FF 03, the length, the name.
    let event: Vec<u8> = [0xff, 0x03, name.len() as u8]
        .into_iter()
        .chain(name.iter().copied())
        .collect();
    let track = head.get(midi_file::HEADER_BYTES..).unwrap_or_default();
    let start = &track[..track.len().min(TRACK_NAME_WITHIN)];
    head.starts_with(fixed) && start.windows(event.len()).any(|w| w == event)
}

/// The whole lines of `head` as text: all of it when it is the `whole` file (which then ends
/// with a line end, as every text file Pneuma writes), else up to its last line end.
fn whole_lines(head: &[u8], whole: bool) -> Option<&str> {
    let end = if whole {
        head.ends_with(b"\n").then_some(head.len())?
    } else {
        head.iter().rposition(|&b| b == b'\n')? + 1
    };
    std::str::from_utf8(&head[..end]).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::encode::midi_cc::CcMap;
    use pneuma_core::encode::midi_file::MidiFileSink;

    /// A MIDI file as Pneuma writes one (no frames).
    fn pneumas_midi() -> Vec<u8> {
        let sink =
            MidiFileSink::new(std::io::Cursor::new(Vec::new()), CcMap::default()).expect("sink");
        sink.finish().expect("finish").into_inner()
    }

    #[test]
    fn pneumas_bvh_and_midi_carry_the_mark_and_other_files_of_their_formats_do_not() {
        let mut bvh = bvh::header(250, 120.0);
        bvh.push_str("0.0 0.0 0.0 0.0 0.0 0.0\n");
        assert!(carries_mark(Optional::Bvh, bvh.as_bytes(), true));
        // A motion capture: another skeleton, or Pneuma's with another joint's offset.
        let mocap = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0.0 0.0 0.0\n  CHANNELS 6 Xposition \
                     Yposition Zposition Zrotation Xrotation Yrotation\n";
        assert!(!carries_mark(Optional::Bvh, mocap.as_bytes(), true));
        let moved = bvh.replacen("OFFSET 0.0 0.1 0.0", "OFFSET 0.0 0.12 0.0", 1);
        assert!(!carries_mark(Optional::Bvh, moved.as_bytes(), true));
        // One written before the hips' height moved from the root's offset to its channels:
        // today's header with that one line as it was.
        let before = bvh::header(250, 120.0).replacen(
            "ROOT Hips\n{\n  OFFSET 0.0 0.0 0.0",
            "ROOT Hips\n{\n  OFFSET 0.0 1.0 0.0",
            1,
        );
        assert_ne!(before, bvh::header(250, 120.0));
        assert!(carries_mark(Optional::Bvh, before.as_bytes(), true));

        let midi = pneumas_midi();
        assert!(carries_mark(Optional::Midi, &midi, true));
        // A song: the same file header, another track name; or no track name at all.
        let at = midi.windows(6).position(|w| w == b"Pneuma").expect("named");
        let mut song = midi.clone();
        song[at..at + 6].copy_from_slice(b"Melody");
        assert!(!carries_mark(Optional::Midi, &song, true));
        assert!(!carries_mark(Optional::Midi, &midi[..at], true));
        // The PNG's and a marker file's marks are tested beside their writers; a PNG is
        // told by its own mark, not by another format's.
        assert!(!carries_mark(Optional::Plot, &midi, true));
        assert!(!carries_mark(
            Optional::Markers(MarkerKind::Audacity),
            &midi,
            true
        ));
    }

    #[test]
    fn a_marker_file_of_no_breaths_is_pneumas_only_when_exactly_as_pneuma_writes_it() {
        for kind in [MarkerKind::Audacity, MarkerKind::Reaper] {
            let none = kind.file_text(&[]);
            let file = Optional::Markers(kind);
            assert!(carries_mark(file, none.as_bytes(), true), "{kind:?}");
            assert!(!carries_mark(file, format!("{none}\n").as_bytes(), true));
            assert!(!carries_mark(file, format!("{none}x").as_bytes(), true));
        }
        assert!(!carries_mark(Optional::Markers(MarkerKind::Cue), b"", true));
    }

    #[test]
    fn a_marker_files_head_is_read_to_its_last_whole_line() {
        let kind = MarkerKind::Audacity;
        let line = "1.000000\t1.400000\tbreath 1 (mouth, -30.0 dBFS)\n";
        let file = Optional::Markers(kind);
        assert!(carries_mark(file, line.as_bytes(), true));
        // The whole file must end with its line; a cut head drops the part line.
        let cut = &line.as_bytes()[..line.len() - 1];
        assert!(!carries_mark(file, cut, true));
        let long = format!("{line}2.0000");
        assert!(carries_mark(file, long.as_bytes(), false));
        assert!(!carries_mark(file, long.as_bytes(), true));
    }

    #[test]
    fn a_link_is_not_followed_to_a_marked_file() {
        let dir = tempfile::tempdir().expect("temp");
        let target = dir.path().join("real.bvh");
        std::fs::write(&target, bvh::header(1, 120.0)).expect("write");
        assert!(is_pneumas(&target, Optional::Bvh));
        #[cfg(unix)]
        {
            let link = dir.path().join("ep.bvh");
            std::os::unix::fs::symlink(&target, &link).expect("link");
            assert!(!is_pneumas(&link, Optional::Bvh));
        }
        assert!(!is_pneumas(&dir.path().join("missing.bvh"), Optional::Bvh));
        assert!(!is_pneumas(dir.path(), Optional::Bvh));
    }

    #[test]
    fn each_optional_file_is_left_out_by_its_option() {
        assert_eq!(Optional::Plot.left_out_by(), "--no-plot");
        assert_eq!(Optional::Midi.left_out_by(), "no --midi");
        let reaper = Optional::Markers(MarkerKind::Reaper);
        assert_eq!(reaper.left_out_by(), "no --markers reaper");
    }
}
