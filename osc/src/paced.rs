//! The CLI's OSC sender: a rendered stream's control frames sent as the plugin sends them (the
//! same bundles, through core's encoders), each when its time comes, in real time or at a
//! multiple of it ([`Speed`]). It runs on the render's own thread: sending a frame waits
//! (sleeps) until the frame is due, so a render with OSC takes the audio's duration divided by
//! the speed. [`Pacer`] holds the schedule (pure arithmetic, tested without a clock);
//! [`PacedSender`] sleeps, encodes and sends.
//!
//! When the stream ends, however it ends (the file's end, an error, Ctrl-C: [`PacedSender::rest`],
//! also on drop), the body eases to the rest pose ([`ControlFrame::rest`]: silent, head
//! straight, breathing at rest) over [`REST_EASE_S`], a frame every period after the last
//! ([`ControlFrame::toward_rest`] on a raised cosine), the last of them the rest pose itself: an
//! avatar is neither left frozen mid-turn with its mouth open nor snapped straight in one
//! frame (7.7° in 1/120 s at the end of a clip that ended mid-turn). The voice is silent from
//! the first of them. The ease waits for its frames' times [`REST_MAX_WAIT_S`] at most in all,
//! each frame its share (a very slow speed does not hold an error or Ctrl-C back: its ease is
//! shortened evenly); at [`Speed::Max`] it waits [`REST_DRAIN_S`] first, so a receiver that fell
//! behind has read the frames before it, and sends the ease's frames a stream period apart (in
//! real time: a burst would reach a receiver as one jump).
//!
//! Time tags: the first frame anchors the stream to the wall clock; a frame's tag is the
//! instant it is due, `anchor + (time_s - first time_s) / speed`. At [`Speed::Max`] frames
//! leave as fast as the socket takes them and are tagged with the audio's time
//! (`anchor + time_s - first time_s`), as the plugin tags an offline bounce.

use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use pneuma_core::encode::osc::{encode_frame, OscFormat, TimeTag, MAX_FRAME_PACKET_BYTES};
use pneuma_core::encode::sink::FrameSink;
use pneuma_core::ControlFrame;

use crate::target::{connect, now_unix_s, resolve, send, socket_for, OscError};

/// Longest wait for the rest pose's time, seconds.
pub const REST_MAX_WAIT_S: f64 = 0.5;
/// At [`Speed::Max`], the wait before the rest pose, seconds.
pub const REST_DRAIN_S: f64 = 0.25;
/// How long the body takes to ease to the rest pose after the last frame, seconds of the
/// stream (a quarter second: a head's return after speech, quicker than a settle, and short
/// enough that Ctrl-C still ends at once).
pub const REST_EASE_S: f64 = 0.25;
/// The most frames an ease to rest takes (the ease at 240 frames per second, the highest frame
/// rate).
const REST_EASE_MAX_STEPS: u64 = 60;

/// How many frames the ease to rest takes at a frame period of `period_s` seconds: one per
/// period over [`REST_EASE_S`], at least 1 and at most [`REST_EASE_MAX_STEPS`].
pub fn rest_ease_steps(period_s: f64) -> u64 {
    ((REST_EASE_S / period_s).round() as u64).clamp(1, REST_EASE_MAX_STEPS)
}

/// How fast frames are sent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Speed {
    /// This many seconds of audio per second (1: real time). Positive and finite.
    Times(f64),
    /// As fast as the socket takes them.
    Max,
}

impl Speed {
    /// Parses `1`, `4`, `0.5` or `max`; the error says what to give.
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        if t.eq_ignore_ascii_case("max") {
            return Ok(Self::Max);
        }
        match t.parse::<f64>() {
            Ok(k) if k.is_finite() && k > 0.0 => Ok(Self::Times(k)),
            _ => Err(format!(
                "`{text}` is not a speed: give a multiple of real time above 0 (1 real time, \
                 4 four times as fast) or max"
            )),
        }
    }
}

impl std::fmt::Display for Speed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Times(k) if *k == 1.0 => write!(f, "real time"),
            Self::Times(k) => write!(f, "{k}x real time"),
            Self::Max => write!(f, "as fast as possible"),
        }
    }
}

/// When each frame is due and its time tag, from the first frame's anchor.
#[derive(Debug, Clone)]
pub struct Pacer {
    speed: Speed,
    /// (clock seconds, Unix seconds, frame time) of the first frame.
    anchor: Option<(f64, f64, f64)>,
}

impl Pacer {
    /// A schedule at `speed`.
    pub fn new(speed: Speed) -> Self {
        Self {
            speed,
            anchor: None,
        }
    }

