//! Generated test signals with known f0: harmonic tones with any f0 contour, glottal-pulse
//! sources through vowel formant filters with jitter and shimmer, and seeded noise at a chosen
//! SNR. Used by unit tests, end-to-end tests and benchmarks, so they are exact without data files.
//! The noise comes from core's seeded generator and is shaped by core's Butterworth sections, so
//! every signal is the same bit for bit on every platform.

use pneuma_core::analysis::{rms, Biquad};
use pneuma_core::rng::SeededRng;
use std::f64::consts::PI;

/// A harmonic tone whose f0 follows `f0_hz(t)` (0 = silence at that instant), with harmonic
/// amplitudes `harmonics[h]` for harmonic `h + 1`; harmonics above 0.45 × rate are left out.
/// Peak level is about `amplitude`.
pub fn harmonic_tone(
    sample_rate_hz: f64,
    length_s: f64,
    amplitude: f64,
    harmonics: &[f64],
    f0_hz: impl Fn(f64) -> f64,
) -> Vec<f32> {
    let n = (length_s * sample_rate_hz).round() as usize;
    let norm: f64 = harmonics.iter().map(|a| a.abs()).sum::<f64>().max(1e-9);
    let mut phase = 0.0f64;
    (0..n)
        .map(|i| {
            let t = i as f64 / sample_rate_hz;
            let f0 = f0_hz(t);
            if f0 <= 0.0 {
                return 0.0;
            }
            phase = (phase + f0 / sample_rate_hz).fract();
            let mut v = 0.0;
            for (h, a) in harmonics.iter().enumerate() {
                let fh = f0 * (h + 1) as f64;
                if fh < 0.45 * sample_rate_hz {
                    v += a * (2.0 * PI * phase * (h + 1) as f64).sin();
                }
            }
            (amplitude * v / norm) as f32
        })
        .collect()
}

/// Formant frequencies and bandwidths (Hz) of a few vowels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Vowel {
    /// /a/ as in "father".
    A,
    /// /i/ as in "see".
    I,
    /// /u/ as in "blue".
    U,
}

impl Vowel {
    fn formants(self) -> [(f64, f64); 3] {
        match self {
            Vowel::A => [(730.0, 90.0), (1090.0, 110.0), (2440.0, 160.0)],
            Vowel::I => [(270.0, 60.0), (2290.0, 100.0), (3010.0, 150.0)],
            Vowel::U => [(300.0, 60.0), (870.0, 90.0), (2240.0, 150.0)],
        }
    }
}

/// Settings of a voiced vowel made from glottal pulses.
#[derive(Debug, Clone)]
pub struct GlottalVowel {
    /// Sample rate, Hz.
    pub sample_rate_hz: f64,
    /// Length, seconds.
    pub length_s: f64,
    /// The vowel.
    pub vowel: Vowel,
    /// Period-to-period f0 jitter, as a fraction (e.g. 0.01 = 1 %).
    pub jitter: f64,
    /// Period-to-period amplitude shimmer, as a fraction.
    pub shimmer: f64,
    /// Peak level after normalisation, 0..1.
    pub peak: f64,
    /// Seed of the jitter and shimmer.
    pub seed: u64,
}

/// A vowel from Rosenberg glottal pulses (open quotient 0.6) through three formant resonators,
/// f0 following `f0_hz(t)`; jitter and shimmer are drawn per period from a seeded source.
pub fn glottal_vowel(cfg: &GlottalVowel, f0_hz: impl Fn(f64) -> f64) -> Vec<f32> {
    let sr = cfg.sample_rate_hz;
    let n = (cfg.length_s * sr).round() as usize;
    let mut rng = SeededRng::new(cfg.seed);
    let mut src = vec![0.0f64; n];
    let mut t0 = 0.0f64; // start of the current period, seconds
    while t0 < cfg.length_s {
        let f0 = f0_hz(t0);
        if f0 <= 0.0 {
            t0 += 0.001;
            continue;
        }
        let period = 1.0 / (f0 * (1.0 + cfg.jitter * rng.normal()));
        let amp = 1.0 + cfg.shimmer * rng.normal();
        let open = 0.6 * period;
        let rise = 0.65 * open;
        let start = (t0 * sr).ceil() as usize;
        let end = (((t0 + period) * sr).ceil() as usize).min(n);
        for (i, s) in src.iter_mut().enumerate().take(end).skip(start) {
            let t = i as f64 / sr - t0;
            *s = amp
                * if t < rise {
                    0.5 * (1.0 - (PI * t / rise).cos())
                } else if t < open {
                    (PI / 2.0 * (t - rise) / (open - rise)).cos()
                } else {
                    0.0
                };
        }
        t0 += period;
    }
    // Differentiate (lip radiation), then the formant resonators in cascade.
    let mut prev = 0.0;
    for s in src.iter_mut() {
        let d = *s - prev;
        prev = *s;
        *s = d;
    }
    for (f, bw) in cfg.vowel.formants() {
        if f >= 0.45 * sr {
            continue;
        }
        let r = (-PI * bw / sr).exp();
        let a1 = 2.0 * r * (2.0 * PI * f / sr).cos();
        let a2 = -r * r;
        let g = 1.0 - a1 - a2;
        let (mut y1, mut y2) = (0.0, 0.0);
        for s in src.iter_mut() {
            let y = g * *s + a1 * y1 + a2 * y2;
            y2 = y1;
            y1 = y;
            *s = y;
        }
    }
    let peak = src.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
    src.iter().map(|v| (v / peak * cfg.peak) as f32).collect()
}

