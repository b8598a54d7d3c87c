//! `cargo xtask eval-pitch --data DIR [--data DIR]... [--check] [--clean-only] [--no-praat]
//! [--no-baselines] [--offset MS] [--verbose] [--dump DIR] [--set name=value]...`: pitch-tracking
//! accuracy against laryngograph references (`<clip>.wav` + `<clip>.f0.csv`, 10 ms reference
//! frames). Each `--data` folder is a data set: PTDB-TUG excerpts (noise and SNR in the clip name,
//! `male1white10`) or clean clips such as Keele's (`f1nw0000`), whose reference frames marked `-1`
//! (uncertain) are left out of every score. Clean clips are also evaluated with seeded added noise
//! (unless `--clean-only`): white (Gaussian) and babble ([`crate::noise::BABBLE_TALKERS`] other
//! clips of the same data set, from seeded start points, summed), each at 20, 10 and 0 dB SNR over
//! the whole clip's power. Figures are printed per data set (per condition, per SNR, per noise, per
//! speaker at the cleanest condition, all), and overall.
//!
//! Every tracker analyses at the same frame rate: Pneuma's, 120 Hz as shipped, or another with
//! `--set frame_rate_hz=200` (Praat's usual 5 ms step; `.ci/run` checks the targets at both).
//! Every tracker's frames are centred at `k / rate`: Pneuma's and the `pitch-detection`
//! detectors' windows by construction, Praat's because the clip is padded with silence to a
//! whole number of steps (Praat centres its frames in the sound). Each reference time, shifted
//! by the global offset, is scored on each tracker's nearest frame. One global time offset
//! (−20…+20 ms in 5 ms steps, the reference is known to sit early) is searched once for the
//! whole data set, minimising the summed FFE of all trackers, and applied to every tracker.
//! A clean data set's targets (Keele: FFE and VDE no higher than Praat's, at every added noise,
//! per speaker within 1.5 points of Praat) are printed as met / MISSED; `--check` fails on
//! those named by `--clean-targets` (`clean,white,babble,speakers`).
//! Metrics (over reference frames): VDE = voicing decisions that differ / all frames;
//! GPE = frames voiced in both with more than 20 % f0 error / frames voiced in both;
//! FFE = (voicing errors + gross errors) / all frames; fine error = median |cents| over frames
//! voiced in both without a gross error.
//!
//! Trackers: Pneuma; the `pitch-detection` crate 0.3.0, McLeod and YIN (2048-sample window at 48
//! kHz, power gate −60 dBFS, clarity 0.6 for McLeod and 0.85 (threshold 0.15) for YIN, f0 outside
//! 50–600 Hz counted unvoiced: a baseline only, never on the audio path); Praat (`To Pitch (ac)`,
//! 50–600 Hz, standard settings, time step one frame) when the `praat` program exists. `--check`
//! fails (exit 1) unless Pneuma meets the PTDB targets of the issue at the frame rate evaluated
//! (when a PTDB-style data set is among the `--data`): FFE at 40 dB no higher than Praat's, at most
//! 8 % at 10 dB white and car noise, below both `pitch-detection` detectors in every condition; a
//! target whose clips are all unreadable counts as missed.

use std::collections::BTreeMap;
use std::path::Path;

use pneuma_core::{AnalysisConfig, VoicingModel};

use crate::data::reference::load_data_set;
use crate::data::shared_data;

mod args;
pub mod baselines;
mod report;
mod score;
mod targets;
mod trackers;

use args::Args;
use report::{print_header, print_row, report_data_set};
use score::{Clip, Counts};
use targets::{
    clean_failures, is_ptdb_noise, is_ptdb_style, judged_index, ptdb_failures, LOSO_NAME,
};
use trackers::{evaluate, start_python_baselines, tracker_names, External};

/// Fits the voicing models of the held-out column (`pneuma-loso`) on the Keele and PTDB
/// folders: one per speaker, each fitted without that speaker, of the kind `--loso-model` names
/// (`None`: the kind `train-voicing` ships). The voicing training (xtask `train-voicing`) gives
/// it to [`main`].
pub type FitHeldOut<'a> =
    dyn Fn(&Path, &Path, Option<&str>) -> Result<BTreeMap<String, VoicingModel>, String> + 'a;

/// Runs `cargo xtask eval-pitch` with `args` (after the command's name), the held-out column
/// fitted by `fit_held_out`; returns the process exit code.
pub fn main(args: &[String], fit_held_out: &FitHeldOut<'_>) -> i32 {
    use clap::Parser as _;
    let args = match Args::try_parse_from(
        std::iter::once("eval-pitch".to_string()).chain(args.iter().cloned()),
    ) {
        Ok(a) => a,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { 2 } else { 0 };
        }
    };
    match run(&args, fit_held_out) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("eval-pitch: {e}");
            2
        }
    }
}

/// The analysis settings Pneuma is evaluated with: the shipped defaults, with `--set`
/// overrides. Its frame rate is every tracker's frame rate.
fn pneuma_config(overrides: &[(String, String)]) -> Result<AnalysisConfig, String> {
    let mut config = AnalysisConfig::default();
    for (k, v) in overrides {
        config.set(k, v).map_err(|e| e.to_string())?;
    }
    Ok(config)
}

