//! Tests of the phrase tracker: scripted level and voicing sequences and the events they give.

use super::*;
use crate::analysis::{BandLevels, FeatureFrame};

fn frame(index: u64, rms_db: f32, voiced: bool) -> FeatureFrame {
    FeatureFrame {
        index,
        time_s: index as f64 / 100.0,
        f0_hz: if voiced { 150.0 } else { 0.0 },
        voiced,
        voicing: if voiced { 0.9 } else { 0.2 },
        rms_db,
        f0_st: 0.0,
        level_db: rms_db - -20.0,
        speech_level_db: -20.0,
        band_db: rms_db,
        bands: breathy(rms_db),
    }
}

/// The mid-band flatness of the noise the test frames stand for (white noise through the
/// analysis window).
const NOISE_FLATNESS: f32 = 0.56;

/// Band levels of broadband breath noise at `rms_db`: most energy in the mid band, the high
/// band 2 dB inside the shipped breath shape's limit.
fn breathy(rms_db: f32) -> BandLevels {
    let mid_db = rms_db - 1.5;
    BandLevels {
        low_db: rms_db - 12.0,
        mid_db,
        high_db: breath_high_db(mid_db),
        mid_flatness: NOISE_FLATNESS,
    }
}

/// The high band of a breath whose mid band is at `mid_db`: 2 dB inside the shipped breath
/// shape's limit.
fn breath_high_db(mid_db: f32) -> f32 {
    mid_db + PhraseConfig::default().breath_max_high_over_mid_db - 2.0
}

/// Runs a scripted level/voicing sequence at 100 frames/s and collects the start and end
/// events.
fn run(script: &[(usize, f32, bool)]) -> Vec<PhraseEvent> {
    run_all(script)
        .into_iter()
        .filter(|e| !matches!(e, PhraseEvent::Activity { .. }))
        .collect()
}

/// The pauses of `events`' phrase starts, in order.
fn pauses_of(events: &[PhraseEvent]) -> Vec<Pause> {
    events
        .iter()
        .filter_map(|e| match e {
            PhraseEvent::Start { pause, .. } => Some(*pause),
            _ => None,
        })
        .collect()
}

/// All events, activity included.
fn run_all(script: &[(usize, f32, bool)]) -> Vec<PhraseEvent> {
    run_edited(script, |_, _| {})
}

/// All events of a script whose frames `edit` changes (given the frame number).
fn run_edited(
    script: &[(usize, f32, bool)],
    edit: impl Fn(u64, &mut FeatureFrame),
) -> Vec<PhraseEvent> {
    run_probed(script, edit, |_, _| {})
}

/// All events of a script whose frames `edit` changes; `probe` sees the tracker after each
/// frame (given the frame number).
fn run_probed(
    script: &[(usize, f32, bool)],
    edit: impl Fn(u64, &mut FeatureFrame),
    mut probe: impl FnMut(u64, &PhraseTracker),
) -> Vec<PhraseEvent> {
    let mut t = PhraseTracker::new(PhraseConfig::default(), 100.0).unwrap();
    let mut events = Vec::new();
    let mut i = 0u64;
    for &(n, db, v) in script {
        for _ in 0..n {
            let mut f = frame(i, db, v);
            edit(i, &mut f);
            t.update(&f, |e| events.push(e));
            probe(i, &t);
            i += 1;
        }
    }
    events
}

