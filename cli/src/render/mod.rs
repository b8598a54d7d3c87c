//! `pneuma render IN -o DIR`: streams an audio file (any format `pneuma-io` reads, or standard
//! input) through the [`Engine`](pneuma_core::engine::Engine) in blocks and writes
//! `DIR/<stem>.wav|flac|aiff` (the input with breaths, same rate, channels and bit depth; see
//! [`output_container`]), `DIR/<stem>.controls.csv`, `DIR/<stem>.breaths.csv`,
//! `DIR/<stem>.png`, with `--bvh` `DIR/<stem>.bvh` and with `--markers` the editors' marker
//! files (contracts in DESIGN.md), removing those an earlier render left that this one does not
//! write; or, with `-o -`, only the audio as WAV to standard output.
//!
//! The engine runs as in the plugin (with `--lookahead-ms` exactly as the plugin; by default
//! with the engine's whole-file lookahead of seconds). The parts, each using only the ones
//! before it:
//!
//! - [`error`]: how a render fails, and Ctrl-C;
//! - [`findings`]: what a render found that the user should know (no signal, no speech, a
//!   quiet input, mostly music, channels in antiphase): warnings, exit status 0;
//! - [`marks`]: Pneuma's mark on each optional file (plot, BVH, MIDI, markers), which tells a
//!   file it wrote from the user's file of the same name;
//! - [`leftovers`]: the files an earlier render of the same stem left that this one does not
//!   write and that carry Pneuma's mark, removed once it is committed and named even under
//!   `--quiet` (kept and named with `--no-overwrite`);
//! - [`plan`]: the arguments turned into a checked plan (inputs, engine settings, the engine
//!   prepared for an input, the output names); nothing is written there;
//! - [`voice`]: the breath voice learned from the recording (or `--breath-like`) before a
//!   whole-file render;
//! - [`bvh_file`]: the BVH, its frame count the lines the decoded audio gave, written whole
//!   at the end;
//! - [`pipeline`]: one planned input through the engine and its sinks, the files committed
//!   together;
//! - [`batch`]: several inputs or folders, in parallel, with a summary table.
//!
//! This module only dispatches ([`main`]): one input with a progress bar and a summary line, or
//! a batch.

pub mod batch;
pub mod bvh_file;
pub mod error;
pub mod findings;
pub mod inputs;
pub mod leftovers;
pub mod marks;
pub mod pipeline;
pub mod plan;
pub mod voice;

use std::path::Path;
use std::process::ExitCode;

pub use error::{
    install_interrupt_handler, interrupted, RenderError, EXIT_INTERRUPTED, INTERRUPTED,
};
pub use pipeline::{describe_band_limit, describe_voice, lossy_note, run, RenderSummary};
pub use plan::{output_container, Args};

/// Runs `pneuma render` from parsed arguments: one input with a progress bar when a terminal
/// is attached and the job takes more than a second, or a batch (several inputs or a folder).
pub fn main(mut args: Args) -> ExitCode {
    install_interrupt_handler();
    let inputs = match inputs::expand_inputs(&args.inputs, &args.output) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    // A file-like -o is one mistake, told once, not once per input of a batch.
    if !args.to_stdout() {
        if let Err(e) = crate::options::check_output_folder("-o", &args.output) {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    }
    let created = crate::options::missing_folders(&args.output);
    crate::output::created_folders(&created);
    let code = if inputs.len() > 1 || args.inputs.iter().any(|p| p.is_dir()) {
        args.in_batch = true;
        batch::main(&args, &inputs)
    } else {
        render_one(&args, &inputs[0].path)
    };
    if code != ExitCode::SUCCESS {
        crate::options::remove_empty(&created);
    }
    code
}

/// Renders one input with a progress bar; prints its summary or error; the exit code.
fn render_one(args: &Args, input: &Path) -> ExitCode {
    let mut bar = crate::options::Progress::new("rendering", !args.quiet && !args.no_progress);
    let result = run(args, input, |f| bar.set(f));
    bar.finish();
    match result {
        Ok(s) => {
            if !args.quiet {
                print_summary(input, &s);
            } else if let Some(removed) = s.leftovers.removed_line() {
                // A removal is never silent.
                eprintln!("{removed}");
            }
            ExitCode::SUCCESS
        }
        Err(RenderError::Interrupted) => {
            eprintln!("error: {}", RenderError::Interrupted);
            ExitCode::from(EXIT_INTERRUPTED)
        }
        // The reader of standard output went away (`| head`): end quietly, as `analyze` and
        // Unix tools do.
        Err(RenderError::Output { ref source, .. })
            if args.output.as_os_str() == "-" && crate::output::is_broken_pipe(source) =>
        {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The summary of one render on standard error: the input's format, breaths, frames, clipped
/// samples, what a lossy input became, the files written, the real breaths heard and the breath
/// voice of the breaths inserted.
fn print_summary(input: &Path, s: &RenderSummary) {
    eprintln!(
        "rendered {} ({}, {}): {}, {}{}{}",
        input.display(),
        s.input_format.0.name(),
        crate::options::describe_format(&s.info, s.input_format.1),
        crate::options::count(s.breaths.len(), "breath"),
        crate::options::count(s.frames as usize, "control frame"),
        if s.clipped > 0 {
            format!(", {} samples clipped", s.clipped)
        } else {
            String::new()
        },
        lossy_note(s)
    );
    for f in &s.files {
        eprintln!("  {}", f.display());
    }
    if let Some(osc) = &s.osc {
        eprintln!("  {osc}");
    }
    if let Some(removed) = s.leftovers.removed_line() {
        eprintln!("  {removed}");
    }
    if s.heard_breaths > 0 {
        eprintln!(
            "  real breaths heard in the pauses and left as they are: {}",
            s.heard_breaths
        );
    }
    // The voice is worth a line only where a breath was inserted (not with --no-breaths).
    if !s.breaths.is_empty() {
        eprintln!("  {}", describe_voice(s.voice, s.voice_level, &s.breaths));
        if let Some(line) = describe_band_limit(s.band_limit_hz) {
            eprintln!("  {line}");
        }
    }
    for w in s.leftovers.warnings() {
        eprintln!("warning: {w}");
    }
    for f in &s.findings {
        eprintln!("warning: {}", f.message());
    }
    for n in &s.notes {
        eprintln!("warning: {n}");
    }
}
