//! Breath sounds: exact length, no DC, no clicks, mouth brighter than nose, energy in
//! 200 Hz–8 kHz, plateau RMS = gain, bit-reproducible from the seed, any rate, user samples fitted
//! without clicks, and no allocation while rendering.

use pneuma_core::analysis::rms;
use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::breathing::third_octave::BANDS;
use pneuma_core::breathing::{BreathSample, BreathVoice, SampleSlot};
use pneuma_core::rng::SeededRng;
use pneuma_core::BreathKind;
use pneuma_testkit::signals;
use realfft::RealFftPlanner;

use crate::support::watched;

const RATES: [f64; 6] = [8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 192_000.0];

/// Renders one breath in blocks of varying size; returns the whole buffer (with a tail of
/// silence to prove the breath ends).
fn breath(rate: f64, mouth: f32, length_s: f64, gain: f32, seed: u64) -> (Vec<f32>, usize) {
    let mut v = BreathVoice::new(seed);
    v.prepare(rate, 512);
    let n = (length_s * rate).round() as usize;
    v.start(mouth, n, gain);
    let mut out = vec![0.0f32; n + (0.05 * rate) as usize];
    let mut pos = 0;
    let mut block = 1;
    while pos < out.len() {
        let end = (pos + block).min(out.len());
        v.render_add(&mut out[pos..end]);
        pos = end;
        block = block * 3 % 700 + 1;
    }
    assert!(!v.is_active());
    (out, n)
}

/// Averaged power spectrum (Hann, 50 % overlap) and the bin width in Hz.
fn spectrum(x: &[f32], rate: f64) -> (Vec<f64>, f64) {
    let n = 2048.min(x.len().next_power_of_two() / 2);
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut acc = vec![0.0; n / 2 + 1];
    let mut spec = fft.make_output_vec();
    let mut start = 0;
    while start + n <= x.len() {
        let mut frame: Vec<f64> = (0..n)
            .map(|i| {
                let w = 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos();
                x[start + i] as f64 * w
            })
            .collect();
        fft.process(&mut frame, &mut spec).unwrap();
        for (a, c) in acc.iter_mut().zip(&spec) {
            *a += c.norm_sqr();
        }
        start += n / 2;
    }
    (acc, rate / n as f64)
}

fn centroid_hz(x: &[f32], rate: f64) -> f64 {
    let (p, df) = spectrum(x, rate);
    let total: f64 = p.iter().sum();
    p.iter()
        .enumerate()
        .map(|(i, v)| i as f64 * df * v)
        .sum::<f64>()
        / total
}

fn band_share(x: &[f32], rate: f64, lo: f64, hi: f64) -> f64 {
    let (p, df) = spectrum(x, rate);
    let total: f64 = p.iter().sum();
    let band: f64 = p
        .iter()
        .enumerate()
        .filter(|(i, _)| (*i as f64 * df) >= lo && (*i as f64 * df) <= hi)
        .map(|(_, v)| v)
        .sum();
    band / total
}

#[test]
fn exact_length_no_dc_no_clicks_at_every_rate() {
    for rate in RATES {
        for mouth in [0.0, 0.5, 1.0] {
            let (out, n) = breath(rate, mouth, 0.6, 0.05, 3);
            // Exact length: the last breath sample is non-zero, everything after is silence.
            assert!(out[n..].iter().all(|&v| v == 0.0), "{rate} {mouth}");
            assert!(out[n - 200..n].iter().any(|&v| v != 0.0));
            assert!(out[..200].iter().any(|&v| v != 0.0));
            let r = rms(&out[..n]);
            let mean = out[..n].iter().map(|&v| v as f64).sum::<f64>() / n as f64;
            assert!(mean.abs() < 0.01 * r, "DC {mean} vs RMS {r} at {rate} Hz");
            // No click: the first and last 5 ms move by much less than the plateau's
            // typical sample-to-sample step.
            let edge = (0.005 * rate) as usize;
            let step = |s: &[f32]| {
                s.windows(2)
                    .map(|w| (w[1] - w[0]).abs())
                    .fold(0.0, f32::max)
            };
            let plateau_step = step(&out[n / 3..2 * n / 3]);
            assert!(
                step(&out[..edge]) < 0.1 * plateau_step,
                "onset click at {rate} Hz"
            );
            assert!(
                step(&out[n - edge..n]) < 0.1 * plateau_step,
                "offset click at {rate} Hz"
            );
            assert!(out[0].abs() < 0.002 && out[n - 1].abs() < 0.002);
        }
    }
}

