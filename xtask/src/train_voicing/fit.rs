//! Fitting the voicing model: the logistic regression (Newton's method with a ridge), the
//! trees boosted from its score ([`super::trees`]), the hysteresis thresholds chosen by
//! simulating the decision, and the thirteen fits (all speakers, each held out) side by side.

use std::collections::BTreeMap;

use pneuma_core::{VoicingFeatures, VoicingModel, N_VOICING_FEATURES};

use super::frames::ClipFrames;
use super::trees::{fit_trees, Row, TreeParams};

/// Which scorer a fit makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ModelKind {
    /// Logistic regression (format version 1).
    Logistic,
    /// Gradient-boosted trees (format version 2) with these settings.
    Trees(TreeParams),
    /// The logistic regression plus trees boosted from its score (format version 3).
    Hybrid(TreeParams),
}

/// Ridge on the standardised weights (not the bias), in units of frames.
pub(crate) const RIDGE: f64 = 1.0;

pub(crate) const NEWTON_STEPS: usize = 12;

/// Threshold grid on the score (log-odds): `threshold_on` from −2 to 3 in eighth steps,
/// `threshold_off` from `threshold_on` down by up to 1 (a wider band keeps voicing through
/// the noise after a vowel, where the period is lost: measured on PTDB at 0 dB at 200 frames/s).
pub(crate) const ON_GRID: (f32, f32, f32) = (-2.0, 3.0, 0.125);

pub(crate) const OFF_BELOW_MAX: f32 = 1.0;

/// Solves `a·x = b` (symmetric positive definite, row-major `n×n`) by Cholesky.
pub(crate) fn solve_spd(a: &[f64], b: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut l = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= l[i * n + k] * l[j * n + k];
            }
            if i == j {
                if s <= 0.0 {
                    return None;
                }
                l[i * n + i] = s.sqrt();
            } else {
                l[i * n + j] = s / l[j * n + j];
            }
        }
    }
    let mut y = vec![0.0; n];
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i * n + k] * y[k];
        }
        y[i] = s / l[i * n + i];
    }
    let mut x = vec![0.0; n];
    for i in (0..n).rev() {
        let mut s = y[i];
        for k in i + 1..n {
            s -= l[k * n + i] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
    Some(x)
}

/// Fits a model of `kind` on the labelled frames of `clips`, thresholds included.
pub(crate) fn fit(clips: &[&ClipFrames], kind: ModelKind) -> Result<VoicingModel, String> {
    let model = match kind {
        ModelKind::Logistic => fit_logistic(clips)?,
        ModelKind::Trees(params) => fit_trees(&rows(clips), &params, None)?,
        ModelKind::Hybrid(params) => fit_trees(&rows(clips), &params, Some(&fit_logistic(clips)?))?,
    };
    with_chosen_thresholds(&model, clips)
}

/// The labelled frames of `clips` as training rows.
pub(crate) fn rows<'a>(clips: &[&'a ClipFrames]) -> Vec<Row<'a>> {
    clips
        .iter()
        .flat_map(|c| c.labels.iter().map(|&(k, y)| (&c.features[k], y, c.weight)))
        .collect()
}

/// The logistic regression on the labelled frames of `clips` (thresholds still 0).
pub(crate) fn fit_logistic(clips: &[&ClipFrames]) -> Result<VoicingModel, String> {
    const D: usize = N_VOICING_FEATURES;
    // Standardisation over the labelled frames.
    let mut n = 0.0f64;
    let mut sum = [0.0f64; D];
    let mut sq = [0.0f64; D];
    let mut count = 0usize;
    for c in clips {
        for &(k, _) in &c.labels {
            n += c.weight;
            count += 1;
            for i in 0..D {
                let v = c.features[k][i] as f64;
                sum[i] += c.weight * v;
                sq[i] += c.weight * v * v;
            }
        }
    }
    if count < 100 {
        return Err("fewer than 100 labelled training frames: check the data folders".into());
    }
    let mut mean = [0.0f32; D];
    let mut scale = [0.0f32; D];
    for i in 0..D {
        let m = sum[i] / n;
        mean[i] = m as f32;
        scale[i] = ((sq[i] / n - m * m).max(0.0).sqrt().max(1e-3)) as f32;
    }
    // Newton steps on the weights (index 0 = bias, 1.. = standardised cues).
    const P: usize = D + 1;
    let mut w = [0.0f64; P];
    let row = |f: &VoicingFeatures| {
        let mut x = [0.0f64; P];
        x[0] = 1.0;
        for i in 0..D {
            x[i + 1] = ((f[i] - mean[i]) / scale[i]) as f64;
        }
        x
    };
    for _ in 0..NEWTON_STEPS {
        let mut h = vec![0.0f64; P * P];
        let mut g = vec![0.0f64; P];
        for c in clips {
            for &(k, y) in &c.labels {
                let x = row(&c.features[k]);
                let z: f64 = x.iter().zip(&w).map(|(a, b)| a * b).sum();
                let p = 1.0 / (1.0 + (-z).exp());
                let r = c.weight * (f64::from(u8::from(y)) - p);
                let s = c.weight * (p * (1.0 - p)).max(1e-9);
                for i in 0..P {
                    g[i] += r * x[i];
                    for j in 0..=i {
                        h[i * P + j] += s * x[i] * x[j];
                    }
                }
            }
        }
        for i in 0..P {
            for j in 0..i {
                h[j * P + i] = h[i * P + j];
            }
            if i > 0 {
                h[i * P + i] += RIDGE;
                g[i] -= RIDGE * w[i];
            }
        }
        let step = solve_spd(&h, &g, P).ok_or("the training frames are degenerate")?;
        for (wi, si) in w.iter_mut().zip(&step) {
            *wi += si;
        }
    }
    let mut weight = [0.0f32; D];
    for i in 0..D {
        weight[i] = w[i + 1] as f32;
    }
    VoicingModel::new(mean, scale, weight, w[0] as f32, 0.0, 0.0).map_err(|e| e.to_string())
}

