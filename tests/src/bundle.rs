//! Which plugin library the tests and benches load.
//!
//! A CLAP plugin on Linux is a shared library under another name, and `pneuma-tests`
//! dev-depends on `pneuma-plugin`: so `cargo test` (and `cargo bench`) build the plugin's
//! `cdylib` in the same run, profile and features as everything else, beside the test binaries
//! (`target/<profile>/deps/libpneuma_plugin.so`). [`plugin_path`] finds it there; nothing is
//! built a second time. Under `cargo test` it is a debug build: debug assertions are on, so
//! nice-plug's allocation guard aborts the test on any allocation inside `process`. Under
//! `cargo bench` it is an optimised (release-like) build.
//!
//! `PNEUMA_CLAP=path` loads that file instead (a relative path is read from the workspace root,
//! not from the crate folder cargo runs the tests in): `.ci/run` runs the same tests on the shipped
//! bundle (`cargo xtask bundle pneuma-plugin --release --features editor`,
//! `target/bundled/Pneuma.clap`).
//!
//! A `cargo build` of the plugin with other features or another profile between two test runs
//! writes the same file name; the next `cargo test` that rebuilds the plugin replaces it again.

use std::path::PathBuf;

/// The environment variable naming a plugin file to load instead of the one cargo built.
pub const PLUGIN_ENV: &str = "PNEUMA_CLAP";

/// The plugin library to load: `PNEUMA_CLAP` if set, else the `cdylib` cargo built beside the
/// running test or bench binary. Panics with what to do when the file is missing.
pub fn plugin_path() -> PathBuf {
    let path = match std::env::var_os(PLUGIN_ENV) {
        Some(p) => from_workspace_root(PathBuf::from(p)),
        None => beside_this_binary(),
    };
    assert!(
        path.is_file(),
        "{} does not exist: {}",
        path.display(),
        if std::env::var_os(PLUGIN_ENV).is_some() {
            "build it (cargo xtask bundle pneuma-plugin --release) or unset PNEUMA_CLAP"
        } else {
            "run the tests through cargo (cargo test -p pneuma-tests builds the plugin library \
             first, as a dev-dependency)"
        }
    );
    path
}

/// A relative `PNEUMA_CLAP` is read from the workspace root, where the user typed the command:
/// cargo runs each test binary in its own crate's folder (`tests/`), where
/// `target/bundled/Pneuma.clap` would name a file that is not there.
fn from_workspace_root(path: PathBuf) -> PathBuf {
    if path.is_absolute() {
        return path;
    }
    let crate_dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    crate_dir
        .parent()
        .expect("the tests crate sits in the workspace")
        .join(path)
}

/// `<dir of this executable>/libpneuma_plugin.so` (the platform's library name).
fn beside_this_binary() -> PathBuf {
    let exe = std::env::current_exe().expect("the test binary's path");
    let dir = exe.parent().expect("the test binary sits in a folder");
    dir.join(format!(
        "{}pneuma_plugin{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ))
}
