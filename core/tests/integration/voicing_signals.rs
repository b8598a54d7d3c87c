//! The shipped voicing model on generated voices that are hard to call voiced: low voices
//! (60–100 Hz) from glottal pulses, vocal fry with period doubling, onsets ramping up over
//! 30–60 ms, and breathy voice under strong noise. Each is voiced where its source is periodic,
//! and the pauses between (with the same background) are not.

use std::cell::Cell;

use pneuma_core::analysis::rms;
use pneuma_core::{AnalysisConfig, Analyzer, FeatureFrame, VOICING_FEATURES};
use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

const RATE: f64 = 48_000.0;
/// Voice from 0.5 s to 2.0 s and from 2.5 s to 4.0 s; silence (plus background) elsewhere.
const SEGMENTS_S: [(f64, f64); 2] = [(0.5, 2.0), (2.5, 4.0)];
const LENGTH_S: f64 = 4.5;

fn in_voice(t: f64) -> bool {
    SEGMENTS_S.iter().any(|&(a, b)| t >= a && t < b)
}

fn analyse(x: &[f32]) -> Vec<FeatureFrame> {
    let mut a = Analyzer::new(AnalysisConfig::default()).expect("default config");
    a.prepare(RATE, 1024).expect("supported rate");
    let mut frames = Vec::new();
    for block in x.chunks(1024) {
        a.process(block, |f| frames.push(*f)).expect("prepared");
    }
    a.finish(|f| frames.push(*f)).expect("prepared");
    frames
}

/// A glottal vowel following `f0_hz(t)` inside the voice segments (each shaped by
/// `envelope(time since its start)`), with `background` added everywhere.
fn voice(
    vowel: Vowel,
    f0_hz: impl Fn(f64) -> f64,
    envelope: impl Fn(f64) -> f64,
    background: &[f32],
) -> Vec<f32> {
    let cfg = GlottalVowel {
        sample_rate_hz: RATE,
        length_s: LENGTH_S,
        vowel,
        jitter: 0.01,
        shimmer: 0.05,
        peak: 0.3,
        seed: 7,
    };
    let mut x = signals::glottal_vowel(&cfg, |t| if in_voice(t) { f0_hz(t) } else { 0.0 });
    for (i, v) in x.iter_mut().enumerate() {
        let t = i as f64 / RATE;
        let start = SEGMENTS_S
            .iter()
            .find(|&&(a, b)| t >= a && t < b)
            .map(|s| s.0);
        *v = match start {
            Some(a) => (*v as f64 * envelope(t - a)) as f32,
            None => 0.0,
        };
        *v += background.get(i).copied().unwrap_or(0.0);
    }
    x
}

/// Fractions of frames voiced inside the voice segments (from `settle_s` after each start to
/// 50 ms before each end) and inside the pauses (50 ms from the voice on both sides, after the
/// first 0.3 s).
fn voiced_fractions(frames: &[FeatureFrame], settle_s: f64) -> (f64, f64) {
    let (mut v, mut vn, mut p, mut pn) = (0usize, 0usize, 0usize, 0usize);
    for f in frames {
        let t = f.time_s;
        let inside = SEGMENTS_S
            .iter()
            .any(|&(a, b)| t >= a + settle_s && t < b - 0.05);
        let pause = t >= 0.3
            && !SEGMENTS_S
                .iter()
                .any(|&(a, b)| t >= a - 0.05 && t < b + 0.05);
        if inside {
            vn += 1;
            v += usize::from(f.voiced);
        } else if pause {
            pn += 1;
            p += usize::from(f.voiced);
        }
    }
    assert!(
        vn > 100 && pn > 20,
        "{vn} voiced-segment and {pn} pause frames"
    );
    (v as f64 / vn as f64, p as f64 / pn as f64)
}

/// [`voiced_fractions`] of a gliding /a/ (120–160 Hz) plus `noise(length, RMS of the voice)`,
/// present in the pauses too.
fn gliding_voice_with(noise: impl Fn(usize, f64) -> Vec<f32>) -> (f64, f64) {
    let clean = voice(Vowel::A, |t| 140.0 + 20.0 * t.sin(), |_| 1.0, &[]);
    let voiced_rms = rms(&clean[(0.5 * RATE) as usize..(2.0 * RATE) as usize]);
    let noise = noise(clean.len(), voiced_rms);
    let x: Vec<f32> = clean.iter().zip(&noise).map(|(a, b)| a + b).collect();
    voiced_fractions(&analyse(&x), 0.05)
}

fn quiet_background() -> Vec<f32> {
    signals::white_noise((LENGTH_S * RATE) as usize, 3e-4, 11)
}

