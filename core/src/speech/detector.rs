//! [`SpeechDetector`]: the stream's mono samples → Silero's probability per 32 ms chunk, and per
//! analysis frame the stacked model's speech probability.
//!
//! The engine hands it the samples up to the one that completed each analysis frame, then the
//! frame; so a frame sees exactly the chunks completed by its own completing sample, whatever
//! the block partition. A frame's Silero probability is the latest completed chunk's (0 before
//! the first; chunk boundaries count from the stream start).

use super::cues::Cues;
use super::model::{silero_logit, SpeechFeatures, SpeechModel};
use super::resample::{SourceClock, ToSileroRate};
use super::silero::{Silero, CHUNK};

/// What the decision knows of one analysis frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpeechFrame {
    /// Silero's probability of the latest completed chunk.
    pub silero_p: f32,
    /// The stacked model's inputs.
    pub features: SpeechFeatures,
    /// The stacked model's probability that the frame is speech.
    pub speech_p: f32,
}

/// See the module docs.
#[derive(Debug, Clone)]
pub struct SpeechDetector {
    model: SpeechModel,
    resampler: ToSileroRate,
    silero: Silero,
    chunk: [f32; CHUNK],
    cues: Cues,
    state: DetectorState,
}

/// What [`SpeechDetector::reset`] clears besides the parts.
#[derive(Debug, Clone, Copy, Default)]
struct DetectorState {
    /// Samples of the current chunk so far.
    filled: usize,
    /// Chunks completed.
    chunks: u64,
    /// The latest completed chunk's probability.
    silero_p: f32,
}

impl SpeechDetector {
    /// A detector for a stream at `sample_rate_hz` (8–768 kHz) with analysis frames at
    /// `frame_rate_hz`. Allocates.
    pub fn new(model: SpeechModel, sample_rate_hz: f64, frame_rate_hz: f64) -> Self {
        Self {
            model,
            resampler: ToSileroRate::new(sample_rate_hz),
            silero: Silero::new(),
            chunk: [0.0; CHUNK],
            cues: Cues::new(frame_rate_hz),
            state: DetectorState::default(),
        }
    }

    /// Back to the start of a stream.
    pub fn reset(&mut self) {
        self.resampler.reset();
        self.silero.reset();
        self.cues.reset();
        self.state = DetectorState::default();
    }

    /// The model in use.
    pub fn model(&self) -> &SpeechModel {
        &self.model
    }

    /// Takes the next mono samples; calls `on_chunk(index, probability)` for every chunk they
    /// complete. Never allocates.
    pub fn push(&mut self, samples: &[f32], mut on_chunk: impl FnMut(u64, f32)) {
        let Self {
            resampler,
            silero,
            chunk,
            state,
            ..
        } = self;
        resampler.process(samples, |y| {
            chunk[state.filled] = y;
            state.filled += 1;
            if state.filled == CHUNK {
                state.filled = 0;
                state.silero_p = silero.step(chunk);
                on_chunk(state.chunks, state.silero_p);
                state.chunks += 1;
            }
        });
    }

    /// The decision's view of the next analysis frame (after the samples that completed it
    /// were pushed).
    pub fn frame(&mut self, voiced: bool, rms_db: f32) -> SpeechFrame {
        let (voiced_near, level_dips) = self.cues.step(voiced, rms_db);
        let features = [silero_logit(self.state.silero_p), voiced_near, level_dips];
        SpeechFrame {
            silero_p: self.state.silero_p,
            features,
            speech_p: self.model.probability(&features),
        }
    }

    /// Where the 16 kHz samples the chunks are made of lie in the input stream.
    pub fn clock(&self) -> SourceClock {
        self.resampler.clock()
    }

    /// Seconds of input between the end of a chunk and the moment it completes (the
    /// resampler's latency).
    pub fn latency_s(&self) -> f64 {
        self.resampler.latency_s()
    }
}
