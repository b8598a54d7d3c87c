//! The engine on generated phrase sequences with known pauses: breath count and placement, no
//! breath in short pauses or on speech, bit-exact output outside breaths, partition invariance,
//! noise at 10 dB SNR, a pause that already holds a breath, live mode, the stereo image and the
//! breathing controls.

use pneuma_core::analysis::rms;
use pneuma_core::engine::offline::{self, Rendered};
use pneuma_core::engine::{ConfigChange, Dropped, Engine, EngineConfig, PlacementMode};
use pneuma_core::head::HeadModel;
use pneuma_core::rng::SeededRng;
use pneuma_core::{ControlFrame, Phase};
use pneuma_testkit::signals;

use crate::generated_phrases::{phrase, sequence, SR};

/// Runs the engine over `input` (one Vec per channel) in the given block sizes (cycled), then
/// flushes the latency and removes it, as an offline render does.
fn render(config: &EngineConfig, input: &[Vec<f32>], blocks: &[usize]) -> Rendered {
    let mut engine = Engine::new(config.clone(), HeadModel::default_model().clone()).unwrap();
    let max_block = blocks.iter().copied().max().unwrap();
    engine.prepare(SR, max_block, input.len()).unwrap();
    offline::render(&mut engine, input, blocks)
}

fn config() -> EngineConfig {
    EngineConfig::default()
}

/// Samples where output and input differ.
fn changed(input: &[f32], output: &[f32]) -> Vec<usize> {
    input
        .iter()
        .zip(output)
        .enumerate()
        .filter(|(_, (a, b))| a.to_bits() != b.to_bits())
        .map(|(i, _)| i)
        .collect()
}

#[test]
fn breaths_go_into_long_pauses_only_and_end_before_the_next_phrase() {
    let pauses = [0.15, 0.2, 0.4, 0.8, 2.0, 0.3];
    let (audio, spans) = sequence(0.6, &[1.2, 0.9, 1.5, 1.0, 2.0, 0.8, 1.1], &pauses);
    let c = config();
    let r = render(&c, std::slice::from_ref(&audio), &[512]);
    // Expected: one breath before the first phrase (0.6 s lead-in) and one in every pause of at
    // least the minimum (0.25 s).
    let expected: Vec<usize> = std::iter::once(0)
        .chain(
            pauses
                .iter()
                .enumerate()
                .filter(|(_, p)| **p >= 0.25)
                .map(|(i, _)| i + 1),
        )
        .collect();
    assert_eq!(r.breaths.len(), expected.len(), "{:?}", r.breaths);
    for (b, &phrase) in r.breaths.iter().zip(&expected) {
        let onset = spans[phrase].0;
        let pause_start = if phrase == 0 {
            0.0
        } else {
            spans[phrase - 1].1
        };
        assert!(
            b.start_s >= pause_start,
            "{b:?} starts in speech (pause from {pause_start})"
        );
        assert!(
            b.end_s <= onset - 0.02 && b.end_s >= onset - 0.1,
            "{b:?} should end shortly before the onset at {onset}"
        );
        assert!(b.end_s - b.start_s >= 0.12, "{b:?} too short");
        assert!(b.peak_db < -10.0 && b.peak_db > -60.0, "{b:?}");
    }
    // Everything else is the input, bit for bit, and every changed sample lies in a breath.
    for i in changed(&audio, &r.audio[0]) {
        let t = i as f64 / SR;
        assert!(
            r.breaths
                .iter()
                .any(|b| t >= b.start_s - 1e-3 && t <= b.end_s + 1e-3),
            "sample at {t:.4} s changed outside every breath"
        );
        assert!(
            !spans.iter().any(|&(on, off)| t >= on && t < off),
            "breath on speech at {t:.4} s"
        );
    }
}

#[test]
fn breaths_are_quieter_than_the_speech_and_follow_the_level_setting() {
    let (audio, _) = sequence(0.6, &[1.5, 1.5, 1.5], &[0.8, 0.8]);
    let speech_rms = rms(&audio
        .iter()
        .copied()
        .filter(|x| *x != 0.0)
        .collect::<Vec<_>>());
    let mut levels = Vec::new();
    for db in [-30.0f32, -18.0] {
        let mut c = config();
        c.placement.breath_level_db = db;
        let r = render(&c, std::slice::from_ref(&audio), &[256]);
        assert!(!r.breaths.is_empty());
        let diff: Vec<f32> = audio.iter().zip(&r.audio[0]).map(|(a, b)| b - a).collect();
        let b = r.breaths[1];
        let seg = &diff[(b.start_s * SR) as usize..(b.end_s * SR) as usize];
        let rel_db = 20.0 * (rms(seg) / speech_rms).log10();
        assert!(rel_db < -6.0, "breath at {rel_db:.1} dB re speech");
        levels.push(rel_db);
    }
    let step = levels[1] - levels[0];
    assert!(
        (step - 12.0).abs() < 3.0,
        "12 dB more level gave {step:.1} dB: {levels:?}"
    );
}

