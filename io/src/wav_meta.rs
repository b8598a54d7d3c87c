//! What a WAV file holds besides its samples that an output can carry over: the `LIST`/`INFO`
//! tags (title `INAM`, artist `IART`, album `IPRD`, comment `ICMT`), the cue points of a DAW
//! (chapter or ad markers: `cue ` with their `labl` labels and `ltxt` lengths from
//! `LIST`/`adtl`), and the form of the `fmt ` chunk (plain or `WAVE_FORMAT_EXTENSIBLE`, the
//! channel mask).
//!
//! Read apart from the samples ([`crate::WavSource`] streams them, and reads nothing after the
//! data of a regular file), by seeking from chunk to chunk of a regular file, before or after
//! the data; the same walk counts the `data` chunks and looks at what follows the first
//! ([`crate::wav_tail`]), so that a second one, or audio its header does not announce, is
//! refused rather than lost (a stream is looked at once its data has been read:
//! [`crate::wav_tail::check_stream`]). Best effort: a
//! chunk that is damaged or a file that ends early gives what was found before it (the reader
//! of the samples reports damage).

use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

use crate::le_bytes::{u16_at, u32_at, u64_at};
use crate::read_full::read_full;
use crate::wav_error::WavError;
use crate::wav_tail::{after_data, AfterData};
use crate::Tags;

/// A cue point of a WAV file (an input's, or an output's): a marker, or a region when it has
/// a length.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CuePoint {
    /// Its sample frame.
    pub start_frame: u64,
    /// Length in sample frames (0: a marker).
    pub length_frames: u64,
    /// Its label (empty when it has none).
    pub label: String,
}

/// The form of the input's `fmt ` chunk, for an output that keeps it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FmtForm {
    /// `WAVE_FORMAT_EXTENSIBLE` (else the plain format tag).
    pub extensible: bool,
    /// The speaker positions (`dwChannelMask`; 0 when unassigned or plain).
    pub channel_mask: u32,
}

/// What [`read`] found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WavMeta {
    /// `LIST`/`INFO` tags.
    pub tags: Tags,
    /// Cue points in the order of their sample frames.
    pub cues: Vec<CuePoint>,
    /// The `fmt ` chunk's form (`None` when there is none).
    pub form: Option<FmtForm>,
}

/// The most cue points, and the most labels and lengths, read in all (a corrupt count or a
/// pile of chunks never drives an allocation or the matching).
const MAX_CUES: u32 = 100_000;
/// The largest `LIST` or `cue ` body read, bytes.
const MAX_BODY: u32 = 16 << 20;

/// Reads the tags, cue points and `fmt ` form of the WAV file at `path`.
pub fn read(path: &Path) -> WavMeta {
    read_counting_data(path).0
}

/// What the chunk walk found about a file's sample data beside its tags.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
struct DataFacts {
    /// `data` chunks that hold a byte (the sample reader reads the first; one after it would
    /// be lost).
    chunks: u32,
    /// Bytes from the end of the first `data` chunk (as its header announces it) to the end of
    /// the file when what follows is no chunk (its id not text, and not zero padding): audio a
    /// header left short, as a recorder that stopped before it updated the size leaves it.
    unannounced_bytes: Option<u64>,
}

/// [`read`], and the [`DataFacts`].
fn read_counting_data(path: &Path) -> (WavMeta, DataFacts) {
    let mut meta = WavMeta::default();
    let mut facts = DataFacts::default();
    if let Ok(mut file) = File::open(path) {
        let _ = scan(&mut file, &mut meta, &mut facts);
    }
    (meta, facts)
}

/// [`read`] for the sample reader of the file at `path` (`block_align` bytes per sample frame,
/// `info` from its header): refuses a second `data` chunk ([`WavError::DataChunks`]) and audio
/// past what the header announces ([`WavError::Unannounced`]), which it would lose.
pub(crate) fn read_checked(
    path: &Path,
    block_align: usize,
    info: &crate::AudioInfo,
) -> Result<WavMeta, WavError> {
    let (meta, facts) = read_counting_data(path);
    if facts.chunks > 1 {
        return Err(WavError::DataChunks {
            path: path.to_owned(),
            count: facts.chunks,
        });
    }
    let frames = |bytes: u64| bytes / block_align.max(1) as u64;
    if let Some(more) = facts.unannounced_bytes.map(frames).filter(|&n| n > 0) {
        let rate = f64::from(info.sample_rate_hz);
        return Err(WavError::Unannounced {
            path: path.to_owned(),
            announced_s: info.frames as f64 / rate,
            more_s: more as f64 / rate,
        });
    }
    Ok(meta)
}

