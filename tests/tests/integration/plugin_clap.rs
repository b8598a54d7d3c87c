//! The built `Pneuma.clap` through a real CLAP host (clack-host): parameters and their stable
//! ids, any sample rate and block size, MIDI CC output, state, latency, NaN and silence.
//!
//! The plugin is the library cargo built for this test run (or `PNEUMA_CLAP`); see
//! `pneuma_tests::bundle`.

use pneuma_testkit::voice::example_voice_at;
use pneuma_tests::bundle::plugin_path;
use pneuma_tests::host::{param_hash, CcEvent, Plugin};

mod breath_voice;
mod engine_seam;
mod plugin_state;

const CLAP_ID: &str = "org.pneuma.pneuma";

/// The promised parameter ids (saved in host projects: they never change).
const PARAM_IDS: &[&str] = &[
    "bypass",
    "preset",
    "thorax_vs_abdomen",
    "capacity_lung",
    "mouth_vs_nose",
    "breath_sound",
    "opening",
    "speaking_loudness",
    "inspiration_length_s",
    "neck_amplitude_deg",
    "breath_level_db",
    "insert_breaths",
    "freeze_breath_voice",
    "speech_only",
    "min_pause_s",
    "mode",
    "lookahead_s",
    "head_amount",
    "head_max_pitch_deg",
    "head_max_yaw_deg",
    "head_max_roll_deg",
    "frame_rate_hz",
    "midi_enabled",
    "midi_channel",
    "cc_14bit",
    "cc_head_range_deg",
    "cc_lung",
    "cc_head_pitch",
    "cc_head_yaw",
    "cc_head_roll",
    "cc_thorax",
    "cc_abdomen",
    "cc_nostril_flare",
    "cc_mouth_open",
    "cc_neck_pitch",
    "cc_speaking",
    "cc_loudness",
    "osc_enabled",
    "osc_port",
    "osc_format",
];

fn load() -> Plugin {
    Plugin::load(&plugin_path(), CLAP_ID).expect("the bundle loads")
}

/// Deterministic block sizes: `pattern` 0 = random 1..=512, else a fixed size.
fn block_sizes(total: usize, pattern: usize, seed: u64) -> Vec<usize> {
    let mut state = seed;
    let mut out = Vec::new();
    let mut left = total;
    while left > 0 {
        let n = if pattern == 0 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            1 + ((state >> 33) % 512) as usize
        } else {
            pattern
        };
        let n = n.min(left);
        out.push(n);
        left -= n;
    }
    out
}

/// Runs `signal` (mono) through `plugin` in the given blocks; returns output and CC events.
fn run(plugin: &mut Plugin, signal: &[f32], blocks: &[usize]) -> (Vec<f32>, Vec<CcEvent>) {
    let mut out = Vec::with_capacity(signal.len());
    let mut events = Vec::new();
    let mut pos = 0;
    for &n in blocks {
        let mut block = vec![signal[pos..pos + n].to_vec()];
        for e in plugin.process(&mut block) {
            assert!(
                (e.offset as usize) < n,
                "offset {} in a block of {n}",
                e.offset
            );
            events.push(e);
        }
        out.extend_from_slice(&block[0]);
        pos += n;
    }
    (out, events)
}

#[test]
fn parameters_carry_the_promised_ids() {
    let mut plugin = load();
    let params = plugin.params();
    let host_ids: Vec<u32> = params.iter().map(|p| p.id).collect();
    let want: Vec<u32> = PARAM_IDS.iter().map(|id| param_hash(id)).collect();
    assert_eq!(host_ids, want, "parameter ids as the host sees them");
    let names: Vec<&str> = params.iter().map(|p| p.name.as_str()).collect();
    assert!(names.contains(&"Breath level"), "{names:?}");
    // Filed in modules (folders in the host's generic view), bypass at the top.
    let module = |id: &str| {
        params
            .iter()
            .find(|p| p.id == param_hash(id))
            .map(|p| p.module.as_str())
            .unwrap()
    };
    assert_eq!(module("bypass"), "");
    assert_eq!(module("mode"), "Breaths & timing");
    assert_eq!(module("cc_loudness"), "MIDI CC");
    assert_eq!(module("frame_rate_hz"), "Analysis");
    assert_eq!(module("osc_format"), "OSC");
    assert!(names.contains(&"OSC port"), "{names:?}");
    // A value set through the host reads back.
    plugin.set_param("osc_port", "9001").unwrap();
    let v = plugin.param_value("osc_port").unwrap();
    let info = params
        .iter()
        .find(|p| p.id == param_hash("osc_port"))
        .unwrap();
    assert!(v != info.default, "osc_port changed from its default");
}

