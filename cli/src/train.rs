//! `pneuma train --data DIR -o model.json`: trains a head-pose model from `<clip>.wav` files
//! paired with `<clip>.head.csv` (`time_s,pitch_deg,yaw_deg,roll_deg`, the styletalk format),
//! compares the synthesis variants leave-one-clip-out (held-out log-likelihood per GMM, each
//! variant's targets on the held-out clips), keeps the best variant and writes the model file.
//!
//! The data loading here ([`load_clips`]) and the tables ([`print_variant_ranks`],
//! [`print_clip_table`]) are shared with `pneuma eval head` and `cargo xtask train-default`.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use pneuma_core::head::evaluate::{ClipEval, CrossValidation};
use pneuma_core::head::targets;
use pneuma_core::head::train::{train, TrainConfig};
use pneuma_core::head::{MotionTrack, TrainingClip, Variant};
use pneuma_core::{AnalysisConfig, AnalysisError, Analyzer, FeatureFrame};
use thiserror::Error;

use pneuma_io::{read_mono, ReadError};

/// Errors of loading head-motion data and training.
#[derive(Debug, Error)]
pub enum TrainCliError {
    /// The data folder is missing or unreadable.
    #[error("cannot read the data folder {path}: {source} (give a folder of <clip>.wav + <clip>.head.csv, e.g. ../shared/data/styletalk)")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// No clip pairs found.
    #[error("no <clip>.wav + <clip>.head.csv pairs in {path}: {unmatched}; each clip needs both files with the same name before the extension")]
    NoClips {
        /// The folder.
        path: PathBuf,
        /// Which files lack their partner, or that the folder has neither kind.
        unmatched: String,
    },
    /// A head CSV is malformed.
    #[error("{path} line {line}: {reason} (expected header time_s,pitch_deg,yaw_deg,roll_deg and numeric rows)")]
    Csv {
        /// The file.
        path: PathBuf,
        /// Line number (1-based).
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// Reading an audio file failed.
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// Analysis settings failed.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// Training failed.
    #[error(transparent)]
    Train(#[from] pneuma_core::head::TrainError),
    /// Writing the model failed.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
}

/// Reads a head-motion CSV (`time_s,pitch_deg,yaw_deg,roll_deg`) into (roll, pitch, yaw).
pub fn read_head_csv(path: &Path) -> Result<MotionTrack, TrainCliError> {
    let text = std::fs::read_to_string(path).map_err(|e| TrainCliError::Csv {
        path: path.into(),
        line: 0,
        reason: e.to_string(),
    })?;
    let csv_err = |line: usize, reason: String| TrainCliError::Csv {
        path: path.into(),
        line,
        reason,
    };
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("").trim();
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| {
        cols.iter()
            .position(|c| *c == name)
            .ok_or_else(|| csv_err(1, format!("column `{name}` is missing")))
    };
    let (it, ip, iy, ir) = (
        find("time_s")?,
        find("pitch_deg")?,
        find("yaw_deg")?,
        find("roll_deg")?,
    );
    let mut m = MotionTrack::default();
    for (n, line) in lines.enumerate() {
        let line_no = n + 2;
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let get = |i: usize| -> Result<f64, TrainCliError> {
            let s = f
                .get(i)
                .ok_or_else(|| csv_err(line_no, format!("has {} fields", f.len())))?;
            let v: f64 = s
                .parse()
                .map_err(|_| csv_err(line_no, format!("`{s}` is not a number")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(csv_err(line_no, format!("`{s}` is not finite")))
            }
        };
        let t = get(it)?;
        if let Some(&last) = m.time_s.last() {
            if t <= last {
                return Err(csv_err(line_no, format!("time {t} does not increase")));
            }
        }
        m.time_s.push(t);
        m.pose_deg.push([get(ir)?, get(ip)?, get(iy)?]);
    }
    if m.time_s.len() < 4 {
        return Err(csv_err(0, "fewer than 4 rows of motion".into()));
    }
    Ok(m)
}

/// Analyses a whole audio file (any input format) into feature frames with `config`.
pub fn analyze_wav(
    path: &Path,
    config: &AnalysisConfig,
) -> Result<Vec<FeatureFrame>, TrainCliError> {
    let (samples, rate) = read_mono(path)?;
    let mut a = Analyzer::new(config.clone())?;
    a.prepare(rate as f64, 4096)?;
    let mut frames = Vec::new();
    for block in samples.chunks(4096) {
        a.process(block, |f| frames.push(*f))?;
    }
    a.finish(|f| frames.push(*f))?;
    Ok(frames)
}

/// Finds the `<clip>.wav` + `<clip>.head.csv` pairs in `dir` (sorted by name), analyses the
/// audio at `config.frame_rate_hz` and pairs it with the resampled motion.
pub fn load_clips(dir: &Path, config: &AnalysisConfig) -> Result<Vec<TrainingClip>, TrainCliError> {
    let folder = |source| TrainCliError::Folder {
        path: dir.into(),
        source,
    };
    let names: Vec<String> = std::fs::read_dir(dir)
        .map_err(folder)?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    let heads: Vec<&str> = names
        .iter()
        .filter_map(|n| n.strip_suffix(".head.csv"))
        .collect();
    // (stem, file name) of every audio file (any format pneuma-io reads).
    let audio: Vec<(&str, &str)> = names
        .iter()
        .filter_map(|n| pneuma_io::audio_stem(n).map(|s| (s, n.as_str())))
        .collect();
    let wavs: Vec<&str> = audio.iter().map(|a| a.0).collect();
    let mut stems: Vec<String> = heads
        .iter()
        .filter(|s| wavs.contains(s))
        .map(|s| s.to_string())
        .collect();
    stems.sort();
    // Which file of a pair is missing, named (at most five of each kind).
    let mut unmatched = Vec::new();
    let list = |v: Vec<&&str>, ext: &str| {
        let shown: Vec<String> = v.iter().take(5).map(|s| format!("{s}{ext}")).collect();
        let more = v.len().saturating_sub(5);
        let tail = if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        };
        format!("{}{tail}", shown.join(", "))
    };
    let lone_wavs: Vec<&&str> = audio
        .iter()
        .filter(|a| !heads.contains(&a.0))
        .map(|a| &a.1)
        .collect();
    let lone_heads: Vec<&&str> = heads.iter().filter(|s| !wavs.contains(s)).collect();
    if !lone_wavs.is_empty() {
        unmatched.push(format!("no .head.csv for {}", list(lone_wavs, "")));
    }
    if !lone_heads.is_empty() {
        unmatched.push(format!(
            "no audio file (.wav, .flac, …) for {}",
            list(lone_heads, ".head.csv")
        ));
    }
    if stems.is_empty() {
        return Err(TrainCliError::NoClips {
            path: dir.into(),
            unmatched: if unmatched.is_empty() {
                "it holds no .wav and no .head.csv files".into()
            } else {
                unmatched.join("; ")
            },
        });
    }
    if !unmatched.is_empty() {
        eprintln!("note: {} skipped: {}", dir.display(), unmatched.join("; "));
    }
    let mut clips = Vec::with_capacity(stems.len());
    for stem in stems {
        let motion = read_head_csv(&dir.join(format!("{stem}.head.csv")))?;
        let name = audio.iter().find(|a| a.0 == stem).map_or("", |a| a.1);
        let frames = analyze_wav(&dir.join(name), config)?;
        clips.push(TrainingClip::from_motion(
            &stem,
            config.frame_rate_hz,
            &frames,
            &motion,
        ));
    }
    Ok(clips)
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
    /// Components per voiced GMM (the paper: 11).
    #[arg(long, default_value_t = 11)]
    pub components: usize,
    /// EM restarts per GMM.
    #[arg(long, default_value_t = 3)]
    pub restarts: usize,
    /// EM seed.
    #[arg(long, default_value_t = 2015)]
    pub seed: u64,
    /// Feature frame rate in Hz.
    #[arg(long, default_value_t = 120.0)]
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
}

/// Prints one line per variant: targets missed on the held-out clips, by how much, the
/// closeness score, the mean CCA (generated, real, chance) and the median speed ratio; then
/// the variant training keeps.
pub fn print_variant_ranks(cv: &CrossValidation) {
    println!(
        "variants, held out (targets missed, summed miss in units of each limit, closeness to real motion: lower is better)"
    );
    println!("variant,missed,miss,closeness,cca_gen,cca_real,cca_chance,speed_ratio_median");
    for e in &cv.evals {
        let (missed, miss, close) = targets::rank(&e.targets(), &e.clips);
        let n = e.clips.len().max(1) as f64;
        let cca = |k: usize| e.clips.iter().map(|c| c.cca[k]).sum::<f64>() / n;
        let mut speed: Vec<f64> = e.clips.iter().map(ClipEval::speed_ratio).collect();
        speed.sort_by(f64::total_cmp);
        println!(
            "{},{missed},{miss:.3},{close:.3},{:.3},{:.3},{:.3},{:.2}",
            e.variant.name(),
            cca(0),
            cca(1),
            cca(2),
            speed.get(speed.len() / 2).copied().unwrap_or(0.0)
        );
    }
    if let Some(best) = cv.best() {
        println!("kept: {}", best.variant.name());
    }
}

/// Prints a per-clip table of held-out (or in-sample) figures and a summary row: CCA with f0
/// on voiced frames (generated, real, chance), mean angles, SD ratio per axis, speeds and their
/// ratio, power above 3 Hz, frozen share and the onset peak speed.
pub fn print_clip_table(clips: &[ClipEval]) {
    println!(
        "clip,frames,cca_gen,cca_real,cca_chance,mean_roll,mean_pitch,mean_yaw,\
sd_ratio_roll,sd_ratio_pitch,sd_ratio_yaw,speed_gen,speed_real,speed_ratio,\
power_above_3hz_gen,power_above_3hz_real,frozen_gen,onset_peak_deg_s"
    );
    for c in clips {
        let m = c.generated.mean_deg;
        let sd = c.sd_ratio();
        println!(
            "{},{},{:.3},{:.3},{:.3},{:+.2},{:+.2},{:+.2},{:.2},{:.2},{:.2},{:.1},{:.1},{:.2},{:.3},{:.3},{:.3},{:.1}",
            c.name,
            c.frames,
            c.cca[0],
            c.cca[1],
            c.cca[2],
            m[0],
            m[1],
            m[2],
            sd[0],
            sd[1],
            sd[2],
            c.generated.mean_speed_deg_s,
            c.real.mean_speed_deg_s,
            c.speed_ratio(),
            c.generated.power_above_3hz,
            c.real.power_above_3hz,
            c.generated.frozen_share,
            c.onset_peak_deg_s
        );
    }
    let n = clips.len().max(1) as f64;
    let mean = |f: &dyn Fn(&ClipEval) -> f64| clips.iter().map(f).sum::<f64>() / n;
    println!(
        "mean,{},{:.3},{:.3},{:.3},{:+.2},{:+.2},{:+.2},{:.2},{:.2},{:.2},{:.1},{:.1},{:.2},{:.3},{:.3},{:.3},{:.1}",
        clips.iter().map(|c| c.frames).sum::<usize>(),
        mean(&|c| c.cca[0]),
        mean(&|c| c.cca[1]),
        mean(&|c| c.cca[2]),
        mean(&|c| c.generated.mean_deg[0]),
        mean(&|c| c.generated.mean_deg[1]),
        mean(&|c| c.generated.mean_deg[2]),
        mean(&|c| c.sd_ratio()[0]),
        mean(&|c| c.sd_ratio()[1]),
        mean(&|c| c.sd_ratio()[2]),
        mean(&|c| c.generated.mean_speed_deg_s),
        mean(&|c| c.real.mean_speed_deg_s),
        mean(&|c| c.speed_ratio()),
        mean(&|c| c.generated.power_above_3hz),
        mean(&|c| c.real.power_above_3hz),
        mean(&|c| c.generated.frozen_share),
        mean(&|c| c.onset_peak_deg_s),
    );
}

/// Trains with `args` settings; returns the model JSON and the cross-validation.
pub fn run(
    args: &Args,
    data_description: &str,
) -> Result<(String, CrossValidation), TrainCliError> {
    let config = AnalysisConfig {
        frame_rate_hz: args.frame_rate,
        ..AnalysisConfig::default()
    };
    let clips = load_clips(&args.data, &config)?;
    let cfg = TrainConfig {
        components: args.components,
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
    let smoothing_ms = args.motion_smoothing_ms as f32;
    if let Err(e) =
        crate::options::check_range("--motion-smoothing-ms", smoothing_ms, 0.0, 500.0, "ms")
    {
        eprintln!("error: {e}");
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
