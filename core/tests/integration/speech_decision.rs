//! The speech decision in the engine (issue 30), on generated signals with the breaths each
//! must (not) get: plucked harmonic chords with note onsets, a sung vowel glide with vibrato,
//! pink noise in bursts, silence and antiphase stereo get none (with the plugin's 500 ms
//! lookahead, one may go before the stream's first sound: see
//! `music_singing_and_noise_get_no_breath_in_any_mode`); speech-like phrases get a breath in
//! every pause of 0.4 s or more and none on a phrase, offline, with the plugin's lookahead and
//! live, and over a steady drone 16 dB under them keep every breath the engine places without
//! the decision; music after the last phrase gets no breath before it, offline and with the
//! plugin's lookahead, nor does a sung line that starts like speech, offline; speech right
//! after a song starts with a filled lung, and speech that runs on from music in one phrase
//! moves the body offline; a long silence before a phrase gets a normal
//! inhalation, not a sigh; any
//! block partition gives the same output with the decision in place. The body does not speak
//! along with music, singing or noise (no speaking flag, a head at rest, no inspiration) and
//! moves on speech as it does without the decision.

use pneuma_core::control::BreathEvent;
use pneuma_core::engine::offline::{self, Rendered};
use pneuma_core::engine::{Engine, EngineConfig, PlacementMode, SpeechSummary};
use pneuma_core::head::HeadModel;
use pneuma_core::rng::SeededRng;
use pneuma_testkit::signals::{self as test_signals, GlottalVowel, Vowel};

use crate::generated_phrases::{sequence, SR};

/// The three ways the engine runs.
#[derive(Debug, Clone, Copy)]
enum Mode {
    /// `pneuma render`: the whole file.
    Offline,
    /// The plugin: 500 ms lookahead.
    Lookahead,
    /// Live: no lookahead.
    Live,
}

const MODES: [Mode; 3] = [Mode::Offline, Mode::Lookahead, Mode::Live];

fn config(mode: Mode) -> EngineConfig {
    let mut c = EngineConfig::default();
    match mode {
        Mode::Offline => c.placement.whole_file = true,
        Mode::Lookahead => {}
        Mode::Live => c.placement.mode = PlacementMode::Live,
    }
    c
}

fn render_with(
    config: &EngineConfig,
    input: &[Vec<f32>],
    blocks: &[usize],
) -> (Rendered, SpeechSummary) {
    let mut engine = Engine::new(config.clone(), HeadModel::default_model().clone()).unwrap();
    let max_block = blocks.iter().copied().max().unwrap_or(512);
    engine.prepare(SR, max_block, input.len()).unwrap();
    let r = offline::render(&mut engine, input, blocks);
    (r, engine.speech_summary())
}

fn render(mode: Mode, audio: &[f32]) -> (Rendered, SpeechSummary) {
    render_with(&config(mode), &[audio.to_vec()], &[512])
}

/// Seconds → samples at the test rate.
fn n(s: f64) -> usize {
    (s * SR).round() as usize
}

/// Plucked chords: every 1.75 s a three-note chord (four chords cycling), each note a harmonic
/// tone whose level decays with a 0.35 s time constant after its onset; 14 s.
fn plucked_chords() -> Vec<f32> {
    let chords = [
        [261.63, 329.63, 392.0],
        [220.0, 261.63, 329.63],
        [174.61, 220.0, 261.63],
        [196.0, 246.94, 293.66],
    ];
    let every_s = 1.75;
    let mut out = vec![0.0f32; n(14.0)];
    for (k, start) in (0..8).map(|k| (k, k as f64 * every_s)) {
        for f0 in chords[k % 4] {
            let note =
                test_signals::harmonic_tone(SR, every_s, 0.12, &[1.0, 0.5, 0.3, 0.2], |_| f0);
            for (i, x) in note.iter().enumerate() {
                let env = (-(i as f64 / SR) / 0.35).exp() as f32;
                out[n(start) + i] += x * env;
            }
        }
    }
    out
}

/// A sung line: a glottal vowel gliding 220 → 330 Hz over `length_s` with a 5.5 Hz vibrato of
/// half a semitone.
fn sung_line(length_s: f64, vowel: Vowel, seed: u64) -> Vec<f32> {
    test_signals::glottal_vowel(
        &GlottalVowel {
            sample_rate_hz: SR,
            length_s,
            vowel,
            jitter: 0.005,
            shimmer: 0.02,
            peak: 0.4,
            seed,
        },
        |t| {
            let glide = 220.0 * 1.5f64.powf(t / length_s);
            glide * 2f64.powf(0.5 / 12.0 * (2.0 * std::f64::consts::PI * 5.5 * t).sin())
        },
    )
}

