//! A causal noise-floor tracker (minimum statistics): the lowest frame level over the last few
//! seconds, kept as the minima of short blocks in a ring, so it follows a changing background
//! within `window_s` and never needs to see the future.

/// Length of one block of the minimum ring, seconds.
const BLOCK_S: f64 = 0.1;

/// Running minimum of frame levels over a sliding window.
#[derive(Debug, Clone)]
pub(crate) struct NoiseFloor {
    block_frames: usize,
    ring: Vec<f32>,
    filled: usize,
    next: usize,
    block_min: f32,
    in_block: usize,
}

impl NoiseFloor {
    /// A tracker over `window_s` seconds of frames at `frame_rate_hz`. Allocates.
    pub(crate) fn new(window_s: f64, frame_rate_hz: f64) -> Self {
        let block_frames = ((BLOCK_S * frame_rate_hz).round() as usize).max(1);
        let blocks = ((window_s / BLOCK_S).round() as usize).max(1);
        Self::with_blocks(block_frames, blocks)
    }

    /// A tracker whose ring holds `blocks` minima of `block_frames` frames each (both at least
    /// 1), for callers that count in their own ticks. Allocates.
    pub(crate) fn with_blocks(block_frames: usize, blocks: usize) -> Self {
        Self {
            block_frames: block_frames.max(1),
            ring: vec![f32::INFINITY; blocks.max(1)],
            filled: 0,
            next: 0,
            block_min: f32::INFINITY,
            in_block: 0,
        }
    }

    pub(crate) fn reset(&mut self) {
        self.ring.fill(f32::INFINITY);
        self.filled = 0;
        self.next = 0;
        self.block_min = f32::INFINITY;
        self.in_block = 0;
    }

    /// Adds one frame: its level in dB, or `None` for a frame that must not teach the floor
    /// (clearly periodic, i.e. voice); returns the current floor in dB (+∞ while the window
    /// holds no usable frame).
    pub(crate) fn update(&mut self, level_db: Option<f32>) -> f32 {
        if let Some(level_db) = level_db {
            self.block_min = self.block_min.min(level_db);
        }
        self.in_block += 1;
        let mut floor = self.block_min;
        for &m in &self.ring[..self.filled] {
            floor = floor.min(m);
        }
        if self.in_block == self.block_frames {
            self.ring[self.next] = self.block_min;
            self.next = (self.next + 1) % self.ring.len();
            self.filled = (self.filled + 1).min(self.ring.len());
            self.block_min = f32::INFINITY;
            self.in_block = 0;
        }
        floor
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_the_minimum_and_forgets_it_after_the_window() {
        let mut n = NoiseFloor::new(1.0, 100.0);
        for i in 0..100 {
            let level = if i % 10 == 0 { -50.0 } else { -20.0 };
            n.update(Some(level));
        }
        assert_eq!(n.update(Some(-20.0)), -50.0);
        // The background rises to -30 dB: after the window the floor follows it.
        let mut last = 0.0;
        for _ in 0..150 {
            last = n.update(Some(-30.0));
        }
        assert_eq!(last, -30.0);
        // Frames kept out of the floor let old minima expire and are not counted.
        for _ in 0..150 {
            last = n.update(None);
        }
        assert_eq!(last, f32::INFINITY);
        n.reset();
        assert_eq!(n.update(Some(-10.0)), -10.0);
    }
}
