//! The tables of `eval-pitch`: the offset search, per condition, SNR, noise and speaker, the
//! error breakdown (`--verbose`) and the per-clip tracks (`--dump`).

use std::collections::BTreeMap;
use std::path::Path;

use super::args::Args;
use super::baselines as f0_baselines;
use super::score::{score, total, Clip, Counts, SetResult, Track, EDGE_FRAMES, GRID_S, LOW_F0_HZ};
use crate::data::reference::Condition;

pub(crate) const OFFSETS_MS: [i32; 9] = [-20, -15, -10, -5, 0, 5, 10, 15, 20];

/// The global offset minimising the summed FFE of all trackers over `clips` (printed).
pub(crate) fn search_offset(clips: &[&Clip], tracker_names: &[&str]) -> i32 {
    let mut best = (f64::INFINITY, 0);
    println!(
        "offset search (summed FFE of all trackers but swift-f0 and pYIN, and each tracker's own):"
    );
    for &o in &OFFSETS_MS {
        let row = total(clips.iter().copied(), tracker_names.len(), o);
        // The Python baselines are scored at the offset the others choose: adding them leaves
        // the offset (and so every other figure) unchanged.
        let sum: f64 = row
            .iter()
            .zip(tracker_names)
            .filter(|(_, n)| ![f0_baselines::SWIFT_F0, f0_baselines::PYIN].contains(n))
            .map(|(c, _)| c.ffe())
            .sum();
        println!(
            "  {o:+3} ms: sum {:.4}  {}",
            sum,
            row.iter()
                .zip(tracker_names)
                .map(|(c, n)| format!("{n} {:.2}%", c.ffe() * 100.0))
                .collect::<Vec<_>>()
                .join("  ")
        );
        if sum < best.0 {
            best = (sum, o);
        }
    }
    best.1
}

pub(crate) fn print_header(tracker_names: &[&str]) {
    let header = tracker_names
        .iter()
        .map(|n| format!("{n:>31}"))
        .collect::<String>();
    println!("{:<20}{header}", "");
    println!(
        "{:<20}{}",
        "",
        "    FFE%   VDE%   GPE%  cents".repeat(tracker_names.len())
    );
}

pub(crate) fn print_row(label: &str, row: &[Counts]) {
    let cells: String = row
        .iter()
        .map(|c| {
            format!(
                " {:>7.2}{:>7.2}{:>7.2}{:>7.1}  ",
                c.ffe() * 100.0,
                c.vde() * 100.0,
                c.gpe() * 100.0,
                c.fine_cents()
            )
        })
        .collect();
    println!("{label:<20}{cells}");
}

/// Prints one data set's tables: per condition, per SNR, per noise, per speaker, all.
pub(crate) fn report_data_set(
    dir: &Path,
    clips: &[&Clip],
    tracker_names: &[&str],
    args: &Args,
) -> Result<SetResult, String> {
    println!("\n=== data set {} ({} clips)", dir.display(), clips.len());
    let searched = search_offset(clips, tracker_names);
    let offset = args.offset.unwrap_or(searched);
    let how = if args.offset.is_some() {
        "given by --offset"
    } else {
        "searched"
    };
    println!(
        "global offset used: {offset:+} ms ({how}; tracker time = reference time {offset:+} ms)\n"
    );
    let n = tracker_names.len();
    let mut by_condition: BTreeMap<Condition, Vec<Counts>> = BTreeMap::new();
    for clip in clips {
        by_condition.insert(
            clip.condition.clone(),
            total(
                clips
                    .iter()
                    .copied()
                    .filter(|c| c.condition == clip.condition),
                n,
                offset,
            ),
        );
    }
    print_header(tracker_names);
    for (condition, row) in &by_condition {
        print_row(&condition.label(), row);
    }
    let snrs: std::collections::BTreeSet<Option<u32>> =
        by_condition.keys().map(|c| c.snr_db).collect();
    let noises: std::collections::BTreeSet<&str> =
        by_condition.keys().map(|c| c.noise.as_str()).collect();
    if snrs.len() > 1 {
        println!();
        for snr in snrs.iter().rev().flatten() {
            let row = total(
                clips
                    .iter()
                    .copied()
                    .filter(|c| c.condition.snr_db == Some(*snr)),
                n,
                offset,
            );
            print_row(&format!("all noise {snr} dB"), &row);
        }
        for noise in &noises {
            let row = total(
                clips
                    .iter()
                    .copied()
                    .filter(|c| c.condition.noise == *noise),
                n,
                offset,
            );
            print_row(&format!("{noise} all SNR"), &row);
        }
    }
    // Per speaker at the cleanest SNR (clean, else the highest), over its noise types.
    let cleanest = snrs
        .iter()
        .max_by_key(|s| s.unwrap_or(u32::MAX))
        .copied()
        .flatten();
    let label = cleanest.map_or("clean".to_string(), |s| format!("all noise {s} dB"));
    let mut by_speaker = BTreeMap::new();
    println!("\nper speaker, {label}:");
    let mut speakers: Vec<&str> = clips.iter().map(|c| c.speaker.as_str()).collect();
    speakers.sort_unstable();
    speakers.dedup();
    for speaker in speakers {
        let row = total(
            clips
                .iter()
                .copied()
                .filter(|c| c.speaker == speaker && c.condition.snr_db == cleanest),
            n,
            offset,
        );
        print_row(speaker, &row);
        by_speaker.insert(speaker.to_string(), row);
    }
    let all = total(clips.iter().copied(), n, offset);
    println!();
    print_row("data set, all", &all);
    print_voicing_split(tracker_names, &all);
    if args.verbose {
        print_breakdown(clips, tracker_names, offset, &by_condition);
    }
    if let Some(dump) = &args.dump {
        dump_tracks(dump, clips, tracker_names, offset)?;
        println!("\nper-clip tracks written to {}", dump.display());
    }
    Ok(SetResult {
        dir: dir.to_owned(),
        offset,
        by_condition,
        by_speaker,
        all,
    })
}

