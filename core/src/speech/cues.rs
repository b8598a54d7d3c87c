//! The speech decision's own cues, per analysis frame, causal, from the frames' `voiced` flag
//! and `rms_db` (any frame rate; windows in seconds):
//! - `voiced_near`: 1 when a frame within the last [`VOICED_NEAR_S`] (this one included) was
//!   voiced, else 0. Speech is voiced in bursts; a Silero error on noise or an instrument often
//!   has no voicing near it.
//! - `level_dips`: the share of the last [`DIP_WINDOW_S`] of frames (those heard so far at the
//!   start of a stream) whose level lies more than [`DIP_DB`] under the window's loudest frame.
//!   Speech falls silent between syllables and words; singing and music hold their level.

/// How far back a voiced frame counts for `voiced_near`, seconds.
pub const VOICED_NEAR_S: f64 = 0.09;
/// The window of `level_dips`, seconds.
pub const DIP_WINDOW_S: f64 = 1.0;
/// How far under the window's loudest frame a frame counts as a dip, dB.
pub const DIP_DB: f32 = 20.0;

/// The cue state. See the module docs.
#[derive(Debug, Clone)]
pub struct Cues {
    voiced_frames: u64,
    /// Frame levels of the dip window (a ring), dBFS.
    levels: Vec<f32>,
    state: CueState,
}

/// What [`Cues::reset`] clears.
#[derive(Debug, Clone, Copy, Default)]
struct CueState {
    /// Frames seen.
    frames: u64,
    /// Index of the last voiced frame.
    last_voiced: Option<u64>,
}

impl Cues {
    /// Cues for frames at `frame_rate_hz`. Allocates.
    pub fn new(frame_rate_hz: f64) -> Self {
        let frames = |s: f64| ((s * frame_rate_hz).round() as u64).max(1);
        Self {
            voiced_frames: frames(VOICED_NEAR_S),
            levels: vec![0.0; frames(DIP_WINDOW_S) as usize],
            state: CueState::default(),
        }
    }

    /// Back to the start of a stream.
    pub fn reset(&mut self) {
        self.state = CueState::default();
    }

    /// The cues `(voiced_near, level_dips)` after frame `voiced`, `rms_db`.
    pub fn step(&mut self, voiced: bool, rms_db: f32) -> (f32, f32) {
        let s = &mut self.state;
        let i = s.frames;
        s.frames += 1;
        if voiced {
            s.last_voiced = Some(i);
        }
        let near = s.last_voiced.is_some_and(|v| i - v < self.voiced_frames);
        let len = self.levels.len();
        self.levels[(i % len as u64) as usize] = if rms_db.is_finite() {
            rms_db
        } else {
            crate::analysis::LEVEL_FLOOR_DB
        };
        let heard = &self.levels[..(s.frames as usize).min(len)];
        let loudest = heard.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        let dips = heard.iter().filter(|&&l| l < loudest - DIP_DB).count();
        (f32::from(u8::from(near)), dips as f32 / heard.len() as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn voiced_near_holds_for_its_window_after_the_last_voiced_frame() {
        let mut c = Cues::new(100.0);
        assert_eq!(c.step(false, -30.0).0, 0.0);
        assert_eq!(c.step(true, -30.0).0, 1.0);
        // 9 frames at 100 frames/s: this one and the 8 after it.
        let after: Vec<f32> = (0..10).map(|_| c.step(false, -30.0).0).collect();
        assert_eq!(after, [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0]);
        c.reset();
        assert_eq!(c.step(false, -30.0).0, 0.0);
    }

    #[test]
    fn level_dips_count_frames_20_db_under_the_loudest_of_the_last_second() {
        let mut c = Cues::new(10.0);
        // Loud, then quiet: the quiet frames are dips while the loud one is in the window.
        assert_eq!(c.step(true, -20.0).1, 0.0);
        let d: Vec<f32> = (0..10).map(|_| c.step(false, -45.0).1).collect();
        assert!((d[0] - 0.5).abs() < 1e-6, "{d:?}");
        assert!((d[8] - 0.9).abs() < 1e-6, "{d:?}");
        // The loud frame has left the 10-frame window: the quiet ones are the level now.
        assert_eq!(d[9], 0.0, "{d:?}");
        // A steady level (singing, a drone) has no dips.
        let mut steady = Cues::new(100.0);
        let last = (0..300)
            .map(|k| steady.step(true, -20.0 - (k % 7) as f32))
            .last();
        assert_eq!(last.map(|c| c.1), Some(0.0));
    }
}
