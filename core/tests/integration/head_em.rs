//! EM recovers known mixtures from seeded samples: weights, means and covariances of a
//! three-component 3-D mixture with correlated covariances, and it is deterministic per seed.

use pneuma_core::head::{EmConfig, Gaussian, Gmm};
use pneuma_core::rng::SeededRng;

fn truth() -> Gmm {
    let c = |weight, mean, cov| Gaussian { weight, mean, cov };
    Gmm::new(
        3,
        &[
            c(
                0.5,
                [0.0, 0.0, 0.0],
                [[1.0, 0.6, 0.0], [0.6, 2.0, 0.3], [0.0, 0.3, 0.5]],
            ),
            c(
                0.3,
                [8.0, -5.0, 2.0],
                [[0.5, 0.0, 0.1], [0.0, 0.5, 0.0], [0.1, 0.0, 1.5]],
            ),
            c(
                0.2,
                [-6.0, 6.0, -4.0],
                [[2.0, -0.8, 0.0], [-0.8, 1.0, 0.0], [0.0, 0.0, 0.3]],
            ),
        ],
    )
    .unwrap()
}

fn samples(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let g = truth();
    let mut rng = SeededRng::new(seed);
    (0..n).map(|_| g.sample(&mut rng)).collect()
}

#[test]
fn recovers_a_known_three_component_mixture() {
    let data = samples(6000, 11);
    let fit = EmConfig::new(3, 3).seed(5).fit(&data).unwrap();
    let t = truth();
    for want in t.components() {
        // Match by nearest mean.
        let got = fit
            .gmm
            .components()
            .min_by(|a, b| {
                let d = |g: &Gaussian| {
                    (0..3)
                        .map(|i| (g.mean[i] - want.mean[i]).powi(2))
                        .sum::<f64>()
                };
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        assert!(
            (got.weight - want.weight).abs() < 0.03,
            "weight {} vs {}",
            got.weight,
            want.weight
        );
        for i in 0..3 {
            assert!(
                (got.mean[i] - want.mean[i]).abs() < 0.12,
                "mean {:?} vs {:?}",
                got.mean,
                want.mean
            );
            for j in 0..3 {
                let tol = 0.15 * (want.cov[i][i] * want.cov[j][j]).sqrt() + 0.02;
                assert!(
                    (got.cov[i][j] - want.cov[i][j]).abs() < tol,
                    "cov[{i}][{j}] {} vs {}",
                    got.cov[i][j],
                    want.cov[i][j]
                );
            }
        }
    }
    // The fit explains the data about as well as the truth does.
    let truth_ll = data.iter().map(|x| t.log_pdf(x)).sum::<f64>() / data.len() as f64;
    assert!(
        fit.mean_log_likelihood > truth_ll - 0.01,
        "{} vs {truth_ll}",
        fit.mean_log_likelihood
    );
}

#[test]
fn recovers_a_one_dimensional_mixture_and_is_deterministic() {
    let mut rng = SeededRng::new(3);
    let data: Vec<[f64; 3]> = (0..4000)
        .map(|i| {
            let x = if i % 4 == 0 {
                10.0 + 0.5 * rng.normal()
            } else {
                -2.0 + rng.normal()
            };
            [x, 0.0, 0.0]
        })
        .collect();
    let a = EmConfig::new(1, 2).seed(9).fit(&data).unwrap();
    let b = EmConfig::new(1, 2).seed(9).fit(&data).unwrap();
    assert_eq!(a, b);
    let mut comps: Vec<&Gaussian> = a.gmm.components().collect();
    comps.sort_by(|x, y| x.mean[0].total_cmp(&y.mean[0]));
    assert!((comps[0].mean[0] + 2.0).abs() < 0.08 && (comps[1].mean[0] - 10.0).abs() < 0.08);
    assert!((comps[1].weight - 0.25).abs() < 0.02);
    assert!((comps[0].cov[0][0] - 1.0).abs() < 0.1 && (comps[1].cov[0][0] - 0.25).abs() < 0.05);
}
