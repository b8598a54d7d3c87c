//! Live placement on the example voice, judged against the speech the same tracker finds in
//! lookahead mode (where the speaking flag is exact): no breath sound over speech beyond the
//! first `live_fade_s` of an onset, the minimum pause respected, no inspiration while speaking,
//! no inaudible stubs reported.

use pneuma_core::engine::offline::{self, Rendered};
use pneuma_core::engine::{Engine, EngineConfig, PlacementMode};
use pneuma_core::head::HeadModel;
use pneuma_core::Phase;
use pneuma_testkit::signals;
use pneuma_testkit::voice::example_voice;

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
    let dt = r
        .frames
        .get(1)
        .map_or(0.01, |f| f.0.time_s - r.frames[0].0.time_s);
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

/// The first sample at or after `from_s` (and before `to_s`) where the input is audible
/// (over −70 dBFS): where a speech span's sound begins. A frame's time is the centre of its
/// analysis window, so the first frame flagged speaking lies about half a window (10–20 ms)
/// before the sound it hears; live mode, with no lookahead, can only react to the sound.
fn sound_onset_s(x: &[f32], sr: f64, from_s: f64, to_s: f64) -> f64 {
    let from = (from_s * sr).ceil() as usize;
    let to = ((to_s * sr) as usize).min(x.len());
    (from..to)
        .find(|&i| x[i].abs() > 10f32.powf(-70.0 / 20.0))
        .map_or(to_s, |i| i as f64 / sr)
}

#[test]
fn live_breaths_stay_off_speech_and_respect_the_minimum_pause() {
    let (voice, sr) = example_voice();
    let sr = f64::from(sr);
    let reference = render(&config(PlacementMode::Lookahead, 0.25), &voice, sr);
    let speech = speech_spans(&reference);
    assert!(speech.len() >= 5, "{speech:?}");
    for min_pause_s in [0.25f32, 1.0] {
        let c = config(PlacementMode::Live, min_pause_s);
        let fade_s = c.placement.live_fade_s as f64;
        let live = render(&c, &voice, sr);
        assert!(
            !live.breaths.is_empty(),
            "min pause {min_pause_s}: no breath"
        );
        // Breath sound (output minus input) over speech, past the first fade of each onset.
        let mut over_speech = Vec::new();
        let mut longest_overlap_s = 0.0f64;
        for &(on, off) in &speech {
            let sound_s = sound_onset_s(&voice, sr, on, off);
            let sound = (sound_s * sr).round() as usize;
            let to = ((off * sr) as usize).min(voice.len());
            if let Some(k) = (sound..to).rfind(|&i| live.audio[0][i] != voice[i]) {
                longest_overlap_s = longest_overlap_s.max((k + 1 - sound) as f64 / sr);
            }
            let from = ((sound_s + fade_s) * sr).ceil() as usize;
            let to = ((off * sr) as usize).min(voice.len());
            if let Some(k) = (from..to).rfind(|&i| live.audio[0][i] != voice[i]) {
                over_speech.push((on, sound_s, k as f64 / sr));
            }
        }
        assert!(
            over_speech.is_empty(),
            "min pause {min_pause_s}: breath over speech (frame onset, sound onset, last \
             sample): {over_speech:?}"
        );
        for b in &live.breaths {
            // The speech before the breath ended at least the minimum pause earlier (the
            // reference's offset is the first frame after it: up to one frame late).
            let prev_off = speech
                .iter()
                .map(|s| s.1)
                .filter(|&off| off <= b.start_s)
                .fold(0.0f64, f64::max);
            assert!(
                prev_off == 0.0 || b.start_s - prev_off >= min_pause_s as f64 - 0.01,
                "min pause {min_pause_s}: {b:?} starts {:.3} s after speech ended",
                b.start_s - prev_off
            );
            assert!(
                b.peak_db >= -60.0 && b.end_s - b.start_s >= 0.06,
                "inaudible stub reported: {b:?}"
            );
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
            "min pause {min_pause_s}: live {} breaths, lookahead {}; breath sound lasts at most \
             {:.1} ms into the sound of an onset",
            live.breaths.len(),
            reference.breaths.len(),
            longest_overlap_s * 1000.0
        );
    }
}

