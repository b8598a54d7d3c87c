//! Resampling for tests through rubato's synchronous FFT resampler: the whole signal at once,
//! its delay removed, `ceil(len × to / from)` samples out. Tests use it to present the example
//! voice at the rates hosts run at; Pneuma itself never resamples.

use rubato::audioadapter_buffers::direct::InterleavedSlice;
use rubato::{Fft, FixedSync, Resampler};

/// Input frames per FFT chunk.
const CHUNK: usize = 1024;

/// `x` (mono, at `from_hz`) resampled to `to_hz`, aligned with the input (the resampler's delay
/// removed). Panics on a rate of 0.
pub fn resample(x: &[f32], from_hz: u32, to_hz: u32) -> Vec<f32> {
    if from_hz == to_hz {
        return x.to_vec();
    }
    let mut resampler =
        Fft::<f32>::new(from_hz as usize, to_hz as usize, CHUNK, 1, FixedSync::Input)
            .unwrap_or_else(|e| panic!("resampling {from_hz} Hz to {to_hz} Hz: {e}"));
    let input = InterleavedSlice::new(x, 1, x.len()).expect("one channel of x.len() frames");
    resampler
        .process_all(&input, x.len(), None)
        .unwrap_or_else(|e| panic!("resampling {from_hz} Hz to {to_hz} Hz: {e}"))
        .take_data()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_keeps_a_tone_its_level_and_its_timing() {
        let from = 16_000;
        let x: Vec<f32> = (0..16_000)
            .map(|i| (2.0 * std::f32::consts::PI * 200.0 * i as f32 / from as f32).sin())
            .collect();
        for to in [44_100u32, 48_000, 8_000] {
            let y = resample(&x, from, to);
            assert_eq!(
                y.len(),
                to as usize,
                "one second in, one second out at {to} Hz"
            );
            // Compare with the ideal tone away from the edges: same level, same phase.
            let err = (2_000.min(y.len() / 4)..y.len() - 2_000.min(y.len() / 4))
                .map(|j| {
                    let ideal =
                        (2.0 * std::f64::consts::PI * 200.0 * j as f64 / f64::from(to)).sin();
                    (f64::from(y[j]) - ideal).abs()
                })
                .fold(0.0, f64::max);
            assert!(err < 0.01, "max error {err} at {to} Hz");
        }
        assert_eq!(resample(&x, from, from), x);
    }
}
