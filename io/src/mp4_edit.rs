//! The edit list of an MP4/M4A file's audio track: which decoded samples are the recording.
//!
//! An AAC encoder primes its stream (ffmpeg: 1024 samples, Apple and Nero: 2112) and pads its
//! last packet; the container's edit list (`moov/trak/edts/elst`) says where the recording
//! starts in the decoded samples (`media_time`) and how long it lasts (`segment_duration`).
//! symphonia reads no edit list, so without this the decoded audio starts those samples late
//! and ends that much long: controls and breaths drift from the video the audio came with.
//!
//! Only the plain case is read: one audio track (`hdlr` `soun`), one edit entry whose media
//! starts after 0 (a priming to drop; a lossless track starting at 0 decodes exactly as it is,
//! and a length in the movie's millisecond timescale is not sample-exact). Anything else (an empty edit before the media, several entries, a
//! damaged box) gives `None`, and the file decodes as before.

use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

/// The recording inside the decoded samples, in sample frames at the track's rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edit {
    /// Decoded frames before the recording starts (the encoder's priming).
    pub skip: u64,
    /// Frames of the recording.
    pub keep: u64,
}

/// Longest `moov` box read, bytes (an hour of AAC holds about 1 MB of tables).
const MAX_MOOV_BYTES: u64 = 64 << 20;
/// Longest priming believed, seconds (encoders prime a few thousand samples).
const MAX_SKIP_S: f64 = 1.0;

/// The edit of the audio track of the MP4 file at `path` decoded at `rate_hz`, if it has a
/// plain one (see the module docs).
pub fn audio_edit(path: &Path, rate_hz: u32) -> Option<Edit> {
    let mut file = std::fs::File::open(path).ok()?;
    let moov = read_top_box(&mut file, b"moov")?;
    edit_in_moov(&moov, rate_hz)
}

/// The size and header length, bytes, of the box whose first bytes are `head` (up to 16) with
/// `left` bytes from its start to the end of its parent; `None` when it does not fit.
fn box_extent(head: &[u8], left: u64) -> Option<(u64, u64)> {
    let (size, header) = match u32_at(head, 0)? {
        0 => (left, 8),
        1 => (u64_at(head, 8)?, 16),
        n => (n, 8),
    };
    (size >= header && size <= left).then_some((size, header))
}

/// The body of the first top-level box of `kind`.
fn read_top_box(file: &mut std::fs::File, kind: &[u8; 4]) -> Option<Vec<u8>> {
    let len = file.metadata().ok()?.len();
    let mut at = 0u64;
    while at + 8 <= len {
        file.seek(SeekFrom::Start(at)).ok()?;
        let mut head = [0u8; 16];
        let n = (len - at).min(16) as usize;
        file.read_exact(&mut head[..n]).ok()?;
        let (size, header) = box_extent(&head[..n], len - at)?;
        if &head[4..8] == kind {
            let body = size - header;
            if body > MAX_MOOV_BYTES {
                return None;
            }
            let mut out = vec![0u8; body as usize];
            file.seek(SeekFrom::Start(at + header)).ok()?;
            file.read_exact(&mut out).ok()?;
            return Some(out);
        }
        at += size;
    }
    None
}

/// The child boxes of `body`: (kind, body) in order; stops at the first malformed one.
fn children(body: &[u8]) -> impl Iterator<Item = (&[u8], &[u8])> {
    let mut at = 0usize;
    std::iter::from_fn(move || {
        let head = body.get(at..at + 8)?;
        let (size, header) = box_extent(&body[at..], (body.len() - at) as u64)?;
        let (size, header) = (size as usize, header as usize);
        let item = (&head[4..8], &body[at + header..at + size]);
        at += size;
        Some(item)
    })
}

/// The first child of `body` of `kind`.
fn child<'a>(body: &'a [u8], kind: &[u8; 4]) -> Option<&'a [u8]> {
    children(body).find(|(k, _)| k == kind).map(|(_, b)| b)
}

fn u32_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u32::from_be_bytes(b.get(at..at + 4)?.try_into().ok()?) as u64)
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_be_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// The timescale of an `mvhd` or `mdhd` body (same layout up to it).
fn timescale(header: &[u8]) -> Option<u64> {
    let at = if *header.first()? == 1 { 20 } else { 12 };
    u32_at(header, at).filter(|&t| t > 0)
}

