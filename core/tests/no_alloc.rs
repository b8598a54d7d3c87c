//! `process` and `finish` never allocate, at any rate and block size: a counting global
//! allocator watches the thread while the analyzer runs.

use pneuma_core::test_signals;
use pneuma_core::{AnalysisConfig, Analyzer};

mod support;
use support::watched;

#[test]
fn the_counter_sees_allocations() {
    let (_, n) = watched(|| vec![1u8; 100]);
    assert!(n >= 1);
}

#[test]
fn process_never_allocates() {
    for rate in [
        8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0,
    ] {
        let mut x =
            test_signals::harmonic_tone(rate, 1.0, 0.5, &[1.0, 0.5, 0.3], |t| 100.0 + 200.0 * t);
        x[1000] = f32::NAN;
        let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
        a.prepare(rate, 4096).expect("rate");
        let mut frames = 0usize;
        let ((), n) = watched(|| {
            for (i, size) in [1usize, 37, 512, 4096].iter().cycle().enumerate() {
                let start = (i * 1000) % (x.len() - 4096);
                a.process(&x[start..start + size], |_| frames += 1)
                    .expect("prepared");
                if i > 200 {
                    break;
                }
            }
            a.finish(|_| frames += 1).expect("prepared");
            a.reset();
        });
        assert!(frames > 10);
        assert_eq!(n, 0, "{n} allocations at {rate} Hz");
    }
}

/// Phrases with pauses at `rate`: 0.8 s voiced, 0.6 s silence, repeated.
fn phrases(rate: f64, seconds: f64) -> Vec<f32> {
    let mut x = test_signals::harmonic_tone(rate, seconds, 0.4, &[1.0, 0.6, 0.4, 0.2], |t| {
        if t % 1.4 < 0.8 {
            120.0 + 30.0 * (2.0 * t).sin()
        } else {
            0.0
        }
    });
    x[777] = f32::NAN;
    x[1234] = f32::INFINITY;
    x
}

#[test]
fn the_engine_never_allocates_while_processing() {
    use pneuma_core::engine::{Engine, EngineConfig, PlacementMode};
    use pneuma_core::head::HeadModel;
    for (rate, channels, mode) in [
        (44_100.0, 1usize, PlacementMode::Lookahead),
        (48_000.0, 2, PlacementMode::Lookahead),
        (16_000.0, 1, PlacementMode::Live),
        (96_000.0, 2, PlacementMode::Live),
    ] {
        let x = phrases(rate, 4.5);
        let mut config = EngineConfig::default();
        config.placement.mode = mode;
        let mut engine = Engine::new(config, HeadModel::default_model().clone()).expect("config");
        engine.prepare(rate, 1024, channels).expect("prepare");
        let mut bufs = vec![x.clone(); channels];
        let mut frames = 0usize;
        let mut breaths = 0usize;
        let ((), n) = watched(|| {
            let mut pos = 0;
            for size in [1usize, 37, 512, 1024, 3000].iter().cycle() {
                if pos >= x.len() {
                    break;
                }
                let size = (*size).min(x.len() - pos);
                let (a, b) = bufs.split_at_mut(1);
                let mut chans: [&mut [f32]; 2] = match b.first_mut() {
                    Some(r) => [&mut a[0][pos..pos + size], &mut r[pos..pos + size]],
                    None => [&mut a[0][pos..pos + size], &mut []],
                };
                engine.process(&mut chans[..channels], &mut |_, _| frames += 1);
                engine.take_breaths(|_| breaths += 1);
                pos += size;
            }
            engine.finish();
            engine.take_breaths(|_| breaths += 1);
            engine.reset();
        });
        assert!(frames > 100, "{frames} frames");
        assert!(breaths >= 1, "no breath inserted at {rate} Hz");
        assert_eq!(
            n, 0,
            "{n} allocations at {rate} Hz, {channels} ch, {mode:?}"
        );
    }
}
