//! The analysis front end on generated signals with known f0: tones and glides at every sample
//! rate, glottal vowels with jitter, shimmer and noise, octave traps, silence, DC, clipping,
//! NaN bursts, block partitions and latency.

use pneuma_core::analysis::rms;
use pneuma_core::{AnalysisConfig, AnalysisError, Analyzer, FeatureFrame};
use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

const RATES: [f64; 9] = [
    8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0, 384_000.0, 768_000.0,
];

fn analyse_blocks(
    x: &[f32],
    rate: f64,
    blocks: &mut dyn FnMut(usize) -> usize,
) -> Vec<FeatureFrame> {
    let mut a = Analyzer::new(AnalysisConfig::default()).expect("default config");
    a.prepare(rate, 4096).expect("supported rate");
    let mut frames = Vec::new();
    let mut pos = 0;
    let mut call = 0;
    while pos < x.len() {
        let n = blocks(call).clamp(1, x.len() - pos);
        a.process(&x[pos..pos + n], |f| frames.push(*f))
            .expect("prepared");
        pos += n;
        call += 1;
    }
    a.finish(|f| frames.push(*f)).expect("prepared");
    frames
}

fn analyse(x: &[f32], rate: f64) -> Vec<FeatureFrame> {
    analyse_blocks(x, rate, &mut |_| 512)
}

fn cents(a: f32, b: f64) -> f64 {
    1200.0 * (a as f64 / b).log2()
}

/// Frames whose centre lies in `from_s..to_s`; panics unless that is every frame the range
/// must hold at the default frame rate, so a loop over it cannot pass by looping over nothing.
fn between(frames: &[FeatureFrame], from_s: f64, to_s: f64) -> Vec<FeatureFrame> {
    let picked: Vec<FeatureFrame> = frames
        .iter()
        .filter(|f| f.time_s >= from_s && f.time_s < to_s)
        .copied()
        .collect();
    let expected = ((to_s - from_s) * AnalysisConfig::default().frame_rate_hz).floor() as usize;
    assert!(
        picked.len() >= expected.max(1),
        "{from_s}..{to_s} s holds {} frames, expected at least {expected} (of {} in all)",
        picked.len(),
        frames.len()
    );
    picked
}

/// Every field of a frame as raw bits, for bit-exact comparison.
type FrameBits = (u64, u64, u32, bool, u32, u32, u32, u32, u32);

const RICH: [f64; 6] = [1.0, 0.7, 0.5, 0.35, 0.25, 0.15];

#[test]
fn steady_tones_at_every_rate() {
    for rate in RATES {
        for f0 in [55.0, 82.0, 110.0, 220.0, 330.0, 440.0, 550.0] {
            let x = signals::harmonic_tone(rate, 0.5, 0.5, &RICH, |_| f0);
            let frames = analyse(&x, rate);
            let mid = between(&frames, 0.06, 0.44);
            assert!(!mid.is_empty());
            for f in &mid {
                assert!(f.voiced, "rate {rate} f0 {f0}: unvoiced at {}", f.time_s);
                let c = cents(f.f0_hz, f0);
                assert!(
                    c.abs() < 20.0,
                    "rate {rate} f0 {f0}: {} Hz ({c:.1} cents)",
                    f.f0_hz
                );
                assert!(f.voicing > 0.9);
            }
            // The level: frame powers average to the signal's own power (a 20 ms window does
            // not hold whole periods of a low tone, so single frames ripple around it).
            let want_db = 20.0 * rms(&x[x.len() / 4..x.len() * 3 / 4]).log10();
            let mean_power = mid
                .iter()
                .map(|f| 10f64.powf(f.rms_db as f64 / 10.0))
                .sum::<f64>()
                / mid.len() as f64;
            let got_db = 10.0 * mean_power.log10();
            assert!(
                (got_db - want_db).abs() < 0.3,
                "rate {rate} f0 {f0}: {got_db} vs {want_db}"
            );
        }
    }
}

