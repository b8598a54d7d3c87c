//! A Python interpreter with the third-party modules a test checks Pneuma's output with
//! (python-osc and vmcp for VMC packets, mido for MIDI files, bvh for BVH), in the virtual
//! environment `.ci/run` makes, or the one a variable names.
//!
//! Without one a test skips visibly, saying how to make it; when the run requires it (CI), it
//! fails instead, so CI never passes by skipping.

use std::path::PathBuf;
use std::process::Command;

use crate::voice::workspace_root;

/// Where a test's Python comes from and what it must hold.
#[derive(Debug, Clone, Copy)]
pub struct Tools {
    /// The variable naming the interpreter (else the virtual environment's).
    pub env_var: &'static str,
    /// The virtual environment `.ci/run` makes, relative to the workspace root.
    pub venv: &'static str,
    /// The modules, as `import` takes them (`mido, bvh`).
    pub modules: &'static str,
    /// pip's arguments that install them (pinned versions).
    pub pip: &'static str,
}

impl Tools {
    /// The interpreter, or `None` (the test named `test` then skips, saying how to get one;
    /// when `required`, it panics instead).
    pub fn python(&self, test: &str, required: bool) -> Option<PathBuf> {
        let python = std::env::var_os(self.env_var)
            .map(PathBuf::from)
            .unwrap_or_else(|| workspace_root().join(self.venv).join("bin/python"));
        let ok = Command::new(&python)
            .args(["-c", &format!("import {}", self.modules)])
            .output()
            .is_ok_and(|o| o.status.success());
        let how = format!(
            "no Python with {} at {} (python3 -m venv {venv} && {venv}/bin/pip install {}, or \
             name one in {})",
            self.modules,
            python.display(),
            self.pip,
            self.env_var,
            venv = self.venv,
        );
        assert!(ok || !required, "{test}: {how}; this run requires it");
        if !ok {
            eprintln!("SKIPPED {test}: {how}");
        }
        ok.then_some(python)
    }
}

/// The independent readers of the CLI's files: mido (MIDI files) and bvh (BVH), in the
/// virtual environment `.ci/run` makes (`target/cli-venv`) or `PNEUMA_PYTHON_TOOLS`.
pub const FILE_READERS: Tools = Tools {
    env_var: "PNEUMA_PYTHON_TOOLS",
    venv: "target/cli-venv",
    modules: "mido, bvh",
    pip: "mido==1.3.3 bvh==0.3",
};

/// Whether this is a CI run (`CI` set to `true` or `1`): tools a test needs must be there.
pub fn ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

#[cfg(test)]
mod tests {
    use super::*;

    const MISSING: Tools = Tools {
        env_var: "PNEUMA_TESTKIT_NO_SUCH_PYTHON",
        venv: "target/no-such-venv",
        modules: "pneuma_no_such_module",
        pip: "nothing",
    };

    #[test]
    fn a_missing_python_skips_unless_required() {
        assert_eq!(MISSING.python("skips", false), None);
        let required = std::panic::catch_unwind(|| MISSING.python("fails", true));
        assert!(required.is_err());
    }
}