#[test]
fn two_phrases_give_start_end_start_with_the_pause() {
    let ev = run(&[
        (100, -70.0, false),
        (150, -20.0, true),
        (60, -70.0, false),
        (150, -20.0, true),
        (100, -70.0, false),
    ]);
    assert_eq!(ev.len(), 4, "{ev:?}");
    match ev[0] {
        PhraseEvent::Start { onset_s, pause } => {
            assert!((onset_s - 1.0).abs() < 0.011, "{onset_s}");
            assert!(pause.leading && pause.start_s == 0.0);
        }
        _ => panic!("{ev:?}"),
    }
    match ev[2] {
        PhraseEvent::Start { onset_s, pause } => {
            let p = pause;
            assert!(!p.leading && p.last_activity_end_s.is_none());
            assert!((onset_s - 3.1).abs() < 0.011, "{onset_s}");
            assert!((p.start_s - 2.5).abs() < 0.011, "{p:?}");
            assert!((p.length_s() - 0.6).abs() < 0.021, "{p:?}");
            assert!(!p.has_breath);
            assert_eq!(p.breath_s, None);
        }
        _ => panic!("{ev:?}"),
    }
}

#[test]
fn a_short_dip_inside_a_phrase_is_not_a_pause() {
    let ev = run(&[
        (100, -70.0, false),
        (100, -20.0, true),
        (8, -70.0, false),
        (100, -20.0, true),
        (100, -70.0, false),
    ]);
    assert_eq!(ev.len(), 2, "{ev:?}");
}

#[test]
fn unvoiced_noise_bursts_do_not_start_phrases_but_count_as_breath() {
    let ev = run(&[
        (100, -70.0, false),
        (100, -20.0, true),
        (40, -70.0, false),
        (35, -48.0, false), // breath-like: 22 dB under speech, 22 dB over the floor
        (30, -70.0, false),
        (100, -20.0, true),
        (50, -70.0, false),
    ]);
    let starts = pauses_of(&ev);
    assert_eq!(starts.len(), 2, "{ev:?}");
    assert!(starts[1].has_breath, "{ev:?}");
    // Its span: the burst's frames 240..275.
    let (start_s, end_s) = starts[1].breath_s.expect("the breath's span");
    assert!(
        (start_s - 2.40).abs() < 0.021 && (end_s - 2.75).abs() < 0.021,
        "breath at {start_s}..{end_s} s, want 2.40..2.75"
    );
    assert_eq!(
        starts[0].breath_s, None,
        "no breath before the first phrase"
    );
}

/// The pauses' `breath_s` of a script's phrase starts.
fn breaths_of(script: &[(usize, f32, bool)]) -> Vec<Option<(f64, f64)>> {
    breaths_edited(script, |_, _| {})
}

#[test]
fn a_reverberant_tail_is_not_a_breath_but_a_rise_after_it_is() {
    // A phrase whose sound decays over 0.6 s (3 dB per 50 ms, unvoiced) into the pause.
    let tail: Vec<(usize, f32, bool)> =
        (0..8).map(|k| (5, -42.0 - 3.0 * k as f32, false)).collect();
    let mut only_tail = vec![(100, -70.0, false), (100, -20.0, true)];
    only_tail.extend(&tail);
    only_tail.extend([(40, -70.0, false), (100, -20.0, true), (50, -70.0, false)]);
    assert_eq!(
        breaths_of(&only_tail),
        [None, None],
        "a tail heard as a breath"
    );
    // The same tail, then noise rising again 8 dB before the next phrase: an inhalation.
    let mut tail_then_breath = vec![(100, -70.0, false), (100, -20.0, true)];
    tail_then_breath.extend(&tail);
    tail_then_breath.extend([
        (25, -55.0, false),
        (5, -70.0, false),
        (100, -20.0, true),
        (50, -70.0, false),
    ]);
    let b = breaths_of(&tail_then_breath);
    assert!(b[1].is_some(), "the rise after the tail is a breath: {b:?}");
}

/// The pauses' `breath_s` of a script whose unvoiced frames between `from` and `to`
/// (frame numbers) carry `bands` instead of breath-like band levels.
fn breaths_with_bands(
    script: &[(usize, f32, bool)],
    (from, to): (u64, u64),
    bands: impl Fn(f32) -> BandLevels,
) -> Vec<Option<(f64, f64)>> {
    breaths_edited(script, |i, f| {
        if (from..to).contains(&i) {
            f.bands = bands(f.band_db);
        }
    })
}

