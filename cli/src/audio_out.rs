//! Audio output in the input's own format: WAV, AIFF or FLAC, to a [`Staged`] file (moved into
//! place only by [`crate::output::commit_all`] with the run's other outputs; dropped uncommitted,
//! nothing is left) or, for WAV, streamed to standard output.
//!
//! Samples are converted back with the inverse of the reader's scaling (`round(x · 2^(bits−1))`,
//! clamped, clipped samples counted), so integer samples that went through unchanged come out
//! bit-identical (8, 16 and 24-bit; 32-bit integer audio is processed at the 24-bit precision of
//! `f32`).
//!
//! - **WAV**: format tag 1 (integer) or 3 (float, with a `fact` chunk, and its `cbSize` when
//!   plain), the input WAV's own form when it is kept (plain or `WAVE_FORMAT_EXTENSIBLE` with
//!   its channel mask), else `WAVE_FORMAT_EXTENSIBLE` above 2 channels or for integers above
//!   16 bits; tags
//!   as a `LIST`/`INFO` chunk; cue points (the input's and the breath markers) as a `cue ` chunk
//!   with a `LIST`/`adtl` chunk of labels (`labl`) and lengths (`ltxt`). On standard output the
//!   sizes are `0xFFFFFFFF` (unknown, as ffmpeg and sox write to a pipe) and no chunk follows the
//!   data.
//! - **AIFF**: big-endian integer PCM, title and artist as `NAME` and `AUTH` chunks.
//! - **FLAC** (flacenc, one frame per 4096 sample frames, streamed): the STREAMINFO block is
//!   rewritten with the MD5 sum and the length at the end; tags and chapters as Vorbis comments
//!   (`TITLE`, `ARTIST`, `CHAPTER001=HH:MM:SS.mmm`, `CHAPTER001NAME`). FLAC holds integers of at
//!   most 24 bits here: float input is written as 24-bit FLAC.
//! - **MP3** (only when asked, [`crate::mp3_out`]): an ID3v2 tag, then LAME's frames; the first
//!   frame (LAME's Info/Xing frame with the encoder delay and padding) is rewritten at the end,
//!   and so is the tag, its last chapter ending at the length written.

use std::fs::File;
use std::io::{BufWriter, Seek, SeekFrom, Write};
use std::path::Path;

use flacenc::component::BitRepr;
use flacenc::error::Verify;
use flacenc::source::Fill;
use pneuma_io::{FmtForm, Tags};

use crate::mp3_out::{Mp3Encoder, Mp3Settings};
use crate::output::{commit_all, Staged};
use crate::wav::WavInfo;

/// The container of an audio output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Container {
    /// RIFF WAVE.
    Wav,
    /// FLAC.
    Flac,
    /// AIFF.
    Aiff,
    /// MP3 (lossy: only when asked).
    Mp3,
}

impl Container {
    /// The file name extension.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Wav => "wav",
            Self::Flac => "flac",
            Self::Aiff => "aiff",
            Self::Mp3 => "mp3",
        }
    }
}

/// The files beside `audio` with its stem in the other formats Pneuma writes (`talk.flac`
/// beside `talk.wav`): an earlier output in another format, or the user's own file.
pub fn other_formats_beside(audio: &Path) -> impl Iterator<Item = std::path::PathBuf> + '_ {
    <Container as clap::ValueEnum>::value_variants()
        .iter()
        .map(move |c| audio.with_extension(c.extension()))
        .filter(move |p| p != audio && p.is_file())
}

/// A labelled span of the output, written as a cue point with a label and length (WAV): the
/// input's cue points and the breath markers alike.
pub use pneuma_io::CuePoint as Cue;

/// Where the bytes go.
enum Dest {
    File {
        writer: BufWriter<File>,
        staged: Staged,
    },
    Stdout(BufWriter<std::io::Stdout>),
}

impl Dest {
    fn writer(&mut self) -> &mut dyn Write {
        match self {
            Self::File { writer, .. } => writer,
            Self::Stdout(w) => w,
        }
    }
}

