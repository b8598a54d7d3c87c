//! Audio file input shared by the `pneuma` CLI (analyze, render, train, breath samples) and the
//! plugin (breath samples), so that a file one accepts the other accepts too.
//!
//! [`AudioSource::open`] looks at the first bytes of a file (or of standard input, `-`) and
//! reads:
//! - **WAV** (RIFF, RF64, BW64) with the own reader in [`wav`], its tags, cue points and `fmt `
//!   form apart in [`wav_meta`], what follows its data (refused where audio would be lost) in
//!   `wav_tail.rs`;
//! - **everything else** (FLAC, MP3, M4A/AAC, Ogg Vorbis, AIFF, CAF) through symphonia, in
//!   [`decode`].
//!
//! Why WAV stays on the own reader (measured with `examples/decode_speed.rs` through
//! `cli/examples/measure_formats.sh`, figures in docs/measurements.md, section 8): on a 60 s 48 kHz
//! stereo episode it decoded at 8 868× real time with 2.5 MB peak memory against 2 127× and
//! 3.0 MB for symphonia's WAV reader, and it does what symphonia's does not — RF64/BW64
//! files over 4 GiB, the "unknown length" sizes ffmpeg and sox write to a pipe (read to the end
//! instead of refused), a truncated data chunk found when the file is opened rather than after
//! an hour of analysis, and errors that name the problem with the `sox` command that fixes it
//! (the CLI's `wav_input` tests hold these messages). Memory is bounded either way: both read
//! block by block.
//!
//! Small user files read whole (a head-pose model, a text to speak, a motion CSV) go through the
//! size cap in [`capped`].
//!
//! Everything here is free of the engine and of plugin-framework types; `pneuma-core` does not
//! depend on it (the engine takes samples, not files).

pub mod capped;
pub mod decode;
pub mod g711;
mod le_bytes;
mod mp3_length;
pub mod mp4_edit;
mod ogg_length;
mod probe;
mod read_full;
pub mod wav;
mod wav_error;
pub mod wav_meta;
mod wav_tail;

use std::io::{Cursor, Read};
use std::path::{Path, PathBuf};

use read_full::read_full;
use thiserror::Error;

pub use capped::{read_text_capped, CappedReadError};
pub use decode::{DecodeError, DecodedSource};
pub use wav::{WavError, WavSource};
pub use wav_meta::{CuePoint, FmtForm, WavMeta};

/// What an audio input holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AudioInfo {
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Channel count.
    pub channels: u16,
    /// Bits per sample of the container (8, 16, 24 or 32; 32 for float). A
    /// `WAVE_FORMAT_EXTENSIBLE` file with fewer valid bits (24 in 32) reports the container; a
    /// lossless file of 20 bits reports 24; lossy input, which has no bit depth, reports 24.
    pub bits: u16,
    /// Float (true) or integer PCM.
    pub float: bool,
    /// Sample frames the header announces; for a file of unknown length (streamed to a pipe and
    /// then saved) the whole frames between the data start and the end of the file, and 0 when
    /// that cannot be known either (the input itself is a pipe, or a container without a
    /// length).
    pub frames: u64,
}

/// The container of an input file, as recognised from its first bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputFormat {
    /// RIFF/RF64/BW64 WAVE.
    Wav,
    /// Native FLAC.
    Flac,
    /// MPEG audio (MP3), with or without an ID3v2 tag.
    Mp3,
    /// AAC in an ADTS stream.
    Adts,
    /// MP4/M4A (AAC or ALAC).
    Mp4,
    /// Ogg (Vorbis or FLAC).
    Ogg,
    /// Ogg Opus (not decoded).
    Opus,
    /// AIFF or AIFF-C.
    Aiff,
    /// Core Audio Format.
    Caf,
    /// Matroska/WebM.
    Matroska,
    /// Not recognised from its first bytes (symphonia still tries).
    Unknown,
}