/// The pauses' `breath_s` of a script whose frames `edit` changes (given the frame number).
fn breaths_edited(
    script: &[(usize, f32, bool)],
    edit: impl Fn(u64, &mut FeatureFrame),
) -> Vec<Option<(f64, f64)>> {
    run_edited(script, edit)
        .into_iter()
        .filter_map(|e| match e {
            PhraseEvent::Start { pause, .. } => Some(pause.breath_s),
            _ => None,
        })
        .collect()
}

/// The pauses' `breath_s` of a script whose unvoiced frames carry `bands(frame number)`.
fn breaths_with_pause_bands(
    script: &[(usize, f32, bool)],
    bands: impl Fn(u64) -> BandLevels,
) -> Vec<Option<(f64, f64)>> {
    breaths_edited(script, |i, f| {
        if !f.voiced {
            f.bands = bands(i);
        }
    })
}

/// Two phrases at −20 dB (frames 100..200 and 305..405) in a room at `room_db`, with an
/// unvoiced burst at `burst_db` in the pause between them (frames 240..275).
fn burst_between_phrases(room_db: f32, burst_db: f32) -> [(usize, f32, bool); 7] {
    [
        (100, room_db, false),
        (100, -20.0, true),
        (40, room_db, false),
        (35, burst_db, false),
        (30, room_db, false),
        (100, -20.0, true),
        (50, room_db, false),
    ]
}

#[test]
fn a_breath_over_a_humming_room_is_heard_in_its_own_bands() {
    // A room whose hum (100-400 Hz) carries its level: a breath adds 20 dB in the mid and
    // high bands but only 3 dB to the voice-band level, under the 6 dB breath margin.
    let room = BandLevels {
        low_db: -50.2,
        mid_db: -70.0,
        high_db: -80.0,
        mid_flatness: NOISE_FLATNESS,
    };
    let breath = BandLevels {
        mid_db: -50.0,
        high_db: breath_high_db(-50.0),
        mid_flatness: NOISE_FLATNESS,
        ..room
    };
    let script = burst_between_phrases(-50.0, -47.0);
    let with = |burst_bands: BandLevels| {
        breaths_with_pause_bands(&script, |i| {
            if (240..275).contains(&i) {
                burst_bands
            } else {
                room
            }
        })
    };
    let heard = with(breath);
    assert_eq!(heard.len(), 2, "{heard:?}");
    let (start_s, end_s) = heard[1].expect("the breath heard over the hum");
    assert!(
        (start_s - 2.40).abs() < 0.021 && (end_s - 2.75).abs() < 0.021,
        "breath at {start_s}..{end_s} s, want 2.40..2.75"
    );
    // The same 3 dB rise in the hum's own band alone is the room, not a breath.
    let louder_hum = BandLevels {
        low_db: -47.0,
        ..room
    };
    assert_eq!(with(louder_hum)[1], None);
}

