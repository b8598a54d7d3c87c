//! Temporary stand-in for `pneuma_core::engine::Engine` (issue 4) with the same shape:
//! `new` / `prepare` / `reset` / `latency_samples` / `process(audio, on_control)`.
//!
//! It runs the analysis front end on the mono mix and turns each feature frame into a
//! [`ControlFrame`] with the analysis fields (f0, voicing, RMS, level) and a speaking gate; the
//! breathing and head fields stay neutral and the audio only loses its non-finite samples. It is
//! replaced by the Engine once that lands on `main`.

use pneuma_core::analysis::FeatureFrame;
use pneuma_core::{AnalysisConfig, AnalysisError, Analyzer, ControlFrame};

/// A speaking frame is at most this far under the speaker's running speech level, dB.
const SPEAKING_LEVEL_DB: f32 = -25.0;

/// The analysis-only engine.
pub struct EngineAdapter {
    analyzer: Analyzer,
    mono: Vec<f32>,
}

impl EngineAdapter {
    /// An adapter with frames at `frame_rate_hz`.
    pub fn new(frame_rate_hz: f64) -> Result<Self, AnalysisError> {
        let config = AnalysisConfig {
            frame_rate_hz,
            ..AnalysisConfig::default()
        };
        Ok(Self {
            analyzer: Analyzer::new(config)?,
            mono: Vec::new(),
        })
    }

    /// Allocates for a stream.
    pub fn prepare(
        &mut self,
        sample_rate_hz: f64,
        max_block: usize,
        _channels: usize,
    ) -> Result<(), AnalysisError> {
        self.analyzer.prepare(sample_rate_hz, max_block.max(1))?;
        self.mono = vec![0.0; max_block.max(1)];
        Ok(())
    }

    /// Clears the stream state.
    pub fn reset(&mut self) {
        self.analyzer.reset();
    }

    /// The adapter does not delay the audio.
    pub fn latency_samples(&self) -> u32 {
        0
    }

    /// Processes one block in place; calls `on_control` for every completed frame with the
    /// sample offset inside the block where it became available. Never allocates.
    pub fn process(
        &mut self,
        audio: &mut [&mut [f32]],
        on_control: &mut dyn FnMut(&ControlFrame, usize),
    ) {
        let n = audio.first().map_or(0, |c| c.len());
        let mut start = 0;
        while start < n {
            let len = (n - start).min(self.mono.len());
            let scale = 1.0 / audio.len().max(1) as f32;
            for (i, m) in self.mono[..len].iter_mut().enumerate() {
                *m = audio.iter().map(|c| c[start + i]).sum::<f32>() * scale;
            }
            for i in 0..len {
                let offset = start + i;
                // `prepare` has run (the plugin only processes when it succeeded).
                let _ = self.analyzer.process(&self.mono[i..=i], |f| {
                    on_control(&to_control(f), offset);
                });
            }
            start += len;
        }
        for channel in audio.iter_mut() {
            for s in channel.iter_mut() {
                if !s.is_normal() {
                    *s = 0.0;
                }
            }
        }
    }
}

/// The analysis part of a control frame.
fn to_control(f: &FeatureFrame) -> ControlFrame {
    ControlFrame {
        index: f.index,
        time_s: f.time_s,
        f0_hz: if f.voiced { f.f0_hz } else { 0.0 },
        voiced: f.voiced,
        rms_db: f.rms_db,
        level_db: f.level_db,
        speaking: f.voiced || f.level_db > SPEAKING_LEVEL_DB,
        ..ControlFrame::default()
    }
}
