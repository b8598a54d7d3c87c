//! Expectation–maximisation for full-covariance Gaussian mixtures: k-means++ initialisation
//! (seeded), several restarts keeping the best log-likelihood, log-domain responsibilities,
//! covariance regularisation relative to each coordinate's variance, and convergence on the
//! relative change of the log-likelihood.
//!
//! Use: [`EmConfig`] (builder-style fields) → [`EmConfig::validate`] → [`EmConfig::fit`].

use thiserror::Error;

use super::gmm::{log_sum_exp, Gaussian, Gmm, GmmError, MAX_COMPONENTS, MAX_DIM};
use crate::rng::SeededRng;

/// Errors of EM training; each message says what to change.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EmError {
    /// A setting is out of range.
    #[error("{name} = {value} is out of range: it must lie in {range}")]
    OutOfRange {
        /// Setting name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// Allowed range.
        range: &'static str,
    },
    /// Too few samples for the number of components.
    #[error("{samples} samples cannot fit {components} components: give at least {needed} samples or fewer components")]
    TooFewSamples {
        /// Samples given.
        samples: usize,
        /// Components asked.
        components: usize,
        /// Samples needed.
        needed: usize,
    },
    /// A sample holds NaN or infinity.
    #[error("sample {0} is not finite: remove NaN/infinite rows before training")]
    NotFinite(usize),
    /// A coordinate does not vary at all.
    #[error("coordinate {0} has zero variance: a constant feature cannot be modelled")]
    Constant(usize),
    /// The fitted mixture is invalid (should not happen with regularisation).
    #[error("the fitted mixture is invalid: {0}")]
    Gmm(#[from] GmmError),
}

/// Settings of EM training.
#[derive(Debug, Clone, PartialEq)]
pub struct EmConfig {
    /// Dimension of the samples, 1..=3.
    pub dim: usize,
    /// Components, 1..=32 (the paper: 11).
    pub components: usize,
    /// Independent restarts (different k-means++ seeds); the best log-likelihood wins, 1..=50
    /// (default 3).
    pub restarts: usize,
    /// Most EM iterations per restart, 1..=10000 (default 300).
    pub max_iterations: usize,
    /// Stop when the mean log-likelihood changes by less than this, relative, 0..0.1
    /// (default 1e-6).
    pub tolerance: f64,
    /// Added to each covariance diagonal, as a fraction of that coordinate's data variance,
    /// 0..1 (default 1e-3).
    pub regularisation: f64,
    /// Seed of the initialisation.
    pub seed: u64,
}

/// Most restarts of one fit.
pub const MAX_RESTARTS: usize = 50;

impl EmConfig {
    /// Defaults for `dim`-dimensional samples and `components` components.
    pub fn new(dim: usize, components: usize) -> Self {
        Self {
            dim,
            components,
            restarts: 3,
            max_iterations: 300,
            tolerance: 1e-6,
            regularisation: 1e-3,
            seed: 1,
        }
    }

    /// Sets the seed.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Sets the number of restarts.
    pub fn restarts(mut self, restarts: usize) -> Self {
        self.restarts = restarts;
        self
    }

    /// Checks every setting.
    pub fn validate(&self) -> Result<(), EmError> {
        let chk = |name, v: f64, lo: f64, hi: f64, range| {
            if v.is_finite() && v >= lo && v <= hi {
                Ok(())
            } else {
                Err(EmError::OutOfRange {
                    name,
                    value: v,
                    range,
                })
            }
        };
        chk("dim", self.dim as f64, 1.0, MAX_DIM as f64, "1..=3")?;
        chk(
            "components",
            self.components as f64,
            1.0,
            MAX_COMPONENTS as f64,
            "1..=32",
        )?;
        chk(
            "restarts",
            self.restarts as f64,
            1.0,
            MAX_RESTARTS as f64,
            "1..=50",
        )?;
        chk(
            "max_iterations",
            self.max_iterations as f64,
            1.0,
            10_000.0,
            "1..=10000",
        )?;
        chk("tolerance", self.tolerance, 0.0, 0.1, "0..0.1")?;
        chk("regularisation", self.regularisation, 0.0, 1.0, "0..1")?;
        Ok(())
    }