#[test]
fn a_breath_right_after_a_tail_rises_in_its_own_bands_over_a_humming_room() {
    // A room whose hum (100-400 Hz) carries the voice-band level, -50 dBFS. The phrase's tail
    // falls to the hum in the voice band while its breath bands still stand over the room, and
    // a breath follows at once: it lifts the voice band 2 dB over the hum (under the 3 dB a
    // run starting at the offset must rise to be more than a tail) but its own bands 10 dB.
    let room = BandLevels {
        low_db: -50.2,
        mid_db: -70.0,
        high_db: -80.0,
        mid_flatness: NOISE_FLATNESS,
    };
    let tail_mid_db = [-44.0, -50.0, -56.0, -60.0];
    let script = [
        (100, -50.0, false),
        (100, -20.0, true),
        (5, -42.0, false), // the tail: frames 200..220
        (5, -46.0, false),
        (5, -50.0, false),
        (5, -50.0, false),
        (35, -48.0, false), // the breath: frames 220..255
        (30, -50.0, false),
        (100, -20.0, true),
        (50, -50.0, false),
    ];
    let heard = |breath_mid_db: f32, breath_low_db: f32| {
        breaths_with_pause_bands(&script, |i| match i {
            200..220 => {
                let mid_db = tail_mid_db[(i as usize - 200) / 5];
                BandLevels {
                    mid_db,
                    high_db: mid_db - 10.0,
                    mid_flatness: NOISE_FLATNESS,
                    ..room
                }
            }
            220..255 => BandLevels {
                low_db: breath_low_db,
                mid_db: breath_mid_db,
                high_db: breath_high_db(breath_mid_db),
                mid_flatness: NOISE_FLATNESS,
            },
            _ => room,
        })
    };
    let with_breath = heard(-50.0, room.low_db);
    assert_eq!(with_breath.len(), 2, "{with_breath:?}");
    let (start_s, end_s) = with_breath[1]
        .unwrap_or_else(|| panic!("the breath after the tail is heard: {with_breath:?}"));
    assert!(
        (2.0..2.2).contains(&start_s) && (end_s - 2.55).abs() < 0.021,
        "breath at {start_s}..{end_s} s, want from the offset in the tail to 2.55 s"
    );
    // Breath-shaped sound that only holds the tail's last level in its own bands (a rise under
    // 3 dB in both levels) is still the tail: no breath.
    assert_eq!(heard(-60.0, -80.0)[1], None);
}

#[test]
fn a_gated_silence_does_not_teach_the_room_that_it_is_silent() {
    // A hissing room (its high band carries its level), a pause an editor gated to digital
    // silence for 3 s, a 3 s phrase, then a pause with a breath over the hiss. The breath
    // alone sits 2 dB inside the shape limit; with the hiss left in, its high band stands over
    // its mid band. Had the gated frames taught the room, the room would be 13 dB too quiet
    // when the breath comes.
    let room = BandLevels {
        low_db: -80.0,
        mid_db: -72.0,
        high_db: -52.0,
        mid_flatness: NOISE_FLATNESS,
    };
    let breath_mid_db = -50.0;
    let power_sum_db =
        |a: f32, b: f32| 10.0 * (10f32.powf(a / 10.0) + 10f32.powf(b / 10.0)).log10();
    let breath_over_room = BandLevels {
        low_db: power_sum_db(room.low_db, breath_mid_db - 12.0),
        mid_db: power_sum_db(room.mid_db, breath_mid_db),
        high_db: power_sum_db(room.high_db, breath_high_db(breath_mid_db)),
        mid_flatness: NOISE_FLATNESS,
    };
    let script = [
        (100, -55.0, false),
        (100, -20.0, true),
        (300, -120.0, false), // gated: frames 200..500
        (300, -20.0, true),
        (40, -55.0, false),
        (35, -46.0, false), // the breath: frames 840..875
        (30, -55.0, false),
        (100, -20.0, true),
        (50, -55.0, false),
    ];
    let heard = breaths_with_pause_bands(&script, |i| match i {
        200..500 => BandLevels::FLOOR,
        840..875 => breath_over_room,
        _ => room,
    });
    assert_eq!(heard.len(), 3, "{heard:?}");
    let (start_s, end_s) =
        heard[2].unwrap_or_else(|| panic!("the breath after the gated pause is heard: {heard:?}"));
    assert!(
        (start_s - 8.40).abs() < 0.021 && (end_s - 8.75).abs() < 0.021,
        "breath at {start_s}..{end_s} s, want 8.40..8.75"
    );
}

