//! Shared by integration tests: the repository root and the example voice
//! (`assets/examples/voice.wav`) as mono samples with its rate.

use std::path::{Path, PathBuf};

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The example voice: 16-bit PCM mono WAV (the asset's format; anything else is a test error).
pub fn example_voice() -> (Vec<f32>, f64) {
    let path = repo_root().join("assets/examples/voice.wav");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
    assert_eq!(&bytes[0..4], b"RIFF");
    assert_eq!(&bytes[8..12], b"WAVE");
    let mut at = 12;
    let mut rate = 0u32;
    while at + 8 <= bytes.len() {
        let id = &bytes[at..at + 4];
        let size = u32::from_le_bytes(bytes[at + 4..at + 8].try_into().unwrap()) as usize;
        let body = &bytes[at + 8..(at + 8 + size).min(bytes.len())];
        if id == b"fmt " {
            let format = u16::from_le_bytes([body[0], body[1]]);
            let channels = u16::from_le_bytes([body[2], body[3]]);
            let bits = u16::from_le_bytes([body[14], body[15]]);
            assert_eq!(
                (format, channels, bits),
                (1, 1, 16),
                "voice.wav is not PCM16 mono"
            );
            rate = u32::from_le_bytes(body[4..8].try_into().unwrap());
        } else if id == b"data" {
            assert!(rate > 0, "fmt chunk after data");
            let samples = body
                .chunks_exact(2)
                .map(|b| i16::from_le_bytes([b[0], b[1]]) as f32 / 32768.0)
                .collect();
            return (samples, rate as f64);
        }
        at += 8 + size + (size & 1);
    }
    panic!("no data chunk in {}", path.display());
}