#[test]
fn generated_phrases_get_a_live_breath_in_every_pause() {
    // 1.5 s phrases and 0.5 s pauses under white noise 20 dB down (a noisy background the gate
    // must learn, unlike the example voice's digital silence).
    let sr = 22_050.0;
    let x = signals::phrases_with_pauses(sr, 12.0, 20.0, 7);
    // A sustained vowel is not speech to the speech decision: this test is about the gate and
    // the live timing, so every pause counts.
    let config = |mode| {
        let mut c = config(mode, 0.25);
        c.placement.speech_only = false;
        c
    };
    let reference = render(&config(PlacementMode::Lookahead), &x, sr);
    let speech = speech_spans(&reference);
    let pauses: Vec<(f64, f64)> = speech.windows(2).map(|w| (w[0].1, w[1].0)).collect();
    assert_eq!(pauses.len(), 5, "{speech:?}");
    let live = render(&config(PlacementMode::Live), &x, sr);
    for &(from, to) in &pauses {
        let inside = live
            .breaths
            .iter()
            .filter(|b| b.start_s >= from && b.start_s < to)
            .count();
        assert_eq!(
            inside, 1,
            "pause {from:.3}..{to:.3} s holds {inside} breaths: {:?}",
            live.breaths
        );
    }
}

#[test]
fn a_longer_minimum_pause_means_fewer_live_breaths() {
    let (voice, sr) = example_voice();
    let sr = f64::from(sr);
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

/// The lung at the first frame flagged speaking of `audio`, rendered live and with a lookahead.
fn first_speaking_lung(audio: &[f32], sample_rate_hz: f64) -> (f32, f32) {
    let lung = |mode| {
        render(&config(mode, 0.25), audio, sample_rate_hz)
            .frames
            .iter()
            .map(|f| &f.0)
            .find(|f| f.speaking)
            .map(|f| f.breathing.lung)
            .expect("a frame speaking")
    };
    (lung(PlacementMode::Live), lung(PlacementMode::Lookahead))
}

#[test]
fn a_live_stream_that_starts_in_speech_starts_with_air_in_the_lung() {
    // The example voice speaks from 0.33 s, less than an inspiration after the stream began:
    // the speaker breathed in before it, as a lookahead render says from its first frame, and
    // the first phrase breathes out from a filled lung, not from an empty one.
    let (voice, sr) = example_voice();
    let (live, lookahead) = first_speaking_lung(&voice, f64::from(sr));
    assert!(
        live >= 0.5 * lookahead && lookahead > 0.3,
        "lung at the first word: live {live:.2}, lookahead {lookahead:.2}"
    );
}

#[test]
fn a_live_stream_that_starts_in_silence_speaks_its_first_phrase_from_a_filled_lung() {
    // 1.5 s of digital silence before the example voice: no breath to hear, but the speaker
    // breathed in before speaking, as a lookahead render says with its inspiration before the
    // first phrase. Live mode, which cannot know when the speech will come, fills the lung when
    // the first phrase is confirmed; before, the first phrase breathed out from the lung's
    // resting level (0.07).
    let (voice, sr) = example_voice();
    let sr = f64::from(sr);
    let mut audio = vec![0.0; (1.5 * sr) as usize];
    audio.extend_from_slice(&voice);
    let (live, lookahead) = first_speaking_lung(&audio, sr);
    assert!(
        live >= 0.5 * lookahead && lookahead > 0.3,
        "lung at the first word after a silence: live {live:.2}, lookahead {lookahead:.2}"
    );
}

/// The time and the lung at the first frame of every run of speaking frames after the first,
/// in `r`.
fn phrase_starts(r: &Rendered) -> Vec<(f64, f32)> {
    let mut out = Vec::new();
    let mut was_speaking = false;
    for (f, _) in &r.frames {
        if f.speaking && !was_speaking {
            out.push((f.time_s, f.breathing.lung));
        }
        was_speaking = f.speaking;
    }
    out.into_iter().skip(1).collect()
}

/// The lung at [`phrase_starts`].
fn lungs_at_phrase_starts(r: &Rendered) -> Vec<f32> {
    phrase_starts(r).into_iter().map(|(_, l)| l).collect()
}

fn median(mut v: Vec<f32>) -> f32 {
    v.sort_by(f32::total_cmp);
    v[v.len() / 2]
}

#[test]
fn live_mode_fills_the_lung_in_the_pauses_the_speaker_takes() {
    // Phrases with half-second pauses, as a read speaker's breath pauses last: live mode waits
    // a minimum pause before it breathes in and cannot know when the next word comes, so its
    // inhalation is sized to the pauses the speaker has taken, and a pause too short for a
    // breath ends no group. The lung at each phrase's start (after the first) comes near what a
    // lookahead render, which knows every pause, gives. Before, the preset's 0.6 s inhalation
    // was cut short by the next word and every short pause started a small group: the median
    // live lung was 0.28 against the lookahead's 0.55.
    let (audio, _) = crate::generated_phrases::sequence(
        0.6,
        &[1.4, 0.9, 1.6, 1.1, 1.3, 0.8, 1.5, 1.2],
        &[0.5, 0.45, 0.12, 0.55, 0.5, 0.1, 0.45, 0.8],
    );
    let sr = crate::generated_phrases::SR;
    let starts = |mode| {
        let mut c = config(mode, 0.25);
        // Generated vowels are not speech to the speech decision.
        c.placement.speech_only = false;
        lungs_at_phrase_starts(&render(&c, &audio, sr))
    };
    let (live, lookahead) = (
        starts(PlacementMode::Live),
        starts(PlacementMode::Lookahead),
    );
    let (live_m, lookahead_m) = (median(live.clone()), median(lookahead.clone()));
    assert!(
        live_m >= 0.75 * lookahead_m && lookahead_m > 0.4,
        "median lung at phrase starts: live {live_m:.2} {live:.2?}, lookahead {lookahead_m:.2} \
         {lookahead:.2?}"
    );
}

#[test]
fn a_long_silence_does_not_lengthen_the_live_breaths_after_it() {
    // Half-second breath pauses, a 10 s silence, and half-second pauses again. The silence is
    // not a breath pause: the live inhalations after it still fit the speaker's pauses and fill
    // the lung near what the lookahead render gives. Before, the silence took the pause
    // estimate from 0.5 to 3.4 s, the next breaths lasted 0.8 s, and the next words cut them
    // short: median lung 0.18 after the silence, against the lookahead's 0.41 (now 0.31).
    let pauses = [0.5, 0.45, 10.0, 0.5, 0.45, 0.5, 0.55];
    let (audio, spans) =
        crate::generated_phrases::sequence(0.6, &[1.4, 1.1, 1.3, 1.2, 1.5, 1.1, 1.3, 1.2], &pauses);
    let after_s = spans[3].0 - 0.1;
    let sr = crate::generated_phrases::SR;
    let starts = |mode| {
        let mut c = config(mode, 0.25);
        // Generated vowels are not speech to the speech decision.
        c.placement.speech_only = false;
        phrase_starts(&render(&c, &audio, sr))
            .into_iter()
            .filter(|&(t, _)| t > after_s)
            .map(|(_, l)| l)
            .collect::<Vec<f32>>()
    };
    let (live, lookahead) = (
        starts(PlacementMode::Live),
        starts(PlacementMode::Lookahead),
    );
    assert!(live.len() >= 3, "phrases after the silence: {live:?}");
    let (live_m, lookahead_m) = (median(live.clone()), median(lookahead.clone()));
    assert!(
        live_m >= 0.6 * lookahead_m && lookahead_m > 0.3,
        "median lung at the phrase starts after the silence: live {live_m:.2} {live:.2?}, \
         lookahead {lookahead_m:.2} {lookahead:.2?}"
    );
}
