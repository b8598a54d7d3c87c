//! `pneuma train --data DIR -o model.json`: trains a head-pose model from `<clip>.wav` files
//! paired with `<clip>.head.csv` (`time_s,pitch_deg,yaw_deg,roll_deg`, the styletalk format),
//! compares the synthesis variants leave-one-clip-out (held-out log-likelihood per GMM, each
//! variant's targets on the held-out clips), keeps the best variant and writes the model file.
//!
//! The data loading ([`load_clips`]) and the variant table are the evaluation crate's, shared
//! with `pneuma eval head` and `cargo xtask train-default`.

use std::path::PathBuf;
use std::process::ExitCode;

use pneuma_core::head::em::MAX_RESTARTS;
use pneuma_core::head::evaluate::CrossValidation;
use pneuma_core::head::gmm::MAX_COMPONENTS;
use pneuma_core::head::select::train;
use pneuma_core::head::train::TrainConfig;
use pneuma_core::head::Variant;
use pneuma_core::AnalysisConfig;
use pneuma_eval::data::styletalk::load_clips;
use pneuma_eval::data::DataError;
use pneuma_eval::head::{print_clip_table, print_variant_ranks};
use thiserror::Error;

use crate::options::FRAME_RATE;

/// Errors of training.
#[derive(Debug, Error)]
pub enum TrainCliError {
    /// Loading the data failed.
    #[error(transparent)]
    Data(#[from] DataError),
    /// Training failed.
    #[error(transparent)]
    Train(#[from] pneuma_core::head::TrainError),
    /// An option is out of its range (the message names the option and the range).
    #[error("{0}")]
    Option(String),
    /// Writing the model failed.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
}

/// Command-line arguments of `pneuma train`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Folder of `<clip>.wav` + `<clip>.head.csv` pairs.
    #[arg(long)]
    pub data: PathBuf,
    /// Output model file (JSON).
    #[arg(short = 'o', long)]
    pub output: PathBuf,
    /// Components of each voiced velocity and acceleration GMM (the paper: 11).
    #[arg(long, default_value_t = 11, help = format!("Components of each voiced velocity and acceleration GMM (the paper: 11), 1 to {MAX_COMPONENTS}"))]
    pub components: usize,
    /// Components of each pose GMM (roll, pitch, yaw; voiced and unvoiced); 1 keeps the head
    /// at the speaker's mean pose on average.
    #[arg(long, default_value_t = TrainConfig::default().pose_components, help = format!("Components of each pose GMM (roll, pitch, yaw; voiced and unvoiced), 1 to {MAX_COMPONENTS}; 1 keeps the head at the speaker's mean pose on average"))]
    pub pose_components: usize,
    /// EM restarts per GMM.
    #[arg(long, default_value_t = 3, help = format!("EM restarts per GMM, 1 to {MAX_RESTARTS}"))]
    pub restarts: usize,
    /// EM seed.
    #[arg(long, default_value_t = 2015)]
    pub seed: u64,
    /// Feature frames per second (the table's `frame_rate_hz`).
    #[arg(long, help = FRAME_RATE.help_saying("Analysis frames per second the model is trained at"), default_value_t = FRAME_RATE.default_value())]
    pub frame_rate: f64,
    /// SD of the Gaussian smoothing of the training motion in milliseconds (tracking-jitter
    /// removal; 0 = none), 0 to 500.
    #[arg(long, default_value_t = 25.0)]
    pub motion_smoothing_ms: f64,
}

/// Prints the held-out log-likelihoods, every variant's rank and the variant kept.
pub fn print_report(cv: &CrossValidation) {
    println!("held-out log-likelihood per voiced GMM (nats/frame, leave-one-clip-out)");
    println!("clip,roll,pitch,yaw,velocity,acceleration");
    for (name, ll) in &cv.held_out {
        println!(
            "{name},{:.3},{:.3},{:.3},{:.3},{:.3}",
            ll[0], ll[1], ll[2], ll[3], ll[4]
        );
    }
    let m = cv.mean_held_out();
    println!(
        "mean,{:.3},{:.3},{:.3},{:.3},{:.3}",
        m[0], m[1], m[2], m[3], m[4]
    );
    print_variant_ranks(cv);
    if let Some(best) = cv.best() {
        println!("the kept variant per clip, held out:");
        print_clip_table(&best.clips);
    }
}

/// Trains with `args` settings; returns the model JSON and the cross-validation.
pub fn run(
    args: &Args,
    data_description: &str,
) -> Result<(String, CrossValidation), TrainCliError> {
    // Checked before anything is read: a typo should not wait for the data to load.
    for (option, value, max) in [
        ("--components", args.components, MAX_COMPONENTS),
        ("--pose-components", args.pose_components, MAX_COMPONENTS),
        ("--restarts", args.restarts, MAX_RESTARTS),
    ] {
        crate::options::check_range(option, value as f64, 1.0, max as f64, "")
            .map_err(TrainCliError::Option)?;
    }
    let config = AnalysisConfig {
        frame_rate_hz: FRAME_RATE
            .check(args.frame_rate)
            .map_err(TrainCliError::Option)?,
        ..AnalysisConfig::default()
    };
    let clips = load_clips(&args.data, &config)?;
    if clips.len() < 2 {
        return Err(TrainCliError::Option(format!(
            "{} holds one clip; training needs at least two (each is left out in turn to choose \
             the model's variant on motion it was not fitted on): add a clip",
            args.data.display()
        )));
    }
    let cfg = TrainConfig {
        components: args.components,
        pose_components: args.pose_components,
        restarts: args.restarts,
        seed: args.seed,
        motion_smoothing_s: args.motion_smoothing_ms / 1000.0,
        data_description: data_description.to_string(),
        ..TrainConfig::default()
    };
    let (model, cv) = train(&clips, &cfg, &Variant::candidates(), |name| {
        eprintln!("leave out {name} ...")
    })?;
    Ok((model.to_json(), cv))
}

/// Runs `pneuma train`.
pub fn main(args: Args) -> ExitCode {
    let smoothing_ms = args.motion_smoothing_ms;
    if let Err(e) =
        crate::options::check_range("--motion-smoothing-ms", smoothing_ms, 0.0, 500.0, "ms")
    {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    // Told before the training, not after it.
    if args.output.is_dir() {
        eprintln!(
            "error: -o {} is a folder; give the model file to write, e.g. -o {}",
            args.output.display(),
            args.output.join("head_model.json").display()
        );
        return ExitCode::FAILURE;
    }
    let desc = format!("clips of {}", args.data.display());
    match run(&args, &desc) {
        Ok((json, cv)) => {
            print_report(&cv);
            if let Err(source) = std::fs::write(&args.output, json) {
                eprintln!(
                    "error: {}",
                    TrainCliError::Write {
                        path: args.output.clone(),
                        source
                    }
                );
                return ExitCode::FAILURE;
            }
            println!("wrote {}", args.output.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
