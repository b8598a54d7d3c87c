//! Silero's speech segments and the frame decision judged on them.
//!
//! [`Hysteresis`] is the rule of the `silero-vad` package's `get_speech_timestamps` (version
//! 6.2.3, its defaults) on the chunk probabilities, step by step: a segment starts at the first
//! chunk with p ≥ [`THRESHOLD`]; once p < [`NEG_THRESHOLD`] it ends there, when the quiet has
//! lasted [`MIN_SILENCE_S`] (a chunk with p ≥ 0.5 in between cancels the end); segments of
//! [`MIN_SPEECH_S`] or less are dropped; each keeps [`PAD_S`] either side (a gap under twice that
//! is split between its two segments). [`segments`] is the same rule on a whole signal (the
//! evaluation's Silero baseline); [`SegmentTrack`] follows it on a stream and judges each
//! segment by the stacked model ([`judge`](super::judge)): a frame is **speech** when it lies in
//! a segment at or after the start of the segment's first half-second window the model calls
//! speech ([`speech_from`]; a segment whose first window is speech keeps its padding before
//! it). Silero joins a music or noise lead-in and the speech right after it into one segment:
//! the lead-in does not veto the speech. The podcast evaluation scores this decision
//! (offline, through [`speech_from`]); the engine itself judges the tracker's phrases.

use super::judge::{speech_from, RecentSpeech, JUDGE_WINDOW_S};
use super::silero::{CHUNK, SILERO_RATE_HZ};

/// Probability that starts (or keeps) a segment.
pub const THRESHOLD: f32 = 0.5;
/// Probability under which a segment may end.
pub const NEG_THRESHOLD: f32 = 0.35;
/// Quiet a segment end needs, seconds.
pub const MIN_SILENCE_S: f64 = 0.1;
/// Segments this long or shorter are dropped, seconds.
pub const MIN_SPEECH_S: f64 = 0.25;
/// Padding either side of a segment, seconds.
pub const PAD_S: f64 = 0.03;

/// 16 kHz samples of a duration (as the package counts them).
fn samples(s: f64) -> u64 {
    (s * SILERO_RATE_HZ) as u64
}

/// What one chunk changed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edge {
    /// A segment started at this 16 kHz sample (a chunk's first).
    Start(u64),
    /// The segment from `start` ended at `end` (16 kHz samples); `kept` unless it was too short.
    End {
        /// Its first sample.
        start: u64,
        /// One past its last.
        end: u64,
        /// Longer than [`MIN_SPEECH_S`].
        kept: bool,
    },
}

/// The package's hysteresis, chunk by chunk. See the module docs.
#[derive(Debug, Clone, Copy, Default)]
pub struct Hysteresis {
    triggered: bool,
    start: u64,
    temp_end: Option<u64>,
}

impl Hysteresis {
    /// Chunk `index` with probability `p`.
    pub fn step(&mut self, index: u64, p: f32) -> Option<Edge> {
        let s = index * CHUNK as u64;
        if p >= THRESHOLD {
            self.temp_end = None;
            if !self.triggered {
                self.triggered = true;
                self.start = s;
                return Some(Edge::Start(s));
            }
            return None;
        }
        if p < NEG_THRESHOLD && self.triggered {
            let temp_end = *self.temp_end.get_or_insert(s);
            if s - temp_end < samples(MIN_SILENCE_S) {
                return None;
            }
            self.triggered = false;
            self.temp_end = None;
            return Some(Edge::End {
                start: self.start,
                end: temp_end,
                kept: temp_end - self.start > samples(MIN_SPEECH_S),
            });
        }
        None
    }

    /// The start of a segment still open.
    pub fn open_start(&self) -> Option<u64> {
        self.triggered.then_some(self.start)
    }
}

/// Silero's segments of a whole signal of `n_samples` (16 kHz) from its chunk probabilities,
/// padded, in 16 kHz samples: exactly the package's `get_speech_timestamps`.
pub fn segments(probabilities: &[f32], n_samples: u64) -> Vec<(u64, u64)> {
    let mut h = Hysteresis::default();
    let mut raw = Vec::new();
    for (i, &p) in probabilities.iter().enumerate() {
        if let Some(Edge::End {
            start,
            end,
            kept: true,
        }) = h.step(i as u64, p)
        {
            raw.push((start, end));
        }
    }
    if let Some(start) = h.open_start() {
        if n_samples.saturating_sub(start) > samples(MIN_SPEECH_S) {
            raw.push((start, n_samples));
        }
    }
    let pad = samples(PAD_S);
    let mut out = raw.clone();
    for i in 0..out.len() {
        if i == 0 {
            out[i].0 = out[i].0.saturating_sub(pad);
        }
        if i + 1 < out.len() {
            let gap = raw[i + 1].0.saturating_sub(out[i].1);
            if gap < 2 * pad {
                out[i].1 += gap / 2;
                out[i + 1].0 = out[i + 1].0.saturating_sub(gap / 2);
            } else {
                out[i].1 = (out[i].1 + pad).min(n_samples);
                out[i + 1].0 = out[i + 1].0.saturating_sub(pad);
            }
        } else {
            out[i].1 = (out[i].1 + pad).min(n_samples);
        }
    }
    out
}

