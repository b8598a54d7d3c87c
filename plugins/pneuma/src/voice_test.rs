//! Test-only: the freeze switch through the real [`Plugin::process`] (under nice-plug's
//! allocation guard, as [`crate::alloc_test`]): a speaker who breathes is learned, the freeze
//! keeps that voice (saved in the persisted `breath_voice`) for two identical playbacks, and
//! turning it off learns afresh; nothing allocates while learning or when the switch moves.
//! (Save and reload through a real host: `tests/tests/integration/plugin_clap.rs`.)

#![allow(unsafe_code)]

use std::num::NonZeroU32;

use nice_plug::prelude::*;
use pneuma_core::engine::EngineConfig;
use pneuma_testkit::signals;

use crate::alloc_test::{activation_ctx, guard_catches_allocations, set, Activation, Host};
use crate::params::breath_voice::FrozenVoice;
use crate::voice::VoiceShown;
use crate::Pneuma;

const RATE_HZ: f32 = 48_000.0;
const BLOCK: usize = 512;

/// A plugin, activated mono at [`RATE_HZ`], with breaths into every pause (the generated
/// speaker's sustained vowels are not speech to the speech decision).
fn plugin() -> Pneuma {
    activated(Pneuma::default())
}

/// `plugin` activated as [`plugin`] does.
fn activated(plugin: Pneuma) -> Pneuma {
    activated_judging(plugin, false)
}

/// `plugin` activated mono at [`RATE_HZ`], with the speech decision on or off.
fn activated_judging(mut plugin: Pneuma, speech_only: bool) -> Pneuma {
    set(&plugin, "speech_only", if speech_only { 1.0 } else { 0.0 });
    let layout = AudioIOLayout {
        main_input_channels: NonZeroU32::new(1),
        main_output_channels: NonZeroU32::new(1),
        ..AudioIOLayout::const_default()
    };
    let config = BufferConfig {
        sample_rate: RATE_HZ,
        min_buffer_size: None,
        max_buffer_size: BLOCK as u32,
        process_mode: ProcessMode::Realtime,
    };
    let activation = Activation {
        api: PluginApi::Clap,
        latency: 0.into(),
    };
    assert!(plugin.activate(&layout, &config, &mut activation_ctx(&activation)));
    plugin
}

/// Plays `signal` from position 0 (a transport start: the stream restarts) through the real
/// `process` under the allocation guard; the output.
fn play(plugin: &mut Pneuma, host: &mut Host, signal: &[f32]) -> Vec<f32> {
    play_from(plugin, host, signal, 0)
}

/// Plays `signal` from position `start` (where the last block ended: no jump, the stream goes
/// on).
fn play_from(plugin: &mut Pneuma, host: &mut Host, signal: &[f32], start: usize) -> Vec<f32> {
    let mut out = Vec::with_capacity(signal.len());
    let mut block = vec![0.0f32; BLOCK];
    for (i, chunk) in signal.chunks(BLOCK).enumerate() {
        let n = chunk.len();
        block[..n].copy_from_slice(chunk);
        host.transport.pos_samples = Some((start + i * BLOCK) as i64);
        let mut buffer = Buffer::default();
        // SAFETY: the slice lives until the end of this iteration, past `process`.
        unsafe {
            buffer.set_slices(n, |slices| {
                slices.clear();
                slices.push(&mut block[..n]);
            });
        }
        let mut aux = AuxiliaryBuffers {
            inputs: &mut [],
            outputs: &mut [],
        };
        nice_assert_no_alloc::assert_no_alloc(|| {
            plugin.process(&mut buffer, &mut aux, host);
        });
        drop(buffer);
        out.extend_from_slice(&block[..n]);
    }
    out
}

fn shown(plugin: &Pneuma) -> VoiceShown {
    VoiceShown::load(&plugin.editor_shared().status.breath_voice)
}

