//! Two voices in one recording (an interview): what a voice learned from both speakers'
//! breaths is worth to each of them. For every pair of labelled speakers, their breaths pooled
//! (as a whole-file learner hears an interview), each speaker's breaths are scored against:
//! - the **blend**: the mean shape of the pooled breaths but the one scored, and their
//!   median level under the speech (what `LearnedVoice` learns from them);
//! - the **built-in voice** fitted without either speaker and coloured by both speakers'
//!   speech, as the engine plays it (what a rule that refused to learn from disagreeing
//!   breaths would fall back on), at the default breath level;
//! - the speaker's **own** other breaths (leave one out: the best a learner could do).
//!
//! Shapes: medians over the speakers of a pair, over all pairs (own: over the speakers).
//! Levels are each clip's against its own speech (two speakers mixed at different levels
//! were not measured).
//!
//! And whether the breaths tell two voices apart at all: the separation [`split`] finds in
//! each speaker's breaths alone against a pair's pooled ones (two-means from the two shapes
//! farthest apart; the distance between the groups' means over the RMS distance of a shape to
//! its group's mean). Measured: the blend fits each speaker better than the built-in voice,
//! and a speaker's own breaths split as far apart as two speakers' do, so the learner learns
//! one voice from every breath it hears (DESIGN.md).

use std::collections::BTreeMap;

use pneuma_core::breathing::third_octave::{distance_db, mean_shape, Bands, BANDS};
use pneuma_core::engine::PlacementConfig;

use super::{reference, Clip};
use crate::breath_sounds::to_the_others_db;
use crate::stats::median;

/// Most two-means rounds.
const ROUNDS: usize = 20;

/// The two groups of a split.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Split {
    /// Distance between the groups' mean shapes over the RMS distance of a shape to its own
    /// group's mean.
    pub separation: f64,
    /// Breaths in the smaller group.
    pub smaller: usize,
}

/// Splits `shapes` in two; `side` (as long as `shapes` or longer) gets each shape's group.
/// `None` with fewer than two shapes or when every shape is alike.
pub fn split(shapes: &[Bands], side: &mut [bool]) -> Option<Split> {
    let n = shapes.len();
    if n < 2 || side.len() < n {
        return None;
    }
    // The two shapes farthest apart start the groups.
    let (mut a, mut b, mut far) = (0, 0, 0.0);
    for i in 0..n {
        for j in i + 1..n {
            let d = distance_db(&shapes[i], &shapes[j]);
            if d > far {
                (a, b, far) = (i, j, d);
            }
        }
    }
    if far <= 0.0 || !far.is_finite() {
        return None;
    }
    let (mut m0, mut m1) = (shapes[a], shapes[b]);
    for round in 0..ROUNDS {
        let mut changed = false;
        for (k, s) in shapes.iter().enumerate() {
            let to_1 = distance_db(s, &m1) < distance_db(s, &m0);
            changed |= round == 0 || side[k] != to_1;
            side[k] = to_1;
        }
        let (mut sum0, mut sum1, mut n0, mut n1) = ([0.0; BANDS], [0.0; BANDS], 0usize, 0usize);
        for (k, s) in shapes.iter().enumerate() {
            let (sum, count) = if side[k] {
                (&mut sum1, &mut n1)
            } else {
                (&mut sum0, &mut n0)
            };
            for (t, x) in sum.iter_mut().zip(s) {
                *t += x;
            }
            *count += 1;
        }
        if n0 == 0 || n1 == 0 {
            return None;
        }
        m0 = sum0.map(|t| t / n0 as f64);
        m1 = sum1.map(|t| t / n1 as f64);
        if !changed {
            break;
        }
    }
    let ones = side[..n].iter().filter(|&&s| s).count();
    let within_sq = shapes
        .iter()
        .zip(side.iter())
        .map(|(s, &one)| distance_db(s, if one { &m1 } else { &m0 }).powi(2))
        .sum::<f64>()
        / n as f64;
    Some(Split {
        separation: distance_db(&m0, &m1) / within_sq.sqrt().max(1e-9),
        smaller: ones.min(n - ones),
    })
}

/// One speaker's breaths: shapes and levels under the clip's speech, dB; and the speaker's
/// voiced speech's long-term spectrum (the mean of their clips', dB per band).
#[derive(Default)]
struct Breaths {
    shapes: Vec<Bands>,
    levels_db: Vec<f64>,
    ltas: Vec<Bands>,
}

/// Median distance of each of `shapes` to `to`, dB.
fn distance_to(shapes: &[Bands], to: &Bands) -> f64 {
    median(
        &shapes
            .iter()
            .map(|s| distance_db(s, to))
            .collect::<Vec<_>>(),
    )
}

