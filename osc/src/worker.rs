//! The plugin's OSC sender: the audio thread hands control frames to a worker thread through a
//! preallocated lock-free `rtrb` queue; the worker encodes them (pneuma or VMC bundles with NTP
//! time tags) and sends them over UDP.
//!
//! - The audio side ([`OscFeed::push`]) never blocks, locks or allocates: if the queue is full
//!   (the worker has not run for `QUEUE_FRAMES` frames) the frame is dropped and counted.
//! - The worker keeps only fresh frames: when more than [`MAX_BACKLOG_FRAMES`] wait, it drops the
//!   oldest ones (an avatar wants the newest pose, not a late replay) and counts them. So a slow
//!   network or a stalled worker drops the oldest frames; only a worker that does not run at all
//!   for a whole queue can cost the newest.
//! - The target (host, port) and format are read by the worker from the shared settings on every
//!   wake-up, so they can change while playing. The host must be a numeric IP address or
//!   `localhost`: names are never looked up (DNS can block for minutes, also when the plugin
//!   unloads and joins the worker). A host that is not an address, or an unreachable one, only
//!   counts send failures and is retried every [`RETRY_INTERVAL`]. Nothing the network does
//!   reaches the audio thread or holds up unloading.
//! - Time tags: the first frame after a start or reset (the frame index goes back) anchors the
//!   frame clock to the wall clock; a frame's tag is `anchor + time_s`. When the tags fall more
//!   than 0.5 s behind the wall clock (playback paused, a stall), or the frame clock jumps
//!   ahead of the last frame's by more than that (the stream again after the bypass's rest
//!   frame, whose clock is 0), they are re-anchored to now, so tags always increase;
//!   faster-than-real-time processing (offline bounce) gives tags ahead of the wall clock, as
//!   the audio time says.
//! - When the worker stops (the plugin unloads, the app quits), one frame of the rest pose
//!   ([`ControlFrame::rest`]) follows the last frame sent, so the avatar is not left mid-turn.

use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicU8, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use pneuma_core::encode::osc::{OscFormat, TimeTag};
use pneuma_core::encode::sink::{FrameSink, OscSink};
use pneuma_core::ControlFrame;

use crate::target::{connect, now_unix_s, resolve, send, socket_for, OscError};

/// Queue capacity in frames (about 4 s at 120 Hz).
pub const QUEUE_FRAMES: usize = 512;
/// Most frames the worker lets wait before dropping the oldest (about 0.1 s at 120 Hz).
pub const MAX_BACKLOG_FRAMES: usize = 12;
/// How long the worker sleeps between polls of the queue.
pub const POLL_INTERVAL: Duration = Duration::from_millis(2);
/// How often the worker looks for frames after 100 ms without any.
pub const IDLE_POLL_INTERVAL: Duration = Duration::from_millis(20);
/// How often an unresolvable target is retried.
pub const RETRY_INTERVAL: Duration = Duration::from_secs(1);

/// Where and how to send; read by the worker on every wake-up.
pub trait OscSettings: Send + Sync + 'static {
    /// Host name or address, and port.
    fn target(&self) -> (String, u16);
    /// Address space.
    fn format(&self) -> OscFormat;
    /// Whether OSC is sent at all (the rest pose a stopping worker sends goes out only then).
    fn enabled(&self) -> bool {
        true
    }
}

/// Counters shared by the audio side and the worker (all monotonic).
#[derive(Debug, Default)]
pub struct OscStats {
    /// Frames dropped because the queue was full (audio side).
    pub dropped_full: AtomicU64,
    /// Old frames the worker skipped to catch up.
    pub dropped_stale: AtomicU64,
    /// Bundles handed to the OS.
    pub sent: AtomicU64,
    /// Frames not sent: unresolvable target, encoding or send error.
    pub failed: AtomicU64,
    /// Why the last frame that failed was not sent ([`OscError`] as its code; 0: none yet).
    pub last_error: AtomicU8,
}

/// The audio-thread end: push frames, never blocks.
pub struct OscFeed {
    producer: rtrb::Producer<ControlFrame>,
    stats: Arc<OscStats>,
}