#[test]
fn a_frozen_voice_plays_the_same_every_time_and_unfreezing_learns_afresh() {
    if let Err(e) = guard_catches_allocations() {
        panic!("{e}");
    }
    let rate = f64::from(RATE_HZ);
    let breathing = signals::phrases_with_breaths(rate, 16.0, 5);
    let breathless = signals::phrases_with_pauses(rate, 10.0, 60.0, 5);
    let mut plugin = plugin();
    let mut host = Host::playing(PluginApi::Clap, RATE_HZ);

    play(&mut plugin, &mut host, &breathing);
    let VoiceShown::Learning {
        breaths,
        level_db: Some(level_db),
    } = shown(&plugin)
    else {
        panic!("learning, with a level: {:?}", shown(&plugin));
    };
    assert!(breaths >= 4, "{breaths} breaths heard");
    assert_eq!(plugin.params.breath_voice.get(), None, "nothing frozen yet");
    // Learning restarts with every playback: the built-in voice at first.
    let learning_again = play(&mut plugin, &mut host, &breathless);
    assert_eq!(
        shown(&plugin),
        VoiceShown::Learning {
            breaths: 0,
            level_db: None
        }
    );

    // Learn again, then freeze while the stream goes on (the switch moves between blocks, as
    // automation does).
    play(&mut plugin, &mut host, &breathing);
    set(&plugin, "freeze_breath_voice", 1.0);
    play_from(
        &mut plugin,
        &mut host,
        &breathless[..BLOCK],
        breathing.len(),
    );
    let frozen = VoiceShown::Frozen {
        breaths,
        level_db: Some(level_db),
    };
    assert_eq!(shown(&plugin), frozen);
    let Some(FrozenVoice::Learned(voice)) = plugin.params.breath_voice.get() else {
        panic!("saved: {:?}", plugin.params.breath_voice.get());
    };
    assert_eq!(voice.breaths, breaths);
    // The editor shows the level the voice plays its breaths at under the speech.
    assert_eq!(f64::from(level_db), voice.level_re_speech_db.round());
    assert!(level_db < 0, "{level_db} dB");

    let one = play(&mut plugin, &mut host, &breathless);
    let two = play(&mut plugin, &mut host, &breathless);
    assert!(
        one.iter()
            .zip(&two)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "two playbacks of a frozen voice differ"
    );
    assert!(
        one != learning_again,
        "the frozen voice sounds like the built-in one"
    );
    assert_eq!(shown(&plugin), frozen);

    // Off: learning restarts, the saved voice is gone.
    set(&plugin, "freeze_breath_voice", 0.0);
    play_from(
        &mut plugin,
        &mut host,
        &breathless[..BLOCK],
        breathless.len(),
    );
    assert_eq!(
        shown(&plugin),
        VoiceShown::Learning {
            breaths: 0,
            level_db: None
        }
    );
    assert_eq!(plugin.params.breath_voice.get(), None);
    let three = play(&mut plugin, &mut host, &breathless);
    assert!(
        three == learning_again,
        "unfrozen, a playback learns from nothing again"
    );

    // Frozen with nothing learned: the built-in voice, kept.
    set(&plugin, "freeze_breath_voice", 1.0);
    play_from(
        &mut plugin,
        &mut host,
        &breathless[..BLOCK],
        breathless.len(),
    );
    assert_eq!(shown(&plugin), VoiceShown::FrozenBuiltIn);
    assert_eq!(plugin.params.breath_voice.get(), Some(FrozenVoice::BuiltIn));
}