/// Sung lines ([`sung_line`], /a/, /i/, /a/) of 2.5 s separated by 0.8 s of silence.
fn sung_glide() -> Vec<f32> {
    let mut out = vec![0.0f32; n(0.5)];
    for line in 0..3u64 {
        let v = sung_line(2.5, if line == 1 { Vowel::I } else { Vowel::A }, 40 + line);
        // Sung lines swell in and out, 0.1 s each.
        let len = v.len();
        out.extend(v.iter().enumerate().map(|(i, x)| {
            let edge = (i.min(len - i) as f64 / (0.1 * SR)).min(1.0) as f32;
            x * edge
        }));
        out.extend(std::iter::repeat_n(0.0, n(0.8)));
    }
    out
}

/// Pink noise (seeded white noise through [`pneuma_core::rng::PinkFilter`]), RMS `rms`.
fn pink_noise(len: usize, rms: f64, seed: u64) -> Vec<f32> {
    let mut filter = pneuma_core::rng::PinkFilter::default();
    let y: Vec<f64> = test_signals::white_noise(len, 1.0, seed)
        .iter()
        .map(|&w| filter.step(f64::from(w)))
        .collect();
    let r = (y.iter().map(|v| v * v).sum::<f64>() / len.max(1) as f64).sqrt();
    y.iter().map(|v| (v * rms / r.max(1e-12)) as f32).collect()
}

/// Pink noise in 2 s bursts separated by 0.8 s of silence (fades of 20 ms); 5 bursts.
fn pink_bursts() -> Vec<f32> {
    let mut out = vec![0.0f32; n(0.5)];
    for k in 0..5 {
        let burst = pink_noise(n(2.0), 0.05, 70 + k);
        let len = burst.len();
        out.extend(
            burst
                .iter()
                .enumerate()
                .map(|(i, x)| x * (i.min(len - i) as f64 / (0.02 * SR)).min(1.0) as f32),
        );
        out.extend(std::iter::repeat_n(0.0, n(0.8)));
    }
    out
}

/// Speech-like phrases with these pauses, a 0.6 s lead-in; and their spans.
fn phrases(pauses: &[f64]) -> (Vec<f32>, Vec<(f64, f64)>) {
    let lengths = [1.6, 1.2, 1.8, 1.4, 1.5, 1.3];
    sequence(0.6, &lengths[..pauses.len() + 1], pauses)
}

const PAUSES: [f64; 4] = [0.5, 0.8, 0.6, 1.0];

/// Seconds of `b` inside any of `spans`.
fn overlap_s(b: &BreathEvent, spans: &[(f64, f64)]) -> f64 {
    spans
        .iter()
        .map(|&(on, off)| (b.end_s.min(off) - b.start_s.max(on)).max(0.0))
        .sum()
}

/// Every pause of `spans` (the gaps between them) holds a breath, no breath lies more than
/// 30 ms on a phrase, and no breath lies outside the pauses and the lead-in.
fn assert_breath_in_every_pause(r: &Rendered, spans: &[(f64, f64)], what: &str) {
    for w in spans.windows(2) {
        let (from, to) = (w[0].1, w[1].0);
        assert!(
            r.breaths.iter().any(|b| b.start_s < to && b.end_s > from),
            "{what}: no breath in the pause {from:.2}–{to:.2} s: {:?}",
            r.breaths
        );
    }
    for b in &r.breaths {
        assert!(
            overlap_s(b, spans) <= 0.03,
            "{what}: a breath on a phrase: {b:?}"
        );
    }
}

#[test]
fn speech_like_phrases_get_a_breath_in_every_pause_in_every_mode() {
    let (audio, spans) = phrases(&PAUSES);
    for mode in MODES {
        let (r, summary) = render(mode, &audio);
        assert_breath_in_every_pause(&r, &spans, &format!("{mode:?}"));
        assert_eq!(
            summary.phrases, summary.speech_phrases,
            "{mode:?}: {summary:?}"
        );
    }
}

