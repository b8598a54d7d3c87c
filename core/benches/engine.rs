//! Throughput of the whole engine per instance (analysis, phrase tracking, breathing cycle,
//! breath sound, head pose, delay line) on 10 s of phrases with pauses, at 48 kHz with
//! 64-sample blocks (the plugin case, mono and stereo) and 512-sample blocks, in lookahead and
//! live mode. Multiples of real time = 10 s / time per iteration. Also the cost of
//! [`Engine::prepare`] at 48, 192 and 768 kHz: a plugin prepares an engine at every activation
//! and every structural change, so it must not grow with the rate.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pneuma_core::engine::{Engine, EngineConfig, PlacementMode};
use pneuma_core::head::HeadModel;
use pneuma_testkit::signals;

fn speech_like(rate: f64) -> Vec<f32> {
    signals::phrases_with_pauses(rate, 10.0, 40.0, 1)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine_10s_48k");
    group.sample_size(10);
    let rate = 48_000.0;
    let x = speech_like(rate);
    for (mode, channels, block) in [
        (PlacementMode::Lookahead, 1usize, 64usize),
        (PlacementMode::Lookahead, 2, 64),
        (PlacementMode::Live, 1, 64),
        (PlacementMode::Lookahead, 1, 512),
    ] {
        let mut config = EngineConfig::default();
        config.placement.mode = mode;
        let mut engine = Engine::new(config, HeadModel::default_model().clone()).expect("config");
        engine.prepare(rate, block, channels).expect("prepare");
        let mut bufs = vec![x.clone(); channels];
        group.throughput(Throughput::Elements(x.len() as u64));
        group.bench_function(
            BenchmarkId::new(format!("{}_{}ch", mode.as_str(), channels), block),
            |b| {
                b.iter(|| {
                    engine.reset();
                    let mut frames = 0u32;
                    let mut pos = 0;
                    while pos < x.len() {
                        let n = block.min(x.len() - pos);
                        for (buf, src) in bufs.iter_mut().zip(std::iter::repeat(&x)) {
                            buf[pos..pos + n].copy_from_slice(&src[pos..pos + n]);
                        }
                        let mut chans: Vec<&mut [f32]> =
                            bufs.iter_mut().map(|b| &mut b[pos..pos + n]).collect();
                        engine.process(&mut chans, &mut |_, _| frames += 1);
                        pos += n;
                    }
                    frames
                })
            },
        );
    }
    group.finish();
}

fn prepare(c: &mut Criterion) {
    let mut group = c.benchmark_group("engine_prepare");
    group.sample_size(10);
    let mut engine =
        Engine::new(EngineConfig::default(), HeadModel::default_model().clone()).expect("config");
    for rate in [48_000.0, 192_000.0, 768_000.0] {
        group.bench_function(BenchmarkId::from_parameter(rate), |b| {
            b.iter(|| engine.prepare(rate, 512, 2).expect("prepare"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench, prepare);
criterion_main!(benches);
