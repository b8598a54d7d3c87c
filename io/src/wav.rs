//! Streaming WAV input, read by our own RIFF/WAVE parser so that the files users actually have
//! open, and every file that cannot be read fails with what is wrong and what to do.
//!
//! What is read:
//! - `RIFF`/`WAVE` files, and `RF64`/`BW64` files (their `ds64` chunk carries the 64-bit sizes of
//!   files over 4 GiB);
//! - format tag 1 (integer PCM: 8-bit unsigned, 16/24/32-bit signed little-endian), tag 3
//!   (32-bit IEEE float) and tag `0xFFFE` (`WAVE_FORMAT_EXTENSIBLE`) with the PCM or IEEE-float
//!   subformat GUID; tags 7 (G.711 µ-law) and 6 (A-law), plain or in `WAVE_FORMAT_EXTENSIBLE`,
//!   expanded to 16-bit linear PCM ([`crate::g711`]; [`WavInfo::bits`] is then 16, so a 16-bit
//!   output keeps the decoded signal exactly). When the valid bits are fewer than the container's (24 valid bits in a 32-bit
//!   container, 20 in 24), the samples sit in the top bits of the container: the whole container
//!   is read as a signed integer and scaled by the container width, so [`WavInfo::bits`] is the
//!   container width and writing that width back (`wav_out`) is lossless;
//! - any channel count, 8000–192000 Hz.
//!
//! Chunks other than `fmt ` and `data` (`LIST`, `bext`, `iXML`, `fact`, `JUNK`, …) are skipped
//! (a file's tags, cue points and `fmt ` form are read apart, [`crate::wav_meta`])
//! with the RIFF pad byte after odd lengths; `fmt ` must come before `data`, and no sample after
//! the first `data` chunk is read: a file with a second non-empty `data` chunk is refused
//! ([`WavError::DataChunks`]; a regular file when it is opened, a stream — standard input, a
//! pipe — once its data has been read, [`crate::wav_tail`]). A data size of `0xFFFFFFFF`, sox's
//! "unspecified" `0x7FFFF000` (when the file is shorter than that), or 0 with a RIFF size of 0
//! or `0xFFFFFFFF` is what ffmpeg or sox write to a pipe: the length is unknown and the data is
//! read to the end of the file (a trailing partial frame is dropped). A data chunk that
//! announces more sample frames than the file holds fails with [`WavError::Truncated`] when it
//! is opened (from a pipe, whose length is not known, when its data runs out); one that
//! announces fewer than follow it, no chunk after it (neither a chunk id nor zero padding), with
//! [`WavError::Unannounced`] when a regular file is opened and [`WavError::UnannouncedStream`]
//! at the end of a stream's data (a recorder stopped before it updated the header: the rest
//! would be lost).
//!
//! Samples become f32 at full scale ±1: an integer sample `v` of a `b`-bit
//! container becomes `v as f32 * (1 / 2^(b−1)) as f32` (8-bit: `(u − 128) / 128`), float samples
//! pass unchanged. The file is read through a [`BufReader`] block by block into one reused byte
//! buffer, so memory stays bounded on hour-long files; header numbers never drive allocations.

use std::fs::File;
use std::io::{BufReader, Read};

/// The byte stream a [`WavSource`] reads: a file, or standard input (with the bytes already
/// looked at to recognise the format put back in front).
pub type ByteStream = Box<dyn Read + Send>;
use std::path::{Path, PathBuf};

use crate::le_bytes::{u16_at, u32_at, u64_at};
pub use crate::mix_to_mono;
use crate::read_full::read_full;
use crate::wav_meta::WavMeta;
use crate::AudioInfo;

pub use crate::wav_error::WavError;

/// What a WAV file holds (the name the CLI and xtask have used; the same type as
/// [`AudioInfo`]).
pub type WavInfo = AudioInfo;

