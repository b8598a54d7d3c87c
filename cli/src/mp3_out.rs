//! MP3 output (`--format mp3`): LAME (the `mp3lame-encoder` crate, which builds LAME 3.100 from
//! source with the C compiler) behind an ID3v2.3 tag (title, artist, album, comment, chapters as
//! `CHAP`/`CTOC` frames, written with the `id3` crate) and LAME's Info/Xing frame, which carries
//! the encoder delay and padding so decoders (ffmpeg, symphonia, players) trim them and the
//! decoded length equals the render's.
//!
//! MP3 is written only when asked: a lossy input is never encoded lossy a second time by default
//! ([`crate::render::output_container`]). The bitrate ([`Mp3Settings::resolve`]) is
//! `--bitrate`, else the input's own for MP3 input ([`input_bitrate`]: the average of a VBR
//! file's Xing header, the first frame's for CBR), else 192 kbps; `--vbr` (or a VBR MP3 input)
//! encodes VBR in LAME's average-bitrate mode around that bitrate (speech with pauses averages
//! under it).
//!
//! MP3 holds 8 to 48 kHz: input at a rate MP3 does not hold is resampled by LAME to the
//! highest MP3 rate below it ([`output_rate_hz`]).

use std::num::NonZeroU32;
use std::path::Path;

use id3::TagLike;
use mp3lame_encoder::{Bitrate, Builder, Encoder, FlushGap, InterleavedPcm, MonoPcm};
use pneuma_io::{InputFormat, Tags};

/// The bitrates the encoder writes, kbps (LAME's CBR steps shared by the MPEG versions).
pub const BITRATES_KBPS: [u32; 16] = [
    8, 16, 24, 32, 40, 48, 64, 80, 96, 112, 128, 160, 192, 224, 256, 320,
];

/// The bitrate without `--bitrate` when the input is not MP3, kbps.
pub const DEFAULT_BITRATE_KBPS: u32 = 192;

/// The sample rates an MP3 holds, Hz (MPEG-2.5, MPEG-2, MPEG-1), ascending.
const RATES_HZ: [u32; 9] = [
    8_000, 11_025, 12_000, 16_000, 22_050, 24_000, 32_000, 44_100, 48_000,
];

/// The MP3 encoding options of `render` and `speak` (`--bitrate`, `--vbr`), one definition
/// flattened into both.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::Args)]
pub struct Mp3Args {
    /// MP3 bitrate, kbps (with --format mp3; 8 to 320 in LAME's steps; default: an MP3
    /// input's own when rendering one, else 192, 160 at 16–24 kHz, 64 at 8–12 kHz). With --vbr,
    /// the average aimed at (pauses and a silent side channel take less: speech usually
    /// averages under it).
    #[arg(long, value_name = "KBPS", value_parser = parse_bitrate)]
    pub bitrate: Option<u32>,
    /// Variable-bitrate MP3 (with --format mp3): LAME's average-bitrate mode, each frame's
    /// bitrate following what it holds around --bitrate. Default: constant bitrate, or VBR when
    /// rendering a VBR MP3.
    #[arg(long)]
    pub vbr: bool,
}

impl Mp3Args {
    /// `Err` when `--bitrate` or `--vbr` is given for an output that is not MP3 (`mp3`:
    /// `--format mp3`): what can be told before the input's rate is known.
    pub fn check_asked(self, mp3: bool) -> Result<(), String> {
        if !mp3 && (self.bitrate.is_some() || self.vbr) {
            return Err(
                "--bitrate and --vbr set the MP3 encoding: add --format mp3, or drop them".into(),
            );
        }
        Ok(())
    }

    /// The encoding of an output that is MP3 (`mp3`: `--format mp3`) from an input at
    /// `input_hz` in `format` (at `path`), as [`Mp3Settings::resolve`] chooses it; `None` for
    /// another output. `Err` says what to do: `--bitrate` or `--vbr` without `--format mp3`,
    /// or a bitrate the MP3's rate does not hold.
    pub fn settings(
        self,
        mp3: bool,
        path: &Path,
        format: InputFormat,
        input_hz: u32,
    ) -> Result<Option<Mp3Settings>, String> {
        self.check_asked(mp3)?;
        if !mp3 {
            return Ok(None);
        }
        Mp3Settings::resolve(self.bitrate, self.vbr, path, format, input_hz).map(Some)
    }
}