/// Adds seeded white Gaussian noise at `snr_db` relative to the RMS of `x`.
pub fn add_white_noise(x: &mut [f32], snr_db: f64, seed: u64) {
    let sigma = rms(x) / 10f64.powf(snr_db / 20.0);
    let mut rng = SeededRng::new(seed);
    for v in x.iter_mut() {
        *v += (sigma * rng.normal()) as f32;
    }
}

/// Seeded white Gaussian noise with standard deviation `sigma`.
pub fn white_noise(len: usize, sigma: f64, seed: u64) -> Vec<f32> {
    let mut rng = SeededRng::new(seed);
    (0..len).map(|_| (sigma * rng.normal()) as f32).collect()
}

/// Seeded band-limited noise: white Gaussian noise through fourth-order Linkwitz–Riley
/// high-pass at `low_hz` and low-pass at `high_hz` (at most 0.45 × the rate), scaled to RMS
/// `sigma`. Breath noise is about 500–5000 Hz; /s/ about 4000–8000 Hz.
pub fn band_noise(
    len: usize,
    sample_rate_hz: f64,
    (low_hz, high_hz): (f64, f64),
    sigma: f64,
    seed: u64,
) -> Vec<f32> {
    let hp = Biquad::butterworth(low_hz, sample_rate_hz, true);
    let lp = Biquad::butterworth(high_hz.min(0.45 * sample_rate_hz), sample_rate_hz, false);
    let mut f = [hp, hp, lp, lp];
    let y: Vec<f64> = white_noise(len, 1.0, seed)
        .into_iter()
        .map(|x| f.iter_mut().fold(f64::from(x), |v, s| s.process(v)))
        .collect();
    let r = (y.iter().map(|v| v * v).sum::<f64>() / len.max(1) as f64).sqrt();
    let g = if r > 0.0 { sigma / r } else { 0.0 };
    y.into_iter().map(|v| (g * v) as f32).collect()
}

/// A speech-like test signal for benchmarks: a jittered glottal /a/ in 1.5 s phrases separated
/// by 0.5 s pauses, f0 wandering 100–200 Hz, with white noise `snr_db` under it.
pub fn phrases_with_pauses(sample_rate_hz: f64, length_s: f64, snr_db: f64, seed: u64) -> Vec<f32> {
    let cfg = GlottalVowel {
        sample_rate_hz,
        length_s,
        vowel: Vowel::A,
        jitter: 0.01,
        shimmer: 0.05,
        peak: 0.5,
        seed,
    };
    let mut x = glottal_vowel(&cfg, |t| {
        if t % 2.0 < 1.5 {
            150.0 + 50.0 * (1.3 * t).sin()
        } else {
            0.0
        }
    });
    add_white_noise(&mut x, snr_db, seed.wrapping_add(1));
    x
}

/// A speaker who breathes: [`phrases_with_pauses`] (60 dB SNR) with a 0.3 s inhalation in each
/// pause from 1.62 s on, every 2 s: breath noise (500–5000 Hz) 24 dB under the first phrase's
/// RMS, with raised-cosine ends. For tests of a breath voice learned from the speaker.
pub fn phrases_with_breaths(sample_rate_hz: f64, length_s: f64, seed: u64) -> Vec<f32> {
    phrases_with_breaths_through(sample_rate_hz, length_s, seed, &[(500.0, 5000.0)])
}