/// The FLAC encoder's state.
struct FlacState {
    config: flacenc::error::Verified<flacenc::config::Encoder>,
    info: flacenc::component::StreamInfo,
    framebuf: flacenc::source::FrameBuf,
    context: flacenc::source::Context,
    /// Interleaved integer samples waiting for a whole block.
    pending: Vec<i32>,
    sink: flacenc::bitsink::ByteSink,
    /// Byte offset of the STREAMINFO body.
    info_at: u64,
}

/// Sample frames per FLAC frame.
const FLAC_BLOCK: usize = 4096;
/// The largest FLAC metadata block body, bytes (its length field has 24 bits).
const FLAC_MAX_BLOCK: usize = (1 << 24) - 1;

/// An audio file being written.
pub struct AudioSink {
    dest: Option<Dest>,
    info: WavInfo,
    container: Container,
    /// Output bits (FLAC of float input: 24).
    bits: u16,
    float: bool,
    tags: Tags,
    /// The input's `fmt ` form to keep (WAV).
    form: Option<FmtForm>,
    /// Where the `fact` chunk's frame count is (float WAV to a file).
    fact_at: Option<u64>,
    cues: Vec<Cue>,
    clipped: u64,
    data_bytes: u64,
    /// Where the header sizes to patch are, from the start of the file.
    header_len: u64,
    bytes: Vec<u8>,
    flac: Option<Box<FlacState>>,
    mp3: Option<Box<Mp3Encoder>>,
    /// Sample frames given to the MP3 encoder (the length its ID3 chapters end at).
    mp3_frames: u64,
}

impl std::fmt::Debug for AudioSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AudioSink")
            .field("container", &self.container)
            .field("info", &self.info)
            .finish()
    }
}

fn flac_err(e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("FLAC encoder: {e}"))
}

/// An IEEE 754 80-bit extended number for an integer sample rate (AIFF's `COMM`).
fn extended(rate_hz: u32) -> [u8; 10] {
    let mut out = [0u8; 10];
    if rate_hz == 0 {
        return out;
    }
    let shift = 31 - rate_hz.leading_zeros(); // floor(log2)
    let exponent = 16383 + shift as u16;
    let mantissa = u64::from(rate_hz) << (63 - shift);
    out[..2].copy_from_slice(&exponent.to_be_bytes());
    out[2..].copy_from_slice(&mantissa.to_be_bytes());
    out
}

/// `HH:MM:SS.mmm` for Vorbis-comment chapters.
fn clock(s: f64) -> String {
    let ms = (s.max(0.0) * 1000.0).round() as u64;
    format!(
        "{:02}:{:02}:{:02}.{:03}",
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1000 % 60,
        ms % 1000
    )
}

/// The WAV `fmt ` form written: `WAVE_FORMAT_EXTENSIBLE` or not, and its channel mask. The
/// input's own form when it is kept (`form`); else extensible above 2 channels or for integers
/// above 16 bits, with the mask unassigned, and float as plain format tag 3 (sox and others
/// warn of an extensible float header).
fn wav_fmt_form(form: Option<FmtForm>, channels: u16, bits: u16, float: bool) -> (bool, u32) {
    match form {
        Some(f) => (f.extensible, f.channel_mask),
        None => (channels > 2 || (bits > 16 && !float), 0),
    }
}

/// A RIFF chunk: id, little-endian size, body, pad byte after an odd length.
fn riff_chunk(out: &mut Vec<u8>, id: &[u8; 4], body: &[u8]) {
    out.extend_from_slice(id);
    out.extend_from_slice(&(body.len() as u32).to_le_bytes());
    out.extend_from_slice(body);
    if body.len() % 2 == 1 {
        out.push(0);
    }
}

impl AudioSink {
    /// Starts writing a WAV file at `target` in the format of `info`.
    pub fn create(target: &Path, info: WavInfo) -> std::io::Result<Self> {
        Self::create_as(target, info, Container::Wav, Tags::default())
    }