impl InputFormat {
    /// Recognises the container from the first bytes of a file (at least 36 for Opus).
    pub fn sniff(head: &[u8]) -> Self {
        let at = |i: usize, m: &[u8]| head.get(i..i + m.len()) == Some(m);
        if at(0, b"RIFF") || at(0, b"RF64") || at(0, b"BW64") || at(0, b"RIFX") {
            Self::Wav
        } else if at(0, b"fLaC") {
            Self::Flac
        } else if at(0, b"OggS") {
            if at(28, b"OpusHead") {
                Self::Opus
            } else {
                Self::Ogg
            }
        } else if at(0, b"FORM") && (at(8, b"AIFF") || at(8, b"AIFC")) {
            Self::Aiff
        } else if at(0, b"caff") {
            Self::Caf
        } else if at(4, b"ftyp") {
            Self::Mp4
        } else if at(0, &[0x1a, 0x45, 0xdf, 0xa3]) {
            Self::Matroska
        } else if at(0, b"ID3") {
            Self::Mp3
        } else if head.len() >= 2 && head[0] == 0xff && head[1] & 0xf6 == 0xf0 {
            // Sync word with layer bits 00: AAC in ADTS.
            Self::Adts
        } else if head.len() >= 2 && head[0] == 0xff && head[1] & 0xe0 == 0xe0 {
            Self::Mp3
        } else {
            Self::Unknown
        }
    }

    /// A name for messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wav => "WAV",
            Self::Flac => "FLAC",
            Self::Mp3 => "MP3",
            Self::Adts => "AAC (ADTS)",
            Self::Mp4 => "M4A/MP4",
            Self::Ogg => "Ogg",
            Self::Opus => "Ogg Opus",
            Self::Aiff => "AIFF",
            Self::Caf => "CAF",
            Self::Matroska => "Matroska/WebM",
            Self::Unknown => "an unknown format",
        }
    }
}

/// A chapter of the input (M4A, Matroska and others that carry them).
#[derive(Debug, Clone, PartialEq)]
pub struct Chapter {
    /// Start, seconds from the beginning.
    pub start_s: f64,
    /// Its title (empty when it has none).
    pub title: String,
}

/// The tags of an input that an output can carry over.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tags {
    /// Title.
    pub title: Option<String>,
    /// Artist.
    pub artist: Option<String>,
    /// Album.
    pub album: Option<String>,
    /// Comment.
    pub comment: Option<String>,
    /// Chapters, in order.
    pub chapters: Vec<Chapter>,
}

impl Tags {
    /// The tags as (Vorbis-comment name, value) pairs.
    pub fn fields(&self) -> Vec<(&'static str, &str)> {
        [
            ("TITLE", &self.title),
            ("ARTIST", &self.artist),
            ("ALBUM", &self.album),
            ("COMMENT", &self.comment),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.as_deref().map(|v| (k, v)))
        .collect()
    }
}

