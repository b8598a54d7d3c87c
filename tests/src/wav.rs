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
