//! Reading the evaluation corpora beside the checkout (`../shared/data`, never in it): the
//! styletalk clips with head motion ([`styletalk`]), the pitch references of Keele and
//! PTDB-TUG ([`reference`]), folders of WAV files, the hand labels of real breaths
//! (`assets/labels/*.csv`, [`read_labels`]), and the feature frames of audio ([`analyse`]).
//! Errors say which file is wrong and what the folder should hold.

use std::path::{Path, PathBuf};

use pneuma_core::{AnalysisConfig, AnalysisError, Analyzer, FeatureFrame};
use pneuma_io::capped::{read_text_capped, CappedReadError, DATA_TEXT_MAX_BYTES};
use pneuma_io::ReadError;
use thiserror::Error;

use crate::labels::{parse_labels, Label};

pub mod reference;
pub mod styletalk;

/// Errors of reading a data set.
#[derive(Debug, Error)]
pub enum DataError {
    /// The data folder is missing or unreadable.
    #[error("cannot read the data folder {path}: {source} (give a folder of {holds})")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
        /// What the folder should hold, and where such folders are.
        holds: &'static str,
    },
    /// A folder holds none of the files the evaluation reads.
    #[error("{path} holds no {what}")]
    Empty {
        /// The folder.
        path: PathBuf,
        /// The files it should hold.
        what: &'static str,
    },
    /// No clip pairs found.
    #[error("no <clip>.wav + <clip>.head.csv pairs in {path}: {unmatched}; each clip needs both files with the same name before the extension")]
    NoClips {
        /// The folder.
        path: PathBuf,
        /// Which files lack their partner, or that the folder has neither kind.
        unmatched: String,
    },
    /// A text file of the data (a head CSV, labels, a pitch reference) cannot be read, is too
    /// large or is no text.
    #[error(transparent)]
    TextFile(#[from] CappedReadError),
    /// A head CSV is malformed.
    #[error("{path} line {line}: {reason} (expected header time_s,pitch_deg,yaw_deg,roll_deg and numeric rows)")]
    Csv {
        /// The file.
        path: PathBuf,
        /// Line number (1-based).
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// A pitch reference (`<clip>.f0.csv`) is unreadable or malformed.
    #[error("{path}: {reason}")]
    Reference {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The labels file cannot be read.
    #[error("cannot read the labels {path}: {source}")]
    LabelsFile {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The labels file is malformed.
    #[error("labels {path}: {reason}")]
    Labels {
        /// The file.
        path: PathBuf,
        /// What is wrong, with its line.
        reason: String,
    },
    /// A labels file names a clip the data folder does not hold.
    #[error("the labels {labels} name clip {clip:?}, which is not in {data}")]
    UnknownClip {
        /// The labels file.
        labels: PathBuf,
        /// The clip.
        clip: String,
        /// The data folder.
        data: PathBuf,
    },
    /// Reading an audio file failed (the reader's message names the file).
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// Analysis settings failed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
}

/// The evaluations that have not moved to [`DataError`] yet report errors as text.
impl From<DataError> for String {
    fn from(e: DataError) -> Self {
        e.to_string()
    }
}

/// The workspace's root: the folder holding `eval/`.
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the evaluation crate lives in the workspace")
        .to_path_buf()
}

/// A data set of the shared folder beside the checkout: `<root>/../shared/data/<name>`.
pub fn shared_data(name: &str) -> PathBuf {
    workspace_root().join(format!("../shared/data/{name}"))
}

/// The `.wav` files of `dir`, sorted by name; `holds` says what the folder should hold (for
/// the error when it cannot be read).
pub fn wav_files(dir: &Path, holds: &'static str) -> Result<Vec<PathBuf>, DataError> {
    let entries = std::fs::read_dir(dir).map_err(|source| DataError::Folder {
        path: dir.into(),
        source,
        holds,
    })?;
    let mut wavs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "wav"))
        .collect();
    wavs.sort();
    Ok(wavs)
}

/// Reads a text file of the data whole (labels, a pitch reference), refused past
/// [`DATA_TEXT_MAX_BYTES`]; `what` says what it should be (in the errors).
pub fn read_text(path: &Path, what: &str) -> Result<String, CappedReadError> {
    read_text_capped(path, DATA_TEXT_MAX_BYTES, what)
}

/// Reads a labels file (see [`parse_labels`]).
pub fn read_labels(path: &Path) -> Result<Vec<Label>, DataError> {
    let what = "a breath labels file (clip,start_s,end_s,kind)";
    let text = read_text(path, what).map_err(|e| match e {
        CappedReadError::Io { path, source } => DataError::LabelsFile { path, source },
        other => DataError::TextFile(other),
    })?;
    parse_labels(&text).map_err(|reason| DataError::Labels {
        path: path.into(),
        reason,
    })
}

/// The feature frames of mono `samples` at `rate_hz` with `config` (the analysis runs in
/// blocks; any block size gives the same frames).
pub fn analyse(
    samples: &[f32],
    rate_hz: f64,
    config: &AnalysisConfig,
) -> Result<Vec<FeatureFrame>, AnalysisError> {
    let mut a = Analyzer::new(config.clone())?;
    a.prepare(rate_hz, 4096)?;
    let mut frames = Vec::new();
    for block in samples.chunks(4096) {
        a.process(block, |f| frames.push(*f))?;
    }
    a.finish(|f| frames.push(*f))?;
    Ok(frames)
}

/// The feature frames of an audio file (any format `pneuma-io` reads), mixed to mono.
pub fn analyse_file(path: &Path, config: &AnalysisConfig) -> Result<Vec<FeatureFrame>, DataError> {
    let (samples, rate) = pneuma_io::read_mono(path)?;
    Ok(analyse(&samples, f64::from(rate), config)?)
}

/// Writes `audio` at `rate_hz` to `path` as a mono 32-bit float WAV; the error names the file.
pub fn write_mono_wav(path: &Path, audio: &[f32], rate_hz: u32) -> Result<(), String> {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate_hz,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let err = |e: hound::Error| format!("{}: {e}", path.display());
    let mut w = hound::WavWriter::create(path, spec).map_err(err)?;
    for &x in audio {
        w.write_sample(x).map_err(err)?;
    }
    w.finalize().map_err(err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_folders_and_labels_name_the_file_and_what_to_give() {
        let e = wav_files(Path::new("no/such/styletalk"), ".wav files, e.g. styletalk")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cannot read the data folder no/such/styletalk")
                && e.contains("give a folder of .wav files"),
            "{e}"
        );
        let e = read_labels(Path::new("no/such/labels.csv"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cannot read the labels no/such/labels.csv"),
            "{e}"
        );
    }

    #[test]
    fn labels_and_pitch_references_past_the_limit_are_refused_by_name() {
        let dir = tempfile::tempdir().expect("temp dir");
        let big = dir.path().join("big.csv");
        std::fs::File::create(&big)
            .and_then(|f| f.set_len(DATA_TEXT_MAX_BYTES + 1))
            .expect("a sparse file");
        let e = read_labels(&big).unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "{} is larger than 64 MiB, the limit for a breath labels file \
                 (clip,start_s,end_s,kind): is it the right file?",
                big.display()
            )
        );
        let e = reference::read_reference(&big).unwrap_err().to_string();
        assert!(
            e.ends_with(
                "larger than 64 MiB, the limit for a pitch reference (time_s,f0_hz): is \
                 it the right file?"
            ),
            "{e}"
        );
        // A missing reference still says which file.
        let missing = dir.path().join("missing.f0.csv");
        let e = reference::read_reference(&missing).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{}: ", missing.display())), "{e}");
    }
}