#[test]
fn plateau_rms_is_the_gain() {
    // 384 and 768 kHz: hosts run there, and the analysis accepts them (up to 768 kHz).
    for rate in [16_000.0, 48_000.0, 96_000.0, 384_000.0, 768_000.0] {
        for mouth in [0.0, 0.3, 1.0] {
            let gain = 0.04;
            let (out, n) = breath(rate, mouth, 2.0, gain, 11);
            // The plateau lies between 30 % and 65 % of the length.
            let r = rms(&out[(0.32 * n as f64) as usize..(0.63 * n as f64) as usize]);
            let db = 20.0 * (r / gain as f64).log10();
            assert!(
                db.abs() < 1.0,
                "plateau {db:.2} dB off at {rate} Hz, mouth {mouth}"
            );
        }
    }
}

#[test]
fn mouth_is_brighter_than_nose_and_energy_lies_in_200_to_8000_hz() {
    for rate in [16_000.0, 44_100.0, 48_000.0, 96_000.0] {
        let (m, n) = breath(rate, 1.0, 1.5, 0.05, 5);
        let (z, _) = breath(rate, 0.0, 1.5, 0.05, 5);
        let cm = centroid_hz(&m[..n], rate);
        let cn = centroid_hz(&z[..n], rate);
        assert!(
            cm > 1.5 * cn,
            "mouth {cm:.0} Hz vs nose {cn:.0} Hz at {rate}"
        );
        for (name, x) in [("mouth", &m), ("nose", &z)] {
            let share = band_share(&x[..n], rate, 200.0, 8000.0);
            assert!(
                share > 0.9,
                "{name}: {share:.3} of the energy in 200–8000 Hz at {rate}"
            );
        }
    }
}

#[test]
fn above_192_khz_the_breath_sounds_as_at_48_khz() {
    // Hosts run at 384 and 768 kHz and the analysis accepts them: the filters must be designed
    // for the real rate (designed for a lower one, every resonance would move up).
    for mouth in [0.0, 1.0] {
        let (x, n) = breath(48_000.0, mouth, 1.5, 0.05, 5);
        let reference_hz = centroid_hz(&x[..n], 48_000.0);
        for rate in [384_000.0, 768_000.0] {
            let (y, m) = breath(rate, mouth, 1.5, 0.05, 5);
            let hz = centroid_hz(&y[..m], rate);
            assert!(
                (hz / reference_hz - 1.0).abs() < 0.15,
                "mouth {mouth}: centroid {hz:.0} Hz at {rate} Hz vs {reference_hz:.0} Hz at 48 kHz"
            );
        }
    }
}

#[test]
fn same_seed_same_bits_other_seed_other_sound() {
    let (a, _) = breath(44_100.0, 0.4, 0.7, 0.05, 42);
    let (b, _) = breath(44_100.0, 0.4, 0.7, 0.05, 42);
    let (c, _) = breath(44_100.0, 0.4, 0.7, 0.05, 43);
    assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(a.iter().zip(&c).any(|(x, y)| x != y));
    // reset() restarts from the seed.
    let mut v = BreathVoice::new(42);
    v.prepare(44_100.0, 64);
    let n = (0.7 * 44_100.0f64).round() as usize;
    v.start(0.2, 1000, 0.1);
    let mut junk = vec![0.0; 500];
    v.render_add(&mut junk);
    v.reset();
    v.start(0.4, n, 0.05);
    let mut d = vec![0.0; a.len()];
    v.render_add(&mut d);
    assert!(a.iter().zip(&d).all(|(x, y)| x.to_bits() == y.to_bits()));
}

