//! [`FrameSink`]: the one shape every output of the engine has. A driver (the plugin's block,
//! the CLI's render, the offline helper) hands each control frame and each inserted breath to a
//! sink; the sink encodes it (CSV row, BVH motion line, MIDI CC messages, OSC bundle) or keeps
//! it. Sinks combine: a tuple of sinks is a sink (each gets every item, in tuple order), an
//! `Option` of a sink is a sink that is switched off when `None`, and `&mut` of a sink is one.
//!
//! The sinks here are pure encoders over a writer or a caller's buffer:
//! - [`TextSink`]: one text line per frame into any `std::io::Write` (controls CSV, BVH
//!   motion); keeps the first write error for the caller ([`TextSink::check`]).
//! - [`CcSink`]: MIDI CC messages from a [`CcEncoder`], each with the frame's sample position.
//! - [`OscSink`]: one OSC bundle per frame (`/pneuma` or VMC) in a fixed buffer, handed to the
//!   caller's function (a socket send, a file, a queue).
//! - [`Collect`]: every frame with its position and every breath, in memory (offline renders
//!   and tests).
//!
//! [`CcSink`] and [`OscSink`] never allocate, so the plugin's audio thread can drive them;
//! [`TextSink`] reuses one line buffer (it allocates only when a line is longer than any
//! before) and does I/O, so it is for offline drivers. Markers and the breaths CSV are
//! written from the breaths a [`Collect`] kept, once a render knows its length (a breath cut by
//! the end of the file ends with it).
//!
//! The position a driver passes with a frame is a sample index counted from an origin the
//! driver names: [`crate::engine::Engine::process_into`] counts from the origin its caller
//! gives (the plugin gives 0, so positions are offsets into the host's block, as MIDI events
//! need); the offline drivers count from the stream's first sample, latency included.

use std::io::Write;

use crate::control::{BreathEvent, ControlFrame};
use crate::encode::midi_cc::{CcEncoder, CcMessage};
use crate::encode::osc::{encode_frame, OscError, OscFormat, TimeTag, MAX_FRAME_PACKET_BYTES};

/// Where the engine's control frames and inserted breaths go.
///
/// Order: frames come in frame order and breaths in their order, each kind once; between the
/// two kinds there is no promise (a block's finished breaths follow its frames, so where a
/// breath lands among the frames depends on the block size). A sink that needs one timeline
/// orders by time itself (frames carry `time_s`, breaths `start_s`/`end_s`); markers and the
/// breaths CSV are written from the collected breaths for that reason.
pub trait FrameSink {
    /// One control frame, due at sample `at` (see the module docs for its origin).
    fn frame(&mut self, frame: &ControlFrame, at: u64);
    /// One finished inserted breath. Sinks that only follow frames ignore it.
    fn breath(&mut self, _breath: &BreathEvent) {}
    /// A breath that was already in the input (heard in a pause, not inserted), from
    /// `start_s` to `end_s`. Sinks that do not show them ignore it.
    fn existing_breath(&mut self, _start_s: f64, _end_s: f64) {}
}

impl<S: FrameSink + ?Sized> FrameSink for &mut S {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        (**self).frame(frame, at);
    }
    fn breath(&mut self, breath: &BreathEvent) {
        (**self).breath(breath);
    }
    fn existing_breath(&mut self, start_s: f64, end_s: f64) {
        (**self).existing_breath(start_s, end_s);
    }
}

/// A switched-off output: `None` takes nothing.
impl<S: FrameSink> FrameSink for Option<S> {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        if let Some(s) = self {
            s.frame(frame, at);
        }
    }
    fn breath(&mut self, breath: &BreathEvent) {
        if let Some(s) = self {
            s.breath(breath);
        }
    }
    fn existing_breath(&mut self, start_s: f64, end_s: f64) {
        if let Some(s) = self {
            s.existing_breath(start_s, end_s);
        }
    }
}

macro_rules! tuple_sink {
    ($($name:ident $idx:tt),+) => {
        /// Several outputs: each gets every frame and breath, in tuple order.
        impl<$($name: FrameSink),+> FrameSink for ($($name,)+) {
            fn frame(&mut self, frame: &ControlFrame, at: u64) {
                $(self.$idx.frame(frame, at);)+
            }
            fn breath(&mut self, breath: &BreathEvent) {
                $(self.$idx.breath(breath);)+
            }
            fn existing_breath(&mut self, start_s: f64, end_s: f64) {
                $(self.$idx.existing_breath(start_s, end_s);)+
            }
        }
    };
}
tuple_sink!(A 0, B 1);
tuple_sink!(A 0, B 1, C 2);
tuple_sink!(A 0, B 1, C 2, D 3);
tuple_sink!(A 0, B 1, C 2, D 3, E 4);

