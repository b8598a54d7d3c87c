//! Figures the evaluations share: the median, the Pearson correlation and the Spearman rank
//! correlation, the mean power, RMS and RMS level of audio, and the overlap of time spans.

/// Median of the finite values of `v` (NaN when there are none).
pub fn median(v: &[f64]) -> f64 {
    let finite: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if finite.is_empty() {
        f64::NAN
    } else {
        pneuma_core::head::metrics::median(finite)
    }
}

/// Ranks (1-based, ties get their mean rank).
fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    let mut i = 0;
    while i < idx.len() {
        let mut j = i;
        while j + 1 < idx.len() && v[idx[j + 1]] == v[idx[i]] {
            j += 1;
        }
        let mean = (i + j) as f64 / 2.0 + 1.0;
        for &k in &idx[i..=j] {
            r[k] = mean;
        }
        i = j + 1;
    }
    r
}

/// Spearman rank correlation of `x` and `y` (NaN with fewer than 3 pairs or a constant side).
pub fn spearman(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    if n < 3 {
        return f64::NAN;
    }
    pearson(&ranks(&x[..n]), &ranks(&y[..n]))
}

/// Pearson correlation of `x` and `y` over their common length (NaN with fewer than 3 pairs
/// or a constant side).
pub fn pearson(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    if n < 3 {
        return f64::NAN;
    }
    let (mx, my) = (
        x[..n].iter().sum::<f64>() / n as f64,
        y[..n].iter().sum::<f64>() / n as f64,
    );
    let (mut sxy, mut sxx, mut syy) = (0.0, 0.0, 0.0);
    for (a, b) in x[..n].iter().zip(&y[..n]) {
        let (a, b) = (a - mx, b - my);
        sxy += a * b;
        sxx += a * a;
        syy += b * b;
    }
    if sxx > 0.0 && syy > 0.0 {
        sxy / (sxx * syy).sqrt()
    } else {
        f64::NAN
    }
}

/// RMS level in dBFS of `x` (−120 for silence).
pub fn rms_db(x: &[f32]) -> f64 {
    if x.is_empty() {
        return -120.0;
    }
    let p = x.iter().map(|v| (*v as f64).powi(2)).sum::<f64>() / x.len() as f64;
    (10.0 * p.max(1e-12).log10()).max(-120.0)
}

/// Mean power (mean square) of `x` (0 for no samples).
pub fn power(x: &[f32]) -> f64 {
    x.iter().map(|&v| v as f64 * v as f64).sum::<f64>() / x.len().max(1) as f64
}

/// RMS of `x` (0 for no samples): the analysis's own.
pub use pneuma_core::analysis::rms;

/// Whether two time spans (start, end) share some time.
pub fn overlaps(a: (f64, f64), b: (f64, f64)) -> bool {
    a.0 < b.1 && b.0 < a.1
}

/// The time two spans (start, end) share, seconds (0 when none).
pub fn overlap_s(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.1.min(b.1) - a.0.max(b.0)).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pearson_sees_a_shifted_copy_as_one_and_a_mirror_as_minus_one() {
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * 0.3).sin()).collect();
        let up: Vec<f64> = x.iter().map(|v| 2.0 * v + 1.0).collect();
        let down: Vec<f64> = x.iter().map(|v| -v).collect();
        assert!((pearson(&x, &up) - 1.0).abs() < 1e-12);
        assert!((pearson(&x, &down) + 1.0).abs() < 1e-12);
        assert!(pearson(&x, &[1.0; 50]).is_nan());
    }

    #[test]
    fn spearman_of_monotone_and_reversed_data() {
        let x = [0.1, 0.5, 0.2, 0.9, 0.4];
        let up = [1.0, 8.0, 2.0, 30.0, 5.0];
        assert!((spearman(&x, &up) - 1.0).abs() < 1e-12);
        let down: Vec<f64> = up.iter().map(|v| -v).collect();
        assert!((spearman(&x, &down) + 1.0).abs() < 1e-12);
        // Ties share their rank: 1, 2.5, 2.5, 4 against 1, 2, 3, 4.
        let r = spearman(&[1.0, 2.0, 2.0, 3.0], &[1.0, 2.0, 3.0, 4.0]);
        assert!((r - 4.5 / 22.5f64.sqrt()).abs() < 1e-12, "{r}");
    }

    #[test]
    fn medians_power_and_overlaps() {
        assert_eq!(median(&[3.0, f64::NAN, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[f64::NAN]).is_nan());
        assert_eq!(power(&[3.0, -1.0]), 5.0);
        assert_eq!(rms(&[]), 0.0);
        assert!((rms_db(&[0.1, -0.1]) + 20.0).abs() < 1e-6);
        assert_eq!(rms_db(&[]), -120.0);
        assert!(overlaps((1.0, 2.0), (1.5, 3.0)) && !overlaps((1.0, 2.0), (2.0, 3.0)));
        assert_eq!(overlap_s((1.0, 2.0), (1.5, 3.0)), 0.5);
        assert_eq!(overlap_s((1.0, 2.0), (2.5, 3.0)), 0.0);
    }
}