#[test]
fn breaths_follow_the_breathing_sound_amplitude() {
    // The breathing parameters' sound amplitude (`breath_sound`, what the presets set) moves
    // the breaths' level as the level setting does, whatever voice plays; 0 is silent.
    let (audio, _) = sequence(0.6, &[1.5, 1.5, 1.5], &[0.8, 0.8]);
    let breath_rms = |amplitude: f32| {
        let mut c = config();
        c.breathing.amplitude_breathing_sound = amplitude;
        let r = render(&c, std::slice::from_ref(&audio), &[256]);
        let diff: Vec<f32> = audio.iter().zip(&r.audio[0]).map(|(a, b)| b - a).collect();
        let b = r.breaths[1];
        rms(&diff[(b.start_s * SR) as usize..(b.end_s * SR) as usize])
    };
    let neutral = config().breathing.amplitude_breathing_sound;
    let step_db = 20.0 * (breath_rms(2.0 * neutral) / breath_rms(neutral)).log10();
    assert!(
        (step_db - 6.02).abs() < 1.5,
        "twice the amplitude gave {step_db:.1} dB"
    );
    assert_eq!(
        breath_rms(0.0),
        0.0,
        "a silent breathing sound still sounds"
    );
}

#[test]
fn any_block_partition_gives_identical_audio_and_controls() {
    let (audio, _) = sequence(0.4, &[0.8, 0.6, 0.9], &[0.6, 0.3]);
    let c = config();
    let reference = render(&c, std::slice::from_ref(&audio), &[4096]);
    let mut rng = SeededRng::new(9);
    let random: Vec<usize> = (0..64)
        .map(|_| 1 + (rng.uniform() * 700.0) as usize)
        .collect();
    for blocks in [vec![1], vec![37], vec![512], random] {
        let r = render(&c, std::slice::from_ref(&audio), &blocks);
        assert_eq!(
            r.audio,
            reference.audio,
            "blocks {:?}",
            &blocks[..blocks.len().min(3)]
        );
        assert_eq!(r.breaths, reference.breaths);
        let a: Vec<_> = r.frames.iter().map(|f| f.0).collect();
        let b: Vec<_> = reference.frames.iter().map(|f| f.0).collect();
        assert_eq!(a, b);
    }
}

#[test]
fn stereo_partitions_agree_too() {
    let (audio, _) = sequence(0.4, &[0.8, 0.6], &[0.6]);
    let right: Vec<f32> = audio.iter().map(|x| -0.5 * x).collect();
    let input = [audio, right];
    let c = config();
    let reference = render(&c, &input, &[1024]);
    for blocks in [vec![1], vec![37, 500, 3]] {
        let r = render(&c, &input, &blocks);
        assert_eq!(r.audio, reference.audio);
        assert_eq!(r.breaths, reference.breaths);
    }
    assert!(!reference.breaths.is_empty());
}

#[test]
fn noise_at_10_db_snr_still_gets_breaths_in_the_pauses_and_none_on_speech() {
    let pauses = [0.8, 1.2, 0.6];
    let (mut audio, spans) = sequence(0.8, &[1.5, 1.2, 1.8, 1.0], &pauses);
    let clean = audio.clone();
    let speech_rms = rms(&clean
        .iter()
        .copied()
        .filter(|x| *x != 0.0)
        .collect::<Vec<_>>());
    let noise = signals::white_noise(audio.len(), speech_rms / 10f64.powf(0.5), 3);
    for (x, n) in audio.iter_mut().zip(&noise) {
        *x += n;
    }
    let r = render(&config(), std::slice::from_ref(&audio), &[512]);
    for (i, _) in pauses.iter().enumerate() {
        let (off, on) = (spans[i].1, spans[i + 1].0);
        assert!(
            r.breaths.iter().any(|b| b.start_s >= off && b.end_s <= on),
            "no breath in the pause {off:.2}–{on:.2}: {:?}",
            r.breaths
        );
    }
    for b in &r.breaths {
        for &(on, off) in &spans {
            assert!(
                b.end_s <= on || b.start_s >= off,
                "{b:?} overlaps {on}–{off}"
            );
        }
    }
}

