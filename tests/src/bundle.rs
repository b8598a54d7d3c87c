//! Where the plugin bundle is, and how the tests get an up-to-date one.
//!
//! Policy: the tests **build the bundle themselves**, once per test binary, by running
//! `cargo xtask bundle pneuma-plugin --release` in the workspace (cargo makes that a quick no-op
//! when nothing changed). So `cargo test --workspace` never tests a stale plugin and needs no
//! earlier step. If the build fails, the tests fail with the command to run by hand and its
//! output. Set `PNEUMA_SKIP_BUNDLE_BUILD=1` to use an existing `target/bundled/Pneuma.clap` as
//! it is (then a missing bundle fails with the command to build it).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The command that builds the bundles.
pub const BUNDLE_COMMAND: &str = "cargo xtask bundle pneuma-plugin --release";

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ sits in the workspace")
        .to_path_buf()
}

/// The cargo target directory (honours `CARGO_TARGET_DIR`).
pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|p| {
            if p.is_absolute() {
                p
            } else {
                workspace_root().join(p)
            }
        })
        .unwrap_or_else(|| workspace_root().join("target"))
}

/// `target/bundled/Pneuma.clap`.
pub fn clap_path() -> PathBuf {
    target_dir().join("bundled").join("Pneuma.clap")
}

/// `target/bundled/Pneuma.vst3`.
pub fn vst3_path() -> PathBuf {
    target_dir().join("bundled").join("Pneuma.vst3")
}

fn build() -> Result<PathBuf, String> {
    let path = clap_path();
    if std::env::var_os("PNEUMA_SKIP_BUNDLE_BUILD").is_none() {
        let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
        let output = Command::new(cargo)
            .args(["xtask", "bundle", "pneuma-plugin", "--release"])
            .current_dir(workspace_root())
            .output()
            .map_err(|e| {
                format!(
                    "cannot run cargo to build the bundle ({e}); run `{BUNDLE_COMMAND}` by hand"
                )
            })?;
        if !output.status.success() {
            return Err(format!(
                "building the plugin bundle failed; run `{BUNDLE_COMMAND}` and fix what it reports:\n{}",
                String::from_utf8_lossy(&output.stderr)
            ));
        }
    }
    if !path.exists() {
        return Err(format!(
            "{} does not exist: run `{BUNDLE_COMMAND}` first",
            path.display()
        ));
    }
    Ok(path)
}

/// The path of an up-to-date `Pneuma.clap`, built once per process; panics with the command to
/// run if that fails.
pub fn ensure_clap() -> PathBuf {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    match BUILT.get_or_init(build) {
        Ok(p) => p.clone(),
        Err(e) => panic!("{e}"),
    }
}

fn build_cli() -> Result<PathBuf, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args(["build", "--release", "-p", "pneuma-cli"])
        .current_dir(workspace_root())
        .output()
        .map_err(|e| format!("cannot run cargo to build the CLI ({e})"))?;
    if !output.status.success() {
        return Err(format!(
            "building the CLI failed; run `cargo build --release -p pneuma-cli`:\n{}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let path = target_dir().join("release").join("pneuma");
    if path.exists() {
        Ok(path)
    } else {
        Err(format!("{} missing after the build", path.display()))
    }
}

/// The release `pneuma` binary, built once per process (same policy as the bundle).
pub fn ensure_cli() -> PathBuf {
    static BUILT: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    match BUILT.get_or_init(build_cli) {
        Ok(p) => p.clone(),
        Err(e) => panic!("{e}"),
    }
}
