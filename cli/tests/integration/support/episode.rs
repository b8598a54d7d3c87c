//! A generated speech-like episode of any length for the long-file tests and the CI measure:
//! glottal vowels (phrases of 1.5 to 4 s with a falling f0) separated by pauses of 0.3 to
//! 1.5 s, chosen by a seeded generator; written block by block, so an hour needs no memory.

use std::path::Path;

use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

/// Writes `length_s` seconds of phrases and pauses to a 16-bit WAV at `rate_hz` with
/// `channels` channels (later channels at 0.7×).
pub fn write_episode(path: &Path, length_s: f64, rate_hz: u32, channels: u16) {
    let spec = hound::WavSpec {
        channels,
        sample_rate: rate_hz,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(path, spec).expect("create episode wav");
    let total = (length_s * rate_hz as f64) as u64;
    let mut written = 0u64;
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let put = |w: &mut hound::WavWriter<_>, x: f32, written: &mut u64| {
        if *written >= total {
            return;
        }
        let s = (x.clamp(-1.0, 1.0) * 32767.0).round() as i16;
        for c in 0..channels {
            let v = if c == 0 { s } else { (s as f32 * 0.7) as i16 };
            w.write_sample(v).expect("write sample");
        }
        *written += 1;
    };
    let mut phrase = 0u64;
    while written < total {
        let pause_s = 0.3 + 1.2 * next();
        for _ in 0..(pause_s * rate_hz as f64) as usize {
            put(&mut w, 0.0, &mut written);
        }
        let len = 1.5 + 2.5 * next();
        let f0 = 110.0 + 60.0 * next();
        let v = signals::glottal_vowel(
            &GlottalVowel {
                sample_rate_hz: rate_hz as f64,
                length_s: len,
                vowel: [Vowel::A, Vowel::I, Vowel::U][(phrase % 3) as usize],
                jitter: 0.01,
                shimmer: 0.04,
                peak: 0.4,
                seed: phrase,
            },
            |t| f0 - 25.0 * t / len,
        );
        for x in v {
            put(&mut w, x, &mut written);
        }
        phrase += 1;
    }
    w.finalize().expect("finalize episode wav");
}