/// Prints the figures; returns the median over speakers and pairs of (blend, built-in) shape
/// distance, dB.
pub fn report(clips: &[Clip]) -> Result<(f64, f64), String> {
    let mut by: BTreeMap<&str, Breaths> = BTreeMap::new();
    for c in clips {
        let b = by.entry(c.speaker.as_str()).or_default();
        b.shapes.extend(c.real_shapes.iter().copied());
        b.levels_db
            .extend(c.real_levels_db.iter().map(|l| l - c.speech_db));
        b.ltas.push(c.speech_ltas_db);
    }
    let speakers: Vec<&str> = by.keys().copied().collect();
    let default_level_db = f64::from(PlacementConfig::default().breath_level_db);
    let (mut blend, mut built_in, mut own) = (Vec::new(), Vec::new(), Vec::new());
    let (mut blend_level, mut built_in_level) = (Vec::new(), Vec::new());
    let mut side = vec![false; 64];
    let (mut alone_sep, mut pooled_sep) = (Vec::new(), Vec::new());
    for s in &speakers {
        let b = &by[s];
        side.resize(side.len().max(b.shapes.len()), false);
        alone_sep.extend(split(&b.shapes, &mut side).map(|x| x.separation));
    }
    for i in 0..speakers.len() {
        for j in i + 1..speakers.len() {
            let (a, b) = (&by[speakers[i]], &by[speakers[j]]);
            let pooled: Vec<Bands> = a.shapes.iter().chain(&b.shapes).copied().collect();
            side.resize(side.len().max(pooled.len()), false);
            pooled_sep.extend(split(&pooled, &mut side).map(|x| x.separation));
            let levels: Vec<f64> = a.levels_db.iter().chain(&b.levels_db).copied().collect();
            let blend_level_db = median(&levels);
            let without = reference::fit(
                clips
                    .iter()
                    .filter(|c| c.speaker != speakers[i] && c.speaker != speakers[j]),
            )
            .ok_or("no other speaker's breath to fit the built-in voice on")?;
            // The built-in voice as the engine plays it: coloured by the interview's speech
            // (both speakers' long-term spectra).
            let ltas: Vec<Bands> = a.ltas.iter().chain(&b.ltas).copied().collect();
            let coloured = without.coloured(&mean_shape(&ltas), 0.0, default_level_db);
            for (x, other) in [(a, b), (b, a)] {
                // Each breath against the blend learned from all the others (never from itself).
                let to_blend: Vec<f64> = x
                    .shapes
                    .iter()
                    .enumerate()
                    .map(|(k, s)| {
                        let rest: Vec<Bands> = x
                            .shapes
                            .iter()
                            .enumerate()
                            .filter(|&(m, _)| m != k)
                            .map(|(_, t)| *t)
                            .chain(other.shapes.iter().copied())
                            .collect();
                        distance_db(s, &mean_shape(&rest))
                    })
                    .collect();
                blend.push(median(&to_blend));
                built_in.push(distance_to(&x.shapes, &coloured.shape_db));
                let own_level = median(&x.levels_db);
                blend_level.push((blend_level_db - own_level).abs());
                built_in_level.push((default_level_db - own_level).abs());
            }
        }
    }
    for s in &speakers {
        own.push(median(&to_the_others_db(&by[s].shapes)));
    }
    let (blend_db, built_in_db) = (median(&blend), median(&built_in));
    println!("
== two voices in one recording (every pair of speakers' breaths pooled; each speaker scored, medians)");
    println!(
        "  shape distance to the speaker's breaths: blend {blend_db:.2} dB, built-in voice fitted without both {built_in_db:.2} dB, the speaker's own other breaths {:.2} dB",
        median(&own)
    );
    println!(
        "  level error: blend {:.1} dB, built-in at the default breath level {:.1} dB",
        median(&blend_level),
        median(&built_in_level)
    );
    println!(
        "  separation of the breaths split in two: one speaker alone {:.2}, two pooled {:.2} (no rule on shape tells two voices from one here)",
        median(&alone_sep),
        median(&pooled_sep)
    );
    Ok((blend_db, built_in_db))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tilt(db_per_band: f64, wobble: f64) -> Bands {
        std::array::from_fn(|k| {
            db_per_band * (k as f64 - (BANDS as f64 - 1.0) / 2.0) + wobble * ((k * 7) % 5) as f64
        })
    }

    #[test]
    fn splits_two_groups_apart_and_measures_their_separation() {
        let shapes: Vec<Bands> = (0..8)
            .map(|k| tilt(if k % 2 == 0 { -1.0 } else { 1.0 }, 0.1 * k as f64))
            .collect();
        let mut side = [false; 8];
        let s = split(&shapes, &mut side).expect("two groups");
        assert_eq!(s.smaller, 4);
        assert!((0..8).all(|k| side[k] == side[k % 2]) && side[0] != side[1]);
        assert!(s.separation > 3.0, "{s:?}");
        assert_eq!(split(&[tilt(0.0, 0.0); 4], &mut side), None, "all alike");
        assert_eq!(split(&shapes[..1], &mut side), None, "one shape");
    }
}
