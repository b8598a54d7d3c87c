//! The Python side of the podcast evaluation: `eval/python/speech_baselines.py` in one worker
//! process (the model loads once), for Silero VAD in onnxruntime (the baseline) and Praat's
//! pitch through parselmouth (styletalk's reference voicing). It needs the virtual environment
//! [`VENV_PYTHON`] that `.ci/run` makes (the command is in [`INSTALL`]).

use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

/// The worker script, embedded so the tools run from any folder.
const SCRIPT: &str = include_str!("../../python/speech_baselines.py");

/// The environment's Python, under the workspace root.
pub const VENV_PYTHON: &str = "target/venv-speech/bin/python";

/// How to make it.
pub const INSTALL: &str = "python3 -m venv target/venv-speech && \
target/venv-speech/bin/pip install onnxruntime==1.32.0 numpy==2.4.6 praat-parselmouth==0.4.7 && \
target/venv-speech/bin/pip install --no-deps silero-vad==6.2.3";

/// A running worker.
pub struct Worker {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
    scratch: PathBuf,
}

impl Worker {
    /// Starts the worker with `python`, checking first that it imports what `modules` name;
    /// `Err` says how to install them.
    pub fn start(python: &Path, scratch: &Path, modules: &[&str]) -> Result<Self, String> {
        let probe = Command::new(python)
            .arg("-c")
            .arg(format!("import {}", modules.join(", ")))
            .output()
            .map_err(|e| format!("{}: {e}; make it with `{INSTALL}`", python.display()))?;
        if !probe.status.success() {
            return Err(format!(
                "{} cannot import {}: install with `{INSTALL}`",
                python.display(),
                modules.join(", ")
            ));
        }
        std::fs::create_dir_all(scratch).map_err(|e| format!("{}: {e}", scratch.display()))?;
        let script = scratch.join("speech_baselines.py");
        std::fs::write(&script, SCRIPT).map_err(|e| format!("{}: {e}", script.display()))?;
        let mut child = Command::new(python)
            .arg(&script)
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
            scratch: scratch.to_path_buf(),
        })
    }

    /// Runs `job` (`silero` or `praat`) on 16 kHz `audio`; returns the text it wrote.
    fn run(&mut self, job: &str, audio: &[f32]) -> Result<String, String> {
        let input = self.scratch.join("job.f32");
        let output = self.scratch.join("job.txt");
        let bytes: Vec<u8> = audio.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&input, bytes).map_err(|e| format!("{}: {e}", input.display()))?;
        writeln!(
            self.stdin,
            "{job}\t{}\t{}",
            input.display(),
            output.display()
        )
        .and_then(|()| self.stdin.flush())
        .map_err(|e| format!("the {job} worker stopped: {e}"))?;
        let mut answer = String::new();
        self.stdout
            .read_line(&mut answer)
            .map_err(|e| format!("the {job} worker stopped: {e}"))?;
        match answer.trim() {
            "ok" => {
                std::fs::read_to_string(&output).map_err(|e| format!("{}: {e}", output.display()))
            }
            "" => Err(format!("the {job} worker stopped")),
            other => Err(format!("{job}: {other}")),
        }
    }

    /// Silero's probability of every 512-sample chunk of 16 kHz `audio` (onnxruntime).
    pub fn silero(&mut self, audio: &[f32]) -> Result<Vec<f32>, String> {
        let text = self.run("silero", audio)?;
        text.lines()
            .map(|l| {
                l.trim()
                    .parse::<f32>()
                    .map_err(|_| format!("silero wrote {l:?}"))
            })
            .collect()
    }

    /// Praat's pitch frames `(time_s, f0_hz)` of 16 kHz `audio`.
    pub fn praat(&mut self, audio: &[f32]) -> Result<Vec<(f64, f64)>, String> {
        let text = self.run("praat", audio)?;
        Ok(super::sources::read_f0_csv(&text))
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