#[test]
fn a_pause_that_already_holds_a_breath_gets_no_second_one() {
    let (mut audio, spans) = sequence(0.6, &[1.5, 1.5, 1.5], &[1.0, 1.0]);
    // A real-ish breath in the second pause: band-limited noise, 400 ms, 24 dB under speech,
    // with 50 ms fades.
    let speech_rms = rms(&audio
        .iter()
        .copied()
        .filter(|x| *x != 0.0)
        .collect::<Vec<_>>());
    let start = ((spans[1].1 + 0.3) * SR) as usize;
    let len = (0.4 * SR) as usize;
    // Breath noise is broadband from about 0.5 to 5 kHz (the phrase tracker checks the shape).
    let noise = signals::band_noise(len, SR, (500.0, 5000.0), 1.0, 11);
    let g = (speech_rms / rms(&noise) * 10f64.powf(-24.0 / 20.0)) as f32;
    let fade = (0.05 * SR) as usize;
    for (i, n) in noise.iter().enumerate() {
        let env = (i.min(len - 1 - i) as f32 / fade as f32).min(1.0);
        audio[start + i] += g * env * n;
    }
    let r = render(&config(), std::slice::from_ref(&audio), &[512]);
    let in_pause = |i: usize| {
        let (off, on) = (spans[i].1, spans[i + 1].0);
        r.breaths
            .iter()
            .filter(|b| b.start_s >= off && b.end_s <= on)
            .count()
    };
    assert_eq!(in_pause(0), 1, "{:?}", r.breaths);
    assert_eq!(
        in_pause(1),
        0,
        "the pause with a breath got another: {:?}",
        r.breaths
    );
}

#[test]
fn no_breaths_setting_passes_the_audio_unchanged_and_keeps_the_controls() {
    let (audio, _) = sequence(0.6, &[1.0, 1.0], &[0.8]);
    let mut c = config();
    c.placement.insert_breaths = false;
    let r = render(&c, std::slice::from_ref(&audio), &[333]);
    assert!(r.breaths.is_empty());
    assert!(changed(&audio, &r.audio[0]).is_empty());
    assert!(r
        .frames
        .iter()
        .any(|f| f.0.breathing.phase == Phase::Expiration));
    // The body still breathes in before each phrase.
    let insp = r
        .frames
        .iter()
        .filter(|f| f.0.breathing.phase == Phase::Inspiration)
        .count();
    assert!(
        insp > 20,
        "{insp} inspiration frames without inserted breaths"
    );
    let max_lung = r
        .frames
        .iter()
        .map(|f| f.0.breathing.lung)
        .fold(0.0, f32::max);
    assert!(max_lung > 0.2, "lung at most {max_lung}");
}

#[test]
fn a_word_too_short_to_confirm_is_never_covered_by_a_breath() {
    // A 1.4 s pause with a 0.1 s vowel in its middle (too short to become a phrase).
    let (mut audio, spans) = sequence(0.6, &[1.2, 1.2], &[1.4]);
    let word = phrase(0.1, 42);
    let at = ((spans[0].1 + 0.7) * SR) as usize;
    audio[at..at + word.len()].copy_from_slice(&word);
    let (w0, w1) = (at as f64 / SR, (at + word.len()) as f64 / SR);
    let r = render(&config(), std::slice::from_ref(&audio), &[512]);
    // The pause still gets its breath, after the word.
    assert!(
        r.breaths
            .iter()
            .any(|b| b.start_s >= w1 && b.end_s <= spans[1].0),
        "no breath between the word and the next phrase: {:?}",
        r.breaths
    );
    for b in &r.breaths {
        assert!(
            b.end_s <= w0 || b.start_s >= w1,
            "{b:?} covers the word at {w0:.2}–{w1:.2}"
        );
    }
    assert!(changed(&audio, &r.audio[0]).iter().all(|&i| {
        let t = i as f64 / SR;
        t < w0 || t >= w1
    }));
}

#[test]
fn a_stream_cut_inside_a_word_gets_no_breath_before_its_first_phrase() {
    // The edit cut into a word: the stream starts on its /s/ (10 dB under the speech), then a
    // 30 ms closure and the phrases. The start is no pause.
    let (speech, spans) = sequence(0.0, &[1.5, 1.5], &[0.8]);
    let speech_rms = rms(&speech[..(1.5 * SR) as usize]);
    let s_len = (0.2 * SR) as usize;
    let mut audio = signals::band_noise(s_len, SR, (4000.0, 8000.0), speech_rms / 3.16, 7);
    audio.extend(std::iter::repeat_n(0.0, (0.03 * SR) as usize));
    let lead_s = audio.len() as f64 / SR;
    audio.extend(&speech);
    let r = render(&config(), std::slice::from_ref(&audio), &[512]);
    let first_onset_s = lead_s + spans[0].0;
    assert!(
        r.breaths.iter().all(|b| b.start_s >= first_onset_s),
        "a breath on the cut word before the first phrase at {first_onset_s:.2} s: {:?}",
        r.breaths
    );
    // The pause between the phrases still gets its breath.
    let pause = (lead_s + spans[0].1, lead_s + spans[1].0);
    assert!(
        r.breaths
            .iter()
            .any(|b| b.start_s >= pause.0 && b.end_s <= pause.1),
        "no breath in the pause {pause:?}: {:?}",
        r.breaths
    );
}

