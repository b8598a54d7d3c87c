//! WAV output in the input's own format: the file is written to a [`Staged`] temporary file
//! and moved into place only by [`WavSink::commit`] (or [`crate::output::commit_all`] with the
//! run's other outputs); dropping the sink without committing removes the temporary file, so
//! an existing file is never half-replaced.
//!
//! Samples are converted back with the inverse of the reader's scaling (`round(x · 2^(bits−1))`,
//! clamped), so integer samples that went through unchanged come out bit-identical (8, 16 and
//! 24-bit; 32-bit integer audio is processed at the 24-bit precision of `f32`).

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use crate::output::{commit_all, Staged};
use crate::wav::WavInfo;

/// A WAV file being written.
pub struct WavSink {
    writer: Option<hound::WavWriter<BufWriter<File>>>,
    info: WavInfo,
    staged: Staged,
    clipped: u64,
}

impl std::fmt::Debug for WavSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WavSink")
            .field("target", &self.staged.target())
            .field("info", &self.info)
            .finish()
    }
}

impl WavSink {
    /// Starts writing `target` with the format of `info` (rate, channels, bits, float).
    pub fn create(target: &Path, info: WavInfo) -> std::io::Result<Self> {
        let spec = hound::WavSpec {
            channels: info.channels,
            sample_rate: info.sample_rate_hz,
            bits_per_sample: info.bits,
            sample_format: if info.float {
                hound::SampleFormat::Float
            } else {
                hound::SampleFormat::Int
            },
        };
        let staged = Staged::new(target)?;
        let writer = hound::WavWriter::create(staged.temp(), spec).map_err(to_io)?;
        Ok(Self {
            writer: Some(writer),
            info,
            staged,
            clipped: 0,
        })
    }

    /// Samples that had to be clipped to the integer range so far.
    pub fn clipped(&self) -> u64 {
        self.clipped
    }

    /// Appends interleaved samples (full scale ±1).
    pub fn write_interleaved(&mut self, samples: &[f32]) -> std::io::Result<()> {
        let w = self.writer.as_mut().expect("writer present until commit");
        if self.info.float {
            for &x in samples {
                w.write_sample(x).map_err(to_io)?;
            }
            return Ok(());
        }
        let full = (1u64 << (self.info.bits - 1)) as f64;
        let (lo, hi) = (-full, full - 1.0);
        for &x in samples {
            let v = (x as f64 * full).round();
            if v < lo || v > hi {
                self.clipped += 1;
            }
            let v = v.clamp(lo, hi) as i32;
            if self.info.bits == 8 {
                w.write_sample(v as i8).map_err(to_io)?;
            } else {
                w.write_sample(v).map_err(to_io)?;
            }
        }
        Ok(())
    }

    /// Finishes the header; the file is returned staged for [`commit_all`].
    pub fn finish(mut self) -> std::io::Result<Staged> {
        let writer = self.writer.take().expect("writer present until finish");
        writer.finalize().map_err(to_io)?;
        Ok(self.staged)
    }

    /// Finishes and moves this single file into place.
    pub fn commit(self) -> std::io::Result<()> {
        commit_all(vec![self.finish()?]).map_err(|(_, e)| e)
    }
}

fn to_io(e: hound::Error) -> std::io::Error {
    match e {
        hound::Error::IoError(io) => io,
        other => std::io::Error::other(other.to_string()),
    }
}
