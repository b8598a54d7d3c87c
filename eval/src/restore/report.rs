//! The restore figures per speaker and overall, and the targets.

use std::collections::BTreeMap;

use pneuma_core::breathing::third_octave::{distance_db, mean_shape, Bands};

use super::{Cut, SpeakerResult};
use crate::stats::median;

/// Figures of one speaker or of all.
#[derive(Debug, Clone, Copy, Default)]
pub struct Figures {
    /// Breaths cut.
    pub cut: usize,
    /// Breaths put back.
    pub back: usize,
    /// Extra inserted breaths.
    pub extra: usize,
    /// Median level of the inserted breath minus the real one, dB.
    pub level_db: f64,
    /// Share of breaths put back within ±4 dB of the real one.
    pub level_within_4db: f64,
    /// For scale: the share of (ordered) pairs of the speaker's real breaths whose levels (each
    /// against its clip's speech) lie within ±4 dB of one another (overall: pooled pairs
    /// within speakers).
    pub real_within_4db: f64,
    /// Median duration ratio, inserted over real.
    pub duration_ratio: f64,
    /// Median distance of an inserted breath's shape to the real one it replaces, dB.
    pub distance_db: f64,
    /// Median distance between two real breaths of the speaker, dB.
    pub real_to_real_db: f64,
    /// `distance_db / real_to_real_db` (overall: the median over speakers).
    pub distance_ratio: f64,
    /// Median distance of an inserted shape to the inserted shapes' mean, dB.
    pub spread_inserted_db: f64,
    /// The same for the real shapes, dB.
    pub spread_real_db: f64,
    /// `spread_inserted_db / spread_real_db` (overall: the median over speakers).
    pub spread_ratio: f64,
    /// Median start of an inserted breath minus the real one's, seconds (positive: later).
    pub start_offset_s: f64,
    /// Median end of an inserted breath minus the real one's, seconds.
    pub end_offset_s: f64,
}

/// Median distance of each shape to the mean of `shapes`.
fn spread_db(shapes: &[Bands]) -> f64 {
    let m = mean_shape(shapes);
    median(
        &shapes
            .iter()
            .map(|s| distance_db(s, &m))
            .collect::<Vec<_>>(),
    )
}

/// Median distance over all pairs of `shapes`.
fn pairwise_db(shapes: &[Bands]) -> f64 {
    let mut d = Vec::new();
    for i in 0..shapes.len() {
        for j in i + 1..shapes.len() {
            d.push(distance_db(&shapes[i], &shapes[j]));
        }
    }
    median(&d)
}

/// Level difference a breath's level is scored within, dB (the issue's ±4 dB).
pub(super) const LEVEL_WITHIN_DB: f64 = 4.0;

/// (pairs within [`LEVEL_WITHIN_DB`] of each other, pairs) over the ordered pairs of two
/// different `levels_db`.
fn level_pairs_within(levels_db: &[f64]) -> (usize, usize) {
    let mut within = 0;
    let mut pairs = 0;
    for (i, a) in levels_db.iter().enumerate() {
        for (j, b) in levels_db.iter().enumerate() {
            if i != j {
                pairs += 1;
                within += usize::from((a - b).abs() <= LEVEL_WITHIN_DB);
            }
        }
    }
    (within, pairs)
}

/// `a / b` as a share (0 when `b` is 0).
fn share((a, b): (usize, usize)) -> f64 {
    a as f64 / b.max(1) as f64
}

/// The figures of one speaker's (or everybody's pooled) result.
fn figures(r: &SpeakerResult) -> Figures {
    let back: Vec<_> = r.restored.iter().flatten().collect();
    let level: Vec<f64> = back.iter().map(|b| b.level_db).collect();
    let shapes: Vec<Bands> = back
        .iter()
        .map(|b| b.shape)
        .filter(|s| s.iter().all(|v| v.is_finite()))
        .collect();
    let (distance, real_to_real) = (
        median(&back.iter().map(|b| b.distance_db).collect::<Vec<_>>()),
        pairwise_db(&r.real_shapes),
    );
    let (spread_ins, spread_real) = (spread_db(&shapes), spread_db(&r.real_shapes));
    Figures {
        cut: r.cut,
        back: back.len(),
        extra: r.extra,
        level_db: median(&level),
        level_within_4db: share((
            level.iter().filter(|l| l.abs() <= LEVEL_WITHIN_DB).count(),
            level.len(),
        )),
        real_within_4db: share(level_pairs_within(&r.real_levels_re_speech_db)),
        duration_ratio: median(&back.iter().map(|b| b.duration_ratio).collect::<Vec<_>>()),
        distance_db: distance,
        real_to_real_db: real_to_real,
        distance_ratio: distance / real_to_real,
        spread_inserted_db: spread_ins,
        spread_real_db: spread_real,
        spread_ratio: spread_ins / spread_real,
        start_offset_s: median(&back.iter().map(|b| b.start_offset_s).collect::<Vec<_>>()),
        end_offset_s: median(&back.iter().map(|b| b.end_offset_s).collect::<Vec<_>>()),
    }
}