/// How one sample is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    /// 8-bit unsigned, offset 128.
    U8,
    /// 16-bit signed little-endian.
    I16,
    /// 24-bit signed little-endian.
    I24,
    /// 32-bit signed little-endian.
    I32,
    /// 32-bit IEEE float little-endian.
    F32,
    /// G.711 µ-law, one byte per sample.
    MuLaw,
    /// G.711 A-law, one byte per sample.
    ALaw,
}

impl Encoding {
    /// Bytes one sample takes in the file.
    fn bytes(self) -> u16 {
        match self {
            Self::U8 | Self::MuLaw | Self::ALaw => 1,
            Self::I16 => 2,
            Self::I24 => 3,
            Self::I32 | Self::F32 => 4,
        }
    }
}

/// Largest read of one [`WavSource::read_interleaved`] call, bytes (more frames are returned
/// by the following calls).
const MAX_READ_BYTES: usize = 1 << 22;
/// The data size sox writes when it cannot know the length (a pipe, or over 4 GiB).
const SOX_UNSPECIFIED: u32 = 0x7fff_f000;
/// The tail shared by every `KSDATAFORMAT_SUBTYPE_*` GUID whose first two bytes are a
/// format tag.
const GUID_TAIL: [u8; 14] = [
    0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xaa, 0x00, 0x38, 0x9b, 0x71,
];
const TAG_PCM: u16 = 0x0001;
const TAG_FLOAT: u16 = 0x0003;
const TAG_ALAW: u16 = 0x0006;
const TAG_MULAW: u16 = 0x0007;
const TAG_EXTENSIBLE: u16 = 0xfffe;

/// A WAV file opened for block-wise reading.
pub struct WavSource {
    path: PathBuf,
    reader: BufReader<ByteStream>,
    info: WavInfo,
    encoding: Encoding,
    /// Bytes per sample frame.
    block_align: usize,
    /// Whole-frame data bytes not yet read; `None` when the length is unknown (read to EOF).
    remaining: Option<u64>,
    /// A stream's (no regular file's) data bytes as its header announces them, until what
    /// follows the data has been looked at ([`crate::wav_tail::check_stream`]).
    stream_data_bytes: Option<u64>,
    frames_read: u64,
    scale: f32,
    /// Reused raw-byte buffer.
    bytes: Vec<u8>,
    /// Tags, cue points and `fmt ` form (read apart, from a regular file only; boxed, as
    /// they are seldom there and the source is moved around).
    meta: Box<WavMeta>,
}

impl std::fmt::Debug for WavSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WavSource")
            .field("path", &self.path)
            .field("info", &self.info)
            .finish()
    }
}

/// The parts of a `fmt ` chunk the reader uses.
#[derive(Debug, Clone, Copy)]
struct Fmt {
    tag: u16,
    channels: u16,
    rate: u32,
    block_align: u16,
    bits: u16,
    /// Bytes the chunk announces.
    size: u32,
    /// `WAVE_FORMAT_EXTENSIBLE` only: valid bits and subformat GUID.
    valid_bits: u16,
    subformat: [u8; 16],
}

/// The sizes a `ds64` chunk gives.
#[derive(Debug, Clone, Copy)]
struct Ds64 {
    riff: u64,
    data: u64,
}

