//! Gradient-boosted regression trees on the voicing cues (the `pneuma-voicing-model 2`
//! scorer): logistic loss, each round one tree of fixed depth grown level by level on
//! quantile-binned cues (histograms of the loss's gradient and curvature), leaf values the
//! Newton step shrunk by the learning rate. Single-threaded, in f64, in a fixed order, with
//! ties broken by the first cue and the first bin: the same rows give the same trees bit for
//! bit.

use pneuma_core::{VoicingFeatures, VoicingModel, N_VOICING_FEATURES};

/// Bins per cue (quantiles of the training rows).
const BINS: usize = 64;
/// L2 penalty on leaf values, in units of (weighted) frames.
const LAMBDA: f64 = 1.0;
/// Least (weighted) curvature on either side of a split.
const MIN_CHILD_HESSIAN: f64 = 5.0;

/// Boosting settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TreeParams {
    /// Splits from root to leaf (1–4).
    pub depth: usize,
    /// Number of trees.
    pub rounds: usize,
    /// Shrinkage of each tree's leaf values.
    pub learning_rate: f64,
    /// Whether the score may only rise with the cues of [`RISING_CUES`] (each split on one
    /// of them keeps every leaf of its upper child at or above every leaf of its lower one).
    pub monotone: bool,
}

/// The cues the score may only rise with under [`TreeParams::monotone`]: the periodicity of
/// the chosen period (whole, short windows at either end, best of them, the previous frame's,
/// the long window's with the background taken out), the level against the speech level,
/// the noise floor and the gate, and how long the pitch track has held. A clearer, louder or
/// longer-held frame is never less voiced, also outside the recordings (a perfectly periodic
/// low tone).
pub(crate) const RISING_CUES: [&str; 11] = [
    "chosen_clarity",
    "edge_newest",
    "edge_oldest",
    "best_clarity",
    "log_unclarity",
    "level_vs_speech",
    "level_vs_floor",
    "previous_clarity",
    "level_vs_gate",
    "denoised_clarity",
    "pitch_track",
];

/// Cues the trees never split on: the period itself. It tells the training speakers apart
/// better than it tells voice from noise, so trees that split on it learn those speakers
/// (held out, the female voices f2 and f4 lost 2–4 FFE points to such trees).
pub(crate) const UNSPLIT_CUES: [&str; 1] = ["log_f0"];

/// One labelled training frame: its cues, its label and its weight.
pub(crate) type Row<'a> = (&'a VoicingFeatures, bool, f64);

/// The bin edges of each cue: sorted, distinct quantiles of the rows' values, without the
/// largest value (a split there would send nothing to the second child).
fn bin_edges(rows: &[Row]) -> Vec<Vec<f32>> {
    (0..N_VOICING_FEATURES)
        .map(|f| {
            let mut v: Vec<f32> = rows.iter().map(|r| r.0[f]).collect();
            v.sort_by(f32::total_cmp);
            let max = v[v.len() - 1];
            let mut edges: Vec<f32> = (1..BINS).map(|k| v[k * v.len() / BINS]).collect();
            edges.dedup();
            edges.retain(|&e| e < max);
            edges
        })
        .collect()
}