#[test]
fn kinds_follow_the_mix() {
    let mut v = BreathVoice::new(1);
    v.prepare(48_000.0, 256);
    v.start(1.0, 100, 0.1);
    assert_eq!(v.kind(), BreathKind::Mouth);
    v.start(0.0, 100, 0.1);
    assert_eq!(v.kind(), BreathKind::Nose);
    v.start(0.5, 100, 0.1);
    assert_eq!(v.kind(), BreathKind::Mixed);
    let sample = BreathSample::from_mono(noise(48_000.0, 0.5, 9), 48_000.0).unwrap();
    v.set_sample(SampleSlot::Mouth, Some(sample));
    v.start(0.9, 100, 0.1);
    assert_eq!(v.kind(), BreathKind::Sample);
    // The mouth sample plays its share of a nose breath too.
    v.start(0.1, 100, 0.1);
    assert_eq!(v.kind(), BreathKind::Sample);
    v.start(0.0, 100, 0.1);
    assert_eq!(v.kind(), BreathKind::Nose);
}

#[test]
fn a_nose_sample_beats_a_learned_voice_at_an_even_mouth_share() {
    // The neutral preset breathes half through the mouth: a user's nose sample alone must
    // still be heard, not a voice learned from the recording.
    let rate = 48_000.0;
    let n = (0.4 * rate) as usize;
    let render = |with_sample: bool| {
        let mut v = BreathVoice::new(2);
        v.prepare(rate, 256);
        v.set_learned(Some(LearnedVoice {
            breaths: 5,
            shape_db: [0.0; BANDS],
            shape_sd_db: [0.0; BANDS],
            level_re_speech_db: -25.0,
            level_sd_db: 0.0,
            speech_db: -20.0,
            length_s: 0.4,
            length_sd_s: 0.05,
        }));
        if with_sample {
            // A 100 Hz tone stands for the sample: nothing the voices make is periodic.
            let tone = (0..(0.5 * rate) as usize)
                .map(|i| 0.3 * (2.0 * std::f32::consts::PI * 100.0 * i as f32 / rate as f32).sin())
                .collect();
            let sample = BreathSample::from_mono(tone, rate).unwrap();
            v.set_sample(SampleSlot::Nose, Some(sample));
        }
        v.start(0.5, n, 0.05);
        let kind = v.kind();
        let mut out = vec![0.0f32; n];
        v.render_add(&mut out);
        (kind, out)
    };
    let (learned_kind, learned) = render(false);
    let (kind, sampled) = render(true);
    assert_ne!(learned_kind, BreathKind::Sample);
    assert_eq!(kind, BreathKind::Sample);
    // The tone's period (480 samples) shows in the plateau's autocorrelation.
    let periodicity = |x: &[f32]| {
        let p = &x[n / 3..2 * n / 3 - 480];
        let q = &x[n / 3 + 480..2 * n / 3];
        let dot: f64 = p.iter().zip(q).map(|(a, b)| f64::from(a * b)).sum();
        dot / (rms(p) * rms(q) * p.len() as f64)
    };
    assert!(periodicity(&sampled) > 0.3, "{}", periodicity(&sampled));
    assert!(
        periodicity(&learned).abs() < 0.1,
        "{}",
        periodicity(&learned)
    );
}

fn noise(rate: f64, length_s: f64, seed: u64) -> Vec<f32> {
    let mut r = SeededRng::new(seed);
    (0..(rate * length_s) as usize)
        .map(|_| (r.uniform() * 2.0 - 1.0) as f32 * 0.3)
        .collect()
}