    /// Starts writing `target` as `container` in the format of `info`, carrying `tags`.
    pub fn create_as(
        target: &Path,
        info: WavInfo,
        container: Container,
        tags: Tags,
    ) -> std::io::Result<Self> {
        Self::create_file(target, info, container, tags, None, None)
    }

    /// Starts writing `target` as [`create_as`](Self::create_as) does, a WAV with the `fmt `
    /// form of the input it renders (`form`: plain or extensible, its channel mask).
    pub fn create_keeping(
        target: &Path,
        info: WavInfo,
        container: Container,
        tags: Tags,
        form: Option<FmtForm>,
    ) -> std::io::Result<Self> {
        Self::create_file(target, info, container, tags, None, form)
    }

    /// Starts writing `target` as MP3 encoded as `settings` ask, carrying `tags`.
    pub fn create_mp3(
        target: &Path,
        info: WavInfo,
        tags: Tags,
        settings: Mp3Settings,
    ) -> std::io::Result<Self> {
        Self::create_file(target, info, Container::Mp3, tags, Some(settings), None)
    }

    fn create_file(
        target: &Path,
        info: WavInfo,
        container: Container,
        tags: Tags,
        mp3: Option<Mp3Settings>,
        form: Option<FmtForm>,
    ) -> std::io::Result<Self> {
        let staged = Staged::new(target)?;
        let file = File::create(staged.temp())?;
        Self::start(
            Dest::File {
                writer: BufWriter::new(file),
                staged,
            },
            info,
            container,
            tags,
            mp3,
            form,
        )
    }

    /// Starts streaming a WAV file of unknown length to standard output.
    pub fn stdout(info: WavInfo) -> std::io::Result<Self> {
        Self::start(
            Dest::Stdout(BufWriter::new(std::io::stdout())),
            info,
            Container::Wav,
            Tags::default(),
            None,
            None,
        )
    }

    fn start(
        dest: Dest,
        info: WavInfo,
        container: Container,
        tags: Tags,
        mp3: Option<Mp3Settings>,
        form: Option<FmtForm>,
    ) -> std::io::Result<Self> {
        // Float goes to FLAC as 24-bit integers and to AIFF as 32-bit integers (AIFF is integer).
        let (bits, float) = match (container, info.float) {
            (Container::Flac, true) => (24, false),
            (Container::Flac, false) => (info.bits.min(24), false),
            (Container::Aiff, true) => (32, false),
            _ => (info.bits, info.float),
        };
        let mut sink = Self {
            dest: Some(dest),
            info,
            container,
            bits,
            float,
            tags,
            form,
            fact_at: None,
            cues: Vec::new(),
            clipped: 0,
            data_bytes: 0,
            header_len: 0,
            bytes: Vec::new(),
            flac: None,
            mp3: None,
            mp3_frames: 0,
        };
        if container == Container::Mp3 {
            let settings = mp3.ok_or_else(|| std::io::Error::other("MP3 settings missing"))?;
            let encoder = Mp3Encoder::new(info.channels, info.sample_rate_hz, settings)?;
            sink.mp3 = Some(Box::new(encoder));
        }
        sink.write_header()?;
        Ok(sink)
    }

    fn to_stdout(&self) -> bool {
        matches!(self.dest, Some(Dest::Stdout(_)))
    }

    fn dest(&mut self) -> &mut dyn Write {
        self.dest
            .as_mut()
            .expect("destination present until finish")
            .writer()
    }