/// [`phrases_with_breaths`] whose `k`-th breath is noise in the band `bands[k % bands.len()]`
/// (Hz): with two bands, two speakers taking turns (an interview).
pub fn phrases_with_breaths_through(
    sample_rate_hz: f64,
    length_s: f64,
    seed: u64,
    bands: &[(f64, f64)],
) -> Vec<f32> {
    let mut x = phrases_with_pauses(sample_rate_hz, length_s, 60.0, seed);
    let speech = rms(&x[..(1.4 * sample_rate_hz) as usize]);
    let n = (0.3 * sample_rate_hz) as usize;
    let mut t = 1.62;
    let mut breath_seed = seed.wrapping_add(6);
    let mut k = 0;
    while t + 0.3 < length_s {
        let b = band_noise(
            n,
            sample_rate_hz,
            bands[k % bands.len()],
            speech * 10f64.powf(-24.0 / 20.0),
            breath_seed,
        );
        let start = (t * sample_rate_hz) as usize;
        for (i, v) in b.iter().enumerate() {
            let ramp = (PI * i as f64 / n as f64).sin().sqrt();
            x[start + i] += v * ramp as f32;
        }
        t += 2.0;
        breath_seed += 1;
        k += 1;
    }
    x
}

/// Music with no speech in it: plucked chords (C major and A minor in turn, three harmonic
/// tones each decaying over 0.35 s) every 1.75 s for `length_s`, quiet gaps between them, as a
/// music file a user might give where a take of the speaker is asked for.
pub fn plucked_chords(sample_rate_hz: f64, length_s: f64) -> Vec<f32> {
    const EVERY_S: f64 = 1.75;
    let chords = [[261.63, 329.63, 392.0], [220.0, 261.63, 329.63]];
    let mut music = vec![0.0f32; (length_s * sample_rate_hz) as usize];
    for k in 0..(length_s / EVERY_S).floor() as usize {
        let start = (k as f64 * EVERY_S * sample_rate_hz) as usize;
        for f0 in chords[k % 2] {
            let note = harmonic_tone(sample_rate_hz, EVERY_S, 0.12, &[1.0, 0.5, 0.3, 0.2], |_| f0);
            for (x, n) in music[start..].iter_mut().zip(note.iter().enumerate()) {
                *x += n.1 * (-(n.0 as f64 / sample_rate_hz) / 0.35).exp() as f32;
            }
        }
    }
    music
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tone_has_the_asked_period() {
        let x = harmonic_tone(8000.0, 1.0, 0.5, &[1.0], |_| 100.0);
        // Zero crossings upward: 100 per second.
        let ups = x.windows(2).filter(|w| w[0] < 0.0 && w[1] >= 0.0).count();
        assert!((99..=101).contains(&ups), "{ups}");
        assert!((x.iter().fold(0.0f32, |m, v| m.max(v.abs())) - 0.5).abs() < 0.01);
    }

    #[test]
    fn glottal_vowel_is_seeded_and_normalised() {
        let cfg = GlottalVowel {
            sample_rate_hz: 16_000.0,
            length_s: 0.5,
            vowel: Vowel::A,
            jitter: 0.01,
            shimmer: 0.05,
            peak: 0.8,
            seed: 3,
        };
        let a = glottal_vowel(&cfg, |_| 120.0);
        let b = glottal_vowel(&cfg, |_| 120.0);
        let c = glottal_vowel(
            &GlottalVowel {
                seed: 4,
                ..cfg.clone()
            },
            |_| 120.0,
        );
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert!((a.iter().fold(0.0f32, |m, v| m.max(v.abs())) - 0.8).abs() < 1e-4);
    }

    #[test]
    fn noise_lands_at_the_asked_snr() {
        let clean = harmonic_tone(16_000.0, 1.0, 0.5, &[1.0, 0.5], |_| 200.0);
        let mut noisy = clean.clone();
        add_white_noise(&mut noisy, 10.0, 1);
        let noise: Vec<f32> = noisy.iter().zip(&clean).map(|(a, b)| a - b).collect();
        let snr = 20.0 * (rms(&clean) / rms(&noise)).log10();
        assert!((snr - 10.0).abs() < 0.2, "{snr}");
    }
}