/// How the MP3 is encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mp3Settings {
    /// CBR bitrate, or the VBR average aimed at, kbps.
    pub bitrate_kbps: u32,
    /// Variable bitrate.
    pub vbr: bool,
    /// The MP3's sample rate (the input's, or the highest MP3 rate below it).
    pub rate_hz: u32,
}

/// The MP3 sample rate for input at `input_hz`: the same, or the highest MP3 rate below it.
pub fn output_rate_hz(input_hz: u32) -> u32 {
    RATES_HZ
        .iter()
        .copied()
        .rfind(|&r| r <= input_hz)
        .unwrap_or(RATES_HZ[0])
}

/// The bitrates an MP3 at `rate_hz` holds, kbps (MPEG-1 32–320, MPEG-2 8–160, MPEG-2.5 8–64).
fn bitrate_range_kbps(rate_hz: u32) -> (u32, u32) {
    match rate_hz {
        32_000.. => (32, 320),
        16_000.. => (8, 160),
        _ => (8, 64),
    }
}

/// `--bitrate`'s parser: one of [`BITRATES_KBPS`] (a trailing `k` is accepted).
pub fn parse_bitrate(text: &str) -> Result<u32, String> {
    let list = BITRATES_KBPS.map(|b| b.to_string()).join(", ");
    let kbps: u32 = text
        .trim()
        .trim_end_matches(['k', 'K'])
        .parse()
        .map_err(|_| format!("'{text}' is not a number of kbps: give one of {list}"))?;
    if BITRATES_KBPS.contains(&kbps) {
        Ok(kbps)
    } else {
        Err(format!(
            "{kbps} kbps is not an MP3 bitrate: give one of {list}"
        ))
    }
}

/// The bitrate of an MP3 file, kbps, and whether it is VBR: a Xing header's average (bytes and
/// frames) for VBR, else the first frame's. `None` when `path` is no MP3 this can read (then
/// the default applies).
pub fn input_bitrate(path: &Path) -> Option<(u32, bool)> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(256 * 1024)
        .read_to_end(&mut head)
        .ok()?;
    let mut at = 0;
    if head.starts_with(b"ID3") && head.len() >= 10 {
        let size = head[6..10]
            .iter()
            .fold(0usize, |s, &b| (s << 7) | usize::from(b & 0x7f));
        let footer = if head[5] & 0x10 != 0 { 10 } else { 0 };
        at = 10 + size + footer;
    }
    let frame_at = (at..head.len().saturating_sub(4))
        .find(|&i| head[i] == 0xff && head[i + 1] & 0xe6 == 0xe2)?;
    let h = &head[frame_at..];
    let version = (h[1] >> 3) & 3; // 3: MPEG-1, 2: MPEG-2, 0: MPEG-2.5
    let index = usize::from(h[2] >> 4);
    let mpeg1 = version == 3;
    const MPEG1: [u32; 15] = [
        0, 32, 40, 48, 56, 64, 80, 96, 112, 128, 160, 192, 224, 256, 320,
    ];
    const MPEG2: [u32; 15] = [0, 8, 16, 24, 32, 40, 48, 56, 64, 80, 96, 112, 128, 144, 160];
    let header_kbps = *if mpeg1 { &MPEG1 } else { &MPEG2 }.get(index)?;
    const RATES: [[u32; 3]; 4] = [
        [11_025, 12_000, 8_000],
        [0, 0, 0],
        [22_050, 24_000, 16_000],
        [44_100, 48_000, 32_000],
    ];
    let rate_hz = RATES
        .get(usize::from(version))?
        .get(usize::from((h[2] >> 2) & 3))
        .copied()?;
    let mono = h[3] >> 6 == 3;
    let side = match (mpeg1, mono) {
        (true, false) => 32,
        (true, true) | (false, false) => 17,
        (false, true) => 9,
    };
    let tag = h.get(4 + side..4 + side + 16)?;
    if &tag[..4] == b"Xing" && tag[7] & 3 == 3 {
        let frames = u64::from(u32::from_be_bytes(tag[8..12].try_into().ok()?));
        let bytes = u64::from(u32::from_be_bytes(tag[12..16].try_into().ok()?));
        let samples = frames * if mpeg1 { 1152 } else { 576 };
        if samples > 0 && rate_hz > 0 {
            let kbps = bytes * 8 * u64::from(rate_hz) / samples / 1000;
            return Some((u32::try_from(kbps).ok()?, true));
        }
    }
    (header_kbps > 0).then_some((header_kbps, false))
}