    fn write_header(&mut self) -> std::io::Result<()> {
        let ch = self.info.channels;
        let rate = self.info.sample_rate_hz;
        let bytes_per = u32::from(self.bits / 8);
        let mut h = Vec::new();
        match self.container {
            Container::Wav => {
                let tag: u16 = if self.float { 3 } else { 1 };
                let (extensible, mask) = wav_fmt_form(self.form, ch, self.bits, self.float);
                let mut fmt = Vec::new();
                fmt.extend_from_slice(&(if extensible { 0xfffe } else { tag }).to_le_bytes());
                fmt.extend_from_slice(&ch.to_le_bytes());
                fmt.extend_from_slice(&rate.to_le_bytes());
                fmt.extend_from_slice(&(rate * bytes_per * u32::from(ch)).to_le_bytes());
                fmt.extend_from_slice(&(bytes_per as u16 * ch).to_le_bytes());
                fmt.extend_from_slice(&self.bits.to_le_bytes());
                if extensible {
                    fmt.extend_from_slice(&22u16.to_le_bytes());
                    fmt.extend_from_slice(&self.bits.to_le_bytes());
                    fmt.extend_from_slice(&mask.to_le_bytes());
                    fmt.extend_from_slice(&tag.to_le_bytes());
                    fmt.extend_from_slice(&[
                        0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xaa, 0x00, 0x38,
                        0x9b, 0x71,
                    ]);
                } else if self.float {
                    // A non-PCM WAVEFORMATEX has its cbSize (readers such as sox warn without).
                    fmt.extend_from_slice(&0u16.to_le_bytes());
                }
                h.extend_from_slice(b"RIFF");
                h.extend_from_slice(&u32::MAX.to_le_bytes()); // patched at the end
                h.extend_from_slice(b"WAVE");
                riff_chunk(&mut h, b"fmt ", &fmt);
                if self.float && !self.to_stdout() {
                    // Non-PCM data (plain or extensible float) has a `fact` chunk: the sample
                    // frames, patched at the end.
                    self.fact_at = Some(h.len() as u64 + 8);
                    riff_chunk(&mut h, b"fact", &0u32.to_le_bytes());
                }
                let fields = self.tags.fields();
                if !fields.is_empty() {
                    let mut info = b"INFO".to_vec();
                    for (key, value) in fields {
                        let id = match key {
                            "TITLE" => b"INAM",
                            "ARTIST" => b"IART",
                            "ALBUM" => b"IPRD",
                            _ => b"ICMT",
                        };
                        let mut text = value.as_bytes().to_vec();
                        text.push(0);
                        riff_chunk(&mut info, id, &text);
                    }
                    riff_chunk(&mut h, b"LIST", &info);
                }
                h.extend_from_slice(b"data");
                h.extend_from_slice(&u32::MAX.to_le_bytes()); // patched at the end
            }
            Container::Aiff => {
                h.extend_from_slice(b"FORM");
                h.extend_from_slice(&0u32.to_be_bytes()); // patched
                h.extend_from_slice(b"AIFF");
                for (id, value) in [(b"NAME", &self.tags.title), (b"AUTH", &self.tags.artist)] {
                    if let Some(v) = value {
                        h.extend_from_slice(id);
                        h.extend_from_slice(&(v.len() as u32).to_be_bytes());
                        h.extend_from_slice(v.as_bytes());
                        if v.len() % 2 == 1 {
                            h.push(0);
                        }
                    }
                }
                h.extend_from_slice(b"COMM");
                h.extend_from_slice(&18u32.to_be_bytes());
                h.extend_from_slice(&ch.to_be_bytes());
                h.extend_from_slice(&0u32.to_be_bytes()); // frames, patched
                h.extend_from_slice(&self.bits.to_be_bytes());
                h.extend_from_slice(&extended(rate));
                h.extend_from_slice(b"SSND");
                h.extend_from_slice(&0u32.to_be_bytes()); // patched
                h.extend_from_slice(&[0u8; 8]); // offset, block size
            }
            Container::Flac => {
                let info = flacenc::component::StreamInfo::new(
                    rate as usize,
                    ch as usize,
                    self.bits as usize,
                )
                .map_err(flac_err)?;
                let mut info = info;
                info.set_block_sizes(FLAC_BLOCK, FLAC_BLOCK)
                    .map_err(flac_err)?;
                let config = flacenc::config::Encoder::default()
                    .into_verified()
                    .map_err(|(_, e)| flac_err(e))?;
                h.extend_from_slice(b"fLaC");
                let comments = self.vorbis_comments();
                h.push(0); // STREAMINFO, not last
                h.extend_from_slice(&34u32.to_be_bytes()[1..]);
                let info_at = h.len() as u64;
                h.extend_from_slice(&[0u8; 34]); // written at the end
                h.push(0x80 | 4); // VORBIS_COMMENT, last
                h.extend_from_slice(&(comments.len() as u32).to_be_bytes()[1..]);
                h.extend_from_slice(&comments);
                self.flac = Some(Box::new(FlacState {
                    config,
                    info,
                    framebuf: flacenc::source::FrameBuf::with_size(ch as usize, FLAC_BLOCK)
                        .map_err(flac_err)?,
                    context: flacenc::source::Context::new(self.bits as usize, ch as usize),
                    pending: Vec::new(),
                    sink: flacenc::bitsink::ByteSink::new(),
                    info_at,
                }));
            }
            Container::Mp3 => {
                // The last chapter ends at the length written, known at the end: the tag is
                // rewritten in place then ([`Self::patch_sizes`]), never the input's announced
                // length (a FLAC's STREAMINFO may announce less than it holds).
                h = crate::mp3_out::id3_tag(&self.tags, None)?;
            }
        }
        self.header_len = h.len() as u64;
        self.dest().write_all(&h)
    }