#[test]
fn a_stream_that_starts_in_steady_room_noise_keeps_its_breath_before_the_first_phrase() {
    // Room noise 15 dB under the speech from the first sample: no word was cut, the level never
    // falls; the 0.6 s lead-in gets its breath as a silent one does.
    let (mut audio, spans) = sequence(0.6, &[1.5, 1.5], &[0.8]);
    let speech_rms = rms(&audio[(0.6 * SR) as usize..]);
    let noise = signals::white_noise(audio.len(), speech_rms * 10f64.powf(-0.75), 11);
    audio.iter_mut().zip(&noise).for_each(|(a, n)| *a += n);
    let r = render(&config(), std::slice::from_ref(&audio), &[512]);
    assert!(
        r.breaths.iter().any(|b| b.end_s <= spans[0].0),
        "no breath before the first phrase at {:.2} s: {:?}",
        spans[0].0,
        r.breaths
    );
}

#[test]
fn the_first_breath_follows_the_level_of_quiet_and_loud_speech() {
    let (audio, spans) = sequence(0.8, &[1.5, 1.5], &[0.8]);
    let speech: Vec<f32> = audio.iter().copied().filter(|x| *x != 0.0).collect();
    let speech_db = 20.0 * rms(&speech).log10();
    // (Speech far under the analysis's −26 dBFS speech-level prior is voiced only once the
    // level has adapted: at −45 dBFS the first onset is found ~0.1 s late and gets no breath.)
    let mut rel = Vec::new();
    for target_db in [-40.0, -30.0, -17.0] {
        let g = 10f64.powf((target_db - speech_db) / 20.0) as f32;
        let scaled: Vec<f32> = audio.iter().map(|x| x * g).collect();
        let r = render(&config(), std::slice::from_ref(&scaled), &[512]);
        let b = r
            .breaths
            .first()
            .unwrap_or_else(|| panic!("{target_db} dBFS: no breath at all"));
        assert!(
            b.end_s <= spans[0].0,
            "{target_db}: {b:?} onset {}",
            spans[0].0
        );
        let diff: Vec<f32> = scaled.iter().zip(&r.audio[0]).map(|(a, b)| b - a).collect();
        let seg = &diff[(b.start_s * SR) as usize..(b.end_s * SR) as usize];
        let rel_db = 20.0 * rms(seg).log10() - target_db;
        // Real inhalations lie 15–40 dB under the speech (the labelled breaths: −21 to −38).
        assert!(
            (-40.0..=-15.0).contains(&rel_db),
            "speech at {target_db} dBFS: first breath at {rel_db:.1} dB re speech"
        );
        rel.push(rel_db);
    }
    // The same breath (same seed) under speech at any level: the same level re the speech.
    let spread =
        rel.iter().fold(f64::MIN, |m, &x| m.max(x)) - rel.iter().fold(f64::MAX, |m, &x| m.min(x));
    assert!(
        spread < 3.0,
        "first breath re speech at −40/−30/−17 dBFS: {rel:.1?}"
    );
}

#[test]
fn a_moving_stereo_image_gives_the_same_result_for_any_partition() {
    let (voice, _) = sequence(0.5, &[1.0, 1.0, 1.0], &[0.7, 0.7]);
    // The voice pans from left to right over the file.
    let n = voice.len() as f32;
    let left: Vec<f32> = voice
        .iter()
        .enumerate()
        .map(|(i, x)| x * (1.0 - i as f32 / n))
        .collect();
    let right: Vec<f32> = voice
        .iter()
        .enumerate()
        .map(|(i, x)| x * (i as f32 / n))
        .collect();
    let input = [left, right];
    let reference = render(&config(), &input, &[4096]);
    assert!(reference.breaths.len() >= 2);
    for blocks in [vec![37], vec![1, 700, 64]] {
        let r = render(&config(), &input, &blocks);
        assert_eq!(r.audio, reference.audio);
        assert_eq!(r.breaths, reference.breaths);
        assert_eq!(
            r.frames, reference.frames,
            "frames and their sample positions"
        );
    }
}

#[test]
fn every_frame_of_the_stream_comes_out_in_both_modes() {
    let (audio, _) = sequence(0.3, &[1.0, 0.8], &[0.6]);
    let expected = pneuma_core::analysis::FrameClock::new(120.0, SR).frames_in(audio.len() as u64);
    for mode in [PlacementMode::Lookahead, PlacementMode::Live] {
        let mut c = config();
        c.placement.mode = mode;
        let r = render(&c, std::slice::from_ref(&audio), &[256]);
        // In order, none twice, none missing, the whole stream (the tail flush may add more).
        let indices: Vec<u64> = r.frames.iter().map(|f| f.0.index).collect();
        assert!(
            indices.len() as u64 >= expected,
            "{mode:?}: {}",
            indices.len()
        );
        assert!(
            indices.iter().copied().eq(0..indices.len() as u64),
            "{mode:?}: frame indices are not 0, 1, 2, …: {indices:?}"
        );
    }
}

