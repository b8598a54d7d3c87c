//! Throughput of the whole analysis front end (decimation, NSDF pitch, level, voicing, speaker
//! normalisation) on 10 s of a jittered glottal vowel with pauses, at 44.1 and 48 kHz (and
//! 16/192 kHz for scale) with 64- and 512-sample blocks. Criterion reports time per 10 s of
//! audio and samples per second; multiples of real time = 10 s / time.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use pneuma_core::synth::{self, GlottalVowel, Vowel};
use pneuma_core::{AnalysisConfig, Analyzer};

fn speech_like(rate: f64) -> Vec<f32> {
    let cfg = GlottalVowel {
        sample_rate_hz: rate,
        length_s: 10.0,
        vowel: Vowel::A,
        jitter: 0.01,
        shimmer: 0.05,
        peak: 0.5,
        seed: 1,
    };
    // 1.5 s phrases separated by 0.5 s pauses, f0 wandering 100–200 Hz.
    let mut x = synth::glottal_vowel(&cfg, |t| {
        if t % 2.0 < 1.5 {
            150.0 + 50.0 * (1.3 * t).sin()
        } else {
            0.0
        }
    });
    synth::add_white_noise(&mut x, 30.0, 2);
    x
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("analysis_10s");
    group.sample_size(20);
    for rate in [44_100.0, 48_000.0, 16_000.0, 192_000.0] {
        let x = speech_like(rate);
        for block in [64usize, 512] {
            if (rate == 16_000.0 || rate == 192_000.0) && block == 64 {
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
