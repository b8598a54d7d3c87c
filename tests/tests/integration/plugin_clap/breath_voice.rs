//! A frozen breath voice survives save and reload (issue 31): a speaker who breathes is learned
//! through the built plugin, the freeze switch keeps that voice, and a state saved then and
//! loaded into a fresh instance plays the same breaths, bit for bit, as the instance that froze
//! it, every playback; a fresh instance that did not learn plays other breaths.

use pneuma_testkit::signals;
use pneuma_tests::host::Plugin;

use super::load;

const RATE_HZ: f64 = 48_000.0;
const BLOCK: usize = 512;

/// Plays `signal` (mono) with the transport rolling from `start` samples; the output.
fn play_from(plugin: &mut Plugin, signal: &[f32], start: usize) -> Vec<f32> {
    let mut out = Vec::with_capacity(signal.len());
    for (i, chunk) in signal.chunks(BLOCK).enumerate() {
        let mut audio = [chunk.to_vec()];
        let pos_s = (start + i * BLOCK) as f64 / RATE_HZ;
        plugin.process_at(&mut audio, Some(pos_s));
        out.extend_from_slice(&audio[0]);
    }
    out
}

/// A playback from the start of the timeline (the stream restarts).
fn play(plugin: &mut Plugin, signal: &[f32]) -> Vec<f32> {
    play_from(plugin, signal, 0)
}

fn same_bits(a: &[f32], b: &[f32]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// An instance with breaths into every pause (the generated speaker's sustained vowels are not
/// speech to the speech decision), activated mono.
fn activated(plugin: &mut Plugin) {
    plugin.set_param("speech_only", "Off").unwrap();
    plugin.activate(RATE_HZ, BLOCK, 1).unwrap();
}

#[test]
fn a_frozen_breath_voice_survives_save_and_reload_and_plays_the_same_every_time() {
    let breathing = signals::phrases_with_breaths(RATE_HZ, 16.0, 5);
    let breathless = signals::phrases_with_pauses(RATE_HZ, 10.0, 60.0, 5);

    let mut a = load();
    activated(&mut a);
    play(&mut a, &breathing);
    a.set_param("freeze_breath_voice", "On").unwrap();
    // The switch arrives with this block; the stream goes on (no jump).
    play_from(&mut a, &breathless[..BLOCK], breathing.len());
    let state = a.save_state();
    let json: serde_json::Value =
        serde_json::from_str(Plugin::state_json(&state)).expect("the state is JSON");
    let saved: serde_json::Value = serde_json::from_str(
        json["fields"]["breath_voice"]
            .as_str()
            .expect("saved voice"),
    )
    .expect("the saved voice is JSON");
    let breaths = saved["learned"]["breaths"].as_u64().unwrap_or(0);
    assert!(breaths >= 4, "a learned voice is saved: {saved}");

    let before = play(&mut a, &breathless);
    assert!(
        same_bits(&before, &play(&mut a, &breathless)),
        "two playbacks of the frozen voice differ"
    );

    let mut b = load();
    b.load_state(&state).unwrap();
    activated(&mut b);
    let reloaded = play(&mut b, &breathless);
    assert!(
        same_bits(&reloaded, &before),
        "the reloaded voice plays otherwise"
    );
    assert!(
        same_bits(&play(&mut b, &breathless), &before),
        "a second playback after the reload differs"
    );
    // Saved again, the same voice.
    let resaved = b.save_state();
    let json_again: serde_json::Value =
        serde_json::from_str(Plugin::state_json(&resaved)).expect("the state is JSON");
    assert_eq!(
        json_again["fields"]["breath_voice"],
        json["fields"]["breath_voice"]
    );

    // Without the frozen voice the breaths are the built-in ones: the state carried the voice.
    let mut fresh = load();
    activated(&mut fresh);
    assert!(
        !same_bits(&play(&mut fresh, &breathless), &before),
        "the frozen voice plays like the built-in one"
    );
}
