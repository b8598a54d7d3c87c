//! The third-party VMC receiver the OSC tests send to: `app/tests/vmc_receiver.py`, which parses
//! every bundle with python-osc and vmcp (see its docs for what it checks), run in a Python
//! environment that has them (`PNEUMA_VMC_PYTHON`, or the virtualenv `.ci/run` makes under
//! `target/vmc-venv`).
//!
//! Without such a Python a test skips visibly; under `PNEUMA_REQUIRE_VMC` (`.ci/run` sets it) it
//! fails instead, so CI never passes by skipping.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::python::Tools;
use crate::voice::workspace_root;

/// The receiver's Python.
const RECEIVER: Tools = Tools {
    env_var: "PNEUMA_VMC_PYTHON",
    venv: "target/vmc-venv",
    modules: "pythonosc, vmcp",
    pip: "python-osc==1.10.2 vmcp==1.0.6",
};

/// Longest wait for the receiver to listen.
const START_TIMEOUT: Duration = Duration::from_secs(30);

/// A Python with python-osc and vmcp, or `None` (the test named `test` then skips, saying how to
/// get one; under `PNEUMA_REQUIRE_VMC` it panics instead).
pub fn receiver_python(test: &str) -> Option<PathBuf> {
    RECEIVER.python(test, std::env::var_os("PNEUMA_REQUIRE_VMC").is_some())
}

/// A running receiver, listening.
pub struct Receiver {
    child: Child,
    ready: PathBuf,
}

impl Receiver {
    /// Starts the receiver in `python` on UDP `port`, expecting `bundles` bundles within
    /// `timeout_s`, with the script's further `args` (`--frame-rate-hz`, `--expect-head`, …), and
    /// waits until it listens. `scratch` is a folder for its ready file.
    ///
    /// # Panics
    /// If it cannot start or does not listen within 30 s.
    pub fn start(
        python: &Path,
        port: u16,
        bundles: usize,
        timeout_s: u32,
        args: &[String],
        scratch: &Path,
    ) -> Receiver {
        let ready = scratch.join(format!("vmc-ready-{port}"));
        let _ = std::fs::remove_file(&ready);
        let child = Command::new(python)
            .arg(workspace_root().join("app/tests/vmc_receiver.py"))
            .args(["--port", &port.to_string()])
            .args(["--bundles", &bundles.to_string()])
            .args(["--timeout-s", &timeout_s.to_string()])
            .args(args)
            .arg("--ready-file")
            .arg(&ready)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start the VMC receiver");
        let t0 = Instant::now();
        while !ready.exists() {
            assert!(
                t0.elapsed() < START_TIMEOUT,
                "the VMC receiver did not start"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        Receiver { child, ready }
    }

    /// Waits for the receiver's verdict: whether it accepted every bundle, and its report
    /// (standard output, then standard error).
    pub fn finish(self) -> (bool, String) {
        let out = self
            .child
            .wait_with_output()
            .expect("the VMC receiver ends");
        let _ = std::fs::remove_file(&self.ready);
        let report = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        (out.status.success(), report)
    }
}
