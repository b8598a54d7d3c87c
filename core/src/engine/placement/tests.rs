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

/// A phrase of the last test: its onset, offset and pause start, s; speech judgement; level.
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

/// Breaths placed (start, end, seconds) in the pauses of `phrases` after a phrase of speech.
fn breaths_between(phrases: &[Seen]) -> Vec<(f64, f64)> {
    let rate = 48_000.0;
    let config = EngineConfig::default();
    let speech = SpeechTrack::new(None, rate, 120.0, (-75.0, 6.0));
    let pending = Queue::with_capacity(4);
    let mut placement = Placement::new(PlacementMode::Lookahead, 24_000, rate, 120.0);
    placement.state.prev_speech = Some(true);
    for &ph in phrases {
        placement.seen.push_back(ph);
    }
    let ctx = EventContext {
        config: &config,
        // The output (half a second behind) reaches the first pause.
        now: (10.0 * rate) as u64 + 24_000,
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
        .breath
        .iter()
        .filter_map(|&(at, a)| match a {
            BreathAction::Start { length, .. } => {
                Some((at as f64 / rate, (at + length as u64) as f64 / rate))
            }
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
    let (start_s, end_s) = quiet[0];
    assert!(start_s > 10.0 && end_s < 10.8 && end_s > 10.55, "{quiet:?}");
    // A note as loud as the speech (a sting) is no pause: nothing goes before the speech.
    assert_eq!(breaths_between(&phrases(-27.0)), vec![]);
    // Nor does a quiet sound after the speech with nothing after it.
    assert_eq!(breaths_between(&phrases(-48.0)[..1]), vec![]);
}

fn round_ms(s: f64) -> i64 {
    (s * 1000.0).round() as i64
}