fn row(name: &str, f: &Figures) {
    println!(
        "{name:<14} {:>2} {:>4} {:>5} {:>+6.1} {:>5.0} % {:>5.0} % {:>5.2} {:>6.1} {:>6.1} {:>5.2} {:>6} {:>6} {:>5.2}",
        f.cut,
        f.back,
        f.extra,
        f.level_db,
        100.0 * f.level_within_4db,
        100.0 * f.real_within_4db,
        f.duration_ratio,
        f.distance_db,
        f.real_to_real_db,
        f.distance_ratio,
        dashed(f.spread_inserted_db),
        dashed(f.spread_real_db),
        f.spread_ratio
    );
}

/// A figure with one decimal, or a dash where none applies (the overall row's spreads: shapes
/// spread within a speaker, not across speakers).
fn dashed(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.1}")
    } else {
        "–".to_string()
    }
}

/// Prints one row per speaker and the overall row; returns the overall figures (sums, medians
/// over all breaths, and the two ratios as medians over speakers).
pub fn print_table(per: &BTreeMap<String, SpeakerResult>) -> Figures {
    println!(
        "speaker       cut back extra  level ±4dB   ±4R     dur  dist   real ratio  sprI  sprR ratio"
    );
    let mut all = SpeakerResult::default();
    let (mut dist_ratios, mut spread_ratios) = (Vec::new(), Vec::new());
    let mut real_pairs = (0, 0);
    for (name, r) in per {
        let (within, pairs) = level_pairs_within(&r.real_levels_re_speech_db);
        real_pairs = (real_pairs.0 + within, real_pairs.1 + pairs);
        let f = figures(r);
        row(name, &f);
        dist_ratios.push(f.distance_ratio);
        spread_ratios.push(f.spread_ratio);
        all.cut += r.cut;
        all.extra += r.extra;
        all.missed.extend_from_slice(&r.missed);
        all.restored.extend_from_slice(&r.restored);
        all.real_shapes.extend_from_slice(&r.real_shapes);
    }
    let mut overall = figures(&all);
    // Levels are compared within a speaker, as shapes are.
    overall.real_within_4db = share(real_pairs);
    // Shapes are compared within a speaker: the pooled real-to-real distance mixes speakers.
    overall.real_to_real_db = median(
        &per.values()
            .map(|r| pairwise_db(&r.real_shapes))
            .collect::<Vec<_>>(),
    );
    overall.spread_inserted_db = f64::NAN;
    overall.spread_real_db = f64::NAN;
    overall.distance_ratio = median(&dist_ratios);
    overall.spread_ratio = median(&spread_ratios);
    row("all", &overall);
    println!(
        "timing, all: inserted breaths start {:+.0} ms and end {:+.0} ms against the real ones they put back (medians; + is later)",
        1e3 * overall.start_offset_s,
        1e3 * overall.end_offset_s
    );
    println!(
        "(level: inserted − real, dB; ±4dB: share within; ±4R: share of pairs of the speaker's real breaths within ±4 dB of each other; dur: duration ratio; dist: shape distance inserted→replaced, dB; real: real↔real, dB; spr I/R: spread of inserted/real shapes, dB; 'all' ratios are medians over speakers)"
    );
    overall
}

/// The targets on `f` for `cut`: (name, met, figure).
pub fn targets(f: &Figures, cut: Cut) -> Vec<(&'static str, bool, String)> {
    let mut t = vec![
        (
            "shape distance ≤ 1.2 × real-to-real",
            f.distance_ratio <= 1.2,
            format!("{:.2} ×", f.distance_ratio),
        ),
        (
            "spread ≥ 0.8 × real",
            f.spread_ratio >= 0.8,
            format!("{:.2} ×", f.spread_ratio),
        ),
    ];
    if cut == Cut::Gated {
        let back = f.back as f64 / f.cut.max(1) as f64;
        let extra = f.extra as f64 / f.cut.max(1) as f64;
        t.extend([
            ("put back ≥ 0.95", back >= 0.95, format!("{back:.2}")),
            (
                "extra ≤ 5 %",
                extra <= 0.05,
                format!("{:.0} %", 100.0 * extra),
            ),
            (
                "level within ±2 dB (median)",
                f.level_db.abs() <= 2.0,
                format!("{:+.1} dB", f.level_db),
            ),
            (
                "90 % within ±4 dB",
                f.level_within_4db >= 0.9,
                format!(
                    "{:.0} % (one real breath against another of the speaker's: {:.0} %)",
                    100.0 * f.level_within_4db,
                    100.0 * f.real_within_4db
                ),
            ),
            (
                "duration ratio 0.8–1.25",
                (0.8..=1.25).contains(&f.duration_ratio),
                format!("{:.2}", f.duration_ratio),
            ),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_pairs_count_each_ordered_pair_of_two_breaths_once() {
        // 0 and 3 dB lie within 4 dB of each other (both ways); 10 dB of neither.
        assert_eq!(level_pairs_within(&[0.0, 3.0, 10.0]), (2, 6));
        assert_eq!(level_pairs_within(&[0.0, 4.0]), (2, 2));
        assert_eq!(level_pairs_within(&[-1.0]), (0, 0));
        assert_eq!(share((0, 0)), 0.0);
    }

    #[test]
    fn a_figure_that_does_not_apply_prints_as_a_dash() {
        assert_eq!(dashed(f64::NAN), "–");
        assert_eq!(dashed(1.26), "1.3");
    }
}