impl OscFeed {
    /// Hands a frame to the worker; if the queue is full the frame is dropped and counted.
    /// Wait-free, allocation-free.
    pub fn push(&mut self, frame: &ControlFrame) {
        if self.producer.push(*frame).is_err() {
            self.stats.dropped_full.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// The OSC output as one of the engine's sinks: every frame is pushed to the worker, which
/// encodes and sends it off the audio thread.
impl FrameSink for OscFeed {
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        self.push(frame);
    }
}

/// The worker thread; stops and joins on drop.
pub struct OscWorker {
    stop: Arc<AtomicBool>,
    handle: Option<JoinHandle<()>>,
}

impl Drop for OscWorker {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

/// Starts a worker; returns the audio-side feed, the worker handle and the counters.
pub fn start<S: OscSettings>(
    settings: Arc<S>,
) -> std::io::Result<(OscFeed, OscWorker, Arc<OscStats>)> {
    let (producer, consumer) = rtrb::RingBuffer::new(QUEUE_FRAMES);
    let stats = Arc::new(OscStats::default());
    let stop = Arc::new(AtomicBool::new(false));
    let handle = std::thread::Builder::new()
        .name("pneuma-osc".into())
        .spawn({
            let stats = stats.clone();
            let stop = stop.clone();
            move || run(consumer, settings, stats, stop)
        })?;
    Ok((
        OscFeed {
            producer,
            stats: stats.clone(),
        },
        OscWorker {
            stop,
            handle: Some(handle),
        },
        stats,
    ))
}

/// The worker's resolved target.
struct Target {
    key: (String, u16),
    addr: Option<SocketAddr>,
    resolved_at: Instant,
}

fn run<S: OscSettings>(
    mut consumer: rtrb::Consumer<ControlFrame>,
    settings: Arc<S>,
    stats: Arc<OscStats>,
    stop: Arc<AtomicBool>,
) {
    let mut socket: Option<UdpSocket> = None;
    // The socket is connected to the target ([`connect`]).
    let mut connected = false;
    let mut target: Option<Target> = None;
    let mut anchor: Option<Anchor> = None;
    let mut idle_polls: u32 = 0;
    // The format the last frames went out in (the rest pose takes it).
    let mut last_format: Option<OscFormat> = None;
    while !stop.load(Ordering::Relaxed) {
        let waiting = consumer.slots();
        if waiting == 0 {
            // Idle (not playing, or OSC off): back off to a slow poll after 100 ms.
            idle_polls = idle_polls.saturating_add(1);
            std::thread::sleep(if idle_polls > 50 {
                IDLE_POLL_INTERVAL
            } else {
                POLL_INTERVAL
            });
            continue;
        }
        idle_polls = 0;
        if waiting > MAX_BACKLOG_FRAMES {
            let skip = waiting - MAX_BACKLOG_FRAMES;
            if let Ok(chunk) = consumer.read_chunk(skip) {
                chunk.commit_all();
                stats
                    .dropped_stale
                    .fetch_add(skip as u64, Ordering::Relaxed);
            }
        }
        let key = settings.target();
        let format = settings.format();
        let stale = match &target {
            Some(t) => {
                t.key != key
                    || ((t.addr.is_none() || socket.is_none())
                        && t.resolved_at.elapsed() > RETRY_INTERVAL)
            }
            None => true,
        };
        if stale {
            let addr = resolve(&key.0, key.1);
            if let Some(a) = &addr {
                let family_ok = socket
                    .as_ref()
                    .and_then(|s| s.local_addr().ok())
                    .is_some_and(|l| l.is_ipv4() == a.is_ipv4());
                if !family_ok {
                    socket = socket_for(a);
                }
                // Connected, the socket hears the receiver's host answer that nothing listens
                // on the port (the editor's advice); an unconnected one is never told.
                connected = socket.as_ref().is_some_and(|s| connect(s, *a));
            }
            target = Some(Target {
                key,
                addr,
                resolved_at: Instant::now(),
            });
        }
        let addr = target.as_ref().and_then(|t| t.addr);
        let link = Link {
            addr,
            socket: socket.as_ref(),
            connected,
            stats: &stats,
        };
        send_frames(
            format,
            &mut anchor,
            link,
            std::iter::from_fn(|| consumer.pop().ok()),
        );
        last_format = Some(format);
    }
    // Stopped (the plugin unloads, the app quits): the avatar is not left mid-turn. One frame
    // of the rest pose follows the last frame sent, a frame period later (the default frame
    // rate's), to the target and in the format of the last frames, as `pneuma render --osc`
    // ends; nothing when OSC is off now (another app may drive the avatar).
    if let (Some(a), Some(format), true) = (anchor, last_format, settings.enabled()) {
        let period_s = 1.0 / f64::from(pneuma_core::settings::analysis::FRAME_RATE_HZ.default);
        let link = Link {
            addr: target.as_ref().and_then(|t| t.addr),
            socket: socket.as_ref(),
            connected,
            stats: &stats,
        };
        let rest = ControlFrame::rest(a.index + 1, a.time_s + period_s);
        send_frames(format, &mut anchor, link, std::iter::once(rest));
    }
}

/// Where a frame goes: the target's address, the socket (connected to it or not) and the
/// counters.
#[derive(Clone, Copy)]
struct Link<'a> {
    addr: Option<SocketAddr>,
    socket: Option<&'a UdpSocket>,
    connected: bool,
    stats: &'a OscStats,
}

/// Sends `frames` through core's OSC sink: each is tagged with its time on the stream's clock
/// (`anchor`, updated) and handed, encoded, to the socket; failures are counted.
fn send_frames(
    format: OscFormat,
    anchor: &mut Option<Anchor>,
    link: Link<'_>,
    frames: impl Iterator<Item = ControlFrame>,
) {
    let stats = link.stats;
    let mut sink = OscSink::new(
        format,
        |frame: &ControlFrame| {
            let base = tag_base(*anchor, frame, now_unix_s());
            *anchor = Some(Anchor {
                base_s: base,
                index: frame.index,
                time_s: frame.time_s,
            });
            TimeTag::from_unix_seconds(base + frame.time_s)
        },
        |_: &ControlFrame, packet: &[u8]| {
            match send(link.addr, link.socket, link.connected, packet) {
                Ok(()) => stats.sent.fetch_add(1, Ordering::Relaxed),
                Err(e) => {
                    stats.last_error.store(e as u8, Ordering::Relaxed);
                    stats.failed.fetch_add(1, Ordering::Relaxed)
                }
            };
        },
    );
    for frame in frames {
        sink.frame(&frame, 0);
    }
    let unencoded = sink.failed();
    if unencoded > 0 {
        stats
            .last_error
            .store(OscError::Encoding as u8, Ordering::Relaxed);
        stats.failed.fetch_add(unencoded, Ordering::Relaxed);
    }
}

/// Where the frame clock stands on the wall clock: the unix seconds of frame time 0, and the
/// last frame tagged.
#[derive(Debug, Clone, Copy)]
struct Anchor {
    base_s: f64,
    index: u64,
    time_s: f64,
}

/// The most a tag may fall behind the wall clock, or the frame clock jump between two frames,
/// before the clock is anchored again, seconds.
const REANCHOR_S: f64 = 0.5;

/// The unix seconds of frame time 0 for `frame` at wall-clock time `now_s` (see the module
/// docs): the anchor's while the frames follow on from the last one, else anchored at now.
fn tag_base(anchor: Option<Anchor>, frame: &ControlFrame, now_s: f64) -> f64 {
    match anchor {
        Some(a)
            if frame.index > a.index
                && frame.time_s - a.time_s < REANCHOR_S
                && a.base_s + frame.time_s > now_s - REANCHOR_S =>
        {
            a.base_s
        }
        _ => now_s - frame.time_s,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_frame;

    use pneuma_core::encode::osc::TimeTag;
    use pneuma_testkit::osc::{decode, Message, OscType};
    use std::sync::Mutex;

    struct Settings {
        target: Mutex<(String, u16)>,
        format: Mutex<OscFormat>,
    }

    impl OscSettings for Settings {
        fn target(&self) -> (String, u16) {
            self.target.lock().unwrap().clone()
        }
        fn format(&self) -> OscFormat {
            *self.format.lock().unwrap()
        }
    }

    fn receive(sock: &UdpSocket) -> Vec<Message> {
        let mut buf = [0u8; 2048];
        let n = sock.recv(&mut buf).expect("a packet within the timeout");
        decode(&buf[..n]).unwrap()
    }

    #[test]
    fn tags_follow_the_stream_and_start_again_at_now_after_the_rest_frame() {
        let frame = |index: u64, time_s: f64| ControlFrame {
            index,
            time_s,
            ..ControlFrame::default()
        };
        let period = 1.0 / 120.0;
        let mut anchor = None;
        let mut tag = |f: &ControlFrame, now_s: f64| {
            let base = tag_base(anchor, f, now_s);
            anchor = Some(Anchor {
                base_s: base,
                index: f.index,
                time_s: f.time_s,
            });
            base + f.time_s
        };
        // A minute played from wall-clock 1000 s, then an offline bounce's burst: tags keep
        // the audio's time, ahead of the wall clock.
        assert_eq!(tag(&frame(0, 0.0), 1000.0), 1000.0);
        let mut last = 0.0;
        for i in 1..=7200 {
            last = tag(&frame(i, i as f64 * period), 1000.0 + i as f64 * period);
        }
        assert!((last - 1060.0).abs() < 1e-6);
        assert!((tag(&frame(7201, 60.0 + period), 1060.0) - (1060.0 + period)).abs() < 1e-6);
        // Bypass: the rest frame (clock 0), then 5 s later the stream goes on where it was.
        assert_eq!(tag(&ControlFrame::rest(0, 0.0), 1061.0), 1061.0);
        let after = tag(&frame(7202, 60.0 + 2.0 * period), 1066.0);
        assert!(
            (after - 1066.0).abs() < 1e-6,
            "tagged {after}, not now (1066)"
        );
    }

    #[test]
    fn frames_arrive_and_the_target_and_format_change_while_running() {
        let a = UdpSocket::bind("127.0.0.1:0").unwrap();
        let b = UdpSocket::bind("127.0.0.1:0").unwrap();
        for s in [&a, &b] {
            s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        }
        let settings = Arc::new(Settings {
            target: Mutex::new(("127.0.0.1".into(), a.local_addr().unwrap().port())),
            format: Mutex::new(OscFormat::Pneuma),
        });
        let (mut feed, worker, stats) = start(settings.clone()).unwrap();
        feed.push(&test_frame(1));
        let msgs = receive(&a);
        assert_eq!(msgs[0].address, "/pneuma/frame");
        assert_eq!(msgs[1].args, vec![OscType::Float(101.0)]);
        let tag = TimeTag(msgs[0].time_tag.unwrap()).to_unix_seconds();
        assert!((tag - now_unix_s()).abs() < 2.0, "time tag near now: {tag}");

        *settings.target.lock().unwrap() = ("127.0.0.1".into(), b.local_addr().unwrap().port());
        *settings.format.lock().unwrap() = OscFormat::Vmc;
        // The change applies from the worker's next wake-up (a frame already being sent may still
        // go to the old target): push until the new target hears.
        b.set_read_timeout(Some(Duration::from_millis(50))).unwrap();
        let mut buf = [0u8; 2048];
        let mut got = None;
        for i in 2..100 {
            feed.push(&test_frame(i));
            if let Ok(n) = b.recv(&mut buf) {
                got = Some(decode(&buf[..n]).unwrap());
                break;
            }
        }
        let msgs = got.expect("the new target receives within 100 frames");
        assert_eq!(msgs[0].address, "/VMC/Ext/OK", "the new format");
        assert!(msgs.iter().any(|m| m.address == "/VMC/Ext/Bone/Pos"));
        drop(worker);
        assert!(stats.sent.load(Ordering::Relaxed) >= 2);
        assert_eq!(stats.failed.load(Ordering::Relaxed), 0);
        assert_eq!(stats.last_error.load(Ordering::Relaxed), 0, "no error");
    }

    #[test]
    fn a_worker_that_stops_leaves_the_avatar_in_the_rest_pose() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let settings = Arc::new(Settings {
            target: Mutex::new(("127.0.0.1".into(), rx.local_addr().unwrap().port())),
            format: Mutex::new(OscFormat::Pneuma),
        });
        let (mut feed, worker, _stats) = start(settings).unwrap();
        let mut turned = test_frame(7);
        turned.head.yaw_deg = 7.0;
        feed.push(&turned);
        let head = |msgs: &[Message]| {
            msgs.iter()
                .find(|m| m.address == "/pneuma/head")
                .map(|m| m.args.clone())
        };
        let first = receive(&rx);
        assert_eq!(first[0].args[0], OscType::Int(7));
        assert_ne!(head(&first), Some(vec![OscType::Float(0.0); 3]));
        // The plugin unloads, the app quits: one more frame, the rest pose, after the last.
        drop(worker);
        let last = receive(&rx);
        assert_eq!(last[0].args[0], OscType::Int(8), "{last:?}");
        assert_eq!(head(&last), Some(vec![OscType::Float(0.0); 3]), "{last:?}");
    }

    #[test]
    fn a_worker_that_stops_with_osc_off_sends_nothing() {
        struct Off(u16);
        impl OscSettings for Off {
            fn target(&self) -> (String, u16) {
                ("127.0.0.1".into(), self.0)
            }
            fn format(&self) -> OscFormat {
                OscFormat::Pneuma
            }
            fn enabled(&self) -> bool {
                false
            }
        }
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_millis(300)))
            .unwrap();
        let (mut feed, worker, _stats) =
            start(Arc::new(Off(rx.local_addr().unwrap().port()))).unwrap();
        // A frame fed before OSC was switched off goes out; the stop sends no rest pose after it.
        feed.push(&test_frame(3));
        receive(&rx);
        drop(worker);
        let mut buf = [0u8; 2048];
        assert!(rx.recv(&mut buf).is_err(), "a rest pose sent with OSC off");
    }