/// Asserts two runs gave the same audio bit for bit and the same CC events at the same absolute
/// samples (their offsets depend on the block boundaries); `what` names the run.
fn assert_same_output(
    (out, events): (&[f32], &[CcEvent]),
    (ref_out, ref_events): &(Vec<f32>, Vec<CcEvent>),
    what: &str,
) {
    assert!(
        out.len() == ref_out.len()
            && out
                .iter()
                .zip(ref_out)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
        "audio differs with {what}"
    );
    let key = |e: &CcEvent| (e.sample, e.channel, e.controller, e.value);
    let first_diff = events
        .iter()
        .zip(ref_events)
        .position(|(a, b)| key(a) != key(b));
    assert!(
        first_diff.is_none() && events.len() == ref_events.len(),
        "CC events differ with {what}: {} vs {} events, first difference at {first_diff:?}: \
         {:?} vs {:?}",
        events.len(),
        ref_events.len(),
        first_diff.map(|i| events[i]),
        first_diff.map(|i| ref_events[i]),
    );
}

/// Live mode (no latency: a control frame goes out in the block that completes it) gives the
/// same audio and CC events in any block partition too.
#[test]
fn live_mode_gives_the_same_output_in_any_block_partition() {
    let rate = 48_000.0;
    let voice = example_voice_at(48_000);
    let voice = &voice[..48_000 * 10];
    let mut reference: Option<(Vec<f32>, Vec<CcEvent>)> = None;
    for (pattern, seed) in [(512, 0), (37, 0), (0, 7)] {
        let mut plugin = load();
        plugin.set_param("mode", "Live").unwrap();
        plugin.activate(rate, 512, 1).unwrap();
        assert_eq!(plugin.latency(), 0, "live mode from the activation");
        let (out, events) = run(&mut plugin, voice, &block_sizes(voice.len(), pattern, seed));
        assert!(!events.is_empty(), "live mode sends CC");
        match &reference {
            None => reference = Some((out, events)),
            Some(r) => assert_same_output(
                (&out, &events),
                r,
                &format!("live mode, blocks of {pattern} (seed {seed})"),
            ),
        }
    }
}

#[test]
fn the_example_voice_gives_the_same_output_in_any_block_partition_at_44k_and_48k() {
    for rate in [44_100.0, 48_000.0] {
        let voice = example_voice_at(rate as u32);
        let mut reference: Option<(Vec<f32>, Vec<CcEvent>)> = None;
        for (pattern, seed) in [(512, 0), (37, 0), (1, 0), (0, 7), (0, 99)] {
            let mut plugin = load();
            plugin.activate(rate, 512, 1).unwrap();
            let blocks = block_sizes(voice.len(), pattern, seed);
            let (out, events) = run(&mut plugin, &voice, &blocks);
            assert!(out.iter().all(|s| s.is_finite()));
            check_cc_stream(&events, rate);
            match &reference {
                None => reference = Some((out, events)),
                Some(r) => assert_same_output(
                    (&out, &events),
                    r,
                    &format!("blocks of {pattern} (seed {seed}) at {rate} Hz"),
                ),
            }
        }
        let (out, events) = reference.unwrap();
        let mut probe = load();
        probe.activate(rate, 512, 1).unwrap();
        let latency = probe.latency() as usize;
        check_breaths_in_audio(&voice, &out, latency, rate);
        check_controls_follow_speech_and_breaths(&events);
    }
}

