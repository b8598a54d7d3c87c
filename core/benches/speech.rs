//! Cost of the speech decision on its own (issue 30): Silero's forward pass per 32 ms chunk
//! (`silero_chunk`), and the whole decision (resampling to 16 kHz, Silero, the cues and the
//! stacked model per analysis frame) on 10 s of audio at 16 and 48 kHz (`decision_10s`; 10 s
//! hold 312.5 chunks, so time per chunk = time / 312.5, multiples of real time = 10 s / time).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use pneuma_core::speech::silero::{Silero, CHUNK};
use pneuma_core::speech::{SpeechDetector, SpeechModel};
use pneuma_testkit::signals as test_signals;

fn bench(c: &mut Criterion) {
    let x16 = test_signals::phrases_with_pauses(16_000.0, 1.0, 30.0, 1);
    let mut chunk = [0.0f32; CHUNK];
    chunk.copy_from_slice(&x16[..CHUNK]);
    let mut silero = Silero::new();
    c.bench_function("silero_chunk", |b| b.iter(|| silero.step(&chunk)));

    let mut group = c.benchmark_group("decision_10s");
    group.sample_size(20);
    for rate in [16_000.0, 48_000.0] {
        let x = test_signals::phrases_with_pauses(rate, 10.0, 30.0, 1);
        // Frames at the engine's default 120 per second.
        let hop = (rate / 120.0) as usize;
        let mut d = SpeechDetector::new(SpeechModel::shipped().clone(), rate, 120.0);
        group.bench_with_input(BenchmarkId::from_parameter(rate as u32), &x, |b, x| {
            b.iter(|| {
                d.reset();
                let mut sum = 0.0f32;
                for frame in x.chunks(hop) {
                    d.push(frame, |_, _| {});
                    sum += d.frame(true, -30.0).speech_p;
                }
                sum
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
