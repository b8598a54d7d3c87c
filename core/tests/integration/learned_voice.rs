//! The breath voice learned from a recording: a generated speaker whose breaths are noise
//! through a known filter is learned within 1 dB per band; the engine's inserted breaths follow
//! the learned voice (shape and level); a recording without breaths learns nothing (the
//! built-in voice stays); with a learned voice the engine still gives the same output for any
//! block partition and never allocates while processing. A stream (the plugin, lookahead and
//! live renders) learns the voice as it goes: from the breaths heard before an editor's cut, the
//! breaths inserted after it sound like the speaker's; any partition gives the same; learning
//! restarts with the stream, and a frozen voice stays, saved and loaded as plain data.

use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::breathing::third_octave::{
    band_level_db, band_powers, distance_db, mean_shape, shape_db, Bands, BANDS,
};
use pneuma_core::engine::voice_learning::{learn_voice, VoiceLearner};
use pneuma_core::engine::{offline, BreathVoiceMode, Engine, EngineConfig, VoiceStatus};
use pneuma_core::head::HeadModel;
use pneuma_core::BreathEvent;
use pneuma_testkit::signals;

use crate::support::{streamed_watched, watched};

const RATE_HZ: f64 = 16_000.0;
/// The speaker's breath filter (`signals::phrases_with_breaths`): band-limited noise, 500 Hz to
/// 5 kHz.
const BREATH_BAND_HZ: (f64, f64) = (500.0, 5000.0);

fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

fn config() -> EngineConfig {
    let mut c = EngineConfig::default();
    c.placement.whole_file = true;
    // The generated speaker's sustained vowels are not speech to the speech decision; these
    // tests are about the breath voice.
    c.placement.speech_only = false;
    c
}

/// 1.5 s phrases every 2 s (`phrases_with_pauses`); with `breaths`, each pause holds a 0.3 s
/// inhalation of the speaker's breath noise (`BREATH_BAND_HZ`), 24 dB under the speech
/// (`phrases_with_breaths`).
fn speaker(seconds: f64, breaths: bool) -> Vec<f32> {
    if breaths {
        signals::phrases_with_breaths(RATE_HZ, seconds, 5)
    } else {
        signals::phrases_with_pauses(RATE_HZ, seconds, 60.0, 5)
    }
}

/// The filter's own shape: a long stretch of its noise.
fn filter_shape() -> Bands {
    let long = signals::band_noise(RATE_HZ as usize * 20, RATE_HZ, BREATH_BAND_HZ, 0.1, 99);
    shape_db(&band_powers(&long, RATE_HZ))
}

/// What the engine added to `input` over breath `b` of `out`.
fn added(out: &offline::Rendered, input: &[f32], b: &BreathEvent) -> Vec<f32> {
    let span = (b.start_s * RATE_HZ) as usize..(b.end_s * RATE_HZ) as usize;
    span.map(|i| out.audio[0][i] - input[i]).collect()
}

fn worst_band_db(a: &Bands, b: &Bands) -> f64 {
    (0..BANDS).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max)
}

#[test]
fn the_learned_envelope_matches_the_speakers_breath_filter_within_a_db_per_band() {
    let x = speaker(14.0, true);
    let v = learn_voice(&config(), &x, RATE_HZ)
        .expect("settings")
        .expect("the breaths are heard");
    assert!(v.breaths >= 5, "{} breaths heard", v.breaths);
    let want = filter_shape();
    let worst = worst_band_db(&v.shape_db, &want);
    assert!(
        worst < 1.0,
        "worst band {worst:.2} dB: {:?} vs {want:?}",
        v.shape_db
    );
    assert!(
        (v.length_s - 0.3).abs() < 0.1,
        "length {} s, the breaths last 0.3 s",
        v.length_s
    );
}

