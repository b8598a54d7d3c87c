//! The shipped example voice (`assets/examples/voice.wav`, 16-bit mono) and WAV files read back
//! as samples, through hound (independent of Pneuma's own reader in `pneuma-io`).

use std::path::{Path, PathBuf};

/// The workspace root (the folder holding `assets/`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("testkit/ sits in the workspace")
        .to_path_buf()
}

/// `assets/examples/voice.wav`.
pub fn example_voice_path() -> PathBuf {
    workspace_root().join("assets/examples/voice.wav")
}

/// Samples per channel (full scale ±1) and the sample rate of an integer or float WAV file.
/// Panics with the path when it cannot be read.
pub fn read_wav(path: &Path) -> (Vec<Vec<f32>>, u32) {
    let mut reader = hound::WavReader::open(path)
        .unwrap_or_else(|e| panic!("cannot open {}: {e}", path.display()));
    let spec = reader.spec();
    let channels = spec.channels as usize;
    let interleaved: Vec<f32> = match spec.sample_format {
        hound::SampleFormat::Float => reader
            .samples::<f32>()
            .map(|s| s.unwrap_or_else(|e| panic!("{}: {e}", path.display())))
            .collect(),
        hound::SampleFormat::Int => {
            let scale = 1.0 / (1u64 << (spec.bits_per_sample - 1)) as f32;
            reader
                .samples::<i32>()
                .map(|s| s.unwrap_or_else(|e| panic!("{}: {e}", path.display())) as f32 * scale)
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

/// The example voice (mono) and its sample rate.
pub fn example_voice() -> (Vec<f32>, u32) {
    let (mut channels, rate_hz) = read_wav(&example_voice_path());
    assert_eq!(channels.len(), 1, "voice.wav is mono");
    (channels.swap_remove(0), rate_hz)
}

/// The example voice resampled to `rate_hz` ([`crate::resample::resample`]).
pub fn example_voice_at(rate_hz: u32) -> Vec<f32> {
    let (voice, rate) = example_voice();
    crate::resample::resample(&voice, rate, rate_hz)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_example_voice_is_16_bit_mono_speech_at_16_khz() {
        let (voice, rate) = example_voice();
        assert_eq!(rate, 16_000);
        assert!(voice.len() > 10 * 16_000, "{} samples", voice.len());
        // 16-bit values: every sample is a multiple of 2^-15 within ±1.
        assert!(voice
            .iter()
            .all(|&v| (-1.0..1.0).contains(&v) && (v * 32768.0).fract() == 0.0));
        let level = pneuma_core::analysis::rms(&voice);
        assert!(level > 0.01, "speech, not silence: RMS {level}");
    }
}
