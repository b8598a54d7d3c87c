//! Fitting the stacked speech model: a class-balanced logistic regression (speech frames and
//! non-speech frames weigh half each) on standardised inputs, by Newton's method in `f64` with
//! a small ridge on the weights, deterministic to the bit. Which frames a model may be fitted on
//! is [`Frames::fit_rows`]'s choice: never the sung piece, and for a held-out model never the
//! music pieces, noise type or speakers of the episode it judges.

use pneuma_core::speech::model::{SpeechFeatures, N_SPEECH_FEATURES};
use pneuma_core::speech::SpeechModel;

/// Ridge on the standardised weights (not the bias).
const RIDGE: f64 = 1e-3;
/// Newton steps at most; the fit stops earlier when no parameter moves by more than
/// [`TOLERANCE`].
const MAX_STEPS: usize = 50;
const TOLERANCE: f64 = 1e-12;
/// The decision threshold on the probability (the classes weigh the same).
pub const THRESHOLD: f32 = 0.5;

/// One training frame.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    /// The model's inputs.
    pub x: SpeechFeatures,
    /// Speech truth.
    pub speech: bool,
}

/// Fits the model on `rows`; `None` when a class is missing.
pub fn fit(rows: &[Row]) -> Option<SpeechModel> {
    let n_pos = rows.iter().filter(|r| r.speech).count();
    let n_neg = rows.len() - n_pos;
    if n_pos == 0 || n_neg == 0 {
        return None;
    }
    let w_pos = 0.5 / n_pos as f64;
    let w_neg = 0.5 / n_neg as f64;
    let weight = |r: &Row| if r.speech { w_pos } else { w_neg };
    // Standardisation: weighted mean and SD (each class half).
    let mut mean = [0.0f64; N_SPEECH_FEATURES];
    for r in rows {
        for (m, x) in mean.iter_mut().zip(r.x) {
            *m += weight(r) * f64::from(x);
        }
    }
    let mut var = [0.0f64; N_SPEECH_FEATURES];
    for r in rows {
        for k in 0..N_SPEECH_FEATURES {
            var[k] += weight(r) * (f64::from(r.x[k]) - mean[k]).powi(2);
        }
    }
    let scale = var.map(|v| v.sqrt().max(1e-6));
    // Round the standardisation to f32 first, so the model file's numbers are the ones fitted.
    let mean32 = mean.map(|m| m as f32);
    let scale32 = scale.map(|s| s as f32);
    let z = |r: &Row| -> [f64; N_SPEECH_FEATURES + 1] {
        let mut v = [1.0; N_SPEECH_FEATURES + 1];
        for k in 0..N_SPEECH_FEATURES {
            v[k + 1] = f64::from((r.x[k] - mean32[k]) / scale32[k]);
        }
        v
    };
    const D: usize = N_SPEECH_FEATURES + 1;
    let mut beta = [0.0f64; D];
    for _ in 0..MAX_STEPS {
        let mut grad = [0.0f64; D];
        let mut hess = [[0.0f64; D]; D];
        for r in rows {
            let v = z(r);
            let eta: f64 = (0..D).map(|k| beta[k] * v[k]).sum();
            let p = 1.0 / (1.0 + (-eta).exp());
            let w = weight(r);
            let y = if r.speech { 1.0 } else { 0.0 };
            for a in 0..D {
                grad[a] += w * (p - y) * v[a];
                for b in 0..D {
                    hess[a][b] += w * p * (1.0 - p) * v[a] * v[b];
                }
            }
        }
        for a in 1..D {
            grad[a] += RIDGE * beta[a];
            hess[a][a] += RIDGE;
        }
        let step = solve(hess, grad)?;
        let mut moved = 0.0f64;
        for a in 0..D {
            beta[a] -= step[a];
            moved = moved.max(step[a].abs());
        }
        if moved < TOLERANCE {
            break;
        }
    }
    let weight32: SpeechFeatures = std::array::from_fn(|k| beta[k + 1] as f32);
    SpeechModel::new(mean32, scale32, weight32, beta[0] as f32, THRESHOLD).ok()
}

/// Solves `a · x = b` by Gaussian elimination with partial pivoting.
fn solve<const D: usize>(mut a: [[f64; D]; D], mut b: [f64; D]) -> Option<[f64; D]> {
    for col in 0..D {
        let pivot = (col..D).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-300 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        for row in col + 1..D {
            let f = a[row][col] / a[col][col];
            let pivot_row = a[col];
            for (v, p) in a[row][col..].iter_mut().zip(&pivot_row[col..]) {
                *v -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    let mut x = [0.0; D];
    for row in (0..D).rev() {
        let s: f64 = (row + 1..D).map(|k| a[row][k] * x[k]).sum();
        x[row] = (b[row] - s) / a[row][row];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::rng::SeededRng;

    #[test]
    fn the_fit_recovers_a_known_logistic_model() {
        // Speech drawn with probability σ(2·x0 − 1·x2 + 0.5) on standard normal inputs.
        let mut rng = SeededRng::new(5);
        let rows: Vec<Row> = (0..20_000)
            .map(|_| {
                let x = [
                    rng.normal() as f32,
                    rng.normal() as f32,
                    rng.normal() as f32,
                ];
                let eta = 2.0 * f64::from(x[0]) - f64::from(x[2]) + 0.5;
                let p = 1.0 / (1.0 + (-eta).exp());
                Row {
                    x,
                    speech: rng.uniform() < p,
                }
            })
            .collect();
        let m = fit(&rows).expect("both classes");
        // Class balancing moves the bias, not the slopes: compare the slopes' ratio and the
        // decisions' agreement with the true model at the balanced threshold.
        let p = |x: [f32; 3]| m.probability(&x);
        let (a, b) = (p([1.0, 0.0, 0.0]), p([0.0, 0.0, 0.0]));
        let logit = |q: f32| (q / (1.0 - q)).ln();
        let slope0 = logit(a) - logit(b);
        let slope2 = logit(p([0.0, 0.0, 1.0])) - logit(b);
        let slope1 = logit(p([0.0, 1.0, 0.0])) - logit(b);
        assert!((slope0 - 2.0).abs() < 0.15, "{slope0}");
        assert!((slope2 + 1.0).abs() < 0.1, "{slope2}");
        assert!(slope1.abs() < 0.1, "{slope1}");
        assert!(fit(&rows[..1]
            .iter()
            .map(|r| Row { speech: true, ..*r })
            .collect::<Vec<_>>())
        .is_none());
    }
}
