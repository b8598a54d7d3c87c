//! How a render fails: [`RenderError`], and Ctrl-C, which stops a render after its current
//! block as an error that leaves nothing behind ([`INTERRUPTED`], [`EXIT_INTERRUPTED`]).
//! SIGTERM (`kill`, `timeout`, a service manager) and SIGHUP (the terminal closed) take the
//! same path: the handler cannot tell the three apart, so each exits with 130. A second signal
//! stops at once, leaving no temporary file either.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use pneuma_core::engine::EngineError;
use pneuma_io::ReadError;
use thiserror::Error;

/// Errors of `pneuma render`.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The input file.
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// The settings.
    #[error("invalid settings: {0}")]
    Settings(#[from] EngineError),
    /// A breath sample or the head model.
    #[error("{0}")]
    Input(String),
    /// An output file.
    #[error("cannot write {path}: {source}{}", crate::output::write_hint(source))]
    Output {
        /// Where we tried to write.
        path: PathBuf,
        /// Why it failed.
        source: std::io::Error,
    },
    /// The plot.
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// Ctrl-C, SIGTERM or SIGHUP.
    #[error(
        "interrupted (Ctrl-C, SIGTERM or SIGHUP): nothing was written, existing files are \
         unchanged"
    )]
    Interrupted,
    /// A batch's file not started because the batch was interrupted first.
    #[error("not started: the batch was interrupted (Ctrl-C, SIGTERM or SIGHUP) before it")]
    NotStarted,
}

impl RenderError {
    /// The table's status word for a render that ended in this error: `interrupted`, `not
    /// started`, or `FAILED` for a real failure.
    pub fn status(&self) -> &'static str {
        match self {
            RenderError::Interrupted => "interrupted",
            RenderError::NotStarted => "not started",
            _ => "FAILED",
        }
    }

    /// Whether this is a failure of the file (not an interruption of the run).
    pub fn is_failure(&self) -> bool {
        !matches!(self, RenderError::Interrupted | RenderError::NotStarted)
    }
}

/// A [`RenderError::Output`] for `path`, for `map_err`.
pub fn out_err(path: &Path) -> impl Fn(std::io::Error) -> RenderError + '_ {
    move |source| RenderError::Output {
        path: path.to_owned(),
        source,
    }
}

/// Set by the Ctrl-C (and SIGTERM, SIGHUP) handler; a render checks it after every block and stops, leaving no
/// partial file (its staged files are removed when dropped).
pub static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Whether Ctrl-C was pressed (or SIGTERM or SIGHUP came).
pub fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::Relaxed)
}

/// Exit code of an interrupted run (128 + SIGINT), as shells expect; also after SIGTERM and
/// SIGHUP, which the handler does not tell from SIGINT.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Two signals this close together are one interruption delivered twice: `timeout` (and a shell
/// killing a job) signals the process and then its process group.
const SAME_INTERRUPTION: Duration = Duration::from_millis(500);

/// Installs the Ctrl-C handler, which SIGTERM and SIGHUP reach too (ctrlc's `termination`
/// feature): the first signal sets [`INTERRUPTED`] (the render stops after its current block
/// and removes its temporary files); a second one at least [`SAME_INTERRUPTION`] later stops
/// at once, after removing every temporary file (and letting a commit in progress finish:
/// [`crate::output::exit_removing_temporaries`]).
pub fn install_interrupt_handler() {
    static FIRST: OnceLock<Instant> = OnceLock::new();
    let _ = ctrlc::set_handler(|| {
        let first = *FIRST.get_or_init(Instant::now);
        if !INTERRUPTED.swap(true, Ordering::Relaxed) || first.elapsed() < SAME_INTERRUPTION {
            return;
        }
        crate::output::exit_removing_temporaries(i32::from(EXIT_INTERRUPTED), |removed| {
            if removed {
                eprintln!("interrupted again: stopped at once; no partial file is left");
            } else {
                eprintln!(
                    "interrupted again: stopped at once while an output was being written \
                     through (a FIFO or device that does not read); its temporary files may remain"
                );
            }
        });
    });
}
