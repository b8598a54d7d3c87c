//! Ctrl+C and SIGTERM end the app, window or not, within [`GRACE`], leaving the avatar in its
//! rest pose.
//!
//! nice-plug's wrapper takes Ctrl+C (SIGINT, through the `ctrlc` crate) only to end its headless
//! loop: with the window open Ctrl+C did nothing, SIGTERM killed the app at once (the avatar
//! left mid-turn), and its JACK backend could hang while it stopped. So the app adds its own
//! handling, after the wrapper's:
//! - **SIGINT**: once the wrapper has taken it, the app registers its own action behind the
//!   wrapper's (signal-hook calls the one already there first), which asks the window to close
//!   ([`request_close`]); headless, the wrapper's loop ends by itself. (The wrapper takes
//!   SIGINT even where it starts ignored, in a script's background job; registered before it,
//!   ours would be replaced.) Either way the wrapper
//!   then stops as when the window is closed, and the plugin's OSC worker sends the rest pose.
//! - **SIGTERM** (a supervisor, `kill`): the same, the app raising SIGINT for the wrapper
//!   (registered at the same moment, behind the wrapper's where it takes SIGTERM too).
//! - If the app still runs [`GRACE`] after either (the backend hangs while it stops), it sends
//!   the rest pose to its OSC target itself, says so, and exits with status 0.
//!
//! Signal handlers only set flags (signal-hook's); a thread of ours does the rest.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use pneuma_plugin::editor::standalone::request_close;
use signal_hook::consts::{SIGINT, SIGTERM};

use crate::rest::{send_rest_pose, RestTarget};

/// How long the wrapper gets to stop after Ctrl+C or SIGTERM before the app ends itself.
pub const GRACE: Duration = Duration::from_secs(2);
/// How often the quitting thread looks at the flags.
const POLL: Duration = Duration::from_millis(20);

/// Starts handling Ctrl+C and SIGTERM (see the module docs); quietly does nothing when the
/// signals cannot be registered (the wrapper's own Ctrl+C handling stays). A SIGTERM ignored
/// when the app starts stays ignored.
pub fn watch(rest: RestTarget) {
    let term = Arc::new(AtomicBool::new(false));
    let int = Arc::new(AtomicBool::new(false));
    let take_term = disposition(SIGTERM) != Disposition::Ignored;
    let _ = std::thread::Builder::new()
        .name("pneuma-quit".into())
        .spawn(move || {
            // Both signals are registered once the wrapper's handler is in place: ctrlc
            // replaces whatever was there, even an ignored SIGINT of a script's background job,
            // and SIGTERM too where a build of the whole workspace turns on its `termination`
            // feature (the CLI's); signal-hook installs its handler only the first time, so
            // ours must come after.
            let mut pending = true;
            let mut quit_at: Option<Instant> = None;
            loop {
                if pending && disposition(SIGINT) == Disposition::Handled {
                    pending = false;
                    let _ = signal_hook::flag::register(SIGINT, int.clone());
                    if take_term {
                        let _ = signal_hook::flag::register(SIGTERM, term.clone());
                    }
                }
                if quit_at.is_none() {
                    let term_now = term.load(Ordering::SeqCst);
                    if term_now || int.load(Ordering::SeqCst) {
                        if term_now {
                            // The wrapper ends its headless loop on SIGINT.
                            let _ = signal_hook::low_level::raise(SIGINT);
                        }
                        request_close();
                        quit_at = Some(Instant::now());
                    }
                }
                if quit_at.is_some_and(|t| t.elapsed() >= GRACE) {
                    let rested = if send_rest_pose(&rest) {
                        " (the avatar was sent its rest pose)"
                    } else {
                        ""
                    };
                    eprintln!(
                        "pneuma-app: the audio backend did not stop within {} s; ended it{rested}",
                        GRACE.as_secs()
                    );
                    exit_now();
                }
                std::thread::sleep(POLL);
            }
        });
}

/// Ends the process at once with status 0, without the exit handlers: the audio thread hangs
/// inside the JACK library, whose own handlers could wait on it.
#[allow(unsafe_code)]
fn exit_now() -> ! {
    // SAFETY: `_exit` ends the process; nothing runs after it in this process. Standard error,
    // which said why, is unbuffered.
    unsafe { libc::_exit(0) }
}

/// What a signal does now.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Disposition {
    Default,
    Ignored,
    /// A handler runs (the wrapper's, or ours).
    Handled,
}

/// What `signal` does now (Default when it cannot be read).
#[allow(unsafe_code)]
fn disposition(signal: libc::c_int) -> Disposition {
    // SAFETY: `sigaction` with a null new action only writes the current action into `old`, a
    // zero-initialised plain C struct owned by this frame; nothing is installed or changed.
    let handler = unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        if libc::sigaction(signal, std::ptr::null(), &mut old) != 0 {
            return Disposition::Default;
        }
        old.sa_sigaction
    };
    match handler {
        libc::SIG_DFL => Disposition::Default,
        libc::SIG_IGN => Disposition::Ignored,
        _ => Disposition::Handled,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_signal_reads_as_handled_once_a_handler_is_registered() {
        // SIGUSR2: nothing else in the test process touches it (SIGINT may start ignored
        // when the tests run in a script's background job).
        assert_eq!(disposition(libc::SIGUSR2), Disposition::Default);
        let flag = Arc::new(AtomicBool::new(false));
        signal_hook::flag::register(libc::SIGUSR2, flag.clone()).expect("register");
        assert_eq!(disposition(libc::SIGUSR2), Disposition::Handled);
        signal_hook::low_level::raise(libc::SIGUSR2).expect("raise");
        assert!(flag.load(Ordering::SeqCst));
    }
}
