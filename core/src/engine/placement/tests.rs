//! Tests of breath placement's pure rules and of its decisions on phrases set up by hand.

use super::*;

#[test]
fn the_rest_of_a_cut_breath_goes_beside_the_heard_part_into_the_gated_stretch() {
    // A 0.4 s breath wanted; 0.1 s of it heard before (or after) a gated stretch.
    let limits = (1.05, 1.56);
    let after = rest_of_cut_breath((1.0, 1.1), (1.1, 1.6), 0.4, limits, 0.0);
    assert_eq!(
        after.map(|(a, b)| (round_ms(a), round_ms(b))),
        Some((1100, 1400))
    );
    let before = rest_of_cut_breath((1.5, 1.6), (1.0, 1.5), 0.4, (1.05, 1.7), 0.0);
    assert_eq!(
        before.map(|(a, b)| (round_ms(a), round_ms(b))),
        Some((1200, 1500))
    );
    // Bounded by the onset's gap, the phrase's margin and what the output has passed.
    let late = rest_of_cut_breath((1.0, 1.1), (1.1, 1.6), 0.4, (1.05, 1.3), 0.0);
    assert_eq!(
        late.map(|(a, b)| (round_ms(a), round_ms(b))),
        Some((1100, 1300))
    );
    let passed = rest_of_cut_breath((1.0, 1.1), (1.1, 1.6), 0.4, limits, 1.5);
    assert_eq!(passed, None, "0.06 s left after what was played");
    // Too little room, no breath.
    assert_eq!(
        rest_of_cut_breath((1.0, 1.1), (1.1, 1.2), 0.4, limits, 0.0),
        None
    );
    // A heard part half a breath long or more is a whole breath (a gate that opened for
    // it): nothing beside it.
    assert_eq!(
        rest_of_cut_breath((0.9, 1.1), (1.1, 1.6), 0.4, limits, 0.0),
        None
    );
    let short = rest_of_cut_breath((0.92, 1.1), (1.1, 1.6), 0.4, limits, 0.0);
    assert_eq!(
        short.map(|(a, b)| (round_ms(a), round_ms(b))),
        Some((1100, 1320))
    );
}

/// A phrase set up for the tests below: its onset, offset and pause start, seconds; its speech
/// judgement; its voiced median, dBFS (the phrase before it spoke at −25 dBFS).
fn seen(onset_s: f64, offset_s: f64, pause_start_s: f64, speech: bool, own_db: f32) -> Seen {
    Seen {
        onset_s,
        speech_onset_s: onset_s,
        offset_s: Some(offset_s),
        pause: Pause {
            start_s: pause_start_s,
            end_s: onset_s,
            leading: false,
            ..Seen::default().pause
        },
        level_db: -25.0,
        own_db: Some(own_db),
        speech: Some(speech),
        ..Seen::default()
    }
}

const RATE_HZ: f64 = 48_000.0;

/// A lookahead placement (0.5 s) after a phrase of speech that ended at 10 s, holding
/// `phrases`.
fn placement_with(phrases: &[Seen]) -> Placement {
    let mut placement = Placement::new(PlacementMode::Lookahead, 24_000, RATE_HZ, 120.0);
    placement.state.prev_speech = Some(true);
    for &ph in phrases {
        placement.seen.push_back(ph);
    }
    placement
}

/// What the placement decides for the pauses of `phrases` (see [`placement_with`]), the output
/// reaching 10 s.
fn decided(phrases: &[Seen]) -> Schedule {
    let config = EngineConfig::default();
    let speech = SpeechTrack::new(None, RATE_HZ, 120.0, (-75.0, 6.0));
    let pending = Queue::with_capacity(4);
    let mut placement = placement_with(phrases);
    let ctx = EventContext {
        config: &config,
        // The output (half a second behind) reaches the first pause.
        now: (10.0 * RATE_HZ) as u64 + 24_000,
        gains: [1.0; MAX_CHANNELS],
        breath_playing: false,
        pending: &pending,
        speech: &speech,
        upper_edge_hz: None,
        speech_db: -25.0,
    };
    let mut schedule = Schedule::new(16);
    while placement.seen.len() > 0 {
        placement.decide_front(&ctx, &mut schedule);
    }
    schedule
}

/// Breaths placed (start, end, seconds; plateau gain) in the pauses of `phrases`.
fn breaths_between(phrases: &[Seen]) -> Vec<(f64, f64, f32)> {
    decided(phrases)
        .breath
        .iter()
        .filter_map(|&(at, a)| match a {
            BreathAction::Start { length, gain, .. } => Some((
                at as f64 / RATE_HZ,
                (at + length as u64) as f64 / RATE_HZ,
                gain,
            )),
            _ => None,
        })
        .collect()
}

#[test]
fn a_quiet_sound_between_phrases_of_speech_is_part_of_their_pause() {
    // Speech ended at 10.0 s; a bed's note (not speech) sounds 10.55–10.8 s; speech again
    // from 10.8 s. The pause 10.0–10.8 s gets its breath, over the note.
    let phrases = |note_db| {
        [
            seen(10.55, 10.8, 10.0, false, note_db),
            seen(10.8, 12.0, 10.8, true, -25.0),
        ]
    };
    let quiet = breaths_between(&phrases(-48.0));
    assert_eq!(quiet.len(), 1, "{quiet:?}");
    let (start_s, end_s, _) = quiet[0];
    assert!(start_s > 10.0 && end_s < 10.8 && end_s > 10.55, "{quiet:?}");
    // A note as loud as the speech (a sting) is no pause: nothing goes before the speech.
    assert_eq!(breaths_between(&phrases(-27.0)), vec![]);
    // A quiet sound with nothing after it yet is decided as a phrase of its own (no breath).
    let alone = decided(&phrases(-48.0)[..1]);
    assert!(alone.breath.iter().next().is_none());
    assert!(alone
        .cycle
        .iter()
        .any(|&(t, a)| { t == 10.55 && matches!(a, CycleAction::UtteranceStarts { .. }) }));
}