/// The chunks of `file` into `meta`, and the [`DataFacts`] into `facts`;
/// stops at the first one it cannot read.
fn scan(
    file: &mut (impl Read + Seek),
    meta: &mut WavMeta,
    facts: &mut DataFacts,
) -> std::io::Result<()> {
    let mut head = [0u8; 12];
    file.read_exact(&mut head)?;
    let rf64 = matches!(&head[..4], b"RF64" | b"BW64");
    if !(rf64 || &head[..4] == b"RIFF") || &head[8..12] != b"WAVE" {
        return Ok(());
    }
    let mut data_size_64 = None;
    let mut ids: Vec<(u32, CuePoint)> = Vec::new();
    let mut labels: Vec<(u32, String)> = Vec::new();
    let mut lengths: Vec<(u32, u64)> = Vec::new();
    loop {
        let mut ch = [0u8; 8];
        if file.read_exact(&mut ch).is_err() {
            break;
        }
        let size = u32::from_le_bytes([ch[4], ch[5], ch[6], ch[7]]);
        let id = &ch[..4];
        let mut len = u64::from(size);
        // A chunk of odd length is followed by a pad byte.
        let mut pad = u64::from(size & 1);
        match id {
            // The first `ds64` only, as the sample reader takes it.
            b"ds64" if rf64 && data_size_64.is_none() => {
                let body = body(file, size)?;
                if body.len() >= 16 {
                    data_size_64 = Some(u64_at(&body, 8));
                }
                len = 0;
            }
            b"fmt " => {
                let body = body(file, size)?;
                if body.len() >= 16 {
                    let extensible = u16_at(&body, 0) == 0xfffe;
                    let channel_mask = if extensible && body.len() >= 24 {
                        u32_at(&body, 20)
                    } else {
                        0
                    };
                    meta.form = Some(FmtForm {
                        extensible,
                        channel_mask,
                    });
                }
                len = 0;
            }
            b"data" => {
                facts.chunks += u32::from(size != 0);
                if rf64 && size == u32::MAX {
                    len = data_size_64.unwrap_or(u64::MAX);
                    pad = len & 1;
                }
                // A stream of unknown length (a pipe's WAV saved): nothing after it is known.
                if len == u64::from(u32::MAX) || len == u64::MAX || len == 0 {
                    break;
                }
                if facts.chunks == 1 {
                    // The first data chunk: what follows it is looked at.
                    let Ok(skip) = i64::try_from(len) else {
                        break;
                    };
                    let end = file.seek(SeekFrom::Current(skip))?;
                    let mut after = [0u8; 9];
                    let n = read_full(file, &mut after[..8 + pad as usize])?;
                    match after_data(&after[..n], pad == 1) {
                        AfterData::End | AfterData::Padding => break,
                        AfterData::Audio { at } => {
                            let file_end = file.seek(SeekFrom::End(0))?;
                            facts.unannounced_bytes =
                                Some(file_end.saturating_sub(end + at as u64));
                            break;
                        }
                        AfterData::Chunk { at } => {
                            file.seek(SeekFrom::Start(end + at as u64))?;
                            continue;
                        }
                    }
                }
            }
            b"cue " => {
                let body = body(file, size)?;
                cue_points(&body, &mut ids);
                len = 0;
            }
            b"LIST" => {
                let body = body(file, size)?;
                list(&body, &mut meta.tags, &mut labels, &mut lengths);
                len = 0;
            }
            _ => {}
        }
        // A length no file has (a corrupt size): nothing after it is known.
        let Some(skip) = len.checked_add(pad).and_then(|n| i64::try_from(n).ok()) else {
            break;
        };
        file.seek(SeekFrom::Current(skip))?;
    }
    // The first label and length of each id, as a reader meets them.
    let mut label_of = HashMap::new();
    for (id, l) in labels {
        label_of.entry(id).or_insert(l);
    }
    let mut length_of = HashMap::new();
    for (id, n) in lengths {
        length_of.entry(id).or_insert(n);
    }
    for (id, mut cue) in ids {
        if let Some(l) = label_of.get(&id) {
            cue.label.clone_from(l);
        }
        if let Some(n) = length_of.get(&id) {
            cue.length_frames = *n;
        }
        meta.cues.push(cue);
    }
    meta.cues.sort_by_key(|c| c.start_frame);
    Ok(())
}