/// Frame errors of `model` over the scored frames of `clips`, and the scored frames.
pub(crate) fn voicing_errors(model: &VoicingModel, clips: &[&ClipFrames]) -> (u64, u64) {
    let (mut errors, mut frames) = (0u64, 0u64);
    for c in clips {
        let scores: Vec<f32> = c.features.iter().map(|f| model.score(f)).collect();
        let decisions = decide(model, &scores, &c.seen);
        let (e, n) = frame_errors(c, &decisions);
        errors += e;
        frames += n;
    }
    (errors, frames)
}

/// Frame errors of one clip's `decisions` as FFE counts them (a wrong decision, or a voiced
/// decision on a frame whose period is wrong), and the frames scored.
pub(crate) fn frame_errors(c: &ClipFrames, decisions: &[bool]) -> (u64, u64) {
    let wrong = c.labels.iter().filter(|&&(k, y)| decisions[k] != y).count() + c.wrong_pitch.len();
    (wrong as u64, (c.labels.len() + c.wrong_pitch.len()) as u64)
}

/// The decisions of `model` over one clip (hysteresis as in the analyzer).
pub(crate) fn decide(model: &VoicingModel, scores: &[f32], seen: &[bool]) -> Vec<bool> {
    let mut voiced = false;
    scores
        .iter()
        .zip(seen)
        .map(|(&z, &s)| {
            voiced = s && z >= model.threshold(voiced);
            voiced
        })
        .collect()
}

/// `model` with the threshold pair of the grid that makes the fewest (weighted) frame errors
/// on `clips` (ties: the first).
pub(crate) fn with_chosen_thresholds(
    model: &VoicingModel,
    clips: &[&ClipFrames],
) -> Result<VoicingModel, String> {
    let (on, off) = choose_thresholds(model, clips);
    model.with_thresholds(on, off).map_err(|e| e.to_string())
}

/// The threshold pair of the grid with the fewest (weighted) frame errors on `clips` (ties:
/// the first).
pub(crate) fn choose_thresholds(model: &VoicingModel, clips: &[&ClipFrames]) -> (f32, f32) {
    let scores: Vec<Vec<f32>> = clips
        .iter()
        .map(|c| c.features.iter().map(|f| model.score(f)).collect())
        .collect();
    let mut best = (f64::INFINITY, 0.0, 0.0);
    let steps = ((ON_GRID.1 - ON_GRID.0) / ON_GRID.2).round() as i32;
    let off_steps = (OFF_BELOW_MAX / ON_GRID.2).round() as i32;
    for i in 0..=steps {
        let on = ON_GRID.0 + i as f32 * ON_GRID.2;
        for j in 0..=off_steps {
            let off = on - j as f32 * ON_GRID.2;
            let Ok(m) = model.with_thresholds(on, off) else {
                continue;
            };
            let mut errors = 0.0f64;
            for (c, z) in clips.iter().zip(&scores) {
                let d = decide(&m, z, &c.seen);
                errors += c.weight * frame_errors(c, &d).0 as f64;
            }
            if errors < best.0 {
                best = (errors, on, off);
            }
        }
    }
    (best.1, best.2)
}

/// The speakers of `clips`, sorted.
pub(crate) fn speakers(clips: &[ClipFrames]) -> Vec<String> {
    let mut s: Vec<String> = clips.iter().map(|c| c.speaker.clone()).collect();
    s.sort();
    s.dedup();
    s
}

/// The shipped model (all speakers) and one model per held-out speaker (fitted without it).
pub(crate) fn fit_all_and_loso(
    clips: &[ClipFrames],
    kind: ModelKind,
) -> Result<(VoicingModel, BTreeMap<String, VoicingModel>), String> {
    // Job 0 fits on every speaker, job k + 1 without speaker k. The jobs are independent and
    // each runs in a fixed order, so spreading them over threads changes no bit of the result.
    let names = speakers(clips);
    let fit_job = |job: usize| {
        let train: Vec<&ClipFrames> = match job {
            0 => clips.iter().collect(),
            k => clips.iter().filter(|c| c.speaker != names[k - 1]).collect(),
        };
        fit(&train, kind)
    };
    let jobs = names.len() + 1;
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, jobs);
    let mut fitted: Vec<Option<Result<VoicingModel, String>>> = (0..jobs).map(|_| None).collect();
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let fit_job = &fit_job;
                scope.spawn(move || {
                    (t..jobs)
                        .step_by(threads)
                        .map(|job| (job, fit_job(job)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for w in workers {
            for (job, result) in w.join().expect("a fitting thread panicked") {
                fitted[job] = Some(result);
            }
        }
    });
    let mut fitted = fitted.into_iter().map(|r| r.expect("every job ran"));
    let shipped = fitted.next().expect("job 0")?;
    let mut loso = BTreeMap::new();
    for (name, model) in names.into_iter().zip(fitted) {
        loso.insert(name, model?);
    }
    Ok((shipped, loso))
}