#[test]
fn the_learned_level_is_the_breaths_own_under_low_rumble_in_the_quiet_frames() {
    // The Keele clips: thumps and rumble under 250 Hz in some quiet frames of the pauses (the
    // quietest frames in the breath bands) as loud as the breaths or louder. They are not the
    // breath's: the level learned is the breath noise's own, however loud the rumble.
    let mut x = speaker(14.0, true);
    let speech = rms(&x[..(1.4 * RATE_HZ) as usize]);
    let breath_rms = speech * 10f64.powf(-24.0 / 20.0);
    let amp = 3.0 * breath_rms * 2f64.sqrt();
    let mut t = 1.5;
    while t + 0.5 < 14.0 {
        // 0.1 s at 40 Hz just after each phrase, 10 dB over the breath.
        let from = (t * RATE_HZ) as usize;
        for (i, v) in x[from..from + (0.1 * RATE_HZ) as usize]
            .iter_mut()
            .enumerate()
        {
            let u = i as f64 / RATE_HZ;
            *v += (amp * (2.0 * std::f64::consts::PI * 40.0 * u).sin()) as f32;
        }
        t += 2.0;
    }
    let v = learn_voice(&config(), &x, RATE_HZ)
        .expect("settings")
        .expect("the breaths are heard");
    // The breath noise lies inside the bands: its level there is its RMS, under the ramps
    // (sin^0.5, a mean square of 2/π over the breath).
    let want =
        20.0 * breath_rms.log10() + 10.0 * (2.0 / std::f64::consts::PI).log10() - v.speech_db;
    assert!(
        (v.level_re_speech_db - want).abs() < 1.5,
        "learned {:+.1} dB re speech, the breaths are {want:+.1}",
        v.level_re_speech_db
    );
}

#[test]
fn a_recording_without_breaths_learns_nothing_and_keeps_the_built_in_voice() {
    let x = speaker(10.0, false);
    assert_eq!(learn_voice(&config(), &x, RATE_HZ).expect("settings"), None);
}

/// Renders `x` with `voice` in blocks of `blocks`.
fn render(x: &[f32], voice: Option<LearnedVoice>, blocks: &[usize]) -> offline::Rendered {
    let mut e = Engine::new(config(), HeadModel::default_model().clone()).expect("config");
    e.set_learned_voice(voice);
    e.prepare(RATE_HZ, 1024, 1).expect("prepare");
    offline::render(&mut e, &[x.to_vec()], blocks)
}

/// A voice with a dark shape, no spread, 30 dB under −20 dBFS speech.
fn dark_voice() -> LearnedVoice {
    LearnedVoice {
        breaths: 5,
        shape_db: shape_db(&std::array::from_fn(|k| {
            10f64.powf(-(k as f64) * 0.6 / 10.0)
        })),
        shape_sd_db: [0.0; BANDS],
        level_re_speech_db: -30.0,
        level_sd_db: 0.0,
        speech_db: -20.0,
        length_s: 0.4,
        length_sd_s: 0.05,
    }
}

#[test]
fn inserted_breaths_follow_the_learned_voice_in_shape_and_level() {
    let x = speaker(12.0, false);
    let v = dark_voice();
    let out = render(&x, Some(v), &[1024]);
    assert!(out.breaths.len() >= 4, "{} breaths", out.breaths.len());
    let added: Vec<f32> = out.audio[0].iter().zip(&x).map(|(o, i)| o - i).collect();
    let (mut levels, mut shapes) = (Vec::new(), Vec::new());
    for b in &out.breaths {
        let s = &added[(b.start_s * RATE_HZ) as usize..(b.end_s * RATE_HZ) as usize];
        let shape = shape_db(&band_powers(s, RATE_HZ));
        // One short noise burst measures each band within a dB or so: the RMS over the bands.
        let d = distance_db(&shape, &v.shape_db);
        assert!(
            d < 1.5,
            "breath at {:.2} s: {d:.2} dB from the learned shape",
            b.start_s
        );
        shapes.push(shape);
        // The level as the voice learns it: the mean square in the bands. One 0.3 s burst of
        // this dark noise (most of its power in the narrow low bands) and the flutter vary by
        // ±3 dB from breath to breath; the median is checked below.
        let level_db = band_level_db(&band_powers(s, RATE_HZ), RATE_HZ);
        assert!(
            (level_db - v.level_db()).abs() < 3.5,
            "breath at {:.2} s: {level_db:.1} dBFS, learned {:.1}",
            b.start_s,
            v.level_db()
        );
        levels.push(level_db - v.level_db());
    }
    let mean = mean_shape(&shapes);
    // The lowest bands hold one or two FFT bins: five 0.3 s bursts measure them within ~2 dB.
    let worst = worst_band_db(&mean, &v.shape_db);
    assert!(
        worst < 2.0,
        "mean inserted shape: worst band {worst:.2} dB: {mean:.1?} vs {:.1?}",
        v.shape_db
    );
    levels.sort_by(f64::total_cmp);
    let median = levels[levels.len() / 2];
    assert!(
        median.abs() < 1.0,
        "median level {median:+.2} dB from the learned: {levels:?}"
    );
    // The built-in voice sounds otherwise.
    let built_in = render(&x, None, &[1024]);
    assert_ne!(built_in.audio, out.audio);
}