/// Output sample `latency + i` is input sample `i` plus the inserted breath: the difference must
/// be zero outside breaths and show several separate breaths.
fn check_breaths_in_audio(input: &[f32], output: &[f32], latency: usize, rate: f64) {
    assert!(
        (latency as f64 - 0.5 * rate).abs() <= 1.0,
        "lookahead latency {latency}"
    );
    let n = input.len() - latency;
    let diff: Vec<f32> = (0..n).map(|i| output[latency + i] - input[i]).collect();
    let exact = diff.iter().filter(|d| **d == 0.0).count();
    assert!(
        exact as f64 > 0.8 * n as f64,
        "the voice passes bit for bit outside breaths: {exact} of {n} samples"
    );
    // Breaths: runs of 20 ms windows where the inserted sound is above -70 dBFS RMS.
    let win = (0.02 * rate) as usize;
    let mut breaths = 0;
    let mut inside = false;
    for w in diff.chunks(win) {
        let rms = (w.iter().map(|d| d * d).sum::<f32>() / w.len() as f32).sqrt();
        let loud = rms > 10f32.powf(-70.0 / 20.0);
        if loud && !inside {
            breaths += 1;
        }
        inside = loud;
    }
    assert!(
        (4..=30).contains(&breaths),
        "{breaths} separate breaths in the audio of the example voice"
    );
}

/// CC 2 (lung) rises during inspirations, CC 16-18 (head) move while the speaking gate (CC 24)
/// is open.
fn check_controls_follow_speech_and_breaths(events: &[CcEvent]) {
    let lung: Vec<u8> = events
        .iter()
        .filter(|e| e.controller == 2)
        .map(|e| e.value)
        .collect();
    // Count rising runs of at least 10 CC steps: inspirations.
    let mut rises = 0;
    let mut run_start = lung.first().copied().unwrap_or(0);
    for w in lung.windows(2) {
        if w[1] < w[0] {
            if w[0] >= run_start + 10 {
                rises += 1;
            }
            run_start = w[1];
        }
    }
    if let (Some(&last), true) = (lung.last(), !lung.is_empty()) {
        if last >= run_start + 10 {
            rises += 1;
        }
    }
    assert!(rises >= 4, "CC 2 rose {rises} times (inspirations)");

    let mut speaking = false;
    let mut head_moves_speaking = 0;
    for e in events {
        match e.controller {
            24 => speaking = e.value == 127,
            16..=18 if speaking => head_moves_speaking += 1,
            _ => {}
        }
    }
    assert!(
        head_moves_speaking > 300,
        "CC 16-18 changed {head_moves_speaking} times during speech"
    );
    let gate_opens = events
        .iter()
        .filter(|e| e.controller == 24 && e.value == 127)
        .count();
    assert!(gate_opens >= 8, "speaking gate opened {gate_opens} times");
}

/// MIDI CC stream rules: channel 0 by default, sorted by time, each controller at most once per
/// frame (frames are 1/120 s apart), values 0..127, only the DESIGN.md controllers.
fn check_cc_stream(events: &[CcEvent], rate: f64) {
    assert!(!events.is_empty(), "no CC output at {rate} Hz");
    let frame = rate / 120.0;
    assert!(events.windows(2).all(|w| w[0].sample <= w[1].sample));
    for e in events {
        assert_eq!(e.channel, 0);
        assert!(e.value <= 127);
        assert!(
            e.controller == 2 || (16..=25).contains(&e.controller),
            "unexpected controller {}",
            e.controller
        );
    }
    for cc in [2u8, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25] {
        let times: Vec<u64> = events
            .iter()
            .filter(|e| e.controller == cc)
            .map(|e| e.sample)
            .collect();
        for w in times.windows(2) {
            assert!(
                // Frames become available on the analysis' decimated clock, so their spacing
                // jitters by a few samples around the frame period; two sends for one frame would
                // be far closer.
                (w[1] - w[0]) as f64 >= frame / 2.0,
                "CC {cc} sent twice within one frame: samples {} and {}",
                w[0],
                w[1]
            );
        }
        // Sent only on change: consecutive values differ.
        let values: Vec<u8> = events
            .iter()
            .filter(|e| e.controller == cc)
            .map(|e| e.value)
            .collect();
        assert!(
            values.windows(2).all(|w| w[0] != w[1]),
            "CC {cc} repeated a value"
        );
    }
}

