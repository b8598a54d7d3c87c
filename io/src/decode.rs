//! Every input format other than WAV, decoded through symphonia: FLAC, MP3, AAC in M4A/MP4 or
//! ADTS, Ogg Vorbis, AIFF/AIFF-C, CAF (PCM and ALAC), and PCM in Matroska/WebM.
//!
//! Opus is not read: symphonia has no Opus decoder and the maintained Opus crates bind the C
//! library, so an Opus file fails with [`DecodeError::Unsupported`] and the `ffmpeg` command that
//! converts it, and a chained Ogg with an Opus stream after the first with
//! [`DecodeError::ChainedOpus`] (found before decoding by [`DecodedSource::count_frames`]).
//!
//! Damage is an error, never a silent gap: a packet the decoder rejects, a FLAC file whose
//! decoded audio does not match the MD5 sum of its STREAMINFO (a bad frame CRC makes the FLAC
//! reader drop the frame, so the sum no longer matches), and a stream that ends well before the
//! length its header announces (a truncated MP3 with a Xing/LAME header, a cut FLAC) each fail
//! with [`DecodeError::Damaged`], naming how far the audio was read and how to keep what is
//! there. An MP3 without a Xing/Info/VBRI frame count announces nothing: symphonia's guess from
//! the file size is replaced by the frames counted one by one ([`crate::mp3_length`]), so a
//! valid VBR file written through a pipe is neither called damaged nor cut at the guess.
//!
//! A chained Ogg file (streams one after another, as `cat a.ogg b.ogg` makes) is read through:
//! at each new stream the decoder is made anew for it, and a change of channels or rate there
//! is an error.
//!
//! Samples come out as f32 at full scale ±1, interleaved. Integer samples are scaled by powers of
//! two, so a 16- or 24-bit FLAC/AIFF sample becomes exactly the f32 the WAV reader makes of the
//! same sample, and lossless input renders bit for bit as its WAV twin.

use std::path::{Path, PathBuf};

use symphonia::core::codecs::audio::well_known::{
    CODEC_ID_FLAC, CODEC_ID_OPUS, CODEC_ID_PCM_ALAW, CODEC_ID_PCM_S32LE, CODEC_ID_TRUEHD,
};
use symphonia::core::codecs::audio::{AudioDecoder, AudioDecoderOptions};
use symphonia::core::errors::Error as SymError;
use symphonia::core::formats::{FormatReader, TrackType};
use symphonia::core::io::MediaSource;
use symphonia::core::meta::{ChapterGroupItem, RawValue, StandardTag, Tag};
use symphonia::core::units::Duration;
use thiserror::Error;

use crate::mp4_edit::{audio_edit, Edit};
use crate::probe::probe;
use crate::{AudioInfo, Chapter, InputFormat, Tags};

/// Errors of the symphonia path.
#[derive(Debug, Error)]
pub enum DecodeError {
    /// Not an audio file symphonia knows.
    #[error("{path} is not an audio file Pneuma can read ({reason}); Pneuma reads WAV, FLAC, MP3, M4A/AAC, Ogg Vorbis, AIFF and CAF: convert it, e.g. `ffmpeg -i IN OUT.flac`")]
    Unknown {
        /// The file.
        path: PathBuf,
        /// What was found.
        reason: String,
    },
    /// A format or codec Pneuma does not decode.
    #[error("{path}: {what} is not supported; convert it, e.g. `ffmpeg -i IN OUT.flac`")]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The format found.
        what: String,
    },
    /// The audio is damaged.
    #[error("{path} is damaged after {frames_read} sample frames ({reason}); re-export it, or keep what can be decoded with `ffmpeg -i IN OUT.flac`")]
    Damaged {
        /// The file.
        path: PathBuf,
        /// Sample frames read before the damage.
        frames_read: u64,
        /// What went wrong.
        reason: String,
    },
    /// A chained Ogg file with an Opus stream after the first (a first Opus stream is
    /// [`DecodeError::Unsupported`]).
    #[error("{path}: Ogg Opus ({which}, chained after others; no maintained pure-Rust Opus decoder) is not supported, and ffmpeg converts only a chained file's first stream: convert each stream from the file it was before it was chained, e.g. `ffmpeg -i PART.opus PART.flac`, and render those")]
    ChainedOpus {
        /// The file.
        path: PathBuf,
        /// Which stream: `its stream 2`, or (from a pipe, not counted) `a later stream`.
        which: String,
    },
    /// The file holds no audio.
    #[error("{path} holds no audio ({detail}); record or export it again")]
    Empty {
        /// The file.
        path: PathBuf,
        /// What was found.
        detail: String,
    },
    /// The sample rate is outside what the engine supports.
    #[error("{path} has a sample rate of {rate_hz} Hz; Pneuma supports 8000–192000 Hz: resample it (e.g. `ffmpeg -i IN -ar 48000 OUT.flac`)")]
    Rate {
        /// The file.
        path: PathBuf,
        /// The rate found.
        rate_hz: u32,
    },
}