/// Keeps every frame with its position and every breath, in order. Allocates.
#[derive(Debug, Clone, Default)]
pub struct Collect {
    /// Every frame with the sample at which it was due.
    pub frames: Vec<(ControlFrame, u64)>,
    /// Every inserted breath.
    pub breaths: Vec<BreathEvent>,
    /// Every breath heard in the input, `(start_s, end_s)`.
    pub existing: Vec<(f64, f64)>,
}

impl FrameSink for Collect {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        self.frames.push((*frame, at));
    }
    fn breath(&mut self, breath: &BreathEvent) {
        self.breaths.push(*breath);
    }
    fn existing_breath(&mut self, start_s: f64, end_s: f64) {
        self.existing.push((start_s, end_s));
    }
}

/// A line encoder: appends the text of one frame (with its line ending) to a `String`.
pub type LineEncoder = fn(&mut String, &ControlFrame);

/// One text line per frame into a writer: the controls CSV
/// ([`crate::encode::controls_csv::write_row`]) or BVH motion
/// ([`crate::encode::bvh::push_control`]). The first write error is kept and later frames are
/// not written; [`TextSink::check`] reports it.
pub struct TextSink<W: Write> {
    out: W,
    encode: LineEncoder,
    line: String,
    error: Option<std::io::Error>,
}

impl<W: Write> TextSink<W> {
    /// Writes `header` (as given: include its line ending) to `out`, then one line per frame
    /// from `encode`.
    pub fn new(mut out: W, header: &str, encode: LineEncoder) -> std::io::Result<Self> {
        out.write_all(header.as_bytes())?;
        Ok(Self {
            out,
            encode,
            line: String::with_capacity(192),
            error: None,
        })
    }

    /// The controls CSV: its header, then [`crate::encode::controls_csv::write_row`].
    pub fn controls_csv(out: W) -> std::io::Result<Self> {
        let header = format!("{}\n", crate::encode::controls_csv::HEADER);
        Self::new(out, &header, crate::encode::controls_csv::write_row)
    }

    /// A BVH file of `frames` frames at `frame_rate_hz`: its header (which needs the count),
    /// then [`crate::encode::bvh::push_control`].
    pub fn bvh(out: W, frames: usize, frame_rate_hz: f64) -> std::io::Result<Self> {
        let header = crate::encode::bvh::header(frames, frame_rate_hz);
        Self::new(out, &header, crate::encode::bvh::push_control)
    }

    /// The first write error, if any: it stays (every later check reports it again and no
    /// later frame is written), so the file is never continued after a gap.
    pub fn check(&self) -> std::io::Result<()> {
        match &self.error {
            None => Ok(()),
            Some(e) => Err(std::io::Error::new(e.kind(), e.to_string())),
        }
    }

    /// The writer back, or the first write error.
    pub fn into_inner(self) -> std::io::Result<W> {
        match self.error {
            None => Ok(self.out),
            Some(e) => Err(e),
        }
    }
}

impl<W: Write> FrameSink for TextSink<W> {
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        if self.error.is_some() {
            return;
        }
        self.line.clear();
        (self.encode)(&mut self.line, frame);
        if let Err(e) = self.out.write_all(self.line.as_bytes()) {
            self.error = Some(e);
        }
    }
}

/// Frames passed on at another rate: at each instant `k / rate_hz` (`k = 0, 1, …`) the inner
/// sink gets the frame there, its body (head angles, breathing values) interpolated between
/// the frames either side and the rest of it the later frame's (a BVH at an animation's 24 or
/// 30 fps from 120 Hz frames; at a higher rate than the frames', the instants between frames
/// glide instead of repeating a frame). An instant goes out once the frame at or after it has
/// come. [`Resample::count`] gives the number passed on for a stream of known length, as a BVH
/// header needs it.
pub struct Resample<S: FrameSink> {
    inner: S,
    rate_hz: f64,
    /// The next instant's index.
    next: u64,
    /// Instants to pass on in all (`u64::MAX`: no limit).
    total: u64,
    /// The frame before, for the instants between it and the next.
    before: Option<ControlFrame>,
}

