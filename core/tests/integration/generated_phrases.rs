//! Shared by integration tests: generated speech-like phrases (voiced glottal vowels with a
//! syllable rhythm) in sequences with known pauses, at 16 kHz.

use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

pub const SR: f64 = 16_000.0;

/// A phrase: a voiced glottal vowel sequence with a syllable rhythm, f0 falling 140 → 100 Hz.
pub fn phrase(length_s: f64, seed: u64) -> Vec<f32> {
    let vowels = [Vowel::A, Vowel::I, Vowel::U];
    let mut out = Vec::new();
    let syllable_s: f64 = 0.2;
    let mut k = 0;
    while (out.len() as f64) < length_s * SR - 1.0 {
        let left = length_s - out.len() as f64 / SR;
        let len = syllable_s.min(left);
        let start = out.len() as f64 / SR;
        let v = signals::glottal_vowel(
            &GlottalVowel {
                sample_rate_hz: SR,
                length_s: len,
                vowel: vowels[k % 3],
                jitter: 0.01,
                shimmer: 0.05,
                peak: 0.4,
                seed: seed * 100 + k as u64,
            },
            |t| 140.0 - 40.0 * (start + t) / length_s,
        );
        // Syllable envelope: the level dips 10 dB between syllables, never to silence.
        let n = v.len();
        out.extend(v.iter().enumerate().map(|(i, x)| {
            let p = i as f64 / n as f64;
            let env = 0.3 + 0.7 * (std::f64::consts::PI * p).sin();
            x * env as f32
        }));
        k += 1;
    }
    out
}

/// Lead-in silence, then phrases separated by the given pauses; returns the audio and the
/// (onset, offset) of every phrase in seconds.
pub fn sequence(lead_s: f64, phrases: &[f64], pauses: &[f64]) -> (Vec<f32>, Vec<(f64, f64)>) {
    let mut audio = vec![0.0f32; (lead_s * SR) as usize];
    let mut spans = Vec::new();
    for (i, &p) in phrases.iter().enumerate() {
        let onset = audio.len() as f64 / SR;
        audio.extend(phrase(p, i as u64 + 1));
        spans.push((onset, audio.len() as f64 / SR));
        let pause = pauses.get(i).copied().unwrap_or(0.5);
        audio.extend(std::iter::repeat_n(0.0, (pause * SR) as usize));
    }
    (audio, spans)
}
