//! How long an inserted breath is, chosen leave-one-speaker-out: the scale of the breath
//! length ([`BREATH_LENGTH_SCALE`]), fitted on the other speakers' labelled breaths and scored
//! on the speaker left out.
//!
//! An inserted breath lasts [`pneuma_core::engine`]'s breath length (the breathing
//! parameters' inspiration times the scale, longer in longer pauses and before longer groups),
//! cut to what fits between `after_offset_s` after the phrase and `gap_s` before the next
//! onset. The grid is the scale alone ([`LENGTH_SCALES`], set through the inspiration length,
//! which scales the breath length in proportion for the default preset), up to ×1.6, where a
//! breath after a pause of 2 s or more reaches the longest breath (0.8 s; real inhalations
//! are rarely longer). The two margins stay: real breaths end a median 73 ms before the
//! voicing of the next phrase and begin a median 127 ms after the voicing of the last (the
//! Keele labels against the laryngograph), and the podcast evaluation counts a breath within
//! 80 ms of voicing as on speech; with `after_offset_s` at 0.02 s instead of 0.06 s the ratio
//! here rises (0.79 → 0.87) but the podcast episodes get 15 more breaths on speech (33).
//!
//! Every clip is rendered gated, every breath cut at once, with the built-in voice (the voice
//! does not move a breath); the score of a scale on a set of speakers is `|ln r|` of the
//! median duration ratio `r` (inserted over labelled) over their breaths put back. Each
//! speaker gets the scale best on the others (ties: the shipped scale, then the smaller), and
//! the held-out figure is the median ratio over every speaker's breaths under their own fold's
//! choice.

use std::collections::BTreeMap;

use pneuma_core::breathing::reference::ReferenceVoice;
use pneuma_core::engine::{EngineConfig, BREATH_LENGTH_SCALE};

use super::{experiment, Clip, Cut, Run, SpeakerResult, Voice};
use crate::stats::median;

/// The renders the fit scores: gated, every breath cut at once, the built-in voice.
pub const RENDERS: (Cut, Run, Voice) = (Cut::Gated, Run::AllAtOnce, Voice::BuiltIn);

/// Values of [`BREATH_LENGTH_SCALE`] tried.
pub const LENGTH_SCALES: [f64; 4] = [1.0, 1.2, 1.4, 1.6];

/// The duration ratios of the breaths put back, per speaker.
fn ratios(per: &BTreeMap<String, SpeakerResult>) -> BTreeMap<String, Vec<f64>> {
    per.iter()
        .map(|(name, r)| {
            let d = r.restored.iter().flatten().map(|b| b.duration_ratio);
            (name.clone(), d.collect())
        })
        .collect()
}

/// Median ratio over the breaths of the speakers `keep` accepts.
fn pooled(by_speaker: &BTreeMap<String, Vec<f64>>, keep: impl Fn(&str) -> bool) -> f64 {
    let all: Vec<f64> = by_speaker
        .iter()
        .filter(|(s, _)| keep(s))
        .flat_map(|(_, r)| r.iter().copied())
        .collect();
    median(&all)
}

/// Renders the grid (`shipped`: the [`RENDERS`] already made with the shipped settings),
/// prints each point's fitted ratio and every speaker's fold, and returns the held-out median
/// duration ratio.
pub fn run(
    clips: &[Clip],
    uncut: &BTreeMap<(String, Voice), Vec<(f64, f64)>>,
    held_out: &BTreeMap<String, ReferenceVoice>,
    shipped: &BTreeMap<String, SpeakerResult>,
) -> Result<f64, String> {
    let mut grid = vec![(BREATH_LENGTH_SCALE, ratios(shipped))];
    for &scale in LENGTH_SCALES.iter().filter(|&&s| s != BREATH_LENGTH_SCALE) {
        let mut config = EngineConfig::default();
        config.breathing.inspiration_length_s *= (scale / BREATH_LENGTH_SCALE) as f32;
        // Extra breaths are not scored here: the uncut renders are the shipped settings'.
        let (cut, run, voice) = RENDERS;
        let per = experiment(&config, clips, cut, run, voice, uncut, held_out)?;
        grid.push((scale, ratios(&per)));
    }
    println!(
        "\n== breath length, leave one speaker out (gated, all cut at once, built-in voice; shipped scale ×{BREATH_LENGTH_SCALE:.1})"
    );
    println!("scale  duration ratio (all speakers, FITTED)");
    for (scale, r) in &grid {
        println!("×{scale:<5.1} {:>5.2}", pooled(r, |_| true));
    }
    println!("speaker       chosen  ratio HELD OUT");
    let speakers: Vec<String> = grid[0].1.keys().cloned().collect();
    let mut held_out: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for s in &speakers {
        let score = |r: &BTreeMap<String, Vec<f64>>| pooled(r, |x| x != s).ln().abs();
        let (scale, r) = grid
            .iter()
            .min_by(|a, b| score(&a.1).total_cmp(&score(&b.1)))
            .expect("the grid is not empty");
        let mine = r[s].clone();
        println!("{s:<14} ×{scale:.1}   {:>5.2}", median(&mine));
        held_out.insert(s.clone(), mine);
    }
    let overall = pooled(&held_out, |_| true);
    println!("all, held out: duration ratio {overall:.2}");
    Ok(overall)
}
