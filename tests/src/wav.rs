//! Reading WAV files for the tests.

use std::path::{Path, PathBuf};

/// The shipped example voice (`assets/examples/voice.wav`).
pub fn example_voice_path() -> PathBuf {
    crate::bundle::workspace_root().join("assets/examples/voice.wav")
}

/// Samples per channel (full scale ±1) and the sample rate of a 16-bit or float WAV.
pub fn read(path: &Path) -> (Vec<Vec<f32>>, u32) {
    let mut reader = hound::WavReader::open(path)
        .unwrap_or_else(|e| panic!("cannot open {}: {e}", path.display()));
    let spec = reader.spec();
    let channels = spec.channels as usize;
    let interleaved: Vec<f32> = match spec.sample_format {
        hound::SampleFormat::Float => reader
            .samples::<f32>()
            .map(|s| s.expect("sample"))
            .collect(),
        hound::SampleFormat::Int => {
            let scale = 1.0 / (1u64 << (spec.bits_per_sample - 1)) as f32;
            reader
                .samples::<i32>()
                .map(|s| s.expect("sample") as f32 * scale)
                .collect()
        }
    };
    let mut out = vec![Vec::with_capacity(interleaved.len() / channels); channels];
    for frame in interleaved.chunks(channels) {
        for (c, &s) in frame.iter().enumerate() {
            out[c].push(s);
        }
    }
    (out, spec.sample_rate)
}

/// The example voice, mono, with its sample rate.
pub fn example_voice() -> (Vec<f32>, u32) {
    let (mut channels, rate) = read(&example_voice_path());
    (channels.swap_remove(0), rate)
}

/// Resamples `x` from `from_hz` to `to_hz` with a Hann-windowed sinc (16 zero crossings each
/// side, cut-off at the lower Nyquist). Good enough to present the example voice at the host
/// rates the tests use; not a production resampler.
pub fn resample(x: &[f32], from_hz: u32, to_hz: u32) -> Vec<f32> {
    if from_hz == to_hz {
        return x.to_vec();
    }
    let ratio = f64::from(to_hz) / f64::from(from_hz);
    let cutoff = ratio.min(1.0); // fraction of the input Nyquist
    let half = 16.0 / cutoff; // half-width in input samples
    let n_out = (x.len() as f64 * ratio).floor() as usize;
    (0..n_out)
        .map(|j| {
            let t = j as f64 / ratio;
            let lo = (t - half).ceil().max(0.0) as usize;
            let hi = ((t + half).floor() as usize).min(x.len().saturating_sub(1));
            let mut acc = 0.0f64;
            for (i, &v) in x.iter().enumerate().take(hi + 1).skip(lo) {
                let d = i as f64 - t;
                let arg = std::f64::consts::PI * d * cutoff;
                let sinc = if d.abs() < 1e-12 {
                    1.0
                } else {
                    arg.sin() / arg
                };
                let w = 0.5 + 0.5 * (std::f64::consts::PI * d / half).cos();
                acc += f64::from(v) * sinc * w * cutoff;
            }
            acc as f32
        })
        .collect()
}

/// The example voice resampled to `rate_hz` (mono).
pub fn example_voice_at(rate_hz: u32) -> Vec<f32> {
    let (voice, rate) = example_voice();
    resample(&voice, rate, rate_hz)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_keeps_a_tone_and_its_level() {
        let from = 16_000;
        let x: Vec<f32> = (0..16_000)
            .map(|i| (2.0 * std::f32::consts::PI * 200.0 * i as f32 / from as f32).sin())
            .collect();
        for to in [44_100u32, 48_000] {
            let y = resample(&x, from, to);
            assert_eq!(y.len(), (16_000.0 * f64::from(to) / 16_000.0) as usize);
            // Compare with the ideal tone away from the edges.
            let err = (2_000..y.len() - 2_000)
                .map(|j| {
                    let ideal =
                        (2.0 * std::f64::consts::PI * 200.0 * j as f64 / f64::from(to)).sin();
                    (f64::from(y[j]) - ideal).abs()
                })
                .fold(0.0, f64::max);
            assert!(err < 0.01, "max error {err} at {to} Hz");
        }
    }
}