#[test]
fn glides_are_followed() {
    // Exponential glides 55 → 550 Hz and 500 → 50 Hz in 2 s.
    let up = |t: f64| 55.0 * 10f64.powf(t / 2.0);
    let down = |t: f64| 500.0 * 10f64.powf(-t / 2.0);
    let glides: [(&str, &dyn Fn(f64) -> f64); 2] = [("rising", &up), ("falling", &down)];
    for rate in [16_000.0, 44_100.0, 48_000.0] {
        for (name, contour) in glides {
            let x = signals::harmonic_tone(rate, 2.0, 0.5, &RICH, contour);
            let frames = analyse(&x, rate);
            let mid = between(&frames, 0.05, 1.95);
            let bad = mid
                .iter()
                .filter(|f| !f.voiced || cents(f.f0_hz, contour(f.time_s)).abs() > 50.0)
                .count();
            assert!(
                bad * 100 <= mid.len(),
                "rate {rate}: {bad} of {} frames off the {name} glide",
                mid.len()
            );
        }
    }
}

#[test]
fn glottal_vowels_with_jitter_shimmer_and_noise() {
    for (i, (vowel, f0)) in [
        (Vowel::A, 110.0),
        (Vowel::I, 220.0),
        (Vowel::U, 180.0),
        (Vowel::A, 300.0),
    ]
    .into_iter()
    .enumerate()
    {
        for rate in [16_000.0, 48_000.0] {
            let cfg = GlottalVowel {
                sample_rate_hz: rate,
                length_s: 1.0,
                vowel,
                jitter: 0.01,
                shimmer: 0.05,
                peak: 0.6,
                seed: 10 + i as u64,
            };
            let contour =
                move |t: f64| f0 * (1.0 + 0.05 * (2.0 * std::f64::consts::PI * 3.0 * t).sin());
            let mut x = signals::glottal_vowel(&cfg, contour);
            signals::add_white_noise(&mut x, 20.0, 99);
            let frames = analyse(&x, rate);
            let mid = between(&frames, 0.06, 0.94);
            let unvoiced = mid.iter().filter(|f| !f.voiced).count();
            let gross = mid
                .iter()
                .filter(|f| f.voiced && cents(f.f0_hz, contour(f.time_s)).abs() > 300.0)
                .count();
            let mut fine: Vec<f64> = mid
                .iter()
                .filter(|f| f.voiced)
                .map(|f| cents(f.f0_hz, contour(f.time_s)).abs())
                .filter(|c| *c <= 300.0)
                .collect();
            fine.sort_by(f64::total_cmp);
            let median_cents = fine[fine.len() / 2];
            println!("{vowel:?} {f0} Hz at {rate}: median error {median_cents:.1} cents");
            // 1 % jitter moves single periods by about 17 cents; the window spans several.
            assert!(
                median_cents < 12.0,
                "{vowel:?} {f0} Hz at {rate}: median error {median_cents:.1} cents"
            );
            assert!(
                unvoiced * 50 <= mid.len(),
                "{vowel:?} {f0} Hz at {rate}: {unvoiced} unvoiced of {}",
                mid.len()
            );
            assert!(
                gross * 50 <= mid.len(),
                "{vowel:?} {f0} Hz at {rate}: {gross} gross errors of {}",
                mid.len()
            );
        }
    }
}

#[test]
fn octave_traps_give_the_fundamental() {
    // Weak fundamental, strong second harmonic: the period is still 1/f0.
    for rate in [16_000.0, 48_000.0] {
        for f0 in [90.0, 130.0, 200.0, 260.0] {
            let x = signals::harmonic_tone(rate, 0.6, 0.5, &[0.1, 1.0, 0.3, 0.2, 0.1], |_| f0);
            let frames = analyse(&x, rate);
            for f in between(&frames, 0.06, 0.54) {
                assert!(f.voiced, "{f0} Hz: unvoiced");
                assert!(
                    cents(f.f0_hz, f0).abs() < 30.0,
                    "{f0} Hz trap gave {} Hz",
                    f.f0_hz
                );
            }
        }
    }
}

#[test]
fn silence_is_unvoiced_at_the_floor() {
    for rate in RATES {
        let frames = analyse(&vec![0.0; (rate * 0.5) as usize], rate);
        assert_eq!(frames.len(), 60);
        for f in frames {
            assert!(!f.voiced && f.f0_hz == 0.0 && f.voicing == 0.0);
            assert_eq!(f.rms_db, -120.0);
        }
    }
}