/// `1 byte`, `2 bytes`: a count with its noun for messages.
fn count(n: u64, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// A chunk or file id for messages: `'LIST'`, or hex when not printable.
fn show_id(id: &[u8]) -> String {
    if id.iter().all(|b| (0x20..0x7f).contains(b)) {
        format!("'{}'", String::from_utf8_lossy(id))
    } else {
        let hex: Vec<String> = id.iter().map(|b| format!("{b:02x}")).collect();
        format!("bytes {}", hex.join(" "))
    }
}

/// What a file that does not start with `RIFF`/`RF64`/`BW64` probably is.
fn not_riff(head: &[u8]) -> String {
    let what = match head {
        [b'f', b'L', b'a', b'C', ..] => "a FLAC file",
        [b'O', b'g', b'g', b'S', ..] => "an Ogg (Vorbis/Opus) file",
        [b'I', b'D', b'3', ..] => "an MP3 file",
        [0xff, b, ..] if b & 0xe0 == 0xe0 => "an MP3/MPEG audio file",
        [b'F', b'O', b'R', b'M', ..] => "an AIFF file",
        [_, _, _, _, b'f', b't', b'y', b'p', ..] => "an MP4/M4A file",
        _ => "",
    };
    if what.is_empty() {
        format!(
            "it starts with {} instead of 'RIFF'",
            show_id(&head[..4.min(head.len())])
        )
    } else {
        format!("it looks like {what}, not WAV")
    }
}

/// A name for a format tag that this reader does not read.
pub(crate) fn tag_name(tag: u16) -> String {
    let name = match tag {
        0x0002 => "Microsoft ADPCM",
        0x0006 => "A-law",
        0x0007 => "µ-law",
        0x0011 => "IMA ADPCM",
        0x0031 => "GSM 6.10",
        0x0050 => "MPEG audio",
        0x0055 => "MP3",
        0x00ff | 0x1610 => "AAC",
        0x2000 => "AC-3",
        _ => "",
    };
    if name.is_empty() {
        format!("WAV format tag 0x{tag:04x}")
    } else {
        format!("{name} audio (WAV format tag 0x{tag:04x})")
    }
}

impl WavSource {
    /// Opens a WAV file and checks its header: format, channels, rate, block alignment and that
    /// it holds at least one sample frame.
    pub fn open(path: &Path) -> Result<Self, WavError> {
        let file = File::open(path).map_err(|source| WavError::Open {
            path: path.to_owned(),
            source,
        })?;
        let meta = file.metadata().ok();
        if meta.as_ref().is_some_and(|m| m.is_dir()) {
            return Err(WavError::Open {
                path: path.to_owned(),
                source: std::io::Error::other("it is a folder; give a WAV file inside it"),
            });
        }
        // The length of a regular file; unknown for a pipe or device.
        let file_len = meta.filter(|m| m.is_file()).map(|m| m.len());
        let mut source = Self::from_stream(path, Box::new(file), file_len)?;
        if file_len.is_some() {
            source.read_meta(path)?;
        }
        Ok(source)
    }

    /// Reads a WAV stream: `name` names it in errors (`-` for standard input), `file_len` is
    /// its length in bytes when known (a regular file), `None` for a pipe.
    pub fn from_stream(
        name: &Path,
        stream: ByteStream,
        file_len: Option<u64>,
    ) -> Result<Self, WavError> {
        Header::parse(name, BufReader::with_capacity(1 << 16, stream), file_len)
    }

    /// What the file holds.
    pub fn info(&self) -> WavInfo {
        self.info
    }

    /// The G.711 companding of the samples (`"µ-law"` or `"A-law"`), expanded to 16-bit linear
    /// PCM as they are read; `None` for linear PCM and float.
    pub fn companding(&self) -> Option<&'static str> {
        match self.encoding {
            Encoding::MuLaw => Some("µ-law"),
            Encoding::ALaw => Some("A-law"),
            _ => None,
        }
    }

    /// Sample frames read so far.
    pub fn frames_read(&self) -> u64 {
        self.frames_read
    }

    /// The tags, cue points and `fmt ` form of the file ([`crate::wav_meta`]; none from a
    /// stream).
    pub fn meta(&self) -> &WavMeta {
        &self.meta
    }

    /// Reads [`Self::meta`] from the regular file `path` this source reads; refuses a file with
    /// more than one `data` chunk ([`WavError::DataChunks`]).
    pub(crate) fn read_meta(&mut self, path: &Path) -> Result<(), WavError> {
        let meta = crate::wav_meta::read_checked(path, self.block_align, &self.info)?;
        *self.meta = meta;
        Ok(())
    }

    /// Reads up to `max_frames` sample frames as interleaved f32 (full scale ±1) into `out`
    /// (cleared first). Returns the number of frames read, which may be fewer than asked for
    /// very large requests; 0 at the end of the data. Fails with [`WavError::Truncated`] when
    /// the data ends before the length the header announces, with [`WavError::Empty`] when
    /// a file of unknown length turns out to hold no frame at all, and at the end of a stream's
    /// data with what would be lost after it ([`crate::wav_tail::check_stream`]).
    pub fn read_interleaved(
        &mut self,
        max_frames: usize,
        out: &mut Vec<f32>,
    ) -> Result<usize, WavError> {
        out.clear();
        if max_frames == 0 {
            return Ok(0);
        }
        let align = self.block_align;
        let mut want = max_frames.min((MAX_READ_BYTES / align).max(1));
        if let Some(left) = self.remaining {
            want = (want as u64).min(left / align as u64) as usize;
        }
        if want == 0 {
            if let Some(data_bytes) = self.stream_data_bytes.take() {
                let (path, align, info) = (&self.path, self.block_align, &self.info);
                crate::wav_tail::check_stream(&mut self.reader, path, data_bytes, align, info)?;
            }
            return self.at_end();
        }
        self.bytes.resize(want * align, 0);
        let got =
            read_full(&mut self.reader, &mut self.bytes).map_err(|e| WavError::Truncated {
                path: self.path.clone(),
                frames_read: self.frames_read,
                reason: format!("read error: {e}"),
            })?;
        let whole = got / align;
        if let Some(left) = &mut self.remaining {
            if got < want * align {
                return Err(WavError::Truncated {
                    path: self.path.clone(),
                    frames_read: self.frames_read + whole as u64,
                    reason: format!(
                        "the header announces {} sample frames but the data ends after {}",
                        self.info.frames,
                        self.frames_read + whole as u64
                    ),
                });
            }
            *left -= (whole * align) as u64;
        }
        if whole == 0 {
            // Unknown length: the end of the file (a trailing partial frame is dropped).
            return self.at_end();
        }
        out.reserve(whole * self.info.channels as usize);
        decode(self.encoding, &self.bytes[..whole * align], self.scale, out);
        self.frames_read += whole as u64;
        Ok(whole)
    }

    /// The end of the data: 0, or [`WavError::Empty`] if nothing was read.
    fn at_end(&self) -> Result<usize, WavError> {
        if self.frames_read == 0 {
            return Err(WavError::Empty {
                path: self.path.clone(),
                detail:
                    "the data chunk ends before the first sample frame; record or export it again"
                        .into(),
            });
        }
        Ok(0)
    }
}

