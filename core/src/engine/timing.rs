//! A stream's delays ([`Timing`]): the lookahead and the silence fed after the input, in
//! samples at the stream's rate.

use super::{EngineConfig, PlacementMode};

/// A stream's delays, in samples at its rate, from its settings and its analysis's delay.
#[derive(Debug, Clone, Copy)]
pub(super) struct Timing {
    /// The lookahead (lookahead mode), 0 in live mode.
    pub(super) latency: usize,
    /// Silence to feed after the input so every frame of it is emitted and every breath
    /// scheduled in it has played: the latency, the analysis delay and one frame.
    pub(super) tail: usize,
}

impl Timing {
    pub(super) fn of(c: &EngineConfig, sample_rate_hz: f64, analysis_latency_s: f64) -> Self {
        let latency = match c.placement.mode {
            PlacementMode::Lookahead => {
                (c.placement.effective_lookahead_s() as f64 * sample_rate_hz).round() as usize
            }
            PlacementMode::Live => 0,
        };
        let tail = latency
            + (analysis_latency_s * sample_rate_hz).ceil() as usize
            + (sample_rate_hz / c.analysis.frame_rate_hz).ceil() as usize
            + 1;
        Self { latency, tail }
    }
}