    /// For a frame at `time_s` seen at clock time `now_s` (Unix time `unix_s`): the clock
    /// time it is due (never before `now_s`) and its time tag in Unix seconds.
    pub fn schedule(&mut self, time_s: f64, now_s: f64, unix_s: f64) -> (f64, f64) {
        let (clock0, unix0, time0) = *self.anchor.get_or_insert((now_s, unix_s, time_s));
        let audio_s = (time_s - time0).max(0.0);
        match self.speed {
            Speed::Times(k) => {
                let offset_s = audio_s / k;
                ((clock0 + offset_s).max(now_s), unix0 + offset_s)
            }
            Speed::Max => (now_s, unix0 + audio_s),
        }
    }
}

/// Where the sender's time comes from: the wall clock, or a test's.
pub trait Clock {
    /// Seconds on a monotonic clock.
    fn now_s(&self) -> f64;
    /// Seconds since the Unix epoch (for time tags).
    fn unix_s(&self) -> f64;
    /// Waits `seconds`.
    fn sleep_s(&mut self, seconds: f64);
}

/// The machine's clocks.
#[derive(Debug, Clone, Copy)]
pub struct WallClock(Instant);

impl Default for WallClock {
    fn default() -> Self {
        Self(Instant::now())
    }
}

impl Clock for WallClock {
    fn now_s(&self) -> f64 {
        self.0.elapsed().as_secs_f64()
    }
    fn unix_s(&self) -> f64 {
        now_unix_s()
    }
    fn sleep_s(&mut self, seconds: f64) {
        if seconds > 0.0 {
            std::thread::sleep(Duration::from_secs_f64(seconds));
        }
    }
}

/// Why the sender could not start.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum OpenError {
    /// The host is not a numeric address or `localhost`.
    NotAnAddress(String),
    /// No UDP socket could be opened.
    NoSocket,
}

impl std::fmt::Display for OpenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotAnAddress(host) => write!(
                f,
                "`{host}` is not an IP address (host names are not looked up, as in the plugin \
                 and pneuma-app): give a numeric address such as 127.0.0.1 or 192.168.1.20, \
                 or localhost"
            ),
            Self::NoSocket => write!(f, "{}", OscError::NoSocket.text()),
        }
    }
}

impl std::error::Error for OpenError {}

/// What a [`PacedSender`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PacedStats {
    /// Bundles handed to the OS.
    pub sent: u64,
    /// Frames not sent (encoding or send errors).
    pub failed: u64,
    /// Why the last failed frame was not sent.
    pub last_error: Option<OscError>,
    /// The rest pose went out after the last frame ([`PacedSender::rest`]).
    pub rested: bool,
}

/// Sends each frame as one bundle in its format when it is due (see the module docs).
pub struct PacedSender<C: Clock = WallClock> {
    addr: SocketAddr,
    socket: UdpSocket,
    /// The socket is connected to `addr` ([`connect`]).
    connected: bool,
    format: OscFormat,
    pacer: Pacer,
    clock: C,
    buf: [u8; MAX_FRAME_PACKET_BYTES],
    stats: PacedStats,
    /// The last frame sent (`period_s` holds the interval before it).
    last: Option<ControlFrame>,
    period_s: f64,
    /// The rest pose was tried after the last frame.
    rested: bool,
}

impl PacedSender<WallClock> {
    /// A sender to `host:port` in `format` at `speed`, on the wall clock.
    pub fn open(host: &str, port: u16, format: OscFormat, speed: Speed) -> Result<Self, OpenError> {
        Self::with_clock(host, port, format, speed, WallClock::default())
    }
}

impl<C: Clock> PacedSender<C> {
    /// A sender on `clock`.
    pub fn with_clock(
        host: &str,
        port: u16,
        format: OscFormat,
        speed: Speed,
        clock: C,
    ) -> Result<Self, OpenError> {
        let addr = resolve(host, port).ok_or_else(|| OpenError::NotAnAddress(host.to_owned()))?;
        let socket = socket_for(&addr).ok_or(OpenError::NoSocket)?;
        // A render's thread may wait for the socket (sending is all it does meanwhile).
        socket
            .set_nonblocking(false)
            .map_err(|_| OpenError::NoSocket)?;
        // Connected, a render hears that nothing listens on the port; a target it cannot
        // connect to (no route, a broadcast address) is still sent to, and its errors counted.
        let connected = connect(&socket, addr);
        Ok(Self {
            addr,
            socket,
            connected,
            format,
            pacer: Pacer::new(speed),
            clock,
            buf: [0; MAX_FRAME_PACKET_BYTES],
            stats: PacedStats::default(),
            last: None,
            period_s: 0.0,
            rested: false,
        })
    }

