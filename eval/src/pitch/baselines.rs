//! The Python pitch baselines of `cargo xtask eval-pitch`: swift-f0 (an ONNX CNN, PyPI) and pYIN
//! (librosa), run by `eval/python/f0_baselines.py` in one worker process per evaluation (the
//! models load once). The worker needs a Python with `swift-f0` (and `librosa` for pYIN):
//! `python3 -m venv target/venv-f0 && target/venv-f0/bin/pip install swift-f0==0.3.0
//! soundfile==0.14.0 soxr==1.1.0 librosa==0.11.0` (librosa only for pYIN; `.ci/run` installs the
//! rest). Each tracker's frames keep their own times; eval-pitch puts them on its
//! scoring grid like Praat's.

use std::path::Path;

use crate::python_worker::{PythonWorker, WorkerScript};

/// The worker script, embedded so the xtask runs from any folder.
const SCRIPT: &str = include_str!("../../python/f0_baselines.py");

/// Where `.ci/run` and the README put the virtual environment.
pub const DEFAULT_PYTHON: &str = "target/venv-f0/bin/python";

/// The names of the trackers the worker runs, as eval-pitch prints them.
pub const SWIFT_F0: &str = "swift-f0";
/// pYIN (librosa).
pub const PYIN: &str = "pyin";

/// How the worker's Python is made.
const INSTALL: &str = "python3 -m venv target/venv-f0 && target/venv-f0/bin/pip install \
swift-f0==0.3.0 soundfile==0.14.0 soxr==1.1.0 librosa==0.11.0  # librosa only for --pyin";

/// A running worker.
pub struct Baselines(PythonWorker);

impl Baselines {
    /// Starts the worker with `python` (checked to import the modules `modules` needs first);
    /// `Err` says what is missing and how to install it.
    pub fn start(python: &Path, scratch: &Path, modules: &[&str]) -> Result<Self, String> {
        let script = WorkerScript {
            name: "f0_baselines.py",
            text: SCRIPT,
            install: INSTALL,
        };
        PythonWorker::start(python, scratch, modules, script).map(Self)
    }

    /// Runs `tracker` on `wav` (frame period `period_s`, used by pYIN) and returns its frames:
    /// times (s) and f0 (Hz, 0 unvoiced).
    pub fn track(
        &mut self,
        tracker: &str,
        wav: &Path,
        period_s: f64,
    ) -> Result<(Vec<f64>, Vec<f32>), String> {
        let wav = std::fs::canonicalize(wav).map_err(|e| format!("{}: {e}", wav.display()))?;
        let out = self.0.scratch_file(&format!("{tracker}_out.csv"));
        let (wav_text, out_text) = (wav.display().to_string(), out.display().to_string());
        let period = format!("{period_s:.9}");
        let context = format!(" on {wav_text}");
        self.0
            .request(tracker, &[&wav_text, &out_text, &period], &context)?;
        let text = std::fs::read_to_string(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        parse_track(&text).map_err(|line| format!("{tracker} wrote {line:?}"))
    }
}

/// Parses a tracker's `time_s,f0_hz` lines (blank lines skipped) into times and f0; `Err` holds
/// the first unreadable line.
pub fn parse_track(text: &str) -> Result<(Vec<f64>, Vec<f32>), String> {
    let mut times = Vec::new();
    let mut f0 = Vec::new();
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let row = line.split_once(',').and_then(|(t, f)| {
            Some((t.trim().parse::<f64>().ok()?, f.trim().parse::<f32>().ok()?))
        });
        let (t, f) = row.ok_or_else(|| line.to_string())?;
        times.push(t);
        f0.push(f);
    }
    Ok((times, f0))
}
