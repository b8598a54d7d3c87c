//! Throughput of the whole analysis front end (decimation, NSDF pitch, level, voicing, speaker
//! normalisation) on 10 s of a jittered glottal vowel with pauses, at 44.1 and 48 kHz (and
//! 16/192/768 kHz for scale) with 64- and 512-sample blocks. Criterion reports time per 10 s of
//! audio and samples per second; multiples of real time = 10 s / time.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pneuma_core::{AnalysisConfig, Analyzer};
use pneuma_testkit::signals;

fn speech_like(rate: f64) -> Vec<f32> {
    signals::phrases_with_pauses(rate, 10.0, 30.0, 1)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("analysis_10s");
    group.sample_size(20);
    for rate in [44_100.0, 48_000.0, 16_000.0, 192_000.0, 768_000.0] {
        let x = speech_like(rate);
        for block in [64usize, 512] {
            if (rate == 16_000.0 || rate >= 192_000.0) && block == 64 {
                continue;
            }
            group.throughput(Throughput::Elements(x.len() as u64));
            let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
            a.prepare(rate, block).expect("rate");
            group.bench_with_input(
                BenchmarkId::new(format!("{}Hz", rate as u32), block),
                &x,
                |b, x| {
                    b.iter(|| {
                        a.reset();
                        let mut voiced = 0u32;
                        for chunk in x.chunks(block) {
                            a.process(chunk, |f| voiced += u32::from(f.voiced))
                                .expect("prepared");
                        }
                        voiced
                    })
                },
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