/// Appends the samples of whole frames in `bytes` to `out`.
fn decode(encoding: Encoding, bytes: &[u8], scale: f32, out: &mut Vec<f32>) {
    match encoding {
        Encoding::U8 => out.extend(bytes.iter().map(|&b| (b as i32 - 128) as f32 * scale)),
        Encoding::I16 => out.extend(
            bytes
                .chunks_exact(2)
                .map(|b| i16::from_le_bytes([b[0], b[1]]) as f32 * scale),
        ),
        Encoding::I24 => out.extend(
            bytes
                .chunks_exact(3)
                .map(|b| (i32::from_le_bytes([0, b[0], b[1], b[2]]) >> 8) as f32 * scale),
        ),
        Encoding::I32 => out.extend(
            bytes
                .chunks_exact(4)
                .map(|b| i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32 * scale),
        ),
        Encoding::F32 => out.extend(
            bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        ),
        Encoding::MuLaw => out.extend(
            bytes
                .iter()
                .map(|&b| f32::from(crate::g711::ulaw_to_i16(b)) * scale),
        ),
        Encoding::ALaw => out.extend(
            bytes
                .iter()
                .map(|&b| f32::from(crate::g711::alaw_to_i16(b)) * scale),
        ),
    }
}

/// Header parsing state.
struct Header<'a> {
    path: &'a Path,
    reader: BufReader<ByteStream>,
    file_len: Option<u64>,
    /// Bytes consumed so far.
    pos: u64,
}