    #[test]
    fn a_closed_port_is_told_as_nothing_listening() {
        // A free port: bound, then closed again.
        let port = UdpSocket::bind("127.0.0.1:0")
            .and_then(|s| s.local_addr())
            .unwrap()
            .port();
        let settings = Arc::new(Settings {
            target: Mutex::new(("127.0.0.1".into(), port)),
            format: Mutex::new(OscFormat::Pneuma),
        });
        let (mut feed, worker, stats) = start(settings).unwrap();
        for i in 0..200 {
            feed.push(&test_frame(i));
            if stats.failed.load(Ordering::Relaxed) > 0 {
                break;
            }
            std::thread::sleep(Duration::from_millis(5));
        }
        drop(worker);
        assert!(stats.failed.load(Ordering::Relaxed) > 0, "no send failed");
        assert_eq!(
            stats.last_error.load(Ordering::Relaxed),
            OscError::Refused as u8,
            "the reason is the closed port"
        );
    }

    #[test]
    fn a_bad_target_never_blocks_the_feed_and_counts_every_frame() {
        let settings = Arc::new(Settings {
            // A host name is never looked up: it fails at once, without a DNS round trip.
            target: Mutex::new(("pneuma-osc.invalid".into(), 9)),
            format: Mutex::new(OscFormat::Pneuma),
        });
        let (mut feed, worker, stats) = start(settings).unwrap();
        // Push as fast as possible until the queue overflows: the feed never blocks.
        let mut pushed = 0u64;
        while stats.dropped_full.load(Ordering::Relaxed) == 0 && pushed < 10_000_000 {
            feed.push(&test_frame(pushed));
            pushed += 1;
        }
        assert!(
            stats.dropped_full.load(Ordering::Relaxed) > 0,
            "queue never overflowed"
        );
        let accounted = || {
            stats.failed.load(Ordering::Relaxed)
                + stats.dropped_full.load(Ordering::Relaxed)
                + stats.dropped_stale.load(Ordering::Relaxed)
        };
        let start = Instant::now();
        while accounted() < pushed && start.elapsed() < Duration::from_secs(10) {
            std::thread::sleep(Duration::from_millis(5));
        }
        assert_eq!(accounted(), pushed, "every frame sent, failed or dropped");
        drop(worker);
        // Stopped, the worker tried the rest pose too (failed as well).
        assert_eq!(accounted(), pushed + 1);
        assert_eq!(stats.sent.load(Ordering::Relaxed), 0);
        assert_eq!(
            OscError::from_code(stats.last_error.load(Ordering::Relaxed)),
            Some(OscError::NotAnAddress),
            "the reason is kept for the editor"
        );
        assert!(
            stats.dropped_stale.load(Ordering::Relaxed) > 0,
            "the oldest were skipped"
        );
    }
}
