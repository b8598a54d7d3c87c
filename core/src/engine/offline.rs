//! Offline rendering of a whole in-memory signal through an [`Engine`]: the loop that feeds
//! blocks, flushes the engine's tail with silence and removes the latency, so the output lines
//! up with the input sample for sample. Used by the tests, the golden-output check and tools
//! that hold the whole signal in memory (the CLI streams from files with its own loop).

use super::Engine;
use crate::control::{BreathEvent, ControlFrame};

/// The result of [`render`].
#[derive(Debug, Clone, Default)]
pub struct Rendered {
    /// One `Vec` per channel, as long as the input, latency removed.
    pub audio: Vec<Vec<f32>>,
    /// Every control frame with the output sample index (latency included) at which the engine
    /// emitted it.
    pub frames: Vec<(ControlFrame, u64)>,
    /// Every inserted breath, in order.
    pub breaths: Vec<BreathEvent>,
    /// The engine's latency, samples.
    pub latency_samples: usize,
}

/// Renders `input` (one `Vec` per channel, equal lengths) through a prepared `engine` in blocks
/// of the given sizes (cycled; each at most the prepared maximum block), feeding
/// [`Engine::tail_samples`] of silence at the end and dropping the first `latency` output
/// samples. Allocates: not for the audio thread.
///
/// # Panics
/// If `blocks` is empty or holds a 0.
pub fn render(engine: &mut Engine, input: &[Vec<f32>], blocks: &[usize]) -> Rendered {
    assert!(
        !blocks.is_empty() && !blocks.contains(&0),
        "give at least one non-zero block size"
    );
    let latency = engine.latency_samples() as usize;
    let len = input.iter().map(Vec::len).min().unwrap_or(0);
    let total = len + engine.tail_samples() as usize;
    let mut padded: Vec<Vec<f32>> = input
        .iter()
        .map(|c| {
            let mut c = c[..len].to_vec();
            c.resize(total, 0.0);
            c
        })
        .collect();
    let mut frames = Vec::new();
    let mut breaths = Vec::new();
    let mut pos = 0;
    for &block in blocks.iter().cycle() {
        if pos >= total {
            break;
        }
        let n = block.min(total - pos);
        let mut chans: Vec<&mut [f32]> = padded.iter_mut().map(|c| &mut c[pos..pos + n]).collect();
        let base = pos as u64;
        engine.process(&mut chans, &mut |f, off| {
            frames.push((*f, base + off as u64))
        });
        engine.take_breaths(|b| breaths.push(*b));
        pos += n;
    }
    engine.finish();
    engine.take_breaths(|b| breaths.push(*b));
    let audio = padded
        .into_iter()
        .map(|c| c[latency..latency + len].to_vec())
        .collect();
    Rendered {
        audio,
        frames,
        breaths,
        latency_samples: latency,
    }
}