#[test]
fn dc_offset_changes_neither_pitch_nor_level() {
    let rate = 44_100.0;
    let x = signals::harmonic_tone(rate, 0.5, 0.3, &RICH, |_| 150.0);
    let shifted: Vec<f32> = x.iter().map(|v| v + 0.4).collect();
    let a = between(&analyse(&x, rate), 0.06, 0.44);
    let b = between(&analyse(&shifted, rate), 0.06, 0.44);
    assert_eq!(a.len(), b.len(), "the DC offset changed the frame count");
    for (fa, fb) in a.iter().zip(&b) {
        assert!(fb.voiced);
        assert!(cents(fb.f0_hz, fa.f0_hz as f64).abs() < 2.0);
        assert!(
            (fa.rms_db - fb.rms_db).abs() < 0.05,
            "{} vs {}",
            fa.rms_db,
            fb.rms_db
        );
    }
}

#[test]
fn clipped_speech_keeps_its_pitch() {
    let rate = 48_000.0;
    let x: Vec<f32> = signals::harmonic_tone(rate, 0.5, 4.0, &RICH, |_| 180.0)
        .into_iter()
        .map(|v| v.clamp(-1.0, 1.0))
        .collect();
    for f in between(&analyse(&x, rate), 0.06, 0.44) {
        assert!(
            f.voiced && cents(f.f0_hz, 180.0).abs() < 20.0,
            "{}",
            f.f0_hz
        );
    }
}

#[test]
fn nan_and_inf_bursts_count_as_silence() {
    let rate = 48_000.0;
    let mut x = signals::harmonic_tone(rate, 1.0, 0.5, &RICH, |_| 200.0);
    for (i, v) in x.iter_mut().enumerate().skip(20_000).take(9_600) {
        *v = match i % 3 {
            0 => f32::NAN,
            1 => f32::INFINITY,
            _ => f32::NEG_INFINITY,
        };
    }
    x[40_000] = 1e30;
    let frames = analyse(&x, rate);
    assert_eq!(frames.len(), 120);
    for f in &frames {
        assert!(f.f0_hz.is_finite() && f.voicing.is_finite() && f.rms_db.is_finite());
        assert!(f.f0_st.is_finite() && f.level_db.is_finite());
    }
    // The burst (0.417–0.617 s) is silence in the middle: unvoiced at the floor.
    for f in between(&frames, 0.45, 0.58) {
        assert!(!f.voiced);
        assert_eq!(f.rms_db, -120.0);
    }
    // And the tone is found again after it.
    assert!(between(&frames, 0.7, 0.8)
        .iter()
        .all(|f| f.voiced && cents(f.f0_hz, 200.0).abs() < 20.0));
}

#[test]
fn any_block_partition_gives_bit_identical_frames() {
    // 8 kHz (no decimation), 44.1 kHz (factor 5, 367.5 samples per frame), 192 kHz (factor 24),
    // 768 kHz (factor 96).
    for rate in [8_000.0, 44_100.0, 192_000.0, 768_000.0] {
        let cfg = GlottalVowel {
            sample_rate_hz: rate,
            length_s: 1.0,
            vowel: Vowel::A,
            jitter: 0.01,
            shimmer: 0.05,
            peak: 0.6,
            seed: 5,
        };
        let mut x = signals::glottal_vowel(&cfg, |t| 120.0 + 60.0 * t);
        let pause = (0.2 * rate) as usize;
        x.extend(std::iter::repeat_n(0.0, pause));
        x.extend(signals::white_noise(pause, 0.05, 3));
        let reference = analyse_blocks(&x, rate, &mut |_| 4096);
        let bits = |v: &[FeatureFrame]| -> Vec<FrameBits> {
            v.iter()
                .map(|f| {
                    (
                        f.index,
                        f.time_s.to_bits(),
                        f.f0_hz.to_bits(),
                        f.voiced,
                        f.voicing.to_bits(),
                        f.rms_db.to_bits(),
                        f.f0_st.to_bits(),
                        f.level_db.to_bits(),
                        f.band_db.to_bits(),
                    )
                })
                .collect()
        };
        let want = bits(&reference);
        assert!(reference.iter().any(|f| f.voiced));
        for size in [1usize, 37, 512] {
            assert_eq!(
                bits(&analyse_blocks(&x, rate, &mut |_| size)),
                want,
                "{rate} Hz, block size {size}"
            );
        }
        let mut s = pneuma_core::rng::SeededRng::new(42);
        let random = analyse_blocks(&x, rate, &mut |_| 1 + (s.next_u64() % 3000) as usize);
        assert_eq!(bits(&random), want, "{rate} Hz, random block sizes");
    }
}