/// A chunk body of `size` bytes (at most [`MAX_BODY`]; the rest is skipped by the caller only
/// when nothing was read, so a larger body is an error here).
fn body(file: &mut impl Read, size: u32) -> std::io::Result<Vec<u8>> {
    if size > MAX_BODY {
        return Err(std::io::Error::other("chunk too large"));
    }
    let mut b = vec![0u8; size as usize];
    file.read_exact(&mut b)?;
    Ok(b)
}

/// The entries of a `cue ` body: id and sample offset.
fn cue_points(body: &[u8], out: &mut Vec<(u32, CuePoint)>) {
    if body.len() < 4 {
        return;
    }
    let n = u32_at(body, 0).min(MAX_CUES) as usize;
    for k in 0..n {
        let at = 4 + 24 * k;
        if at + 24 > body.len() || out.len() >= MAX_CUES as usize {
            break;
        }
        out.push((
            u32_at(body, at),
            CuePoint {
                start_frame: u64::from(u32_at(body, at + 20)),
                length_frames: 0,
                label: String::new(),
            },
        ));
    }
}

/// The sub-chunks of a `LIST` body: `INFO` tags, or `adtl` labels and lengths.
fn list(
    body: &[u8],
    tags: &mut Tags,
    labels: &mut Vec<(u32, String)>,
    lengths: &mut Vec<(u32, u64)>,
) {
    if body.len() < 4 {
        return;
    }
    let kind = &body[..4];
    let mut at = 4;
    while at + 8 <= body.len() {
        let id = &body[at..at + 4];
        let size = u32_at(body, at + 4) as usize;
        let start = at + 8;
        let Some(sub) = body.get(start..start + size) else {
            break;
        };
        match (kind, id) {
            (b"INFO", _) => {
                let slot = match id {
                    b"INAM" => &mut tags.title,
                    b"IART" => &mut tags.artist,
                    b"IPRD" => &mut tags.album,
                    b"ICMT" => &mut tags.comment,
                    _ => &mut None,
                };
                let value = text(sub);
                if !value.is_empty() {
                    *slot = Some(value);
                }
            }
            (b"adtl", b"labl") if sub.len() >= 4 && labels.len() < MAX_CUES as usize => {
                labels.push((u32_at(sub, 0), text(&sub[4..])));
            }
            (b"adtl", b"ltxt") if sub.len() >= 8 && lengths.len() < MAX_CUES as usize => {
                lengths.push((u32_at(sub, 0), u64::from(u32_at(sub, 4))));
            }
            _ => {}
        }
        at = start + size + (size & 1);
    }
}