#[test]
fn with_a_learned_voice_any_partition_gives_the_same_output_and_nothing_allocates() {
    let x = speaker(8.0, false);
    let v = dark_voice();
    let reference = render(&x, Some(v), &[4096]);
    assert!(!reference.breaths.is_empty());
    for blocks in [vec![1], vec![37, 512, 3], vec![700]] {
        let r = render(&x, Some(v), &blocks);
        assert!(r.audio == reference.audio, "blocks {blocks:?}");
        assert_eq!(r.breaths, reference.breaths);
    }
    let mut e = Engine::new(config(), HeadModel::default_model().clone()).expect("config");
    e.set_learned_voice(Some(v));
    e.prepare(RATE_HZ, 1024, 1).expect("prepare");
    let mut buf = x.clone();
    let mut breaths = 0;
    let mut silence = vec![0.0f32; 1000];
    let ((), n) = watched(|| {
        for chunk in buf.chunks_mut(1000) {
            e.process(&mut [chunk], &mut |_, _| {});
            e.take_breaths(|_| breaths += 1);
        }
        for _ in 0..(e.tail_samples() / 1000 + 1) {
            e.process(&mut [&mut silence[..]], &mut |_, _| {});
            e.take_breaths(|_| breaths += 1);
        }
    });
    assert!(breaths >= 1, "no breath inserted");
    assert_eq!(n, 0, "{n} allocations with a learned voice");
}

/// As [`speaker`], with the breaths of the pauses after `cut_from_s` cut out (an editor's work):
/// the breaths heard before teach the voice, the pauses after get inserted breaths.
fn speaker_cut(seconds: f64, cut_from_s: f64) -> Vec<f32> {
    let with = speaker(seconds, true);
    let without = speaker(seconds, false);
    let cut = (cut_from_s * RATE_HZ) as usize;
    with[..cut].iter().chain(&without[cut..]).copied().collect()
}

/// A stream's engine (lookahead, as the plugin) with `mode`, prepared.
fn stream_engine(mode: BreathVoiceMode) -> Engine {
    let mut c = config();
    c.placement.whole_file = false;
    let mut e = Engine::new(c, HeadModel::default_model().clone()).expect("config");
    e.set_voice_mode(mode);
    e.prepare(RATE_HZ, 1024, 1).expect("prepare");
    e
}

#[test]
fn a_stream_learns_the_breath_as_it_goes_and_inserts_breaths_in_that_voice() {
    let x = speaker_cut(20.0, 10.5);
    let mut e = stream_engine(BreathVoiceMode::Learn);
    assert_eq!(e.voice_status(), VoiceStatus::Learning { breaths: 0 });
    let out = offline::render(&mut e, std::slice::from_ref(&x), &[1024]);
    let VoiceStatus::Learning { breaths } = e.voice_status() else {
        panic!("{:?}", e.voice_status());
    };
    assert!(breaths >= 4, "{breaths} breaths heard");
    let v = *e.learned_voice().expect("a voice learned");
    let want = filter_shape();
    let worst = worst_band_db(&v.shape_db, &want);
    assert!(worst < 1.0, "learned {:.1?} vs {want:.1?}", v.shape_db);
    // The breaths inserted after the cut sound like the speaker's filter, the built-in ones not.
    let inserted_shape = |out: &offline::Rendered| {
        let shapes: Vec<Bands> = out
            .breaths
            .iter()
            .filter(|b| b.start_s > 10.5)
            .map(|b| {
                let s = added(out, &x, b);
                shape_db(&band_powers(&s, RATE_HZ))
            })
            .collect();
        assert!(shapes.len() >= 3, "{} breaths after the cut", shapes.len());
        mean_shape(&shapes)
    };
    let learned = distance_db(&inserted_shape(&out), &want);
    let mut b = stream_engine(BreathVoiceMode::BuiltIn);
    let built_in = distance_db(
        &inserted_shape(&offline::render(&mut b, std::slice::from_ref(&x), &[1024])),
        &want,
    );
    // Each inserted breath varies within the spread learned from a handful of breaths: their
    // mean lies within 2.5 dB (RMS over the bands) of the filter; the built-in voice ~9 dB.
    assert!(
        learned < 2.5 && built_in > 2.0 * learned,
        "inserted breaths {learned:.2} dB from the speaker's shape, built-in {built_in:.2} dB"
    );
}

