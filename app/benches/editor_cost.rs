//! What the editor costs the audio thread: the plugin's audio-thread work (`run_block`: the
//! engine, then every frame and breath to the outputs) over the example voice (25 s, 16 kHz,
//! 256-sample blocks), with the editor's feed (1) absent, (2) present with the editor closed,
//! (3) open while a GUI thread drains it every 16 ms, as the window does.
//!
//! `cargo bench -p pneuma-app --bench editor_cost`; figures: time per pass of the 25 s voice.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion};
use pneuma_core::engine::Engine;
use pneuma_core::head::HeadModel;
use pneuma_plugin::editor::feed;
use pneuma_plugin::{run_block, Outputs, PneumaParams};
use pneuma_testkit::voice::example_voice;

const BLOCK: usize = 256;

fn engine(rate: f64) -> Engine {
    let mut e = Engine::new(
        PneumaParams::default().engine_config(),
        HeadModel::default_model().clone(),
    )
    .unwrap();
    e.prepare(rate, BLOCK, 1).unwrap();
    e
}

fn pass(
    engine: &mut Engine,
    voice: &[f32],
    buf: &mut [f32],
    mut view: Option<&mut feed::EditorFeed>,
) {
    engine.reset();
    for chunk in voice.chunks(BLOCK) {
        let b = &mut buf[..chunk.len()];
        b.copy_from_slice(chunk);
        if let Some(v) = view.as_deref_mut() {
            v.begin_block(&[&mut *b]);
        }
        run_block(
            engine,
            &mut [b],
            Outputs {
                cc: None,
                osc: None,
                view: view.as_deref_mut(),
            },
            &mut |_, _| {},
        );
    }
}

fn bench(c: &mut Criterion) {
    let (voice, rate) = example_voice();
    let rate = f64::from(rate);
    let mut buf = vec![0.0f32; BLOCK];
    let mut g = c.benchmark_group("audio thread, 25 s example voice");
    g.sample_size(10).measurement_time(Duration::from_secs(20));

    let mut e = engine(rate);
    g.bench_function("no editor feed", |b| {
        b.iter(|| pass(&mut e, &voice, &mut buf, None))
    });

    let (mut f, _shared) = feed::channel();
    g.bench_function("editor closed", |b| {
        b.iter(|| pass(&mut e, &voice, &mut buf, Some(&mut f)))
    });

    let (mut f, shared) = feed::channel();
    shared.open.store(true, Ordering::Relaxed);
    let stop = Arc::new(AtomicBool::new(false));
    let gui = std::thread::spawn({
        let (shared, stop) = (shared.clone(), stop.clone());
        move || {
            let (mut frames, mut breaths) = (0u64, 0u64);
            while !stop.load(Ordering::Relaxed) {
                shared.drain(|_| frames += 1, |_| breaths += 1);
                std::thread::sleep(Duration::from_millis(16));
            }
            frames + breaths
        }
    });
    g.bench_function("editor open, GUI draining", |b| {
        b.iter(|| pass(&mut e, &voice, &mut buf, Some(&mut f)))
    });
    stop.store(true, Ordering::Relaxed);
    let drained = gui.join().unwrap();
    assert!(drained > 0, "the GUI side received the frames");
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