/// Fits `params.rounds` trees on `rows`, boosted from `start`'s score when given (a logistic
/// model: the result is it plus the trees) or else from the log prior odds; the thresholds of
/// the returned model are both 0 (the caller chooses them).
pub(crate) fn fit_trees(
    rows: &[Row],
    params: &TreeParams,
    start: Option<&VoicingModel>,
) -> Result<VoicingModel, String> {
    const D: usize = N_VOICING_FEATURES;
    let rising: Vec<bool> = pneuma_core::VOICING_FEATURES
        .iter()
        .map(|n| params.monotone && RISING_CUES.contains(n))
        .collect();
    let unsplit: Vec<bool> = pneuma_core::VOICING_FEATURES
        .iter()
        .map(|n| UNSPLIT_CUES.contains(n))
        .collect();
    let n = rows.len();
    if n == 0 {
        return Err("no labelled training frames".into());
    }
    let edges = bin_edges(rows);
    // bin = the number of edges below the value, so `bin ≤ j` ⇔ `value ≤ edges[j]`: the
    // binned split and the model's float comparison agree exactly.
    let mut bins = vec![0u8; n * D];
    for (i, r) in rows.iter().enumerate() {
        for f in 0..D {
            bins[i * D + f] = edges[f].partition_point(|&e| e < r.0[f]) as u8;
        }
    }
    let (mut pos, mut neg) = (0.0f64, 0.0f64);
    for r in rows {
        if r.1 {
            pos += r.2;
        } else {
            neg += r.2;
        }
    }
    if pos <= 0.0 || neg <= 0.0 {
        return Err("the training frames hold only one class".into());
    }
    let base = (pos / neg).ln() as f32;
    let mut score: Vec<f64> = match start {
        Some(m) => rows.iter().map(|r| f64::from(m.score(r.0))).collect(),
        None => vec![f64::from(base); n],
    };
    let depth = params.depth;
    let n_leaves = 1usize << depth;
    let mut splits = Vec::with_capacity(params.rounds * (n_leaves - 1));
    let mut leaves = Vec::with_capacity(params.rounds * n_leaves);
    let mut grad = vec![0.0f64; n];
    let mut hess = vec![0.0f64; n];
    let mut node = vec![0usize; n];
    for _ in 0..params.rounds {
        for i in 0..n {
            let p = 1.0 / (1.0 + (-score[i]).exp());
            let (_, y, w) = rows[i];
            grad[i] = w * (p - f64::from(u8::from(y)));
            hess[i] = w * (p * (1.0 - p)).max(1e-12);
            node[i] = 0;
        }
        let mut tree_splits = vec![(0usize, f32::MAX); n_leaves - 1];
        // Bounds on each node's leaf values (before shrinkage), from the rising splits above.
        let mut bounds = vec![(f64::NEG_INFINITY, f64::INFINITY)];
        for level in 0..depth {
            let n_nodes = 1usize << level;
            let mut hist = vec![0.0f64; n_nodes * D * BINS * 2];
            for i in 0..n {
                let at = node[i] * D * BINS;
                for f in 0..D {
                    let k = (at + f * BINS + bins[i * D + f] as usize) * 2;
                    hist[k] += grad[i];
                    hist[k + 1] += hess[i];
                }
            }
            // Per node: the split (cue, last bin of the first child), or none.
            let mut chosen: Vec<Option<(usize, usize)>> = vec![None; n_nodes];
            let mut child_bounds = Vec::with_capacity(2 * n_nodes);
            for (nd, choice) in chosen.iter_mut().enumerate() {
                let (lo, hi) = bounds[nd];
                let value = |g: f64, h: f64| (-g / (h + LAMBDA)).clamp(lo, hi);
                let mut split_at = None;
                let h0 = &hist[nd * D * BINS * 2..(nd + 1) * D * BINS * 2];
                let (mut g_all, mut h_all) = (0.0, 0.0);
                for b in 0..BINS {
                    g_all += h0[b * 2];
                    h_all += h0[b * 2 + 1];
                }
                let parent = g_all * g_all / (h_all + LAMBDA);
                let mut best = 1e-9;
                for (f, e) in edges.iter().enumerate() {
                    if unsplit[f] {
                        continue;
                    }
                    let (mut gl, mut hl) = (0.0, 0.0);
                    for j in 0..e.len() {
                        let k = (f * BINS + j) * 2;
                        gl += h0[k];
                        hl += h0[k + 1];
                        let (gr, hr) = (g_all - gl, h_all - hl);
                        if hl < MIN_CHILD_HESSIAN || hr < MIN_CHILD_HESSIAN {
                            continue;
                        }
                        let (wl, wr) = (value(gl, hl), value(gr, hr));
                        if rising[f] && wl > wr {
                            continue;
                        }
                        let gain = gl * gl / (hl + LAMBDA) + gr * gr / (hr + LAMBDA) - parent;
                        if gain > best {
                            best = gain;
                            *choice = Some((f, j));
                            split_at = Some((wl + wr) / 2.0).filter(|_| rising[f]);
                        }
                    }
                }
                if let Some((f, j)) = *choice {
                    tree_splits[n_nodes - 1 + nd] = (f, edges[f][j]);
                }
                match split_at {
                    Some(mid) => child_bounds.extend([(lo, mid), (mid, hi)]),
                    None => child_bounds.extend([(lo, hi), (lo, hi)]),
                }
            }
            bounds = child_bounds;
            for i in 0..n {
                let right = match chosen[node[i]] {
                    Some((f, j)) => bins[i * D + f] as usize > j,
                    None => false,
                };
                node[i] = 2 * node[i] + usize::from(right);
            }
        }
        let mut gh = vec![(0.0f64, 0.0f64); n_leaves];
        for i in 0..n {
            gh[node[i]].0 += grad[i];
            gh[node[i]].1 += hess[i];
        }
        let values: Vec<f32> = gh
            .iter()
            .zip(&bounds)
            .map(|(&(g, h), &(lo, hi))| {
                (params.learning_rate * (-g / (h + LAMBDA)).clamp(lo, hi)) as f32
            })
            .collect();
        for i in 0..n {
            score[i] += values[node[i]] as f64;
        }
        splits.extend(tree_splits);
        leaves.extend(values);
    }
    match start {
        Some(m) => m.plus_trees(depth, splits, leaves, 0.0, 0.0),
        None => VoicingModel::trees(depth, base, splits, leaves, 0.0, 0.0),
    }
    .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_rising_cue_is_a_cue_of_the_model() {
        // A misspelt name would silently drop its monotone constraint.
        assert_cues_of_the_model(&RISING_CUES);
    }

    fn assert_cues_of_the_model(names: &[&str]) {
        for name in names {
            assert!(
                pneuma_core::VOICING_FEATURES.contains(name),
                "{name} is not one of the model's cues"
            );
        }
    }

    #[test]
    fn the_shipped_trees_never_split_on_an_unsplit_cue() {
        // A misspelt name would silently let the trees split on it.
        assert_cues_of_the_model(&UNSPLIT_CUES);
        let shipped = include_str!("../../../assets/models/voicing.txt");
        let trees: Vec<&str> = shipped.lines().filter(|l| l.starts_with("tree ")).collect();
        assert!(!trees.is_empty(), "the shipped model has no trees");
        for line in trees {
            for name in UNSPLIT_CUES {
                assert!(
                    !line.split_whitespace().any(|w| w == name),
                    "a shipped tree splits on {name}: {line}"
                );
            }
        }
    }

    #[test]
    fn trees_separate_what_one_line_cannot() {
        // Voiced inside a band of cue 0 and only when cue 1 is high: an interaction a
        // logistic score over these two cues cannot draw.
        let mut feats = Vec::new();
        for a in 0..40 {
            for b in 0..10 {
                let mut f = [0.0f32; N_VOICING_FEATURES];
                f[0] = a as f32 / 40.0;
                f[1] = b as f32 / 10.0;
                feats.push(f);
            }
        }
        let label = |f: &VoicingFeatures| (0.3..0.7).contains(&f[0]) && f[1] >= 0.5;
        let rows: Vec<Row> = feats.iter().map(|f| (f, label(f), 10.0)).collect();
        let params = TreeParams {
            depth: 3,
            rounds: 60,
            learning_rate: 0.3,
            monotone: false,
        };
        let m = fit_trees(&rows, &params, None).unwrap();
        let wrong = feats
            .iter()
            .filter(|f| (m.score(f) >= 0.0) != label(f))
            .count();
        assert_eq!(wrong, 0, "{wrong} of {} frames misjudged", feats.len());
        // The same rows give the same model, and it survives its file format.
        assert_eq!(fit_trees(&rows, &params, None).unwrap(), m);
        assert_eq!(VoicingModel::parse(&m.to_text(&[])).unwrap(), m);
    }

    #[test]
    fn monotone_trees_never_score_a_clearer_frame_lower() {
        // Labels that fall with chosen_clarity (cue 1) above 0.6 and depend on low_band
        // (cue 10): unconstrained trees follow the fall, monotone ones must not.
        let mut feats = Vec::new();
        for a in 0..50 {
            for b in 0..4 {
                let mut f = [0.0f32; N_VOICING_FEATURES];
                f[1] = a as f32 / 50.0;
                f[10] = b as f32 / 4.0;
                feats.push(f);
            }
        }
        let label = |f: &VoicingFeatures| (0.3..0.6).contains(&f[1]) || f[10] > 0.6;
        let rows: Vec<Row> = feats.iter().map(|f| (f, label(f), 10.0)).collect();
        let params = |monotone| TreeParams {
            depth: 2,
            rounds: 30,
            learning_rate: 0.3,
            monotone,
        };
        let falls = |m: &VoicingModel| {
            feats
                .windows(8)
                .filter(|w| m.score(&w[4]) < m.score(&w[0]) - 1e-6)
                .count()
        };
        let free = fit_trees(&rows, &params(false), None).unwrap();
        assert!(falls(&free) > 0, "the data should make free trees fall");
        let monotone = fit_trees(&rows, &params(true), None).unwrap();
        assert_eq!(falls(&monotone), 0);
    }
}