impl<'a> Header<'a> {
    fn format(&self, reason: impl Into<String>) -> WavError {
        WavError::Format {
            path: self.path.to_owned(),
            reason: reason.into(),
        }
    }

    fn unsupported(&self, what: impl Into<String>) -> WavError {
        WavError::Unsupported {
            path: self.path.to_owned(),
            what: what.into(),
        }
    }

    /// The file ends `got` bytes into the chunk `id` that announces `size` bytes.
    fn ends_inside(
        &self,
        id: &[u8; 4],
        size: impl std::fmt::Display,
        got: impl std::fmt::Display,
    ) -> WavError {
        let hint = if show_id(id).starts_with("bytes") {
            " (that id is not text: the chunks are out of step, perhaps an odd-length chunk \
             was written without its pad byte)"
        } else {
            ""
        };
        self.format(format!(
            "the {} chunk announces {size} bytes but the file ends {got} bytes into it, \
             before any data chunk{hint}",
            show_id(id)
        ))
    }

    /// Reads up to `buf.len()` bytes; the count read.
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, WavError> {
        let n = read_full(&mut self.reader, buf)
            .map_err(|e| self.format(format!("the header cannot be read: {e}")))?;
        self.pos += n as u64;
        Ok(n)
    }

    /// Reads the start of the chunk `id` (announced as `size` bytes, at least `need`) into
    /// `body`, as much as fits; returns the bytes read.
    fn read_body(
        &mut self,
        id: &[u8; 4],
        size: u32,
        need: u32,
        body: &mut [u8],
    ) -> Result<usize, WavError> {
        if size < need {
            return Err(self.format(format!(
                "the {} chunk is {size} bytes, shorter than the {need} it needs",
                String::from_utf8_lossy(id).trim_end()
            )));
        }
        let want = (size as usize).min(body.len());
        let got = self.read(&mut body[..want])?;
        if got < want {
            return Err(self.ends_inside(id, size, got));
        }
        Ok(want)
    }

    /// Skips `n` bytes of the chunk `id` (announced as `size` bytes, of which `done` are
    /// already read).
    fn skip(&mut self, n: u64, id: &[u8; 4], size: u32, done: u64) -> Result<(), WavError> {
        match self.file_len {
            Some(len) => {
                let left = len.saturating_sub(self.pos);
                if n > left {
                    return Err(self.ends_inside(id, size, done + left));
                }
                // Skipped by reading: header chunks are small, and the stream may be a pipe.
                let copied = std::io::copy(&mut (&mut self.reader).take(n), &mut std::io::sink())
                    .map_err(|e| self.format(format!("the header cannot be read: {e}")))?;
                self.pos += copied;
            }
            None => {
                let copied = std::io::copy(&mut (&mut self.reader).take(n), &mut std::io::sink())
                    .map_err(|e| self.format(format!("the header cannot be read: {e}")))?;
                self.pos += copied;
                if copied < n {
                    return Err(self.ends_inside(id, size, done + copied));
                }
            }
        }
        Ok(())
    }

