//! Offline rendering: the one loop that feeds a whole signal through an [`Engine`] block by
//! block, flushes the engine's tail with silence and removes the latency, so the output lines
//! up with the input sample for sample.
//!
//! - [`stream`] is the streaming form: the signal comes from a reader callback block by block
//!   (a file being decoded, standard input), frames and breaths go to a [`FrameSink`], the
//!   output goes to a callback block by block. Memory stays bounded by the block size. The
//!   CLI's `pneuma render` runs on it.
//! - [`render`] is the in-memory form over [`stream`]: a whole signal in, the whole output,
//!   every frame and every breath back ([`Rendered`]). Used by the tests, the golden-output
//!   check and the evaluations.
//!
//! Both allocate (buffers of one block per channel): not for the audio thread.

use std::ops::Range;

use super::Engine;
use crate::analysis::FrameClock;
use crate::control::{BreathEvent, ControlFrame};
use crate::encode::sink::{Collect, FrameSink};

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
    /// Every breath heard in the input (`start_s`, `end_s`), in order.
    pub existing_breaths: Vec<(f64, f64)>,
    /// The engine's latency, samples.
    pub latency_samples: usize,
}

/// Which frames of the tail [`stream`] hands to the sink.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TailFrames {
    /// Every frame the engine emits, also those of the silence fed after the input.
    All,
    /// Only frames whose centre lies inside the input (as many as
    /// [`FrameClock::frames_in`] the input's length): a file's frames.
    InputOnly,
}

/// What [`stream`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Streamed {
    /// Sample frames read from the input (and written to the output).
    pub input_samples: u64,
    /// The engine's latency, samples.
    pub latency_samples: usize,
}

/// Streams a signal through a prepared `engine` with `channels` channels.
///
/// - `read(buffers, max)` fills the first `n ≤ max` samples of each channel's buffer and
///   returns `n`; 0 ends the input. `max` cycles through `blocks` (each at most the prepared
///   maximum block).
/// - After the input, [`Engine::tail_samples`] of silence are fed so every frame of the input
///   is emitted and every breath scheduled in it has played.
/// - `sink` gets every control frame at its stream position (sample index of the engine's
///   output, latency included; `tail` says which frames of the flush) and every inserted
///   breath.
/// - `on_block(sink, buffers, range)` gets the output after each block: `buffers[c][range]`
///   for each channel, the first `latency` output samples dropped and never more than the
///   input's length in all (the range may be empty). An error stops the stream and is
///   returned (a failed write, an interruption).
///
/// # Panics
/// If `blocks` is empty or holds a 0.
pub fn stream<S: FrameSink, E>(
    engine: &mut Engine,
    channels: usize,
    blocks: &[usize],
    tail: TailFrames,
    mut read: impl FnMut(&mut [Vec<f32>], usize) -> Result<usize, E>,
    sink: &mut S,
    mut on_block: impl FnMut(&mut S, &[Vec<f32>], Range<usize>) -> Result<(), E>,
) -> Result<Streamed, E> {
    assert!(
        !blocks.is_empty() && !blocks.contains(&0),
        "give at least one non-zero block size"
    );
    let latency = engine.latency_samples() as u64;
    let clock = FrameClock::new(
        engine.config().analysis.frame_rate_hz,
        engine.sample_rate_hz().unwrap_or(1.0),
    );
    let max_block = blocks.iter().copied().max().unwrap_or(1);
    let mut buffers = vec![vec![0.0f32; max_block]; channels];
    let mut fed = 0u64; // sample frames given to the engine
    let mut read_total = 0u64; // sample frames read from the input
    let mut input_done = false;
    for &block in blocks.iter().cycle() {
        // Next block: from the input, then silence to flush the tail.
        let n = if !input_done {
            let n = read(&mut buffers, block)?;
            debug_assert!(
                n <= block,
                "the reader gave {n} samples for a block of {block}"
            );
            let n = n.min(block);
            if n == 0 {
                input_done = true;
            }
            read_total += n as u64;
            n
        } else {
            0
        };
        let n = if input_done {
            let remaining = (read_total + engine.tail_samples()).saturating_sub(fed);
            if remaining == 0 {
                break;
            }
            let n = (remaining as usize).min(block);
            buffers.iter_mut().for_each(|b| b[..n].fill(0.0));
            n
        } else {
            n
        };
        let frames_limit = clock.frames_in(read_total);
        {
            let mut chans: Vec<&mut [f32]> = buffers.iter_mut().map(|b| &mut b[..n]).collect();
            let mut kept = OnlyInput {
                inner: &mut *sink,
                limit: (input_done && tail == TailFrames::InputOnly).then_some(frames_limit),
            };
            engine.process_into(&mut chans, fed, &mut kept);
        }
        // Drop the first `latency` output samples; never write past the input's length.
        let start = latency.saturating_sub(fed).min(n as u64) as usize;
        let end = (latency + read_total).saturating_sub(fed).min(n as u64) as usize;
        fed += n as u64;
        on_block(sink, &buffers, start..end.max(start))?;
    }
    engine.finish();
    engine.take_breaths(|b| sink.breath(b));
    engine.take_existing_breaths(|start_s, end_s| sink.existing_breath(start_s, end_s));
    Ok(Streamed {
        input_samples: read_total,
        latency_samples: latency as usize,
    })
}

/// Passes frames below `limit` (all when `None`) and every breath.
struct OnlyInput<'a, S: FrameSink> {
    inner: &'a mut S,
    limit: Option<u64>,
}

impl<S: FrameSink> FrameSink for OnlyInput<'_, S> {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        if self.limit.is_none_or(|l| frame.index < l) {
            self.inner.frame(frame, at);
        }
    }
    fn breath(&mut self, breath: &BreathEvent) {
        self.inner.breath(breath);
    }
    fn existing_breath(&mut self, start_s: f64, end_s: f64) {
        self.inner.existing_breath(start_s, end_s);
    }
}