/// How far short of the announced length a stream may end before it counts as truncated, in
/// sample frames beyond one packet (decoders trim encoder delay and padding a little
/// differently from what the header counted).
const LENGTH_SLACK_FRAMES: u64 = 4096;

/// A file opened through symphonia for block-wise reading.
pub struct DecodedSource {
    path: PathBuf,
    reader: Box<dyn FormatReader>,
    decoder: Box<dyn AudioDecoder>,
    track_id: u32,
    info: AudioInfo,
    format: InputFormat,
    lossless: bool,
    tags: Tags,
    /// Sample frames the container announces, if it does.
    announced: Option<u64>,
    /// Most frames one packet decodes to, if known.
    max_packet_frames: u64,
    /// Decoded interleaved samples not yet handed out, from `pending_at`.
    pending: Vec<f32>,
    pending_at: usize,
    frames_read: u64,
    /// An MP4 file's edit list: the priming dropped, the length kept ([`crate::mp4_edit`]).
    edit: Option<Edit>,
    /// The length symphonia trims the last packets to is its guess, not the file's: keep
    /// every decoded frame ([`crate::mp3_length`]).
    keep_packet_ends: bool,
    /// Decoded frames dropped as priming so far.
    skipped: u64,
    ended: bool,
}

impl std::fmt::Debug for DecodedSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DecodedSource")
            .field("path", &self.path)
            .field("format", &self.format)
            .field("info", &self.info)
            .finish()
    }
}

fn is_lossless(codec: symphonia::core::codecs::audio::AudioCodecId) -> bool {
    (CODEC_ID_PCM_S32LE..CODEC_ID_PCM_ALAW).contains(&codec)
        || (CODEC_ID_FLAC..=CODEC_ID_TRUEHD).contains(&codec)
}

/// The text of a tag value, if it is text or a number.
fn tag_text(tag: &Tag) -> Option<String> {
    match &tag.raw.value {
        RawValue::String(s) => Some(s.to_string()),
        RawValue::StringList(l) => Some(l.join("; ")),
        RawValue::UnsignedInt(n) => Some(n.to_string()),
        RawValue::SignedInt(n) => Some(n.to_string()),
        _ => None,
    }
}

/// Whether `tag` is a comment written where ffmpeg writes one: an ID3 `TXXX` frame described
/// `comment`, or a Vorbis/FLAC `DESCRIPTION` (`ffmpeg -metadata comment=…`), where the standard
/// places (ID3 `COMM`, Vorbis `COMMENT`) hold none.
fn ffmpeg_comment(tag: &Tag) -> Option<String> {
    let described_comment = tag.raw.key.eq_ignore_ascii_case("TXXX")
        && tag.raw.sub_fields.as_deref().is_some_and(|fields| {
            fields.iter().any(
                |f| matches!(&f.value, RawValue::String(d) if d.eq_ignore_ascii_case("comment")),
            )
        });
    // A Vorbis/FLAC DESCRIPTION only: an M4A's description (`desc`, `ldes`) is show notes.
    let description = matches!(tag.std, Some(StandardTag::Description(_)))
        && tag.raw.key.eq_ignore_ascii_case("DESCRIPTION");
    (described_comment || description)
        .then(|| tag_text(tag))
        .flatten()
}

/// Adds the title, artist, album and comment among `tags` to `out` (the first found wins; a
/// comment where ffmpeg writes one counts when no standard one is there).
fn collect_tags(tags: &[Tag], out: &mut Tags) {
    let mut fallback_comment = None;
    for tag in tags {
        if fallback_comment.is_none() {
            fallback_comment = ffmpeg_comment(tag);
        }
        match &tag.std {
            Some(StandardTag::TrackTitle(s)) if out.title.is_none() => {
                out.title = Some(s.to_string())
            }
            Some(StandardTag::Artist(s)) if out.artist.is_none() => {
                out.artist = Some(s.to_string())
            }
            Some(StandardTag::Album(s)) if out.album.is_none() => out.album = Some(s.to_string()),
            Some(StandardTag::Comment(s)) if out.comment.is_none() => {
                out.comment = Some(s.to_string())
            }
            _ => {}
        }
    }
    if out.comment.is_none() {
        out.comment = fallback_comment;
    }
}

