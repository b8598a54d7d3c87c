//! `cargo xtask train-default [--data DIR] [--check]`: trains the shipped head model on the
//! styletalk clips with the project's own code and writes `assets/models/head-default.json`
//! (embedded into `pneuma-core`). Training is deterministic (seeded EM, single thread), so the
//! same data and code regenerate the file bit for bit; `--check` verifies that instead of
//! writing.

use pneuma_cli::train::{print_report, run, Args};

/// Description of the data recorded in the model's provenance (no machine-specific paths).
const DATA_DESCRIPTION: &str =
    "styletalk clips (../shared/data/styletalk; MIT-licensed research repository): \
16 kHz speech with head rotation from monocular 3D face reconstruction at 30 fps";

/// Runs the chore; returns the process exit code.
pub fn main(args: &[String]) -> i32 {
    let root = crate::workspace_root();
    let (data, check) = match crate::data_and_check(args, root.join("../shared/data/styletalk")) {
        Ok(parsed) => parsed,
        Err(code) => return code,
    };
    if !data.is_dir() {
        eprintln!(
            "error: {} not found: the default model is trained on ../shared/data/styletalk beside the checkout (or pass --data DIR)",
            data.display()
        );
        return 1;
    }
    let out = root.join("assets/models/head-default.json");
    let train_args = Args {
        data,
        output: out.clone(),
        components: 11,
        pose_components: pneuma_core::head::TrainConfig::default().pose_components,
        restarts: 3,
        seed: 2015,
        frame_rate: 120.0,
        motion_smoothing_ms: 25.0,
    };
    let (json, cv) = match run(&train_args, DATA_DESCRIPTION) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return 1;
        }
    };
    print_report(&cv);
    if check {
        let old = std::fs::read_to_string(&out).unwrap_or_default();
        if old == json {
            println!("{} is reproduced bit for bit", out.display());
            0
        } else {
            eprintln!("error: {} differs from a fresh training run", out.display());
            1
        }
    } else {
        match std::fs::write(&out, json) {
            Ok(()) => {
                println!("wrote {}", out.display());
                0
            }
            Err(e) => {
                eprintln!("error: cannot write {}: {e}", out.display());
                1
            }
        }
    }
}