/// A NUL-terminated text: up to its first NUL, invalid UTF-8 replaced, spaces trimmed.
fn text(b: &[u8]) -> String {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    String::from_utf8_lossy(&b[..end]).trim().to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    /// A chunk: id, size field, body and its pad byte.
    fn chunk(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
        let mut c = id.to_vec();
        c.extend_from_slice(&(body.len() as u32).to_le_bytes());
        c.extend_from_slice(body);
        if body.len() % 2 == 1 {
            c.push(0);
        }
        c
    }

    fn ds64(data_size: u64) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(&0u64.to_le_bytes()); // RIFF size
        b.extend_from_slice(&data_size.to_le_bytes());
        b.extend_from_slice(&2u64.to_le_bytes()); // sample count
        b.extend_from_slice(&0u32.to_le_bytes()); // table length
        chunk(b"ds64", &b)
    }

    fn fmt_pcm16_mono() -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(&1u16.to_le_bytes());
        b.extend_from_slice(&1u16.to_le_bytes());
        b.extend_from_slice(&8000u32.to_le_bytes());
        b.extend_from_slice(&16000u32.to_le_bytes());
        b.extend_from_slice(&2u16.to_le_bytes());
        b.extend_from_slice(&16u16.to_le_bytes());
        chunk(b"fmt ", &b)
    }

    /// An RF64 file of `chunks`, its `data` chunk's size field `u32::MAX`.
    fn rf64(chunks: &[Vec<u8>]) -> WavMeta {
        let mut f = b"RF64".to_vec();
        f.extend_from_slice(&u32::MAX.to_le_bytes());
        f.extend_from_slice(b"WAVE");
        for c in chunks {
            f.extend_from_slice(c);
        }
        let mut meta = WavMeta::default();
        let _ = scan(&mut Cursor::new(f), &mut meta, &mut DataFacts::default());
        meta
    }

    /// A `data` chunk of `samples` 16-bit samples whose size field says "see ds64".
    fn rf64_data(samples: usize) -> Vec<u8> {
        let mut c = b"data".to_vec();
        c.extend_from_slice(&u32::MAX.to_le_bytes());
        c.extend(std::iter::repeat_n(0u8, 2 * samples));
        c
    }

    fn info_title(title: &str) -> Vec<u8> {
        let mut body = b"INFO".to_vec();
        let mut t = title.as_bytes().to_vec();
        t.push(0);
        body.extend_from_slice(&chunk(b"INAM", &t));
        chunk(b"LIST", &body)
    }

    #[test]
    fn the_tags_after_an_rf64_data_chunk_of_even_length_are_read() {
        // The size field (u32::MAX) is odd; the data's real length, 4 bytes, has no pad byte.
        let meta = rf64(&[ds64(4), fmt_pcm16_mono(), rf64_data(2), info_title("Ep 1")]);
        assert_eq!(meta.tags.title.as_deref(), Some("Ep 1"));
        assert!(meta.form.is_some());
    }

    #[test]
    fn a_second_ds64_claiming_a_huge_data_size_ends_the_scan() {
        // The sample reader takes the first ds64; a later one saying the data is 2^64 - 9
        // bytes long once sent the scan back to the data header, forever.
        let meta = rf64(&[
            ds64(4),
            fmt_pcm16_mono(),
            ds64(0xFFFF_FFFF_FFFF_FFF7),
            rf64_data(2),
            info_title("after"),
        ]);
        assert_eq!(meta.tags.title.as_deref(), Some("after"));
    }

    #[test]
    fn a_cue_takes_the_first_label_given_for_its_id() {
        let mut cue = 1u32.to_le_bytes().to_vec();
        cue.extend_from_slice(&7u32.to_le_bytes()); // id
        cue.extend_from_slice(&[0u8; 16]); // position, chunk id, chunk and block starts
        cue.extend_from_slice(&480u32.to_le_bytes()); // sample offset
        let label = |id: u32, text: &str| {
            let mut b = id.to_le_bytes().to_vec();
            b.extend_from_slice(text.as_bytes());
            b.push(0);
            chunk(b"labl", &b)
        };
        let mut adtl = b"adtl".to_vec();
        adtl.extend_from_slice(&label(3, "other"));
        adtl.extend_from_slice(&label(7, "first"));
        adtl.extend_from_slice(&label(7, "second"));
        let meta = rf64(&[
            ds64(4),
            fmt_pcm16_mono(),
            chunk(b"cue ", &cue),
            chunk(b"LIST", &adtl),
            rf64_data(2),
        ]);
        assert_eq!(
            meta.cues,
            vec![CuePoint {
                start_frame: 480,
                length_frames: 0,
                label: "first".into(),
            }]
        );
    }

    /// A RIFF file of `chunks` after `WAVE`, written to `dir/name`.
    fn riff_file(dir: &Path, name: &str, chunks: &[&[u8]]) -> std::path::PathBuf {
        let body = [&b"WAVE"[..], &chunks.concat()].concat();
        let file = [&b"RIFF"[..], &(body.len() as u32).to_le_bytes(), &body].concat();
        let path = dir.join(name);
        std::fs::write(&path, file).expect("write");
        path
    }

    #[test]
    fn audio_past_a_data_chunk_that_announces_less_is_refused_rather_than_cut() {
        let dir = tempfile::tempdir().expect("temp dir");
        // 1600 sample frames (0.2 s at 8 kHz), the header announcing 800 of them.
        let samples: Vec<u8> = (0..1600i16)
            .flat_map(|k| (k * 7 + 1).to_le_bytes())
            .collect();
        let short_head = [&b"data"[..], &1600u32.to_le_bytes()].concat();
        let path = riff_file(
            dir.path(),
            "short.wav",
            &[&fmt_pcm16_mono(), &short_head, &samples],
        );
        let Err(e) = crate::WavSource::open(&path) else {
            panic!("half the audio read")
        };
        assert!(matches!(e, crate::WavError::Unannounced { .. }), "{e}");
        let Err(e) = crate::AudioSource::open(&path) else {
            panic!("half the audio read")
        };
        assert_eq!(
            e.to_string(),
            format!(
                "{}: its data chunk announces 0.1 s, yet 0.1 s more of audio follow it (the \
                 header was not updated when the recording stopped); `sox --ignore-length IN \
                 OUT.wav` recovers all of it",
                path.display()
            )
        );
        // What may follow the data: a chunk, zero padding, or a chunk a byte early where the
        // writer left out an odd data chunk's pad byte.
        let list = chunk(
            b"LIST",
            &[&b"INFO"[..], &chunk(b"INAM", b"title\0")].concat(),
        );
        let data = chunk(b"data", &samples);
        for (name, after) in [("list.wav", list.clone()), ("zeros.wav", vec![0; 4096])] {
            let path = riff_file(dir.path(), name, &[&fmt_pcm16_mono(), &data, &after]);
            let (read, _) = crate::read_mono(&path).expect(name);
            assert_eq!(read.len(), 1600, "{name}");
        }
        let mut fmt8 = fmt_pcm16_mono();
        fmt8[8 + 12..8 + 16].copy_from_slice(&[1, 0, 8, 0]); // block align 1, 8 bits
        let odd: Vec<u8> = (0..801u32).map(|k| 100 + (k % 50) as u8).collect();
        let unpadded = [&b"data"[..], &801u32.to_le_bytes(), &odd, &list].concat();
        let path = riff_file(dir.path(), "unpadded.wav", &[&fmt8, &unpadded]);
        let (read, _) = crate::read_mono(&path).expect("an unpadded data chunk");
        assert_eq!(read.len(), 801);
    }

    #[test]
    fn a_wav_file_with_two_data_chunks_is_refused_rather_than_half_read() {
        let data = |v: i16| chunk(b"data", &[v.to_le_bytes(); 800].concat());
        let mut body = b"WAVE".to_vec();
        // An empty data chunk after the two loses nothing and is not counted.
        for c in [
            fmt_pcm16_mono(),
            data(1000),
            data(-1000),
            chunk(b"data", &[]),
        ] {
            body.extend_from_slice(&c);
        }
        let mut file = b"RIFF".to_vec();
        file.extend_from_slice(&(body.len() as u32).to_le_bytes());
        file.extend_from_slice(&body);
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("two.wav");
        std::fs::write(&path, &file).expect("write");
        let want = format!(
            "{} holds 2 data chunks; Pneuma reads one, and sox and ffmpeg read only the first \
             too: export the recording again as one WAV file",
            path.display()
        );
        let Err(e) = crate::AudioSource::open(&path) else {
            panic!("two data chunks read")
        };
        assert_eq!(e.to_string(), want);
        let Err(e) = crate::WavSource::open(&path) else {
            panic!("two data chunks read")
        };
        assert!(
            matches!(e, crate::WavError::DataChunks { count: 2, .. }),
            "{e}"
        );
        // One data chunk (and an empty one after it) reads as before.
        let one = [&file[..12 + 24 + 8 + 1600], &chunk(b"data", &[])].concat();
        std::fs::write(&path, one).expect("write");
        let (samples, _) = crate::read_mono(&path).expect("one data chunk");
        assert_eq!(samples.len(), 800);
    }
}