#[test]
fn channel_and_fourteen_bit_settings_reach_the_midi_output() {
    let voice = example_voice_at(48_000);
    let voice = &voice[..48_000 * 4];
    let mut plugin = load();
    plugin.set_param("midi_channel", "5").unwrap();
    plugin.set_param("cc_14bit", "On").unwrap();
    // A controller above 31 cannot carry a 14-bit pair: that signal goes quiet, the rest stay.
    plugin.set_param("cc_loudness", "40").unwrap();
    plugin.activate(48_000.0, 256, 1).unwrap();
    let (_, events) = run(&mut plugin, voice, &block_sizes(voice.len(), 256, 0));
    assert!(!events.is_empty());
    assert!(
        events.iter().all(|e| e.channel == 4),
        "channel 5 is 4 on the wire"
    );
    // Every MSB on 2, 16..25 is followed at once by its LSB on controller + 32.
    let mut i = 0;
    while i < events.len() {
        let msb = events[i];
        assert!(msb.controller < 32, "MSB first: {msb:?}");
        let lsb = events[i + 1];
        assert_eq!(lsb.controller, msb.controller + 32);
        assert_eq!(lsb.sample, msb.sample);
        i += 2;
    }
    // MIDI off: nothing.
    plugin.set_param("midi_enabled", "Off").unwrap();
    let (_, events) = run(&mut plugin, voice, &block_sizes(voice.len(), 256, 0));
    assert!(
        events.len() <= 22,
        "at most one block's worth before the change applies"
    );
}