    /// Fits a mixture to `samples` (first `dim` entries of each row used).
    pub fn fit(&self, samples: &[[f64; MAX_DIM]]) -> Result<EmFit, EmError> {
        self.validate()?;
        let (n, d, k) = (samples.len(), self.dim, self.components);
        let needed = (k * (d + 1)).max(2 * k);
        if n < needed {
            return Err(EmError::TooFewSamples {
                samples: n,
                components: k,
                needed,
            });
        }
        if let Some(i) = samples
            .iter()
            .position(|s| s[..d].iter().any(|v| !v.is_finite()))
        {
            return Err(EmError::NotFinite(i));
        }
        let (_, var) = moments(samples, d);
        if let Some(i) = (0..d).find(|&i| var[i] <= 0.0) {
            return Err(EmError::Constant(i));
        }
        let mut reg = [0.0; MAX_DIM];
        for i in 0..d {
            reg[i] = self.regularisation * var[i] + 1e-12;
        }
        let mut best: Option<EmFit> = None;
        let mut rng = SeededRng::new(self.seed);
        for _ in 0..self.restarts {
            let init = kmeans_init(samples, d, k, &var, &reg, &mut rng);
            let fit = self.run(samples, init, &reg)?;
            if best
                .as_ref()
                .is_none_or(|b| fit.mean_log_likelihood > b.mean_log_likelihood)
            {
                best = Some(fit);
            }
        }
        Ok(best.expect("at least one restart"))
    }

    fn run(
        &self,
        samples: &[[f64; MAX_DIM]],
        mut comps: Vec<Gaussian>,
        reg: &[f64; MAX_DIM],
    ) -> Result<EmFit, EmError> {
        let (n, d) = (samples.len(), self.dim);
        let k = comps.len();
        let mut resp = vec![0.0; n * k];
        let mut prev = f64::NEG_INFINITY;
        let mut iterations = 0;
        let mut gmm = Gmm::new(d, &comps)?;
        let mut ll = f64::NEG_INFINITY;
        for it in 0..self.max_iterations {
            iterations = it + 1;
            // E-step in the log domain.
            let mut total = 0.0;
            let mut t = [0.0; MAX_COMPONENTS];
            for (s, r) in samples.iter().zip(resp.chunks_exact_mut(k)) {
                gmm.log_joint_into(s, &mut t);
                let lse = log_sum_exp(&t[..k]);
                total += lse;
                for j in 0..k {
                    r[j] = (t[j] - lse).exp();
                }
            }
            ll = total / n as f64;
            let converged = (ll - prev).abs() <= self.tolerance * ll.abs().max(1e-12);
            prev = ll;
            if converged {
                break;
            }
            // M-step.
            let mut next = Vec::with_capacity(k);
            for j in 0..k {
                let mut nk = 0.0;
                let mut mu = [0.0; MAX_DIM];
                for (s, r) in samples.iter().zip(resp.chunks_exact(k)) {
                    nk += r[j];
                    for i in 0..d {
                        mu[i] += r[j] * s[i];
                    }
                }
                if nk < 1e-8 * n as f64 {
                    // A dead component keeps its previous shape with a tiny weight.
                    let mut g = comps[j];
                    g.weight = 1e-8;
                    next.push(g);
                    continue;
                }
                for m in mu.iter_mut().take(d) {
                    *m /= nk;
                }
                let mut cov = [[0.0; MAX_DIM]; MAX_DIM];
                for (s, r) in samples.iter().zip(resp.chunks_exact(k)) {
                    let w = r[j];
                    for a in 0..d {
                        let da = s[a] - mu[a];
                        for b in 0..=a {
                            cov[a][b] += w * da * (s[b] - mu[b]);
                        }
                    }
                }
                for a in 0..d {
                    for b in 0..=a {
                        cov[a][b] /= nk;
                        cov[b][a] = cov[a][b];
                    }
                    cov[a][a] += reg[a];
                }
                next.push(Gaussian {
                    weight: nk / n as f64,
                    mean: mu,
                    cov,
                });
            }
            let sum: f64 = next.iter().map(|g| g.weight).sum();
            for g in &mut next {
                g.weight /= sum;
            }
            comps = next;
            gmm = Gmm::new(d, &comps)?;
        }
        Ok(EmFit {
            gmm,
            mean_log_likelihood: ll,
            iterations,
        })
    }
}

/// A fitted mixture.
#[derive(Debug, Clone, PartialEq)]
pub struct EmFit {
    /// The mixture.
    pub gmm: Gmm,
    /// Mean log-likelihood of the training samples, nats per sample.
    pub mean_log_likelihood: f64,
    /// EM iterations of the winning restart.
    pub iterations: usize,
}

fn moments(samples: &[[f64; MAX_DIM]], d: usize) -> ([f64; MAX_DIM], [f64; MAX_DIM]) {
    let n = samples.len() as f64;
    let mut mean = [0.0; MAX_DIM];
    for s in samples {
        for i in 0..d {
            mean[i] += s[i];
        }
    }
    for m in mean.iter_mut() {
        *m /= n;
    }
    let mut var = [0.0; MAX_DIM];
    for s in samples {
        for i in 0..d {
            var[i] += (s[i] - mean[i]).powi(2);
        }
    }
    for v in var.iter_mut() {
        *v /= n;
    }
    (mean, var)
}