    /// The target.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// What was sent so far.
    pub fn stats(&self) -> PacedStats {
        self.stats
    }

    /// The clock (a test's, to read what it saw).
    pub fn clock(&self) -> &C {
        &self.clock
    }

    fn fail(&mut self, e: OscError) {
        self.stats.failed += 1;
        self.stats.last_error = Some(e);
    }

    /// Eases the body to the rest pose after the last frame (see the module docs), once after
    /// the last frame (nothing before any frame); the frames are a period apart (the default
    /// frame rate's period after a single frame). Also done on drop.
    pub fn rest(&mut self) {
        let (Some(last), false) = (self.last, self.rested) else {
            return;
        };
        self.rested = true;
        let period_s = if self.period_s > 0.0 {
            self.period_s
        } else {
            1.0 / f64::from(pneuma_core::settings::analysis::FRAME_RATE_HZ.default)
        };
        if self.pacer.speed == Speed::Max {
            self.clock.sleep_s(REST_DRAIN_S);
        }
        let steps = rest_ease_steps(period_s);
        // Each frame of the ease waits its share of the half second at most, so a very slow
        // speed shortens the whole ease evenly; at `max` the frames are due at once, and are
        // paced a stream period apart (the ease in real time, a receiver sees it as one).
        let share_s = REST_MAX_WAIT_S / steps as f64;
        for k in 1..=steps {
            let toward = 0.5 - 0.5 * (std::f64::consts::PI * k as f64 / steps as f64).cos();
            let frame = last.toward_rest(
                last.index + k,
                last.time_s + k as f64 * period_s,
                toward as f32,
            );
            if self.pacer.speed == Speed::Max && k > 1 {
                self.clock.sleep_s(period_s.min(share_s));
            }
            self.stats.rested = self.send_when_due(&frame, share_s);
        }
    }

    /// Sends `frame` when it is due, waiting `max_wait_s` at most; whether it was sent.
    fn send_when_due(&mut self, frame: &ControlFrame, max_wait_s: f64) -> bool {
        let now_s = self.clock.now_s();
        let (due_s, tag_s) = self
            .pacer
            .schedule(frame.time_s, now_s, self.clock.unix_s());
        self.clock.sleep_s((due_s - now_s).min(max_wait_s));
        let tag = TimeTag::from_unix_seconds(tag_s);
        match encode_frame(self.format, frame, tag, &mut self.buf) {
            Ok(n) => match send(
                Some(self.addr),
                Some(&self.socket),
                self.connected,
                &self.buf[..n],
            ) {
                Ok(()) => {
                    self.stats.sent += 1;
                    true
                }
                Err(e) => {
                    self.fail(e);
                    false
                }
            },
            Err(_) => {
                self.fail(OscError::Encoding);
                false
            }
        }
    }
}

impl<C: Clock> Drop for PacedSender<C> {
    fn drop(&mut self) {
        self.rest();
    }
}

impl<C: Clock> FrameSink for PacedSender<C> {
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        if let Some(last) = self.last {
            if frame.time_s > last.time_s {
                self.period_s = frame.time_s - last.time_s;
            }
        }
        self.last = Some(*frame);
        self.rested = false;
        self.stats.rested = false;
        self.send_when_due(frame, f64::INFINITY);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_frame;
    use pneuma_testkit::osc::decode;

    /// A clock that only moves when slept on; records every wait.
    #[derive(Default)]
    struct TestClock {
        now_s: f64,
        waits_s: Vec<f64>,
    }

    impl Clock for TestClock {
        fn now_s(&self) -> f64 {
            self.now_s
        }
        fn unix_s(&self) -> f64 {
            1_000.0 + self.now_s
        }
        fn sleep_s(&mut self, seconds: f64) {
            self.waits_s.push(seconds);
            self.now_s += seconds.max(0.0);
        }
    }

    /// A sender in the pneuma format to `host:port` at `speed`, on a [`TestClock`].
    fn test_sender(host: &str, port: u16, speed: Speed) -> PacedSender<TestClock> {
        PacedSender::with_clock(host, port, OscFormat::Pneuma, speed, TestClock::default()).unwrap()
    }