#[test]
fn state_restores_into_a_fresh_instance_with_the_same_output() {
    let voice = example_voice_at(48_000);
    let voice = &voice[..48_000 * 6];
    let mut a = load();
    a.set_param("midi_channel", "3").unwrap();
    a.set_param("cc_loudness", "40").unwrap();
    a.set_param("osc_port", "9100").unwrap();
    a.set_param("osc_format", "VMC").unwrap();
    a.set_param("head_amount", "2.5").unwrap();
    a.set_param("preset", "Calm").unwrap();
    let state = a.save_state();
    // The persisted OSC host travels in the state; give it a different host.
    let text = Plugin::state_json(&state);
    assert!(
        text.contains("127.0.0.1"),
        "OSC host is in the state: {text}"
    );
    let state = Plugin::edit_state(&state, "127.0.0.1", "10.1.2.3");
    a.load_state(&state).unwrap();

    let mut b = load();
    b.load_state(&state).unwrap();
    for id in PARAM_IDS {
        assert_eq!(a.param_value(id), b.param_value(id), "{id} restored");
    }
    let resaved = b.save_state();
    let resaved = Plugin::state_json(&resaved);
    assert!(
        resaved.contains("10.1.2.3"),
        "persisted OSC host restored: {resaved}"
    );

    a.activate(48_000.0, 512, 1).unwrap();
    b.activate(48_000.0, 512, 1).unwrap();
    let blocks = block_sizes(voice.len(), 0, 3);
    let (out_a, ev_a) = run(&mut a, voice, &blocks);
    let (out_b, ev_b) = run(&mut b, voice, &blocks);
    assert!(out_a
        .iter()
        .zip(&out_b)
        .all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(ev_a, ev_b);
    assert!(ev_a.iter().all(|e| e.channel == 2));
    assert!(
        ev_a.iter().any(|e| e.controller == 40),
        "remapped loudness CC"
    );
    assert!(!ev_a.iter().any(|e| e.controller == 25));
}

/// Sets `changes` (id, value text) on `plugin`, saves its state and loads it into a fresh
/// instance: every changed value must differ from its default in the saved instance and come
/// back in the fresh one, every other value too.
fn assert_state_holds(plugin: &mut Plugin, changes: &[(&str, &str)], case: &str) {
    let mut defaults = load();
    let state = plugin.save_state();
    let mut fresh = load();
    fresh.load_state(&state).unwrap();
    for (id, text) in changes {
        assert_ne!(
            plugin.param_value(id),
            defaults.param_value(id),
            "{case}: {id} was set to {text}"
        );
    }
    for id in PARAM_IDS {
        assert_eq!(
            fresh.param_value(id),
            plugin.param_value(id),
            "{case}: {id} in the saved state"
        );
    }
}

const CHANGES: &[(&str, &str)] = &[
    ("breath_level_db", "-10"),
    ("mode", "Live"),
    ("cc_lung", "off"),
    ("preset", "Tired"),
    ("frame_rate_hz", "60"),
];

#[test]
fn a_state_saved_right_after_a_change_holds_the_new_values() {
    // Inactive: the host hands the values over with `params.flush`, then saves.
    let mut plugin = load();
    for (id, text) in CHANGES {
        plugin.set_param(id, text).unwrap();
    }
    assert_state_holds(&mut plugin, CHANGES, "set while inactive");
    // Active: the values arrive as events with the next block; the host saves right after it.
    let mut plugin = load();
    plugin.activate(48_000.0, 256, 2).unwrap();
    plugin.process(&mut vec![vec![0.0; 256]; 2]);
    for (id, text) in CHANGES {
        plugin.set_param(id, text).unwrap();
    }
    plugin.process(&mut vec![vec![0.0; 256]; 2]);
    assert_state_holds(&mut plugin, CHANGES, "set while processing");
}

#[test]
fn nan_infinity_and_silence_never_break_the_output() {
    for channels in [1, 2] {
        let mut plugin = load();
        plugin.activate(44_100.0, 333, channels).unwrap();
        let blocks: Vec<Vec<f32>> = vec![
            vec![0.0; 333],
            vec![f32::NAN; 100],
            vec![f32::INFINITY; 7],
            (0..333)
                .map(|i| if i % 2 == 0 { f32::NEG_INFINITY } else { 0.5 })
                .collect(),
            vec![1e-41; 64], // subnormal
            vec![0.0; 1],
        ];
        for _ in 0..50 {
            for b in &blocks {
                let mut audio = vec![b.clone(); channels];
                plugin.process(&mut audio);
                for c in &audio {
                    assert!(
                        c.iter()
                            .all(|s| s.is_finite() && (*s == 0.0 || s.is_normal())),
                        "non-finite or subnormal output"
                    );
                }
            }
        }
    }
}

/// Index of the first sample above -60 dBFS.
fn first_sound(signal: &[f32]) -> Option<usize> {
    signal.iter().position(|s| s.abs() > 1e-3)
}

/// Processes silent blocks until the plugin asks the host for a restart (a structural change
/// that moves the latency is built on the plugin's background thread), at most 10 s of wall time.
fn process_until_restart_requested(plugin: &mut Plugin, channels: usize) -> usize {
    let start = std::time::Instant::now();
    let mut samples = 0;
    while !plugin.restart_requested() {
        assert!(
            start.elapsed() < std::time::Duration::from_secs(10),
            "no restart requested within 10 s (latency {})",
            plugin.latency()
        );
        plugin.process(&mut vec![vec![0.0; 128]; channels]);
        samples += 128;
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    samples
}

/// Smallest distance between two messages of `controller`, samples.
/// The controller of the loudness CC in the default map: it changes on nearly every frame of
/// speech, so the closest messages show the frame period. (The head's angles move too slowly
/// for a 7-bit step every frame, and hold still before the first voiced frame.)
fn loudness_cc() -> u8 {
    use pneuma_core::encode::midi_cc::CcSignal;
    CcSignal::DEFAULT_CONTROLLERS[CcSignal::Loudness.index()]
}

fn closest_messages(events: &[CcEvent], controller: u8) -> u64 {
    let times: Vec<u64> = events
        .iter()
        .filter(|e| e.controller == controller)
        .map(|e| e.sample)
        .collect();
    assert!(
        times.len() > 20,
        "{} messages of CC {controller}",
        times.len()
    );
    times.windows(2).map(|w| w[1] - w[0]).min().unwrap()
}

/// CLAP allows a new latency only inside `activate` (clap-validator's fuzzer fails a plugin that
/// calls `clap_host_latency::changed` elsewhere, e.g. when the host deactivated before running
/// a latency report queued from the audio thread). So a Mode change while active asks for a
/// restart, keeps the running engine (and the latency the host compensates) until then, and the
/// re-activation is live from the first sample.
#[test]
fn live_mode_takes_effect_at_the_restart_the_plugin_asks_for() {
    let rate = 48_000.0;
    let voice = example_voice_at(48_000);
    let voice = &voice[..48_000 * 3];
    let onset = first_sound(voice).expect("the voice starts within 3 s");

    let mut plugin = load();
    plugin.activate(rate, 128, 1).unwrap();
    let lookahead = plugin.latency();
    assert_eq!(lookahead, 24_000, "lookahead latency at 48 kHz");
    assert_eq!(plugin.latency_changes_outside_activate(), 0);
    plugin.set_param("mode", "Live").unwrap();
    // The silence processed meanwhile (as many blocks as the build takes) is stream time too.
    let waited = process_until_restart_requested(&mut plugin, 1);
    // Until the restart the lookahead engine keeps running, with the latency the host knows.
    assert_eq!(
        plugin.latency(),
        lookahead,
        "no latency change while active"
    );
    let (out, _) = run(&mut plugin, voice, &block_sizes(voice.len(), 128, 0));
    // (A lookahead breath may come before the voice's onset, even in the silence before it,
    // never before the delay from the stream's start.)
    let first = first_sound(&out).expect("the voice comes out");
    let earliest = (lookahead as usize).saturating_sub(waited);
    assert!(
        (earliest..=onset + lookahead as usize).contains(&first),
        "first sound at {first}: not delayed by the latency the host compensates"
    );
    // The host deactivates before it runs the plugin's main-thread callback: nothing queued
    // may report a latency change there.
    plugin.deactivate();
    plugin.run_main_thread_callback();
    assert_eq!(
        plugin.latency_changes_outside_activate(),
        0,
        "clap_host_latency::changed called outside activate"
    );
    let (voice, voice_rate, rendered) = cli_render(&["--mode", "live"]);
    let before = plugin.latency_changes();
    plugin.activate(f64::from(voice_rate), 128, 1).unwrap();
    assert_eq!(plugin.latency(), 0, "live mode after the restart");
    assert_eq!(
        plugin.latency_changes(),
        before + 1,
        "the host hears of the new latency inside the re-activation"
    );
    assert_eq!(plugin.latency_changes_outside_activate(), 0);
    let (out, _) = run(&mut plugin, &voice, &block_sizes(voice.len(), 128, 0));
    assert_matches_render(&out, &rendered, "live mode after the restart");
    // And it is not the lookahead render.
    let (_, _, lookahead_render) = cli_render(&["--lookahead-ms", "500"]);
    let differ = out
        .iter()
        .zip(&lookahead_render)
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        differ as f64 > 0.1 * f64::from(voice_rate),
        "live and lookahead renders differ in {differ} samples only"
    );

    // Back to lookahead with another length: another restart, with the main thread running
    // the plugin's callbacks while it is still active.
    plugin.set_param("mode", "Lookahead").unwrap();
    plugin.set_param("lookahead_s", "0.8").unwrap();
    process_until_restart_requested(&mut plugin, 1);
    plugin.run_main_thread_callback();
    assert_eq!(plugin.latency(), 0, "still live until the restart");
    plugin.activate(f64::from(voice_rate), 128, 1).unwrap();
    assert_eq!(
        plugin.latency(),
        (0.8 * f64::from(voice_rate)).round() as u32
    );
    assert_eq!(plugin.latency_changes_outside_activate(), 0);
}

/// A change that keeps the latency (the control frame rate) takes effect while active, without
/// a restart.
#[test]
fn a_latency_neutral_change_swaps_in_without_a_restart() {
    let mut plugin = load();
    plugin.activate(48_000.0, 256, 1).unwrap();
    plugin.set_param("frame_rate_hz", "60").unwrap();
    // The engine is built in the background: give it two seconds of wall time.
    let start = std::time::Instant::now();
    while start.elapsed() < std::time::Duration::from_secs(2) {
        plugin.process(&mut [vec![0.0; 256]]);
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    let voice = example_voice_at(48_000);
    let (_, events) = run(&mut plugin, &voice[..48_000 * 4], &[256; 750]);
    let closest = closest_messages(&events, loudness_cc());
    assert!(
        (780..=820).contains(&closest),
        "loudness messages at least {closest} samples apart: not at 60 Hz"
    );
    assert!(!plugin.restart_requested(), "no restart for the frame rate");
    assert_eq!(plugin.latency(), 24_000);
}

#[test]
fn a_state_saved_in_live_mode_restores_live_mode_active_or_not() {
    let mut a = load();
    a.set_param("mode", "Live").unwrap();
    a.set_param("frame_rate_hz", "60").unwrap();
    let state = a.save_state();
    // Restored into an instance that is already active (a host reopening a session): live at
    // the restart the plugin asks for.
    let mut b = load();
    b.activate(48_000.0, 256, 2).unwrap();
    assert_eq!(b.latency(), 24_000);
    b.load_state(&state).unwrap();
    process_until_restart_requested(&mut b, 2);
    b.activate(48_000.0, 256, 2).unwrap();
    assert_eq!(b.latency(), 0, "restored live mode after the restart");
    assert_eq!(b.latency_changes_outside_activate(), 0);
    // Restored before activation: the first activation is live.
    let mut c = load();
    c.load_state(&state).unwrap();
    c.activate(48_000.0, 256, 2).unwrap();
    assert_eq!(c.latency(), 0, "restored live mode at the first activation");
    // The frame rate came back too: CC messages at most 60 per second per controller.
    let voice = example_voice_at(48_000);
    let voice: Vec<Vec<f32>> = vec![voice[..48_000 * 4].to_vec(); 2];
    let mut events = Vec::new();
    for start in (0..voice[0].len()).step_by(256) {
        let mut block: Vec<Vec<f32>> = voice
            .iter()
            .map(|c| c[start..start + 256].to_vec())
            .collect();
        events.extend(c.process(&mut block));
    }
    // Frames 800 samples apart (a few samples of jitter), not 400 as at the default 120 Hz.
    let closest = closest_messages(&events, loudness_cc());
    assert!(
        (780..=820).contains(&closest),
        "loudness messages at least {closest} samples apart: the frame rate is not 60 Hz"
    );
}

/// The plugin and `pneuma render` give the same audio for the same file and settings, apart
/// from the latency the plugin reports.
#[test]
fn the_plugin_output_equals_the_cli_render() {
    let (voice, rate, rendered) = cli_render(&["--lookahead-ms", "500"]);
    let mut plugin = load();
    plugin.activate(f64::from(rate), 512, 1).unwrap();
    let latency = plugin.latency() as usize;
    // Feed the voice plus `latency` samples of silence so the delayed output is complete.
    let mut input = voice.clone();
    input.resize(voice.len() + latency, 0.0);
    let (out, _) = run(&mut plugin, &input, &block_sizes(input.len(), 512, 0));
    assert_matches_render(&out[latency..], &rendered, "no transport");
}

/// The example voice and `pneuma render` of it (mono) with the extra `options`:
/// `(voice, rate, rendered)`.
fn cli_render(options: &[&str]) -> (Vec<f32>, u32, Vec<f32>) {
    let voice_path = pneuma_testkit::voice::example_voice_path();
    let (voice, rate) = pneuma_testkit::voice::example_voice();
    let dir = std::env::temp_dir().join(format!(
        "pneuma-render-{}-{:?}",
        std::process::id(),
        std::thread::current().id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    // `pneuma render` in process: the command's own arguments and code path (`render::run`).
    use clap::{Args as _, FromArgMatches as _};
    let mut argv = vec![
        "render".into(),
        voice_path.clone().into_os_string(),
        "-o".into(),
        dir.clone().into_os_string(),
        "--quiet".into(),
    ];
    argv.extend(options.iter().map(|o| o.into()));
    let matches = pneuma_cli::render::Args::augment_args(clap::Command::new("render"))
        .try_get_matches_from(argv)
        .expect("valid render options");
    let args = pneuma_cli::render::Args::from_arg_matches(&matches).expect("render options");
    pneuma_cli::render::run(&args, &voice_path, |_| {}).expect("pneuma render");
    let (mut rendered, rendered_rate) = pneuma_testkit::voice::read_wav(&dir.join("voice.wav"));
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(rendered_rate, rate);
    let rendered = rendered.swap_remove(0);
    assert_eq!(rendered.len(), voice.len(), "the render keeps the length");
    (voice, rate, rendered)
}

/// The plugin's latency-compensated output equals the render from the first sample (the
/// render is stored as a 16-bit or float WAV: one 16-bit step allowed).
fn assert_matches_render(out: &[f32], rendered: &[f32], case: &str) {
    assert!(out.len() >= rendered.len(), "{case}: output too short");
    let first_diff = out
        .iter()
        .zip(rendered)
        .position(|(a, b)| (a - b).abs() > 1.5 / 32768.0);
    assert!(
        first_diff.is_none(),
        "{case}: plugin vs CLI render differ from sample {first_diff:?}"
    );
}

#[test]
fn the_plugin_output_equals_the_cli_render_when_the_host_pre_rolls_from_time_zero() {
    // A region at the start of the timeline, played from time 0 by a host that compensates the
    // latency: it feeds the plugin the region from its first sample while it pre-rolls the
    // latency, then rolls. Hosts report the pre-roll differently: positions running up to 0
    // from -latency, or the position held at 0 until the roll starts.
    let (voice, rate, rendered) = cli_render(&["--lookahead-ms", "500"]);
    let block = 512;
    for held_at_zero in [false, true] {
        let mut plugin = load();
        plugin.activate(f64::from(rate), block, 1).unwrap();
        let latency = plugin.latency() as usize;
        let mut input = voice.clone();
        input.resize(voice.len() + latency, 0.0);
        let mut out = Vec::with_capacity(input.len());
        // The host splits its cycle where the pre-roll ends (as Ardour does).
        let (pre_roll, roll) = input.split_at(latency);
        let chunks = pre_roll.chunks(block).chain(roll.chunks(block));
        let mut fed = 0i64;
        for chunk in chunks {
            let timeline = fed - latency as i64;
            let pos = if held_at_zero {
                timeline.max(0)
            } else {
                timeline
            };
            let mut audio = [chunk.to_vec()];
            plugin.process_at(&mut audio, Some(pos as f64 / f64::from(rate)));
            out.extend_from_slice(&audio[0]);
            fed += chunk.len() as i64;
        }
        let case = if held_at_zero {
            "pre-roll held at 0"
        } else {
            "pre-roll from -latency"
        };
        assert_matches_render(&out[latency..], &rendered, case);
    }
}

#[test]
fn a_transport_jump_resets_the_stream() {
    let voice = example_voice_at(48_000);
    let rate = 48_000.0;
    let block = 480;
    let jump_block = 1000; // at 10 s of audio
    let run_with = |jump: bool| {
        let mut plugin = load();
        plugin.activate(rate, block, 1).unwrap();
        let mut out = Vec::new();
        for (i, chunk) in voice.chunks(block).take(jump_block + 200).enumerate() {
            // Song position in seconds; with `jump` it leaps 60 s ahead at `jump_block`.
            let mut pos = (i * block) as f64 / rate;
            if jump && i >= jump_block {
                pos += 60.0;
            }
            let mut audio = [chunk.to_vec()];
            plugin.process_at(&mut audio, Some(pos));
            out.extend_from_slice(&audio[0]);
        }
        (out, plugin.latency() as usize)
    };
    let (steady, latency) = run_with(false);
    let (jumped, _) = run_with(true);
    let at = jump_block * block;
    assert_eq!(&steady[..at], &jumped[..at], "identical before the jump");
    // After the reset the delay line starts empty: one latency of silence, where the steady
    // stream still plays the voice.
    let after = &jumped[at..at + latency];
    assert!(
        after.iter().all(|s| *s == 0.0),
        "silence for the lookahead after a jump"
    );
    let steady_energy: f32 = steady[at..at + latency].iter().map(|s| s * s).sum();
    assert!(steady_energy > 0.0, "the steady stream plays on");
}

#[test]
fn any_sample_rate_activates_and_unsupported_rates_pass_the_audio_with_controls_at_rest() {
    // A noise-like signal with no exact zeros, so a pass-through is visible bit for bit.
    let signal: Vec<f32> = (0..4096)
        .map(|i| 0.3 * ((i as f32 * 0.731).sin() + 0.05))
        .collect();
    for rate in [1.0, 1_234.567_8, 8_000.0, 48_000.0, 384_000.0, 768_000.0] {
        let mut plugin = load();
        plugin
            .activate(rate, 512, 1)
            .unwrap_or_else(|e| panic!("activation at {rate} Hz refused: {e}"));
        let blocks = block_sizes(signal.len(), 512, 0);
        let (out, events) = run(&mut plugin, &signal, &blocks);
        assert!(out.iter().all(|s| s.is_finite()), "{rate} Hz");
        if plugin.latency() == 0 {
            // The engine does not run here: the audio passes untouched and each controller is
            // sent once, at rest.
            assert_eq!(out, signal, "pass-through at {rate} Hz");
            let mut controllers: Vec<u8> = events.iter().map(|e| e.controller).collect();
            let sent = controllers.len();
            controllers.sort_unstable();
            controllers.dedup();
            assert_eq!(
                controllers.len(),
                sent,
                "one message per controller at {rate} Hz"
            );
            assert!(sent > 0, "the rest pose goes out at {rate} Hz");
        }
    }
}