#[test]
fn breaths_switched_off_mid_stream_fade_the_one_playing_and_start_no_more() {
    // The plugin's bypass switches breath insertion off: a breath already playing fades out
    // at once, and breaths placed before the switch (live mode places them a minimum pause
    // ahead; lookahead mode up to its lookahead) do not sound.
    let (audio, _) = sequence(0.6, &[1.2; 6], &[0.8; 5]);
    for mode in [PlacementMode::Live, PlacementMode::Lookahead] {
        let mut c = config();
        c.placement.mode = mode;
        let run = |off_at: Option<usize>| {
            let mut engine = Engine::new(c.clone(), HeadModel::default_model().clone()).unwrap();
            engine.prepare(SR, 256, 1).unwrap();
            let mut out = audio.clone();
            for (k, chunk) in out.chunks_mut(256).enumerate() {
                if Some(k * 256) == off_at {
                    let mut off = c.clone();
                    off.placement.insert_breaths = false;
                    engine.set_config(&off).unwrap();
                }
                engine.process(&mut [chunk], &mut |_, _| {});
            }
            out
        };
        let latency = {
            let mut e = Engine::new(c.clone(), HeadModel::default_model().clone()).unwrap();
            e.prepare(SR, 256, 1).unwrap();
            e.latency_samples() as usize
        };
        // The output (delayed by the latency) against the input.
        let added = |out: &[f32]| -> Vec<usize> {
            (latency..out.len())
                .filter(|&i| out[i] != audio[i - latency])
                .collect()
        };
        let on = added(&run(None));
        let first = *on.first().unwrap_or_else(|| panic!("{mode:?}: no breath"));
        // Switched off 20 ms into the first breath.
        let at = (first + (0.02 * SR) as usize) / 256 * 256;
        let off = added(&run(Some(at)));
        let fade = (c.placement.live_fade_s as f64 * SR) as usize + 256;
        let last = off.last().copied().unwrap_or(0);
        assert!(
            last <= at + fade,
            "{mode:?}: breath sound at output sample {last}, switched off at {at}"
        );
        assert!(on.len() > off.len(), "{mode:?}");
    }
}

#[test]
fn settings_change_while_playing_without_changing_the_frame_clock() {
    let (audio, _) = sequence(0.3, &[1.0, 1.0], &[0.6]);
    let mut engine = Engine::new(config(), HeadModel::default_model().clone()).unwrap();
    engine.prepare(SR, 512, 1).unwrap();
    let mut buf = audio.clone();
    let mut times = Vec::new();
    for (k, chunk) in buf.chunks_mut(512).enumerate() {
        if k == 10 {
            let mut c = config();
            c.analysis.frame_rate_hz = 30.0; // takes effect at the next prepare only
            c.placement.breath_level_db = -30.0;
            c.head.amount = 0.5;
            engine.set_config(&c).unwrap();
        }
        engine.process(&mut [chunk], &mut |f, _| times.push(f.time_s));
    }
    assert!(times.len() > 100);
    for w in times.windows(2) {
        assert!(
            (w[1] - w[0] - 1.0 / 120.0).abs() < 1e-9,
            "frame step {}",
            w[1] - w[0]
        );
    }
    let mut bad = config();
    bad.placement.breath_level_db = 3.0;
    assert!(
        engine.set_config(&bad).is_err(),
        "a breath louder than speech is refused"
    );
}

#[test]
fn live_mode_adds_no_latency_and_breathes_after_the_pause_is_confirmed() {
    let pauses = [1.0, 0.8];
    let (audio, spans) = sequence(0.6, &[1.2, 1.2, 1.2], &pauses);
    let mut c = config();
    c.placement.mode = PlacementMode::Live;
    let r = render(&c, std::slice::from_ref(&audio), &[128]);
    assert_eq!(r.latency_samples, 0);
    for (i, _) in pauses.iter().enumerate() {
        let off = spans[i].1;
        let b = r
            .breaths
            .iter()
            .find(|b| b.start_s > off && b.start_s < spans[i + 1].0)
            .unwrap_or_else(|| panic!("no live breath after {off}: {:?}", r.breaths));
        // Confirmed after the hangover (0.15 s) plus the analysis delay.
        assert!(
            b.start_s - off > 0.1 && b.start_s - off < 0.3,
            "{b:?} after {off}"
        );
    }
}

