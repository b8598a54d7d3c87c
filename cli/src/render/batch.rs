//! `pneuma render A.mp3 B.flac FOLDER … -o OUTDIR`: many files rendered in parallel (rayon,
//! `--jobs N`, default the number of cores), one progress bar for the whole batch, a summary
//! table at the end. A file that fails is reported in the table and the others are finished; the
//! exit code is non-zero when any failed (130 when interrupted: the files under way then read
//! `interrupted`, those not reached `not started`, neither counted as failed).
//!
//! The inputs come expanded and checked from [`super::plan`] (folders give every file directly
//! inside them; two inputs that would write the same output names, `a.wav` and `A.flac`, are
//! refused before anything runs). Every file of a folder has a row: rendered, failed (why) or
//! skipped (why: not audio, or a format Pneuma does not read and the command that converts it).
//! Under the table, the files each render removed because an earlier render left them
//! ([`super::leftovers`]), also under `--quiet`. The same file met twice (given twice, or given
//! and in a folder given) is rendered once.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Mutex;

use rayon::prelude::*;

use super::error::{RenderError, EXIT_INTERRUPTED, INTERRUPTED};
use super::inputs::Input;
use super::pipeline::{lossy_note, run, RenderSummary};
use super::plan::{check_batch, Args};

/// Columns of the summary table.
const COLUMNS: usize = 7;

/// What became of one input of a batch.
type Outcome = Result<RenderSummary, RenderError>;

/// One row of the summary table: `Err(why)` is why a folder's file was not rendered.
fn row(input: &Path, result: Result<&Outcome, &str>) -> [String; COLUMNS] {
    let name = input.display().to_string();
    let result = match result {
        Ok(r) => r,
        Err(why) => {
            let dash = || "-".to_string();
            return [
                name,
                "skipped".into(),
                dash(),
                dash(),
                dash(),
                dash(),
                why.into(),
            ];
        }
    };
    match result {
        Ok(s) => [
            name,
            "ok".into(),
            s.breaths.len().to_string(),
            s.heard_breaths.to_string(),
            format!("{:.1}", s.length_s),
            warnings_cell(s.findings.iter().map(|f| f.short()), s.notes.len()),
            s.files
                .first()
                .map(|f| f.display().to_string())
                .unwrap_or_default()
                + &lossy_note(s),
        ],
        Err(e) => [
            name,
            e.status().into(),
            "-".into(),
            "-".into(),
            "-".into(),
            "-".into(),
            e.to_string(),
        ],
    }
}

/// The warnings column of a rendered file: each finding's short form, then where its notes
/// are (printed under the table), or "-" when there are neither.
fn warnings_cell<'a>(findings: impl Iterator<Item = &'a str>, notes: usize) -> String {
    let mut cell: Vec<String> = findings.map(str::to_string).collect();
    match notes {
        0 => {}
        1 => cell.push("see below".into()),
        n => cell.push(format!("{n} notes below")),
    }
    if cell.is_empty() {
        "-".into()
    } else {
        cell.join(", ")
    }
}

/// Prints the summary table to standard error.
fn print_table(rows: &[[String; COLUMNS]]) {
    let header = [
        "input",
        "result",
        "breaths",
        "heard",
        "length_s",
        "warnings",
        "output / error",
    ];
    let mut width = header.map(str::len);
    for r in rows {
        for (w, c) in width.iter_mut().zip(r).take(COLUMNS - 1) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |cells: [&str; COLUMNS]| {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            if i < COLUMNS - 1 {
                s.push_str(&format!("{c:<w$}  ", w = width[i]));
            } else {
                s.push_str(c);
            }
        }
        eprintln!("{}", s.trim_end());
    };
    line(header);
    for r in rows {
        line(r.each_ref().map(String::as_str));
    }
}

/// The lines after the table: each render's warnings on what its outputs could not carry, and
/// the files earlier renders left: what each render removed (even when `quiet`: a removal is
/// never silent), or kept (`--no-overwrite`).
fn print_leftovers(inputs: &[PathBuf], results: &[Outcome], quiet: bool) {
    for (input, s) in inputs
        .iter()
        .zip(results)
        .filter_map(|(i, r)| Some((i, r.as_ref().ok()?)))
    {
        if !quiet {
            for n in &s.notes {
                eprintln!("warning: {}: {n}", input.display());
            }
        }
        if let Some(removed) = s.leftovers.removed_line() {
            eprintln!("{removed}");
        }
        if !quiet {
            for w in s.leftovers.warnings() {
                eprintln!("warning: {w}");
            }
        }
    }
}

/// Renders every input that is not skipped; prints the table (every input, skipped ones
/// with why); the exit code: failure when one failed or none was rendered.
pub fn main(args: &Args, all: &[Input]) -> ExitCode {
    let inputs: Vec<PathBuf> = all
        .iter()
        .filter(|i| i.skip.is_none())
        .map(|i| i.path.clone())
        .collect();
    let jobs = match check_batch(args, &inputs) {
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
    let results: Vec<Outcome> = pool.install(|| {
        inputs
            .par_iter()
            .enumerate()
            .map(|(i, input)| {
                if INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
                    return Err(RenderError::NotStarted);
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
    let failed = results
        .iter()
        .filter(|r| r.as_ref().is_err_and(RenderError::is_failure))
        .count();
    let stopped = results.iter().filter(|r| r.is_err()).count() - failed;
    let skipped = all.len() - inputs.len();
    if !args.quiet || failed + stopped > 0 {
        // Every input in the order given, the rendered ones with their results.
        let mut rendered = results.iter();
        let rows: Vec<[String; COLUMNS]> = all
            .iter()
            .filter_map(|i| match &i.skip {
                Some(why) => (!args.quiet).then(|| row(&i.path, Err(why))),
                None => rendered
                    .next()
                    .filter(|r| !args.quiet || r.is_err())
                    .map(|r| row(&i.path, Ok(r))),
            })
            .collect();
        print_table(&rows);
        let stopped = if stopped > 0 {
            format!(", {stopped} interrupted or not started")
        } else {
            String::new()
        };
        eprintln!(
            "{} rendered, {failed} failed{stopped}, {skipped} skipped, into {}",
            results.iter().filter(|r| r.is_ok()).count(),
            args.output.display()
        );
    }
    print_leftovers(&inputs, &results, args.quiet);
    if results
        .iter()
        .any(|r| r.as_ref().is_err_and(|e| !e.is_failure()))
    {
        ExitCode::from(EXIT_INTERRUPTED)
    } else if failed > 0 || inputs.is_empty() {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

#[cfg(test)]
mod tests {
    use super::warnings_cell;

    #[test]
    fn the_warnings_cell_points_to_the_notes_once() {
        assert_eq!(warnings_cell(std::iter::empty(), 0), "-");
        assert_eq!(warnings_cell(["no speech"].into_iter(), 0), "no speech");
        assert_eq!(warnings_cell(std::iter::empty(), 1), "see below");
        assert_eq!(
            warnings_cell(["mostly music"].into_iter(), 2),
            "mostly music, 2 notes below"
        );
    }
}
