//! Parameters (Equation 1), presets and the breath cycle (sawtooth slopes, rest, outputs).

use pneuma_core::breathing::{
    BreathCycle, BreathingError, BreathingParams, LowLevelParams, Preset, BASE_SYLLABLE_RATE_HZ,
    MIN_LUNG_VOLUME,
};
use pneuma_core::Phase;

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-5 * (1.0 + b.abs())
}

#[test]
fn equation_1_values_for_chosen_inputs() {
    let p = BreathingParams {
        thorax_vs_abdomen: 0.25,
        capacity_lung: 80.0,
        mouth_vs_nose: 0.75,
        amplitude_breathing_sound: 0.4,
        opening_inspiration_channels: 0.6,
        speaking_loudness: 0.2,
        prosody_rate: 1.25,
        inspiration_length_s: 1.5,
        neck_motion_amplitude_deg: 4.0,
        norm_syllables: 1.5,
        rest_period_s: 5.0,
        rest_depth: 0.1,
    };
    p.validate().unwrap();
    let l = p.map();
    // volume_abdomen = TvA * cap / 100; volume_thorax = (1 - TvA) * cap / 100.
    assert!(close(l.volume_abdomen, 0.2), "{}", l.volume_abdomen);
    assert!(close(l.volume_thorax, 0.6), "{}", l.volume_thorax);
    // Mouth share 0.75 (our reading: 1 = mouth).
    assert!(close(l.amplitude_sound_mouth, 0.3));
    assert!(close(l.amplitude_sound_nose, 0.1));
    assert!(close(l.amplitude_mouth_open, 0.45));
    assert!(close(l.amplitude_nostril_flare, 0.15));
    // sqrt(80 / 0.2) * 1.5 = 20 * 1.5 = 30 syllables; urgency 60 characters.
    assert!(close(l.length_utterance_syllables, 30.0));
    assert!(close(l.urgency_limit, 60.0));
    assert!(close(
        l.length_utterance_s,
        30.0 / (BASE_SYLLABLE_RATE_HZ * 1.25)
    ));
    // length_inspiration = 1.5 s * 80 / 100.
    assert!(close(l.length_inspiration_s, 1.2));
    assert!(close(l.amplitude_neck_motion_deg, 4.0));
    assert!(close(l.mouth_share(), 0.75));
}

#[test]
fn validation_names_the_parameter() {
    let p = BreathingParams {
        capacity_lung: 150.0,
        ..Default::default()
    };
    let e = p.validate().unwrap_err();
    assert!(matches!(
        e,
        BreathingError::OutOfRange {
            name: "capacity_lung",
            ..
        }
    ));
    assert!(e.to_string().contains("capacity_lung"));
    let nan = BreathingParams {
        mouth_vs_nose: f32::NAN,
        ..Default::default()
    };
    assert!(nan.validate().is_err());
}

#[test]
fn presets_are_valid_named_and_different() {
    for p in Preset::ALL {
        p.params().validate().unwrap();
        assert_eq!(Preset::from_name(p.name()).unwrap(), p);
        assert_eq!(Preset::from_name(&p.name().to_uppercase()).unwrap(), p);
    }
    assert!(Preset::from_name("sleepy").is_err());
    let calm = Preset::Calm.params().map();
    let anxious = Preset::Anxious.params().map();
    // Calm: long and deep; anxious: fast and shallow.
    assert!(calm.length_inspiration_s > 2.0 * anxious.length_inspiration_s);
    assert!(calm.length_utterance_syllables > 1.5 * anxious.length_utterance_syllables);
    assert!(calm.volume_abdomen > calm.volume_thorax);
    assert!(anxious.volume_thorax > anxious.volume_abdomen);
    assert!(calm.mouth_share() < 0.5 && anxious.mouth_share() > 0.5);
    assert!(calm.rest_period_s > 2.0 * anxious.rest_period_s);
}

fn run(cycle: &mut BreathCycle, seconds: f32, dt: f32) -> Vec<pneuma_core::BreathingState> {
    let n = (seconds / dt).round() as usize;
    (0..n).map(|_| cycle.advance(dt)).collect()
}