#[test]
fn a_live_breath_fades_out_when_speech_resumes() {
    // The pause is shorter than the inspiration: speech resumes during the breath.
    let (audio, spans) = sequence(0.6, &[1.2, 1.2], &[0.45]);
    let mut c = config();
    c.placement.mode = PlacementMode::Live;
    let r = render(&c, std::slice::from_ref(&audio), &[64]);
    let b = r
        .breaths
        .iter()
        .find(|b| b.start_s > spans[0].1)
        .expect("a live breath in the pause");
    // It ends within the onset confirmation + fade (< 100 ms) after speech resumes.
    assert!(
        b.end_s < spans[1].0 + 0.1,
        "{b:?}, speech resumes at {}",
        spans[1].0
    );
}

#[test]
fn on_stereo_input_the_breath_sits_in_the_voice_image() {
    let (voice, _) = sequence(0.6, &[1.2, 1.2, 1.2], &[0.8, 0.8]);
    // Voice panned left: right channel at a quarter of the amplitude.
    let left = voice.clone();
    let right: Vec<f32> = voice.iter().map(|x| x * 0.25).collect();
    let r = render(&config(), &[left.clone(), right.clone()], &[512]);
    assert!(!r.breaths.is_empty());
    let dl: Vec<f32> = left.iter().zip(&r.audio[0]).map(|(a, b)| b - a).collect();
    let dr: Vec<f32> = right.iter().zip(&r.audio[1]).map(|(a, b)| b - a).collect();
    let ratio_db = 20.0 * (rms(&dl) / rms(&dr)).log10();
    assert!(
        (ratio_db - 12.0).abs() < 2.0,
        "breath L/R {ratio_db:.1} dB, voice 12 dB"
    );
}

#[test]
fn a_breath_between_two_speakers_sits_on_the_side_of_the_one_who_speaks_next() {
    // An interview in stereo: the host (left, the right channel 12 dB down) speaks two
    // phrases, the guest (the mirror image) two more. The breath before the guest's first
    // phrase is the guest's: in a render (8 s of lookahead) on the guest's side, as the
    // guest's voice is. (The plugin's 500 ms decide it before the image has moved far.)
    let (voice, spans) = sequence(0.6, &[1.2, 1.2, 1.2, 1.2], &[0.8, 0.8, 0.8]);
    let turn = ((spans[1].1 + spans[2].0) / 2.0 * SR) as usize;
    let quiet = |k: usize, host_side: bool| if (k < turn) == host_side { 1.0 } else { 0.25 };
    let left: Vec<f32> = voice
        .iter()
        .enumerate()
        .map(|(k, x)| x * quiet(k, true))
        .collect();
    let right: Vec<f32> = voice
        .iter()
        .enumerate()
        .map(|(k, x)| x * quiet(k, false))
        .collect();
    let mut c = config();
    c.placement.whole_file = true;
    let r = render(&c, &[left.clone(), right.clone()], &[512]);
    let b = r
        .breaths
        .iter()
        .find(|b| b.start_s > spans[1].1 && b.end_s <= spans[2].0 + 0.01)
        .unwrap_or_else(|| panic!("no breath at the turn: {:?}", r.breaths));
    let span = (b.start_s * SR) as usize..(b.end_s * SR) as usize;
    let added = |input: &[f32], out: &[f32]| -> Vec<f32> {
        input[span.clone()]
            .iter()
            .zip(&out[span.clone()])
            .map(|(a, o)| o - a)
            .collect()
    };
    let ratio_db =
        20.0 * (rms(&added(&right, &r.audio[1])) / rms(&added(&left, &r.audio[0]))).log10();
    assert!(
        (ratio_db - 12.0).abs() < 3.0,
        "the turn's breath R/L {ratio_db:.1} dB, the guest's voice 12 dB"
    );
}

