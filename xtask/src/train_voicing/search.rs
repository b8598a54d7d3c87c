//! `--search`: the held-out voicing error of the logistic model and of every tree setting of
//! a grid, under each weighting, over all frames and per group of clips.

use pneuma_core::{AnalysisConfig, VoicingModel};

use super::fit::{fit_logistic, rows, speakers, voicing_errors, with_chosen_thresholds};
use super::frames::ClipFrames;
use super::trees::{fit_trees, TreeParams};
use super::weights::{set_weights, Weighting, WEIGHTING};

/// The `--search` grid of the hybrid's trees: depths, one learning rate, and the tree counts
/// scored (prefixes of the largest).
pub(crate) const SEARCH_DEPTHS: [usize; 2] = [2, 3];

pub(crate) const SEARCH_RATE: f64 = 0.1;

pub(crate) const SEARCH_ROUNDS: [usize; 4] = [10, 25, 50, 100];

/// Fits models (on the given clips) whose held-out errors `search` adds up, one per entry.
pub(crate) type FitMany<'a> = dyn Fn(&[&ClipFrames]) -> Result<Vec<VoicingModel>, String> + 'a;

/// Held-out frame errors and frames per clip (`[model][clip]`) of the models `fit_many`
/// makes: every clip judged by models fitted without its speaker, thresholds chosen on the
/// other eleven.
pub(crate) fn held_out_errors(
    clips: &[ClipFrames],
    fit_many: &FitMany<'_>,
) -> Result<Vec<Vec<(u64, u64)>>, String> {
    let mut errors: Vec<Vec<(u64, u64)>> = Vec::new();
    for s in speakers(clips) {
        let others: Vec<&ClipFrames> = clips.iter().filter(|c| c.speaker != s).collect();
        for (i, m) in fit_many(&others)?.iter().enumerate() {
            let m = with_chosen_thresholds(m, &others)?;
            if errors.len() <= i {
                errors.push(vec![(0, 0); clips.len()]);
            }
            for (j, c) in clips.iter().enumerate() {
                if c.speaker == s {
                    errors[i][j] = voicing_errors(&m, &[c]);
                }
            }
        }
    }
    Ok(errors)
}

/// The groups of clips `--search` reports (all at the shipped frame rate but the first).
pub(crate) const SEARCH_GROUPS: [(&str, &str); 7] = [
    ("all", ""),
    ("k clean", "keele clean"),
    ("k white", "keele white"),
    ("k babble", "keele babble"),
    ("k m1/m4", "m"),
    ("k f2/f4", "f"),
    ("ptdb", "ptdb"),
];

/// Whether `c` belongs to `--search` group `g` (see [`SEARCH_GROUPS`]).
pub(crate) fn in_group(c: &ClipFrames, g: usize) -> bool {
    let shipped_rate = c.frame_rate_hz == AnalysisConfig::default().frame_rate_hz;
    let key = SEARCH_GROUPS[g].1;
    match g {
        0 => true,
        4 | 5 => {
            let who: [&str; 2] = if g == 4 {
                ["m1nw0000", "m4nw0000"]
            } else {
                ["f2nw0000", "f4nw0000"]
            };
            shipped_rate && c.condition == "keele clean" && who.contains(&c.speaker.as_str())
        }
        _ => shipped_rate && c.condition.starts_with(key),
    }
}

/// `--search`: the held-out voicing error (leave-one-speaker-out, see [`held_out_errors`]) of
/// the logistic model and of every tree setting of the grid, over all frames and per group
/// of clips; prints the table and returns nothing to ship (the choice is [`SHIPPED_KIND`],
/// set by hand from this table).
pub(crate) fn search(clips: &mut [ClipFrames]) -> Result<(), String> {
    let pct = |(e, n): (u64, u64)| e as f64 * 100.0 / n.max(1) as f64;
    println!(
        "\nheld-out voicing error % on labelled frames (leave-one-speaker-out; groups but `all` at {} frames/s):",
        AnalysisConfig::default().frame_rate_hz
    );
    print!("  {:<44}", "model");
    for (name, _) in SEARCH_GROUPS {
        print!(" {name:>8}");
    }
    println!();
    let print = |label: &str, per_clip: &[(u64, u64)], clips: &[ClipFrames]| {
        print!("  {label:<44}");
        for g in 0..SEARCH_GROUPS.len() {
            let mut t = (0, 0);
            for (c, e) in clips.iter().zip(per_clip) {
                if in_group(c, g) {
                    t.0 += e.0;
                    t.1 += e.1;
                }
            }
            print!(" {:>8.2}", pct(t));
        }
        println!();
    };
    for weighting in [
        Weighting::DataSet,
        Weighting::Condition,
        Weighting::Speaker,
        Weighting::Blend(50),
    ] {
        set_weights(clips, weighting);
        let w = format!("{weighting:?}").to_lowercase();
        let logistic = held_out_errors(clips, &|c| Ok(vec![fit_logistic(c)?]))?;
        print(&format!("logistic, {w} weights"), &logistic[0], clips);
        for monotone in [false, true] {
            for depth in SEARCH_DEPTHS {
                let params = TreeParams {
                    depth,
                    rounds: SEARCH_ROUNDS[SEARCH_ROUNDS.len() - 1],
                    learning_rate: SEARCH_RATE,
                    monotone,
                };
                let errors = held_out_errors(clips, &|c| {
                    let m = fit_trees(&rows(c), &params, Some(&fit_logistic(c)?))?;
                    Ok(SEARCH_ROUNDS.iter().map(|&r| m.first_trees(r)).collect())
                })?;
                let m = if monotone { "monotone " } else { "" };
                for (r, e) in SEARCH_ROUNDS.iter().zip(&errors) {
                    print(
                        &format!("logistic + {r} {m}trees d{depth}, {w} weights"),
                        e,
                        clips,
                    );
                }
            }
        }
    }
    set_weights(clips, WEIGHTING);
    Ok(())
}