    /// The Vorbis comment block body: vendor, then TITLE/ARTIST/… and chapters, as many as
    /// fit in a FLAC metadata block ([`FLAC_MAX_BLOCK`]).
    fn vorbis_comments(&self) -> Vec<u8> {
        let mut fields: Vec<String> = self
            .tags
            .fields()
            .into_iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        for (i, c) in self.tags.chapters.iter().enumerate() {
            fields.push(format!("CHAPTER{:03}={}", i + 1, clock(c.start_s)));
            fields.push(format!("CHAPTER{:03}NAME={}", i + 1, c.title));
        }
        let vendor = concat!("pneuma ", env!("CARGO_PKG_VERSION"));
        // The block's length has 24 bits: fields that would not fit are left out, whole.
        let mut room = FLAC_MAX_BLOCK - 8 - vendor.len();
        fields.retain(|f| {
            let fits = 4 + f.len() <= room;
            if fits {
                room -= 4 + f.len();
            }
            fits
        });
        let mut out = Vec::new();
        out.extend_from_slice(&(vendor.len() as u32).to_le_bytes());
        out.extend_from_slice(vendor.as_bytes());
        out.extend_from_slice(&(fields.len() as u32).to_le_bytes());
        for f in fields {
            out.extend_from_slice(&(f.len() as u32).to_le_bytes());
            out.extend_from_slice(f.as_bytes());
        }
        out
    }

    /// Samples that had to be clipped to the integer range so far.
    pub fn clipped(&self) -> u64 {
        self.clipped
    }

    /// The breath markers to write with a WAV file (as cue points with labels).
    pub fn set_cues(&mut self, cues: Vec<Cue>) {
        self.cues = cues;
    }

    /// `x` as an integer of the output's bits, counting clipped samples.
    fn quantize(&mut self, x: f32) -> i32 {
        let full = (1u64 << (self.bits - 1)) as f64;
        let v = (x as f64 * full).round();
        if v < -full || v > full - 1.0 {
            self.clipped += 1;
        }
        v.clamp(-full, full - 1.0) as i32
    }