#[test]
fn a_breath_is_as_loud_as_the_voice_of_the_speaker_who_speaks_next() {
    // A mono interview: the host's phrases at full level, the guest's 12 dB under, in runs
    // of two. Each breath plays under the speaker after it: those before the guest's phrases
    // lie about 12 dB under those before the host's in a render (8 s of lookahead). With the
    // plugin's 500 ms, which has heard only the rising onset of the phrase after a breath (too
    // little to tell a new speaker by: the breath before a turn takes the level of the speaker
    // before it), within a turn: the guest's breaths lie under the host's, the host's against
    // the running speech level (the guest drags it down), the guest's against the guest's own.
    // (The whole recording's level for every breath made the guest's breaths 12 dB too loud
    // against the guest.)
    let (voice, spans) = sequence(0.6, &[1.2; 8], &[0.8; 7]);
    let guest = |k: usize| (k / 2) % 2 == 1;
    let mut x = voice.clone();
    for (k, &(a, b)) in spans.iter().enumerate() {
        if guest(k) {
            let (a, b) = ((a - 0.4) * SR, (b + 0.4) * SR);
            for v in &mut x[(a.max(0.0) as usize)..(b as usize).min(voice.len())] {
                *v *= 0.25;
            }
        }
    }
    for whole_file in [true, false] {
        let mut c = config();
        c.placement.whole_file = whole_file;
        let r = render(&c, std::slice::from_ref(&x), &[512]);
        let (mut host, mut guests) = (Vec::new(), Vec::new());
        // The plugin's breaths before a turn, by the speaker before it.
        let (mut after_host, mut after_guest) = (Vec::new(), Vec::new());
        for b in &r.breaths {
            // The phrase after the breath.
            let Some(k) = spans.iter().position(|&(a, _)| a >= b.end_s - 0.01) else {
                continue;
            };
            let span = (b.start_s * SR) as usize..(b.end_s * SR) as usize;
            let added: Vec<f32> = (x[span.clone()].iter().zip(&r.audio[0][span]))
                .map(|(a, o)| o - a)
                .collect();
            let db = 20.0 * rms(&added).log10();
            let turn = k > 0 && guest(k) != guest(k - 1);
            match (whole_file || !turn, guest(k)) {
                (true, true) => guests.push(db),
                (true, false) => host.push(db),
                (false, true) => after_host.push(db),
                (false, false) => after_guest.push(db),
            }
        }
        assert!(
            !host.is_empty() && !guests.is_empty(),
            "whole file {whole_file}: breaths before the host {host:?}, the guest {guests:?}"
        );
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let apart_db = mean(&host) - mean(&guests);
        let expected_db = if whole_file { 9.0..15.0 } else { 3.0..15.0 };
        assert!(
            expected_db.contains(&apart_db),
            "whole file {whole_file}: host's breaths {host:?} dB, guest's {guests:?} dB"
        );
        // The plugin places breaths before turns too (their level: the unit test
        // `a_phrase_heard_for_less_than_the_speech_window_keeps_the_last_speaker_level`).
        assert!(
            whole_file || !(after_host.is_empty() || after_guest.is_empty()),
            "no breath before a turn: {after_host:?} {after_guest:?}"
        );
    }
}

#[test]
fn speech_from_the_first_frames_starts_breathed_in_without_a_twitch_of_inspiration() {
    // Speech 0–100 ms into the stream: no room for a breath before it. The controls start
    // breathed in, or with an inspiration as long as a short breath; never one of a frame or
    // two (a blink of the mouth and nostrils on VMC and MIDI).
    for lead_s in [0.0, 0.01, 0.02, 0.05, 0.1] {
        let (audio, _) = sequence(lead_s, &[1.5, 1.5], &[0.8]);
        let c = config();
        let r = render(&c, std::slice::from_ref(&audio), &[512]);
        let first: Vec<Phase> = r.frames.iter().map(|f| f.0.breathing.phase).collect();
        let inspiring = first
            .iter()
            .take_while(|&&p| p == Phase::Inspiration)
            .count();
        // A short breath lasts 0.1 s or more.
        let short_breath = (0.1 * c.analysis.frame_rate_hz).round() as usize;
        assert!(
            inspiring == 0 || inspiring >= short_breath,
            "lead {lead_s} s: {inspiring} inspiration frames first: {:?}",
            &first[..inspiring + 2]
        );
        // Breathed in: where the body speaks from the first phrase on, the lung holds at least
        // a breath's volume from the first frame.
        let speaks = r.frames.iter().take(short_breath * 3).any(|f| f.0.speaking);
        if inspiring == 0 && speaks {
            let lung = r.frames[0].0.breathing.lung;
            assert!(
                lung >= pneuma_core::breathing::MIN_LUNG_VOLUME,
                "lead {lead_s} s: lung {lung} at the first frame"
            );
        }
    }
}

#[test]
fn the_lung_fills_during_inspirations_and_empties_while_speaking() {
    let (audio, spans) = sequence(0.6, &[2.0, 2.0], &[0.9]);
    let r = render(&config(), std::slice::from_ref(&audio), &[512]);
    let frames: Vec<ControlFrame> = r.frames.iter().map(|f| f.0).collect();
    let insp: Vec<&ControlFrame> = frames
        .iter()
        .filter(|f| f.breathing.phase == Phase::Inspiration)
        .collect();
    assert!(insp.len() > 10, "inspiration frames: {}", insp.len());
    // Rising lung during inspiration, falling during expiration.
    let rising = frames
        .windows(2)
        .filter(|w| {
            w[1].breathing.phase == Phase::Inspiration && w[0].breathing.phase == Phase::Inspiration
        })
        .all(|w| w[1].breathing.lung >= w[0].breathing.lung);
    assert!(rising);
    let falling = frames
        .windows(2)
        .filter(|w| {
            w[1].breathing.phase == Phase::Expiration && w[0].breathing.phase == Phase::Expiration
        })
        .all(|w| w[1].breathing.lung <= w[0].breathing.lung);
    assert!(falling);
    // `speaking` follows the phrases (within two frames of 120 Hz and the onset edge).
    for f in &frames {
        let inside = spans
            .iter()
            .any(|&(on, off)| f.time_s >= on + 0.03 && f.time_s < off - 0.03);
        let outside = spans
            .iter()
            .all(|&(on, off)| f.time_s < on - 0.2 || f.time_s >= off + 0.3);
        if inside {
            assert!(f.speaking, "not speaking at {:.3}", f.time_s);
        }
        if outside {
            assert!(!f.speaking, "speaking at {:.3}", f.time_s);
        }
    }
    // Frames come once each, in order, at the output time of their centre.
    for (k, (f, at)) in r.frames.iter().enumerate() {
        assert_eq!(f.index, k as u64);
        let expected = (f.time_s * SR).round() as u64 + r.latency_samples as u64;
        assert!(
            at.abs_diff(expected) <= 1,
            "frame {k} at {at}, expected {expected}"
        );
    }
}