#[test]
fn a_burst_shaped_like_a_sibilant_or_a_vowel_tail_is_no_breath() {
    // A breath-like burst 22 dB under speech.
    let script = burst_between_phrases(-70.0, -48.0);
    let burst = (240, 275);
    assert!(breaths_with_bands(&script, burst, breathy)[1].is_some());
    // /s/: the high band 10 dB over the mid band.
    let sibilant = |db: f32| BandLevels {
        low_db: db - 25.0,
        mid_db: db - 10.0,
        high_db: db - 0.5,
        mid_flatness: NOISE_FLATNESS,
    };
    assert_eq!(breaths_with_bands(&script, burst, sibilant)[1], None);
    // A vowel's tail or rumble: the low band 8 dB over the mid band.
    let low = |db: f32| BandLevels {
        low_db: db - 0.5,
        mid_db: db - 8.5,
        high_db: db - 20.0,
        mid_flatness: NOISE_FLATNESS,
    };
    assert_eq!(breaths_with_bands(&script, burst, low)[1], None);
}

#[test]
fn a_quiet_initial_consonant_moves_the_onset_back() {
    let ev = run(&[
        (100, -70.0, false),
        (10, -45.0, false), // an /f/ 25 dB under speech
        (100, -20.0, true),
        (50, -70.0, false),
    ]);
    match ev[0] {
        PhraseEvent::Start { onset_s, .. } => assert!((onset_s - 1.0).abs() < 0.011),
        _ => panic!("{ev:?}"),
    }
}

#[test]
fn a_loud_unvoiced_burst_in_a_pause_is_reported_and_bounds_the_pause() {
    let ev = run_all(&[
        (100, -70.0, false),
        (100, -20.0, true),
        (30, -70.0, false),
        (8, -22.0, false), // a click or a word too short to confirm, at 2.3 s
        (40, -70.0, false),
        (100, -20.0, true),
        (50, -70.0, false),
    ]);
    let activity: Vec<f64> = ev
        .iter()
        .filter_map(|e| match e {
            PhraseEvent::Activity { time_s } => Some(*time_s),
            _ => None,
        })
        .collect();
    assert!(activity.iter().any(|t| (t - 2.3).abs() < 0.011), "{ev:?}");
    let last = *pauses_of(&ev).last().unwrap();
    let end = last.last_activity_end_s.expect("the burst is reported");
    assert!((end - 2.38).abs() < 0.011, "{last:?}");
}

/// A phrase at 1–2 s, then, in the pause, an unvoiced burst at 2.3–2.35 s (`burst_voiced`: its
/// middle frame voiced), `gap` frames of quiet, a soft onset (over the floor, not active) and
/// the next phrase at 2.45 s.
fn pause_with_a_leading_burst(burst_voiced: bool, gap: usize) -> Pause {
    let ev = run(&[
        (100, -70.0, false),
        (100, -20.0, true),
        (30, -70.0, false),
        (2, -22.0, false),
        (1, -22.0, burst_voiced),
        (2, -22.0, false),
        (gap, -70.0, false),
        (10 - gap, -45.0, false),
        (100, -20.0, true),
        (50, -70.0, false),
    ]);
    *pauses_of(&ev).last().unwrap()
}

#[test]
fn an_unvoiced_burst_a_stop_closure_before_the_onset_is_the_phrases_lead_in() {
    // An /s/, its stop's closure (40 ms: longer than the run gap, so the burst dies as a run
    // of its own), the vowel's soft onset: the speech starts at the /s/, and the pause holds
    // no other activity. Before, the burst was the pause's last activity, ending 40 ms before
    // the onset: nothing could be placed before the phrase.
    let p = pause_with_a_leading_burst(false, 4);
    assert!(
        p.lead_in_s.is_some_and(|t| (t - 2.30).abs() < 0.011),
        "{p:?}"
    );
    assert_eq!(p.last_activity_end_s, None, "{p:?}");
    assert!((p.end_s - 2.39).abs() < 0.011, "the onset stays: {p:?}");
    // A voiced burst (a word too short to confirm) and a burst further from the onset than a
    // run gap stay the pause's activity.
    for p in [
        pause_with_a_leading_burst(true, 4),
        pause_with_a_leading_burst(false, 10),
    ] {
        assert_eq!(p.lead_in_s, None, "{p:?}");
        assert!(
            p.last_activity_end_s
                .is_some_and(|t| (t - 2.35).abs() < 0.011),
            "{p:?}"
        );
    }
}