/// Squared distance with each coordinate scaled by its variance.
fn dist2(a: &[f64; MAX_DIM], b: &[f64; MAX_DIM], var: &[f64; MAX_DIM], d: usize) -> f64 {
    (0..d).map(|i| (a[i] - b[i]).powi(2) / var[i]).sum()
}

/// k-means++ seeding then a few Lloyd iterations, in variance-scaled coordinates; returns the
/// initial components (cluster weights, means and regularised covariances).
fn kmeans_init(
    samples: &[[f64; MAX_DIM]],
    d: usize,
    k: usize,
    var: &[f64; MAX_DIM],
    reg: &[f64; MAX_DIM],
    rng: &mut SeededRng,
) -> Vec<Gaussian> {
    let n = samples.len();
    let mut centres: Vec<[f64; MAX_DIM]> = Vec::with_capacity(k);
    centres.push(samples[(rng.uniform() * n as f64) as usize % n]);
    let mut best: Vec<f64> = samples
        .iter()
        .map(|s| dist2(s, &centres[0], var, d))
        .collect();
    while centres.len() < k {
        let total: f64 = best.iter().sum();
        let pick = if total > 0.0 {
            let u = rng.uniform() * total;
            let mut acc = 0.0;
            let mut p = n - 1;
            for (i, b) in best.iter().enumerate() {
                acc += b;
                if acc > u {
                    p = i;
                    break;
                }
            }
            p
        } else {
            (rng.uniform() * n as f64) as usize % n
        };
        let c = samples[pick];
        centres.push(c);
        for (b, s) in best.iter_mut().zip(samples) {
            *b = b.min(dist2(s, &c, var, d));
        }
    }
    let mut label = vec![0usize; n];
    for _ in 0..10 {
        for (l, s) in label.iter_mut().zip(samples) {
            let mut bd = f64::INFINITY;
            for (j, c) in centres.iter().enumerate() {
                let dd = dist2(s, c, var, d);
                if dd < bd {
                    bd = dd;
                    *l = j;
                }
            }
        }
        let mut sum = vec![[0.0; MAX_DIM]; k];
        let mut cnt = vec![0usize; k];
        for (l, s) in label.iter().zip(samples) {
            cnt[*l] += 1;
            for i in 0..d {
                sum[*l][i] += s[i];
            }
        }
        for j in 0..k {
            if cnt[j] > 0 {
                for i in 0..d {
                    centres[j][i] = sum[j][i] / cnt[j] as f64;
                }
            }
        }
    }
    let mut comps = Vec::with_capacity(k);
    for (j, c) in centres.iter().enumerate() {
        let members: Vec<&[f64; MAX_DIM]> = label
            .iter()
            .zip(samples)
            .filter(|(l, _)| **l == j)
            .map(|(_, s)| s)
            .collect();
        let mut cov = [[0.0; MAX_DIM]; MAX_DIM];
        if members.len() > d + 1 {
            for s in &members {
                for a in 0..d {
                    for b in 0..d {
                        cov[a][b] += (s[a] - c[a]) * (s[b] - c[b]);
                    }
                }
            }
            for row in cov.iter_mut().take(d) {
                for v in row.iter_mut().take(d) {
                    *v /= members.len() as f64;
                }
            }
        } else {
            // Too few members: a diagonal covariance of a tenth of the data variance.
            for a in 0..d {
                cov[a][a] = 0.1 * var[a];
            }
        }
        for a in 0..d {
            cov[a][a] += reg[a];
        }
        comps.push(Gaussian {
            weight: (members.len().max(1)) as f64,
            mean: *c,
            cov,
        });
    }
    let total: f64 = comps.iter().map(|g| g.weight).sum();
    for g in &mut comps {
        g.weight /= total;
    }
    comps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_settings_and_data() {
        assert!(matches!(
            EmConfig::new(4, 2).validate(),
            Err(EmError::OutOfRange { name: "dim", .. })
        ));
        let few = vec![[0.0, 1.0, 2.0]; 5];
        assert!(matches!(
            EmConfig::new(3, 2).fit(&few),
            Err(EmError::TooFewSamples { .. })
        ));
        let mut rows: Vec<[f64; 3]> = (0..100)
            .map(|i| [i as f64, (i * 7 % 13) as f64, 1.0])
            .collect();
        assert!(matches!(
            EmConfig::new(3, 2).fit(&rows),
            Err(EmError::Constant(2))
        ));
        rows[3][0] = f64::NAN;
        assert!(matches!(
            EmConfig::new(2, 2).fit(&rows),
            Err(EmError::NotFinite(3))
        ));
    }
}