#[test]
fn nan_and_infinite_input_never_reach_the_output() {
    let (mut audio, _) = sequence(0.3, &[1.0, 1.0], &[0.6]);
    for i in (1000..audio.len()).step_by(997) {
        audio[i] = if i % 2 == 0 { f32::NAN } else { f32::INFINITY };
    }
    let r = render(&config(), std::slice::from_ref(&audio), &[300]);
    assert!(r.audio[0].iter().all(|x| x.is_finite()));
    assert!(r
        .frames
        .iter()
        .all(|f| f.0.rms_db.is_finite() && f.0.breathing.lung.is_finite()));
}

#[test]
fn a_stream_change_waits_for_prepare_and_config_reports_what_is_in_effect() {
    let mut engine = Engine::new(config(), HeadModel::default_model().clone()).unwrap();
    // Before the first prepare everything applies at once.
    let mut early = config();
    early.placement.lookahead_s = 0.6;
    let change = engine.set_config(&early).unwrap();
    assert!(!change.needs_prepare && !change.live, "{change:?}");
    assert_eq!(engine.config().placement.lookahead_s, 0.6);
    engine.prepare(SR, 256, 1).unwrap();
    let lookahead = engine.latency_samples();
    assert_eq!(lookahead, (0.6 * SR).round() as u32);
    let mut c = early.clone();
    c.placement.mode = PlacementMode::Live;
    c.placement.breath_level_db = -30.0;
    let change = engine.set_config(&c).unwrap();
    assert_eq!(
        change,
        ConfigChange {
            live: true,
            needs_prepare: true
        }
    );
    // The live part is in effect, the mode is not yet, and config() says exactly that.
    assert_eq!(engine.config().placement.breath_level_db, -30.0);
    assert_eq!(engine.config().placement.mode, PlacementMode::Lookahead);
    assert_eq!(engine.latency_samples(), lookahead);
    assert_eq!(engine.pending_config(), Some(&c));
    engine.prepare(SR, 256, 1).unwrap();
    assert_eq!(engine.config(), &c);
    assert_eq!(engine.pending_config(), None);
    assert_eq!(engine.latency_samples(), 0);
    // Going back before a prepare cancels the pending change.
    engine.set_config(&early).unwrap();
    let change = engine.set_config(&c).unwrap();
    assert!(!change.needs_prepare, "{change:?}");
    assert_eq!(engine.pending_config(), None);
}

#[test]
fn nothing_is_dropped_on_a_render_and_uncollected_breaths_are_counted() {
    let pauses = [0.6; 79];
    let (audio, _) = sequence(0.6, &[0.8; 80], &pauses);
    let r = {
        let mut engine = Engine::new(config(), HeadModel::default_model().clone()).unwrap();
        engine.prepare(SR, 512, 1).unwrap();
        let r = offline::render(&mut engine, std::slice::from_ref(&audio), &[512]);
        assert!(engine.dropped().is_none(), "{:?}", engine.dropped());
        r
    };
    assert!(r.breaths.len() > 70, "{} breaths", r.breaths.len());
    // The same stream without take_breaths: all but the last 64 are pushed out, and counted.
    let mut engine = Engine::new(config(), HeadModel::default_model().clone()).unwrap();
    engine.prepare(SR, 512, 1).unwrap();
    let mut buf = audio.clone();
    buf.resize(audio.len() + engine.tail_samples() as usize, 0.0);
    for chunk in buf.chunks_mut(512) {
        engine.process(&mut [chunk], &mut |_, _| {});
    }
    engine.finish();
    let mut kept = 0;
    engine.take_breaths(|_| kept += 1);
    let dropped = engine.dropped();
    assert_eq!(kept, 64);
    assert_eq!(
        dropped.breaths as usize,
        r.breaths.len() - 64,
        "{dropped:?}"
    );
    assert_eq!(
        Dropped {
            breaths: 0,
            ..dropped
        },
        Dropped::default()
    );
}