fn run(args: &Args, fit_held_out: &FitHeldOut<'_>) -> Result<i32, String> {
    let config = pneuma_config(&args.set)?;
    let frame_rate_hz = config.frame_rate_hz;
    println!(
        "every tracker at {frame_rate_hz} frames per second (Pneuma's frame rate{}); each reference time is scored on each tracker's nearest frame",
        if args.set.iter().any(|(k, _)| k == "frame_rate_hz") { ", set" } else { ", as shipped" }
    );
    // Every clip is read before the minutes of fitting and tracking, so a `--check` with
    // nothing to judge fails at once.
    let mut skipped = Vec::new();
    let mut sources = Vec::new();
    for (set, dir) in args.data.iter().enumerate() {
        for source in load_data_set(dir, args.clean_only, &mut skipped)? {
            sources.push((set, source));
        }
    }
    let any_ptdb = sources
        .iter()
        .any(|(_, s)| is_ptdb_noise(&s.condition.noise));
    // The PTDB targets compare with the `pitch-detection` baselines; the clean-data targets
    // only with Praat.
    if args.check && args.no_baselines && any_ptdb {
        return Err(
            "--check on PTDB-style data compares with the baselines: drop --no-baselines".into(),
        );
    }
    if args.check && args.clean_targets.is_empty() && !any_ptdb {
        return Err("--check has nothing to judge: give a PTDB-style data set (clips in cafeteria, car or traffic noise), or name clean-data targets with --clean-targets".into());
    }
    let loso = if args.no_loso {
        None
    } else {
        let (keele, ptdb) = (shared_data("keele"), shared_data("ptdb"));
        println!(
            "fitting the voicing model leave-one-speaker-out on {} and {} (the `{LOSO_NAME}` column: each clip judged by a model fitted without its speaker)",
            keele.display(),
            ptdb.display()
        );
        Some(fit_held_out(&keele, &ptdb, args.loso_model.as_deref())?)
    };
    let mut unseen = std::collections::BTreeSet::new();
    let scratch = std::env::temp_dir().join(format!("pneuma-eval-pitch-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).map_err(|e| e.to_string())?;
    let python = start_python_baselines(args, &scratch)?;
    let (tracker_names, praat) = tracker_names(args, loso.is_some(), python.is_some());
    let mut external = External { praat, python };
    let mut clips = Vec::new();
    let mut seconds = vec![0.0f64; tracker_names.len()];
    let mut audio_s = 0.0;
    for (set, source) in sources {
        audio_s += source.audio.len() as f64 / source.rate as f64;
        let held_out = loso.as_ref().map(|models| {
            let mut c = config.clone();
            match models.get(&source.speaker) {
                Some(m) => c.voicing_model = m.clone(),
                None => {
                    unseen.insert(source.speaker.clone());
                }
            }
            c
        });
        clips.push(evaluate(
            source,
            set,
            &config,
            held_out.as_ref(),
            args,
            &mut external,
            &scratch,
            &mut seconds,
        )?);
    }
    let _ = std::fs::remove_dir_all(&scratch);
    if !unseen.is_empty() {
        println!(
            "speakers outside the training set (their `{LOSO_NAME}` figure is the shipped model's, already held out): {}",
            unseen.into_iter().collect::<Vec<_>>().join(", ")
        );
    }
    if !skipped.is_empty() {
        println!(
            "skipped {} unreadable clip(s) (evaluated on the rest):",
            skipped.len()
        );
        for s in &skipped {
            println!("  - {s}");
        }
    }
    if clips.is_empty() {
        return Err("no readable clip: every WAV failed to load (see above)".into());
    }
    let mut results = Vec::new();
    let mut overall = vec![Counts::default(); tracker_names.len()];
    for (set, dir) in args.data.iter().enumerate() {
        let of_set: Vec<&Clip> = clips.iter().filter(|c| c.data_set == set).collect();
        if of_set.is_empty() {
            continue;
        }
        let result = report_data_set(dir, &of_set, &tracker_names, args)?;
        for (o, c) in overall.iter_mut().zip(&result.all) {
            o.add(c);
        }
        results.push(result);
    }
    if results.len() > 1 {
        println!(
            "\n=== overall ({} data sets, each at its own offset)",
            results.len()
        );
        print_header(&tracker_names);
        print_row("overall", &overall);
    }
    println!(
        "\n{} clips, {:.1} s of audio; tracker time: {}",
        clips.len(),
        audio_s,
        tracker_names
            .iter()
            .zip(&seconds)
            .map(|(n, s)| format!("{n} {:.2} s ({:.0}x real time)", s, audio_s / s.max(1e-9)))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let praat = external.praat.then(|| tracker_names.len() - 1);
    let judged = if args.judge_fitted {
        0
    } else {
        judged_index(&tracker_names)
    };
    println!(
        "\ntargets judged on the `{}` column{}",
        tracker_names[judged],
        if judged == 0 && loso.is_some() {
            " (--judge-fitted: the model was fitted on these speakers too)"
        } else {
            ""
        }
    );
    let mut failures = Vec::new();
    for result in results.iter().filter(|r| !is_ptdb_style(r)) {
        // Every clean-data target is printed; only those named by --clean-targets count.
        failures.extend(
            clean_failures(result, &tracker_names, praat, judged)
                .into_iter()
                .filter(|(target, _)| args.clean_targets.iter().any(|t| t == target))
                .map(|(_, failure)| failure),
        );
    }
    if !args.check {
        return Ok(0);
    }
    if !skipped.is_empty() {
        println!(
            "\ncheck: {} unreadable clip(s) were left out (listed at the top)",
            skipped.len()
        );
    }
    for result in results.iter().filter(|r| is_ptdb_style(r)) {
        failures.extend(ptdb_failures(result, &tracker_names, praat, judged));
    }

    if failures.is_empty() {
        println!("\ncheck: pitch checks passed");
        Ok(0)
    } else {
        println!("\ncheck: {} target(s) missed:", failures.len());
        for f in &failures {
            println!("  - {f}");
        }
        Ok(1)
    }
}
