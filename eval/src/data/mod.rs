//! Reading the evaluation corpora: the styletalk clips (audio with head motion,
//! [`styletalk`]). Errors say which file is wrong and what the folder should hold.

use std::path::PathBuf;

use pneuma_core::AnalysisError;
use pneuma_io::ReadError;
use thiserror::Error;

pub mod styletalk;

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

/// Errors of reading a data set.
#[derive(Debug, Error)]
pub enum DataError {
    /// The data folder is missing or unreadable.
    #[error("cannot read the data folder {path}: {source} (give a folder of <clip>.wav + <clip>.head.csv, e.g. ../shared/data/styletalk)")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// No clip pairs found.
    #[error("no <clip>.wav + <clip>.head.csv pairs in {path}: {unmatched}; each clip needs both files with the same name before the extension")]
    NoClips {
        /// The folder.
        path: PathBuf,
        /// Which files lack their partner, or that the folder has neither kind.
        unmatched: String,
    },
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
    /// Reading an audio file failed.
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// Analysis settings failed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
}
