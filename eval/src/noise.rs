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

/// `audio` with seeded white or brown noise added `snr_db` under the speech's RMS (over the
/// active samples only: a recording with digital silence between phrases).
pub fn with_noise(audio: &[f32], snr_db: f64, brown: bool, seed: u64) -> Vec<f32> {
    let active: Vec<f32> = audio.iter().copied().filter(|x| *x != 0.0).collect();
    let speech = rms(&active);
    let mut rng = SeededRng::new(seed);
    let mut noise: Vec<f32> = (0..audio.len()).map(|_| rng.normal() as f32).collect();
    if brown {
        // Leaky integration: a 1/f² spectrum above ~16 Hz, like road rumble.
        let mut y = 0.0f32;
        for n in noise.iter_mut() {
            y = 0.995 * y + *n;
            *n = y;
        }
    }
    let gain = speech / rms(&noise) / 10f64.powf(snr_db / 20.0);
    audio
        .iter()
        .zip(&noise)
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
        for brown in [false, true] {
            let noisy = with_noise(&audio, 20.0, brown, 9);
            let added: Vec<f32> = noisy.iter().zip(&audio).map(|(n, a)| n - a).collect();
            let snr_db = 20.0 * (rms(&audio[10_000..20_000]) / rms(&added)).log10();
            assert!((snr_db - 20.0).abs() < 0.01, "{snr_db}");
        }
    }
}