    /// Appends interleaved samples (full scale ±1).
    pub fn write_interleaved(&mut self, samples: &[f32]) -> std::io::Result<()> {
        if self.container == Container::Flac {
            return self.write_flac(samples);
        }
        if let Some(mut mp3) = self.mp3.take() {
            let mut clipped = self.clipped;
            let result = match mp3.encode(samples, &mut clipped) {
                Ok(bytes) => {
                    self.data_bytes += bytes.len() as u64;
                    self.mp3_frames += (samples.len() / usize::from(self.info.channels)) as u64;
                    self.dest().write_all(bytes)
                }
                Err(e) => Err(e),
            };
            self.clipped = clipped;
            self.mp3 = Some(mp3);
            return result;
        }
        let mut bytes = std::mem::take(&mut self.bytes);
        bytes.clear();
        let big = self.container == Container::Aiff;
        for &x in samples {
            if self.float {
                bytes.extend_from_slice(&x.to_le_bytes());
                continue;
            }
            let v = self.quantize(x);
            match (self.bits, big) {
                (8, false) => bytes.push((v + 128) as u8),
                (8, true) => bytes.push(v as i8 as u8),
                (16, false) => bytes.extend_from_slice(&(v as i16).to_le_bytes()),
                (16, true) => bytes.extend_from_slice(&(v as i16).to_be_bytes()),
                (24, false) => bytes.extend_from_slice(&v.to_le_bytes()[..3]),
                (24, true) => bytes.extend_from_slice(&v.to_be_bytes()[1..]),
                (_, false) => bytes.extend_from_slice(&v.to_le_bytes()),
                (_, true) => bytes.extend_from_slice(&v.to_be_bytes()),
            }
        }
        let result = self.dest().write_all(&bytes);
        self.data_bytes += bytes.len() as u64;
        self.bytes = bytes;
        result
    }

    fn write_flac(&mut self, samples: &[f32]) -> std::io::Result<()> {
        let mut flac = self.flac.take().expect("FLAC state present");
        for &x in samples {
            let v = self.quantize(x);
            flac.pending.push(v);
        }
        let whole = FLAC_BLOCK * self.info.channels as usize;
        let mut at = 0;
        let mut result = Ok(());
        while flac.pending.len() - at >= whole && result.is_ok() {
            let end = at + whole;
            result = self.encode_flac_block(&mut flac, at, end);
            at = end;
        }
        flac.pending.drain(..at);
        self.flac = Some(flac);
        result
    }

    /// Encodes `flac.pending[from..to]` as one frame and writes it.
    fn encode_flac_block(
        &mut self,
        flac: &mut FlacState,
        from: usize,
        to: usize,
    ) -> std::io::Result<()> {
        let FlacState {
            config,
            info,
            framebuf,
            context,
            pending,
            sink,
            ..
        } = flac;
        (&mut *framebuf, &mut *context)
            .fill_interleaved(&pending[from..to])
            .map_err(flac_err)?;
        let number = context.current_frame_number().unwrap_or(0);
        let frame =
            flacenc::encode_fixed_size_frame(config, framebuf, number, info).map_err(flac_err)?;
        info.update_frame_info(&frame);
        sink.clear();
        frame.write(sink).map_err(flac_err)?;
        self.data_bytes += sink.as_slice().len() as u64;
        let bytes = sink.as_slice().to_vec();
        self.dest().write_all(&bytes)
    }

    /// Finishes the file: the remaining FLAC block, the chunks after the data and the sizes in
    /// the header. A file is returned staged for [`commit_all`]; standard output is flushed
    /// and `None` returned.
    pub fn finish(mut self) -> std::io::Result<Option<Staged>> {
        if let Some(mut flac) = self.flac.take() {
            if !flac.pending.is_empty() {
                let n = flac.pending.len();
                self.encode_flac_block(&mut flac, 0, n)?;
            }
            self.flac = Some(flac);
        }
        let mut lame_info = Vec::new();
        if let Some(mp3) = self.mp3.as_mut() {
            let (last, info) = mp3.finish()?;
            lame_info = info;
            self.data_bytes += last.len() as u64;
            self.dest().write_all(&last)?;
        }
        let tail = self.tail_chunks();
        self.dest().write_all(&tail)?;
        match self.dest.take().expect("destination present until finish") {
            Dest::Stdout(mut w) => w.flush().map(|()| None),
            Dest::File { writer, staged } => {
                let mut file = writer.into_inner().map_err(|e| e.into_error())?;
                self.patch_sizes(&mut file, tail.len() as u64)?;
                if !lame_info.is_empty() {
                    // LAME's Info frame replaces the placeholder frame after the ID3 tag.
                    file.seek(SeekFrom::Start(self.header_len))?;
                    file.write_all(&lame_info)?;
                    file.seek(SeekFrom::End(0))?;
                }
                file.sync_all()?;
                Ok(Some(staged))
            }
        }
    }