#[test]
fn an_engine_learns_the_voice_of_the_breath_like_file_and_a_bad_file_leaves_learning() {
    let rate = f64::from(RATE_HZ);
    let (dir, take) = breathing_take("pneuma-breath-like");
    // The generated speaker's vowels are not speech: learned as the plugin above learns it.
    let mut any_sound = EngineConfig::default();
    any_sound.placement.speech_only = false;
    let learned = crate::breath_like::learn(take.to_str().unwrap(), &any_sound)
        .unwrap()
        .voice
        .expect("breaths heard in the take");
    assert!(learned.breaths >= 4, "{} breaths", learned.breaths);

    let from_file = Pneuma::default();
    from_file
        .params
        .breath_like
        .set_path(take.to_string_lossy().into_owned());
    let mut from_file = activated(from_file);
    let mut host = Host::playing(PluginApi::Clap, RATE_HZ);
    let breathless = signals::phrases_with_pauses(rate, 4.0, 60.0, 5);
    play(&mut from_file, &mut host, &breathless);
    let VoiceShown::BreathLike {
        breaths,
        level_db: Some(level_db),
    } = shown(&from_file)
    else {
        panic!("from the file, with a level: {:?}", shown(&from_file));
    };
    assert_eq!(breaths, learned.breaths);
    // The file's level under its speech, kept against this track's speech.
    assert_eq!(f64::from(level_db), learned.level_re_speech_db.round());

    let missing = Pneuma::default();
    missing
        .params
        .breath_like
        .set_path(dir.join("missing.wav").to_string_lossy().into_owned());
    let mut missing = activated(missing);
    play(&mut missing, &mut host, &breathless);
    assert_eq!(
        shown(&missing),
        VoiceShown::Learning {
            breaths: 0,
            level_db: None
        }
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_editors_check_of_a_breath_like_file_is_the_read_the_engine_learns_from() {
    // The editor checks the file (off the GUI thread); the engine built at activation learns
    // from the same file: one read. To see it, the file is replaced after the check by a
    // shorter take with fewer breaths, under the same modification time: the engine keeps
    // the voice the check learned. (Each reading it for itself, the engine learned the
    // replacement, and a long take was decoded and analysed twice.)
    let rate = f64::from(RATE_HZ);
    let (dir, take) = breathing_take("pneuma-breath-check");
    let path = take.to_string_lossy().into_owned();
    let plugin = Pneuma::default();
    plugin.params.breath_like.set_path(path.clone());
    set(&plugin, "speech_only", 0.0);
    let config = plugin.params.engine_config();
    let checked = crate::breath_like::check(&plugin.breath_like_voices, &path, &config);
    let checked = checked.expect("the take is learned from");
    let breaths = match plugin.breath_like_voices.learn(&path, &config) {
        Ok(like) => like.voice.expect("breaths heard in the take").breaths,
        Err(e) => panic!("{e}"),
    };
    assert!(checked.contains(&format!("{breaths} breaths")), "{checked}");
    assert_eq!(plugin.breath_like_voices.reads(), 1);

    let modified = std::fs::metadata(&take).unwrap().modified().unwrap();
    write_take(&take, &signals::phrases_with_breaths(rate, 6.0, 9));
    std::fs::File::options()
        .write(true)
        .open(&take)
        .unwrap()
        .set_modified(modified)
        .unwrap();
    let mut plugin = activated(plugin);
    let mut host = Host::playing(PluginApi::Clap, RATE_HZ);
    play(
        &mut plugin,
        &mut host,
        &signals::phrases_with_pauses(rate, 4.0, 60.0, 5),
    );
    assert!(
        matches!(shown(&plugin), VoiceShown::BreathLike { breaths: b, .. } if b == breaths),
        "{:?}, the check learned {breaths} breaths",
        shown(&plugin)
    );
    assert_eq!(plugin.breath_like_voices.reads(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn checking_another_file_keeps_the_voice_of_the_one_in_use() {
    // The engine learned take A; the editor checks take B; the next engine build for A (a
    // re-activation before the path changes) does not read A again, nor after a check of a
    // third take C (the voice used last is kept).
    let (dir, a) = breathing_take("pneuma-breath-two");
    let (b, c) = (dir.join("other.wav"), dir.join("third.wav"));
    let rate = f64::from(RATE_HZ);
    write_take(&b, &signals::phrases_with_breaths(rate, 8.0, 3));
    write_take(&c, &signals::phrases_with_breaths(rate, 8.0, 4));
    let mut config = EngineConfig::default();
    config.placement.speech_only = false;
    let cache = crate::breath_like::VoiceCache::default();
    let (a, b, c) = (
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        c.to_str().unwrap(),
    );
    for (path, reads) in [(a, 1), (b, 2), (a, 2), (b, 2), (a, 2), (c, 3), (a, 3)] {
        assert!(cache.learn(path, &config).is_ok(), "{path}");
        assert_eq!(cache.reads(), reads, "after {path}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A folder for one test (`name` and the process id) holding `take.wav`: 16 s of the
/// generated speaker breathing in its pauses. Returns the folder and the take's path.
fn breathing_take(name: &str) -> (std::path::PathBuf, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let take = dir.join("take.wav");
    let rate = f64::from(RATE_HZ);
    write_take(&take, &signals::phrases_with_breaths(rate, 16.0, 9));
    (dir, take)
}

/// `samples` written as a mono float WAV at [`RATE_HZ`] to `path`.
fn write_take(path: &std::path::Path, samples: &[f32]) {
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: RATE_HZ as u32,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(path, spec).unwrap();
    for &s in samples {
        w.write_sample(s).unwrap();
    }
    w.finalize().unwrap();
}

#[test]
fn a_breath_like_file_of_music_is_not_learned_from_and_the_check_says_why() {
    // As `render --breath-like`: a music file given where a take of the speaker is asked for
    // holds no speaker's breath (the gaps between its chords passed for breaths). The speech
    // decision hears it first: no speech, not learned from, the voice learned as the audio
    // goes, and the editor's file check says why.
    let dir = std::env::temp_dir().join(format!("pneuma-breath-like-music-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let music = dir.join("chords.wav");
    write_take(&music, &signals::plucked_chords(f64::from(RATE_HZ), 14.0));
    let path = music.to_str().unwrap();
    let err = crate::breath_like::learn(path, &EngineConfig::default()).unwrap_err();
    assert!(
        matches!(err, crate::breath_like::BreathLikeError::NotSpeech { .. }),
        "{err}"
    );
    assert!(err.to_string().contains("holds no speech"), "{err}");
    // With the decision off ("any sound", a voice it does not take for speech) the user's
    // file is learned from.
    let mut any_sound = EngineConfig::default();
    any_sound.placement.speech_only = false;
    assert!(crate::breath_like::learn(path, &any_sound).is_ok());

    let judged = Pneuma::default();
    judged.params.breath_like.set_path(path.to_owned());
    let mut judged = activated_judging(judged, true);
    let mut host = Host::playing(PluginApi::Clap, RATE_HZ);
    play(
        &mut judged,
        &mut host,
        &signals::phrases_with_pauses(f64::from(RATE_HZ), 4.0, 60.0, 5),
    );
    assert_eq!(
        shown(&judged),
        VoiceShown::Learning {
            breaths: 0,
            level_db: None
        }
    );
    let _ = std::fs::remove_dir_all(&dir);
}