/// [`Edit`] from a `moov` body.
fn edit_in_moov(moov: &[u8], rate_hz: u32) -> Option<Edit> {
    let movie_scale = timescale(child(moov, b"mvhd")?)?;
    let trak = children(moov)
        .filter(|(k, _)| k == b"trak")
        .map(|(_, b)| b)
        .find(|t| {
            child(t, b"mdia")
                .and_then(|m| child(m, b"hdlr"))
                .and_then(|h| h.get(8..12))
                == Some(b"soun")
        })?;
    let media_scale = timescale(child(child(trak, b"mdia")?, b"mdhd")?)?;
    let elst = child(child(trak, b"edts")?, b"elst")?;
    let version = *elst.first()?;
    if u32_at(elst, 4)? != 1 {
        return None;
    }
    let (duration, media_time) = if version == 1 {
        (u64_at(elst, 8)?, u64_at(elst, 16)? as i64)
    } else {
        (u32_at(elst, 8)?, u32_at(elst, 12)? as u32 as i32 as i64)
    };
    if media_time < 0 || duration == 0 {
        return None;
    }
    let rate = f64::from(rate_hz);
    let skip = (media_time as f64 * rate / media_scale as f64).round() as u64;
    let keep = (duration as f64 * rate / movie_scale as f64).round() as u64;
    (skip > 0 && skip as f64 <= MAX_SKIP_S * rate && keep > 0).then_some(Edit { skip, keep })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box of `kind` around `body`.
    fn boxed(kind: &[u8; 4], body: &[u8]) -> Vec<u8> {
        let mut out = ((body.len() + 8) as u32).to_be_bytes().to_vec();
        out.extend_from_slice(kind);
        out.extend_from_slice(body);
        out
    }

    /// A version-0 `mvhd`/`mdhd` body with `scale`.
    fn header(scale: u32) -> Vec<u8> {
        let mut b = vec![0u8; 12];
        b.extend_from_slice(&scale.to_be_bytes());
        b.extend_from_slice(&[0u8; 8]);
        b
    }

    fn hdlr(kind: &[u8; 4]) -> Vec<u8> {
        let mut b = vec![0u8; 8];
        b.extend_from_slice(kind);
        b.extend_from_slice(&[0u8; 12]);
        boxed(b"hdlr", &b)
    }

    fn elst(entries: &[(u32, i32)]) -> Vec<u8> {
        let mut b = vec![0u8; 4];
        b.extend_from_slice(&(entries.len() as u32).to_be_bytes());
        for &(duration, media_time) in entries {
            b.extend_from_slice(&duration.to_be_bytes());
            b.extend_from_slice(&media_time.to_be_bytes());
            b.extend_from_slice(&0x0001_0000u32.to_be_bytes());
        }
        boxed(b"elst", &b)
    }

    fn trak(handler: &[u8; 4], media_scale: u32, entries: &[(u32, i32)]) -> Vec<u8> {
        let mdia = [boxed(b"mdhd", &header(media_scale)), hdlr(handler)].concat();
        let body = [boxed(b"edts", &elst(entries)), boxed(b"mdia", &mdia)].concat();
        boxed(b"trak", &body)
    }

    fn moov(traks: &[Vec<u8>]) -> Vec<u8> {
        [vec![boxed(b"mvhd", &header(1000))], traks.to_vec()]
            .concat()
            .concat()
    }

    #[test]
    fn the_audio_tracks_single_edit_gives_the_priming_and_the_length() {
        // A video track first; audio at 16 kHz media scale: 1024 primed, 2.5 s long.
        let m = moov(&[
            trak(b"vide", 25, &[(2500, 0)]),
            trak(b"soun", 16_000, &[(2500, 1024)]),
        ]);
        assert_eq!(
            edit_in_moov(&m, 16_000),
            Some(Edit {
                skip: 1024,
                keep: 40_000
            })
        );
        // Decoded at another rate than the media scale: both scale.
        assert_eq!(
            edit_in_moov(&m, 32_000),
            Some(Edit {
                skip: 2048,
                keep: 80_000
            })
        );
    }

    #[test]
    fn anything_but_a_plain_edit_is_left_alone() {
        let none = |m: Vec<u8>| assert_eq!(edit_in_moov(&m, 16_000), None);
        // An empty edit (media time -1) before the media, or two entries.
        none(moov(&[trak(b"soun", 16_000, &[(100, -1), (2500, 0)])]));
        none(moov(&[trak(b"soun", 16_000, &[(2500, -1)])]));
        // Nothing primed (a lossless track): decoded as it is.
        none(moov(&[trak(b"soun", 16_000, &[(2500, 0)])]));
        // No audio track.
        none(moov(&[trak(b"vide", 16_000, &[(2500, 1024)])]));
        // A priming over a second is not believed.
        none(moov(&[trak(b"soun", 16_000, &[(2500, 20_000)])]));
        // A box whose size runs past its parent.
        let mut m = moov(&[trak(b"soun", 16_000, &[(2500, 1024)])]);
        m[3] = 0xff;
        none(m);
    }
}
