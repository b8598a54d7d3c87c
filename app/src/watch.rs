//! Watches the JACK server the app runs on. When the server stops (it quits or crashes),
//! nice-plug's JACK backend neither says so nor returns: the app would hang on with a frozen
//! window and the avatar in its last pose. A client of our own (no ports) hears the server's
//! shutdown instead: the app says what happened, sends one OSC frame of the rest pose to the
//! target it was started with, and exits with status 1 (a supervisor can start it again).
//!
//! JACK calls the shutdown callback in a context where only async-signal-safe work is allowed:
//! it sets a flag, and a thread of ours does the rest.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use pneuma_core::encode::osc::{OscFormat, TimeTag};
use pneuma_core::encode::sink::{FrameSink, OscSink};
use pneuma_core::ControlFrame;
use pneuma_osc::target::{now_unix_s, resolve, send, socket_for};

/// The JACK client that watches the server (it has no ports).
const WATCH_CLIENT: &str = "pneuma_watch";
/// How often the watching thread looks at the flag.
const POLL: Duration = Duration::from_millis(50);

/// Where the rest pose goes: host, port and format (`None`: no OSC).
pub type RestTarget = Option<(String, u16, OscFormat)>;

/// Sets the flag when the server shuts down (async-signal-safe: one atomic store).
struct OnShutdown(Arc<AtomicBool>);

// The trait's method is `unsafe` to implement (it runs where only async-signal-safe work is
// allowed); this one only stores to an atomic.
#[allow(unsafe_code)]
impl jack::NotificationHandler for OnShutdown {
    unsafe fn shutdown(&mut self, _status: jack::ClientStatus, _reason: &str) {
        self.0.store(true, Ordering::SeqCst);
    }
}

/// The watch while it runs: keep it alive as long as the app runs.
pub struct Watch {
    _client: jack::AsyncClient<OnShutdown, ()>,
}

/// Starts watching the running JACK server; `None` when no client can be opened (the app then
/// runs as before).
pub fn start(rest: RestTarget) -> Option<Watch> {
    let (client, status) =
        jack::Client::new(WATCH_CLIENT, jack::ClientOptions::NO_START_SERVER).ok()?;
    if !status.is_empty() {
        return None;
    }
    let stopped = Arc::new(AtomicBool::new(false));
    let client = client
        .activate_async(OnShutdown(stopped.clone()), ())
        .ok()?;
    std::thread::Builder::new()
        .name("pneuma-jack-watch".into())
        .spawn(move || loop {
            if stopped.load(Ordering::SeqCst) {
                let rested = if send_rest_pose(&rest) {
                    " (the avatar was sent its rest pose)"
                } else {
                    ""
                };
                eprintln!(
                    "pneuma-app: the JACK server stopped; start it again, then pneuma-app{rested}"
                );
                std::process::exit(1);
            }
            std::thread::sleep(POLL);
        })
        .ok()?;
    Some(Watch { _client: client })
}

/// One frame of the rest pose ([`ControlFrame::rest`]) to `rest`'s target, tagged now (best
/// effort); whether it was sent.
fn send_rest_pose(rest: &RestTarget) -> bool {
    let Some((host, port, format)) = rest else {
        return false;
    };
    let Some(addr) = resolve(host, *port) else {
        return false;
    };
    let socket = socket_for(&addr);
    let mut sent = false;
    let mut sink = OscSink::new(
        *format,
        |_: &ControlFrame| TimeTag::from_unix_seconds(now_unix_s()),
        |_: &ControlFrame, packet: &[u8]| {
            sent = send(Some(addr), socket.as_ref(), false, packet).is_ok();
        },
    );
    sink.frame(&ControlFrame::rest(0, 0.0), 0);
    sent
}
