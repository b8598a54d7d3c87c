//! Output files that are never half-written: data goes to a temporary file beside the target,
//! which replaces the target only when everything succeeded. `-` means standard output.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A destination: a file written atomically, or standard output.
pub struct Output {
    inner: Option<Inner>,
}

enum Inner {
    Stdout(BufWriter<std::io::Stdout>),
    File {
        writer: BufWriter<File>,
        temp: PathBuf,
        target: PathBuf,
    },
}

impl Output {
    /// Opens `path` (`-` for standard output). A file is written to a temporary name beside it.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        if path.as_os_str() == "-" {
            return Ok(Self {
                inner: Some(Inner::Stdout(BufWriter::new(std::io::stdout()))),
            });
        }
        let temp = temp_path(path);
        let file = File::create(&temp)?;
        Ok(Self {
            inner: Some(Inner::File {
                writer: BufWriter::new(file),
                temp,
                target: path.to_owned(),
            }),
        })
    }

    /// The writer.
    pub fn writer(&mut self) -> &mut dyn Write {
        match self.inner.as_mut() {
            Some(Inner::Stdout(w)) => w,
            Some(Inner::File { writer, .. }) => writer,
            None => unreachable!("an Output is only emptied by commit, which consumes it"),
        }
    }

    /// Flushes and, for a file, moves it onto the target.
    pub fn commit(mut self) -> std::io::Result<()> {
        match self.inner.take() {
            Some(Inner::Stdout(mut w)) => w.flush(),
            Some(Inner::File {
                mut writer,
                temp,
                target,
            }) => {
                let result = writer
                    .flush()
                    .and_then(|()| writer.get_ref().sync_all())
                    .and_then(|()| std::fs::rename(&temp, &target));
                if result.is_err() {
                    let _ = std::fs::remove_file(&temp);
                }
                result
            }
            None => Ok(()),
        }
    }
}

/// The temporary name beside `target` that a file is written under before it is renamed
/// into place: `.<name>.<pid>.partial` in the same folder (so the rename stays on one file
/// system).
pub fn temp_path(target: &Path) -> PathBuf {
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_owned(),
        _ => PathBuf::from("."),
    };
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    dir.join(format!(".{name}.{}.partial", std::process::id()))
}

impl Drop for Output {
    fn drop(&mut self) {
        // Dropped without commit (an error happened): remove the temporary file; the target
        // keeps whatever it held before.
        if let Some(Inner::File { temp, .. }) = self.inner.take() {
            let _ = std::fs::remove_file(temp);
        }
    }
}