impl Mp3Settings {
    /// The settings for an input at `input_hz` in `format` (at `path`; `-` is standard input):
    /// `asked_kbps` (`--bitrate`) else the MP3 input's own bitrate (snapped to the nearest of
    /// [`BITRATES_KBPS`] the rate holds) else [`DEFAULT_BITRATE_KBPS`]; VBR with `vbr` or
    /// when the MP3 input is VBR. `Err` says what to give when the bitrate does not fit the rate.
    pub fn resolve(
        asked_kbps: Option<u32>,
        vbr: bool,
        path: &Path,
        format: InputFormat,
        input_hz: u32,
    ) -> Result<Self, String> {
        let rate_hz = output_rate_hz(input_hz);
        let (lo, hi) = bitrate_range_kbps(rate_hz);
        let from_input = (format == InputFormat::Mp3 && path.as_os_str() != "-")
            .then(|| input_bitrate(path))
            .flatten();
        let bitrate_kbps = match (asked_kbps, from_input) {
            (Some(kbps), _) => {
                if !(lo..=hi).contains(&kbps) {
                    return Err(format!(
                        "--bitrate {kbps}: an MP3 at {rate_hz} Hz holds {lo} to {hi} kbps; give \
                         a bitrate in that range"
                    ));
                }
                kbps
            }
            (None, Some((kbps, _))) => nearest(kbps, lo, hi),
            (None, None) => nearest(DEFAULT_BITRATE_KBPS, lo, hi),
        };
        Ok(Self {
            bitrate_kbps,
            vbr: vbr || from_input.is_some_and(|(_, v)| v),
            rate_hz,
        })
    }
}

/// The one of [`BITRATES_KBPS`] within `lo..=hi` nearest `kbps` (the higher on a tie).
fn nearest(kbps: u32, lo: u32, hi: u32) -> u32 {
    BITRATES_KBPS
        .iter()
        .copied()
        .filter(|b| (lo..=hi).contains(b))
        .min_by_key(|&b| (b.abs_diff(kbps), u32::MAX - b))
        .unwrap_or(hi)
}

/// Sets the average of LAME's average-bitrate mode, which `mp3lame_encoder::Builder` has no
/// setter for.
#[allow(unsafe_code)]
fn set_average_bitrate(b: &mut mp3lame_encoder::Builder, kbps: u32) -> std::io::Result<()> {
    let kbps = i32::try_from(kbps).unwrap_or(i32::MAX);
    // SAFETY: `as_ptr` is the builder's own live LAME context, owned by `b` for this call and
    // not yet initialised (`build` runs `lame_init_params` later); the setter only stores the
    // number in it.
    let status = unsafe { mp3lame_encoder::ffi::lame_set_VBR_mean_bitrate_kbps(b.as_ptr(), kbps) };
    if status == 0 {
        Ok(())
    } else {
        Err(lame_err(format!("average bitrate {kbps} kbps refused")))
    }
}

fn lame_err(e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(format!("MP3 encoder (LAME): {e}"))
}

fn bitrate_enum(kbps: u32) -> Bitrate {
    use Bitrate::*;
    match kbps {
        8 => Kbps8,
        16 => Kbps16,
        24 => Kbps24,
        32 => Kbps32,
        40 => Kbps40,
        48 => Kbps48,
        64 => Kbps64,
        80 => Kbps80,
        96 => Kbps96,
        112 => Kbps112,
        128 => Kbps128,
        160 => Kbps160,
        192 => Kbps192,
        224 => Kbps224,
        256 => Kbps256,
        _ => Kbps320,
    }
}

