//! The podcast material of issue 30: the seeded recipe of episodes from `../shared/data`
//! ([`recipe`], [`sources`]), the Python baselines ([`python`]), the stacked model's fit
//! ([`fit`]), which frames a model may be fitted on, and `pneuma eval podcast` ([`evaluate`];
//! its episodes as files: [`export`]).
//!
//! **Held out** means: an episode is judged by a model fitted without any frame of the music
//! pieces it holds, of its noise type and of its speakers (and without the episode itself).
//! The sung piece is never fitted on, by any model.

pub mod evaluate;
pub mod export;
pub mod fit;
pub mod python;
pub mod real_breaths;
pub mod recipe;
pub mod sources;

use std::path::Path;

use pneuma_core::analysis::AnalysisConfig;
use pneuma_core::speech::{self, SpeechAnalysis, SpeechModel};

use fit::Row;
use recipe::{Condition, Episode};
use sources::{FRAMES_PER_S, MUSIC, SUNG_PIECE};

/// Frames called speech, as (called, frames): per class, and per music piece of the speech
/// under its beds (recall) and of its music and singing (false speech).
#[derive(Debug, Clone, Copy, Default)]
pub struct FrameTally {
    /// [class] → (called speech, frames).
    pub class: [(u64, u64); 7],
    /// [piece] → speech frames under its beds: (called speech, frames).
    pub piece_recall: [(u64, u64); 6],
    /// [piece] → non-speech frames of the piece (music, singing): (called speech, frames).
    pub piece_false: [(u64, u64); 6],
}

impl FrameTally {
    /// Counts label frame `k` of `labels`, `called` speech or not; unlabelled and masked-out
    /// frames are left out.
    pub fn count(&mut self, labels: &recipe::Labels, k: usize, called: bool) {
        let (Some(class), true) = (labels.class[k], labels.mask[k]) else {
            return;
        };
        let c = u64::from(called);
        let t = &mut self.class[class as usize];
        t.0 += c;
        t.1 += 1;
        if let Some(p) = labels.piece[k] {
            let t = if class.is_speech() {
                &mut self.piece_recall[p]
            } else {
                &mut self.piece_false[p]
            };
            t.0 += c;
            t.1 += 1;
        }
    }
}

/// The recipe's episodes from `data` (the shared data folder) with a Python worker started for
/// them: the recipe needs Praat (parselmouth, numpy); `extra_modules` are what the caller asks
/// of the worker beside it (`onnxruntime` for Silero). `root` is the checkout (its virtualenv
/// and scratch folder).
pub fn episodes_with_worker(
    root: &Path,
    data: &Path,
    extra_modules: &[&str],
) -> Result<(python::Worker, Vec<Episode>), String> {
    if !data.join("music").is_dir() {
        return Err(format!(
            "{} has no music/: the podcast recipe needs ../shared/data beside the checkout (or --data DIR)",
            data.display()
        ));
    }
    let mut modules = vec!["parselmouth", "numpy"];
    modules.extend_from_slice(extra_modules);
    let mut worker = python::Worker::start(
        &root.join(python::VENV_PYTHON),
        &root.join("target/podcast-scratch"),
        &modules,
    )?;
    eprintln!(
        "building the podcast episodes from {} (Praat's pitch on the speech clips) ...",
        data.display()
    );
    let lib = recipe::library(data, &mut |a| worker.praat(a))?;
    Ok((worker, recipe::episodes(&lib)))
}

/// `(a, n)` as a percentage (0 for no frames).
pub fn percent((a, n): (u64, u64)) -> f64 {
    100.0 * a as f64 / n.max(1) as f64
}

/// The label frame (10 ms) holding time `t_s`, if inside an episode of `n` label frames.
pub fn label_frame(t_s: f64, n: usize) -> Option<usize> {
    let k = (t_s * FRAMES_PER_S).floor();
    (k >= 0.0 && (k as usize) < n).then_some(k as usize)
}

/// An episode through the analysis and the speech decision as the engine runs them (the
/// features do not depend on the model; `model` only sets each frame's probability).
pub fn analyse(episode: &Episode, model: &SpeechModel) -> Result<SpeechAnalysis, String> {
    speech::analyse(
        &AnalysisConfig::default(),
        model,
        &episode.audio,
        sources::RATE_HZ,
    )
    .map_err(|e| format!("episode {}: {e}", episode.index))
}

/// What a held-out model must not have seen: the episode's pieces, noise type and speakers.
#[derive(Debug, Clone, Default)]
pub struct Exclusion {
    episode: Option<usize>,
    pieces: Vec<usize>,
    noises: Vec<recipe::Noise>,
    speakers: Vec<usize>,
}

impl Exclusion {
    /// Nothing excluded (the shipped model) but the sung piece.
    pub fn none() -> Self {
        Self::default()
    }

    /// Everything of `episode`.
    pub fn of(episode: &Episode) -> Self {
        Self {
            episode: Some(episode.index),
            pieces: episode.pieces(),
            noises: episode
                .segments
                .iter()
                .filter_map(|s| match s.condition {
                    Condition::Noise(n, _) => Some(n),
                    _ => None,
                })
                .collect(),
            speakers: episode.segments.iter().map(|s| s.speaker).collect(),
        }
    }
}

/// The training rows of `episodes` (with their analyses) a model may be fitted on under
/// `exclusion`: labelled, scored frames, never the sung piece's.
pub fn fit_rows(
    episodes: &[Episode],
    analysed: &[SpeechAnalysis],
    exclusion: &Exclusion,
) -> Vec<Row> {
    let sung = MUSIC.iter().position(|m| *m == SUNG_PIECE);
    let mut rows = Vec::new();
    for (ep, a) in episodes.iter().zip(analysed) {
        if exclusion.episode == Some(ep.index) {
            continue;
        }
        let l = &ep.labels;
        for (f, s) in a.frames.iter().zip(&a.speech) {
            let Some(k) = label_frame(f.time_s, ep.frames()) else {
                continue;
            };
            let allowed = l.class[k].is_some()
                && l.mask[k]
                && l.piece[k] != sung
                && !l.piece[k].is_some_and(|p| exclusion.pieces.contains(&p))
                && !l.noise[k].is_some_and(|n| exclusion.noises.contains(&n))
                && !l.speaker[k].is_some_and(|p| exclusion.speakers.contains(&p));
            if allowed {
                rows.push(Row {
                    x: s.features,
                    speech: l.truth[k],
                });
            }
        }
    }
    rows
}