/// One of Silero's segments on the stream, with its judgement.
#[derive(Debug, Clone, Copy, Default)]
struct Tracked {
    start_s: f64,
    /// `None` while it lasts.
    end_s: Option<f64>,
    /// The start of the next window to judge while none has been called speech.
    next_window_s: f64,
    /// Where the segment is speech from ([`speech_from`]), once a window has been called speech.
    speech_from_s: Option<f64>,
}

/// Segments kept for frames still to be decided.
const KEPT_SEGMENTS: usize = 32;
/// Frames kept to judge a segment's windows (its start is known a chunk late, its end after
/// [`MIN_SILENCE_S`] of quiet and a chunk), seconds.
const RECENT_S: f64 = 1.0;

/// Silero's segments on a stream, each judged by the stacked model. See the module docs.
/// Allocation-free after `new`.
#[derive(Debug, Clone)]
pub struct SegmentTrack {
    threshold: f32,
    hysteresis: Hysteresis,
    /// Newest last; at most [`KEPT_SEGMENTS`].
    segments: Vec<Tracked>,
    recent: RecentSpeech,
    /// The time of the last frame heard.
    latest_s: Option<f64>,
}

impl SegmentTrack {
    /// A track for frames at `frame_rate_hz` judging with the model's `threshold`. Allocates.
    pub fn new(frame_rate_hz: f64, threshold: f32) -> Self {
        Self {
            threshold,
            hysteresis: Hysteresis::default(),
            segments: Vec::with_capacity(KEPT_SEGMENTS),
            recent: RecentSpeech::new(RECENT_S, frame_rate_hz),
            latest_s: None,
        }
    }

    /// Back to the start of a stream.
    pub fn reset(&mut self) {
        self.hysteresis = Hysteresis::default();
        self.segments.clear();
        self.recent.reset();
        self.latest_s = None;
    }

    /// Chunk `index` with Silero's probability `p`; `at_s` maps a 16 kHz sample to stream
    /// seconds.
    pub fn on_chunk(&mut self, index: u64, p: f32, at_s: impl Fn(u64) -> f64) {
        match self.hysteresis.step(index, p) {
            Some(Edge::Start(s)) => {
                if self.segments.len() == KEPT_SEGMENTS {
                    self.segments.remove(0);
                }
                let start_s = at_s(s);
                self.segments.push(Tracked {
                    start_s,
                    end_s: None,
                    next_window_s: start_s,
                    speech_from_s: None,
                });
                self.judge_open_windows();
            }
            Some(Edge::End { end, kept, .. }) => {
                if !kept {
                    self.segments.pop();
                } else if let Some(last) = self.segments.last_mut() {
                    let end_s = at_s(end);
                    last.end_s = Some(end_s);
                    // Windows judged with frames heard after the end (while its quiet was
                    // confirmed) are judged again without them, each cut at the end.
                    let first_cut = std::iter::once(last.start_s)
                        .chain(self.recent.iter().map(|(t, _)| t))
                        .filter(|&w| w >= last.start_s)
                        .find(|&w| w + JUDGE_WINDOW_S > end_s)
                        .unwrap_or(end_s);
                    if last.speech_from_s.is_none_or(|w| w >= first_cut) {
                        let from = last.next_window_s.min(first_cut);
                        let frames = self.recent.iter().filter(|&(t, _)| t >= from);
                        last.speech_from_s = speech_from(frames, from, end_s, self.threshold);
                    }
                }
            }
            None => {}
        }
    }

    /// The next analysis frame with its speech probability.
    pub fn on_frame(&mut self, time_s: f64, speech_p: f32) {
        self.recent.push(time_s, speech_p);
        self.latest_s = Some(time_s);
        self.judge_open_windows();
    }

