//! [`WavError`]: what can go wrong reading a WAV file, each with what to do (the WAV reader's,
//! [`crate::wav`], the chunk walk's, [`crate::wav_meta`], and the look after a stream's data,
//! [`crate::wav_tail`]).

use std::path::PathBuf;

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
        /// What is wrong with the header.
        reason: String,
    },
    /// A sample format Pneuma does not read.
    #[error("{path}: {what} is not supported; Pneuma reads 8/16/24/32-bit integer, 32-bit float, µ-law and A-law WAV, and IMA or Microsoft ADPCM WAV from a file (not from standard input): convert it, e.g. `sox IN -b 24 OUT.wav`")]
    Unsupported {
        /// The file.
        path: PathBuf,
        /// The format found.
        what: String,
    },
    /// The data ends early or cannot be read.
    #[error("{path} is damaged after {frames_read} sample frames ({reason}); re-export it, or keep what is there with `sox --ignore-length IN OUT.wav`")]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Sample frames read before the damage.
        frames_read: u64,
        /// What went wrong.
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
    /// A WAV file with more than one `data` chunk: the reader reads the first (as sox and
    /// ffmpeg do), so the audio of the others would be lost.
    #[error("{path} holds {count} data chunks; Pneuma reads one, and sox and ffmpeg read only the first too: export the recording again as one WAV file")]
    DataChunks {
        /// The file.
        path: PathBuf,
        /// How many non-empty `data` chunks it holds.
        count: u32,
    },
    /// More audio follows the data chunk than its header announces (no chunk after it).
    #[error(
        "{path}: its data chunk announces {announced_s:.1} s, yet {more_s:.1} s more of audio \
         follow it (the header was not updated when the recording stopped); \
         `sox --ignore-length IN OUT.wav` recovers all of it"
    )]
    Unannounced {
        /// The file.
        path: PathBuf,
        /// The length the header announces, seconds.
        announced_s: f64,
        /// The audio after it, seconds.
        more_s: f64,
    },
    /// More audio follows the data chunk of a stream (standard input, a pipe) than its header
    /// announces: how much is not known without reading it all.
    #[error(
        "{path}: its data chunk announces {announced_s:.1} s, yet more audio follows it (the \
         header was not updated when the recording stopped); put `sox --ignore-length -t wav - \
         -t wav -` in the pipe before Pneuma to read all of it, or save it to a file and run \
         `sox --ignore-length IN OUT.wav`"
    )]
    UnannouncedStream {
        /// The stream.
        path: PathBuf,
        /// The length the header announces, seconds.
        announced_s: f64,
    },
    /// A well-formed WAV file without a single sample frame.
    #[error("{path} holds no audio: {detail}")]
    Empty {
        /// The file.
        path: PathBuf,
        /// What the header says, and what to do.
        detail: String,
    },
}