#[test]
fn speech_like_phrases_over_a_drone_16_db_under_keep_their_breaths() {
    let (mut audio, spans) = phrases(&PAUSES);
    let speech_rms = {
        let voiced: Vec<f32> = spans
            .iter()
            .flat_map(|&(on, off)| audio[n(on)..n(off)].to_vec())
            .collect();
        pneuma_core::analysis::rms(&voiced)
    };
    let harmonics: Vec<f64> = (1..=12).map(|k| 1.0 / k as f64).collect();
    let drone = test_signals::harmonic_tone(SR, audio.len() as f64 / SR, 1.0, &harmonics, |_| 98.0);
    let g = speech_rms * 10f64.powf(-16.0 / 20.0) / pneuma_core::analysis::rms(&drone);
    for (a, d) in audio.iter_mut().zip(&drone) {
        *a += (g * *d as f64) as f32;
    }
    for mode in MODES {
        let (on, summary) = render(mode, &audio);
        let mut c = config(mode);
        c.placement.speech_only = false;
        let (off, _) = render_with(&c, std::slice::from_ref(&audio), &[512]);
        // The tracker merges the first two phrases over the drone (0.5 s pause): that is the
        // tracker's, with or without the decision. The decision takes no breath away offline
        // and live. With the plugin's lookahead it may take one: the merged first phrase
        // starts with the drone alone, so its first half second is no speech, and the next
        // pause must be decided with only 0.1 s of the phrase after it heard.
        assert!(off.breaths.len() >= 3, "{mode:?}: {:?}", off.breaths);
        let lost = usize::from(matches!(mode, Mode::Lookahead));
        assert!(
            on.breaths.len() + lost >= off.breaths.len(),
            "{mode:?}: {:?} vs {:?} ({summary:?})",
            on.breaths,
            off.breaths
        );
        for b in &on.breaths {
            assert!(overlap_s(b, &spans) <= 0.03, "{mode:?}: on a phrase: {b:?}");
            assert!(
                off.breaths.iter().any(|o| (o.end_s - b.end_s).abs() < 0.02),
                "{mode:?}: {b:?} where the engine without the decision has none"
            );
        }
    }
}

