//! Head-pose synthesis throughput: the default model on 10 s of speech-like feature frames at
//! 120 Hz (voiced stretches with a moving f0 and level, unvoiced gaps), for each unvoiced
//! behaviour. Criterion reports frames per second (target ≥ 20 000 on one core). Also the cost
//! of fitting one 11-component 3-D GMM by EM on 6 000 samples.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pneuma_core::head::{EmConfig, HeadConfig, HeadModel, HeadSynth, UnvoicedBehaviour};
use pneuma_core::rng::SeededRng;
use pneuma_core::FeatureFrame;

fn frames(n: usize) -> Vec<FeatureFrame> {
    (0..n)
        .map(|i| {
            let t = i as f64 / 120.0;
            let voiced = (i / 30) % 5 != 4;
            FeatureFrame {
                index: i as u64,
                time_s: t,
                f0_hz: if voiced { 160.0 } else { 0.0 },
                voiced,
                voicing: if voiced { 0.9 } else { 0.2 },
                rms_db: -22.0,
                f0_st: if voiced {
                    (4.0 * (1.3 * t).sin() + 2.0 * (3.7 * t).sin()) as f32
                } else {
                    0.0
                },
                level_db: (3.0 * (2.1 * t).sin() - if voiced { 0.0 } else { 12.0 }) as f32,
                speech_level_db: -22.0,
                band_db: -22.0,
                bands: Default::default(),
            }
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let input = frames(1200);
    let mut group = c.benchmark_group("head_synth_10s_120hz");
    group.throughput(Throughput::Elements(input.len() as u64));
    for b in UnvoicedBehaviour::ALL {
        let cfg = HeadConfig {
            unvoiced: Some(b),
            ..HeadConfig::default()
        };
        let mut s = HeadSynth::new(HeadModel::default_model().clone(), cfg).unwrap();
        group.bench_function(BenchmarkId::from_parameter(b.as_str()), |bench| {
            bench.iter(|| {
                s.reset();
                let mut acc = 0.0f32;
                for f in &input {
                    acc += s.process(f, 120.0).pitch_deg;
                }
                acc
            })
        });
    }
    group.finish();

    let mut rng = SeededRng::new(1);
    let data: Vec<[f64; 3]> = (0..6000)
        .map(|i| {
            let k = (i % 3) as f64;
            [
                4.0 * k + rng.normal(),
                rng.normal() - k,
                0.5 * rng.normal() + k,
            ]
        })
        .collect();
    let mut em = c.benchmark_group("head_em");
    em.sample_size(10);
    em.bench_function("fit_11x3d_6000", |b| {
        b.iter(|| {
            EmConfig::new(3, 11)
                .restarts(1)
                .fit(&data)
                .unwrap()
                .mean_log_likelihood
        })
    });
    em.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
