//! Reading a small user file whole (a head-pose model, a text to speak, a motion CSV, an
//! evaluation's labels or pitch references) through a size cap, so that a wrong path
//! (`/dev/zero`, a recording given as a model) is refused with a message instead of filling
//! memory. The cap is enforced while reading (`Read::take`), not from
//! the file's metadata: a device or a pipe reports a length of 0.

use std::io::Read;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// One mebibyte.
pub const MIB: u64 = 1024 * 1024;

/// The largest head-pose model file read (`--head-model`): the shipped model is 20 KB and one
/// of 32 components in every GMM (the most `pneuma train` makes) under 1 MB.
pub const HEAD_MODEL_MAX_BYTES: u64 = 16 * MIB;

/// The largest text file spoken (`pneuma speak --text-file`): a long novel is about 1 MB.
pub const TEXT_MAX_BYTES: u64 = 16 * MIB;

/// The largest head-motion CSV read for training (`<clip>.head.csv`): about 5 MB an hour at
/// 30 frames a second, so some 50 hours for one clip.
pub const MOTION_CSV_MAX_BYTES: u64 = 256 * MIB;

/// The largest text file of an evaluation's data read (`pneuma eval`, `cargo xtask eval-*`): a
/// breath labels file (`assets/labels/*.csv`, a few KB) or a pitch reference
/// (`<clip>.f0.csv`: Keele's are 55 KB for 40 s, so this is some 13 hours of one clip).
pub const DATA_TEXT_MAX_BYTES: u64 = 64 * MIB;

/// Why a capped file could not be read.
#[derive(Debug, Error)]
pub enum CappedReadError {
    /// Opening or reading failed.
    #[error("cannot read {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// The file holds more than the limit.
    #[error(
        "{path} is larger than {} MiB, the limit for {what}: is it the right file?",
        limit_bytes / MIB
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// The limit, bytes.
        limit_bytes: u64,
        /// What the file should be, for the message ("a head-pose model (JSON)").
        what: String,
    },
    /// The file is not UTF-8 text.
    #[error(
        "{path} is not UTF-8 text, as {what} is: save it as UTF-8 (a Latin-1 or Windows-1252 \
         file converts with `iconv -f WINDOWS-1252 -t UTF-8 FILE > FILE.utf8`)"
    )]
    NotText {
        /// The file.
        path: PathBuf,
        /// What the file should be.
        what: String,
    },
}

/// The whole of `path` as text, refused when it holds more than `limit_bytes`; `what` says what
/// the file should be (in the errors: "the limit for {what}").
pub fn read_text_capped(
    path: &Path,
    limit_bytes: u64,
    what: &str,
) -> Result<String, CappedReadError> {
    let io = |source| CappedReadError::Io {
        path: path.into(),
        source,
    };
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .map_err(io)?
        .take(limit_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > limit_bytes {
        return Err(CappedReadError::TooLarge {
            path: path.into(),
            limit_bytes,
            what: what.into(),
        });
    }
    String::from_utf8(bytes).map_err(|_| CappedReadError::NotText {
        path: path.into(),
        what: what.into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_up_to_the_limit_is_read_and_a_longer_one_refused() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("model.json");
        std::fs::write(&path, "0123456789").expect("write");
        assert_eq!(
            read_text_capped(&path, 10, "a model").expect("read"),
            "0123456789"
        );
        let e = read_text_capped(&path, 9, "a model").expect_err("too large");
        assert!(
            matches!(e, CappedReadError::TooLarge { limit_bytes: 9, .. }),
            "{e}"
        );
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_device_is_refused_at_the_limit() {
        let e = read_text_capped(Path::new("/dev/zero"), 4 * MIB, "a head-pose model (JSON)")
            .expect_err("endless");
        assert_eq!(
            e.to_string(),
            "/dev/zero is larger than 4 MiB, the limit for a head-pose model (JSON): is it the \
             right file?"
        );
    }

    #[test]
    fn bytes_that_are_not_text_are_refused() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("model.json");
        std::fs::write(&path, [0xff, 0xfe, 0x00]).expect("write");
        let e = read_text_capped(&path, 10, "a model").expect_err("not text");
        assert!(matches!(e, CappedReadError::NotText { .. }), "{e}");
    }
}