/// The generated signals that are not speech, named.
fn not_speech() -> [(&'static str, Vec<f32>); 3] {
    [
        ("plucked chords", plucked_chords()),
        ("sung glide", sung_glide()),
        ("pink noise bursts", pink_bursts()),
    ]
}

#[test]
fn music_singing_and_noise_get_no_breath_in_any_mode() {
    for (name, audio) in not_speech() {
        // The first sound of the signal.
        let first_s = audio.iter().position(|x| x.abs() > 1e-4).unwrap_or(0) as f64 / SR;
        for mode in MODES {
            let (r, summary) = render(mode, &audio);
            // With the plugin's 500 ms lookahead, the breath before the stream's first phrase
            // must start when about 0.1 s of that phrase has been heard, with no phrase before
            // it to go by: Silero's own threshold decides, and Silero takes singing for speech.
            // Such a breath lies in the silence before the first sound, never in the music.
            let breaths: Vec<&BreathEvent> = r
                .breaths
                .iter()
                .filter(|b| !matches!(mode, Mode::Lookahead) || b.end_s > first_s)
                .collect();
            assert!(
                breaths.is_empty(),
                "{name}, {mode:?}: {:?} ({summary:?})",
                r.breaths
            );
            // The tracker did find phrases: the decision is what kept the breaths out.
            assert!(summary.phrases >= 2, "{name}, {mode:?}: {summary:?}");
            assert_eq!(summary.speech_phrases, 0, "{name}, {mode:?}: {summary:?}");
        }
        // With the decision off the same signal gets breaths (what the decision prevents).
        let mut off = config(Mode::Offline);
        off.placement.speech_only = false;
        let (r, _) = render_with(&off, std::slice::from_ref(&audio), &[512]);
        assert!(
            !r.breaths.is_empty(),
            "{name}: no breath even without the decision"
        );
    }
}

/// Share of `r`'s frames flagged speaking, and the largest SD of a head angle, degrees.
fn body_motion(r: &Rendered) -> (f64, f64) {
    let frames: Vec<_> = r.frames.iter().map(|(f, _)| f).collect();
    let count = frames.len().max(1) as f64;
    let speaking = frames.iter().filter(|f| f.speaking).count() as f64 / count;
    let sd = |angle: &dyn Fn(&pneuma_core::control::ControlFrame) -> f32| {
        let xs: Vec<f64> = frames.iter().map(|f| f64::from(angle(f))).collect();
        let mean = xs.iter().sum::<f64>() / count;
        (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / count).sqrt()
    };
    let head_sd = [
        sd(&|f| f.head.pitch_deg),
        sd(&|f| f.head.yaw_deg),
        sd(&|f| f.head.roll_deg),
    ]
    .into_iter()
    .fold(0.0, f64::max);
    (speaking, head_sd)
}

#[test]
fn music_singing_and_noise_move_no_body() {
    for (name, audio) in not_speech() {
        // Without the decision the body speaks along and the head follows the notes: what the
        // decision must prevent.
        let mut off = config(Mode::Offline);
        off.placement.speech_only = false;
        let (r, _) = render_with(&off, std::slice::from_ref(&audio), &[512]);
        let (speaking_off, head_off) = body_motion(&r);
        assert!(speaking_off > 0.3, "{name}: speaking {speaking_off:.2}");
        assert!(head_off > 0.5, "{name}: head SD {head_off:.2}°");
        for mode in MODES {
            let (r, _) = render(mode, &audio);
            let (speaking, head_sd) = body_motion(&r);
            // Live mode judges a phrase once its window has been heard, and takes a phrase for
            // speech before that when Silero does (Silero takes singing for speech): its first
            // frames may still move. The plugin's lookahead sees the first phrase's window just
            // too late for a few of its frames.
            let (most_speaking, most_head_sd) = match mode {
                Mode::Offline => (0.0, 0.01),
                Mode::Lookahead => (0.01, 0.1),
                Mode::Live => (0.1, 0.6 * head_off),
            };
            assert!(
                speaking <= most_speaking,
                "{name}, {mode:?}: speaking on {:.1} % of frames",
                100.0 * speaking
            );
            assert!(
                head_sd <= most_head_sd,
                "{name}, {mode:?}: head SD {head_sd:.3}° (without the decision {head_off:.2}°)"
            );
            // No inspiration: the mouth never opens for a breath (with the plugin's lookahead,
            // but for the one that may go before the first sound, as the breath does in
            // `music_singing_and_noise_get_no_breath_in_any_mode`).
            let first_s = audio.iter().position(|x| x.abs() > 1e-4).unwrap_or(0) as f64 / SR;
            let mouth = r
                .frames
                .iter()
                .filter(|(f, _)| !matches!(mode, Mode::Lookahead) || f.time_s > first_s)
                .map(|(f, _)| f.breathing.mouth_open)
                .fold(0.0f32, f32::max);
            assert!(mouth < 1e-3, "{name}, {mode:?}: mouth open {mouth:.2}");
        }
    }
}

/// Share of `r`'s frames in `[from_s, to_s)` flagged speaking.
fn speaking_between(r: &Rendered, from_s: f64, to_s: f64) -> f64 {
    let (speaking, all) = r
        .frames
        .iter()
        .filter(|(f, _)| f.time_s >= from_s && f.time_s < to_s)
        .fold((0, 0), |(s, a), (f, _)| {
            (s + usize::from(f.speaking), a + 1)
        });
    speaking as f64 / all.max(1) as f64
}

/// 0.6 s of silence, `speech_s` of a speech-like phrase running straight into `sung_s` of a
/// sung line, 1 s of silence.
fn speech_into_singing(speech_s: f64, sung_s: f64) -> Vec<f32> {
    let lead = vec![0.0f32; n(0.6)];
    let rest = vec![0.0f32; n(1.0)];
    let speech = crate::generated_phrases::phrase(speech_s, 1);
    let sung = sung_line(sung_s, Vowel::A, 41);
    [&lead[..], &speech, &sung, &rest].concat()
}

#[test]
fn the_body_stops_speaking_when_a_phrase_of_speech_runs_into_singing() {
    // Speech running straight into a sung line: one phrase, judged speech by its first half
    // second (its breaths), and the body follows its voiced frames of the last half second
    // after that: it stops speaking once the singing brings their mean under the threshold.
    let (speech_s, sung_s) = (2.5, 4.0);
    let audio = speech_into_singing(speech_s, sung_s);
    for mode in MODES {
        let (r, summary) = render(mode, &audio);
        // One phrase, judged speech: the singing is not judged by a window of its own.
        assert_eq!(
            (summary.phrases, summary.speech_phrases),
            (1, 1),
            "{mode:?}: {summary:?}"
        );
        let talking = speaking_between(&r, 0.6 + 0.5, 0.6 + speech_s);
        // With a lookahead the frames of the window judged not speech that still wait for the
        // output take the judgement: under 5 % of the singing speaks, from its start (8 %
        // when only the frames from the judgement on take it). Live mode stops from the
        // moment of the judgement.
        let settle_s = match mode {
            Mode::Live => 1.0,
            Mode::Offline | Mode::Lookahead => 0.0,
        };
        let singing = speaking_between(&r, 0.6 + speech_s + settle_s, 0.6 + speech_s + sung_s);
        assert!(
            talking > 0.8,
            "{mode:?}: speaking on {talking:.2} of the speech"
        );
        assert!(
            singing < 0.05,
            "{mode:?}: speaking on {singing:.2} of the singing after its first {settle_s} s"
        );
    }
}

#[test]
fn a_sung_line_that_starts_like_speech_moves_no_body_when_its_frames_wait_for_the_output() {
    // A sung line whose first half second the model takes for speech (here a spoken syllable
    // or two leading straight into it, one phrase): the phrase is judged speech by that window,
    // its voiced frames of the last half second then say singing, and so do all its voiced
    // frames so far. A render (8 s of frames waiting for the output) takes that back to the
    // phrase's onset: the body never speaks on it. The plugin's 500 ms lookahead cannot.
    let (speech_s, sung_s) = (0.5, 2.0);
    let audio = speech_into_singing(speech_s, sung_s);
    let (r, summary) = render(Mode::Offline, &audio);
    assert_eq!(
        (summary.phrases, summary.speech_phrases),
        (1, 1),
        "the window judges it speech: {summary:?}"
    );
    let speaking = speaking_between(&r, 0.6, 0.6 + speech_s + sung_s);
    assert!(speaking < 0.05, "speaking on {speaking:.2} of the line");
}

#[test]
fn the_body_on_speech_is_the_body_without_the_decision() {
    let (audio, _) = phrases(&PAUSES);
    for mode in [Mode::Offline, Mode::Lookahead, Mode::Live] {
        let on = config(mode);
        let mut off = on.clone();
        off.placement.speech_only = false;
        let (a, _) = render_with(&on, std::slice::from_ref(&audio), &[512]);
        let (b, _) = render_with(&off, std::slice::from_ref(&audio), &[512]);
        assert_eq!(a.frames.len(), b.frames.len());
        let (speaking, head_sd) = body_motion(&a);
        assert!(
            speaking > 0.5 && head_sd > 0.5,
            "{mode:?}: {speaking} {head_sd}"
        );
        for ((fa, _), (fb, _)) in a.frames.iter().zip(&b.frames) {
            assert_eq!(fa.head, fb.head, "{mode:?} at {} s", fa.time_s);
            assert_eq!(fa.speaking, fb.speaking, "{mode:?} at {} s", fa.time_s);
            assert_eq!(fa.breathing, fb.breathing, "{mode:?} at {} s", fa.time_s);
        }
    }
}

#[test]
fn silence_and_antiphase_stereo_get_no_breath_and_no_sound() {
    let silence = vec![0.0f32; n(10.0)];
    let (speech, _) = phrases(&PAUSES);
    let inverted: Vec<f32> = speech.iter().map(|x| -x).collect();
    for mode in MODES {
        for (name, input) in [
            ("silence", vec![silence.clone()]),
            ("antiphase", vec![speech.clone(), inverted.clone()]),
        ] {
            let (r, summary) = render_with(&config(mode), &input, &[512]);
            assert!(r.breaths.is_empty(), "{name}, {mode:?}: {:?}", r.breaths);
            assert_eq!(summary.sound_frames, 0, "{name}, {mode:?}: {summary:?}");
            assert!(summary.frames > 0);
        }
    }
}

#[test]
fn a_long_silence_gets_a_normal_inhalation_before_the_next_phrase() {
    for silence_s in [10.0, 60.0] {
        let (audio, spans) = sequence(0.6, &[1.6, 1.4], &[silence_s]);
        let (r, _) = render(Mode::Offline, &audio);
        let before_second: Vec<&BreathEvent> = r
            .breaths
            .iter()
            .filter(|b| b.start_s > spans[0].1 && b.end_s <= spans[1].0)
            .collect();
        assert_eq!(before_second.len(), 1, "{silence_s} s: {:?}", r.breaths);
        let b = before_second[0];
        let length_s = b.end_s - b.start_s;
        // Real inhalations are rarely over 0.8 s (the longest breath, to a sample).
        assert!(
            (0.3..=0.8 + 1e-4).contains(&length_s),
            "{silence_s} s of silence: a breath of {length_s:.4} s"
        );
        // It lies just before the phrase, not somewhere in the silence.
        assert!(spans[1].0 - b.end_s < 0.1, "{b:?} vs onset {}", spans[1].0);
    }
}

#[test]
fn music_after_the_last_phrase_gets_no_breath_before_it() {
    // Two phrases, a pause, then an outro of chords: the pause after the last words leads into
    // no speech. With the plugin's lookahead the breath before the chords is decided when a
    // little of them has been heard: enough to show they are not speech.
    let (mut audio, spans) = sequence(0.6, &[1.6, 1.2], &[0.8, 1.5]);
    let last_s = spans[1].1;
    let music_s = audio.len() as f64 / SR;
    audio.extend_from_slice(&plucked_chords()[..n(5.0)]);
    for mode in [Mode::Offline, Mode::Lookahead] {
        let (r, _) = render(mode, &audio);
        assert_breath_in_every_pause(&r, &spans, &format!("{mode:?}"));
        let after: Vec<&BreathEvent> = r.breaths.iter().filter(|b| b.end_s > last_s).collect();
        assert!(
            after.is_empty(),
            "{mode:?}: a breath after the last phrase (ends {last_s:.2} s, chords from \
             {music_s:.2} s): {after:?}"
        );
    }
}

#[test]
fn speech_right_after_a_song_starts_with_a_filled_lung() {
    // A host who speaks as the song ends: a sung line, 0.15 s of silence (no pause to breathe
    // in), then the example voice's first 6 s (real speech: the generated phrases are not
    // judged speech straight after a song). The speaker breathed in under the song; the body
    // must not speak from the resting lung (it did for 5.5 s on a podcast episode, in every
    // mode). Offline the lung fills before the first word, under the song's end; with the
    // plugin's lookahead (the phrase not yet judged when the output reaches it) and live
    // (which judges a phrase at its end), at the first speaking frame. No sound goes into
    // the 0.15 s.
    let mut audio = vec![0.0f32; n(0.6)];
    let sung = sung_line(3.0, Vowel::A, 41);
    let len = sung.len();
    audio.extend(sung.iter().enumerate().map(|(i, x)| {
        // Swells in and out over 0.1 s, as sung lines do.
        x * (i.min(len - i) as f64 / (0.1 * SR)).min(1.0) as f32
    }));
    let song_end_s = audio.len() as f64 / SR;
    audio.extend(std::iter::repeat_n(0.0, n(0.15)));
    // The example voice's first word starts 0.3 s in.
    let voice = pneuma_testkit::voice::example_voice_at(SR as u32);
    audio.extend_from_slice(&voice[n(0.28)..n(6.0)]);
    let onset_s = song_end_s + 0.15;
    for mode in MODES {
        let (r, summary) = render(mode, &audio);
        assert!(
            summary.speech_phrases >= 1 && summary.speech_phrases < summary.phrases,
            "{mode:?}: the song not speech, the voice speech: {summary:?}"
        );
        let first = r
            .frames
            .iter()
            .position(|(f, _)| f.speaking && f.time_s >= onset_s - 0.1)
            .unwrap_or_else(|| panic!("{mode:?}: never speaks"));
        // The resting lung lies under 0.11; a breath for the voice's first group (1.4 s of
        // speech) fills it to about 0.35.
        let lung_at = |k: usize| r.frames[k].0.breathing.lung;
        assert!(
            lung_at(first) > 0.25,
            "{mode:?}: speaks from a lung of {:.2} at {:.2} s",
            lung_at(first),
            r.frames[first].0.time_s
        );
        // And not spent at once: the lowest lung over the first half second of speaking.
        let t0 = r.frames[first].0.time_s;
        let held = r.frames[first..]
            .iter()
            .take_while(|(f, _)| f.time_s <= t0 + 0.5)
            .map(|(f, _)| f.breathing.lung)
            .fold(f32::INFINITY, f32::min);
        assert!(
            held > 0.2,
            "{mode:?}: the lung falls to {held:.2} within 0.5 s"
        );
        if matches!(mode, Mode::Offline) {
            // Filled by an inspiration before the first word, not a step at it.
            assert!(
                lung_at(first - 1) > 0.25,
                "{mode:?}: lung {:.2} the frame before the speech",
                lung_at(first - 1)
            );
        }
        let in_gap: Vec<&BreathEvent> = r
            .breaths
            .iter()
            .filter(|b| b.start_s < onset_s + 0.1 && b.end_s > song_end_s - 1.0)
            .collect();
        assert!(in_gap.is_empty(), "{mode:?}: {in_gap:?}");
    }
}

#[test]
fn speech_that_runs_on_from_music_in_one_phrase_moves_the_body_offline() {
    // A host who starts speaking while the intro's last chord rings (no silence between: the
    // tracker hears one phrase, judged not speech by its first window, the chords). Offline
    // (its frames wait 8 s for the output) the body speaks on the speech from where the
    // phrase turned to speech to its end, with a filled lung. Before, it kept the phrase's
    // judgement and stood still through the whole first sentence.
    let chords = plucked_chords();
    let mut audio = chords[..n(3.5 + 0.4)].to_vec();
    let voice = pneuma_testkit::voice::example_voice_at(SR as u32);
    // The example voice's first word starts 0.3 s in; its first sentence ends at 1.7 s.
    let start = audio.len() - n(0.3);
    audio.resize(start + n(6.0), 0.0);
    for (a, v) in audio[start..].iter_mut().zip(&voice[..n(6.0)]) {
        *a += v;
    }
    let (speech_from_s, speech_to_s) = (start as f64 / SR + 0.3, start as f64 / SR + 1.7);
    let (r, _) = render(Mode::Offline, &audio);
    let talking = speaking_between(&r, speech_from_s + 0.5, speech_to_s);
    assert!(
        talking > 0.5,
        "speaking on {talking:.2} of the first sentence"
    );
    let first = r.frames.iter().find(|(f, _)| f.speaking).expect("speaks");
    assert!(
        first.0.breathing.lung > 0.25,
        "speaks from a lung of {:.2}",
        first.0.breathing.lung
    );
    // The chords before it do not speak (up to 0.2 s before the first word).
    let chords_speaking = speaking_between(&r, 0.0, speech_from_s - 0.2);
    assert!(chords_speaking < 0.01, "{chords_speaking:.2}");
}

#[test]
fn a_sung_line_that_starts_like_speech_gets_no_breath_before_it_offline() {
    // Two phrases, a pause, then a sung line whose first half second the model takes for
    // speech (a spoken syllable or two leading straight into it, one phrase): the window
    // judges it speech, but all its voiced frames say singing by the time a render decides
    // the pause before it. That pause leads into no speech: no breath (a podcast's song after
    // the talk). The pauses between the phrases keep theirs. Before, the placement kept the
    // window's judgement and a breath went before the song.
    let (mut audio, spans) = sequence(0.6, &[1.6, 1.2], &[0.8, 2.0]);
    let last_s = spans[1].1;
    let song_s = audio.len() as f64 / SR;
    audio.extend(speech_into_singing(0.5, 3.0));
    let (r, summary) = render(Mode::Offline, &audio);
    assert_eq!(
        (summary.phrases, summary.speech_phrases),
        (3, 3),
        "the window judges the sung line speech: {summary:?}"
    );
    assert_breath_in_every_pause(&r, &spans, "offline");
    let after: Vec<&BreathEvent> = r.breaths.iter().filter(|b| b.end_s > last_s).collect();
    assert!(
        after.is_empty(),
        "a breath after the last phrase of speech (ends {last_s:.2} s, the sung line from \
         {song_s:.2} s): {after:?}"
    );
}

#[test]
fn the_shortest_lookahead_keeps_a_breath_in_every_pause_of_speech() {
    // At 0.3 s a pause cannot wait for 0.15 s of the phrase after it: the breath before
    // speech is decided as before, never lost to the wait.
    let (audio, spans) = phrases(&PAUSES);
    let mut c = config(Mode::Lookahead);
    c.placement.lookahead_s = 0.3;
    let (r, _) = render_with(&c, &[audio], &[512]);
    assert_breath_in_every_pause(&r, &spans, "0.3 s lookahead");
}

#[test]
fn any_block_partition_gives_the_same_output_with_the_decision_in_place() {
    // Chords, then speech-like phrases, then singing: the decision says no, yes and no.
    let mut audio = plucked_chords()[..n(4.0)].to_vec();
    audio.extend(phrases(&[0.6, 0.9]).0);
    audio.extend(sung_glide());
    let mut rng = SeededRng::new(30);
    let random: Vec<usize> = (0..97)
        .map(|_| 1 + (rng.uniform() * 900.0) as usize)
        .collect();
    for mode in MODES {
        let c = config(mode);
        let (reference, summary) = render_with(&c, std::slice::from_ref(&audio), &[4096]);
        assert!(!reference.breaths.is_empty(), "{mode:?}");
        assert!(
            summary.speech_phrases < summary.phrases,
            "{mode:?}: {summary:?}"
        );
        for blocks in [vec![1, 2, 3, 700], vec![37], random.clone()] {
            let (r, s) = render_with(&c, std::slice::from_ref(&audio), &blocks);
            assert_eq!(
                r.audio,
                reference.audio,
                "{mode:?} {:?}",
                &blocks[..3.min(blocks.len())]
            );
            assert_eq!(r.breaths, reference.breaths, "{mode:?}");
            assert_eq!(s, summary, "{mode:?}");
            // Control frames too, and the sample each is emitted at, live mode included (it
            // emits a frame at the sample that completes it, after the events of that frame
            // and of none after it).
            assert_eq!(r.frames, reference.frames, "{mode:?}");
        }
    }
}

/// Sustained three-note chords (harmonic tones at a constant level), a new chord every 2 s,
/// `length_s` long.
fn sustained_chords(length_s: f64) -> Vec<f32> {
    let chords = [[261.63, 329.63, 392.0], [220.0, 261.63, 329.63]];
    let mut out = Vec::with_capacity(n(length_s));
    for k in 0..(length_s / 2.0) as usize {
        let mut chord = vec![0.0f32; n(2.0)];
        for f0 in chords[k % 2] {
            let note = test_signals::harmonic_tone(SR, 2.0, 0.12, &[1.0, 0.5, 0.3, 0.2], |_| f0);
            chord.iter_mut().zip(&note).for_each(|(c, x)| *c += x);
        }
        out.extend(chord);
    }
    out
}

/// Share of the frames with sound that the decision calls speech.
fn speech_share(s: &SpeechSummary) -> f64 {
    s.speech_frames as f64 / s.sound_frames.max(1) as f64
}

#[test]
fn a_steady_hiss_around_one_sentence_is_no_sound_but_music_after_it_is() {
    let (speech, _) = phrases(&PAUSES);
    let speech_rms = pneuma_core::analysis::rms(&speech[n(0.6)..]);
    // The sentence with 8 s of room before and after it, all over white noise 40 dB under,
    // after 2 s of digital silence (an export's fade-in).
    let mut hissed = vec![0.0f32; n(8.0)];
    hissed.extend(&speech);
    hissed.extend(std::iter::repeat_n(0.0, n(8.0)));
    let hiss = test_signals::white_noise(hissed.len(), speech_rms * 0.01, 91);
    for (x, h) in hissed.iter_mut().zip(&hiss) {
        *x += h;
    }
    hissed.splice(0..0, std::iter::repeat_n(0.0, n(2.0)));
    // The sentence, then 28 s of plucked chords at about its level; then 28 s of sustained
    // chords (an organ: the noise floor climbs into them).
    let mut with_music = speech.clone();
    with_music.extend(plucked_chords());
    with_music.extend(plucked_chords());
    let mut with_organ = speech.clone();
    with_organ.extend(sustained_chords(28.0));
    // In a room (the hiss): the floor has a room to start from.
    let room = test_signals::white_noise(with_organ.len(), speech_rms * 0.01, 92);
    with_organ.iter_mut().zip(&room).for_each(|(x, h)| *x += h);
    for mode in MODES {
        let (_, s) = render(mode, &hissed);
        assert!(speech_share(&s) > 0.6, "hiss, {mode:?}: {s:?}");
        let (_, s) = render(mode, &with_music);
        assert!(speech_share(&s) < 0.4, "music, {mode:?}: {s:?}");
        let (_, s) = render(mode, &with_organ);
        assert!(speech_share(&s) < 0.4, "organ, {mode:?}: {s:?}");
    }
}
