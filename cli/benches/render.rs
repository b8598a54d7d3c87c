//! Speed of a whole `pneuma render` (WAV in, engine with breaths and head pose, WAV, controls
//! CSV, breaths CSV and plot out) on the example voice brought to 48 kHz mono (25 s, resampled by
//! `pneuma_testkit`). Multiples of real time = 25.3 s / time per iteration; the target
//! is ≥ 200×.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use pneuma_cli::render::{run, Args};

fn voice_48k(dir: &std::path::Path) -> PathBuf {
    let x = pneuma_testkit::voice::example_voice_at(48_000);
    let path = dir.join("voice48.wav");
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 48_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(&path, spec).expect("create");
    for v in x {
        w.write_sample((v * 32767.0).round() as i16).expect("write");
    }
    w.finalize().expect("finalize");
    path
}

fn bench(c: &mut Criterion) {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = voice_48k(dir.path());
    let args = Args {
        inputs: vec![input.clone()],
        output: dir.path().join("out"),
        format: None,
        mp3: Default::default(),
        markers: Vec::new(),
        in_batch: false,
        jobs: None,
        preset: "neutral".into(),
        breath_level_db: -22.0,
        min_pause_ms: 250.0,
        mode: "lookahead".into(),
        lookahead_ms: Some(500.0),
        no_breaths: false,
        any_sound: false,
        channel: None,
        breath_samples: None,
        breath_mouth: None,
        breath_nose: None,
        breath_like: None,
        built_in_breath: false,
        head_model: None,
        seed: 1,
        frame_rate: 120.0,
        bvh: Default::default(),
        midi: Default::default(),
        osc: Default::default(),
        no_plot: false,
        no_overwrite: false,
        no_progress: true,
        quiet: true,
    };
    let mut group = c.benchmark_group("render_voice_25s_48k_mono");
    group.sample_size(10);
    group.bench_function("with_breaths_controls_plot", |b| {
        b.iter(|| run(&args, &input, |_| {}).expect("render").breaths.len())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