#[test]
fn low_voices_from_60_to_100_hz_are_voiced() {
    for f0 in [60.0, 70.0, 85.0, 100.0] {
        for vowel in [Vowel::A, Vowel::U] {
            let x = voice(vowel, |_| f0, |_| 1.0, &quiet_background());
            let frames = analyse(&x);
            let (voiced, pauses) = voiced_fractions(&frames, 0.05);
            assert!(
                voiced >= 0.95 && pauses <= 0.05,
                "{f0} Hz {vowel:?}: {:.0} % of the voice voiced, {:.0} % of the pauses",
                voiced * 100.0,
                pauses * 100.0
            );
            // The pitch is the voice's, not an octave off.
            let good = frames
                .iter()
                .filter(|f| f.voiced && in_voice(f.time_s))
                .filter(|f| (f.f0_hz as f64 / f0 - 1.0).abs() < 0.2)
                .count();
            let all = frames
                .iter()
                .filter(|f| f.voiced && in_voice(f.time_s))
                .count();
            assert!(good * 10 >= all * 9, "{f0} Hz: {good} of {all} right");
        }
    }
}

/// A glottal `vowel` whose periods alternate `alternation` longer and shorter around `f0`
/// (period doubling: a subharmonic at half the rate), with the voice's own jitter, over the
/// quiet background.
fn alternating_voice(vowel: Vowel, f0: f64, alternation: f64) -> Vec<f32> {
    let long = Cell::new(false);
    voice(
        vowel,
        |_| {
            long.set(!long.get());
            if long.get() {
                f0 / (1.0 + alternation)
            } else {
                f0 / (1.0 - alternation)
            }
        },
        |_| 1.0,
        &quiet_background(),
    )
}

/// [`alternating_voice`] as an /a/: the fractions voiced in the voice and in the pauses.
fn fry(f0: f64, alternation: f64) -> (f64, f64) {
    let x = alternating_voice(Vowel::A, f0, alternation);
    voiced_fractions(&analyse(&x), 0.05)
}

#[test]
fn vocal_fry_with_period_doubling_is_voiced() {
    for (f0, alternation, needed) in [(75.0, 0.05, 0.95), (90.0, 0.05, 0.95), (90.0, 0.1, 0.8)] {
        let (voiced, pauses) = fry(f0, alternation);
        assert!(
            voiced >= needed && pauses <= 0.05,
            "fry {f0} Hz ±{alternation}: {:.0} % of the voice voiced, {:.0} % of the pauses",
            voiced * 100.0,
            pauses * 100.0
        );
    }
}

/// Known limitation, measured: at 75 Hz with periods alternating ±10 % or more the doubled
/// period (37.5 Hz) lies below the searched range (50 Hz) and the single period is no longer
/// clear, so under 10 % of the frames are voiced. Run with `--ignored` to see it.
#[test]
#[ignore = "known limitation: strong period doubling of a 75 Hz voice is not voiced yet"]
fn strong_period_doubling_of_a_75_hz_voice_is_voiced() {
    for alternation in [0.1, 0.15] {
        let (voiced, _) = fry(75.0, alternation);
        assert!(
            voiced >= 0.8,
            "fry 75 Hz ±{alternation}: {:.0} % of the voice voiced",
            voiced * 100.0
        );
    }
}

#[test]
fn onsets_ramping_over_30_to_60_ms_are_voiced_once_the_voice_is_there() {
    for ramp_s in [0.03, 0.045, 0.06] {
        for f0 in [110.0, 220.0] {
            let x = voice(
                Vowel::A,
                |_| f0,
                |t| (t / ramp_s).min(1.0),
                &quiet_background(),
            );
            let frames = analyse(&x);
            // Every frame from the end of the ramp (plus 10 ms) on is voiced, at each onset.
            let (voiced, pauses) = voiced_fractions(&frames, ramp_s + 0.01);
            assert!(
                voiced >= 0.98 && pauses <= 0.05,
                "ramp {ramp_s} s, {f0} Hz: {:.1} % voiced after the ramp, {:.0} % of the pauses",
                voiced * 100.0,
                pauses * 100.0
            );
            for &(a, _) in &SEGMENTS_S {
                let first = frames
                    .iter()
                    .find(|f| f.time_s >= a && f.voiced)
                    .map(|f| f.time_s - a);
                assert!(
                    first.is_some_and(|d| d <= ramp_s + 0.01),
                    "ramp {ramp_s} s, {f0} Hz: first voiced frame {first:?} s after the onset at {a} s"
                );
            }
        }
    }
}