/// Errors while reading an audio input.
#[derive(Debug, Error)]
pub enum ReadError {
    /// The file could not be opened.
    #[error("cannot open {path}: {source}")]
    Open {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// A WAV input.
    #[error(transparent)]
    Wav(#[from] WavError),
    /// Any other format.
    #[error(transparent)]
    Decode(#[from] DecodeError),
    /// Text (notes, a playlist, a CSV) where audio was expected, whatever its name says.
    #[error("{path} is not audio: it holds text (\"{start}…\"); give an audio file (WAV, FLAC, MP3, M4A/AAC, Ogg Vorbis, AIFF or CAF)")]
    NotAudio {
        /// The file.
        path: PathBuf,
        /// Its first characters.
        start: String,
    },
}

/// The first characters of `head` when it is text (UTF-8 without control characters but
/// tab, CR and LF; at least four bytes): such a file is no audio whatever its name says.
fn text_start(head: &[u8]) -> Option<String> {
    let valid = match std::str::from_utf8(head) {
        Ok(t) => t,
        // A character cut by the end of the bytes looked at still counts as text.
        Err(e) if e.error_len().is_none() => std::str::from_utf8(&head[..e.valid_up_to()]).ok()?,
        Err(_) => return None,
    };
    let text = valid.len() >= 4
        && valid
            .chars()
            .all(|c| !c.is_control() || matches!(c, '\t' | '\r' | '\n'));
    // On one line (an error message quotes it; a batch table shows it in a cell).
    text.then(|| {
        let start: String = valid.chars().take(24).collect();
        start.split_whitespace().collect::<Vec<_>>().join(" ")
    })
}

/// Bytes looked at to recognise a format.
const SNIFF_BYTES: usize = 64;

/// An audio input opened for block-wise reading.
#[derive(Debug)]
pub enum AudioSource {
    /// WAV through the own reader.
    Wav(WavSource),
    /// Any other format through symphonia.
    Decoded(Box<DecodedSource>),
}

/// What standard input is called in messages.
pub const STDIN_NAME: &str = "standard input";

impl AudioSource {
    /// Opens `path`, or standard input for `-`, recognising the format from its first bytes.
    pub fn open(path: &Path) -> Result<Self, ReadError> {
        if path.as_os_str() == "-" {
            return Self::open_stdin();
        }
        let open_err = |source| ReadError::Open {
            path: path.to_owned(),
            source,
        };
        if path.is_dir() {
            return Err(open_err(std::io::Error::other(
                "it is a folder; give an audio file inside it",
            )));
        }
        let mut file = std::fs::File::open(path).map_err(open_err)?;
        // The length of a regular file; unknown for a pipe or device (`/dev/stdin`).
        let file_len = file
            .metadata()
            .ok()
            .filter(|m| m.is_file())
            .map(|m| m.len());
        let mut head = vec![0u8; SNIFF_BYTES];
        let n = read_full(&mut file, &mut head).map_err(open_err)?;
        head.truncate(n);
        not_text(path, &head)?;
        let format = match InputFormat::sniff(&head) {
            // Empty and unrecognised `.wav` files go to the WAV reader: it names what it finds.
            InputFormat::Unknown if n < 4 || path_says_wav(path) => InputFormat::Wav,
            f => f,
        };
        let adpcm = Some(format)
            .filter(|f| *f == InputFormat::Wav)
            .and_then(|_| wav_format_tag(&head))
            .filter(|&t| is_adpcm(t));
        if (format != InputFormat::Wav || adpcm.is_some()) && file_len.is_some() {
            // A regular file is opened again: symphonia seeks in it (trailing tags, MP4 boxes).
            let file = std::fs::File::open(path).map_err(open_err)?;
            let source = DecodedSource::open(path, Box::new(file), format).and_then(|mut s| {
                s.read_edit_list(path);
                s.count_frames(path)?;
                Ok(s)
            });
            return match (source, adpcm) {
                // An ADPCM header symphonia cannot read is a WAV problem: say which format.
                (Err(DecodeError::Unknown { reason, .. }), Some(tag)) => {
                    Err(ReadError::Wav(WavError::Format {
                        path: path.to_owned(),
                        reason: format!(
                            "{}, its header cannot be read: {reason}",
                            wav::tag_name(tag)
                        ),
                    }))
                }
                (source, _) => Ok(Self::Decoded(Box::new(source?))),
            };
        }
        let mut source = Self::from_stream(path, head, file, file_len, format)?;
        if let (Self::Wav(s), Some(_)) = (&mut source, file_len) {
            s.read_meta(path)?;
        }
        Ok(source)
    }

    /// Opens standard input.
    fn open_stdin() -> Result<Self, ReadError> {
        let name = Path::new(STDIN_NAME);
        let mut stdin = std::io::stdin();
        let mut head = vec![0u8; SNIFF_BYTES];
        let n = read_full(&mut stdin, &mut head).map_err(|source| ReadError::Open {
            path: name.to_owned(),
            source,
        })?;
        head.truncate(n);
        not_text(name, &head)?;
        let format = match InputFormat::sniff(&head) {
            InputFormat::Unknown => InputFormat::Wav,
            f => f,
        };
        Self::from_stream(name, head, stdin, None, format)
    }

    /// Reads `head` (the bytes already read to recognise the `format`) followed by `rest`.
    fn from_stream(
        name: &Path,
        head: Vec<u8>,
        rest: impl Read + Send + Sync + 'static,
        file_len: Option<u64>,
        format: InputFormat,
    ) -> Result<Self, ReadError> {
        let stream = Cursor::new(head).chain(rest);
        if format == InputFormat::Wav {
            return Ok(Self::Wav(WavSource::from_stream(
                name,
                Box::new(stream),
                file_len,
            )?));
        }
        Ok(Self::Decoded(Box::new(DecodedSource::open(
            name,
            Box::new(symphonia::core::io::ReadOnlySource::new(stream)),
            format,
        )?)))
    }

    /// What the input holds.
    pub fn info(&self) -> AudioInfo {
        match self {
            Self::Wav(s) => s.info(),
            Self::Decoded(s) => s.info(),
        }
    }

    /// The container found.
    pub fn format(&self) -> InputFormat {
        match self {
            Self::Wav(_) => InputFormat::Wav,
            Self::Decoded(s) => s.format(),
        }
    }

    /// Whether the audio is stored losslessly (so it can be written back without a second lossy
    /// generation).
    pub fn lossless(&self) -> bool {
        match self {
            Self::Wav(_) => true,
            Self::Decoded(s) => s.lossless(),
        }
    }

    /// Tags found in the input (WAV: its `LIST`/`INFO` chunk, from a regular file).
    pub fn tags(&self) -> Tags {
        match self {
            Self::Wav(s) => s.meta().tags.clone(),
            Self::Decoded(s) => s.tags().clone(),
        }
    }

    /// The cue points of a WAV file (a DAW's markers and regions); none for other formats.
    pub fn cue_points(&self) -> &[CuePoint] {
        match self {
            Self::Wav(s) => &s.meta().cues,
            Self::Decoded(_) => &[],
        }
    }

    /// The G.711 companding of a WAV file's samples (`"µ-law"`, `"A-law"`), read as 16-bit
    /// linear PCM; `None` for every other input.
    pub fn companding(&self) -> Option<&'static str> {
        match self {
            Self::Wav(s) => s.companding(),
            Self::Decoded(_) => None,
        }
    }

    /// The `fmt ` chunk's form of a WAV file (`None` for other formats and streams).
    pub fn fmt_form(&self) -> Option<FmtForm> {
        match self {
            Self::Wav(s) => s.meta().form,
            Self::Decoded(_) => None,
        }
    }

    /// Sample frames read so far.
    pub fn frames_read(&self) -> u64 {
        match self {
            Self::Wav(s) => s.frames_read(),
            Self::Decoded(s) => s.frames_read(),
        }
    }

    /// Reads up to `max_frames` sample frames as interleaved f32 (full scale ±1) into `out`
    /// (cleared first); the number read, 0 at the end. Damage is an error, never a gap.
    pub fn read_interleaved(
        &mut self,
        max_frames: usize,
        out: &mut Vec<f32>,
    ) -> Result<usize, ReadError> {
        Ok(match self {
            Self::Wav(s) => s.read_interleaved(max_frames, out)?,
            Self::Decoded(s) => s.read_interleaved(max_frames, out)?,
        })
    }
}

/// File name extensions of the formats read, lower case.
pub const AUDIO_EXTENSIONS: [&str; 14] = [
    "wav", "flac", "mp3", "m4a", "mp4", "aac", "ogg", "oga", "aif", "aiff", "aifc", "caf", "mka",
    "webm",
];

/// The stem of a file name whose extension is one of [`AUDIO_EXTENSIONS`] (any case).
pub fn audio_stem(name: &str) -> Option<&str> {
    let (stem, ext) = name.rsplit_once('.')?;
    (!stem.is_empty() && AUDIO_EXTENSIONS.iter().any(|e| e.eq_ignore_ascii_case(ext)))
        .then_some(stem)
}

/// Audio formats Pneuma does not read, by file name extension (lower case), with their names
/// for messages. A folder given to `pneuma render` lists such files as skipped, with the
/// conversion that makes them readable.
pub const UNREAD_AUDIO_EXTENSIONS: [(&str, &str); 8] = [
    ("opus", "Opus"),
    ("wma", "WMA"),
    ("wv", "WavPack"),
    ("ape", "Monkey's Audio"),
    ("amr", "AMR"),
    ("ac3", "AC-3"),
    ("mpc", "Musepack"),
    ("dsf", "DSD"),
];

/// The first bytes of an ASF file (WMA, WMV): its header object's GUID.
const ASF_GUID: [u8; 8] = [0x30, 0x26, 0xb2, 0x75, 0x8e, 0x66, 0xcf, 0x11];

/// Why the file at `path`, found in a folder, is not worth opening as audio: `"not audio"`, or
/// the unread format with the command that converts it (`"Opus: convert it, e.g. …"`). `None`
/// when it is (or may be) audio Pneuma reads, and when it cannot be read at all (opening it
/// then reports why). Looks at the name's extension and the first bytes.
pub fn skip_reason(path: &Path) -> Option<String> {
    let mut head = vec![0u8; SNIFF_BYTES];
    let n = read_full(&mut std::fs::File::open(path).ok()?, &mut head).ok()?;
    head.truncate(n);
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    let unread = if InputFormat::sniff(&head) == InputFormat::Opus {
        Some("Opus")
    } else if head.starts_with(&ASF_GUID) {
        Some("WMA")
    } else {
        UNREAD_AUDIO_EXTENSIONS
            .iter()
            .find(|(e, _)| *e == ext)
            .map(|(_, name)| *name)
    };
    if let Some(name) = unread {
        // The paths as the batch found them (from where the user typed it), so the command
        // runs as printed.
        return Some(format!(
            "{name}, which Pneuma does not read: convert it, e.g. `ffmpeg -i '{}' '{}'`",
            path.display(),
            path.with_extension("flac").display()
        ));
    }
    let known_ext = AUDIO_EXTENSIONS.contains(&ext.as_str());
    (InputFormat::sniff(&head) == InputFormat::Unknown && !known_ext).then(|| "not audio".into())
}

/// The audio file `dir/<stem>.<ext>` for the first extension of [`AUDIO_EXTENSIONS`] that
/// exists (`mouth.wav`, else `mouth.flac`, …), as breath-sample folders are searched.
pub fn find_audio(dir: &Path, stem: &str) -> Option<PathBuf> {
    AUDIO_EXTENSIONS
        .iter()
        .map(|ext| dir.join(format!("{stem}.{ext}")))
        .find(|p| p.is_file())
}

/// [`ReadError::NotAudio`] when an input of no known format starts with text.
fn not_text(path: &Path, head: &[u8]) -> Result<(), ReadError> {
    if InputFormat::sniff(head) != InputFormat::Unknown {
        return Ok(());
    }
    match text_start(head) {
        Some(start) => Err(ReadError::NotAudio {
            path: path.to_owned(),
            start,
        }),
        None => Ok(()),
    }
}

/// The format tag of a RIFF WAV file's `fmt ` chunk, if it lies within `head`.
fn wav_format_tag(head: &[u8]) -> Option<u16> {
    let u32_at = |i: usize| -> Option<u32> {
        Some(u32::from_le_bytes(head.get(i..i + 4)?.try_into().ok()?))
    };
    if head.get(0..4) != Some(b"RIFF") || head.get(8..12) != Some(b"WAVE") {
        return None;
    }
    let mut at = 12;
    while at + 8 <= head.len() {
        let size = u32_at(at + 4)? as usize;
        if head.get(at..at + 4) == Some(b"fmt ") {
            return Some(u16::from_le_bytes(
                head.get(at + 8..at + 10)?.try_into().ok()?,
            ));
        }
        at = at.checked_add(8 + size + size % 2)?;
    }
    None
}

/// IMA and Microsoft ADPCM: read from a file through symphonia's WAV reader and ADPCM decoder
/// (the own WAV reader takes PCM, float and G.711 only).
fn is_adpcm(tag: u16) -> bool {
    matches!(tag, 0x0002 | 0x0011)
}

/// A name ending in `.wav` (any case): an unrecognised file is reported by the WAV reader.
fn path_says_wav(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wav"))
}

/// Mixes interleaved frames to mono (mean of the channels) into `mono` (cleared first).
pub fn mix_to_mono(interleaved: &[f32], channels: usize, mono: &mut Vec<f32>) {
    mono.clear();
    let k = 1.0 / channels as f32;
    mono.extend(
        interleaved
            .chunks_exact(channels)
            .map(|f| f.iter().sum::<f32>() * k),
    );
}

/// Reads every block `read` gives (interleaved, `channels` per frame) mixed to mono.
fn collect_mono<E>(
    channels: u16,
    mut read: impl FnMut(&mut Vec<f32>) -> Result<usize, E>,
) -> Result<Vec<f32>, E> {
    let mut all = Vec::new();
    let mut block = Vec::new();
    let mut mono = Vec::new();
    while read(&mut block)? > 0 {
        mix_to_mono(&block, channels as usize, &mut mono);
        all.extend_from_slice(&mono);
    }
    Ok(all)
}

/// Reads a whole audio file of any format mixed to mono, with its sample rate (for breath
/// samples, training clips and evaluation).
pub fn read_mono(path: &Path) -> Result<(Vec<f32>, u32), ReadError> {
    let mut src = AudioSource::open(path)?;
    let info = src.info();
    let all = collect_mono(info.channels, |block| src.read_interleaved(8192, block))?;
    Ok((all, info.sample_rate_hz))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adpcm_tags_are_found_in_the_header() {
        let mut head = b"RIFF\0\0\0\0WAVE".to_vec();
        head.extend_from_slice(b"LIST\x04\0\0\0abcd");
        head.extend_from_slice(b"fmt \x14\0\0\0\x11\0\x01\0");
        assert_eq!(wav_format_tag(&head), Some(0x0011));
        assert!(is_adpcm(0x0011) && is_adpcm(0x0002) && !is_adpcm(0x0001) && !is_adpcm(0x0007));
        assert_eq!(wav_format_tag(&head[..20]), None);
        assert_eq!(wav_format_tag(b"RIFX\0\0\0\0WAVEfmt "), None);
    }

    #[test]
    fn formats_are_recognised_by_their_first_bytes() {
        let mut opus = b"OggS".to_vec();
        opus.resize(28, 0);
        opus.extend_from_slice(b"OpusHead");
        for (head, want) in [
            (&b"RIFF\0\0\0\0WAVE"[..], InputFormat::Wav),
            (b"RF64", InputFormat::Wav),
            (b"fLaC\0\0\0\x22", InputFormat::Flac),
            (b"OggS\0\x02", InputFormat::Ogg),
            (&opus, InputFormat::Opus),
            (b"FORM\0\0\0\0AIFC", InputFormat::Aiff),
            (b"caff", InputFormat::Caf),
            (b"\0\0\0\x20ftypM4A ", InputFormat::Mp4),
            (b"ID3\x04", InputFormat::Mp3),
            (&[0xff, 0xfb, 0x90][..], InputFormat::Mp3),
            (&[0xff, 0xf1, 0x50][..], InputFormat::Adts),
            (b"show notes", InputFormat::Unknown),
            (b"", InputFormat::Unknown),
        ] {
            assert_eq!(InputFormat::sniff(head), want, "{head:?}");
        }
    }

    #[test]
    fn files_in_a_folder_are_skipped_with_the_reason() {
        let dir = tempfile::tempdir().expect("temp dir");
        let file = |name: &str, bytes: &[u8]| {
            let p = dir.path().join(name);
            std::fs::write(&p, bytes).expect("write");
            p
        };
        let mut opus = b"OggS".to_vec();
        opus.resize(28, 0);
        opus.extend_from_slice(b"OpusHead");
        let mut asf = ASF_GUID.to_vec();
        asf.resize(30, 0);
        let opus_path = file("ep04.opus", &opus);
        let opus_reason = skip_reason(&opus_path).expect("opus skipped");
        assert!(opus_reason.starts_with("Opus"), "{opus_reason}");
        // The command names the file where the batch found it, not only its name.
        let folder = dir.path().display();
        assert!(
            opus_reason.contains(&format!(
                "ffmpeg -i '{folder}/ep04.opus' '{folder}/ep04.flac'"
            )),
            "{opus_reason}"
        );
        // The same Opus data under another name, and WMA by its header or its name.
        assert!(skip_reason(&file("ep05.bin", &opus)).is_some_and(|r| r.starts_with("Opus")));
        assert!(skip_reason(&file("ep06.wma", &asf)).is_some_and(|r| r.starts_with("WMA")));
        assert!(skip_reason(&file("ep07.wma", b"junk")).is_some_and(|r| r.starts_with("WMA")));
        assert_eq!(
            skip_reason(&file("notes.txt", b"show notes")),
            Some("not audio".into())
        );
        // Audio names and audio contents are opened (and fail clearly if they are not audio).
        assert_eq!(skip_reason(&file("text.wav", b"show notes")), None);
        assert_eq!(skip_reason(&file("ep.dat", b"RIFF\0\0\0\0WAVE")), None);
        assert_eq!(skip_reason(&file("ep.flac", b"fLaC")), None);
    }

    #[test]
    fn text_is_told_apart_from_binary_data() {
        assert_eq!(text_start(b"show notes\n"), Some("show notes".into()));
        // Quoted on one line: line breaks and tabs become single spaces.
        assert_eq!(text_start(b"abc\ndef\r\n\tghi"), Some("abc def ghi".into()));
        assert_eq!(text_start("épisode €".as_bytes()), Some("épisode €".into()));
        // A character cut by the end of the bytes looked at.
        assert!(text_start(&"abcd€".as_bytes()[..6]).is_some());
        assert_eq!(text_start(b"RIFF\0\0"), None);
        assert_eq!(text_start(&[0xff, 0xfb, 0x90, 0x00]), None);
        assert_eq!(text_start(b"abc"), None);
    }

    #[test]
    fn audio_names_are_recognised_by_extension() {
        assert_eq!(audio_stem("ep 1.FLAC"), Some("ep 1"));
        assert_eq!(audio_stem("a.b.mp3"), Some("a.b"));
        assert_eq!(audio_stem("notes.txt"), None);
        assert_eq!(audio_stem(".wav"), None);
        assert_eq!(audio_stem("wav"), None);
    }
}
