//! Judging a span of sound as speech: the mean speech probability (the stacked model's) of a
//! window of [`JUDGE_WINDOW_S`], against the model's threshold. The phrase tracker's phrases
//! (where breaths go) are judged by their first window ([`SpanJudge`]); Silero's segments (the
//! frame decision) are speech from their first window that is ([`speech_from`]).
//!
//! A half second, not the whole span: the tracker merges a music lead-in with the speech after
//! it into one phrase, and speech shows itself within a syllable or two.

/// How much of a span's start is judged, seconds.
pub const JUDGE_WINDOW_S: f64 = 0.5;

/// The running judgement of one span.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpanJudge {
    start_s: f64,
    sum: f64,
    count: u32,
    /// The window has been heard to its end (or the span ended before it).
    complete: bool,
}

impl SpanJudge {
    /// A span starting at `start_s`, nothing heard yet.
    pub fn new(start_s: f64) -> Self {
        Self {
            start_s,
            ..Self::default()
        }
    }

    /// Where the span starts, seconds.
    pub fn start_s(&self) -> f64 {
        self.start_s
    }

    /// A frame at `time_s` with speech probability `p` (frames in order; those before the
    /// start are ignored, the first one past the window completes it).
    pub fn add(&mut self, time_s: f64, p: f32) {
        if self.complete || time_s < self.start_s {
            return;
        }
        if time_s >= self.start_s + JUDGE_WINDOW_S {
            self.complete = true;
            return;
        }
        self.sum += f64::from(p);
        self.count += 1;
    }

    /// The span ended (its last frame added): what was heard is all there is.
    pub fn close(&mut self) {
        self.complete = true;
    }

    /// The window has been heard (or the span ended).
    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// Frames heard in the window.
    pub fn frames(&self) -> u32 {
        self.count
    }

    /// The mean probability so far (`None` before the first frame).
    pub fn mean(&self) -> Option<f32> {
        (self.count > 0).then(|| (self.sum / f64::from(self.count)) as f32)
    }

    /// Speech by what was heard so far (`None` before the first frame).
    pub fn is_speech(&self, threshold: f32) -> Option<bool> {
        self.mean().map(|m| m >= threshold)
    }
}

/// Where the span `[start_s, end_s)` becomes speech: the start of its first window of
/// [`JUDGE_WINDOW_S`] (cut at `end_s`) whose mean probability reaches `threshold`, the windows
/// starting at `start_s` and at each frame of the span after it; `None` when none does.
/// `frames`: `(time_s, p)` in time order. Speech that follows a music or noise lead-in inside
/// one span is speech from where it shows itself, not vetoed with the lead-in; a span whose
/// first window is speech is speech from its start.
pub fn speech_from(
    frames: impl Iterator<Item = (f64, f32)> + Clone,
    start_s: f64,
    end_s: f64,
    threshold: f32,
) -> Option<f64> {
    let starts = std::iter::once(start_s).chain(
        frames
            .clone()
            .map(|(t, _)| t)
            .filter(move |&t| t > start_s && t < end_s),
    );
    for w in starts {
        let mut judge = SpanJudge::new(w);
        let window = frames
            .clone()
            .skip_while(|&(t, _)| t < w)
            .take_while(|&(t, _)| t < end_s.min(w + JUDGE_WINDOW_S));
        for (t, p) in window {
            judge.add(t, p);
        }
        judge.close();
        if judge.is_speech(threshold) == Some(true) {
            return Some(w);
        }
    }
    None
}

/// The last frames' speech probabilities (a ring, allocated once), so that a span reported
/// after its start (a phrase onset is confirmed tens of milliseconds late, a Silero segment
/// a chunk late) is judged from its start.
#[derive(Debug, Clone)]
pub struct RecentSpeech {
    /// `(time_s, p)`, oldest overwritten.
    ring: Vec<(f64, f32)>,
    next: usize,
    len: usize,
}

impl RecentSpeech {
    /// Room for `seconds` of frames at `frame_rate_hz`. Allocates.
    pub fn new(seconds: f64, frame_rate_hz: f64) -> Self {
        let n = (seconds * frame_rate_hz).ceil().max(1.0) as usize + 1;
        Self {
            ring: vec![(0.0, 0.0); n],
            next: 0,
            len: 0,
        }
    }

    /// Forgets every frame.
    pub fn reset(&mut self) {
        self.next = 0;
        self.len = 0;
    }

