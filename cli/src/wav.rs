//! Streaming WAV input: 8/16/24/32-bit integer and 32-bit float PCM, any channel count, any
//! rate, read block by block so memory stays bounded on hour-long files. Every failure says
//! what is wrong with the file and what to do.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// Errors while reading a WAV file.
#[derive(Debug, Error)]
pub enum WavError {
    /// The file could not be opened.
    #[error("cannot open {path}: {source}")]
    Open {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The file is not a WAV file or its header is damaged.
    #[error("{path} is not a readable WAV file ({reason}); convert it to PCM WAV, e.g. `sox IN -b 16 OUT.wav`")]
    Format {
        /// The file.
        path: PathBuf,
        /// What the decoder said.
        reason: String,
    },
    /// A sample format Pneuma does not read.
    #[error("{path}: {what} is not supported; use 8/16/24/32-bit integer or 32-bit float PCM (e.g. `sox IN -b 24 OUT.wav`)")]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The format found.
        what: String,
    },
    /// The data ends early or is damaged.
    #[error("{path} is damaged after {frames_read} sample frames ({reason}); re-export or repair the file")]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Sample frames read before the damage.
        frames_read: u64,
        /// What the decoder said.
        reason: String,
    },
    /// The sample rate is outside what the engine supports.
    #[error("{path} has a sample rate of {rate_hz} Hz; Pneuma supports 8000–192000 Hz: resample it (e.g. `sox IN -r 48000 OUT.wav`)")]
    Rate {
        /// The file.
        path: PathBuf,
        /// The rate found.
        rate_hz: u32,
    },
}

/// What a WAV file holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WavInfo {
    /// Sample rate, Hz.
    pub sample_rate_hz: u32,
    /// Channel count.
    pub channels: u16,
    /// Bits per sample.
    pub bits: u16,
    /// Float (true) or integer PCM.
    pub float: bool,
    /// Sample frames the header announces.
    pub frames: u64,
}

/// A WAV file opened for block-wise reading.
pub struct WavSource {
    path: PathBuf,
    reader: hound::WavReader<BufReader<File>>,
    info: WavInfo,
    frames_read: u64,
    scale: f32,
}

impl std::fmt::Debug for WavSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WavSource")
            .field("path", &self.path)
            .field("info", &self.info)
            .finish()
    }
}

impl WavSource {
    /// Opens and checks a WAV file.
    pub fn open(path: &Path) -> Result<Self, WavError> {
        let file = File::open(path).map_err(|source| WavError::Open {
            path: path.to_owned(),
            source,
        })?;
        let reader = hound::WavReader::new(BufReader::new(file)).map_err(|e| match e {
            hound::Error::Unsupported => WavError::Unsupported {
                path: path.to_owned(),
                what: "this WAV encoding (compressed or unusual format tag)".into(),
            },
            hound::Error::IoError(io) => WavError::Format {
                path: path.to_owned(),
                reason: format!("header ends early or cannot be read: {io}"),
            },
            other => WavError::Format {
                path: path.to_owned(),
                reason: other.to_string(),
            },
        })?;
        let spec = reader.spec();
        let float = spec.sample_format == hound::SampleFormat::Float;
        let ok_bits = if float {
            spec.bits_per_sample == 32
        } else {
            matches!(spec.bits_per_sample, 8 | 16 | 24 | 32)
        };
        if !ok_bits || spec.channels == 0 {
            return Err(WavError::Unsupported {
                path: path.to_owned(),
                what: format!(
                    "{}-bit {} with {} channels",
                    spec.bits_per_sample,
                    if float { "float" } else { "integer" },
                    spec.channels
                ),
            });
        }
        if !(8_000..=192_000).contains(&spec.sample_rate) {
            return Err(WavError::Rate {
                path: path.to_owned(),
                rate_hz: spec.sample_rate,
            });
        }
        let info = WavInfo {
            sample_rate_hz: spec.sample_rate,
            channels: spec.channels,
            bits: spec.bits_per_sample,
            float,
            frames: reader.duration() as u64,
        };
        Ok(Self {
            path: path.to_owned(),
            reader,
            info,
            frames_read: 0,
            scale: if float {
                1.0
            } else {
                1.0 / (1u64 << (spec.bits_per_sample - 1)) as f32
            },
        })
    }

    /// What the file holds.
    pub fn info(&self) -> WavInfo {
        self.info
    }

    /// Sample frames read so far.
    pub fn frames_read(&self) -> u64 {
        self.frames_read
    }

    /// Reads up to `max_frames` sample frames as interleaved f32 (full scale ±1) into `out`
    /// (cleared first). Returns the number of frames read; 0 at the end of the data.
    pub fn read_interleaved(
        &mut self,
        max_frames: usize,
        out: &mut Vec<f32>,
    ) -> Result<usize, WavError> {
        out.clear();
        let want = max_frames * self.info.channels as usize;
        let scale = self.scale;
        let r = if self.info.float {
            collect(self.reader.samples::<f32>(), want, out, |v| v)
        } else {
            collect(self.reader.samples::<i32>(), want, out, |v| {
                v as f32 * scale
            })
        };
        if let Err(e) = r {
            return Err(WavError::Truncated {
                path: self.path.clone(),
                frames_read: self.frames_read + (out.len() / self.info.channels as usize) as u64,
                reason: e.to_string(),
            });
        }
        if !out.len().is_multiple_of(self.info.channels as usize) {
            return Err(WavError::Truncated {
                path: self.path.clone(),
                frames_read: self.frames_read + (out.len() / self.info.channels as usize) as u64,
                reason: "the data ends in the middle of a sample frame".into(),
            });
        }
        let frames = out.len() / self.info.channels as usize;
        self.frames_read += frames as u64;
        Ok(frames)
    }
}

fn collect<S, I: Iterator<Item = Result<S, hound::Error>>>(
    iter: I,
    want: usize,
    out: &mut Vec<f32>,
    convert: impl Fn(S) -> f32,
) -> Result<(), hound::Error> {
    for s in iter.take(want) {
        out.push(convert(s?));
    }
    Ok(())
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

/// Reads a whole file mixed to mono (for evaluation of short clips).
pub fn read_mono(path: &Path) -> Result<(Vec<f32>, u32), WavError> {
    let mut src = WavSource::open(path)?;
    let channels = src.info().channels as usize;
    let mut all = Vec::new();
    let mut block = Vec::new();
    let mut mono = Vec::new();
    while src.read_interleaved(8192, &mut block)? > 0 {
        mix_to_mono(&block, channels, &mut mono);
        all.extend_from_slice(&mono);
    }
    Ok((all, src.info().sample_rate_hz))
}
