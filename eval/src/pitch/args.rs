//! The arguments of `cargo xtask eval-pitch` (see the module docs of [`super`]).

use std::path::PathBuf;

use super::targets::CLEAN_TARGETS;

/// `cargo xtask eval-pitch`: pitch and voicing accuracy against laryngograph references.
#[derive(clap::Parser, Debug)]
#[command(name = "cargo xtask eval-pitch")]
pub(crate) struct Args {
    /// A folder of `<clip>.wav` + `<clip>.f0.csv` (PTDB or Keele style); give it several times
    /// (`--data ../shared/data/ptdb --data ../shared/data/keele`).
    #[arg(long, required = true)]
    pub(crate) data: Vec<PathBuf>,
    /// Analysis setting override for Pneuma (`--set frame_rate_hz=200`); repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_setting)]
    pub(crate) set: Vec<(String, String)>,
    /// Exit 1 unless Pneuma meets the PTDB targets (see the module documentation), and the
    /// clean-data targets named by `--clean-targets`.
    #[arg(long)]
    pub(crate) check: bool,
    /// With `--check`, also fail on these targets of a clean data set (Keele), each judged
    /// like the PTDB ones: `clean` (FFE and VDE no higher than Praat's), `white` and `babble`
    /// (FFE no higher than Praat's at every SNR of that noise), `speakers` (every speaker's
    /// FFE within 1.5 points of Praat's). The others are printed as met / MISSED only.
    #[arg(long, value_delimiter = ',', value_name = "TARGET", value_parser = CLEAN_TARGETS)]
    pub(crate) clean_targets: Vec<String>,
    /// Leave Praat out even when it is installed.
    #[arg(long)]
    pub(crate) no_praat: bool,
    /// Use this global offset (ms) for every data set instead of searching one.
    #[arg(long, allow_hyphen_values = true)]
    pub(crate) offset: Option<i32>,
    /// Skip the held-out column (`pneuma-loso`: each clip judged by a voicing model fitted
    /// without its speaker on ../shared/data/keele and ../shared/data/ptdb); the targets then
    /// judge the shipped model, fitted on every speaker.
    #[arg(long)]
    pub(crate) no_loso: bool,
    /// The kind of model the held-out column fits: `logistic` (format version 1), `trees`
    /// (boosted trees, version 2) or `hybrid` (the logistic regression plus trees boosted from
    /// its score, version 3), to compare them on held-out speakers; default the kind
    /// `train-voicing` ships.
    #[arg(long, value_name = "KIND", value_parser = ["logistic", "trees", "hybrid"])]
    pub(crate) loso_model: Option<String>,
    /// Judge the targets on the shipped model's figure (fitted on every speaker, the evaluated
    /// ones included) instead of the held-out one; both are printed either way.
    #[arg(long)]
    pub(crate) judge_fitted: bool,
    /// Skip the `pitch-detection` baselines (faster; `--check` on PTDB-style data needs them,
    /// the clean-data targets compare with Praat only).
    #[arg(long)]
    pub(crate) no_baselines: bool,
    /// Evaluate clean data sets (no noise in their clip names) without the generated noise.
    #[arg(long)]
    pub(crate) clean_only: bool,
    /// Print the error breakdown per condition and per clip.
    #[arg(long)]
    pub(crate) verbose: bool,
    /// Write one CSV per clip (reference and every track on the reference grid) here.
    #[arg(long, value_name = "DIR")]
    pub(crate) dump: Option<PathBuf>,
    /// The Python that runs the swift-f0 and pYIN baselines (`eval/python/f0_baselines.py`);
    /// default `target/venv-f0/bin/python` when it exists, else they are left out.
    #[arg(long, value_name = "PYTHON")]
    pub(crate) baselines_python: Option<PathBuf>,
    /// Also run pYIN (librosa; slow: about real time, so best with `--clean-only`).
    #[arg(long)]
    pub(crate) pyin: bool,
}

pub(crate) fn parse_setting(kv: &str) -> Result<(String, String), String> {
    let (k, v) = kv
        .split_once('=')
        .ok_or_else(|| format!("{kv:?}: --set needs name=value"))?;
    Ok((k.to_string(), v.to_string()))
}
