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

use crate::rest::{send_rest_pose, RestTarget};

/// The JACK client that watches the server (it has no ports).
const WATCH_CLIENT: &str = "pneuma_watch";
/// How often the watching thread looks at the flag.
const POLL: Duration = Duration::from_millis(50);

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
