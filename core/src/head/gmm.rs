//! Gaussian mixture models with full covariances in a small fixed dimension (1..=[`MAX_DIM`]),
//! with Cholesky-based log densities, and the conditional 1-D mixture of the first coordinate
//! given the others that the per-frame synthesis maximises.
//!
//! All math uses fixed-size arrays: evaluating or conditioning never allocates.

use thiserror::Error;

/// Largest dimension a [`Gmm`] supports.
pub const MAX_DIM: usize = 3;
/// Largest number of components a [`Gmm`] supports.
pub const MAX_COMPONENTS: usize = 32;

const LN_2PI: f64 = 1.837_877_066_409_345_3;

/// Errors of a mixture's parameters; each message says what to change.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GmmError {
    /// The dimension is outside 1..=MAX_DIM.
    #[error("dimension {0} is not supported: use 1..={MAX_DIM}")]
    Dimension(usize),
    /// The number of components is outside 1..=MAX_COMPONENTS.
    #[error("{0} components is not supported: use 1..={MAX_COMPONENTS}")]
    Components(usize),
    /// A mean or covariance has the wrong number of entries.
    #[error(
        "component {component}: {what} has {got} entries where the dimension {dim} needs {want}"
    )]
    Shape {
        /// Component index.
        component: usize,
        /// `mean` or `covariance`.
        what: &'static str,
        /// Dimension of the mixture.
        dim: usize,
        /// Entries given.
        got: usize,
        /// Entries needed.
        want: usize,
    },
    /// A number is NaN or infinite.
    #[error("component {component}: {what} is not a finite number: every weight, mean and covariance entry must be finite")]
    NotFinite {
        /// Component index.
        component: usize,
        /// Which parameter.
        what: &'static str,
    },
    /// A weight is not positive.
    #[error("component {component}: weight {weight} must be > 0 (drop the component instead)")]
    Weight {
        /// Component index.
        component: usize,
        /// The weight given.
        weight: f64,
    },
    /// The weights do not sum to 1.
    #[error("weights sum to {0}, not 1: normalise them (tolerance 1e-6)")]
    WeightSum(f64),
    /// A covariance is not symmetric.
    #[error("component {0}: covariance is not symmetric")]
    NotSymmetric(usize),
    /// A covariance is not positive definite.
    #[error("component {0}: covariance is not positive definite (regularise it: add a small multiple of the identity)")]
    NotPositiveDefinite(usize),
}

/// One Gaussian of a mixture; entries past the mixture's dimension are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gaussian {
    /// Mixing weight, > 0; the weights of a mixture sum to 1.
    pub weight: f64,
    /// Mean vector.
    pub mean: [f64; MAX_DIM],
    /// Full covariance matrix (symmetric positive definite in the used block).
    pub cov: [[f64; MAX_DIM]; MAX_DIM],
}

/// A validated component with its Cholesky factor.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Prepared {
    g: Gaussian,
    /// Lower Cholesky factor of the covariance.
    chol: [[f64; MAX_DIM]; MAX_DIM],
    /// log weight − ½·(d·ln 2π + ln|Σ|).
    log_norm: f64,
}

/// A validated Gaussian mixture model.
#[derive(Debug, Clone, PartialEq)]
pub struct Gmm {
    dim: usize,
    comps: Vec<Prepared>,
}

