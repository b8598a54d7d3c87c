//! Settings a standalone program (the `pneuma-app` crate) gives every plugin instance of its
//! process before nice-plug's standalone wrapper creates it: they become the parameters'
//! defaults (live mode, OSC on to the avatar app). Plugin hosts never set them, so the
//! plugin's own defaults stay as documented. The program can also ask its window to close
//! ([`request_close`]: Ctrl+C in the terminal while the window is open).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

use super::OscFormatChoice;

/// Defaults for the standalone program.
#[derive(Debug, Clone, PartialEq)]
pub struct AppDefaults {
    /// Live mode (zero latency) instead of lookahead.
    pub live: bool,
    /// OSC target host (a numeric address or `localhost`).
    pub osc_host: String,
    /// OSC target port.
    pub osc_port: u16,
    /// OSC address space.
    pub osc_format: OscFormatChoice,
}

static APP_DEFAULTS: OnceLock<AppDefaults> = OnceLock::new();

/// Sets the defaults once per process, before the plugin is created. A second call is refused
/// (returns the defaults already set).
pub fn set_app_defaults(defaults: AppDefaults) -> Result<(), AppDefaults> {
    APP_DEFAULTS.set(defaults)
}

/// The standalone defaults, when a standalone program set them.
pub fn app_defaults() -> Option<&'static AppDefaults> {
    APP_DEFAULTS.get()
}

static CLOSE_REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks the editor window of this process to close (the standalone program got Ctrl+C or
/// SIGTERM): the window closes at its next repaint and nice-plug's wrapper then stops as when
/// the user closes it. Plugin hosts never call it.
pub fn request_close() {
    CLOSE_REQUESTED.store(true, Ordering::SeqCst);
}

/// Whether the program asked its window to close ([`request_close`]).
pub fn close_requested() -> bool {
    CLOSE_REQUESTED.load(Ordering::SeqCst)
}