/// The ID3v2.3 tag for `tags` (empty when there are none); chapters end where the next one
/// starts, the last at `length_s` (the length written; its start when unknown). The tag's size
/// does not depend on `length_s`, so the writer rewrites it in place once the length is known.
pub fn id3_tag(tags: &Tags, length_s: Option<f64>) -> std::io::Result<Vec<u8>> {
    let mut tag = id3::Tag::new();
    if let Some(t) = &tags.title {
        tag.set_title(t.as_str());
    }
    if let Some(a) = &tags.artist {
        tag.set_artist(a.as_str());
    }
    if let Some(a) = &tags.album {
        tag.set_album(a.as_str());
    }
    if let Some(c) = &tags.comment {
        tag.add_frame(id3::frame::Comment {
            lang: "eng".into(),
            description: String::new(),
            text: c.clone(),
        });
    }
    let ms = |s: f64| (s.max(0.0) * 1000.0).round().min(f64::from(u32::MAX)) as u32;
    let ids: Vec<String> = (1..=tags.chapters.len())
        .map(|i| format!("ch{i}"))
        .collect();
    for (i, c) in tags.chapters.iter().enumerate() {
        let end_s = tags
            .chapters
            .get(i + 1)
            .map(|n| n.start_s)
            .or(length_s)
            .unwrap_or(c.start_s);
        let mut title = id3::Tag::new();
        title.set_title(c.title.as_str());
        tag.add_frame(id3::frame::Chapter {
            element_id: ids[i].clone(),
            start_time: ms(c.start_s),
            end_time: ms(end_s.max(c.start_s)),
            start_offset: u32::MAX,
            end_offset: u32::MAX,
            frames: title.frames().cloned().collect(),
        });
    }
    if !ids.is_empty() {
        tag.add_frame(id3::frame::TableOfContents {
            element_id: "toc".into(),
            top_level: true,
            ordered: true,
            elements: ids,
            frames: Vec::new(),
        });
    }
    let mut out = Vec::new();
    if tag.frames().next().is_some() {
        tag.write_to(&mut out, id3::Version::Id3v23)
            .map_err(|e| std::io::Error::other(format!("ID3 tag: {e}")))?;
    }
    Ok(out)
}

/// A running LAME encoder; the bytes it returns follow the ID3 tag in the file, and its Info
/// frame ([`Mp3Encoder::finish`]) replaces the first frame of them.
pub struct Mp3Encoder {
    encoder: Encoder,
    channels: usize,
    /// Encoded bytes waiting to be written.
    out: Vec<u8>,
    /// Clamped input samples.
    scratch: Vec<f32>,
}

impl Mp3Encoder {
    /// An encoder for `channels` (1 or 2) at `input_hz`, as `settings` ask.
    pub fn new(channels: u16, input_hz: u32, settings: Mp3Settings) -> std::io::Result<Self> {
        if !(1..=2).contains(&channels) {
            return Err(std::io::Error::other(format!(
                "MP3 holds one or two channels and the input has {channels}: add --channel \
                 left, or write --format flac"
            )));
        }
        let mut b = Builder::new().ok_or_else(|| lame_err("cannot start"))?;
        b.set_num_channels(channels as u8).map_err(lame_err)?;
        b.set_sample_rate(input_hz).map_err(lame_err)?;
        b.set_output_sample_rate(NonZeroU32::new(settings.rate_hz))
            .map_err(lame_err)?;
        b.set_mode(if channels == 1 {
            mp3lame_encoder::Mode::Mono
        } else {
            mp3lame_encoder::Mode::JointStereo
        })
        .map_err(lame_err)?;
        // LAME's recommended algorithm quality (`-q 2`, the `-h` of its front end).
        b.set_quality(mp3lame_encoder::Quality::NearBest)
            .map_err(lame_err)?;
        if settings.vbr {
            // LAME's average-bitrate mode (`--abr N`): each frame's bitrate varies with what
            // it holds, around the average asked. Its quality levels (`-V`) aim at no bitrate:
            // on the example voice at 44.1 kHz the level whose documented music average is 128
            // kbps averaged 60 (this mode: 85).
            b.set_vbr_mode(mp3lame_encoder::VbrMode::Abr)
                .map_err(lame_err)?;
            set_average_bitrate(&mut b, settings.bitrate_kbps)?;
        } else {
            b.set_vbr_mode(mp3lame_encoder::VbrMode::Off)
                .map_err(lame_err)?;
            b.set_brate(bitrate_enum(settings.bitrate_kbps))
                .map_err(lame_err)?;
        }
        // The Info/Xing frame with the LAME extension: delay and padding for gapless decoding.
        b.set_to_write_vbr_tag(true).map_err(lame_err)?;
        Ok(Self {
            encoder: b.build().map_err(lame_err)?,
            channels: usize::from(channels),
            out: Vec::new(),
            scratch: Vec::new(),
        })
    }

