//! The frame clock: frame `k` is centred at `k / frame_rate_hz` seconds, whatever the sample
//! rate. Positions are computed from the frame number (never accumulated), so a 120 Hz clock at
//! 44.1 kHz (367.5 samples per frame) does not drift over hours.

/// Maps frame numbers to times and fractional sample positions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameClock {
    frame_rate_hz: f64,
    sample_rate_hz: f64,
}

impl FrameClock {
    /// A clock at `frame_rate_hz` over a stream sampled at `sample_rate_hz`.
    pub fn new(frame_rate_hz: f64, sample_rate_hz: f64) -> Self {
        Self {
            frame_rate_hz,
            sample_rate_hz,
        }
    }

    /// Frame rate in Hz.
    pub fn frame_rate_hz(&self) -> f64 {
        self.frame_rate_hz
    }

    /// Time of the centre of frame `index`, seconds from the start of the stream.
    pub fn time_s(&self, index: u64) -> f64 {
        index as f64 / self.frame_rate_hz
    }

    /// Fractional sample position of the centre of frame `index` (sample 0 is the first sample).
    pub fn sample_pos(&self, index: u64) -> f64 {
        index as f64 * self.sample_rate_hz / self.frame_rate_hz
    }

    /// Number of frames whose centre lies inside a stream of `length_samples` samples.
    pub fn frames_in(&self, length_samples: u64) -> u64 {
        // Frame k is inside when k * sr / fr < length, i.e. k < length * fr / sr.
        let bound = length_samples as f64 * self.frame_rate_hz / self.sample_rate_hz;
        let n = bound.ceil() as u64;
        // Guard against rounding at exact multiples.
        if n > 0 && self.sample_pos(n - 1) >= length_samples as f64 {
            n - 1
        } else {
            n
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_land_at_the_same_times_at_any_rate() {
        let a = FrameClock::new(120.0, 44_100.0);
        let b = FrameClock::new(120.0, 48_000.0);
        for k in [0u64, 1, 7, 120, 431_999, 10_000_000] {
            assert_eq!(a.time_s(k), b.time_s(k));
            assert!((a.sample_pos(k) / 44_100.0 - b.sample_pos(k) / 48_000.0).abs() < 1e-9);
        }
        // 367.5 samples per frame at 44.1 kHz, kept fractional.
        assert_eq!(a.sample_pos(1), 367.5);
        assert_eq!(a.sample_pos(2), 735.0);
        // One hour later there is still no drift.
        assert_eq!(a.sample_pos(120 * 3600), 44_100.0 * 3600.0);
    }

    #[test]
    fn frames_in_counts_centres_inside_the_stream() {
        let c = FrameClock::new(100.0, 48_000.0);
        assert_eq!(c.frames_in(0), 0);
        assert_eq!(c.frames_in(1), 1);
        assert_eq!(c.frames_in(480), 1);
        assert_eq!(c.frames_in(481), 2);
        assert_eq!(c.frames_in(48_000), 100);
        let c = FrameClock::new(120.0, 44_100.0);
        assert_eq!(c.frames_in(368), 2);
        assert_eq!(c.frames_in(367), 1);
    }
}