#[test]
fn a_breath_before_the_first_phrase_is_seen() {
    let ev = run(&[
        (50, -70.0, false),
        (35, -48.0, false),
        (30, -70.0, false),
        (100, -20.0, true),
        (30, -70.0, false),
    ]);
    match ev[0] {
        PhraseEvent::Start { pause, .. } => assert!(pause.leading && pause.has_breath),
        _ => panic!("{ev:?}"),
    }
}

#[test]
fn nan_levels_are_silence() {
    let ev = run(&[
        (100, f32::NAN, false),
        (100, -20.0, true),
        (50, f32::NAN, false),
    ]);
    assert_eq!(ev.len(), 2, "{ev:?}");
}

#[test]
fn an_unvoiced_burst_is_speech_only_near_the_speech_level() {
    // An unvoiced burst at −30 dBFS, 40 dB over the floor, in a pause (at 2.3 s): within
    // `unvoiced_drop_db` (12 dB) of a −25 dBFS speaker it is activity; 25 dB under a −5 dBFS
    // speaker it is not. Only the frames' speech level differs (their level_db stays).
    let script = [
        (100, -70.0, false),
        (100, -20.0, true),
        (30, -70.0, false),
        (8, -30.0, false),
        (40, -70.0, false),
        (100, -20.0, true),
        (50, -70.0, false),
    ];
    for (speech_level_db, heard) in [(-25.0, true), (-5.0, false)] {
        let ev = run_edited(&script, |_, f| f.speech_level_db = speech_level_db);
        let activity = ev
            .iter()
            .any(|e| matches!(e, PhraseEvent::Activity { time_s } if (time_s - 2.3).abs() < 0.011));
        assert_eq!(
            activity, heard,
            "speech level {speech_level_db} dBFS: {ev:?}"
        );
    }
}

#[test]
fn a_breath_cut_short_by_digital_silence_or_dither_reports_the_stretch_beside_it() {
    // A breath's first 0.15 s (frames 240..255) heard, the rest of the pause gated to digital
    // silence (frames 255..305) as an editor's cut leaves it.
    let pauses = |gated_db: f32| -> Vec<Pause> {
        pauses_of(&run(&[
            (100, -70.0, false),
            (100, -20.0, true),
            (40, -70.0, false),
            (15, -48.0, false),
            (50, gated_db, false),
            (100, -20.0, true),
            (50, -70.0, false),
        ]))
    };
    let cut = pauses(-120.0);
    assert_eq!(cut.len(), 2, "{cut:?}");
    let (heard_from_s, heard_to_s) = cut[1].breath_s.expect("the breath's remnant is heard");
    let (gated_from_s, gated_to_s) = cut[1].gated_s.expect("the gated stretch is reported");
    assert!(
        (heard_from_s - 2.40).abs() < 0.021 && (heard_to_s - 2.55).abs() < 0.021,
        "heard {heard_from_s}..{heard_to_s} s, want 2.40..2.55"
    );
    assert!(
        (gated_from_s - 2.55).abs() < 0.011 && (gated_to_s - 3.05).abs() < 0.011,
        "gated {gated_from_s}..{gated_to_s} s, want 2.55..3.05"
    );
    assert_eq!(cut[0].gated_s, None, "{cut:?}");
    // A quiet room (the tracker's own silence level and under) is no cut.
    for room_db in [-70.0, -80.0] {
        assert_eq!(pauses(room_db)[1].gated_s, None, "room at {room_db} dBFS");
    }
    // A cut exported at 16 bits with dither (about -96 dBFS over the full band, lower in the
    // voice band) is a cut, as digital silence is.
    for dither_db in [-96.0, -100.0, -105.0] {
        let dithered = pauses(dither_db);
        assert_eq!(dithered[1].breath_s, cut[1].breath_s, "{dither_db} dBFS");
        assert_eq!(dithered[1].gated_s, cut[1].gated_s, "{dither_db} dBFS");
    }
}