    /// Encodes interleaved samples (full scale ±1; beyond it clamped, counted in `clipped`) and
    /// returns the bytes to write.
    pub fn encode(&mut self, samples: &[f32], clipped: &mut u64) -> std::io::Result<&[u8]> {
        self.scratch.clear();
        self.scratch.extend(samples.iter().map(|&x| {
            if !(-1.0..=1.0).contains(&x) {
                *clipped += 1;
            }
            x.clamp(-1.0, 1.0)
        }));
        let frames = samples.len() / self.channels;
        self.out.clear();
        self.out
            .reserve(mp3lame_encoder::max_required_buffer_size(frames));
        let r = if self.channels == 1 {
            self.encoder
                .encode_to_vec(MonoPcm(&self.scratch[..]), &mut self.out)
        } else {
            self.encoder
                .encode_to_vec(InterleavedPcm(&self.scratch[..]), &mut self.out)
        };
        r.map_err(lame_err)?;
        Ok(&self.out)
    }

    /// Flushes the encoder: the last frames, and the Info frame that replaces the first frame
    /// written.
    pub fn finish(&mut self) -> std::io::Result<(Vec<u8>, Vec<u8>)> {
        let mut last = Vec::with_capacity(7200);
        self.encoder
            .flush_to_vec::<FlushGap>(&mut last)
            .map_err(lame_err)?;
        let mut info = Vec::with_capacity(self.encoder.lame_tag_size().max(1));
        self.encoder.lame_tag_encode_to_vec(&mut info);
        Ok((last, info))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bitrates_are_parsed_and_bad_ones_refused_with_the_list() {
        assert_eq!(parse_bitrate("128"), Ok(128));
        assert_eq!(parse_bitrate("320k"), Ok(320));
        let e = parse_bitrate("100").unwrap_err();
        assert!(e.contains("100 kbps is not an MP3 bitrate"), "{e}");
        assert!(e.contains("8, 16, 24"), "{e}");
        let e = parse_bitrate("fast").unwrap_err();
        assert!(e.contains("'fast' is not a number of kbps"), "{e}");
    }

    #[test]
    fn the_default_bitrate_is_192_for_non_mp3_input_and_fits_the_rate() {
        let wav = Path::new("x.wav");
        let s = Mp3Settings::resolve(None, false, wav, InputFormat::Wav, 44_100).unwrap();
        assert_eq!((s.bitrate_kbps, s.vbr, s.rate_hz), (192, false, 44_100));
        // MPEG-2 rates hold at most 160 kbps.
        let s = Mp3Settings::resolve(None, false, wav, InputFormat::Wav, 16_000).unwrap();
        assert_eq!((s.bitrate_kbps, s.rate_hz), (160, 16_000));
        // 96 kHz is written at 48 kHz.
        let s = Mp3Settings::resolve(Some(64), true, wav, InputFormat::Flac, 96_000).unwrap();
        assert_eq!((s.bitrate_kbps, s.vbr, s.rate_hz), (64, true, 48_000));
        let e = Mp3Settings::resolve(Some(320), false, wav, InputFormat::Wav, 8_000).unwrap_err();
        assert!(e.contains("8000 Hz holds 8 to 64 kbps"), "{e}");
    }
}