#[test]
fn breathy_voice_in_strong_noise_is_voiced_and_the_noise_alone_is_not() {
    // Aspiration noise as loud as the voice (0 dB) and 6 dB under it, present in the pauses
    // too: the voice is periodic, the pauses are only noise.
    for snr_db in [0.0, 6.0] {
        let (voiced, pauses) = gliding_voice_with(|len, voiced_rms| {
            signals::white_noise(len, voiced_rms / 10f64.powf(snr_db / 20.0), 23)
        });
        assert!(
            voiced >= 0.8 && pauses <= 0.05,
            "breathy voice at {snr_db} dB: {:.0} % of the voice voiced, {:.0} % of the noise",
            voiced * 100.0,
            pauses * 100.0
        );
    }
}

#[test]
fn a_rumble_under_the_high_pass_does_not_gate_the_voice() {
    // Traffic or handling rumble (20–60 Hz) as loud as the voice, in the pauses too: the
    // full-band level rises only 3 dB when the voice comes in, but the band the pitch analysis
    // hears (above the 120 Hz high-pass) holds only the voice.
    let (voiced, pauses) = gliding_voice_with(|len, voiced_rms| {
        signals::band_noise(len, RATE, (20.0, 60.0), voiced_rms, 31)
    });
    assert!(
        voiced >= 0.9 && pauses <= 0.05,
        "voice under rumble: {:.0} % of the voice voiced, {:.0} % of the rumble",
        voiced * 100.0,
        pauses * 100.0
    );
}

/// The index of the cue named `name` among the analyzer's voicing cues.
fn cue(name: &str) -> usize {
    VOICING_FEATURES
        .iter()
        .position(|&n| n == name)
        .unwrap_or_else(|| panic!("the analyzer offers a {name} cue"))
}

/// The `log_f0` and `pitch_track` cues (the latter: how long the chosen period has moved
/// smoothly, 0–1 of its cap) of every frame of `x` centred inside `keep`.
fn pitch_track_cue(x: &[f32], keep: impl Fn(f64) -> bool) -> Vec<(f32, f32)> {
    let (log_f0, track) = (cue("log_f0"), cue("pitch_track"));
    let mut a = Analyzer::new(AnalysisConfig::default()).expect("default config");
    a.prepare(RATE, 1024).expect("supported rate");
    let mut values = Vec::new();
    for block in x.chunks(1024) {
        a.process_with_features(block, |f, v| {
            if keep(f.time_s) {
                values.push((v[log_f0], v[track]));
            }
        })
        .expect("prepared");
    }
    values
}

/// Fraction of `values` at least `at_least`.
fn share_at_least(values: &[f32], at_least: f32) -> f64 {
    values.iter().filter(|&&v| v >= at_least).count() as f64 / values.len().max(1) as f64
}

#[test]
fn the_pitch_track_cue_holds_through_a_voice_and_not_through_noise() {
    // Well inside each voice segment (150 ms after its start, where the track has had time to
    // reach its cap) a gliding voice and a low voice with alternating periods keep one smooth
    // track; noise alone (its chance periods jump) seldom holds one for long.
    let inside = |t: f64| {
        SEGMENTS_S
            .iter()
            .any(|&(a, b)| t >= a + 0.15 && t < b - 0.05)
    };
    let gliding = voice(
        Vowel::A,
        |t| 140.0 + 20.0 * t.sin(),
        |_| 1.0,
        &quiet_background(),
    );
    let alternating = alternating_voice(Vowel::U, 80.0, 0.05);
    for (name, x) in [("gliding 125-160 Hz", gliding), ("80 Hz ±5 %", alternating)] {
        let track: Vec<f32> = pitch_track_cue(&x, inside).iter().map(|c| c.1).collect();
        let held = share_at_least(&track, 0.99);
        assert!(
            held >= 0.9,
            "{name}: the track is held on {:.0} % of the voice's frames",
            held * 100.0
        );
    }
    // Judged on the noise frames where a period was found (log f0 reads 0 without one, or at
    // exactly 150 Hz): the track must break because the periods jump, not for want of one.
    let noise = signals::white_noise((LENGTH_S * RATE) as usize, 0.05, 31);
    let cues = pitch_track_cue(&noise, |t| t >= 0.3);
    let (frames, values) = (
        cues.len(),
        cues.iter()
            .filter(|c| c.0 != 0.0)
            .map(|c| c.1)
            .collect::<Vec<f32>>(),
    );
    assert!(
        values.len() * 2 >= frames,
        "a period on only {} of {frames} noise frames",
        values.len()
    );
    let held = share_at_least(&values, 0.5);
    assert!(
        held <= 0.1,
        "white noise: a track held over half the cap on {:.0} % of the frames",
        held * 100.0
    );
}