#[test]
fn learning_as_it_goes_gives_the_same_output_for_any_partition_and_never_allocates() {
    let x = speaker_cut(14.0, 7.0);
    let run = |blocks: &[usize]| {
        let mut e = stream_engine(BreathVoiceMode::Learn);
        let r = offline::render(&mut e, std::slice::from_ref(&x), blocks);
        (r, e.learned_voice().copied())
    };
    let (reference, voice) = run(&[4096]);
    assert!(voice.is_some(), "nothing learned");
    assert!(!reference.breaths.is_empty());
    for blocks in [vec![1], vec![37, 512, 3], vec![700]] {
        let (r, v) = run(&blocks);
        assert!(r.audio == reference.audio, "blocks {blocks:?}");
        assert_eq!(r.breaths, reference.breaths);
        assert_eq!(v, voice, "blocks {blocks:?}");
    }
    let mut e = stream_engine(BreathVoiceMode::Learn);
    let (breaths, n) = streamed_watched(&mut e, &x, |e| {
        // Freezing and thawing happen on a plugin's audio thread too.
        e.freeze_voice();
        e.set_voice_mode(BreathVoiceMode::Learn);
        e.reset();
    });
    assert!(breaths >= 1, "no breath inserted");
    assert_eq!(n, 0, "{n} allocations while learning");
}

#[test]
fn learning_restarts_with_the_stream_and_a_frozen_voice_stays_through_resets() {
    let x = speaker_cut(14.0, 7.0);
    let mut e = stream_engine(BreathVoiceMode::Learn);
    offline::render(&mut e, std::slice::from_ref(&x), &[1024]);
    assert!(e.learned_voice().is_some());
    e.reset();
    assert_eq!(e.voice_status(), VoiceStatus::Learning { breaths: 0 });
    assert_eq!(e.learned_voice(), None, "learning restarts with the stream");
    // Learn again, freeze, then play twice: the same voice and the same audio both times.
    offline::render(&mut e, std::slice::from_ref(&x), &[1024]);
    let frozen = e.freeze_voice().expect("a voice to freeze");
    assert_eq!(
        e.voice_status(),
        VoiceStatus::Fixed {
            breaths: frozen.breaths
        }
    );
    let without_breaths = speaker(8.0, false);
    let play = |e: &mut Engine| {
        e.reset();
        offline::render(e, std::slice::from_ref(&without_breaths), &[512])
    };
    let (one, two) = (play(&mut e), play(&mut e));
    assert!(!one.breaths.is_empty());
    assert!(one.audio == two.audio, "two playbacks differ");
    assert_eq!(e.learned_voice(), Some(&frozen));
    // The frozen voice is plain data: saved (as a plugin's state) and loaded into a new engine,
    // it plays the same.
    let saved = serde_json::to_string(&frozen).expect("serialise");
    let loaded: LearnedVoice = serde_json::from_str(&saved).expect("deserialise");
    assert_eq!(loaded, frozen);
    let mut fresh = stream_engine(BreathVoiceMode::Fixed(loaded));
    let three = offline::render(&mut fresh, std::slice::from_ref(&without_breaths), &[512]);
    assert!(
        three.audio == one.audio,
        "the reloaded voice plays otherwise"
    );
    // Nothing learned yet: freezing keeps the built-in voice.
    let mut early = stream_engine(BreathVoiceMode::Learn);
    assert_eq!(early.freeze_voice(), None);
    assert_eq!(early.voice_status(), VoiceStatus::BuiltIn);
}

/// Least-squares slope over the bands of `d`, dB per band.
fn tilt_db_per_band(d: &Bands) -> f64 {
    let mid = (BANDS as f64 - 1.0) / 2.0;
    let (num, den) = (0..BANDS).fold((0.0, 0.0), |(n, q), k| {
        let x = k as f64 - mid;
        (n + x * d[k], q + x * x)
    });
    num / den
}