#[test]
fn the_breath_over_a_quiet_sound_takes_the_speech_level_and_keeps_off_later_activity() {
    let config = EngineConfig::default();
    // The next phrase's level as the note left it (the last phrase heard): the breath takes
    // the speech's before the note.
    let mut next = seen(10.8, 12.0, 10.8, true, -25.0);
    next.level_db = -48.0;
    let breaths = breaths_between(&[seen(10.55, 10.8, 10.0, false, -48.0), next]);
    assert_eq!(breaths.len(), 1, "{breaths:?}");
    assert_eq!(breaths[0].2, Placement::breath_gain(&config, -25.0));
    // Activity after the note (a click, up to 10.5 s) keeps the breath after it.
    let mut next = seen(10.9, 12.0, 10.45, true, -25.0);
    next.pause.last_activity_end_s = Some(10.5);
    let breaths = breaths_between(&[seen(10.3, 10.45, 10.0, false, -48.0), next]);
    assert_eq!(breaths.len(), 1, "{breaths:?}");
    let after_s = 10.5 + f64::from(config.placement.after_offset_s);
    assert!(breaths[0].0 >= after_s - 1e-6, "{breaths:?}");
    // Two notes in one pause.
    let mut second = seen(10.55, 10.7, 10.45, false, -48.0);
    second.level_db = -47.0;
    let two = [
        seen(10.3, 10.45, 10.0, false, -48.0),
        second,
        seen(10.8, 12.0, 10.7, true, -25.0),
    ];
    let breaths = breaths_between(&two);
    assert_eq!(breaths.len(), 1, "{breaths:?}");
    assert!(breaths[0].0 < 10.55 && breaths[0].1 < 10.8, "{breaths:?}");
}

#[test]
fn a_quiet_sound_between_phrases_does_not_end_the_group_it_lies_in() {
    // Speech 9–10 s, a note 10.1–10.3 s, speech from 10.4 s: the gaps either side of the note
    // are shorter than a usable pause, the pause around it is not. The group known ends at
    // 10 s, with 1 s of speech.
    let mut first = seen(9.0, 10.0, 8.0, true, -25.0);
    first.level_db = -25.0;
    let placement = placement_with(&[
        first,
        seen(10.1, 10.3, 10.0, false, -48.0),
        seen(10.4, 12.0, 10.3, true, -25.0),
    ]);
    let min_pause_s = f64::from(EngineConfig::default().placement.min_pause_s);
    assert!(0.1 < min_pause_s && 0.4 >= min_pause_s);
    let (known_s, ended) = placement.known_group_s(12.5, min_pause_s);
    assert!((known_s - 1.0).abs() < 1e-9 && ended, "{known_s} {ended}");
}

fn round_ms(s: f64) -> i64 {
    (s * 1000.0).round() as i64
}

/// Voiced frames at `rms_db` every 1/120 s over `(from_s, to_s)`, as the lookahead holds them.
fn pending_frames(from_s: f64, to_s: f64, rms_db: f32) -> Queue<Pending> {
    let n = ((to_s - from_s) * 120.0).round() as usize;
    let mut q = Queue::with_capacity(n + 200);
    for k in 0..n {
        q.push_back(Pending {
            frame: FeatureFrame {
                time_s: from_s + k as f64 / 120.0,
                voiced: true,
                rms_db,
                ..FeatureFrame::default()
            },
            other_sound: false,
            emit_at: 0,
        });
    }
    q
}

#[test]
fn a_phrase_heard_for_less_than_the_speech_window_keeps_the_last_speaker_level() {
    // The last phrase spoke at −25 dBFS; the next one's first 0.1 s (a plugin's view of it
    // when its breath is decided) rises at −40 dBFS.
    let mut placement = placement_with(&[]);
    let spoken = pending_frames(8.0, 9.0, -25.0);
    placement.state.levels.start();
    for p in spoken.iter() {
        placement.state.levels.frame(&p.frame);
    }
    placement.state.levels.end();
    let mut next = seen(10.5, 12.0, 10.0, true, -40.0);
    next.own_db = None;
    let onset = pending_frames(10.5, 10.6, -40.0);
    let speaker_db = placement.speaker_of(&onset, Some(&next));
    assert!((speaker_db + 25.0).abs() < 0.5, "{speaker_db}");
    // Heard for the whole window, a quieter voice is its own speaker (an interview's guest).
    let window = pending_frames(10.5, 10.5 + JUDGE_WINDOW_S + 0.05, -40.0);
    let speaker_db = placement.speaker_of(&window, Some(&next));
    assert!((speaker_db + 40.0).abs() < 0.5, "{speaker_db}");
    // A phrase that ended at 10.6 s with too few voiced frames for a level of its own: the
    // next phrase's frames in the lookahead are not its own.
    next.offset_s = Some(10.6);
    let mut two = pending_frames(10.5, 10.6, -40.0);
    for p in pending_frames(10.8, 11.6, -40.0).iter() {
        two.push_back(*p);
    }
    let speaker_db = placement.speaker_of(&two, Some(&next));
    assert!((speaker_db + 25.0).abs() < 0.5, "{speaker_db}");
}