    /// The WAV chunks after the data: the pad byte, `cue ` and `LIST`/`adtl`.
    fn tail_chunks(&self) -> Vec<u8> {
        let mut out = Vec::new();
        if self.container != Container::Wav || self.to_stdout() {
            return out;
        }
        if self.data_bytes % 2 == 1 {
            out.push(0);
        }
        if self.cues.is_empty() {
            return out;
        }
        let mut cue = (self.cues.len() as u32).to_le_bytes().to_vec();
        let mut adtl = b"adtl".to_vec();
        for (i, c) in self.cues.iter().enumerate() {
            let id = i as u32 + 1;
            let at = u32::try_from(c.start_frame).unwrap_or(u32::MAX);
            cue.extend_from_slice(&id.to_le_bytes());
            cue.extend_from_slice(&at.to_le_bytes());
            cue.extend_from_slice(b"data");
            cue.extend_from_slice(&0u32.to_le_bytes());
            cue.extend_from_slice(&0u32.to_le_bytes());
            cue.extend_from_slice(&at.to_le_bytes());
            let mut labl = id.to_le_bytes().to_vec();
            labl.extend_from_slice(c.label.as_bytes());
            labl.push(0);
            riff_chunk(&mut adtl, b"labl", &labl);
            let mut ltxt = id.to_le_bytes().to_vec();
            ltxt.extend_from_slice(
                &u32::try_from(c.length_frames)
                    .unwrap_or(u32::MAX)
                    .to_le_bytes(),
            );
            ltxt.extend_from_slice(b"rgn ");
            ltxt.extend_from_slice(&[0u8; 8]); // country, language, dialect, code page
            riff_chunk(&mut adtl, b"ltxt", &ltxt);
        }
        riff_chunk(&mut out, b"cue ", &cue);
        riff_chunk(&mut out, b"LIST", &adtl);
        out
    }

