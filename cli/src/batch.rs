//! `pneuma render A.mp3 B.flac FOLDER … -o OUTDIR`: many files rendered in parallel (rayon,
//! `--jobs N`, default the number of cores), one progress bar for the whole batch, a summary
//! table at the end. A file that fails is reported in the table and the others are finished; the
//! exit code is non-zero when any failed (130 when interrupted).
//!
//! Folders give the audio files directly inside them (by extension, see
//! [`pneuma_io::AUDIO_EXTENSIONS`]), sorted by name. Two inputs that would write the same output
//! names (`a.wav` and `a.flac`) are refused before anything runs.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;

use rayon::prelude::*;

use crate::render::{run, Args, RenderError, RenderSummary, EXIT_INTERRUPTED};

/// Most jobs accepted by `--jobs`.
const MAX_JOBS: usize = 256;

/// The input files of `args`: files as given, folders expanded to the audio files inside.
pub fn expand_inputs(args: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    for p in args {
        if p.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| format!("cannot read the folder {}: {e}", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    f.is_file()
                        && f.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                            !n.starts_with('.') && pneuma_io::audio_stem(n).is_some()
                        })
                })
                .collect();
            if found.is_empty() {
                return Err(format!(
                    "{} holds no audio files (.{}); give files or a folder of them",
                    p.display(),
                    pneuma_io::AUDIO_EXTENSIONS.join(", .")
                ));
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// The first two inputs whose outputs would have the same names.
fn clashing_stems(inputs: &[PathBuf]) -> Option<(&Path, &Path)> {
    let stem = |p: &Path| p.file_stem().map(|s| s.to_os_string());
    for (i, a) in inputs.iter().enumerate() {
        if let Some(b) = inputs[..i].iter().find(|b| stem(b) == stem(a)) {
            return Some((b, a));
        }
    }
    None
}

/// Checks a batch's arguments before anything runs.
fn check(args: &Args, inputs: &[PathBuf]) -> Result<usize, String> {
    if args.output.as_os_str() == "-" {
        return Err(
            "-o - (standard output) takes one input; give an output folder for a batch".into(),
        );
    }
    if inputs.iter().any(|p| p.as_os_str() == "-") {
        return Err("- (standard input) cannot be part of a batch; render it on its own".into());
    }
    if let Some((a, b)) = clashing_stems(inputs) {
        return Err(format!(
            "{} and {} would write the same output files in {}; rename one, or render them \
             into different folders",
            a.display(),
            b.display(),
            args.output.display()
        ));
    }
    let jobs = match args.jobs {
        Some(n) if !(1..=MAX_JOBS).contains(&n) => {
            return Err(format!("--jobs {n} is out of range: use 1 to {MAX_JOBS}"))
        }
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, |n| n.get()),
    };
    Ok(jobs.min(inputs.len()).max(1))
}

/// One row of the summary table.
fn row(input: &Path, result: &Result<RenderSummary, RenderError>) -> [String; 5] {
    let name = input.display().to_string();
    match result {
        Ok(s) => [
            name,
            "ok".into(),
            s.breaths.len().to_string(),
            format!("{:.1}", s.length_s),
            s.files
                .first()
                .map(|f| f.display().to_string())
                .unwrap_or_default()
                + &crate::render::lossy_note(s),
        ],
        Err(e) => [name, "FAILED".into(), "-".into(), "-".into(), e.to_string()],
    }
}

/// Prints the summary table to standard error.
fn print_table(rows: &[[String; 5]]) {
    let header = ["input", "result", "breaths", "length_s", "output / error"];
    let mut width = header.map(str::len);
    for r in rows {
        for (w, c) in width.iter_mut().zip(r).take(4) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: [&str; 5]| {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            if i < 4 {
                s.push_str(&format!("{c:<w$}  ", w = width[i]));
            } else {
                s.push_str(c);
            }
        }
        eprintln!("{}", s.trim_end());
    };
    line(header);
    for r in rows {
        line([&r[0], &r[1], &r[2], &r[3], &r[4]]);
    }
}

/// Renders every input; prints the table; the exit code.
pub fn main(args: &Args, inputs: &[PathBuf]) -> ExitCode {
    let jobs = match check(args, inputs) {
        Ok(j) => j,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(jobs).build() {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: cannot start {jobs} render threads: {e}");
            return ExitCode::FAILURE;
        }
    };
    // One bar: the mean of the files' fractions done.
    let bar = Mutex::new(crate::options::Progress::new(
        &format!("rendering {} files", inputs.len()),
        !args.quiet && !args.no_progress,
    ));
    let done = Mutex::new(vec![0.0f64; inputs.len()]);
    let report = |i: usize, f: f64| {
        if let (Ok(mut d), Ok(mut b)) = (done.lock(), bar.lock()) {
            d[i] = f;
            let mean = d.iter().sum::<f64>() / d.len() as f64;
            b.set(mean);
        }
    };
    let results: Vec<Result<RenderSummary, RenderError>> = pool.install(|| {
        inputs
            .par_iter()
            .enumerate()
            .map(|(i, input)| {
                if crate::render::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
                    return Err(RenderError::Interrupted);
                }
                let r = run(args, input, |f| report(i, f));
                report(i, 1.0);
                r
            })
            .collect()
    });
    if let Ok(b) = bar.lock() {
        b.finish();
    }
    let failed = results.iter().filter(|r| r.is_err()).count();
    if !args.quiet || failed > 0 {
        let rows: Vec<[String; 5]> = inputs
            .iter()
            .zip(&results)
            .filter(|(_, r)| !args.quiet || r.is_err())
            .map(|(p, r)| row(p, r))
            .collect();
        print_table(&rows);
        eprintln!(
            "{} rendered, {failed} failed, into {}",
            inputs.len() - failed,
            args.output.display()
        );
    }
    if results
        .iter()
        .any(|r| matches!(r, Err(RenderError::Interrupted)))
    {
        ExitCode::from(EXIT_INTERRUPTED)
    } else if failed > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