pub(crate) fn print_voicing_split(tracker_names: &[&str], row: &[Counts]) {
    println!(
        "voicing errors split (false voiced / missed voiced, % of all frames): {}",
        tracker_names
            .iter()
            .zip(row)
            .map(|(n, c)| format!(
                "{n} {:.2}/{:.2}",
                c.false_voiced as f64 * 100.0 / c.frames.max(1) as f64,
                (c.voicing_errors - c.false_voiced) as f64 * 100.0 / c.frames.max(1) as f64
            ))
            .collect::<Vec<_>>()
            .join(", ")
    );
}

/// `--verbose`: where the frame errors come from, per condition and per clip (Pneuma and Praat).
pub(crate) fn print_breakdown(
    clips: &[&Clip],
    tracker_names: &[&str],
    offset: i32,
    by_condition: &BTreeMap<Condition, Vec<Counts>>,
) {
    let shown: Vec<usize> = tracker_names
        .iter()
        .enumerate()
        .filter(|(_, n)| **n == "pneuma" || **n == "praat")
        .map(|(i, _)| i)
        .collect();
    println!(
        "\nerror breakdown (% of all frames; edges = first/last {EDGE_FRAMES} reference frames of a voiced run; low f0 < {LOW_F0_HZ} Hz):"
    );
    for (condition, row) in by_condition {
        for &i in &shown {
            println!(
                "  {:<14} {:<8} FFE {:5.2} {}",
                condition.label(),
                tracker_names[i],
                row[i].ffe() * 100.0,
                row[i].breakdown()
            );
        }
    }
    println!("\nper clip:");
    for clip in clips {
        for &i in &shown {
            let c = score(&clip.reference, &clip.tracks[i], offset);
            println!(
                "  {:<20} {:<8} FFE {:5.2} {}",
                clip.name,
                tracker_names[i],
                c.ffe() * 100.0,
                c.breakdown()
            );
        }
    }
}

/// `--dump DIR`: one CSV per clip on the reference grid: time, reference f0, every tracker's f0
/// and Pneuma's voicing, RMS and level.
pub(crate) fn dump_tracks(
    dir: &Path,
    clips: &[&Clip],
    tracker_names: &[&str],
    offset: i32,
) -> Result<(), String> {
    use std::fmt::Write as _;
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for clip in clips {
        let mut text = format!(
            "time_s,ref_hz,{},voicing,rms_db,level_db\n",
            tracker_names.join(",")
        );
        for &(t, f_ref) in &clip.reference {
            let k = ((t + offset as f64 / 1000.0) / GRID_S).round() as i64;
            let at = |tr: &Track| {
                if k >= 0 && (k as usize) < tr.len() {
                    tr[k as usize]
                } else {
                    0.0
                }
            };
            let _ = write!(text, "{t:.3},{f_ref:.1}");
            for tr in &clip.tracks {
                let _ = write!(text, ",{:.1}", at(tr));
            }
            let inner = if k >= 0 && (k as usize) < clip.internals.len() {
                clip.internals[k as usize]
            } else {
                [0.0; 3]
            };
            let _ = writeln!(text, ",{:.3},{:.1},{:.1}", inner[0], inner[1], inner[2]);
        }
        let path = dir.join(format!("{}.csv", clip.name));
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}