    /// Writes the real sizes into the header of a finished file (MP3: the ID3 tag, its last
    /// chapter ending at the length written).
    fn patch_sizes(&mut self, file: &mut File, tail: u64) -> std::io::Result<()> {
        let too_big = || {
            std::io::Error::other(
                "the output is over 4 GiB, more than a WAV or AIFF file holds; write FLAC \
                 (--format flac) or split the input",
            )
        };
        match self.container {
            Container::Wav => {
                let data = u32::try_from(self.data_bytes).map_err(|_| too_big())?;
                let riff = u32::try_from(self.header_len - 8 + self.data_bytes + tail)
                    .map_err(|_| too_big())?;
                file.seek(SeekFrom::Start(4))?;
                file.write_all(&riff.to_le_bytes())?;
                file.seek(SeekFrom::Start(self.header_len - 4))?;
                file.write_all(&data.to_le_bytes())?;
                if let Some(at) = self.fact_at {
                    let frame_bytes = u64::from(self.bits / 8) * u64::from(self.info.channels);
                    let frames = u32::try_from(self.data_bytes / frame_bytes).unwrap_or(u32::MAX);
                    file.seek(SeekFrom::Start(at))?;
                    file.write_all(&frames.to_le_bytes())?;
                }
            }
            Container::Aiff => {
                let frame_bytes = u64::from(self.bits / 8) * u64::from(self.info.channels);
                let frames = u32::try_from(self.data_bytes / frame_bytes).map_err(|_| too_big())?;
                let ssnd = u32::try_from(self.data_bytes + 8).map_err(|_| too_big())?;
                let form =
                    u32::try_from(self.header_len - 8 + self.data_bytes).map_err(|_| too_big())?;
                file.seek(SeekFrom::Start(4))?;
                file.write_all(&form.to_be_bytes())?;
                // COMM's frame count sits 10 bytes into its body; SSND's size 12 bytes before
                // the data.
                file.seek(SeekFrom::Start(self.header_len - 16 - 18 + 2))?;
                file.write_all(&frames.to_be_bytes())?;
                file.seek(SeekFrom::Start(self.header_len - 12))?;
                file.write_all(&ssnd.to_be_bytes())?;
            }
            Container::Flac => {
                let flac = self.flac.as_mut().expect("FLAC state present");
                flac.info.set_md5_digest(&flac.context.md5_digest());
                flac.info.set_total_samples(flac.context.total_samples());
                // A fixed-block-size stream announces its block size as both bounds (the last,
                // shorter block is allowed), as the reference encoder does.
                flac.info
                    .set_block_sizes(FLAC_BLOCK, FLAC_BLOCK)
                    .map_err(flac_err)?;
                let mut sink = flacenc::bitsink::ByteSink::new();
                flac.info.write(&mut sink).map_err(flac_err)?;
                file.seek(SeekFrom::Start(flac.info_at))?;
                file.write_all(sink.as_slice())?;
            }
            Container::Mp3 => {
                // The ID3 tag again, its last chapter ending at the length written: the same
                // frames and sizes, only the times differ.
                let length_s = self.mp3_frames as f64 / f64::from(self.info.sample_rate_hz);
                let tag = crate::mp3_out::id3_tag(&self.tags, Some(length_s))?;
                if tag.len() as u64 != self.header_len {
                    return Err(std::io::Error::other(
                        "the MP3's ID3 tag changed size when its length was written; write \
                         --format flac (and report this)",
                    ));
                }
                file.seek(SeekFrom::Start(0))?;
                file.write_all(&tag)?;
            }
        }
        file.seek(SeekFrom::End(0))?;
        Ok(())
    }

    /// Finishes and moves this single file into place.
    pub fn commit(self) -> std::io::Result<()> {
        match self.finish()? {
            Some(s) => commit_all(vec![s]).map_err(|(_, e)| e),
            None => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tags_too_long_for_a_flac_metadata_block_are_left_out_whole() {
        // A WAV's INFO chunks can give a 9 MB title and a 9 MB comment: together over the
        // 24-bit block length, which once wrapped and made the FLAC unreadable.
        let dir = std::env::temp_dir().join(format!("pneuma-flac-tags-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join("long-tags.flac");
        let info = WavInfo {
            sample_rate_hz: 16_000,
            channels: 1,
            bits: 16,
            float: false,
            frames: 0,
        };
        let tags = Tags {
            title: Some("t".repeat(9 << 20)),
            comment: Some("c".repeat(9 << 20)),
            ..Tags::default()
        };
        let mut sink = AudioSink::create_as(&path, info, Container::Flac, tags).expect("create");
        sink.write_interleaved(&[0.0; 8192]).expect("write");
        sink.commit().expect("commit");
        let bytes = std::fs::read(&path).expect("read");
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(&bytes[..4], b"fLaC");
        // STREAMINFO (34 bytes), then the Vorbis comment block, then the first frame's sync.
        let at = 4 + 4 + 34;
        assert_eq!(bytes[at], 0x80 | 4, "the last block is the Vorbis comments");
        let len = u32::from_be_bytes([0, bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as usize;
        let frame = at + 4 + len;
        assert!(
            bytes[frame] == 0xFF && bytes[frame + 1] & 0xFE == 0xF8,
            "no frame sync where the comment block ends ({len} bytes)"
        );
        let block = &bytes[at + 4..frame];
        assert!(block.windows(8).any(|w| w == b"TITLE=tt"), "the title fits");
        assert!(
            !block.windows(10).any(|w| w == b"COMMENT=cc"),
            "the comment does not"
        );
    }
}
