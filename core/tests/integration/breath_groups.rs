//! Breath-group planning on generated phrase sequences: long runs of short pauses never run the
//! lung dry (catch breaths in the short pauses, never on speech), a 2 s pause gets a longer
//! breath from an offline render (whole-file lookahead) than with the plugin's 0.5 s lookahead,
//! and both stay independent of the block partition.

use pneuma_core::engine::offline::{self, Rendered};
use pneuma_core::engine::{Engine, EngineConfig};
use pneuma_core::head::HeadModel;

use crate::generated_phrases::{sequence, SR};

/// The lung counts as empty under this volume (as in `pneuma eval breaths`).
const EMPTY_LUNG: f32 = 0.05;

fn render(config: &EngineConfig, audio: &[f32], blocks: &[usize]) -> Rendered {
    let mut engine = Engine::new(config.clone(), HeadModel::default_model().clone()).unwrap();
    engine
        .prepare(SR, blocks.iter().copied().max().unwrap(), 1)
        .unwrap();
    offline::render(&mut engine, &[audio.to_vec()], blocks)
}

/// The plugin's settings (0.5 s lookahead) or an offline render's (whole-file lookahead).
fn config(whole_file: bool) -> EngineConfig {
    let mut c = EngineConfig::default();
    c.placement.whole_file = whole_file;
    c
}

/// 24 phrases of 1.1–1.5 s in runs of short pauses: mostly 0.1 s (too short for any breath),
/// every third 0.24 s (under the 0.25 s minimum pause, room for a catch breath).
fn short_pause_runs() -> (Vec<f32>, Vec<(f64, f64)>, Vec<f64>) {
    let phrases: Vec<f64> = (0..24).map(|i| 1.1 + 0.1 * (i % 5) as f64).collect();
    let pauses: Vec<f64> = (0..23)
        .map(|i| if i % 3 == 2 { 0.24 } else { 0.1 })
        .collect();
    let (audio, spans) = sequence(0.6, &phrases, &pauses);
    (audio, spans, pauses)
}

#[test]
fn long_runs_of_short_pauses_never_run_the_lung_dry() {
    let (audio, spans, pauses) = short_pause_runs();
    let speech_s: f64 = spans.iter().map(|s| s.1 - s.0).sum();
    assert!(speech_s > 25.0, "{speech_s} s of speech");
    for whole_file in [false, true] {
        let r = render(&config(whole_file), &audio, &[512]);
        // The lung is never empty inside a phrase (away from the onset edge).
        let empty: Vec<f64> = r
            .frames
            .iter()
            .map(|f| &f.0)
            .filter(|f| {
                spans
                    .iter()
                    .any(|&(on, off)| f.time_s >= on + 0.05 && f.time_s < off)
            })
            .filter(|f| f.breathing.lung < EMPTY_LUNG)
            .map(|f| f.time_s)
            .collect();
        assert!(
            empty.is_empty(),
            "whole file {whole_file}: lung empty while speaking at {} frames from {:?} s",
            empty.len(),
            empty.first()
        );
        // Catch breaths went into the 0.24 s pauses, inside them and never on speech.
        let catch: Vec<_> = r
            .breaths
            .iter()
            .filter(|b| b.start_s > spans[0].0)
            .collect();
        assert!(
            catch.len() >= 3,
            "whole file {whole_file}: {} catch breaths: {:?}",
            catch.len(),
            r.breaths
        );
        for b in &catch {
            let k = spans
                .iter()
                .position(|&(_, off)| off <= b.start_s + 1e-9 && b.start_s < off + 0.3)
                .unwrap_or_else(|| panic!("{b:?} is in no pause"));
            let (off, next_on) = (spans[k].1, spans[k + 1].0);
            assert!(
                pauses[k] > 0.2 && b.start_s >= off && b.end_s <= next_on,
                "whole file {whole_file}: {b:?} not inside the {:.2} s pause {off:.3}..{next_on:.3}",
                pauses[k]
            );
            let length_s = b.end_s - b.start_s;
            assert!(
                (0.1..=0.26).contains(&length_s),
                "whole file {whole_file}: a catch breath of {length_s:.3} s"
            );
        }
    }
}

#[test]
fn a_two_second_pause_gets_a_longer_breath_offline_than_with_the_plugin_lookahead() {
    let (audio, spans) = sequence(0.6, &[2.0, 3.0], &[2.0]);
    let in_pause = |r: &Rendered| {
        let v: Vec<(f64, f64)> = r
            .breaths
            .iter()
            .filter(|b| b.start_s >= spans[0].1 && b.end_s <= spans[1].0)
            .map(|b| (b.start_s, b.end_s))
            .collect();
        assert_eq!(v.len(), 1, "one breath in the 2 s pause: {:?}", r.breaths);
        v[0]
    };
    let plugin = in_pause(&render(&config(false), &audio, &[512]));
    let offline = in_pause(&render(&config(true), &audio, &[512]));
    let (plugin_s, offline_s) = (plugin.1 - plugin.0, offline.1 - offline.0);
    eprintln!(
        "breath in a 2 s pause: {plugin_s:.3} s with 0.5 s lookahead, {offline_s:.3} s offline"
    );
    // The plugin sees the onset only half a second ahead; the offline render sees the pause.
    assert!(plugin_s <= 0.5, "plugin breath {plugin_s:.3} s");
    assert!(
        offline_s >= plugin_s + 0.15 && offline_s >= 0.6,
        "offline breath {offline_s:.3} s, plugin {plugin_s:.3} s"
    );
    // Both end just before the onset.
    for (a, b) in [plugin, offline] {
        assert!(b <= spans[1].0 - 0.02 && b >= spans[1].0 - 0.12, "{a}..{b}");
    }
}

#[test]
fn whole_file_and_catch_breath_renders_are_independent_of_the_block_partition() {
    let (audio, _, _) = short_pause_runs();
    let audio = &audio[..(12.0 * SR) as usize];
    for whole_file in [false, true] {
        let c = config(whole_file);
        let reference = render(&c, audio, &[4096]);
        assert!(reference.breaths.len() >= 2, "{:?}", reference.breaths);
        for blocks in [vec![1, 700], vec![37], vec![333, 5, 1024]] {
            let r = render(&c, audio, &blocks);
            assert_eq!(
                r.audio, reference.audio,
                "whole file {whole_file} {blocks:?}"
            );
            assert_eq!(r.breaths, reference.breaths);
            let a: Vec<_> = r.frames.iter().map(|f| f.0).collect();
            let b: Vec<_> = reference.frames.iter().map(|f| f.0).collect();
            assert_eq!(a, b, "whole file {whole_file} {blocks:?}");
        }
    }
}