#[test]
fn user_samples_fit_any_length_without_clicks() {
    // A sample at another rate with a hard edge at both ends (worst case for clicks).
    let sample = BreathSample::from_mono(noise(22_050.0, 0.3, 4), 22_050.0).unwrap();
    for length_s in [0.2, 0.3, 1.1] {
        let rate = 48_000.0;
        let mut v = BreathVoice::new(2);
        v.set_sample(SampleSlot::Nose, Some(sample.clone()));
        v.prepare(rate, 128);
        let n = (length_s * rate) as usize;
        v.start(0.0, n, 0.05);
        assert_eq!(v.kind(), BreathKind::Sample);
        let mut out = vec![0.0f32; n + 100];
        v.render_add(&mut out);
        assert!(out[n..].iter().all(|&x| x == 0.0));
        let plateau = rms(&out[(0.35 * n as f64) as usize..(0.6 * n as f64) as usize]);
        assert!(
            (plateau / 0.05 - 1.0).abs() < 0.35,
            "{length_s}: plateau {plateau}"
        );
        assert!(out[0].abs() < 0.002 && out[n - 1].abs() < 0.002);
        // Looping does not leave gaps: every 20 ms window of the plateau carries sound.
        let w = (0.02 * rate) as usize;
        for win in out[(0.3 * n as f64) as usize..(0.65 * n as f64) as usize].chunks(w) {
            assert!(rms(win) > 0.3 * 0.05, "{length_s}: a hole in the loop");
        }
    }
}

#[test]
fn bad_samples_are_rejected_with_reasons() {
    assert!(BreathSample::from_mono(vec![0.0; 10_000], 48_000.0)
        .unwrap_err()
        .to_string()
        .contains("silent"));
    assert!(BreathSample::from_mono(vec![0.1; 100], 48_000.0).is_err());
    assert!(BreathSample::from_mono(noise(4_000.0, 1.0, 1), 4_000.0).is_err());
    let mut bad = noise(16_000.0, 0.5, 1);
    bad[10] = f32::NAN;
    assert!(BreathSample::from_mono(bad, 16_000.0).is_err());
    // White noise of one 16-bit step (-90 dBFS RMS), as dither leaves: silent too.
    let dither = signals::white_noise(24_000, 1.0 / 32_768.0, 2);
    assert!(BreathSample::from_mono(dither, 48_000.0)
        .unwrap_err()
        .to_string()
        .contains("silent"));
    // A 40 s take or song is no breath sample; a 2.5 s one is.
    let long = BreathSample::from_mono(noise(16_000.0, 40.0, 3), 16_000.0).unwrap_err();
    assert!(long.to_string().contains("40.00 s long"), "{long}");
    assert!(BreathSample::from_mono(noise(16_000.0, 2.5, 3), 16_000.0).is_ok());
}

#[test]
fn fade_out_ends_early_and_smoothly() {
    let rate = 48_000.0;
    let mut v = BreathVoice::new(8);
    v.prepare(rate, 256);
    let n = 48_000;
    v.start(0.7, n, 0.05);
    let mut out = vec![0.0f32; n];
    v.render_add(&mut out[..24_000]);
    v.fade_out(2_400);
    v.render_add(&mut out[24_000..]);
    assert!(!v.is_active());
    assert!(out[26_400..].iter().all(|&x| x == 0.0));
    let tail = &out[26_400 - 100..26_400];
    assert!(tail.iter().all(|x| x.abs() < 0.01), "fade ends near zero");
}

#[test]
fn rendering_never_allocates_and_idle_is_silent() {
    for rate in RATES {
        let mut v = BreathVoice::new(5);
        v.set_sample(
            SampleSlot::Mouth,
            Some(BreathSample::from_mono(noise(rate, 0.2, 3), rate).unwrap()),
        );
        v.prepare(rate, 1024);
        let mut buf = vec![0.0f32; 1024];
        let (_, count) = watched(|| {
            v.render_add(&mut buf);
            for mix in [0.0, 0.5, 1.0] {
                v.start(mix, (0.5 * rate) as usize, 0.05);
                for _ in 0..((0.6 * rate) as usize / 1024 + 1) {
                    v.render_add(&mut buf);
                }
            }
            v.fade_out(10);
        });
        assert_eq!(count, 0, "render allocated at {rate} Hz");
        let mut idle = vec![0.25f32; 64];
        v.render_add(&mut idle);
        assert!(idle.iter().all(|&x| x == 0.25));
    }
}
