//! Tests of the pitch estimator as a whole (the rooms' own tests sit beside their code).

use super::nsdf::HEARD_NSDF_MAX;
use super::*;
use crate::rng::SeededRng;

fn tone(f0: f64, rate: f64, n: usize, harmonics: &[f64]) -> Vec<f32> {
    (0..n)
        .map(|i| {
            let t = i as f64 / rate;
            harmonics
                .iter()
                .enumerate()
                .map(|(h, a)| a * (2.0 * std::f64::consts::PI * f0 * (h + 1) as f64 * t).sin())
                .sum::<f64>() as f32
                * 0.3
        })
        .collect()
}

/// Seeded uniform noise in −0.5..0.5.
fn uniform(rng: &mut SeededRng) -> f32 {
    (rng.uniform() - 0.5) as f32
}

#[test]
fn many_lobes_do_not_hide_the_period() {
    // 52 Hz with all energy near 1 kHz: about 19 lobes before the true period.
    let rate = 8_000.0;
    let mut p = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
    let mut h = vec![0.0; 22];
    h[17] = 0.6;
    h[18] = 1.0;
    h[19] = 0.8;
    h[20] = 0.5;
    let x = tone(52.0, rate, 320, &h);
    let e = p.analyse(&x);
    // The true period stays among the candidates, as the strongest lobe, and the choice
    // lands near it rather than at a short lag (a narrow-band signal has near-equal lobes
    // around the period, so the key-maximum rule may take one a lobe or two early).
    let best = p
        .candidates()
        .iter()
        .copied()
        .fold(PitchEstimate::default(), |m, c| {
            if c.clarity > m.clarity {
                c
            } else {
                m
            }
        });
    assert!((best.f0_hz - 52.0).abs() < 1.0, "{:?}", p.candidates());
    assert!(e.f0_hz < 65.0, "{}", e.f0_hz);
    assert_eq!(p.analyse(&x[..100]), PitchEstimate::default());
}

/// A harmonic-rich tone whose f0 falls exponentially at `octaves_per_s`, `f0_mid` at the
/// centre of the `n` samples.
fn glide(f0_mid: f64, octaves_per_s: f64, rate: f64, n: usize) -> Vec<f32> {
    let mut phase = 0.0f64;
    (0..n)
        .map(|i| {
            let t = (i as f64 - n as f64 / 2.0) / rate;
            let f0 = f0_mid * (-octaves_per_s * t).exp2();
            phase += 2.0 * std::f64::consts::PI * f0 / rate;
            (1..=12)
                .map(|h| (h as f64 * phase).sin() / h as f64)
                .sum::<f64>() as f32
                * 0.2
        })
        .collect()
}

#[test]
fn the_short_window_keeps_a_fast_glide_periodic() {
    // 125 Hz falling 6 octaves per second (a fast phrase-final fall): over the 40 ms
    // window the period changes by 16 %.
    let rate = 8_000.0;
    let x = glide(125.0, 6.0, rate, 320);
    let mut long_only = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
    let mut both = NsdfPitch::with_short_window(rate, 320, 160, 50.0, 600.0, 0.88);
    let a = long_only.analyse(&x);
    let b = both.analyse(&x);
    let cents = |f: f32| 1200.0 * (f as f64 / 125.0).log2();
    assert!(cents(b.f0_hz).abs() < 100.0, "short: {} Hz", b.f0_hz);
    assert!(
        both.periodicity() > long_only.periodicity() + 0.05,
        "long {} ({} Hz), with short {} ({} Hz)",
        long_only.periodicity(),
        a.f0_hz,
        both.periodicity(),
        b.f0_hz
    );
    // A steady tone gains nothing: both windows see the same period.
    let steady = tone(125.0, rate, 320, &[1.0, 0.5, 0.3]);
    long_only.analyse(&steady);
    let e = both.analyse(&steady);
    assert!(cents(e.f0_hz).abs() < 10.0);
    assert!((both.periodicity() - long_only.periodicity()).abs() < 0.02);
    // The short window never brings a period the long window did not see: for a 60 Hz
    // tone (beyond its reach) the choice is the long window's.
    let low = tone(60.0, rate, 320, &[1.0, 0.8, 0.6, 0.4]);
    let a = long_only.analyse(&low);
    let b = both.analyse(&low);
    assert_eq!(a, b);
}

