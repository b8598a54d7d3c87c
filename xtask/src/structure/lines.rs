//! The size check: no source file over [`MAX_LINES`] lines, except the generated files listed
//! in [`GENERATED`], each with the command that regenerates it (and checks it bit for bit).

use std::path::{Path, PathBuf};

/// The most lines a source file may have.
pub const MAX_LINES: usize = 900;

/// The kinds of files that count as source: code, scripts, manifests and the model and data
/// files the code embeds. Documentation (`.md`), the lock file, licences and binary assets do
/// not count (the README has its own limit).
pub const SOURCE_EXTENSIONS: [&str; 9] =
    ["rs", "py", "lua", "sh", "toml", "json", "txt", "csv", "yml"];

/// Generated files allowed over [`MAX_LINES`]: (path from the root, the command that
/// regenerates it and whose `--check` reproduces it).
pub const GENERATED: [(&str, &str); 1] = [(
    "assets/models/head-default.json",
    "cargo xtask train-default --check",
)];

/// A file over the limit.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LongFile {
    /// Path from the root.
    pub path: PathBuf,
    /// Its lines.
    pub lines: usize,
}

/// The source files over `max_lines` under `root` that `generated` does not list, and the
/// listed files that do not exist (a stale list is an error too).
pub fn long_files(
    root: &Path,
    max_lines: usize,
    generated: &[(&str, &str)],
) -> Result<(Vec<LongFile>, Vec<PathBuf>), String> {
    let mut long = Vec::new();
    let mut read_error = None;
    super::walk(root, &mut |rel| {
        let source = rel
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| SOURCE_EXTENSIONS.contains(&e));
        if !source || generated.iter().any(|(g, _)| Path::new(g) == rel) {
            return;
        }
        match std::fs::read(root.join(rel)) {
            Ok(bytes) => {
                let lines = String::from_utf8_lossy(&bytes).lines().count();
                if lines > max_lines {
                    long.push(LongFile {
                        path: rel.to_path_buf(),
                        lines,
                    });
                }
            }
            Err(e) => read_error = Some(format!("cannot read {}: {e}", rel.display())),
        }
    })?;
    if let Some(e) = read_error {
        return Err(e);
    }
    long.sort_by(|a, b| a.path.cmp(&b.path));
    let missing = generated
        .iter()
        .map(|(g, _)| PathBuf::from(g))
        .filter(|g| !root.join(g).is_file())
        .collect();
    Ok((long, missing))
}