    #[test]
    fn speeds_parse_and_refuse_with_advice() {
        assert_eq!(Speed::parse("4"), Ok(Speed::Times(4.0)));
        assert_eq!(Speed::parse(" MAX "), Ok(Speed::Max));
        assert_eq!(Speed::parse("0.5"), Ok(Speed::Times(0.5)));
        for bad in ["0", "-2", "inf", "fast", ""] {
            let e = Speed::parse(bad).unwrap_err();
            assert!(e.contains("or max"), "{bad}: {e}");
        }
    }

    #[test]
    fn a_multiple_of_real_time_is_due_at_time_over_the_multiple() {
        let mut p = Pacer::new(Speed::Times(4.0));
        // First frame at 10 s of audio, seen at clock 2 s: the anchor.
        assert_eq!(p.schedule(10.0, 2.0, 100.0), (2.0, 100.0));
        // One second of audio later: due 0.25 s after the anchor, tagged the same.
        assert_eq!(p.schedule(11.0, 2.1, 100.1), (2.25, 100.25));
        // Seen late: due now, still tagged by the schedule.
        assert_eq!(p.schedule(12.0, 3.0, 101.0), (3.0, 100.5));
        let mut max = Pacer::new(Speed::Max);
        assert_eq!(max.schedule(0.0, 5.0, 100.0), (5.0, 100.0));
        assert_eq!(max.schedule(2.0, 5.01, 100.01), (5.01, 102.0), "audio time");
    }