#[test]
fn without_breaths_the_built_in_voice_is_coloured_as_the_channel_colours_the_speech() {
    // One recording without breaths, and the same through a tilting EQ (a first-order
    // pre-emphasis: darker lows, brighter highs). The built-in voice's breaths tilt as the
    // speech does. (The generated vowel falls far more steeply than real speech: two
    // pre-emphases first bring it within the colouring's range of real channels.)
    let emphasis = |x: &[f32], a: f32| -> Vec<f32> {
        (0..x.len())
            .map(|i| x[i] - a * if i > 0 { x[i - 1] } else { 0.0 })
            .collect()
    };
    let plain = emphasis(&emphasis(&speaker(12.0, false), 0.9), 0.9);
    let tilted = emphasis(&plain, 0.4);
    // As the plugin (coloured by the speech heard so far), and as a whole-file render
    // (coloured by the whole file's, heard by its learning pass and replayed).
    for whole_file in [false, true] {
        let run = |x: &[f32]| {
            let mut e = if whole_file {
                let mut e =
                    Engine::new(config(), HeadModel::default_model().clone()).expect("config");
                e.set_voice_mode(BreathVoiceMode::BuiltIn);
                e.prepare(RATE_HZ, 1024, 1).expect("prepare");
                let mut l = VoiceLearner::recording(&config(), RATE_HZ).expect("config");
                l.feed(x).expect("prepared");
                let learned = l.finish().expect("prepared");
                assert_eq!(learned.voice, None, "no breath to learn");
                e.replay_analysis(learned.record.expect("recorded"))
                    .expect("same rates");
                e
            } else {
                stream_engine(BreathVoiceMode::Learn)
            };
            let out = offline::render(&mut e, std::slice::from_ref(&x.to_vec()), &[1024]);
            if whole_file {
                assert_eq!(e.voice_status(), VoiceStatus::BuiltIn);
                assert_eq!(e.replay_verified(), Some(true));
            } else {
                assert_eq!(e.voice_status(), VoiceStatus::Learning { breaths: 0 });
            }
            let shapes: Vec<Bands> = out
                .breaths
                .iter()
                .map(|b| {
                    let s = added(&out, x, b);
                    shape_db(&band_powers(&s, RATE_HZ))
                })
                .collect();
            assert!(shapes.len() >= 4, "{} breaths", shapes.len());
            (mean_shape(&shapes), shape_db(&band_powers(x, RATE_HZ)))
        };
        let (breath_a, speech_a) = run(&plain);
        let (breath_b, speech_b) = run(&tilted);
        let speech_tilt = tilt_db_per_band(&std::array::from_fn(|k| speech_b[k] - speech_a[k]));
        let breath_tilt = tilt_db_per_band(&std::array::from_fn(|k| breath_b[k] - breath_a[k]));
        assert!(
            speech_tilt > 0.3,
            "the EQ tilts the speech by {speech_tilt:.2} dB/band"
        );
        assert!(
        (breath_tilt - speech_tilt).abs() < 0.1 * speech_tilt.abs() + 0.05,
        "whole file {whole_file}: speech tilted {speech_tilt:.2} dB/band, the breaths {breath_tilt:.2}"
    );
    }
}

#[test]
fn another_takes_voice_keeps_its_level_under_this_streams_speech() {
    // The take the voice is learned from, and a recording of the same speaker 12 dB quieter
    // whose breaths were edited out: breaths drawn from the take's voice lie as far under this
    // recording's speech as the take's lie under its own (`Like`), where a voice fixed at the
    // take's levels would be 12 dB too loud.
    let take = speaker(14.0, true);
    let v = learn_voice(&config(), &take, RATE_HZ)
        .expect("settings")
        .expect("the take's breaths are heard");
    let quiet: Vec<f32> = speaker(12.0, false).iter().map(|x| x * 0.25).collect();
    let median_level = |mode: BreathVoiceMode| {
        let mut e = stream_engine(mode);
        let out = offline::render(&mut e, std::slice::from_ref(&quiet), &[1024]);
        let mut levels: Vec<f64> = out
            .breaths
            .iter()
            .map(|b| {
                let s = added(&out, &quiet, b);
                band_level_db(&band_powers(&s, RATE_HZ), RATE_HZ)
            })
            .collect();
        assert!(levels.len() >= 4, "{} breaths", levels.len());
        levels.sort_by(f64::total_cmp);
        levels[levels.len() / 2]
    };
    let like = median_level(BreathVoiceMode::Like(v));
    let fixed = median_level(BreathVoiceMode::Fixed(v));
    let want = v.level_db() - 12.04;
    assert!(
        (like - want).abs() < 2.0,
        "Like: {like:.1} dBFS, the take's level under this speech {want:.1}"
    );
    assert!(
        (fixed - like - 12.04).abs() < 1.0,
        "Fixed {fixed:.1} vs Like {like:.1} dBFS"
    );
}