    fn parse(
        path: &'a Path,
        reader: BufReader<ByteStream>,
        file_len: Option<u64>,
    ) -> Result<WavSource, WavError> {
        let mut h = Header {
            path,
            reader,
            file_len,
            pos: 0,
        };
        let mut head = [0u8; 12];
        let n = h.read(&mut head)?;
        if n == 0 {
            return Err(WavError::Empty {
                path: path.to_owned(),
                detail: "it is 0 bytes long; record or export it again".into(),
            });
        }
        if n < head.len() {
            // Too short for any header, whatever its bytes are (`hi` typed into a file).
            return Err(WavError::Empty {
                path: path.to_owned(),
                detail: format!(
                    "it is {n} bytes long, too short to hold any audio; record or export \
                     it again"
                ),
            });
        }
        if &head[..4] == b"RIFX" {
            return Err(h.unsupported("big-endian WAV (RIFX)"));
        }
        let rf64 = match &head[..4] {
            b"RIFF" => false,
            b"RF64" | b"BW64" => true,
            _ => return Err(h.format(not_riff(&head))),
        };
        if &head[8..12] != b"WAVE" {
            return Err(h.format(format!(
                "a RIFF file of form {}, not WAVE",
                show_id(&head[8..12])
            )));
        }
        let riff_size = u32_at(&head, 4);

        let mut fmt: Option<Fmt> = None;
        let mut ds64: Option<Ds64> = None;
        // A chunk id already read (libsndfile's oversized ds64, see below).
        let mut next_id: Option<[u8; 4]> = None;
        let (fmt, data_size) = loop {
            let mut ch = [0u8; 8];
            let (id, size) = match next_id.take() {
                Some(id) => {
                    let got = h.read(&mut ch[..4])?;
                    (id, (got == 4).then(|| u32_at(&ch, 0)))
                }
                None => {
                    let got = h.read(&mut ch)?;
                    let mut id = [0u8; 4];
                    id.copy_from_slice(&ch[..4]);
                    (id, (got == 8).then(|| u32_at(&ch, 4)))
                }
            };
            let Some(size) = size else {
                return Err(h.format(if fmt.is_none() {
                    "there is no fmt chunk (the file ends first)"
                } else {
                    "there is no data chunk (the file ends first)"
                }));
            };
            let pad = u64::from(size & 1);
            match &id {
                b"ds64" if rf64 && ds64.is_none() => {
                    let mut body = [0u8; 32];
                    let want = h.read_body(&id, size, 24, &mut body)?;
                    ds64 = Some(Ds64 {
                        riff: u64_at(&body, 0),
                        data: u64_at(&body, 8),
                    });
                    if size == 32 && &body[28..32] == b"fmt " {
                        // Old libsndfile wrote a 28-byte ds64 chunk announced as 32 bytes.
                        next_id = Some(*b"fmt ");
                    } else {
                        h.skip(u64::from(size) - want as u64 + pad, &id, size, want as u64)?;
                    }
                }
                b"fmt " if fmt.is_none() => {
                    let mut body = [0u8; 40];
                    let want = h.read_body(&id, size, 16, &mut body)?;
                    let mut subformat = [0u8; 16];
                    subformat.copy_from_slice(&body[24..40]);
                    fmt = Some(Fmt {
                        tag: u16_at(&body, 0),
                        channels: u16_at(&body, 2),
                        rate: u32_at(&body, 4),
                        block_align: u16_at(&body, 12),
                        bits: u16_at(&body, 14),
                        size,
                        valid_bits: u16_at(&body, 18),
                        subformat,
                    });
                    h.skip(u64::from(size) - want as u64 + pad, &id, size, want as u64)?;
                }
                b"data" => match fmt {
                    Some(f) => break (f, size),
                    None => {
                        return Err(h.format(
                            "the data chunk comes before the fmt chunk that describes it \
                             (or there is no fmt chunk)",
                        ))
                    }
                },
                // LIST, bext, iXML, fact, JUNK, PAD, cue, a second fmt, …
                _ => h.skip(u64::from(size) + pad, &id, size, 0)?,
            }
        };
        let data_start = h.pos;
        let (encoding, bits) = h.check(&fmt)?;
        let align = usize::from(fmt.block_align);

        // The data length: known, or unknown (streamed) and read to the end of the file.
        let unknown =
            |d: u64, riff: u64, max: u64| d == max || (d == 0 && (riff == 0 || riff == max));
        let data_len = if rf64 && data_size == u32::MAX {
            match ds64 {
                Some(d) if !unknown(d.data, d.riff, u64::MAX) => Some(d.data),
                _ => None,
            }
        } else if unknown(
            data_size.into(),
            // An RF64 file's RIFF size is always 0xFFFFFFFF: its real one is in ds64.
            match (rf64, ds64) {
                (true, Some(d)) => d.riff,
                _ => riff_size.into(),
            },
            if rf64 && ds64.is_some() {
                u64::MAX
            } else {
                u32::MAX.into()
            },
        ) || (data_size == SOX_UNSPECIFIED
            && file_len.is_none_or(|len| len < data_start + u64::from(SOX_UNSPECIFIED)))
        {
            None
        } else {
            Some(u64::from(data_size))
        };
        let frames = match data_len {
            Some(n) => n / align as u64,
            None => file_len.map_or(0, |len| len.saturating_sub(data_start) / align as u64),
        };
        let following = file_len.map(|len| len.saturating_sub(data_start));
        if frames == 0 && (data_len.is_some() || following.is_some()) {
            let detail = match (data_len, following) {
                (Some(0), Some(f)) if f >= align as u64 => format!(
                    "its data chunk announces 0 bytes, yet {f} bytes follow it; if it was \
                     written to a pipe, `sox --ignore-length IN OUT.wav` recovers them"
                ),
                (Some(0), _) => "its data chunk is empty; record or export it again".to_string(),
                (Some(n), _) => format!(
                    "its data chunk holds {n} bytes, less than one {align}-byte sample frame; \
                     record or export it again"
                ),
                _ => "its data chunk ends before the first sample frame; record or export it again"
                    .to_string(),
            };
            return Err(WavError::Empty {
                path: path.to_owned(),
                detail,
            });
        }
        if let (Some(n), Some(f)) = (data_len, following) {
            // Whole frames: a trailing partial frame announced but missing loses nothing.
            if f < align as u64 {
                // Only the header was written (a recorder stopped before the first block, a
                // copy cut short): there is nothing to keep.
                return Err(WavError::Empty {
                    path: path.to_owned(),
                    detail: format!(
                        "its header announces {frames} sample frames, but not one follows it \
                         (only the header was written); record or export it again"
                    ),
                });
            }
            if n / align as u64 > f / align as u64 {
                // Found now rather than after reading (and analysing) everything there is.
                return Err(WavError::Truncated {
                    path: path.to_owned(),
                    frames_read: f / align as u64,
                    reason: format!(
                        "the header announces {frames} sample frames but the file holds only {}",
                        f / align as u64
                    ),
                });
            }
        }
        let info = WavInfo {
            sample_rate_hz: fmt.rate,
            channels: fmt.channels,
            bits,
            float: encoding == Encoding::F32,
            frames,
        };
        Ok(WavSource {
            path: path.to_owned(),
            reader: h.reader,
            info,
            encoding,
            block_align: align,
            remaining: data_len.map(|n| n / align as u64 * align as u64),
            stream_data_bytes: data_len.filter(|_| file_len.is_none()),
            frames_read: 0,
            scale: if encoding == Encoding::F32 {
                1.0
            } else {
                1.0 / (1u64 << (bits - 1)) as f32
            },
            bytes: Vec::new(),
            meta: Box::default(),
        })
    }