    #[test]
    fn frames_are_sent_at_the_chosen_speed_with_tags_a_period_over_the_speed_apart() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let port = rx.local_addr().unwrap().port();
        let mut tx = test_sender("localhost", port, Speed::Times(4.0));
        for i in 0..24 {
            tx.frame(&test_frame(i), 0);
        }
        // 23 periods of 1/120 s at 4x: the clock waited 23/480 s in all, one period each.
        let clock = tx.clock();
        assert!((clock.now_s - 23.0 / 480.0).abs() < 1e-9, "{}", clock.now_s);
        for w in &clock.waits_s[1..] {
            assert!((w - 1.0 / 480.0).abs() < 1e-9, "{w}");
        }
        assert_eq!(tx.stats().sent, 24);
        let mut buf = [0u8; 2048];
        let mut tags = Vec::new();
        for i in 0..24 {
            let n = rx.recv(&mut buf).expect("a bundle");
            let msgs = decode(&buf[..n]).unwrap();
            assert_eq!(
                msgs[1].args[0],
                pneuma_testkit::osc::OscType::Float(100.0 + i as f32)
            );
            tags.push(TimeTag(msgs[0].time_tag.unwrap()).to_unix_seconds());
        }
        for w in tags.windows(2) {
            let step_s = w[1] - w[0];
            assert!((step_s - 1.0 / 480.0).abs() < 1e-6, "tag step {step_s}");
        }
    }

    #[test]
    fn the_wall_clock_paces_no_faster_than_asked() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        let port = rx.local_addr().unwrap().port();
        let mut tx =
            PacedSender::open("127.0.0.1", port, OscFormat::Vmc, Speed::Times(4.0)).unwrap();
        let start = Instant::now();
        for i in 0..25 {
            tx.frame(&test_frame(i), 0);
        }
        // A lower bound only (a busy machine may be slower, never faster): 24 periods at 4x.
        assert!(start.elapsed().as_secs_f64() >= 24.0 / 480.0 - 1e-3);
        assert_eq!(tx.stats().sent, 25);
    }

    #[test]
    fn a_host_name_is_refused_with_what_to_give() {
        let e = PacedSender::open("my-avatar-pc", 39539, OscFormat::Vmc, Speed::Max)
            .err()
            .expect("refused");
        assert_eq!(e, OpenError::NotAnAddress("my-avatar-pc".into()));
        let text = e.to_string();
        assert!(
            text.contains("numeric address") && text.contains("localhost"),
            "{text}"
        );
    }

    #[test]
    fn a_stream_eases_to_the_rest_pose_after_its_last_frame_however_it_ends() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_millis(300)))
            .unwrap();
        let port = rx.local_addr().unwrap().port();
        let turned = |i: u64| {
            let mut f = test_frame(i);
            f.head.yaw_deg = 5.0;
            f.head.pitch_deg = -3.0;
            f.breathing.lung = 0.6;
            f
        };
        let period_s = 1.0 / 120.0;
        let steps = rest_ease_steps(period_s) as usize;
        let rest = ControlFrame::rest(2 + steps as u64, (2 + steps) as f64 * period_s);
        let messages = |frame: &ControlFrame| {
            let mut buf = [0u8; MAX_FRAME_PACKET_BYTES];
            let n = encode_frame(OscFormat::Pneuma, frame, TimeTag(0), &mut buf).unwrap();
            decode(&buf[..n]).unwrap()
        };
        let mut buf = [0u8; 2048];
        let mut received = |n: usize| -> Vec<Vec<pneuma_testkit::osc::Message>> {
            (0..n)
                .map_while(|_| rx.recv(&mut buf).ok().map(|k| decode(&buf[..k]).unwrap()))
                .collect()
        };
        // Dropped after three frames, as on an error or Ctrl-C: the ease, ending in the rest
        // pose.
        {
            let mut tx = test_sender("127.0.0.1", port, Speed::Times(4.0));
            for i in 0..3 {
                tx.frame(&turned(i), 0);
            }
        }
        let got = received(3 + steps + 2);
        assert_eq!(got.len(), 3 + steps, "three frames and the ease to rest");
        let strip = |m: &[pneuma_testkit::osc::Message]| {
            m.iter()
                .map(|m| (m.address.clone(), format!("{:?}", m.args)))
                .collect::<Vec<_>>()
        };
        let arg = |m: &[pneuma_testkit::osc::Message], address: &str, k: usize| -> f32 {
            let found = m.iter().find(|m| m.address == address).expect(address);
            match found.args[k] {
                pneuma_testkit::osc::OscType::Float(v) => v,
                ref other => panic!("{address}: {other:?}"),
            }
        };
        assert_eq!(strip(&got[2 + steps]), strip(&messages(&rest)));
        // The head turns back a little each frame, never jumping, and the lung empties the
        // same way; the voice is silent from the first frame of the ease.
        let yaw: Vec<f32> = got[2..].iter().map(|m| arg(m, "/pneuma/head", 1)).collect();
        let lung: Vec<f32> = got[2..]
            .iter()
            .map(|m| arg(m, "/pneuma/breath/lung", 0))
            .collect();
        assert_eq!((yaw[0], *yaw.last().unwrap()), (5.0, 0.0));
        let largest_step = yaw.windows(2).map(|w| w[0] - w[1]).fold(0.0f32, f32::max);
        assert!(
            yaw.windows(2).all(|w| w[1] <= w[0]) && largest_step < 5.0 * 2.0 / steps as f32,
            "yaw back to rest in even steps: {yaw:?}"
        );
        assert!(lung.windows(2).all(|w| w[1] <= w[0]), "{lung:?}");
        assert!(
            got[3..]
                .iter()
                .all(|m| arg(m, "/pneuma/rms", 0) == rest.rms_db),
            "the voice is silent through the ease"
        );
        // Rested at the end, then dropped: the ease goes out once; before any frame, never.
        let mut tx = test_sender("127.0.0.1", port, Speed::Max);
        tx.rest();
        tx.frame(&turned(0), 0);
        tx.rest();
        drop(tx);
        assert_eq!(
            received(2 + steps).len(),
            1 + steps,
            "one frame, one ease to rest"
        );
    }

    #[test]
    fn the_rest_pose_waits_half_a_second_at_most_and_lets_a_receiver_catch_up_at_max() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        let port = rx.local_addr().unwrap().port();
        let open = |speed| test_sender("127.0.0.1", port, speed);
        // A thousandth of real time: the next frame would be due 8.3 s later.
        let mut slow = open(Speed::Times(0.001));
        slow.frame(&test_frame(0), 0);
        slow.frame(&test_frame(1), 0);
        let before = slow.clock().waits_s.len();
        assert!(!slow.stats().rested);
        slow.rest();
        let waits = &slow.clock().waits_s[before..];
        let share_s = REST_MAX_WAIT_S / waits.len() as f64;
        assert!(
            waits.iter().all(|w| (w - share_s).abs() < 1e-9),
            "every frame of the ease waits its share of half a second: {waits:?}"
        );
        assert!(slow.stats().rested, "{:?}", slow.stats());
        // As fast as possible: the frames leave at once, the rest pose after the drain.
        let mut max = open(Speed::Max);
        max.frame(&test_frame(0), 0);
        let before = max.clock().waits_s.len();
        max.rest();
        let waits = &max.clock().waits_s[before..];
        assert_eq!(waits[0], REST_DRAIN_S);
        // The ease's frames leave a stream period apart, not in one burst.
        let period_s = 1.0 / f64::from(pneuma_core::settings::analysis::FRAME_RATE_HZ.default);
        let paced = waits
            .iter()
            .filter(|&&w| (w - period_s).abs() < 1e-12)
            .count();
        assert_eq!(paced as u64, rest_ease_steps(period_s) - 1, "{waits:?}");
        assert!(max.stats().rested);
    }
}