#[test]
fn no_candidate_lies_outside_the_f0_range() {
    // Just above the top of the range the period falls between two lags, and parabolic
    // refinement of the peak at the shortest searched lag would land above 600 Hz; just
    // below the bottom, past the longest lag. Rates 8 kHz, 8.82 kHz (44.1 kHz / 5) and
    // 12 kHz (48 kHz / 4, 96 kHz / 8).
    for rate in [8_000.0, 8_820.0, 12_000.0] {
        let len = (0.04 * rate) as usize;
        let mut p = NsdfPitch::with_short_window(rate, len, len / 2, 50.0, 600.0, 0.88);
        for f0 in [601.0, 605.0, 615.0, 630.0, 645.0, 48.0, 49.5] {
            let x = tone(f0, rate, len, &[1.0, 0.5, 0.3]);
            let e = p.analyse(&x);
            for c in p.candidates().iter().chain([&e]) {
                assert!(
                    c.f0_hz == 0.0 || (50.0..=600.0).contains(&c.f0_hz),
                    "rate {rate}, tone {f0} Hz: candidate {} Hz",
                    c.f0_hz
                );
            }
        }
        // A voice above the range has no pitch, rather than its subharmonic.
        for f0 in [605.0, 630.0, 700.0] {
            let e = p.analyse(&tone(f0, rate, len, &[1.0, 0.5, 0.3]));
            assert_eq!(
                e.f0_hz, 0.0,
                "rate {rate}, tone {f0} Hz reported at {}",
                e.f0_hz
            );
        }
        // Inside the range, next to its ends, the tones are still found.
        for f0 in [52.0, 590.0] {
            let e = p.analyse(&tone(f0, rate, len, &[1.0, 0.5, 0.3]));
            assert!(
                (e.f0_hz / f0 as f32 - 1.0).abs() < 0.01,
                "{rate}: {f0} → {}",
                e.f0_hz
            );
        }
    }
}

#[test]
fn finds_pure_and_rich_tones_across_the_range() {
    let rate = 8_000.0;
    let mut p = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
    for f0 in [55.0, 80.0, 110.0, 220.0, 330.0, 440.0, 550.0] {
        for h in [&[1.0][..], &[1.0, 0.6, 0.4, 0.3, 0.2]] {
            let x = tone(f0, rate, 320, h);
            let e = p.analyse(&x);
            let cents = 1200.0 * (e.f0_hz as f64 / f0).log2();
            assert!(
                cents.abs() < 10.0,
                "f0 {f0}: got {} ({cents} cents)",
                e.f0_hz
            );
            assert!(e.clarity > 0.95, "f0 {f0}: clarity {}", e.clarity);
        }
    }
}

#[test]
fn true_normalisation_ignores_amplitude_and_dc() {
    let rate = 8_000.0;
    let mut p = NsdfPitch::new(rate, 320, 50.0, 600.0, 0.88);
    let x = tone(200.0, rate, 320, &[1.0, 0.5]);
    let a = p.analyse(&x);
    let quiet: Vec<f32> = x.iter().map(|v| v * 1e-3 + 0.4).collect();
    let b = p.analyse(&quiet);
    assert!((a.f0_hz - b.f0_hz).abs() < 0.05);
    assert!((a.clarity - b.clarity).abs() < 1e-3);
}

#[test]
fn a_low_voice_has_edge_cues_at_its_onset() {
    // A 70 Hz voice (period 14.3 ms, beyond the 20 ms short window's reach) filling only
    // the newest 29 ms of a 40 ms window: the newest end is clearly periodic, the oldest
    // (mostly silence with a little noise) much less.
    let (rate, n) = (8_000.0, 320);
    let mut p = NsdfPitch::with_short_window(rate, n, 160, 50.0, 600.0, 0.88);
    let voice = tone(70.0, rate, n, &[1.0, 0.6, 0.4, 0.3]);
    let mut s = SeededRng::new(99);
    let window: Vec<f32> = voice
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let noise = uniform(&mut s) * 0.01;
            if i >= 88 {
                v + noise
            } else {
                noise
            }
        })
        .collect();
    let chosen = p.analyse(&window);
    assert!((chosen.f0_hz - 70.0).abs() < 2.0, "{chosen:?}");
    let newest = p.edge_clarity(&window, chosen, true).unwrap();
    let oldest = p.edge_clarity(&window, chosen, false).unwrap();
    assert!(newest > 0.95, "newest end {newest}");
    // The oldest two periods hold 3 ms of the voice's 14 ms period in the older one.
    assert!(
        oldest < newest - 0.25,
        "oldest end {oldest}, newest {newest}"
    );
}

