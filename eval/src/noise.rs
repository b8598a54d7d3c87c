//! Seeded noise for the evaluations: white (Gaussian), brown (a rumble) and babble (other
//! talkers of the same data set), mixed at a signal-to-noise ratio. Every generator is seeded
//! (core's SplitMix64, [`SeededRng`]), so every figure repeats bit for bit.

use pneuma_core::rng::SeededRng;

use crate::stats::{power, rms};

/// The noise added to clean data sets (Keele), and the SNRs (dB over the whole clip's power).
pub const ADDED_NOISES: [&str; 2] = ["white", "babble"];
/// The SNRs of [`ADDED_NOISES`], dB.
pub const ADDED_SNRS_DB: [u32; 3] = [20, 10, 0];
/// Other speakers mixed into the babble noise.
pub const BABBLE_TALKERS: usize = 4;

/// A standard normal from `rng`: Box–Muller on two uniforms in (0, 1]. Not
/// [`SeededRng::normal`] (uniforms in [0, 1)): the pitch evaluation's noisy clips, and the
/// voicing model trained on them, were drawn with this one.
fn gaussian(rng: &mut SeededRng) -> f64 {
    let mut unit = || ((rng.next_u64() >> 11) + 1) as f64 / (1u64 << 53) as f64;
    let (u, v) = (unit(), unit());
    (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
}

/// Noise of `len` samples: white (seeded Gaussian) or babble (the other clips of the data set,
/// [`BABBLE_TALKERS`] of them, each from a seeded start, looped, summed).
pub fn make_noise(kind: &str, len: usize, others: &[&[f32]], seed: u64) -> Vec<f32> {
    let mut rng = SeededRng::new(seed);
    if kind == "white" || others.is_empty() {
        return (0..len).map(|_| gaussian(&mut rng) as f32).collect();
    }
    let mut noise = vec![0.0f32; len];
    for t in 0..BABBLE_TALKERS {
        let talker = others[(rng.next_u64() as usize + t) % others.len()];
        if talker.is_empty() {
            continue;
        }
        let start = rng.next_u64() as usize % talker.len();
        for (i, n) in noise.iter_mut().enumerate() {
            *n += talker[(start + i) % talker.len()];
        }
    }
    noise
}

/// `speech + noise` scaled to `snr_db` over the whole clip.
pub fn mix_at_snr(speech: &[f32], noise: &[f32], snr_db: u32) -> Vec<f32> {
    let gain = (power(speech) / power(noise).max(1e-20) / 10f64.powf(snr_db as f64 / 10.0)).sqrt();
    speech
        .iter()
        .zip(noise)
        .map(|(&s, &n)| s + (gain * n as f64) as f32)
        .collect()
}

/// The colour of [`coloured_noise`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colour {
    /// Flat: hiss.
    White,
    /// −3 dB per octave: a room's air and electronics (Paul Kellet's refined filter of white
    /// noise, within ±0.05 dB of 1/f from 9 Hz at 44.1 kHz; its corner moves with the rate).
    Pink,
    /// −6 dB per octave above ~16 Hz (a leaky integration): road rumble.
    Brown,
}

/// `len` samples of seeded noise of `colour` (unscaled: see [`add_noise`]).
pub fn coloured_noise(len: usize, colour: Colour, seed: u64) -> Vec<f32> {
    let mut rng = SeededRng::new(seed);
    let mut noise: Vec<f32> = (0..len).map(|_| rng.normal() as f32).collect();
    match colour {
        Colour::White => {}
        Colour::Brown => {
            let mut y = 0.0f32;
            for n in noise.iter_mut() {
                y = 0.995 * y + *n;
                *n = y;
            }
        }
        Colour::Pink => {
            // Six one-pole stages and a direct path, summed.
            const POLES: [f64; 6] = [0.99886, 0.99332, 0.96900, 0.86650, 0.55000, -0.7616];
            const GAINS: [f64; 6] = [
                0.0555179, 0.0750759, 0.1538520, 0.3104856, 0.5329522, -0.0168980,
            ];
            let mut state = [0.0f64; 6];
            let mut last = 0.0f64;
            for n in noise.iter_mut() {
                let w = f64::from(*n);
                for ((s, p), g) in state.iter_mut().zip(POLES).zip(GAINS) {
                    *s = p * *s + g * w;
                }
                let y = state.iter().sum::<f64>() + 0.5362 * w + last;
                last = 0.115926 * w;
                *n = y as f32;
            }
        }
    }
    noise
}