impl<S: FrameSink> Resample<S> {
    /// Passes frames to `inner` at `rate_hz`, at most `total` instants of them.
    pub fn new(inner: S, rate_hz: f64, total: u64) -> Self {
        Self {
            inner,
            rate_hz,
            next: 0,
            total,
            before: None,
        }
    }

    /// The instants `k / rate_hz` up to the last of `frames` frames at `frame_rate_hz`.
    pub fn count(frames: u64, frame_rate_hz: f64, rate_hz: f64) -> u64 {
        if frames == 0 {
            return 0;
        }
        let last_s = (frames - 1) as f64 / frame_rate_hz;
        (last_s * rate_hz + 1e-9).floor() as u64 + 1
    }

    /// The inner sink.
    pub fn inner(&self) -> &S {
        &self.inner
    }

    /// The inner sink back.
    pub fn into_inner(self) -> S {
        self.inner
    }
}

impl<S: FrameSink> FrameSink for Resample<S> {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        // Instants at this frame's time, give or take a rounding, are this frame.
        const SAME_S: f64 = 1e-9;
        while self.next < self.total {
            let t = self.next as f64 / self.rate_hz;
            if t > frame.time_s + SAME_S {
                break;
            }
            let out = match &self.before {
                Some(b) if t < frame.time_s - SAME_S && frame.time_s > b.time_s => {
                    let share = (t - b.time_s) / (frame.time_s - b.time_s);
                    b.body_toward(frame, share as f32)
                }
                _ => *frame,
            };
            self.inner.frame(&out, at);
            self.next += 1;
        }
        self.before = Some(*frame);
    }
    fn breath(&mut self, breath: &BreathEvent) {
        self.inner.breath(breath);
    }
    fn existing_breath(&mut self, start_s: f64, end_s: f64) {
        self.inner.existing_breath(start_s, end_s);
    }
}

/// MIDI CC: the [`CcEncoder`]'s messages for each frame (only changed values), each handed to
/// `send` with the frame's position. Never allocates.
pub struct CcSink<'a, F: FnMut(u64, CcMessage)> {
    encoder: &'a mut CcEncoder,
    send: F,
}

impl<'a, F: FnMut(u64, CcMessage)> CcSink<'a, F> {
    /// Encodes with `encoder` (which remembers what was sent) and hands messages to `send`.
    pub fn new(encoder: &'a mut CcEncoder, send: F) -> Self {
        Self { encoder, send }
    }
}

impl<F: FnMut(u64, CcMessage)> FrameSink for CcSink<'_, F> {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        let send = &mut self.send;
        self.encoder.encode(frame, |m| send(at, m));
    }
}

/// OSC: one bundle per frame in `format`, written into the sink's own fixed buffer and handed
/// to `send` with the frame; the time tag comes from `time_tag(frame)`. A frame that does not
/// encode (it cannot: every bundle fits [`MAX_FRAME_PACKET_BYTES`]) is counted in
/// [`OscSink::failed`]. Never allocates.
pub struct OscSink<T: FnMut(&ControlFrame) -> TimeTag, F: FnMut(&ControlFrame, &[u8])> {
    format: OscFormat,
    buf: [u8; MAX_FRAME_PACKET_BYTES],
    time_tag: T,
    send: F,
    failed: u64,
}

impl<T: FnMut(&ControlFrame) -> TimeTag, F: FnMut(&ControlFrame, &[u8])> OscSink<T, F> {
    /// Bundles in `format` (VMC with the default rig), tagged by `time_tag`, given to `send`.
    pub fn new(format: OscFormat, time_tag: T, send: F) -> Self {
        Self {
            format,
            buf: [0; MAX_FRAME_PACKET_BYTES],
            time_tag,
            send,
            failed: 0,
        }
    }

    /// Changes the address space for the next frames.
    pub fn set_format(&mut self, format: OscFormat) {
        self.format = format;
    }

    /// Frames that could not be encoded.
    pub fn failed(&self) -> u64 {
        self.failed
    }

    fn encode(&mut self, frame: &ControlFrame) -> Result<usize, OscError> {
        let tag = (self.time_tag)(frame);
        encode_frame(self.format, frame, tag, &mut self.buf)
    }
}

