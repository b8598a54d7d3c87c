//! `cargo xtask train-speech [--data DIR] [--check]`: fits the stacked speech model
//! (`assets/models/speech.txt`, embedded in `pneuma-core`) on the podcast recipe's episodes
//! (`eval/src/podcast/`), with the engine's own analysis and Silero, and writes it with its
//! provenance and its frame figures held out beside fitted (held out: each episode judged by a
//! model fitted without its music pieces, noise type and speakers; the sung piece never fitted
//! on). Deterministic: `--check` regenerates the file and fails on any difference.
//!
//! Needs `../shared/data` and the virtual environment of [`podcast::python`] (Praat, through
//! parselmouth, gives styletalk's reference voicing).

use std::path::PathBuf;

use pneuma_core::speech::SpeechModel;

use pneuma_eval::podcast::fit::{fit, THRESHOLD};
use pneuma_eval::podcast::recipe::{self, Class, Episode, EPISODES, SEED};
use pneuma_eval::podcast::sources::MUSIC;
use pneuma_eval::podcast::{self, fit_rows, label_frame, python, Exclusion};

const OUTPUT: &str = "assets/models/speech.txt";

/// Runs the chore; returns the process exit code.
pub fn main(args: &[String]) -> i32 {
    let root = crate::workspace_root();
    let mut data = root.join("../shared/data");
    let mut check = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--data" => match it.next() {
                Some(d) => data = PathBuf::from(d),
                None => {
                    eprintln!("error: --data needs a folder");
                    return 2;
                }
            },
            "--check" => check = true,
            other => {
                eprintln!("error: unknown argument `{other}` (use --data DIR, --check)");
                return 2;
            }
        }
    }
    match run(&root, &data, check) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("train-speech: {e}");
            1
        }
    }
}

/// Share of frames called speech per class, and per music piece of its non-speech frames.
#[derive(Debug, Clone, Default)]
struct Tally {
    /// [class] → (called speech, frames).
    class: [(u64, u64); 7],
    /// [piece] → non-speech frames of the piece (music, singing): (called speech, frames).
    piece_false: [(u64, u64); 6],
    /// [piece] → speech frames under its beds: (called speech, frames).
    piece_recall: [(u64, u64); 6],
}

impl Tally {
    fn add(
        &mut self,
        episode: &Episode,
        a: &pneuma_core::speech::SpeechAnalysis,
        model: &SpeechModel,
    ) {
        let l = &episode.labels;
        for (f, s) in a.frames.iter().zip(&a.speech) {
            let Some(k) = label_frame(f.time_s, episode.frames()) else {
                continue;
            };
            let (Some(class), true) = (l.class[k], l.mask[k]) else {
                continue;
            };
            let called = u64::from(model.probability(&s.features) >= model.threshold());
            let c = &mut self.class[class as usize];
            c.0 += called;
            c.1 += 1;
            if let Some(p) = l.piece[k] {
                let t = if class.is_speech() {
                    &mut self.piece_recall[p]
                } else {
                    &mut self.piece_false[p]
                };
                t.0 += called;
                t.1 += 1;
            }
        }
    }
}

fn percent((a, n): (u64, u64)) -> f64 {
    100.0 * a as f64 / n.max(1) as f64
}

fn run(root: &std::path::Path, data: &std::path::Path, check: bool) -> Result<i32, String> {
    if !data.join("music").is_dir() {
        return Err(format!(
            "{} has no music/: the podcast recipe needs ../shared/data beside the checkout (or --data DIR)",
            data.display()
        ));
    }
    let mut worker = python::Worker::start(
        &root.join(python::VENV_PYTHON),
        &root.join("target/podcast-scratch"),
        &["parselmouth", "numpy"],
    )?;
    let lib = recipe::library(data, &mut |a| worker.praat(a))?;
    let episodes = recipe::episodes(&lib);
    let any = SpeechModel::shipped();
    let analysed = episodes
        .iter()
        .map(|e| podcast::analyse(e, any))
        .collect::<Result<Vec<_>, _>>()?;
    let all_rows = fit_rows(&episodes, &analysed, &Exclusion::none());
    let model = fit(&all_rows).ok_or("the recipe gave no speech or no non-speech frame")?;
    let mut fitted = Tally::default();
    let mut held = Tally::default();
    for (e, a) in episodes.iter().zip(&analysed) {
        fitted.add(e, a, &model);
        let rows = fit_rows(&episodes, &analysed, &Exclusion::of(e));
        let m = fit(&rows).ok_or(format!("episode {}: nothing left to fit on", e.index))?;
        held.add(e, a, &m);
    }
    let seconds: f64 = episodes
        .iter()
        .map(|e| e.audio.len() as f64 / 16_000.0)
        .sum();
    let mut notes = vec![
        "Pneuma speech model: logistic regression over Silero VAD's logit and two cues of Pneuma's own".to_string(),
        "(voiced frames within 90 ms, level dips in the last second); format: core/src/speech/model.rs.".into(),
        "Generated by `cargo xtask train-speech` (deterministic; --check reproduces it bit for bit); do not".into(),
        "edit by hand. Data: the podcast recipe (eval/src/podcast/recipe.rs, seed ".to_string()
            + &format!("{SEED}, {EPISODES} episodes, {:.1} min):", seconds / 60.0),
        "real speech (Keele, PTDB, styletalk: 19 clips, 15 speakers) with music intros, beds, stings,".into(),
        "outros, a sung passage and noise, frames of the engine's analysis (120 frames/s).".into(),
        format!(
            "Fitted on {} frames (speech and non-speech weighing half each); lets_go_fishin (the sung piece)",
            all_rows.len()
        ),
        "is never fitted on. Frames called speech (probability >= threshold), held out (each episode".into(),
        "judged by a model fitted without its music pieces, noise type and speakers) vs fitted:".into(),
        format!("{:<28} {:>8} {:>8} {:>8}", "class", "held", "fitted", "frames"),
    ];
    for class in Class::ALL {
        let i = class as usize;
        notes.push(format!(
            "{:<28} {:>7.2}% {:>7.2}% {:>8}",
            class.name(),
            percent(held.class[i]),
            percent(fitted.class[i]),
            fitted.class[i].1
        ));
    }
    notes.push("Per music piece: speech under its beds called speech; its music and singing called speech:".into());
    for (p, name) in MUSIC.iter().enumerate() {
        notes.push(format!(
            "{:<18} recall {:>6.2}% (fitted {:>6.2}%)  false {:>6.2}% (fitted {:>6.2}%)",
            name,
            percent(held.piece_recall[p]),
            percent(fitted.piece_recall[p]),
            percent(held.piece_false[p]),
            percent(fitted.piece_false[p])
        ));
    }
    let text = model.to_text(&notes);
    print!("{text}");
    SpeechModel::parse(&text).map_err(|e| format!("the written model does not read back: {e}"))?;
    debug_assert_eq!(model.threshold(), THRESHOLD);
    let out = root.join(OUTPUT);
    if check {
        let committed =
            std::fs::read_to_string(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        if committed != text {
            eprintln!("{OUTPUT} differs from the model fitted now: run `cargo xtask train-speech` and commit it");
            return Ok(1);
        }
        println!("{OUTPUT} is reproduced bit for bit");
        return Ok(0);
    }
    std::fs::write(&out, &text).map_err(|e| format!("{}: {e}", out.display()))?;
    println!("wrote {OUTPUT}");
    Ok(0)
}