#[test]
fn sawtooth_slopes_equal_volume_over_length() {
    let params = LowLevelParams::default();
    let mut c = BreathCycle::new(&params);
    let dt = 1.0 / 120.0;
    let insp_s = 0.6;
    let utt_s = 2.0;
    let volume = c.lung_volume_for(utt_s);
    assert!(close(volume, utt_s / params.length_utterance_s));
    c.inspire(insp_s, utt_s);
    let rise = run(&mut c, 0.3, dt);
    assert!(rise.iter().all(|s| s.phase == Phase::Inspiration));
    let slope_in = (rise[29].lung - rise[9].lung) / (20.0 * dt);
    assert!(
        close(slope_in, volume / insp_s),
        "{slope_in} vs {}",
        volume / insp_s
    );
    run(&mut c, 0.3, dt);
    assert!((c.lung() - volume).abs() < 1e-4, "{} {volume}", c.lung());
    c.utterance_starts(utt_s);
    let fall = run(&mut c, 1.0, dt);
    assert!(fall.iter().all(|s| s.phase == Phase::Expiration));
    let slope_out = (fall[10].lung - fall[90].lung) / (80.0 * dt);
    assert!(
        close(slope_out, volume / utt_s),
        "{slope_out} vs {}",
        volume / utt_s
    );
    // Outputs follow the lung.
    let s = fall[50];
    assert!(close(s.thorax, s.lung * params.volume_thorax));
    assert!(close(s.abdomen, s.lung * params.volume_abdomen));
    assert!(close(
        s.neck_pitch_deg,
        s.lung * params.amplitude_neck_motion_deg
    ));
    // Empty at the expected end, then rest.
    run(&mut c, 1.0, dt);
    assert!(c.lung() < 1e-4);
    c.speech_stopped();
    assert_eq!(c.advance(dt).phase, Phase::Rest);
}

#[test]
fn volume_follows_the_upcoming_utterance() {
    let params = LowLevelParams::default();
    let c = BreathCycle::new(&params);
    assert!(close(c.lung_volume_for(0.1), MIN_LUNG_VOLUME));
    assert!(close(c.lung_volume_for(100.0), 1.0));
    assert!(c.lung_volume_for(3.0) > c.lung_volume_for(1.5));
}

#[test]
fn rest_is_a_gentle_continuous_tidal_breath() {
    let params = LowLevelParams::default();
    let mut c = BreathCycle::new(&params);
    let dt = 1.0 / 120.0;
    let states = run(&mut c, 4.0 * params.rest_period_s, dt);
    let max = states.iter().map(|s| s.lung).fold(0.0, f32::max);
    assert!(
        max > 0.5 * params.rest_depth && max <= params.rest_depth + 1e-6,
        "{max}"
    );
    for w in states.windows(2) {
        assert!((w[1].lung - w[0].lung).abs() < 0.01);
        assert_eq!(w[1].phase, Phase::Rest);
        assert_eq!(w[1].mouth_open, 0.0);
    }
    // Speech stopping mid-breath relaxes continuously toward the resting breath.
    c.inspire(0.5, 3.0);
    run(&mut c, 0.5, dt);
    c.utterance_starts(3.0);
    run(&mut c, 1.0, dt);
    let before = c.lung();
    c.speech_stopped();
    let after = run(&mut c, 3.0, dt);
    assert!((after[0].lung - before).abs() < 0.02);
    assert!(after.last().unwrap().lung < 0.5 * before);
}

#[test]
fn channels_open_during_inspiration_only() {
    let params = LowLevelParams::default();
    let mut c = BreathCycle::new(&params);
    let dt = 1.0 / 120.0;
    c.inspire(0.6, 2.0);
    let s = run(&mut c, 0.6, dt);
    let peak_mouth = s.iter().map(|s| s.mouth_open).fold(0.0, f32::max);
    assert!(close(peak_mouth, params.amplitude_mouth_open));
    assert!(s[0].mouth_open < 0.2 * params.amplitude_mouth_open);
    c.utterance_starts(2.0);
    let e = run(&mut c, 0.5, dt);
    assert!(e
        .iter()
        .all(|s| s.mouth_open == 0.0 && s.nostril_flare == 0.0));
}

#[test]
fn a_breath_group_fills_to_its_plan_spends_it_to_the_reserve_and_holds_in_its_pauses() {
    use pneuma_core::breathing::{RESERVE_DECAY_S, RESERVE_LUNG};
    let params = LowLevelParams::default();
    let mut c = BreathCycle::new(&params);
    let dt = 1.0 / 120.0;
    // A stream that starts in speech: the lung is at the plan at once.
    c.breathed_in(0.6);
    assert!(close(c.lung(), 0.6));
    // 3 s of speech left in the group: the lung reaches the reserve after 3 s, not before.
    c.expire_group(3.0);
    run(&mut c, 1.5, dt);
    let half = 0.6 - 0.5 * (0.6 - RESERVE_LUNG);
    assert!((c.lung() - half).abs() < 0.01, "{} vs {half}", c.lung());
    // A pause inside the group holds the breath.
    c.pause_in_group();
    let held = run(&mut c, 0.5, dt);
    assert!(held.iter().all(|s| (s.lung - half).abs() < 1e-4));
    c.expire_group(1.5);
    run(&mut c, 1.5, dt);
    assert!((c.lung() - RESERVE_LUNG).abs() < 0.01, "{}", c.lung());
    // Speech past the plan draws the reserve down with its time constant, never to 0 at once.
    run(&mut c, RESERVE_DECAY_S, dt);
    let expect = RESERVE_LUNG * (-1.0f32).exp();
    assert!((c.lung() - expect).abs() < 0.01, "{} vs {expect}", c.lung());
    // A catch breath tops the lung up to its target.
    c.inspire_to(0.2, 0.5);
    run(&mut c, 0.2, dt);
    assert!((c.lung() - 0.5).abs() < 0.01, "{}", c.lung());
}