    /// The next frame.
    pub fn push(&mut self, time_s: f64, p: f32) {
        self.ring[self.next] = (time_s, p);
        self.next = (self.next + 1) % self.ring.len();
        self.len = (self.len + 1).min(self.ring.len());
    }

    /// The kept frames, oldest first.
    pub fn iter(&self) -> impl Iterator<Item = (f64, f32)> + Clone + '_ {
        let n = self.ring.len();
        (0..self.len).map(move |k| self.ring[(self.next + n - self.len + k) % n])
    }

    /// A judge of the span from `start_s`, fed the kept frames from its start on.
    pub fn judge_from(&self, start_s: f64) -> SpanJudge {
        let mut j = SpanJudge::new(start_s);
        for (t, p) in self.iter() {
            j.add(t, p);
        }
        j
    }

    /// The mean probability of the kept frames after `from_s` (`None` when there are none),
    /// read from the newest back to `from_s` only.
    pub fn mean_since(&self, from_s: f64) -> Option<f32> {
        let n = self.ring.len();
        mean_p(
            (0..self.len)
                .map(|k| self.ring[(self.next + n - 1 - k) % n])
                .take_while(|&(t, _)| t > from_s),
        )
    }

    /// Every frame since `from_s` is still kept: none after it has been overwritten.
    pub fn holds_since(&self, from_s: f64) -> bool {
        self.len < self.ring.len() || self.iter().next().is_some_and(|(t, _)| t < from_s)
    }

    /// The mean probability of the kept frames in `[from_s, to_s)` (`None` when there are none).
    pub fn mean_between(&self, from_s: f64, to_s: f64) -> Option<f32> {
        mean_p(self.iter().filter(|&(t, _)| t >= from_s && t < to_s))
    }
}

/// The mean probability of `frames` (`(time_s, p)`), summed in their order (`None` when there
/// are none).
fn mean_p(frames: impl Iterator<Item = (f64, f32)>) -> Option<f32> {
    let (sum, n) = frames.fold((0.0f64, 0u32), |(s, n), (_, p)| (s + f64::from(p), n + 1));
    (n > 0).then(|| (sum / f64::from(n)) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_span_is_judged_by_the_mean_of_its_first_half_second() {
        let mut j = SpanJudge::new(1.0);
        assert_eq!(j.is_speech(0.5), None);
        // 10 frames/s: 0.9 (ignored), then 0.2, 0.9, 0.9, 0.9, 0.9 in the window, then 0.0 past it.
        for (k, p) in [0.9, 0.2, 0.9, 0.9, 0.9, 0.9, 0.0, 0.0].iter().enumerate() {
            j.add(0.9 + k as f64 * 0.1, *p);
        }
        assert!(j.is_complete());
        assert_eq!(j.frames(), 5);
        assert!((j.mean().unwrap_or(0.0) - 0.76).abs() < 1e-6);
        assert_eq!(j.is_speech(0.5), Some(true));
        assert_eq!(j.is_speech(0.8), Some(false));
        let mut short = SpanJudge::new(0.0);
        short.add(0.0, 0.3);
        assert!(!short.is_complete());
        short.close();
        assert!(short.is_complete() && short.is_speech(0.5) == Some(false));
    }

    #[test]
    fn recent_frames_judge_a_span_reported_late() {
        let mut r = RecentSpeech::new(0.3, 10.0);
        for k in 0..10 {
            r.push(k as f64 * 0.1, k as f32 / 10.0);
        }
        // Room for 4 frames: 0.6 .. 0.9.
        assert_eq!(r.iter().count(), 4);
        let j = r.judge_from(0.75);
        assert_eq!(j.frames(), 2);
        assert!((j.mean().unwrap_or(0.0) - 0.85).abs() < 1e-6);
        assert!((r.mean_between(0.6, 0.8).unwrap_or(0.0) - 0.65).abs() < 1e-6);
        assert_eq!(r.mean_between(2.0, 3.0), None);
        assert!((r.mean_since(0.75).unwrap_or(0.0) - 0.85).abs() < 1e-6);
        assert!((r.mean_since(0.0).unwrap_or(0.0) - 0.75).abs() < 1e-6);
        assert_eq!(r.mean_since(0.9), None);
        assert!(r.holds_since(0.65) && !r.holds_since(0.6));
        r.reset();
        assert_eq!(r.iter().count(), 0);
        r.push(0.5, 0.1);
        assert!(r.holds_since(0.0), "nothing overwritten since the reset");
    }
}
