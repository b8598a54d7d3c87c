//! Live placement on the example voice, judged against the speech the same tracker finds in
//! lookahead mode (where the speaking flag is exact): no breath sound over speech beyond the
//! first `live_fade_s` of an onset, the minimum pause respected, no inspiration while speaking,
//! no inaudible stubs reported.

mod example_voice;

use example_voice::example_voice;
use pneuma_core::engine::offline::{self, Rendered};
use pneuma_core::engine::{Engine, EngineConfig, PlacementMode};
use pneuma_core::head::HeadModel;
use pneuma_core::Phase;

fn render(config: &EngineConfig, audio: &[f32], sample_rate_hz: f64) -> Rendered {
    let mut engine = Engine::new(config.clone(), HeadModel::default_model().clone()).unwrap();
    engine.prepare(sample_rate_hz, 512, 1).unwrap();
    offline::render(&mut engine, &[audio.to_vec()], &[512])
}

fn config(mode: PlacementMode, min_pause_s: f32) -> EngineConfig {
    let mut c = EngineConfig::default();
    c.placement.mode = mode;
    c.placement.min_pause_s = min_pause_s;
    c
}

/// The (start, end) seconds of every run of frames flagged speaking.
fn speech_spans(r: &Rendered) -> Vec<(f64, f64)> {
    let dt = r.frames.get(1).map_or(0.01, |f| f.0.time_s - r.frames[0].0.time_s);
    let mut spans: Vec<(f64, f64)> = Vec::new();
    let mut open: Option<f64> = None;
    for (f, _) in &r.frames {
        match (f.speaking, open) {
            (true, None) => open = Some(f.time_s),
            (false, Some(s)) => {
                spans.push((s, f.time_s));
                open = None;
            }
            _ => {}
        }
    }
    if let (Some(s), Some(last)) = (open, r.frames.last()) {
        spans.push((s, last.0.time_s + dt));
    }
    spans
}

#[test]
fn live_breaths_stay_off_speech_and_respect_the_minimum_pause() {
    let (voice, sr) = example_voice();
    let reference = render(&config(PlacementMode::Lookahead, 0.25), &voice, sr);
    let speech = speech_spans(&reference);
    assert!(speech.len() >= 5, "{speech:?}");
    for min_pause_s in [0.25f32, 1.0] {
        let c = config(PlacementMode::Live, min_pause_s);
        let fade_s = c.placement.live_fade_s as f64;
        let live = render(&c, &voice, sr);
        // Breath sound (output minus input) over speech, past each onset's first fade.
        let mut over_speech = Vec::new();
        for &(on, off) in &speech {
            let from = ((on + fade_s) * sr).ceil() as usize;
            let to = ((off * sr) as usize).min(voice.len());
            if let Some(k) = (from..to).rfind(|&i| live.audio[0][i] != voice[i]) {
                over_speech.push((on, k as f64 / sr));
            }
        }
        assert!(
            over_speech.is_empty(),
            "min pause {min_pause_s}: breath over speech (onset, last sample): {over_speech:?}"
        );
        for b in &live.breaths {
            // The speech before the breath ended at least the minimum pause earlier.
            let prev_off = speech
                .iter()
                .map(|s| s.1)
                .filter(|&off| off <= b.start_s)
                .fold(0.0f64, f64::max);
            assert!(
                prev_off == 0.0 || b.start_s - prev_off >= min_pause_s as f64 - 0.02,
                "min pause {min_pause_s}: {b:?} starts {:.3} s after speech ended",
                b.start_s - prev_off
            );
            assert!(b.peak_db >= -60.0, "inaudible stub reported: {b:?}");
        }
        let inspiring_while_speaking: Vec<f64> = live
            .frames
            .iter()
            .map(|f| &f.0)
            .filter(|f| f.breathing.phase == Phase::Inspiration)
            .filter(|f| {
                f.speaking
                    || speech
                        .iter()
                        .any(|&(on, off)| f.time_s >= on + fade_s && f.time_s < off)
            })
            .map(|f| f.time_s)
            .collect();
        assert!(
            inspiring_while_speaking.is_empty(),
            "min pause {min_pause_s}: inspiration while speaking at {inspiring_while_speaking:?}"
        );
        eprintln!(
            "min pause {min_pause_s}: live {} breaths, lookahead {}",
            live.breaths.len(),
            reference.breaths.len()
        );
    }
}

#[test]
fn a_longer_minimum_pause_means_fewer_live_breaths() {
    let (voice, sr) = example_voice();
    let short = render(&config(PlacementMode::Live, 0.25), &voice, sr);
    let long = render(&config(PlacementMode::Live, 1.0), &voice, sr);
    assert!(!long.breaths.is_empty());
    assert!(
        long.breaths.len() < short.breaths.len(),
        "{} breaths with 1 s, {} with 0.25 s",
        long.breaths.len(),
        short.breaths.len()
    );
}
