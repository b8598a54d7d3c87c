//! The voice's stereo image: each channel's energy, smoothed over about 20 ms sample by sample,
//! and its share of the total averaged over voiced frames, so an inserted breath is spread over
//! the channels as the voice is (a centred voice gets it at full level in every channel).

use super::MAX_CHANNELS;

/// Time constant of the per-channel energy, seconds.
const ENERGY_S: f64 = 0.02;
/// Weight of one voiced frame in the running channel shares.
const SHARE_SMOOTHING: f64 = 0.05;

/// See the module docs. Allocation-free after `new`.
#[derive(Debug, Clone)]
pub(crate) struct StereoImage {
    smoothing: f64,
    /// The smoothed energy at every sample of the current block, per channel.
    trace: Vec<Vec<f64>>,
    state: StereoState,
}

/// What [`StereoImage::reset`] clears.
#[derive(Debug, Clone, Copy, Default)]
struct StereoState {
    /// Per-channel mean square smoothed over `ENERGY_S`.
    short_ms: [f64; MAX_CHANNELS],
    /// Running share of each channel over voiced frames.
    shares: [f64; MAX_CHANNELS],
}

impl StereoImage {
    /// For `channels` channels at `sample_rate_hz` in blocks of at most `max_block`. Allocates.
    pub(crate) fn new(sample_rate_hz: f64, channels: usize, max_block: usize) -> Self {
        Self {
            smoothing: 1.0 - (-1.0 / (ENERGY_S * sample_rate_hz)).exp(),
            trace: vec![vec![0.0; max_block]; channels],
            state: StereoState::default(),
        }
    }

    /// Back to no image (every channel's share 0 until a voiced frame).
    pub(crate) fn reset(&mut self) {
        self.state = StereoState::default();
    }

    /// Follows channel `c`'s energy over the block's cleaned `input`.
    pub(crate) fn track(&mut self, c: usize, input: impl Iterator<Item = f32>) {
        let mut ms = self.state.short_ms[c];
        for (x, t) in input.zip(self.trace[c].iter_mut()) {
            ms += self.smoothing * ((x as f64) * (x as f64) - ms);
            *t = ms;
        }
        self.state.short_ms[c] = ms;
    }

    /// A voiced frame completed at sample `i` of the block: the channels' shares of the energy
    /// there teach the image.
    pub(crate) fn learn(&mut self, i: usize, channels: usize) {
        let total: f64 = (0..channels).map(|c| self.trace[c][i]).sum();
        if total > 0.0 {
            for c in 0..channels {
                self.state.shares[c] +=
                    SHARE_SMOOTHING * (self.trace[c][i] / total - self.state.shares[c]);
            }
        }
    }

    /// Per-channel gains of a breath: the square root of each channel's share times the channel
    /// count (1 everywhere for mono or before any voiced frame).
    pub(crate) fn gains(&self, channels: usize) -> [f32; MAX_CHANNELS] {
        let mut g = [0.0f32; MAX_CHANNELS];
        let total: f64 = self.state.shares[..channels].iter().sum();
        for (c, gc) in g.iter_mut().enumerate().take(channels) {
            *gc = if channels == 1 || total <= 0.0 {
                1.0
            } else {
                ((self.state.shares[c] / total) * channels as f64).sqrt() as f32
            };
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_voice_on_the_left_gets_the_breath_on_the_left() {
        let mut s = StereoImage::new(1000.0, 2, 100);
        let left = vec![0.5f32; 100];
        let right = vec![0.1f32; 100];
        s.track(0, left.iter().copied());
        s.track(1, right.iter().copied());
        for _ in 0..200 {
            s.learn(99, 2);
        }
        let g = s.gains(2);
        // Shares 25:1 of the energy: gains sqrt(2·25/26) and sqrt(2/26).
        assert!((g[0] - (50.0f32 / 26.0).sqrt()).abs() < 1e-3, "{g:?}");
        assert!((g[1] - (2.0f32 / 26.0).sqrt()).abs() < 1e-3, "{g:?}");
        s.reset();
        assert_eq!(&s.gains(2)[..2], &[1.0, 1.0]);
    }
}