#[test]
fn learning_resumes_when_switched_on_mid_stream() {
    // A plugin user turns the freeze off during playback (fixed → learn), or the voice was
    // built in (built-in → learn): the breaths after the switch are heard and learned, as a
    // stream learning from the start hears them.
    let x = speaker(30.0, true);
    let switch_at = 160_000; // 10 s in, on a block boundary
    let run = |before: BreathVoiceMode| {
        let mut e = stream_engine(before);
        let mut buf = x.clone();
        for (k, chunk) in buf.chunks_mut(1000).enumerate() {
            if k * 1000 == switch_at {
                e.set_voice_mode(BreathVoiceMode::Learn);
                assert_eq!(e.voice_status(), VoiceStatus::Learning { breaths: 0 });
            }
            e.process(&mut [chunk], &mut |_, _| {});
        }
        e.voice_status()
    };
    let mut from_start = stream_engine(BreathVoiceMode::Learn);
    let mut buf = x.clone();
    let mut heard_before_switch = 0;
    for (k, chunk) in buf.chunks_mut(1000).enumerate() {
        if k * 1000 == switch_at {
            if let VoiceStatus::Learning { breaths } = from_start.voice_status() {
                heard_before_switch = breaths;
            }
        }
        from_start.process(&mut [chunk], &mut |_, _| {});
    }
    let VoiceStatus::Learning { breaths: all } = from_start.voice_status() else {
        panic!("{:?}", from_start.voice_status());
    };
    let after_switch = all - heard_before_switch;
    assert!(after_switch >= 5, "{after_switch} breaths after 10 s");
    let frozen = dark_voice();
    for before in [BreathVoiceMode::BuiltIn, BreathVoiceMode::Fixed(frozen)] {
        assert_eq!(
            run(before),
            VoiceStatus::Learning {
                breaths: after_switch
            },
            "switched from {before:?}"
        );
    }
}

#[test]
fn two_voices_in_one_recording_learn_one_voice_between_them() {
    // An interview: two speakers take turns, one breathing darker (300 Hz–3 kHz), one brighter
    // (800 Hz–5 kHz; a breath with nothing under 1 kHz stands over the shipped breath shape
    // limit and is not heard in a quiet room). Pneuma learns one voice from every breath it
    // hears: on the labelled breaths of eleven real speakers such a blend lies nearer each
    // speaker's breaths than the built-in voice does, and one speaker's own breaths split as far
    // apart as two speakers' (`pneuma eval restore`, DESIGN.md). The blend lies between the
    // two voices, and its spread covers both.
    let (dark_hz, bright_hz) = ((300.0, 3000.0), (800.0, 5000.0));
    let learn = |bands: &[(f64, f64)]| {
        let x = signals::phrases_with_breaths_through(RATE_HZ, 24.0, 5, bands);
        learn_voice(&config(), &x, RATE_HZ)
            .expect("settings")
            .unwrap_or_else(|| panic!("breaths heard {bands:?}"))
    };
    let (dark, bright, both) = (
        learn(&[dark_hz]),
        learn(&[bright_hz]),
        learn(&[dark_hz, bright_hz]),
    );
    assert!(
        both.breaths >= dark.breaths.min(bright.breaths),
        "{} breaths from both",
        both.breaths
    );
    let apart = distance_db(&dark.shape_db, &bright.shape_db);
    assert!(apart > 3.0, "the two voices lie {apart:.1} dB apart");
    for (name, one) in [("dark", &dark), ("bright", &bright)] {
        let d = distance_db(&both.shape_db, &one.shape_db);
        assert!(
            d < 0.75 * apart,
            "the blend lies {d:.1} dB from the {name} voice, the voices {apart:.1} dB apart"
        );
    }
    for k in 0..BANDS {
        let (lo, hi) = (
            dark.shape_db[k].min(bright.shape_db[k]),
            dark.shape_db[k].max(bright.shape_db[k]),
        );
        assert!(
            both.shape_db[k] > lo - 1.5 && both.shape_db[k] < hi + 1.5,
            "band {k}: blend {:.1} dB outside the two voices {lo:.1}..{hi:.1}",
            both.shape_db[k]
        );
    }
    let mean_sd = |v: &LearnedVoice| v.shape_sd_db.iter().sum::<f64>() / BANDS as f64;
    assert!(
        mean_sd(&both) > mean_sd(&dark).max(mean_sd(&bright)),
        "spread: blend {:.2} dB, dark {:.2}, bright {:.2}",
        mean_sd(&both),
        mean_sd(&dark),
        mean_sd(&bright)
    );
}