/// Renders `input` (one `Vec` per channel, equal lengths) through a prepared `engine` in blocks
/// of the given sizes (cycled; each at most the prepared maximum block): [`stream`] over the
/// whole signal, keeping every frame (also the tail's) and breath.
///
/// # Panics
/// If `blocks` is empty or holds a 0.
pub fn render(engine: &mut Engine, input: &[Vec<f32>], blocks: &[usize]) -> Rendered {
    let len = input.iter().map(Vec::len).min().unwrap_or(0);
    let mut audio: Vec<Vec<f32>> = input.iter().map(|_| Vec::with_capacity(len)).collect();
    let mut pos = 0;
    let mut kept = Collect::default();
    let done = stream(
        engine,
        input.len(),
        blocks,
        TailFrames::All,
        |buffers, max| {
            let n = max.min(len - pos);
            for (b, c) in buffers.iter_mut().zip(input) {
                b[..n].copy_from_slice(&c[pos..pos + n]);
            }
            pos += n;
            Ok::<_, std::convert::Infallible>(n)
        },
        &mut kept,
        |_, buffers, range| {
            for (out, b) in audio.iter_mut().zip(buffers) {
                out.extend_from_slice(&b[range.clone()]);
            }
            Ok(())
        },
    );
    let Ok(done) = done;
    Rendered {
        audio,
        frames: kept.frames,
        breaths: kept.breaths,
        existing_breaths: kept.existing,
        latency_samples: done.latency_samples,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::EngineConfig;
    use crate::head::HeadModel;

    const RATE_HZ: f64 = 16_000.0;

    fn engine() -> Engine {
        // The test signal is a sustained vowel, which the speech decision calls no speech:
        // these tests are about the loop, so every pause counts.
        let mut config = EngineConfig::default();
        config.placement.speech_only = false;
        let mut e =
            Engine::new(config, HeadModel::default_model().clone()).expect("default engine");
        e.prepare(RATE_HZ, 300, 1).expect("prepare");
        e
    }

    /// Streams `input` in blocks of `blocks` (cycled); returns the output, what the sink kept
    /// and what `stream` reported.
    fn run(input: &[f32], blocks: &[usize], tail: TailFrames) -> (Vec<f32>, Collect, Streamed) {
        let mut e = engine();
        let (mut pos, mut out, mut kept) = (0, Vec::new(), Collect::default());
        let done = stream(
            &mut e,
            1,
            blocks,
            tail,
            |b, max| {
                let n = max.min(input.len() - pos);
                b[0][..n].copy_from_slice(&input[pos..pos + n]);
                pos += n;
                Ok::<_, String>(n)
            },
            &mut kept,
            |_, b, range| {
                out.extend_from_slice(&b[0][range]);
                Ok(())
            },
        )
        .expect("no error");
        (out, kept, done)
    }

    #[test]
    fn input_only_hands_exactly_the_input_frames_and_the_output_is_the_input_length() {
        let input = pneuma_testkit::signals::phrases_with_pauses(RATE_HZ, 3.0, 30.0, 3);
        let clock = FrameClock::new(EngineConfig::default().analysis.frame_rate_hz, RATE_HZ);
        let (out, kept, done) = run(&input, &[300, 17, 4096], TailFrames::InputOnly);
        let indices: Vec<u64> = kept.frames.iter().map(|(f, _)| f.index).collect();
        let want: Vec<u64> = (0..clock.frames_in(input.len() as u64)).collect();
        assert_eq!(indices, want);
        assert_eq!(out.len(), input.len());
        assert_eq!(done.input_samples, input.len() as u64);
        // The whole-signal form hands the tail's frames too, and the same audio.
        let all = render(&mut engine(), std::slice::from_ref(&input), &[300]);
        assert!(all.frames.len() > kept.frames.len());
        assert!(all.audio[0] == out, "the output differs from render's");
        // Latency removed: outside the breaths the output is the input, sample for sample.
        let in_breath = |i: usize| {
            let t = i as f64 / RATE_HZ;
            kept.breaths
                .iter()
                .any(|b| t >= b.start_s - 0.01 && t <= b.end_s + 0.01)
        };
        let same = (0..input.len())
            .filter(|&i| !in_breath(i))
            .all(|i| out[i].to_bits() == input[i].to_bits());
        assert!(same, "the output is not the input outside the breaths");
        assert!(!kept.breaths.is_empty(), "the phrases get breaths");
    }

    #[test]
    fn an_error_of_the_reader_or_the_writer_stops_the_stream_and_is_returned() {
        let input = vec![0.1f32; 10_000];
        let mut e = engine();
        let mut reads = 0;
        let err = stream(
            &mut e,
            1,
            &[256],
            TailFrames::All,
            |b, max| {
                reads += 1;
                if reads == 3 {
                    return Err("damaged at block 3".to_string());
                }
                b[0][..max].copy_from_slice(&input[..max]);
                Ok(max)
            },
            &mut Collect::default(),
            |_, _, _| Ok(()),
        )
        .unwrap_err();
        assert_eq!((err.as_str(), reads), ("damaged at block 3", 3));
        let mut writes = 0;
        let err = stream(
            &mut engine(),
            1,
            &[256],
            TailFrames::All,
            |b, max| {
                b[0][..max].fill(0.0);
                Ok(max)
            },
            &mut Collect::default(),
            |_, _, _| {
                writes += 1;
                if writes == 5 {
                    Err("disk full".to_string())
                } else {
                    Ok(())
                }
            },
        )
        .unwrap_err();
        assert_eq!((err.as_str(), writes), ("disk full", 5));
    }
}