    /// Judges the open segment's windows that the frames heard so far complete, in order,
    /// until one is speech.
    fn judge_open_windows(&mut self) {
        let Some(latest_s) = self.latest_s else {
            return;
        };
        let Some(last) = self.segments.last_mut() else {
            return;
        };
        if last.end_s.is_some() {
            return;
        }
        while last.speech_from_s.is_none() && latest_s >= last.next_window_s + JUDGE_WINDOW_S {
            let w = last.next_window_s;
            if self
                .recent
                .mean_between(w, w + JUDGE_WINDOW_S)
                .is_some_and(|m| m >= self.threshold)
            {
                last.speech_from_s = Some(w);
            } else {
                match self.recent.iter().map(|(t, _)| t).find(|&t| t > w) {
                    Some(next) => last.next_window_s = next,
                    None => break,
                }
            }
        }
    }

    /// Whether a frame at `time_s` is speech as far as the stream has been heard: inside a
    /// segment (with its padding) from where the model calls it speech ([`speech_from`]).
    pub fn speech_at(&self, time_s: f64) -> bool {
        let n = self.segments.len();
        (0..n).any(|i| {
            let s = &self.segments[i];
            let Some(from_s) = s.speech_from_s else {
                return false;
            };
            let lo = match i.checked_sub(1).and_then(|j| self.segments[j].end_s) {
                _ if from_s > s.start_s => from_s,
                Some(prev_end) if s.start_s - prev_end < 2.0 * PAD_S => {
                    s.start_s - (s.start_s - prev_end) / 2.0
                }
                _ => s.start_s - PAD_S,
            };
            let hi = match (s.end_s, self.segments.get(i + 1)) {
                (Some(end), Some(next)) if next.start_s - end < 2.0 * PAD_S => {
                    end + (next.start_s - end) / 2.0
                }
                (Some(end), _) => end + PAD_S,
                (None, _) => f64::INFINITY,
            };
            time_s >= lo && time_s < hi
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const C: u64 = CHUNK as u64;

    #[test]
    fn the_offline_rule_is_the_packages() {
        // 0.5 at chunks 2..12 (a 320 ms segment), a one-chunk dip at 0.4 inside (no end: not
        // under 0.35), an end after 4 quiet chunks (128 ms ≥ 100 ms), a 3-chunk segment
        // (96 ms: dropped), a segment open at the end.
        let mut p = vec![0.0f32; 40];
        p[2..12].fill(0.9);
        p[6] = 0.4;
        p[20..23].fill(0.9);
        p[30..40].fill(0.9);
        let n = 40 * C;
        let pad = samples(PAD_S);
        assert_eq!(
            segments(&p, n),
            vec![(2 * C - pad, 12 * C + pad), (30 * C - pad, n)]
        );
        // A quiet of three chunks (96 ms) does not end a segment.
        let mut q = vec![0.9f32; 20];
        q[8..11].fill(0.1);
        assert_eq!(segments(&q, 20 * C), vec![(0, 20 * C)]);
        // Step by step: the end is reported once the quiet has lasted four chunks (128 ms).
        let mut h = Hysteresis::default();
        let edges: Vec<Edge> = [
            0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.9, 0.0, 0.0, 0.0, 0.0, 0.0,
        ]
        .iter()
        .enumerate()
        .filter_map(|(i, &p)| h.step(i as u64, p))
        .collect();
        assert_eq!(
            edges,
            [
                Edge::Start(0),
                Edge::End {
                    start: 0,
                    end: 9 * C,
                    kept: true
                }
            ]
        );
    }

    /// Feeds `t` chunks and frames (100 frames/s) in time order: `silero` per 32 ms chunk,
    /// `stacked(frame)` per frame, for `seconds` from where the feed stands.
    struct Feed {
        chunk: u64,
        frame: u64,
    }

    impl Feed {
        fn run(&mut self, t: &mut SegmentTrack, seconds: f64, silero: f32, stacked: f32) {
            self.run_with(t, seconds, |_| silero, |_| stacked);
        }

        fn run_with(
            &mut self,
            t: &mut SegmentTrack,
            seconds: f64,
            silero: impl Fn(u64) -> f32,
            stacked: impl Fn(u64) -> f32,
        ) {
            let at = |s: u64| s as f64 / SILERO_RATE_HZ;
            let chunk_s = CHUNK as f64 / SILERO_RATE_HZ;
            let end = seconds + self.chunk as f64 * chunk_s;
            while (self.chunk + 1) as f64 * chunk_s <= end + 1e-9 {
                let chunk_end_s = (self.chunk + 1) as f64 * chunk_s;
                while (self.frame as f64) / 100.0 < chunk_end_s {
                    t.on_frame(self.frame as f64 / 100.0, stacked(self.frame));
                    self.frame += 1;
                }
                t.on_chunk(self.chunk, silero(self.chunk), at);
                self.chunk += 1;
            }
        }
    }

    #[test]
    fn a_frame_is_speech_in_a_segment_whose_start_the_model_calls_speech() {
        let mut t = SegmentTrack::new(100.0, 0.5);
        let mut f = Feed { chunk: 0, frame: 0 };
        f.run(&mut t, 0.64, 0.0, 0.1);
        f.run(&mut t, 0.96, 0.95, 0.9); // speech: Silero and the model agree
        f.run(&mut t, 0.64, 0.0, 0.1);
        f.run(&mut t, 0.96, 0.8, 0.2); // singing: Silero says speech, the model does not
        f.run(&mut t, 0.64, 0.0, 0.1);
        assert!(!t.speech_at(0.3));
        assert!(t.speech_at(0.62), "padding before the segment");
        assert!(t.speech_at(1.0));
        assert!(!t.speech_at(2.0), "the quiet between");
        assert!(!t.speech_at(2.8), "a segment the model rejects");
        t.reset();
        assert!(!t.speech_at(1.0));
    }

    #[test]
    fn speech_after_a_lead_in_in_the_same_segment_is_speech_from_where_it_shows() {
        // One Silero segment from 0.64 s: 1.28 s of music the model rejects, then 1.28 s of
        // speech, then quiet.
        let mut t = SegmentTrack::new(100.0, 0.5);
        let mut f = Feed { chunk: 0, frame: 0 };
        f.run(&mut t, 0.64, 0.0, 0.1);
        f.run(&mut t, 1.28, 0.8, 0.1);
        f.run(&mut t, 1.28, 0.95, 0.95);
        f.run(&mut t, 0.64, 0.0, 0.1);
        assert!(!t.speech_at(0.7), "the lead-in's start");
        assert!(!t.speech_at(1.5), "the lead-in");
        assert!(t.speech_at(2.0), "the speech after it");
        assert!(t.speech_at(3.1), "the speech's end");
        assert!(!t.speech_at(3.5), "the quiet after");
        // The first window whose mean reaches 0.5 starts at 1.66 s: 26 frames of the lead-in
        // (0.1) and 24 of speech (0.95), mean 0.508; from 1.65 s, 27 and 23: 0.491.
        assert_eq!(t.segments[0].speech_from_s, Some(1.66));
    }

    #[test]
    fn the_streamed_judgement_is_the_offline_one() {
        // Random runs of Silero and model probabilities; every segment's judgement on the
        // stream (windows judged as they complete, judged again when the end cuts them)
        // against `speech_from` on the whole record.
        let mut rng = crate::rng::SeededRng::new(32);
        let n_chunks = 900u64;
        let mut silero = Vec::new();
        while (silero.len() as u64) < n_chunks {
            let p = if rng.uniform() < 0.5 { 0.9 } else { 0.1 };
            let len = 1 + (rng.uniform() * 30.0) as usize;
            silero.extend(std::iter::repeat_n(p as f32, len));
        }
        let n_frames = (n_chunks as f64 * CHUNK as f64 / SILERO_RATE_HZ * 100.0) as usize + 10;
        let mut stacked = Vec::new();
        while stacked.len() < n_frames {
            let p = rng.uniform() as f32;
            let len = 1 + (rng.uniform() * 40.0) as usize;
            stacked.extend(std::iter::repeat_n(p, len));
        }
        let mut t = SegmentTrack::new(100.0, 0.5);
        let mut f = Feed { chunk: 0, frame: 0 };
        let seconds = n_chunks as f64 * CHUNK as f64 / SILERO_RATE_HZ;
        f.run_with(
            &mut t,
            seconds,
            |c| silero[c as usize],
            |k| stacked[k as usize],
        );
        let frames: Vec<(f64, f32)> = (0..f.frame)
            .map(|k| (k as f64 / 100.0, stacked[k as usize]))
            .collect();
        let closed: Vec<&Tracked> = t.segments.iter().filter(|s| s.end_s.is_some()).collect();
        assert!(closed.len() >= 10, "{} segments", closed.len());
        assert!(closed.len() < KEPT_SEGMENTS);
        let mut later = 0;
        for s in closed {
            let end_s = s.end_s.unwrap_or(f64::NAN);
            let offline = speech_from(frames.iter().copied(), s.start_s, end_s, 0.5);
            assert_eq!(s.speech_from_s, offline, "segment {}-{end_s}", s.start_s);
            later += usize::from(offline.is_some_and(|w| w > s.start_s));
        }
        assert!(later >= 1, "no segment judged speech after its start");
    }
}