/// `audio` with seeded noise of `colour` added `snr_db` under the speech's RMS (over the active
/// samples only: a recording with digital silence between phrases).
pub fn with_noise(audio: &[f32], snr_db: f64, colour: Colour, seed: u64) -> Vec<f32> {
    let active: Vec<f32> = audio.iter().copied().filter(|x| *x != 0.0).collect();
    let speech = rms(&active);
    let noise = coloured_noise(audio.len(), colour, seed);
    let gain = speech / rms(&noise) / 10f64.powf(snr_db / 20.0);
    mix(audio, &noise, gain)
}

/// `audio` with seeded noise of `colour` added at RMS `noise_rms` (full scale 1).
pub fn add_noise(audio: &[f32], noise_rms: f64, colour: Colour, seed: u64) -> Vec<f32> {
    let noise = coloured_noise(audio.len(), colour, seed);
    mix(audio, &noise, noise_rms / rms(&noise).max(1e-20))
}

/// `audio + gain · noise`.
fn mix(audio: &[f32], noise: &[f32], gain: f64) -> Vec<f32> {
    audio
        .iter()
        .zip(noise)
        .map(|(x, n)| x + (gain * *n as f64) as f32)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_repeats_with_its_seed_and_mixes_at_its_snr() {
        let white = make_noise("white", 20_000, &[], 3);
        assert_eq!(white, make_noise("white", 20_000, &[], 3));
        assert_ne!(white, make_noise("white", 20_000, &[], 4));
        assert!((power(&white) - 1.0).abs() < 0.05, "{}", power(&white));
        let speech: Vec<f32> = (0..20_000).map(|i| (i as f32 * 0.05).sin()).collect();
        let mixed = mix_at_snr(&speech, &white, 10);
        let added: Vec<f32> = mixed.iter().zip(&speech).map(|(m, s)| m - s).collect();
        let snr_db = 10.0 * (power(&speech) / power(&added)).log10();
        assert!((snr_db - 10.0).abs() < 0.01, "{snr_db}");
        // Babble is the other talkers, summed.
        let talker = [0.5f32; 10];
        let babble = make_noise("babble", 5, &[&talker], 1);
        assert_eq!(babble, [2.0; 5]);
    }

    #[test]
    fn noise_under_the_active_speech_ignores_digital_silence() {
        let mut audio = vec![0.0f32; 40_000];
        for (i, x) in audio[10_000..20_000].iter_mut().enumerate() {
            *x = 0.3 * (i as f32 * 0.07).sin();
        }
        for colour in [Colour::White, Colour::Pink, Colour::Brown] {
            let noisy = with_noise(&audio, 20.0, colour, 9);
            let added: Vec<f32> = noisy.iter().zip(&audio).map(|(n, a)| n - a).collect();
            let snr_db = 20.0 * (rms(&audio[10_000..20_000]) / rms(&added)).log10();
            assert!((snr_db - 20.0).abs() < 0.01, "{snr_db}");
        }
    }

    /// Slope of the third-octave band levels (250 Hz–6.3 kHz) of `x`, dB per octave.
    fn slope_db_per_octave(x: &[f32], rate_hz: f64) -> f64 {
        use pneuma_core::breathing::third_octave::{band_powers, BAND_CENTRES_HZ};
        let p = band_powers(x, rate_hz);
        let pts: Vec<(f64, f64)> = BAND_CENTRES_HZ
            .iter()
            .zip(p)
            .map(|(f, p)| (f.log2(), 10.0 * p.log10()))
            .collect();
        let n = pts.len() as f64;
        let (mx, my) = pts
            .iter()
            .fold((0.0, 0.0), |a, q| (a.0 + q.0 / n, a.1 + q.1 / n));
        let cov: f64 = pts.iter().map(|q| (q.0 - mx) * (q.1 - my)).sum();
        let var: f64 = pts.iter().map(|q| (q.0 - mx).powi(2)).sum();
        cov / var
    }

    #[test]
    fn each_colour_has_its_slope_and_the_room_its_level() {
        let rate_hz = 44_100.0;
        let len = 4 * 44_100;
        // Third-octave bands widen with frequency: white rises 3 dB per octave in them, pink
        // is flat, brown falls 3 dB per octave.
        for (colour, want) in [
            (Colour::White, 3.0),
            (Colour::Pink, 0.0),
            (Colour::Brown, -3.0),
        ] {
            let slope = slope_db_per_octave(&coloured_noise(len, colour, 5), rate_hz);
            assert!(
                (slope - want).abs() < 0.5,
                "{colour:?}: {slope:.2} dB/octave"
            );
        }
        let silence = vec![0.0f32; len];
        let room = add_noise(&silence, 0.001, Colour::Pink, 5);
        assert!((rms(&room) - 0.001).abs() < 1e-6, "{}", rms(&room));
        assert_eq!(room, add_noise(&silence, 0.001, Colour::Pink, 5));
    }
}