#[test]
fn digital_silence_between_two_rooms_does_not_teach_the_noise_floor() {
    // A segment in a room at -50 dB, 4 s of digital silence (an edit), a segment in a room at
    // -55 dB whose pause is 0.5 s of room tone. The floor after the silence is the rooms'
    // (-55 dB), not the silence's: the room tone is no sound over the floor, and the pause
    // keeps its length.
    let script = [
        (100, -50.0, false),
        (100, -20.0, true),
        (100, -50.0, false),
        (400, -120.0, false),
        (100, -55.0, false),
        (100, -20.0, true),
        (50, -55.0, false),
        (100, -20.0, true),
        (100, -55.0, false),
    ];
    let mut floor_after_silence_db = f32::NAN;
    let events = run_probed(
        &script,
        |_, _| {},
        |i, t| {
            if i == 710 {
                floor_after_silence_db = t.noise_floor_db();
            }
        },
    );
    assert_eq!(floor_after_silence_db, -55.0);
    let starts = pauses_of(&events);
    assert_eq!(starts.len(), 3, "{events:?}");
    let last = starts[2];
    assert!((last.end_s - 9.5).abs() < 0.011, "{last:?}");
    assert!((last.length_s() - 0.5).abs() < 0.021, "{last:?}");
}

/// The pause of a script: a phrase, a breath-like run (2.3–2.5 s), a loud burst of 8 frames
/// (2.5–2.58 s) whose middle `voiced` frames are voiced (too few to confirm a phrase),
/// breath-like frames again (2.58–2.73 s), quiet, a phrase.
fn pause_around_a_burst(voiced: usize) -> Pause {
    let side = (8 - voiced) / 2;
    let ev = run(&[
        (100, -70.0, false),
        (100, -20.0, true),
        (30, -70.0, false),
        (20, -48.0, false),
        (side, -22.0, false),
        (voiced, -22.0, true),
        (8 - voiced - side, -22.0, false),
        (15, -48.0, false),
        (40, -70.0, false),
        (100, -20.0, true),
        (50, -70.0, false),
    ]);
    *pauses_of(&ev).last().unwrap()
}

/// `span` lies at (`a`, `b`) seconds, within a frame.
fn at(span: Option<(f64, f64)>, a: f64, b: f64) -> bool {
    span.is_some_and(|(x, y)| (x - a).abs() < 0.011 && (y - b).abs() < 0.011)
}

#[test]
fn a_breath_heard_again_after_a_short_word_is_not_one_breath_over_the_word() {
    // The voiced burst closes the first run: the pause's breath is that run, never a span
    // reaching over the word (such a span was learnt as one breath as loud as the speech).
    let pause = pause_around_a_burst(2);
    assert!(at(pause.breath_s, 2.3, 2.5), "{pause:?}");
    assert!(at(pause.breath_clean_s, 2.3, 2.5), "{pause:?}");
}

#[test]
fn an_unvoiced_blip_inside_a_breath_leaves_the_breath_whole() {
    // A breath's loudest moment may reach the activity level without voicing: the run goes
    // on after it (a gated cut after the breath then touches the breath it belongs to), and
    // a voice learns from the part before the blip only.
    let pause = pause_around_a_burst(0);
    assert!(at(pause.breath_s, 2.3, 2.73), "{pause:?}");
    assert!(at(pause.breath_clean_s, 2.3, 2.5), "{pause:?}");
}

