//! One Python worker process for the evaluations' baselines (swift-f0 and pYIN for eval-pitch,
//! Silero and Praat for the podcast material): the script is embedded and written to a scratch
//! folder, the process is started once (its models load once) and answers one tab-separated
//! request line at a time with `ok` or an error, writing its result into a file the request
//! names.

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

/// What a worker runs and how its Python is made.
#[derive(Debug, Clone, Copy)]
pub struct WorkerScript<'a> {
    /// The script's file name in the scratch folder.
    pub name: &'a str,
    /// The script's text.
    pub text: &'a str,
    /// The command that makes a Python that imports what the script needs.
    pub install: &'a str,
}

/// A running worker; dropping it ends the process.
pub struct PythonWorker {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
    script: PathBuf,
}

impl PythonWorker {
    /// Starts `script` with `python` in `scratch`, checking first that `python` imports
    /// `modules`; `Err` says how to install them.
    pub fn start(
        python: &Path,
        scratch: &Path,
        modules: &[&str],
        script: WorkerScript<'_>,
    ) -> Result<Self, String> {
        let install = script.install;
        let probe = Command::new(python)
            .arg("-c")
            .arg(format!("import {}", modules.join(", ")))
            .output()
            .map_err(|e| format!("{}: {e}; make it with `{install}`", python.display()))?;
        if !probe.status.success() {
            return Err(format!(
                "{} cannot import {}: install with `{install}`",
                python.display(),
                modules.join(", ")
            ));
        }
        std::fs::create_dir_all(scratch).map_err(|e| format!("{}: {e}", scratch.display()))?;
        let path = scratch.join(script.name);
        std::fs::write(&path, script.text).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut child = Command::new(python)
            .arg(&path)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start {}: {e}", python.display()))?;
        let stdin = child.stdin.take().ok_or("no stdin")?;
        let stdout = BufReader::new(child.stdout.take().ok_or("no stdout")?);
        Ok(Self {
            child,
            stdin,
            stdout,
            script: path,
        })
    }

    /// The scratch file `name` beside the script (where requests put their inputs and outputs),
    /// named for this process: two evaluations running at once never share one. Removed when
    /// the worker is dropped.
    pub fn scratch_file(&self, name: &str) -> PathBuf {
        self.script
            .with_file_name(format!("{}{name}", scratch_prefix()))
    }

    /// Sends `job`'s request `fields` (joined by tabs after the job's name) and waits for its
    /// `ok`; errors name the job and `context` (e.g. " on FILE").
    pub fn request(&mut self, job: &str, fields: &[&str], context: &str) -> Result<(), String> {
        let mut line = job.to_string();
        for f in fields {
            line.push('\t');
            line.push_str(f);
        }
        writeln!(self.stdin, "{line}")
            .and_then(|()| self.stdin.flush())
            .map_err(|e| format!("the {job} worker stopped: {e}"))?;
        let mut answer = String::new();
        self.stdout
            .read_line(&mut answer)
            .map_err(|e| format!("the {job} worker stopped: {e}"))?;
        match answer.trim() {
            "ok" => Ok(()),
            "" => Err(format!("the {job} worker stopped{context}")),
            other => Err(format!("{job}{context}: {other}")),
        }
    }
}

impl Drop for PythonWorker {
    fn drop(&mut self) {
        // Killing it ends the worker's loop whatever it was doing.
        let _ = self.child.kill();
        let _ = self.child.wait();
        let prefix = scratch_prefix();
        let Some(dir) = self.script.parent() else {
            return;
        };
        for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            if entry.file_name().to_string_lossy().starts_with(&prefix) {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// The start of this process's scratch file names.
fn scratch_prefix() -> String {
    format!("{}-", std::process::id())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Answers `ok` after writing its second field into the file its third names, or the
    /// error `boom` for the job `fail`.
    const ECHO: &str = r"import sys
for line in sys.stdin:
    job, text, out = line.rstrip('\n').split('\t')
    if job == 'fail':
        print('boom', flush=True)
        continue
    open(out, 'w').write(text)
    print('ok', flush=True)
";

    fn python() -> Option<PathBuf> {
        let found = Command::new("python3").arg("-c").arg("pass").output();
        match found {
            Ok(o) if o.status.success() => Some(PathBuf::from("python3")),
            _ if std::env::var_os("CI").is_some() => panic!("CI needs python3 for this test"),
            _ => {
                eprintln!("skipped: no python3");
                None
            }
        }
    }

    fn script() -> WorkerScript<'static> {
        WorkerScript {
            name: "echo.py",
            text: ECHO,
            install: "make-python",
        }
    }

    #[test]
    fn requests_are_answered_in_turn_and_errors_name_the_job_and_context() {
        let Some(python) = python() else { return };
        let dir = tempfile::tempdir().expect("temp");
        let mut w = PythonWorker::start(&python, dir.path(), &["sys"], script()).expect("starts");
        let out = w.scratch_file("out.txt");
        let out_text = out.display().to_string();
        w.request("echo", &["first", &out_text], "").expect("ok");
        assert_eq!(std::fs::read_to_string(&out).expect("written"), "first");
        let err = w
            .request("fail", &["x", &out_text], " on f.wav")
            .expect_err("the worker answered boom");
        assert_eq!(err, "fail on f.wav: boom");
        w.request("echo", &["second", &out_text], "").expect("ok");
        assert_eq!(std::fs::read_to_string(&out).expect("written"), "second");
        // The scratch files are this process's, and go with the worker.
        assert!(out
            .file_name()
            .unwrap()
            .to_string_lossy()
            .starts_with(&scratch_prefix()));
        drop(w);
        assert!(!out.exists(), "{}", out.display());
        assert!(dir.path().join("echo.py").exists());
    }

    #[test]
    fn a_python_without_the_modules_is_told_how_to_install_them() {
        let Some(python) = python() else { return };
        let dir = tempfile::tempdir().expect("temp");
        let err = PythonWorker::start(&python, dir.path(), &["no_such_module_x"], script())
            .err()
            .expect("refused");
        assert!(err.contains("cannot import no_such_module_x"), "{err}");
        assert!(err.contains("install with `make-python`"), "{err}");
    }
}
