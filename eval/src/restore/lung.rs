//! The lung against the speaker's own breathing, with the real breaths left in. No respiratory
//! belt recorded these clips, so the breathing the labels describe stands in for one: the lung
//! full at the clip's start, falling steadily to empty at each labelled inhalation's start,
//! filling over the inhalation, and empty again at the clip's end (a belt's sawtooth with the
//! labels' timing, without its depths or its holds in pauses). Reported, with the clear labels
//! alone and with the unsure ones as inhalations too, beside the chance level: each clip's lung
//! against another clip's labels. Nothing here is fitted.

use std::collections::BTreeMap;

use super::left_in::UncutRender;
use super::{Clip, Voice};
use crate::stats::pearson;

/// The labels' breathing at `times_s`: 1 (full) at 0 s, 0 at each inhalation's start, 1 at its
/// end, 0 at `length_s`, straight lines between.
pub fn labelled_lung(inhalations: &[(f64, f64)], times_s: &[f64], length_s: f64) -> Vec<f64> {
    let mut knots = vec![(0.0, 1.0)];
    for &(start_s, end_s) in inhalations {
        knots.push((start_s, 0.0));
        knots.push((end_s, 1.0));
    }
    knots.push((length_s, 0.0));
    // Overlapping labels (an unsure span inside a clear one) or one past the end: in time
    // order all the same, so the lookup below holds.
    knots.sort_by(|a, b| a.0.total_cmp(&b.0));
    times_s
        .iter()
        .map(|&t| {
            let i = knots.partition_point(|&(k, _)| k <= t);
            match (knots.get(i.wrapping_sub(1)), knots.get(i)) {
                (Some(&(t0, v0)), Some(&(t1, v1))) if t1 > t0 => {
                    v0 + (v1 - v0) * (t - t0) / (t1 - t0)
                }
                (Some(&(_, v)), _) | (None, Some(&(_, v))) => v,
                (None, None) => 0.0,
            }
        })
        .collect()
}

/// Mean over clips of the lung's correlation with the clip's own labels, and with every other
/// clip's labels (the chance level): (own, chance), with the clear labels alone or the unsure
/// ones too.
fn correlations(
    clips: &[Clip],
    renders: &BTreeMap<(String, Voice), UncutRender>,
    voice: Voice,
    with_unsure: bool,
) -> (f64, f64) {
    // Each clip's inhalations and length, once (`labelled_lung` puts them in time order).
    let labels: Vec<(Vec<(f64, f64)>, f64)> = clips
        .iter()
        .map(|c| {
            let mut v = c.breaths.clone();
            if with_unsure {
                v.extend_from_slice(&c.unsure);
            }
            (v, c.audio.len() as f64 / c.rate_hz)
        })
        .collect();
    let lungs: Vec<(Vec<f64>, Vec<f64>)> = clips
        .iter()
        .map(|c| {
            let lung = &renders[&(c.name.clone(), voice)].lung;
            (
                lung.iter().map(|&(t, _)| t).collect(),
                lung.iter().map(|&(_, v)| f64::from(v)).collect(),
            )
        })
        .collect();
    let (mut own, mut chance) = (Vec::new(), Vec::new());
    for (i, (times_s, lung)) in lungs.iter().enumerate() {
        for (j, (inhalations, length_s)) in labels.iter().enumerate() {
            let n = times_s.partition_point(|&t| t < *length_s);
            let truth = labelled_lung(inhalations, &times_s[..n], *length_s);
            let r = pearson(&lung[..n], &truth);
            if r.is_finite() {
                if i == j { &mut own } else { &mut chance }.push(r);
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    (mean(&own), mean(&chance))
}

/// Prints the line for the renders with `voice`.
pub fn print(clips: &[Clip], renders: &BTreeMap<(String, Voice), UncutRender>, voice: Voice) {
    let (clear, clear_chance) = correlations(clips, renders, voice, false);
    let (all, all_chance) = correlations(clips, renders, voice, true);
    println!(
        "  lung against the labels' breathing (full at each inhalation's end, empty at the next's \
         start; mean r over clips): clear labels {clear:.3} (chance {clear_chance:.3}), clear and \
         unsure {all:.3} (chance {all_chance:.3})"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_labels_breathing_falls_to_each_inhalation_and_fills_over_it() {
        let times: Vec<f64> = (0..=10).map(|i| i as f64).collect();
        let lung = labelled_lung(&[(4.0, 5.0)], &times, 10.0);
        let want = [1.0, 0.75, 0.5, 0.25, 0.0, 1.0, 0.8, 0.6, 0.4, 0.2, 0.0];
        for (got, want) in lung.iter().zip(want) {
            assert!((got - want).abs() < 1e-12, "{lung:?}");
        }
        // Past the clip's end: empty.
        assert_eq!(labelled_lung(&[], &[12.0], 10.0), vec![0.0]);
    }
}