fn collect_chapters(items: &[ChapterGroupItem], out: &mut Vec<Chapter>) {
    for item in items {
        match item {
            ChapterGroupItem::Group(g) => collect_chapters(&g.items, out),
            ChapterGroupItem::Chapter(c) => {
                let mut t = Tags::default();
                collect_tags(&c.tags, &mut t);
                out.push(Chapter {
                    start_s: c.start_time.as_secs_f64(),
                    title: t
                        .title
                        .or_else(|| c.tags.iter().find_map(tag_text))
                        .unwrap_or_default(),
                });
            }
        }
    }
}

impl DecodedSource {
    /// Opens `source` (named `path` in errors) as the container `format` found by sniffing.
    pub fn open(
        path: &Path,
        source: Box<dyn MediaSource>,
        format: InputFormat,
    ) -> Result<Self, DecodeError> {
        let unsupported = |what: String| DecodeError::Unsupported {
            path: path.to_owned(),
            what,
        };
        if format == InputFormat::Opus {
            return Err(unsupported(
                "Ogg Opus (no maintained pure-Rust Opus decoder)".into(),
            ));
        }
        let mut reader =
            probe(source, path.extension().and_then(|e| e.to_str())).map_err(|e| match e {
                SymError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
                    DecodeError::Empty {
                        path: path.to_owned(),
                        detail: format!("it ends inside its {} header", format.name()),
                    }
                }
                other => DecodeError::Unknown {
                    path: path.to_owned(),
                    reason: if format == InputFormat::Unknown {
                        format!("no known format; {other}")
                    } else {
                        format!(
                            "it looks like {} but cannot be opened: {other}",
                            format.name()
                        )
                    },
                },
            })?;
        let track = reader
            .default_track(TrackType::Audio)
            .ok_or_else(|| DecodeError::Empty {
                path: path.to_owned(),
                detail: "it has no audio track".into(),
            })?;
        let params = track
            .codec_params
            .as_ref()
            .and_then(|p| p.audio())
            .ok_or_else(|| DecodeError::Empty {
                path: path.to_owned(),
                detail: "its audio track has no codec parameters".into(),
            })?
            .clone();
        let track_id = track.id;
        let announced = track.num_frames.filter(|&n| n > 0);
        if params.codec == CODEC_ID_OPUS {
            return Err(unsupported(
                "Opus audio (no maintained pure-Rust Opus decoder)".into(),
            ));
        }
        let decoder = symphonia::default::get_codecs()
            .make_audio_decoder(&params, &AudioDecoderOptions::default().verify(true))
            .map_err(|e| unsupported(format!("its codec {} ({e})", params.codec)))?;
        let rate_hz = params.sample_rate.ok_or_else(|| DecodeError::Empty {
            path: path.to_owned(),
            detail: "its header gives no sample rate".into(),
        })?;
        if !(8_000..=192_000).contains(&rate_hz) {
            return Err(DecodeError::Rate {
                path: path.to_owned(),
                rate_hz,
            });
        }
        let channels = params.channels.as_ref().map_or(0, |c| c.count());
        let channels = u16::try_from(channels).unwrap_or(0);
        if channels == 0 {
            return Err(DecodeError::Empty {
                path: path.to_owned(),
                detail: "its header gives no channels".into(),
            });
        }
        let lossless = is_lossless(params.codec);
        let float = matches!(
            params.sample_format,
            Some(symphonia::core::audio::sample::SampleFormat::F32)
                | Some(symphonia::core::audio::sample::SampleFormat::F64)
        );
        let bits = if float {
            32
        } else if lossless {
            // Whole bytes, as the output formats store them (20 bits in 24).
            let b = params.bits_per_sample.unwrap_or(16).clamp(8, 32);
            (b.div_ceil(8) * 8) as u16
        } else {
            // Lossy audio has no bit depth; 24 bits keep the decoder's precision.
            24
        };
        let mut tags = Tags::default();
        {
            let mut meta = reader.metadata();
            if let Some(rev) = meta.skip_to_latest() {
                collect_tags(&rev.media.tags, &mut tags);
            }
        }
        if let Some(group) = reader.chapters() {
            collect_chapters(&group.items, &mut tags.chapters);
        }
        let info = AudioInfo {
            sample_rate_hz: rate_hz,
            channels,
            bits,
            float,
            frames: announced.unwrap_or(0),
        };
        Ok(Self {
            path: path.to_owned(),
            reader,
            decoder,
            track_id,
            info,
            format,
            lossless,
            tags,
            announced,
            max_packet_frames: params.max_frames_per_packet.unwrap_or(0),
            pending: Vec::new(),
            pending_at: 0,
            frames_read: 0,
            edit: None,
            keep_packet_ends: false,
            skipped: 0,
            ended: false,
        })
    }

    /// An MP4 opened from the regular file at `path` (read again, apart from symphonia): its
    /// audio track's edit list drops the encoder's priming and ends the audio where the
    /// recording ends ([`crate::mp4_edit`]). Call before reading; nothing changes for other
    /// formats or without a plain edit list.
    pub fn read_edit_list(&mut self, path: &Path) {
        if self.format != InputFormat::Mp4 || self.frames_read > 0 {
            return;
        }
        self.edit = audio_edit(path, self.info.sample_rate_hz);
        if let Some(e) = self.edit {
            self.info.frames = e.keep;
        }
    }

    /// The length of a source opened from the regular file at `path`, counted where
    /// symphonia's announced one is wrong (call before reading; nothing changes otherwise):
    /// - an MP3 whose first frame holds no frame count: its frames are counted
    ///   ([`crate::mp3_length`]) and the count replaces symphonia's guess;
    /// - an Ogg that chains logical streams one after another: the sum of their lengths
    ///   ([`crate::ogg_length`]) replaces symphonia's, the length of one.
    ///
    /// An Ogg with an Opus stream after the first is refused here, before any audio is decoded.
    pub fn count_frames(&mut self, path: &Path) -> Result<(), DecodeError> {
        if self.frames_read > 0 {
            return Ok(());
        }
        let (counted, mp3) = match self.format {
            InputFormat::Mp3 => (crate::mp3_length::counted_frames(path), true),
            InputFormat::Ogg => match crate::ogg_length::chained_frames(path) {
                Ok(frames) => (frames, false),
                Err(opus) => {
                    return Err(DecodeError::ChainedOpus {
                        path: self.path.clone(),
                        which: format!("its stream {}", opus.number),
                    })
                }
            },
            _ => return Ok(()),
        };
        if let Some(frames) = counted {
            self.announced = (frames > 0).then_some(frames);
            self.info.frames = frames;
            // An MP3 counted so is read to the last packet's end.
            self.keep_packet_ends |= mp3;
        }
        Ok(())
    }

    /// What the stream holds (`frames` is what the container announces, 0 if it does not).
    pub fn info(&self) -> AudioInfo {
        self.info
    }

    /// The container and codec found.
    pub fn format(&self) -> InputFormat {
        self.format
    }

    /// Whether the codec is lossless (FLAC, ALAC, PCM) rather than lossy (MP3, AAC, Vorbis).
    pub fn lossless(&self) -> bool {
        self.lossless
    }

    /// Title, artist and chapters found in the file.
    pub fn tags(&self) -> &Tags {
        &self.tags
    }

    /// Sample frames handed out so far.
    pub fn frames_read(&self) -> u64 {
        self.frames_read
    }

    fn damaged(&self, reason: String) -> DecodeError {
        DecodeError::Damaged {
            path: self.path.clone(),
            frames_read: self.frames_read + self.pending_frames(),
            reason,
        }
    }

    fn pending_frames(&self) -> u64 {
        ((self.pending.len() - self.pending_at) / self.info.channels as usize) as u64
    }

    /// Decodes the next packet of the track into `pending`; false at the end of the stream.
    fn decode_next(&mut self) -> Result<bool, DecodeError> {
        loop {
            let mut packet = match self.reader.next_packet() {
                Ok(Some(p)) => p,
                Ok(None) => return Ok(false),
                Err(SymError::ResetRequired) => {
                    self.next_chained_stream()?;
                    continue;
                }
                Err(SymError::IoError(e)) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
                    return Err(self.damaged("the file ends inside an audio packet".into()))
                }
                Err(e) => return Err(self.damaged(e.to_string())),
            };
            if packet.track_id != self.track_id {
                continue;
            }
            if self.keep_packet_ends {
                packet.trim_end = Duration::ZERO;
            }
            let channels = self.info.channels as usize;
            let rate_hz = self.info.sample_rate_hz;
            let decoded = match self.decoder.decode(&packet) {
                Ok(buf) => {
                    let (c, r) = (buf.spec().channels().count(), buf.spec().rate());
                    if c != channels {
                        Err(format!(
                            "the channel count changes from {channels} to {c} mid-stream"
                        ))
                    } else if r != rate_hz {
                        Err(format!(
                            "the sample rate changes from {rate_hz} Hz to {r} Hz mid-stream"
                        ))
                    } else {
                        self.pending.clear();
                        self.pending_at = 0;
                        buf.copy_to_vec_interleaved(&mut self.pending);
                        Ok(())
                    }
                }
                Err(e) => Err(e.to_string()),
            };
            decoded.map_err(|reason| self.damaged(reason))?;
            if !self.pending.is_empty() {
                return Ok(true);
            }
        }
    }

    /// A chained Ogg file's next stream begins: its audio track and a decoder made for it.
    fn next_chained_stream(&mut self) -> Result<(), DecodeError> {
        let params = self
            .reader
            .default_track(TrackType::Audio)
            .and_then(|t| Some((t.id, t.codec_params.as_ref()?.audio()?.clone())));
        let Some((track_id, params)) = params else {
            return Err(self.damaged("a chained stream has no audio track".into()));
        };
        // Found before reading by [`Self::count_frames`] in a regular file; here from a pipe.
        if params.codec == CODEC_ID_OPUS {
            return Err(DecodeError::ChainedOpus {
                path: self.path.clone(),
                which: "a later stream".into(),
            });
        }
        self.decoder = symphonia::default::get_codecs()
            .make_audio_decoder(&params, &AudioDecoderOptions::default().verify(true))
            .map_err(|e| self.damaged(format!("a chained stream cannot be decoded: {e}")))?;
        self.track_id = track_id;
        Ok(())
    }

    /// The end of the stream: checks the length and the decoder's verification.
    fn finish_stream(&mut self) -> Result<(), DecodeError> {
        self.ended = true;
        if self.frames_read == 0 {
            return Err(DecodeError::Empty {
                path: self.path.clone(),
                detail: "not a single sample frame decodes".into(),
            });
        }
        if let Some(n) = self.announced {
            let decoded = self.frames_read + self.skipped;
            if decoded + self.max_packet_frames + LENGTH_SLACK_FRAMES < n {
                return Err(self.damaged(format!(
                    "the header announces {n} sample frames but the audio ends after {decoded}"
                )));
            }
        }
        if self.decoder.finalize().verify_ok == Some(false) {
            return Err(self.damaged(
                "the decoded audio does not match the file's checksum (a damaged frame was \
                 dropped)"
                    .into(),
            ));
        }
        Ok(())
    }

    /// Reads up to `max_frames` sample frames as interleaved f32 into `out` (cleared first);
    /// the number read, 0 at the end.
    pub fn read_interleaved(
        &mut self,
        max_frames: usize,
        out: &mut Vec<f32>,
    ) -> Result<usize, DecodeError> {
        out.clear();
        let channels = self.info.channels as usize;
        while out.len() < max_frames * channels && !self.ended {
            if self.pending_at == self.pending.len() && !self.decode_next()? {
                self.finish_stream()?;
                break;
            }
            let mut take =
                (max_frames * channels - out.len()).min(self.pending.len() - self.pending_at);
            if let Some(e) = self.edit {
                // The priming goes; the recording ends where the edit says.
                let prime = (e.skip - self.skipped).min(self.pending_frames());
                if prime > 0 {
                    self.pending_at += prime as usize * channels;
                    self.skipped += prime;
                    continue;
                }
                let room = e.keep.saturating_sub(self.frames_read);
                if room == 0 {
                    self.finish_stream()?;
                    break;
                }
                take = take.min(room as usize * channels);
            }
            out.extend_from_slice(&self.pending[self.pending_at..self.pending_at + take]);
            self.pending_at += take;
            self.frames_read += (take / channels) as u64;
        }
        Ok(out.len() / channels)
    }
}