#[test]
fn frames_are_timestamped_on_the_clock_and_complete() {
    for rate in [44_100.0, 48_000.0] {
        let x = signals::harmonic_tone(rate, 1.0, 0.5, &RICH, |_| 200.0);
        let frames = analyse(&x, rate);
        assert_eq!(frames.len(), 120);
        for (k, f) in frames.iter().enumerate() {
            assert_eq!(f.index, k as u64);
            assert_eq!(f.time_s, k as f64 / 120.0);
        }
    }
}

#[test]
fn a_pitch_change_is_reported_within_the_stated_latency() {
    // The latency docs/measurements.md reports and the issue limits to 35 ms: from a 150 → 250 Hz step
    // in the input to the input sample at which the first frame reporting 250 Hz is emitted
    // (`--nocapture` prints it), at every rate class from 8 to 192 kHz. Half the 40 ms window
    // and the decimation filter (`latency_s`) plus up to one frame spacing (the step falls
    // between two frame centres); the outlier filter adds no frame to a change the newest
    // samples confirm.
    const LIMIT_S: f64 = 0.035;
    for rate in [
        8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0,
    ] {
        let frame_s = 1.0 / 120.0;
        let mut worst_s: f64 = 0.0;
        let mut latency_s = 0.0;
        // Steps at several phases relative to the frame clock.
        for phase in 0..4 {
            let step_s = 0.5 + phase as f64 * frame_s / 4.0;
            let x = signals::harmonic_tone(rate, 1.0, 0.5, &RICH, |t| {
                if t < step_s {
                    150.0
                } else {
                    250.0
                }
            });
            let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
            a.prepare(rate, 1).expect("rate");
            latency_s = a.latency_s().expect("prepared");
            let mut reported_at = None;
            for (i, s) in x.iter().enumerate() {
                let mut hit = false;
                a.process(std::slice::from_ref(s), |f| {
                    hit |= f.voiced && cents(f.f0_hz, 250.0).abs() < 50.0;
                })
                .expect("prepared");
                if hit {
                    reported_at = Some((i + 1) as f64 / rate);
                    break;
                }
            }
            let delay_s = reported_at
                .unwrap_or_else(|| panic!("{rate} Hz: the new pitch is never reported"))
                - step_s;
            assert!(delay_s > 0.0, "{rate} Hz: reported before the change");
            worst_s = worst_s.max(delay_s);
        }
        println!(
            "{rate} Hz: pitch change reported after at most {:.1} ms (frames complete {:.1} ms after their centre)",
            worst_s * 1e3,
            latency_s * 1e3
        );
        assert!(latency_s > 0.02 && latency_s < 0.025, "{latency_s}");
        assert!(
            worst_s <= LIMIT_S,
            "{rate} Hz: a pitch change is reported {worst_s} s late, over the {LIMIT_S} s limit"
        );
    }
}

#[test]
fn speaker_normalisation_centres_on_the_voice() {
    let rate = 16_000.0;
    let x = signals::harmonic_tone(rate, 6.0, 0.2, &RICH, |t| {
        220.0 * (1.0 + 0.03 * (7.0 * t).sin())
    });
    let frames = analyse(&x, rate);
    let late = between(&frames, 5.0, 5.9);
    let mean_st = late.iter().map(|f| f.f0_st as f64).sum::<f64>() / late.len() as f64;
    let mean_level = late.iter().map(|f| f.level_db as f64).sum::<f64>() / late.len() as f64;
    assert!(mean_st.abs() < 0.5, "{mean_st}");
    assert!(mean_level.abs() < 1.5, "{mean_level}");
    // The level is measured against the speech level each frame reports, and that is the
    // voice's own level by now.
    for f in &frames {
        assert_eq!(
            f.level_db.to_bits(),
            (f.rms_db - f.speech_level_db).to_bits()
        );
    }
    let mean_rms = late.iter().map(|f| f.rms_db as f64).sum::<f64>() / late.len() as f64;
    let speech_db = late[late.len() - 1].speech_level_db as f64;
    assert!(
        (speech_db - mean_rms).abs() < 1.5,
        "{speech_db} vs {mean_rms}"
    );
    // Early on the prior (150 Hz) still weighs: 220 Hz lies well above it.
    assert!(between(&frames, 0.06, 0.1)[0].f0_st > 3.0);
}