#[test]
fn the_fused_frame_analysis_is_bit_identical_to_the_calls_one_by_one() {
    // Voices from 60 to 400 Hz (beyond and within the short window's reach), with onsets,
    // offsets, noise, a DC offset and silence, at the internal rates of 8, 44.1, 48 and
    // 22.05 kHz, with and without the low-pass.
    for (rate, n, short, low_pass) in [
        (8_000.0, 320, 160, false),
        (8_820.0, 353, 176, false),
        (12_000.0, 480, 240, false),
        (8_000.0, 320, 160, true),
        (8_820.0, 353, 176, true),
        // Windows of lengths that are not whole multiples of the sums' lanes.
        (11_025.0, 441, 221, true),
        (11_025.0, 441, 221, false),
    ] {
        let mut fused = NsdfPitch::with_short_window(rate, n, short, 50.0, 600.0, 0.88);
        let mut plain = NsdfPitch::with_short_window(rate, n, short, 50.0, 600.0, 0.88);
        if low_pass {
            fused.low_pass(Biquad::butterworth(1800.0, rate, false));
            plain.low_pass(Biquad::butterworth(1800.0, rate, false));
        }
        let mut s = SeededRng::new(5);
        for (k, f0) in [60.0f64, 70.0, 95.0, 130.0, 210.0, 400.0, 0.0]
            .into_iter()
            .enumerate()
        {
            let voice = tone(f0.max(1.0), rate, n, &[1.0, 0.6, 0.4, 0.3]);
            let window: Vec<f32> = voice
                .iter()
                .enumerate()
                .map(|(i, &v)| {
                    let noise = uniform(&mut s) * 0.02;
                    let on = match k % 3 {
                        0 => i >= n / 3,
                        1 => i < 2 * n / 3,
                        _ => true,
                    };
                    let v = if on && f0 > 0.0 { v } else { 0.0 };
                    v + noise + 0.01 * k as f32
                })
                .collect();
            for w in [&window[..], &vec![0.0; n][..]] {
                let got = fused.analyse_frame(w);
                let chosen = plain.analyse(w);
                let want = FrameAnalysis {
                    chosen,
                    edge_newest: plain.edge_clarity(w, chosen, true),
                    edge_oldest: plain.edge_clarity(w, chosen, false),
                    square_sum: square_sum(w),
                    heard_energy: plain.long.heard_energy,
                };
                let bits = |a: &FrameAnalysis| {
                    (
                        a.chosen.f0_hz.to_bits(),
                        a.chosen.clarity.to_bits(),
                        a.edge_newest.map(f32::to_bits),
                        a.edge_oldest.map(f32::to_bits),
                        a.square_sum.to_bits(),
                        a.heard_energy.to_bits(),
                    )
                };
                assert_eq!(bits(&got), bits(&want), "{rate} Hz, f0 {f0}");
                assert_eq!(fused.candidates(), plain.candidates());
                assert_eq!(fused.short_window_pick(), plain.short_window_pick());
                assert_eq!(fused.low_band().to_bits(), plain.low_band().to_bits());
                assert_eq!(fused.periodicity().to_bits(), plain.periodicity().to_bits());
            }
        }
    }
}

#[test]
fn the_low_pass_hears_a_voice_through_white_noise() {
    // A 150 Hz voice (harmonics falling 6 dB per octave) in white noise of equal power at
    // 8 kHz: through the low-pass the NSDF finds the voice clearer, and on the voice alone
    // its peaks stay within a few thousandths of 1 (the filter's ringing past the window's
    // end is in r(τ), not in m(τ)), under the clamp at HEARD_NSDF_MAX.
    let (rate, n) = (8_000.0, 320);
    let voice = tone(
        150.0,
        rate,
        n,
        &[1.0, 0.5, 0.33, 0.25, 0.2, 0.17, 0.14, 0.12],
    );
    let power = |x: &[f32]| x.iter().map(|&v| (v as f64).powi(2)).sum::<f64>();
    let mut s = SeededRng::new(7);
    let mut noise: Vec<f32> = (0..n).map(|_| uniform(&mut s)).collect();
    let gain = (power(&voice) / power(&noise)).sqrt() as f32;
    noise.iter_mut().for_each(|v| *v *= gain);
    let noisy: Vec<f32> = voice.iter().zip(&noise).map(|(a, b)| a + b).collect();
    let mut plain = NsdfPitch::with_short_window(rate, n, 160, 50.0, 600.0, 0.88);
    let mut heard = NsdfPitch::with_short_window(rate, n, 160, 50.0, 600.0, 0.88);
    heard.low_pass(Biquad::butterworth(1800.0, rate, false));
    let (a, b) = (plain.analyse(&noisy), heard.analyse(&noisy));
    assert!((b.f0_hz - 150.0).abs() < 3.0, "{b:?}");
    assert!(b.clarity > a.clarity + 0.1, "plain {a:?}, low-passed {b:?}");
    let clean = heard.analyse(&voice);
    assert!(clean.clarity > 0.95, "{clean:?}");
    let top = heard.nsdf().iter().fold(f32::MIN, |m, &v| m.max(v));
    assert!(top < 1.03 && top < HEARD_NSDF_MAX as f32, "NSDF peak {top}");
    assert!((clean.f0_hz - 150.0).abs() < 0.5, "{clean:?}");
}

#[test]
fn noise_and_silence_have_low_clarity() {
    let mut p = NsdfPitch::new(8_000.0, 320, 50.0, 600.0, 0.88);
    assert_eq!(p.analyse(&[0.0; 320]), PitchEstimate::default());
    let mut s = SeededRng::new(12345);
    let noise: Vec<f32> = (0..320).map(|_| uniform(&mut s)).collect();
    assert!(p.analyse(&noise).clarity < 0.5);
}
