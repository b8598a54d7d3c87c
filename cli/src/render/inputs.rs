//! The inputs of `pneuma render`: files as given, folders expanded to the files directly
//! inside them ([`expand_inputs`]), each either rendered or listed as skipped with why.

use std::path::{Path, PathBuf};

/// One input of a render: a file to render, or a file found in a folder that is skipped, with
/// why (not audio, or a format Pneuma does not read; see [`pneuma_io::skip_reason`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Input {
    /// The file.
    pub path: PathBuf,
    /// Why it is not rendered; `None` to render it.
    pub skip: Option<String>,
}

/// Why a folder inside a folder given is not rendered.
const SUBFOLDER_SKIPPED: &str = "a folder: its files are not searched; give it as an input too";

/// The inputs of `args`: files as given (each rendered, so a file that is not audio fails with
/// why), folders expanded to every file directly inside them, sorted by name, hidden files
/// (`.DS_Store`) left out; a folder's file that is not audio Pneuma reads is listed as skipped,
/// and so is a folder in it ([`SUBFOLDER_SKIPPED`]) unless it is `output` (the render's output
/// folder) or given as well.
/// A file met again (given twice, or given and in a folder given) is left out the second time:
/// rendering it twice would write the same files twice.
pub fn expand_inputs(args: &[PathBuf], output: &Path) -> Result<Vec<Input>, String> {
    // A path's identity: resolved when it exists, else as given.
    let real = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_owned());
    // Folders inside a folder that are told of: not the render's own output, nor one given.
    let not_told: Vec<PathBuf> = args.iter().map(|p| real(p)).chain([real(output)]).collect();
    let mut out: Vec<Input> = Vec::new();
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut push = |input: Input| {
        // Standard input is no file: a second `-` is the batch's to refuse.
        if input.path.as_os_str() != "-" {
            let id = real(&input.path);
            if seen.contains(&id) {
                return;
            }
            seen.push(id);
        }
        out.push(input);
    };
    for p in args {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| format!("cannot read the folder {}: {e}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    (f.is_file() || (f.is_dir() && !not_told.contains(&real(f))))
                        && f.file_name()
                            .is_some_and(|n| !n.to_string_lossy().starts_with('.'))
                })
                .collect();
            if !found.iter().any(|f| f.is_file()) {
                return Err(format!(
                    "{} holds no files{}; give audio files (.{}) or a folder of them",
                    p.display(),
                    if found.is_empty() {
                        ""
                    } else {
                        " directly inside it (the folders in it are not searched)"
                    },
                    pneuma_io::AUDIO_EXTENSIONS.join(", .")
                ));
            }
            found.sort();
            for path in found {
                // A folder in the folder is listed, not searched: its files would not be
                // rendered without a word.
                let skip = if path.is_dir() {
                    Some(SUBFOLDER_SKIPPED.to_string())
                } else {
                    pneuma_io::skip_reason(&path)
                };
                push(Input { skip, path });
            }
        } else {
            push(Input {
                path: p.clone(),
                skip: None,
            });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_in_a_folder_is_listed_as_skipped_not_left_out() {
        let dir = tempfile::tempdir().expect("temp");
        let ep = dir.path().join("ep.wav");
        std::fs::write(&ep, "audio").expect("write");
        for sub in ["season2", ".git"] {
            std::fs::create_dir(dir.path().join(sub)).expect("mkdir");
            std::fs::write(dir.path().join(sub).join("ep2.wav"), "audio").expect("write");
        }
        let out = dir.path().join("out");
        std::fs::create_dir(&out).expect("mkdir");
        let inputs = expand_inputs(&[dir.path().to_owned()], &out).expect("inputs");
        assert_eq!(inputs.len(), 2, "{inputs:?}");
        assert_eq!((&inputs[0].path, &inputs[0].skip), (&ep, &None));
        assert_eq!(inputs[1].path, dir.path().join("season2"));
        assert_eq!(inputs[1].skip.as_deref(), Some(SUBFOLDER_SKIPPED));
        // A folder given as well is rendered, not told of.
        let both = [dir.path().to_owned(), dir.path().join("season2")];
        let paths: Vec<PathBuf> = expand_inputs(&both, &out)
            .expect("inputs")
            .into_iter()
            .map(|i| i.path)
            .collect();
        assert_eq!(paths, [ep.clone(), dir.path().join("season2/ep2.wav")]);
        // Folders only: no file to render, and why.
        std::fs::remove_file(&ep).expect("rm");
        let err = expand_inputs(&[dir.path().to_owned()], &out).expect_err("no file");
        assert!(err.contains("the folders in it are not searched"), "{err}");
    }

    #[test]
    fn a_file_met_twice_is_an_input_once() {
        let dir = tempfile::tempdir().expect("temp");
        let ep = dir.path().join("ep.wav");
        std::fs::write(&ep, "audio").expect("write");
        let via_dot = dir.path().join(".").join("ep.wav");
        let dash = PathBuf::from("-");
        let given = [
            ep.clone(),
            dir.path().to_owned(),
            via_dot,
            ep.clone(),
            dash.clone(),
            dash.clone(),
        ];
        let paths: Vec<PathBuf> = expand_inputs(&given, Path::new("out"))
            .expect("inputs")
            .into_iter()
            .map(|i| i.path)
            .collect();
        assert_eq!(paths, [ep, dash.clone(), dash]);
    }
}