/// Lower Cholesky factor of the leading `dim`×`dim` block, or `None` when not positive definite.
pub(crate) fn cholesky(
    a: &[[f64; MAX_DIM]; MAX_DIM],
    dim: usize,
) -> Option<[[f64; MAX_DIM]; MAX_DIM]> {
    let mut l = [[0.0; MAX_DIM]; MAX_DIM];
    for i in 0..dim {
        for j in 0..=i {
            let mut s = a[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            if i == j {
                // Relative pivot test: a pivot lost to rounding is not positive.
                if s.is_nan() || s <= 1e-12 * a[i][i].abs() || !s.is_finite() {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    Some(l)
}

/// ½·xᵀΣ⁻¹x via forward substitution with the Cholesky factor.
fn half_mahalanobis(l: &[[f64; MAX_DIM]; MAX_DIM], x: &[f64; MAX_DIM], dim: usize) -> f64 {
    let mut z = [0.0; MAX_DIM];
    let mut s = 0.0;
    for i in 0..dim {
        let mut v = x[i];
        for k in 0..i {
            v -= l[i][k] * z[k];
        }
        z[i] = v / l[i][i];
        s += z[i] * z[i];
    }
    0.5 * s
}

/// log Σ exp(v) of a slice, stable; −∞ for an empty slice.
pub(crate) fn log_sum_exp(v: &[f64]) -> f64 {
    let m = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !m.is_finite() {
        return m;
    }
    m + v.iter().map(|x| (x - m).exp()).sum::<f64>().ln()
}

impl Gmm {
    /// Validates and prepares a mixture of `dim`-dimensional Gaussians.
    pub fn new(dim: usize, components: &[Gaussian]) -> Result<Self, GmmError> {
        if dim == 0 || dim > MAX_DIM {
            return Err(GmmError::Dimension(dim));
        }
        if components.is_empty() || components.len() > MAX_COMPONENTS {
            return Err(GmmError::Components(components.len()));
        }
        let mut sum = 0.0;
        let mut comps = Vec::with_capacity(components.len());
        for (c, g) in components.iter().enumerate() {
            if !g.weight.is_finite() {
                return Err(GmmError::NotFinite {
                    component: c,
                    what: "weight",
                });
            }
            if g.weight <= 0.0 {
                return Err(GmmError::Weight {
                    component: c,
                    weight: g.weight,
                });
            }
            if g.mean[..dim].iter().any(|m| !m.is_finite()) {
                return Err(GmmError::NotFinite {
                    component: c,
                    what: "mean",
                });
            }
            for i in 0..dim {
                for j in 0..dim {
                    if !g.cov[i][j].is_finite() {
                        return Err(GmmError::NotFinite {
                            component: c,
                            what: "covariance",
                        });
                    }
                    let tol = 1e-9 * (g.cov[i][i].abs() * g.cov[j][j].abs()).sqrt().max(1e-300);
                    if (g.cov[i][j] - g.cov[j][i]).abs() > tol {
                        return Err(GmmError::NotSymmetric(c));
                    }
                }
            }
            let chol = cholesky(&g.cov, dim).ok_or(GmmError::NotPositiveDefinite(c))?;
            let log_det: f64 = (0..dim).map(|i| 2.0 * chol[i][i].ln()).sum();
            let mut clean = *g;
            for i in 0..MAX_DIM {
                if i >= dim {
                    clean.mean[i] = 0.0;
                }
                for j in 0..MAX_DIM {
                    if i >= dim || j >= dim {
                        clean.cov[i][j] = 0.0;
                    }
                }
            }
            comps.push(Prepared {
                g: clean,
                chol,
                log_norm: g.weight.ln() - 0.5 * (dim as f64 * LN_2PI + log_det),
            });
            sum += g.weight;
        }
        if (sum - 1.0).abs() > 1e-6 {
            return Err(GmmError::WeightSum(sum));
        }
        Ok(Self { dim, comps })
    }

    /// Dimension of the mixture.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of components.
    pub fn len(&self) -> usize {
        self.comps.len()
    }

    /// Always false: a mixture has at least one component.
    pub fn is_empty(&self) -> bool {
        self.comps.is_empty()
    }

    /// The components.
    pub fn components(&self) -> impl Iterator<Item = &Gaussian> + '_ {
        self.comps.iter().map(|p| &p.g)
    }

    /// Log density at `x` (the first `dim` entries are used). Allocation-free.
    pub fn log_pdf(&self, x: &[f64]) -> f64 {
        let mut terms = [0.0; MAX_COMPONENTS];
        let n = self.log_joint_into(x, &mut terms);
        log_sum_exp(&terms[..n])
    }

    /// Writes log(weight·N(x; μ, Σ)) per component into `out`; returns the component count.
    pub(crate) fn log_joint_into(&self, x: &[f64], out: &mut [f64; MAX_COMPONENTS]) -> usize {
        let mut d = [0.0; MAX_DIM];
        for (k, p) in self.comps.iter().enumerate() {
            for i in 0..self.dim {
                d[i] = x[i] - p.g.mean[i];
            }
            out[k] = p.log_norm - half_mahalanobis(&p.chol, &d, self.dim);
        }
        self.comps.len()
    }

    /// Draws one sample into the first `dim` entries of the result.
    pub fn sample(&self, rng: &mut crate::rng::SeededRng) -> [f64; MAX_DIM] {
        let u = rng.uniform();
        let mut acc = 0.0;
        let mut pick = self.comps.len() - 1;
        for (k, p) in self.comps.iter().enumerate() {
            acc += p.g.weight;
            if u < acc {
                pick = k;
                break;
            }
        }
        let p = &self.comps[pick];
        let mut z = [0.0; MAX_DIM];
        for zi in z.iter_mut().take(self.dim) {
            *zi = rng.normal();
        }
        let mut x = p.g.mean;
        for i in 0..self.dim {
            for k in 0..=i {
                x[i] += p.chol[i][k] * z[k];
            }
        }
        x
    }

    /// Precomputes the conditional of coordinate 0 given coordinates 1..dim.
    pub fn conditioner(&self) -> Conditioner {
        let r = self.dim - 1;
        let mut parts = [CondPart::default(); MAX_COMPONENTS];
        for (k, p) in self.comps.iter().enumerate() {
            let g = &p.g;
            // Σ_rr (indices 1..dim) and its inverse via Cholesky (r ≤ 2).
            let mut srr = [[0.0; MAX_DIM]; MAX_DIM];
            for i in 0..r {
                for j in 0..r {
                    srr[i][j] = g.cov[i + 1][j + 1];
                }
            }
            let mut inv = [[0.0; MAX_DIM]; MAX_DIM];
            let mut log_det_rr = 0.0;
            if r > 0 {
                // The block of a positive-definite matrix is positive definite.
                let l = cholesky(&srr, r).unwrap_or_else(|| {
                    let mut l = [[0.0; MAX_DIM]; MAX_DIM];
                    for (i, row) in l.iter_mut().enumerate().take(r) {
                        row[i] = srr[i][i].abs().max(1e-12).sqrt();
                    }
                    l
                });
                log_det_rr = (0..r).map(|i| 2.0 * l[i][i].ln()).sum();
                for j in 0..r {
                    let mut e = [0.0; MAX_DIM];
                    e[j] = 1.0;
                    let col = chol_solve(&l, &e, r);
                    for i in 0..r {
                        inv[i][j] = col[i];
                    }
                }
            }
            // Regression coefficients b = Σ_0r Σ_rr⁻¹ and the conditional variance.
            let mut b = [0.0; MAX_DIM];
            for j in 0..r {
                b[j] = (0..r).map(|i| g.cov[0][i + 1] * inv[i][j]).sum();
            }
            let var = (g.cov[0][0] - (0..r).map(|j| b[j] * g.cov[0][j + 1]).sum::<f64>())
                .max(1e-9 * g.cov[0][0]);
            let mut mean_r = [0.0; MAX_DIM];
            mean_r[..r].copy_from_slice(&g.mean[1..(r + 1)]);
            parts[k] = CondPart {
                log_w_marg: g.weight.ln() - 0.5 * (r as f64 * LN_2PI + log_det_rr),
                mean_r,
                inv_rr: inv,
                mean0: g.mean[0],
                b,
                var,
            };
        }
        Conditioner {
            r,
            n: self.comps.len(),
            parts,
        }
    }
}

fn chol_solve(l: &[[f64; MAX_DIM]; MAX_DIM], b: &[f64; MAX_DIM], n: usize) -> [f64; MAX_DIM] {
    let mut y = [0.0; MAX_DIM];
    for i in 0..n {
        let mut v = b[i];
        for k in 0..i {
            v -= l[i][k] * y[k];
        }
        y[i] = v / l[i][i];
    }
    let mut x = [0.0; MAX_DIM];
    for i in (0..n).rev() {
        let mut v = y[i];
        for k in i + 1..n {
            v -= l[k][i] * x[k];
        }
        x[i] = v / l[i][i];
    }
    x
}

#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct CondPart {
    log_w_marg: f64,
    mean_r: [f64; MAX_DIM],
    inv_rr: [[f64; MAX_DIM]; MAX_DIM],
    mean0: f64,
    b: [f64; MAX_DIM],
    var: f64,
}

/// Precomputed pieces of p(x₀ | x₁..) for a [`Gmm`]; turns the given coordinates into a
/// [`Mixture1`] without allocating.
#[derive(Debug, Clone, PartialEq)]
pub struct Conditioner {
    r: usize,
    n: usize,
    parts: [CondPart; MAX_COMPONENTS],
}

impl Conditioner {
    /// Number of conditioning coordinates (dimension − 1).
    pub fn given_dim(&self) -> usize {
        self.r
    }

    /// The conditional density of coordinate 0 given `given` (length ≥ dimension − 1).
    pub fn condition(&self, given: &[f64], out: &mut Mixture1) {
        let mut lw = [0.0; MAX_COMPONENTS];
        for k in 0..self.n {
            let p = &self.parts[k];
            let mut d = [0.0; MAX_DIM];
            for i in 0..self.r {
                d[i] = given[i] - p.mean_r[i];
            }
            let mut q = 0.0;
            let mut shift = 0.0;
            for i in 0..self.r {
                let mut row = 0.0;
                for j in 0..self.r {
                    row += p.inv_rr[i][j] * d[j];
                }
                q += d[i] * row;
                shift += p.b[i] * d[i];
            }
            lw[k] = p.log_w_marg - 0.5 * q;
            out.mean[k] = p.mean0 + shift;
            out.inv_var[k] = 1.0 / p.var;
            out.log_w[k] = -0.5 * (LN_2PI + p.var.ln());
        }
        let total = log_sum_exp(&lw[..self.n]);
        for (k, w) in lw.iter().enumerate().take(self.n) {
            out.log_w[k] += w - total;
        }
        out.n = self.n;
    }
}

/// A 1-D Gaussian mixture in log form: the conditional density that synthesis maximises.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mixture1 {
    n: usize,
    /// log weight + log normalisation per component.
    log_w: [f64; MAX_COMPONENTS],
    mean: [f64; MAX_COMPONENTS],
    inv_var: [f64; MAX_COMPONENTS],
}

impl Default for Mixture1 {
    fn default() -> Self {
        Self {
            n: 1,
            log_w: [-0.5 * LN_2PI; MAX_COMPONENTS],
            mean: [0.0; MAX_COMPONENTS],
            inv_var: [1.0; MAX_COMPONENTS],
        }
    }
}

impl Mixture1 {
    /// Log density and its derivative at `x`.
    #[inline]
    pub fn log_pdf_grad(&self, x: f64) -> (f64, f64) {
        let mut t = [0.0; MAX_COMPONENTS];
        let mut m = f64::NEG_INFINITY;
        for k in 0..self.n {
            let d = x - self.mean[k];
            t[k] = self.log_w[k] - 0.5 * d * d * self.inv_var[k];
            m = m.max(t[k]);
        }
        let mut s = 0.0;
        let mut g = 0.0;
        for k in 0..self.n {
            let e = (t[k] - m).exp();
            s += e;
            g -= e * (x - self.mean[k]) * self.inv_var[k];
        }
        (m + s.ln(), g / s)
    }

    /// The weight of component `k` (the log weight without the normalisation).
    fn weight(&self, k: usize) -> f64 {
        (self.log_w[k] + 0.5 * (LN_2PI - self.inv_var[k].ln())).exp()
    }

    /// The mean of the mixture.
    pub fn mean(&self) -> f64 {
        (0..self.n).map(|k| self.weight(k) * self.mean[k]).sum()
    }

    /// The mean and the variance of the mixture (within-component variance plus the spread of
    /// the component means).
    pub fn mean_variance(&self) -> (f64, f64) {
        let mean = self.mean();
        let var = (0..self.n)
            .map(|k| self.weight(k) * (1.0 / self.inv_var[k] + (self.mean[k] - mean).powi(2)))
            .sum();
        (mean, var)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g(weight: f64, mean: [f64; 3], cov: [[f64; 3]; 3]) -> Gaussian {
        Gaussian { weight, mean, cov }
    }

    #[test]
    fn single_gaussian_density_matches_formula() {
        let cov = [[2.0, 0.5, 0.0], [0.5, 1.0, 0.2], [0.0, 0.2, 3.0]];
        let m = Gmm::new(3, &[g(1.0, [1.0, -1.0, 0.5], cov)]).unwrap();
        // Determinant and inverse by cofactors.
        let det = 2.0 * (1.0 * 3.0 - 0.04) - 0.5 * (0.5 * 3.0 - 0.0) + 0.0;
        let x = [1.0, -1.0, 0.5];
        let expect = -0.5 * (3.0 * LN_2PI + f64::ln(det));
        assert!((m.log_pdf(&x) - expect).abs() < 1e-12);
    }

    #[test]
    fn conditional_of_bivariate_normal_is_the_textbook_one() {
        // x0 | x1 ~ N(μ0 + ρσ0/σ1 (x1 − μ1), σ0²(1 − ρ²)).
        let (s0, s1, rho) = (2.0, 3.0, 0.6);
        let cov = [
            [s0 * s0, rho * s0 * s1, 0.0],
            [rho * s0 * s1, s1 * s1, 0.0],
            [0.0, 0.0, 0.0],
        ];
        let m = Gmm::new(2, &[g(1.0, [1.0, 2.0, 0.0], cov)]).unwrap();
        let mut out = Mixture1::default();
        m.conditioner().condition(&[5.0], &mut out);
        let mu = 1.0 + rho * s0 / s1 * (5.0 - 2.0);
        let var = s0 * s0 * (1.0 - rho * rho);
        assert!((out.mean() - mu).abs() < 1e-12);
        let (lp, grad) = out.log_pdf_grad(mu + 1.0);
        assert!((lp - (-0.5 * (LN_2PI + var.ln()) - 0.5 / var)).abs() < 1e-12);
        assert!((grad + 1.0 / var).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_parameters() {
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(
            Gmm::new(4, &[g(1.0, [0.0; 3], id)]),
            Err(GmmError::Dimension(4))
        );
        assert!(matches!(
            Gmm::new(3, &[g(0.5, [0.0; 3], id)]),
            Err(GmmError::WeightSum(_))
        ));
        assert!(matches!(
            Gmm::new(3, &[g(1.0, [f64::NAN, 0.0, 0.0], id)]),
            Err(GmmError::NotFinite { .. })
        ));
        let mut bad = id;
        bad[2][2] = -1.0;
        assert_eq!(
            Gmm::new(3, &[g(1.0, [0.0; 3], bad)]),
            Err(GmmError::NotPositiveDefinite(0))
        );
        let mut asym = id;
        asym[0][1] = 0.5;
        assert_eq!(
            Gmm::new(3, &[g(1.0, [0.0; 3], asym)]),
            Err(GmmError::NotSymmetric(0))
        );
    }
}