    /// Checks the format; the sample encoding and the container bits.
    fn check(&self, fmt: &Fmt) -> Result<(Encoding, u16), WavError> {
        if fmt.channels == 0 {
            return Err(self.format("the fmt chunk gives 0 channels"));
        }
        if fmt.rate == 0 {
            return Err(self.format("the fmt chunk gives a sample rate of 0 Hz"));
        }
        let (float, valid_bits) = match fmt.tag {
            TAG_ALAW | TAG_MULAW => return self.g711(fmt, fmt.tag),
            TAG_PCM => (false, fmt.bits),
            TAG_FLOAT => (true, fmt.bits),
            TAG_EXTENSIBLE => {
                if fmt.size < 40 {
                    return Err(self.format(format!(
                        "the WAVE_FORMAT_EXTENSIBLE fmt chunk is {} bytes, shorter than the 40 \
                         it needs",
                        fmt.size
                    )));
                }
                let tag = u16_at(&fmt.subformat, 0);
                let standard = fmt.subformat[2..] == GUID_TAIL;
                let valid = if fmt.valid_bits == 0 {
                    fmt.bits
                } else {
                    fmt.valid_bits
                };
                match (standard, tag) {
                    (true, TAG_PCM) => (false, valid),
                    (true, TAG_FLOAT) => (true, valid),
                    (true, TAG_ALAW | TAG_MULAW) => return self.g711(fmt, tag),
                    (true, other) => {
                        return Err(self
                            .unsupported(format!("{} in WAVE_FORMAT_EXTENSIBLE", tag_name(other))))
                    }
                    (false, _) => {
                        let hex: String =
                            fmt.subformat.iter().map(|b| format!("{b:02x}")).collect();
                        return Err(self.unsupported(format!(
                            "WAVE_FORMAT_EXTENSIBLE with the unknown subformat GUID {hex}"
                        )));
                    }
                }
            }
            other => return Err(self.unsupported(tag_name(other))),
        };
        if fmt.bits == 0 {
            return Err(self.format("the fmt chunk gives 0 bits per sample"));
        }
        if valid_bits > fmt.bits {
            return Err(self.format(format!(
                "the fmt chunk gives {valid_bits} valid bits in a {}-bit container",
                fmt.bits
            )));
        }
        let (encoding, bits) = if float {
            if fmt.bits != 32 {
                return Err(self.unsupported(format!("{}-bit float", fmt.bits)));
            }
            (Encoding::F32, 32)
        } else {
            // Integer samples fill whole bytes, left-justified (a 20-bit sample in 24 bits).
            match fmt.bits.div_ceil(8) {
                1 => (Encoding::U8, 8),
                2 => (Encoding::I16, 16),
                3 => (Encoding::I24, 24),
                4 => (Encoding::I32, 32),
                _ => return Err(self.unsupported(format!("{}-bit integer", fmt.bits))),
            }
        };
        self.check_layout(fmt, encoding)?;
        Ok((encoding, bits))
    }