impl<T: FnMut(&ControlFrame) -> TimeTag, F: FnMut(&ControlFrame, &[u8])> FrameSink
    for OscSink<T, F>
{
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        match self.encode(frame) {
            Ok(n) => (self.send)(frame, &self.buf[..n]),
            Err(_) => self.failed += 1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::BreathKind;
    use crate::encode::midi_cc::{CcMap, CcSignal};
    use pneuma_testkit::osc::{decode, OscType};

    #[test]
    fn resampled_frames_are_the_frames_or_glide_between_them() {
        // 120 Hz frames over 1 s (121 frames, 0 to 1.0 s) whose head yaw is the frame index in
        // degrees, at 24 fps: 25 instants, every fifth frame itself; at 50 and 360 fps the
        // instants between frames at the yaw between theirs (2.4° and 1/3° an instant), the
        // rest of each the later frame's.
        let frames = |rate_hz: f64| {
            let mut r = Resample::new(
                Collect::default(),
                rate_hz,
                Resample::<Collect>::count(121, 120.0, rate_hz),
            );
            for i in 0..121u64 {
                let mut f = ControlFrame {
                    index: i,
                    time_s: i as f64 / 120.0,
                    ..Default::default()
                };
                f.head.yaw_deg = i as f32;
                r.frame(&f, i);
            }
            r.into_inner().frames
        };
        assert_eq!(Resample::<Collect>::count(121, 120.0, 24.0), 25);
        let at_24: Vec<u64> = frames(24.0).iter().map(|(f, _)| f.index).collect();
        assert_eq!(at_24, (0..=120).step_by(5).collect::<Vec<u64>>());
        assert!(frames(24.0)
            .iter()
            .all(|(f, _)| f.head.yaw_deg == f.index as f32));
        for (rate, per_instant) in [(50.0, 2.4f32), (360.0, 1.0 / 3.0)] {
            let got = frames(rate);
            assert_eq!(
                got.len() as u64,
                Resample::<Collect>::count(121, 120.0, rate)
            );
            for (k, (f, _)) in got.iter().enumerate() {
                let want = k as f32 * per_instant;
                assert!(
                    (f.head.yaw_deg - want).abs() < 1e-3,
                    "{rate} fps, instant {k}"
                );
                // The later frame's index: the frame at or after the instant.
                assert_eq!(
                    f.index,
                    (want - 1e-3).ceil().max(0.0) as u64,
                    "{rate} fps, {k}"
                );
            }
        }
        assert_eq!(Resample::<Collect>::count(0, 120.0, 24.0), 0);
    }

    #[test]
    fn an_unlimited_resample_ends_where_the_count_does() {
        // 1000 fps from 120 Hz frames: no instant after the last frame (1.0 s) goes out, so
        // a stream whose length is known only at its end needs no limit to match the count.
        let mut open = Resample::new(Collect::default(), 1000.0, u64::MAX);
        let mut counted = Resample::new(
            Collect::default(),
            1000.0,
            Resample::<Collect>::count(121, 120.0, 1000.0),
        );
        for i in 0..121u64 {
            let f = ControlFrame {
                index: i,
                time_s: i as f64 / 120.0,
                ..Default::default()
            };
            open.frame(&f, i);
            counted.frame(&f, i);
        }
        let (open, counted) = (open.into_inner().frames, counted.into_inner().frames);
        assert_eq!(open.len(), 1001);
        assert_eq!(open, counted);
    }

    fn frame(index: u64) -> ControlFrame {
        ControlFrame {
            index,
            time_s: index as f64 / 100.0,
            f0_hz: 100.0 + index as f32,
            voiced: true,
            rms_db: -20.0 - index as f32,
            ..Default::default()
        }
    }

    fn breath(start_s: f64) -> BreathEvent {
        BreathEvent {
            start_s,
            end_s: start_s + 0.3,
            kind: BreathKind::Mouth,
            peak_db: -30.0,
        }
    }

    /// Drives `sink` like an engine would: frames 0..n at positions 10·i, a breath after every
    /// fourth frame, an existing breath after frame 5.
    fn drive(sink: &mut impl FrameSink, n: u64) {
        for i in 0..n {
            sink.frame(&frame(i), 10 * i);
            if i % 4 == 3 {
                sink.breath(&breath(i as f64));
            }
            if i == 5 {
                sink.existing_breath(5.0, 5.5);
            }
        }
    }

    #[test]
    fn every_sink_of_a_tuple_gets_every_frame_and_breath_once_in_order() {
        let mut sinks = (
            Collect::default(),
            Some(Collect::default()),
            None::<Collect>,
        );
        drive(&mut sinks, 10);
        for c in [&sinks.0, sinks.1.as_ref().unwrap()] {
            let indices: Vec<u64> = c.frames.iter().map(|(f, _)| f.index).collect();
            assert_eq!(indices, (0..10).collect::<Vec<_>>());
            let at: Vec<u64> = c.frames.iter().map(|&(_, at)| at).collect();
            assert_eq!(at, (0..10).map(|i| 10 * i).collect::<Vec<_>>());
            let starts: Vec<f64> = c.breaths.iter().map(|b| b.start_s).collect();
            assert_eq!(starts, [3.0, 7.0]);
            assert_eq!(c.existing, [(5.0, 5.5)]);
        }
    }

    #[test]
    fn a_text_sink_writes_the_header_and_one_line_per_frame() {
        let mut sink = TextSink::controls_csv(Vec::new()).unwrap();
        drive(&mut sink, 5);
        let text = String::from_utf8(sink.into_inner().unwrap()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], crate::encode::controls_csv::HEADER);
        // One row per frame, in order: the time column is index / 100.
        let times: Vec<&str> = lines[1..]
            .iter()
            .map(|l| l.split(',').next().unwrap())
            .collect();
        assert_eq!(
            times,
            ["0.000000", "0.010000", "0.020000", "0.030000", "0.040000"]
        );
    }

    /// A writer that fails after `ok` writes.
    struct Failing {
        ok: usize,
        writes: usize,
    }
    impl Write for Failing {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.writes += 1;
            if self.writes > self.ok {
                return Err(std::io::Error::other("disk full"));
            }
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_text_sink_keeps_the_first_write_error_and_stops_writing() {
        let mut sink = TextSink::controls_csv(Failing { ok: 3, writes: 0 }).unwrap();
        drive(&mut sink, 6);
        let e = sink.check().unwrap_err();
        assert_eq!(e.to_string(), "disk full");
        // Header + 2 rows written, the 3rd row failed, nothing tried after it.
        assert_eq!(sink.out.writes, 4);
        // The error stays: checking again, or writing on, never continues the file.
        drive(&mut sink, 2);
        assert!(sink.check().is_err());
        assert_eq!(sink.out.writes, 4);
        assert!(sink
            .into_inner()
            .is_err_and(|e| e.to_string() == "disk full"));
    }

    #[test]
    fn a_cc_sink_sends_changes_with_the_frame_position() {
        let mut encoder = CcEncoder::new(CcMap::default()).unwrap();
        let mut sent = Vec::new();
        let mut sink = CcSink::new(&mut encoder, |at, m: CcMessage| sent.push((at, m)));
        drive(&mut sink, 3);
        // The first frame sends every mapped controller; later frames only what changed
        // (loudness, which falls by 1 dB per frame).
        let loudness = CcSignal::DEFAULT_CONTROLLERS[CcSignal::Loudness.index()];
        let first = sent.iter().filter(|(at, _)| *at == 0).count();
        assert_eq!(first, crate::encode::midi_cc::SIGNAL_COUNT);
        let later: Vec<u64> = sent
            .iter()
            .filter(|(_, m)| m.controller == loudness)
            .map(|&(at, _)| at)
            .collect();
        assert_eq!(later, [0, 10, 20]);
    }

    #[test]
    fn an_osc_sink_sends_one_decodable_bundle_per_frame() {
        let mut packets = Vec::new();
        {
            let mut sink = OscSink::new(
                OscFormat::Pneuma,
                |f: &ControlFrame| TimeTag::from_unix_seconds(f.time_s),
                |f: &ControlFrame, bytes: &[u8]| packets.push((f.index, bytes.to_vec())),
            );
            drive(&mut sink, 4);
            assert_eq!(sink.failed(), 0);
        }
        let indices: Vec<u64> = packets.iter().map(|(i, _)| *i).collect();
        assert_eq!(indices, [0, 1, 2, 3]);
        for (i, bytes) in &packets {
            let messages = decode(bytes).unwrap();
            assert_eq!(messages[0].address, crate::encode::osc::address::FRAME);
            assert_eq!(messages[0].args[0], OscType::Int(*i as i32));
        }
    }
}
