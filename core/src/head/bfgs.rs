//! A small box-bounded BFGS minimiser in three dimensions with analytic gradients: the search
//! direction is projected so that variables sitting on a bound and pushed outward stay put, and
//! the backtracking (Armijo) line search clamps every trial point into the box. Fixed-size math,
//! no allocation, deterministic.

use glam::{DMat3, DVec3};

/// Settings of the minimiser.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BfgsConfig {
    /// Most iterations (default 30).
    pub max_iterations: u32,
    /// Stop when the projected gradient's largest entry is below this (default 1e-5).
    pub gradient_tolerance: f64,
    /// Stop when a step changes the objective by less than this, relative (default 1e-10).
    pub value_tolerance: f64,
}

impl Default for BfgsConfig {
    fn default() -> Self {
        Self {
            max_iterations: 30,
            gradient_tolerance: 1e-5,
            value_tolerance: 1e-10,
        }
    }
}

/// The result of a minimisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BfgsResult {
    /// Best point found (inside the box).
    pub x: DVec3,
    /// Objective there.
    pub value: f64,
    /// Iterations used.
    pub iterations: u32,
    /// Objective evaluations used.
    pub evaluations: u32,
}

fn project_gradient(x: DVec3, g: DVec3, lo: DVec3, hi: DVec3) -> DVec3 {
    let mut p = g;
    for i in 0..3 {
        if (x[i] <= lo[i] && g[i] > 0.0) || (x[i] >= hi[i] && g[i] < 0.0) {
            p[i] = 0.0;
        }
    }
    p
}

/// Minimises `f` (returning value and gradient) from `x0` inside the box `lo..=hi`.
/// A non-finite objective counts as +∞ (the line search backs off from it).
pub fn minimize(
    mut f: impl FnMut(DVec3) -> (f64, DVec3),
    x0: DVec3,
    lo: DVec3,
    hi: DVec3,
    cfg: &BfgsConfig,
) -> BfgsResult {
    let mut x = x0.clamp(lo, hi);
    let (mut fx, mut g) = f(x);
    let mut evals = 1;
    if !fx.is_finite() || !g.is_finite() {
        return BfgsResult {
            x,
            value: fx,
            iterations: 0,
            evaluations: evals,
        };
    }
    let mut h = DMat3::IDENTITY; // inverse Hessian estimate
    let mut first = true;
    let mut it = 0;
    while it < cfg.max_iterations {
        it += 1;
        let pg = project_gradient(x, g, lo, hi);
        if pg.abs().max_element() < cfg.gradient_tolerance {
            break;
        }
        let mut d = -(h * pg);
        // Keep the direction inside the box and downhill; else fall back to steepest descent.
        for i in 0..3 {
            if (x[i] <= lo[i] && d[i] < 0.0) || (x[i] >= hi[i] && d[i] > 0.0) {
                d[i] = 0.0;
            }
        }
        if d.dot(pg) >= 0.0 || !d.is_finite() {
            h = DMat3::IDENTITY;
            d = -pg;
        }
        if first {
            // Scale the first step to a sensible length (1 unit), as the Hessian is unknown.
            let n = d.length();
            if n > 1.0 {
                d /= n;
            }
        }
        let slope = d.dot(g);
        let mut t = 1.0;
        let mut accepted = None;
        for _ in 0..30 {
            let xn = (x + d * t).clamp(lo, hi);
            let (fnew, gnew) = f(xn);
            evals += 1;
            if fnew.is_finite() && gnew.is_finite() && fnew <= fx + 1e-4 * t * slope.min(0.0) {
                accepted = Some((xn, fnew, gnew));
                break;
            }
            t *= 0.5;
        }
        let Some((xn, fnew, gnew)) = accepted else {
            break;
        };
        let s = xn - x;
        let y = gnew - g;
        let sy = s.dot(y);
        let done = (fx - fnew).abs() <= cfg.value_tolerance * (1.0 + fx.abs());
        if sy > 1e-12 * s.length() * y.length() {
            if first {
                // Shanno–Phua scaling of the initial inverse Hessian.
                h = DMat3::IDENTITY * (sy / y.dot(y));
            }
            let rho = 1.0 / sy;
            let hy = h * y;
            let yhy = y.dot(hy);
            // H ← H + ((sᵀy + yᵀHy)/(sᵀy)²) ssᵀ − (Hy sᵀ + s yᵀH)/(sᵀy)
            let ss = outer(s, s);
            let hys = outer(hy, s);
            h = h + ss * ((sy + yhy) * rho * rho) - (hys + hys.transpose()) * rho;
            first = false;
        }
        x = xn;
        fx = fnew;
        g = gnew;
        if done {
            break;
        }
    }
    BfgsResult {
        x,
        value: fx,
        iterations: it,
        evaluations: evals,
    }
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    // Column j is a·b[j].
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_skewed_quadratic() {
        let c = DVec3::new(1.0, -2.0, 3.0);
        let a = DMat3::from_cols_array(&[4.0, 1.0, 0.0, 1.0, 3.0, 0.5, 0.0, 0.5, 2.0]);
        let f = |x: DVec3| {
            let d = x - c;
            (0.5 * d.dot(a * d), a * d)
        };
        let r = minimize(
            f,
            DVec3::ZERO,
            DVec3::splat(-10.0),
            DVec3::splat(10.0),
            &BfgsConfig::default(),
        );
        assert!((r.x - c).length() < 1e-4, "{:?}", r);
    }

    #[test]
    fn respects_the_box() {
        let c = DVec3::new(5.0, 0.0, -5.0);
        let f = |x: DVec3| ((x - c).length_squared(), 2.0 * (x - c));
        let r = minimize(
            f,
            DVec3::ZERO,
            DVec3::splat(-2.0),
            DVec3::splat(2.0),
            &BfgsConfig::default(),
        );
        assert!(
            (r.x - DVec3::new(2.0, 0.0, -2.0)).length() < 1e-6,
            "{:?}",
            r
        );
    }

    #[test]
    fn minimises_rosenbrock_in_two_of_three_variables() {
        let f = |x: DVec3| {
            let (a, b) = (x.x, x.y);
            let v = (1.0 - a).powi(2) + 100.0 * (b - a * a).powi(2) + x.z * x.z;
            let g = DVec3::new(
                -2.0 * (1.0 - a) - 400.0 * a * (b - a * a),
                200.0 * (b - a * a),
                2.0 * x.z,
            );
            (v, g)
        };
        let cfg = BfgsConfig {
            max_iterations: 200,
            ..Default::default()
        };
        let r = minimize(
            f,
            DVec3::new(-1.2, 1.0, 0.5),
            DVec3::splat(-5.0),
            DVec3::splat(5.0),
            &cfg,
        );
        assert!((r.x - DVec3::new(1.0, 1.0, 0.0)).length() < 1e-3, "{:?}", r);
    }
}