#[test]
fn a_quiet_take_hears_the_breath_a_loud_one_hears() {
    // Two phrases with a breath between them in a quiet room, at a normal gain (speech at
    // -20 dBFS, the breath 30 dB under it at -50, the room at -70) and the same take 35 dB
    // quieter (the breath at -85 dBFS, under the default silence level of -75).
    let script = |gain_db: f32| {
        [
            (100, -70.0 + gain_db, false),
            (100, -20.0 + gain_db, true),
            (30, -70.0 + gain_db, false),
            (30, -50.0 + gain_db, false),
            (30, -70.0 + gain_db, false),
            (100, -20.0 + gain_db, true),
            (50, -70.0 + gain_db, false),
        ]
    };
    let breath = |gain_db: f32| {
        let ev = run_edited(&script(gain_db), |_, f| {
            f.speech_level_db = -20.0 + gain_db;
            f.level_db = f.rms_db - f.speech_level_db;
        });
        pauses_of(&ev).get(1).map(|p| (p.breath_s, p.gated_s))
    };
    let (loud, gated) = breath(0.0).expect("a pause at a normal gain");
    let loud = loud.expect("the breath is heard at a normal gain");
    assert!((loud.0 - 2.3).abs() < 0.03, "{loud:?}");
    assert_eq!(gated, None, "a room is no cut");
    // The same breath, and the quiet take's room (-105 dBFS) is no cut either.
    assert_eq!(breath(-35.0), Some((Some(loud), None)));
}

/// Frames `n` of a level `db` that dips to `dip_db` on every fourth frame (unvoiced).
fn dipping(n: usize, db: f32, dip_db: f32) -> Vec<(usize, f32, bool)> {
    (0..n)
        .map(|k| (1, if k % 4 == 3 { dip_db } else { db }, false))
        .collect()
}

#[test]
fn a_breath_that_dips_under_the_margin_in_a_noisy_room_is_held_but_not_learnt() {
    // A room at -70 dB: the breath margin lies at -64 dB, the hold at -67 dB. A breath 8 dB over
    // the room dips to 3.5 dB over it on every fourth frame: its strict runs (3 frames) are too
    // short to count.
    let mut script = vec![(100, -70.0, false), (100, -20.0, true), (30, -70.0, false)];
    script.extend(dipping(40, -62.0, -66.5));
    script.extend([(20, -70.0, false), (100, -20.0, true), (50, -70.0, false)]);
    let pauses = pauses_of(&run(&script));
    let (from_s, to_s) = pauses[1].breath_s.expect("the breath is heard");
    assert!(
        (2.28..=2.32).contains(&from_s) && (2.68..=2.72).contains(&to_s),
        "{from_s}-{to_s}"
    );
    // A held run's edges hold more room than breath: the voice does not learn from it.
    assert_eq!(pauses[1].breath_clean_s, None);
    // Noise that never reaches the margin starts no run, however long it hovers over the hold.
    let mut hover = vec![(100, -70.0, false), (100, -20.0, true), (30, -70.0, false)];
    hover.push((40, -65.5, false));
    hover.extend([(20, -70.0, false), (100, -20.0, true), (50, -70.0, false)]);
    assert_eq!(breaths_of(&hover), [None, None]);
}

#[test]
fn a_tail_whose_ripple_dips_under_the_margin_is_no_breath() {
    // A phrase's tail from its offset on, 6 to 2 dB over the margin, dipping under it (3.5 dB
    // over the room) on every fourth frame: a held run from the offset rises after each dip,
    // yet it only continues the decay.
    let mut script = vec![(100, -70.0, false), (100, -20.0, true)];
    script.extend(
        dipping(40, 0.0, -66.5)
            .into_iter()
            .enumerate()
            .map(|(k, (n, db, v))| {
                (
                    n,
                    if db == 0.0 {
                        -58.0 - 0.1 * k as f32
                    } else {
                        db
                    },
                    v,
                )
            }),
    );
    script.extend([(30, -70.0, false), (100, -20.0, true), (50, -70.0, false)]);
    let p = pauses_of(&run(&script));
    assert_eq!(p[1].breath_s, None, "a tail heard as a breath: {:?}", p[1]);
    // Its first dip (the offset's frame) under the hold too: the decay is still open after it.
    script[5].1 = -67.5;
    let p = pauses_of(&run(&script));
    assert_eq!(p[1].breath_s, None, "a tail heard as a breath: {:?}", p[1]);
}