    /// G.711 (`tag` 6 A-law, 7 µ-law): 8 bits a sample, read as 16-bit linear PCM.
    fn g711(&self, fmt: &Fmt, tag: u16) -> Result<(Encoding, u16), WavError> {
        if fmt.bits != 8 {
            return Err(self.unsupported(format!("{} with {} bits", tag_name(tag), fmt.bits)));
        }
        let encoding = if tag == TAG_ALAW {
            Encoding::ALaw
        } else {
            Encoding::MuLaw
        };
        self.check_layout(fmt, encoding)?;
        Ok((encoding, 16))
    }

    /// The rate, and the block alignment for samples of `encoding`.
    fn check_layout(&self, fmt: &Fmt, encoding: Encoding) -> Result<(), WavError> {
        if !(8_000..=192_000).contains(&fmt.rate) {
            return Err(WavError::Rate {
                path: self.path.to_owned(),
                rate_hz: fmt.rate,
            });
        }
        let bits = encoding.bytes() * 8;
        let need = u32::from(fmt.channels) * u32::from(encoding.bytes());
        if u32::from(fmt.block_align) != need {
            return Err(self.format(format!(
                "the fmt chunk gives a block_align of {} per sample frame, but {} of \
                 {bits}-bit samples take {need}",
                count(fmt.block_align.into(), "byte"),
                count(fmt.channels.into(), "channel")
            )));
        }
        Ok(())
    }
}

/// Reads a whole WAV file mixed to mono (for evaluation of short clips).
pub fn read_mono(path: &Path) -> Result<(Vec<f32>, u32), WavError> {
    let mut src = WavSource::open(path)?;
    let info = src.info();
    let all = crate::collect_mono(info.channels, |block| src.read_interleaved(8192, block))?;
    Ok((all, info.sample_rate_hz))
}
