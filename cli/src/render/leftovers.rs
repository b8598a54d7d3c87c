//! Files an earlier render left beside this one's outputs: the files Pneuma names for the same
//! stem in the same folder (the plot, the BVH, the MIDI file, the marker files; see the plan's
//! `FolderFiles::optional`) that this render does not write. Left in place they would describe
//! other audio (an editor would import seven breath labels for audio that holds three), so once
//! the render's own files are committed they are removed and named in the summary (even under
//! `--quiet`: a removal is never silent); with `--no-overwrite` they are kept and named in a
//! warning.
//!
//! Only a file Pneuma provably wrote is a leftover: a regular file under one of those exact
//! names that carries Pneuma's mark for its format ([`super::marks`]). A file of such a name
//! without the mark is the user's (episode artwork `ep.png`, a motion capture `take1.bvh`) and
//! is neither touched nor named; so are links, folders, the audio of another format (it may be
//! the user's own recording, even the input) and every name the naming rule does not give for
//! that stem.

use std::path::PathBuf;

use super::marks::Optional;

/// A file a render names for its stem but does not write this time.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Leftover {
    /// Its path in the output folder.
    pub path: PathBuf,
    /// Which of the optional files it is.
    pub file: Optional,
}

/// What became of the leftovers that existed after a render.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cleared {
    /// Removed.
    pub removed: Vec<Leftover>,
    /// Kept, as `--no-overwrite` asks.
    pub kept: Vec<Leftover>,
    /// Not removable, with why.
    pub failed: Vec<(Leftover, String)>,
}

/// Removes the `candidates` that exist and carry Pneuma's mark, or with `keep`
/// (`--no-overwrite`) only notes them; call it once the render's own files are committed.
pub fn clear(candidates: &[Leftover], keep: bool) -> Cleared {
    let mut done = Cleared::default();
    for c in candidates
        .iter()
        .filter(|c| super::marks::is_pneumas(&c.path, c.file))
    {
        if keep {
            done.kept.push(c.clone());
        } else {
            match std::fs::remove_file(&c.path) {
                Ok(()) => done.removed.push(c.clone()),
                Err(e) => done.failed.push((c.clone(), e.to_string())),
            }
        }
    }
    done
}

/// `out/X.bvh (no --bvh), out/X.png (--no-plot)`.
fn list(leftovers: &[Leftover]) -> String {
    leftovers
        .iter()
        .map(|l| format!("{} ({})", l.path.display(), l.file.left_out_by()))
        .collect::<Vec<_>>()
        .join(", ")
}

impl Cleared {
    /// The summary's line on the removed files, if any.
    pub fn removed_line(&self) -> Option<String> {
        (!self.removed.is_empty()).then(|| {
            format!(
                "removed {}: left by an earlier render, {} no longer matched the audio",
                list(&self.removed),
                if self.removed.len() == 1 {
                    "it"
                } else {
                    "they"
                }
            )
        })
    }

    /// The warnings (after `warning: `): files kept by `--no-overwrite`, files not removable.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if !self.kept.is_empty() {
            let (verb, them) = if self.kept.len() == 1 {
                ("matches", "it")
            } else {
                ("match", "them")
            };
            w.push(format!(
                "{} left from an earlier render no longer {verb} the audio; --no-overwrite \
                 keeps {them}: remove {them} by hand",
                list(&self.kept)
            ));
        }
        for (l, why) in &self.failed {
            w.push(format!(
                "cannot remove {} ({}), left from an earlier render: {why}; it no longer \
                 matches the audio",
                l.path.display(),
                l.file.left_out_by()
            ));
        }
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::markers::MarkerKind;
    use pneuma_core::encode::bvh;

    #[test]
    fn only_the_existing_files_named_that_pneuma_wrote_are_removed_or_with_keep_kept() {
        let dir = tempfile::tempdir().expect("temp");
        let named = |name: &str, file| Leftover {
            path: dir.path().join(name),
            file,
        };
        let candidates = [
            named("x.bvh", Optional::Bvh),
            named("x.mid", Optional::Midi),
            named("x.png", Optional::Plot),
            named("x.breaths.txt", Optional::Markers(MarkerKind::Audacity)),
        ];
        let pneumas_bvh = bvh::header(10, 120.0);
        std::fs::write(dir.path().join("x.bvh"), &pneumas_bvh).expect("write");
        // The user's: a MIDI file of their own, a folder of a companion's name, a link to a
        // file Pneuma wrote, another stem's file.
        std::fs::write(dir.path().join("x.mid"), b"MThd\0\0\0\x06the user's song").expect("write");
        std::fs::create_dir(dir.path().join("x.png")).expect("dir");
        std::fs::write(dir.path().join("y.bvh"), &pneumas_bvh).expect("write");
        #[cfg(unix)]
        std::os::unix::fs::symlink(dir.path().join("y.bvh"), dir.path().join("x.breaths.txt"))
            .expect("link");
        let kept = clear(&candidates, true);
        assert_eq!(kept.kept, [candidates[0].clone()]);
        assert!(kept.removed.is_empty() && kept.removed_line().is_none());
        assert!(dir.path().join("x.bvh").exists());
        assert!(kept.warnings()[0].contains("x.bvh (no --bvh) left from an earlier render"));
        let done = clear(&candidates, false);
        assert_eq!(done.removed, [candidates[0].clone()]);
        assert!(done.warnings().is_empty());
        let line = done.removed_line().expect("a line");
        assert!(
            line.starts_with("removed ") && line.contains("x.bvh (no --bvh)"),
            "{line}"
        );
        assert!(!dir.path().join("x.bvh").exists());
        assert!(dir.path().join("x.mid").is_file());
        assert!(dir.path().join("x.png").is_dir());
        assert!(dir.path().join("y.bvh").is_file());
        #[cfg(unix)]
        assert!(std::fs::symlink_metadata(dir.path().join("x.breaths.txt")).is_ok());
    }
}
