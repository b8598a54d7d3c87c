//! The Python side of the podcast evaluation: `eval/python/speech_baselines.py` in one worker
//! process (the model loads once), for Silero VAD in onnxruntime (the baseline) and Praat's
//! pitch through parselmouth (styletalk's reference voicing). It needs the virtual environment
//! [`VENV_PYTHON`] that `.ci/run` makes (the command is in [`INSTALL`]).

use std::path::Path;

use crate::python_worker::{PythonWorker, WorkerScript};

/// The worker script, embedded so the tools run from any folder.
const SCRIPT: &str = include_str!("../../python/speech_baselines.py");

/// The environment's Python, under the workspace root.
pub const VENV_PYTHON: &str = "target/venv-speech/bin/python";

/// How to make it.
pub const INSTALL: &str = "python3 -m venv target/venv-speech && \
target/venv-speech/bin/pip install onnxruntime==1.32.0 numpy==2.4.6 praat-parselmouth==0.4.7 && \
target/venv-speech/bin/pip install --no-deps silero-vad==6.2.3";

/// A running worker.
pub struct Worker(PythonWorker);

impl Worker {
    /// Starts the worker with `python`, checking first that it imports what `modules` name;
    /// `Err` says how to install them.
    pub fn start(python: &Path, scratch: &Path, modules: &[&str]) -> Result<Self, String> {
        let script = WorkerScript {
            name: "speech_baselines.py",
            text: SCRIPT,
            install: INSTALL,
        };
        PythonWorker::start(python, scratch, modules, script).map(Self)
    }

    /// Runs `job` (`silero` or `praat`) on 16 kHz `audio`; returns the text it wrote.
    fn run(&mut self, job: &str, audio: &[f32]) -> Result<String, String> {
        let input = self.0.scratch_file("job.f32");
        let output = self.0.scratch_file("job.txt");
        let bytes: Vec<u8> = audio.iter().flat_map(|v| v.to_le_bytes()).collect();
        std::fs::write(&input, bytes).map_err(|e| format!("{}: {e}", input.display()))?;
        let fields = [input.display().to_string(), output.display().to_string()];
        self.0.request(job, &[&fields[0], &fields[1]], "")?;
        std::fs::read_to_string(&output).map_err(|e| format!("{}: {e}", output.display()))
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