#[test]
fn unsupported_rates_and_unprepared_use_are_errors() {
    let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
    assert_eq!(a.process(&[0.0], |_| ()), Err(AnalysisError::NotPrepared));
    assert!(matches!(
        a.prepare(4_000.0, 64),
        Err(AnalysisError::SampleRate(_))
    ));
    assert!(matches!(
        a.prepare(768_001.0, 64),
        Err(AnalysisError::SampleRate(_))
    ));
    assert!(a.prepare(8_000.0, 64).is_ok());
    let err = Analyzer::new(AnalysisConfig {
        f0_min_hz: 20.0,
        ..Default::default()
    })
    .expect_err("20 Hz is out of range");
    assert_eq!(
        err.to_string(),
        "f0_min_hz 20 Hz is out of range: use 30 to 600 Hz"
    );
}

/// First voiced frame at or after `from_s`, in seconds.
fn first_voiced_after(frames: &[FeatureFrame], from_s: f64) -> f64 {
    frames
        .iter()
        .find(|f| f.time_s >= from_s && f.voiced)
        .map_or(f64::INFINITY, |f| f.time_s)
}

#[test]
fn a_vowel_after_a_fricative_is_voiced_from_its_onset() {
    // 0.3 s of loud noise (a fricative), then a 150 Hz vowel-like tone: the frames whose long
    // window still holds the noise are judged on the newest 20 ms too, so voicing starts near
    // the onset, not only once the noise has left the 40 ms window.
    let rate = 16_000.0;
    let mut seed = 7u32;
    let mut x: Vec<f32> = (0..(0.3 * rate) as usize)
        .map(|_| {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            ((seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 0.4
        })
        .collect();
    x.extend(signals::harmonic_tone(rate, 0.3, 0.5, &RICH, |_| 150.0));
    let run = |short_window_s: f32| {
        let mut a = Analyzer::new(AnalysisConfig {
            short_window_s,
            ..Default::default()
        })
        .expect("config");
        a.prepare(rate, 512).expect("rate");
        let mut frames = Vec::new();
        a.process(&x, |f| frames.push(*f)).expect("prepared");
        a.finish(|f| frames.push(*f)).expect("prepared");
        frames
    };
    let with_edges = first_voiced_after(&run(0.02), 0.2);
    let long_only = first_voiced_after(&run(0.0), 0.2);
    assert!(
        (0.3..0.31).contains(&with_edges),
        "voiced from {with_edges} s (onset 0.3 s; long window only: {long_only} s)"
    );
    assert!(
        with_edges < long_only,
        "{with_edges} s vs {long_only} s (long window only)"
    );
}

#[test]
fn a_quiet_talker_is_voiced_before_the_speech_level_adapts() {
    // A clean vowel at −46 dBFS, 20 dB under the −26 dBFS speech-level prior: the loudness
    // penalty is bounded (±10 dB of the speech level), so the clearly periodic onset is voiced
    // at once instead of waiting for the level to learn the talker.
    let rate = 16_000.0;
    let mut x = vec![0.0f32; (0.3 * rate) as usize];
    let vowel = signals::harmonic_tone(rate, 0.6, 1.0, &RICH, |_| 120.0);
    let gain = (10f64.powf(-46.0 / 20.0) / rms(&vowel)) as f32;
    x.extend(vowel.iter().map(|v| v * gain));
    let frames = analyse(&x, rate);
    let onset_s = first_voiced_after(&frames, 0.2);
    assert!(
        (0.3..0.33).contains(&onset_s),
        "voiced from {onset_s} s (onset 0.3 s)"
    );
    let f = between(&frames, 0.4, 0.8);
    assert!(f.iter().all(|f| f.voiced), "a frame of the vowel unvoiced");
    assert!(f.iter().all(|f| cents(f.f0_hz, 120.0).abs() < 20.0));
}

#[test]
fn a_quiet_take_is_voiced_as_the_same_take_at_a_normal_level() {
    // The example voice 35 dB down (speech near -55 dBFS): its soft syllables lie under the
    // voicing's silence gate (-60 dBFS) and went unvoiced (1417 of the 1640 frames voiced at the
    // normal level); the gate now moves down with the speaker's running level under -30 dBFS.
    let (voice, sr) = pneuma_testkit::voice::example_voice();
    let sr = f64::from(sr);
    let quiet: Vec<f32> = voice.iter().map(|v| v * 10f32.powf(-35.0 / 20.0)).collect();
    let voiced = |x: &[f32]| analyse(x, sr).iter().filter(|f| f.voiced).count();
    let (normal, low) = (voiced(&voice), voiced(&quiet));
    assert!(
        low as f64 >= 0.9 * normal as f64,
        "{low} frames voiced 35 dB down, {normal} at the normal level"
    );
}
