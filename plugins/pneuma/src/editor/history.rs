//! The GUI's memory of the last seconds: view frames and breaths (inserted or already there), trimmed to a time
//! span, and the phrases and pauses read from the speaking gate. GUI thread only (allocates).

use std::collections::VecDeque;

use super::feed::{ViewBreath, ViewFrame};

/// How much the timeline shows, seconds.
pub const SPAN_S: f64 = 10.0;

/// A stretch of the speaking gate: a phrase (`speaking`) or a pause, in stream seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// Start, seconds.
    pub start_s: f64,
    /// End, seconds.
    pub end_s: f64,
    /// Inside a phrase (true) or a pause.
    pub speaking: bool,
}

/// The last [`SPAN_S`] seconds (and a little more) of frames and breaths.
#[derive(Debug, Default)]
pub struct History {
    frames: VecDeque<ViewFrame>,
    breaths: VecDeque<ViewBreath>,
}

impl History {
    /// Adds a frame. A frame older than the newest one (the stream restarted) clears the
    /// history first.
    pub fn push_frame(&mut self, frame: &ViewFrame) {
        if self
            .frames
            .back()
            .is_some_and(|last| frame.control.time_s < last.control.time_s)
        {
            self.frames.clear();
            self.breaths.clear();
        }
        self.frames.push_back(*frame);
        let keep_from = frame.control.time_s - SPAN_S - 1.0;
        while self
            .frames
            .front()
            .is_some_and(|f| f.control.time_s < keep_from)
        {
            self.frames.pop_front();
        }
        while self.breaths.front().is_some_and(|b| b.end_s < keep_from) {
            self.breaths.pop_front();
        }
    }

    /// Adds a breath (inserted or already there).
    pub fn push_breath(&mut self, breath: &ViewBreath) {
        self.breaths.push_back(*breath);
    }

    /// The frames, oldest first.
    pub fn frames(&self) -> &VecDeque<ViewFrame> {
        &self.frames
    }

    /// The breaths, oldest first.
    pub fn breaths(&self) -> &VecDeque<ViewBreath> {
        &self.breaths
    }

    /// The input's peak over the frames kept, dBFS, and the seconds they span; `None` before
    /// any frame.
    pub fn input_peak_db(&self) -> Option<(f64, f64)> {
        let (first, last) = (self.frames.front()?, self.frames.back()?);
        let peak = self.frames.iter().fold(0.0f32, |m, f| m.max(f.input_peak));
        Some((
            f64::from(pneuma_core::analysis::amplitude_to_db(f64::from(peak))),
            last.control.time_s - first.control.time_s,
        ))
    }

    /// Time of the newest frame, seconds (0 before any).
    pub fn now_s(&self) -> f64 {
        self.frames.back().map_or(0.0, |f| f.control.time_s)
    }

    /// The phrases and pauses of the speaking gate, oldest first; each frame counts from its
    /// time to the next frame's.
    pub fn segments(&self) -> Vec<Segment> {
        let mut out: Vec<Segment> = Vec::new();
        let mut iter = self.frames.iter().peekable();
        while let Some(f) = iter.next() {
            let end_s = iter.peek().map_or(f.control.time_s, |n| n.control.time_s);
            match out.last_mut() {
                Some(seg) if seg.speaking == f.control.speaking => seg.end_s = end_s,
                _ => out.push(Segment {
                    start_s: f.control.time_s,
                    end_s,
                    speaking: f.control.speaking,
                }),
            }
        }
        out
    }
}

/// The editor's word on an input too quiet for its speech to be heard in full (the render
/// summary's "very quiet" rule, on the input's peak over the timeline's `span_s` seconds);
/// `None` for a loud enough input or for no signal at all (a muted input, dither).
pub fn input_level_note(peak_db: f64, span_s: f64) -> Option<String> {
    use pneuma_core::analysis::{no_signal_peak_db, quiet_peak_db};
    (peak_db >= no_signal_peak_db() && peak_db < quiet_peak_db()).then(|| {
        format!(
            "input peaks at {peak_db:.0} dBFS over the last {span_s:.0} s: speech needs about \
             {:.0} dBFS to be heard in full (raise the input gain)",
            quiet_peak_db()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::ControlFrame;

    fn view(time_s: f64, speaking: bool) -> ViewFrame {
        ViewFrame {
            control: ControlFrame {
                time_s,
                speaking,
                ..ControlFrame::default()
            },
            input_peak: 0.0,
        }
    }

    #[test]
    fn a_quiet_input_is_told_over_the_timeline_and_a_loud_or_silent_one_is_not() {
        let note = |peaks: &[f32]| {
            let mut h = History::default();
            for (i, &p) in peaks.iter().enumerate() {
                h.push_frame(&ViewFrame {
                    input_peak: p,
                    ..view(i as f64, true)
                });
            }
            h.input_peak_db()
                .and_then(|(db, span)| input_level_note(db, span))
        };
        // A voice peaking at -50 dBFS (0.00316) somewhere in the last 9 s: told, with its peak.
        let quiet = note(&[0.0001, 0.003_162, 0.0002, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        let text = quiet.expect("a voice peaking at -50 dBFS is told");
        assert!(
            text.contains("-50 dBFS over the last 9 s") && text.contains("-30 dBFS"),
            "{text}"
        );
        // At -20 dBFS: loud enough. Digital silence or dither (one 16-bit step): no signal.
        assert_eq!(note(&[0.1, 0.0]), None);
        assert_eq!(note(&[0.0, 1.0 / 32768.0]), None);
        assert_eq!(History::default().input_peak_db(), None);
    }

    #[test]
    fn segments_follow_the_speaking_gate() {
        let mut h = History::default();
        // 0.0..0.3 pause, 0.3..0.6 phrase, 0.6..0.9 pause (frames every 0.1 s).
        for (i, speaking) in [
            false, false, false, true, true, true, false, false, false, false,
        ]
        .into_iter()
        .enumerate()
        {
            h.push_frame(&view(i as f64 * 0.1, speaking));
        }
        let s = h.segments();
        assert_eq!(s.len(), 3, "{s:?}");
        assert!(!s[0].speaking && s[1].speaking && !s[2].speaking);
        assert!((s[1].start_s - 0.3).abs() < 1e-9 && (s[1].end_s - 0.6).abs() < 1e-9);
        assert!((s[2].end_s - 0.9).abs() < 1e-9);
    }

    #[test]
    fn only_the_last_span_is_kept_and_a_restart_clears() {
        let mut h = History::default();
        h.push_breath(&ViewBreath {
            start_s: 0.5,
            end_s: 0.8,
            existing: false,
        });
        for i in 0..=2000 {
            h.push_frame(&view(i as f64 / 100.0, false));
        }
        assert_eq!(h.now_s(), 20.0);
        let oldest = h.frames().front().unwrap().control.time_s;
        assert!((oldest - (20.0 - SPAN_S - 1.0)).abs() < 0.011, "{oldest}");
        assert!(
            h.breaths().is_empty(),
            "the old breath left with its frames"
        );
        h.push_frame(&view(0.0, true));
        assert_eq!(h.frames().len(), 1, "a stream restart clears the history");
    }
}
