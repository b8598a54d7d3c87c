//! The styletalk format: `<clip>.wav` (any audio format `pneuma-io` reads) paired with
//! `<clip>.head.csv` (`time_s,pitch_deg,yaw_deg,roll_deg`). Read by `pneuma train`, `cargo
//! xtask train-default` and `pneuma eval head`.

use std::path::Path;

use pneuma_core::head::{MotionTrack, TrainingClip};
use pneuma_core::AnalysisConfig;
use pneuma_io::capped::{read_text_capped, MOTION_CSV_MAX_BYTES};

use super::{analyse_file, DataError};

/// Reads a head-motion CSV (`time_s,pitch_deg,yaw_deg,roll_deg`) into (roll, pitch, yaw).
pub fn read_head_csv(path: &Path) -> Result<MotionTrack, DataError> {
    let what = "a head-motion CSV (time_s,pitch_deg,yaw_deg,roll_deg)";
    let text = read_text_capped(path, MOTION_CSV_MAX_BYTES, what).map_err(DataError::TextFile)?;
    let csv_err = |line: usize, reason: String| DataError::Csv {
        path: path.into(),
        line,
        reason,
    };
    let mut lines = text.lines();
    let header = lines.next().unwrap_or("").trim();
    let cols: Vec<&str> = header.split(',').map(str::trim).collect();
    let find = |name: &str| {
        cols.iter()
            .position(|c| *c == name)
            .ok_or_else(|| csv_err(1, format!("column `{name}` is missing")))
    };
    let (it, ip, iy, ir) = (
        find("time_s")?,
        find("pitch_deg")?,
        find("yaw_deg")?,
        find("roll_deg")?,
    );
    let mut m = MotionTrack::default();
    for (n, line) in lines.enumerate() {
        let line_no = n + 2;
        if line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split(',').map(str::trim).collect();
        let get = |i: usize| -> Result<f64, DataError> {
            let s = f
                .get(i)
                .ok_or_else(|| csv_err(line_no, format!("has {} fields", f.len())))?;
            let v: f64 = s
                .parse()
                .map_err(|_| csv_err(line_no, format!("`{s}` is not a number")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(csv_err(line_no, format!("`{s}` is not finite")))
            }
        };
        let t = get(it)?;
        if let Some(&last) = m.time_s.last() {
            if t <= last {
                return Err(csv_err(line_no, format!("time {t} does not increase")));
            }
        }
        m.time_s.push(t);
        m.pose_deg.push([get(ir)?, get(ip)?, get(iy)?]);
    }
    if m.time_s.len() < 4 {
        return Err(csv_err(0, "fewer than 4 rows of motion".into()));
    }
    Ok(m)
}

/// Finds the `<clip>.wav` + `<clip>.head.csv` pairs in `dir` (sorted by name), analyses the
/// audio at `config.frame_rate_hz` and pairs it with the resampled motion.
pub fn load_clips(dir: &Path, config: &AnalysisConfig) -> Result<Vec<TrainingClip>, DataError> {
    let folder = |source| DataError::Folder {
        path: dir.into(),
        source,
        holds: "<clip>.wav + <clip>.head.csv, e.g. ../shared/data/styletalk",
    };
    let names: Vec<String> = std::fs::read_dir(dir)
        .map_err(folder)?
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    let heads: Vec<&str> = names
        .iter()
        .filter_map(|n| n.strip_suffix(".head.csv"))
        .collect();
    // (stem, file name) of every audio file (any format pneuma-io reads).
    let audio: Vec<(&str, &str)> = names
        .iter()
        .filter_map(|n| pneuma_io::audio_stem(n).map(|s| (s, n.as_str())))
        .collect();
    let wavs: Vec<&str> = audio.iter().map(|a| a.0).collect();
    let mut stems: Vec<String> = heads
        .iter()
        .filter(|s| wavs.contains(s))
        .map(|s| s.to_string())
        .collect();
    stems.sort();
    // Which file of a pair is missing, named (at most five of each kind).
    let mut unmatched = Vec::new();
    let list = |v: Vec<&&str>, ext: &str| {
        let shown: Vec<String> = v.iter().take(5).map(|s| format!("{s}{ext}")).collect();
        let more = v.len().saturating_sub(5);
        let tail = if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        };
        format!("{}{tail}", shown.join(", "))
    };
    let lone_wavs: Vec<&&str> = audio
        .iter()
        .filter(|a| !heads.contains(&a.0))
        .map(|a| &a.1)
        .collect();
    let lone_heads: Vec<&&str> = heads.iter().filter(|s| !wavs.contains(s)).collect();
    if !lone_wavs.is_empty() {
        unmatched.push(format!("no .head.csv for {}", list(lone_wavs, "")));
    }
    if !lone_heads.is_empty() {
        unmatched.push(format!(
            "no audio file (.wav, .flac, …) for {}",
            list(lone_heads, ".head.csv")
        ));
    }
    if stems.is_empty() {
        return Err(DataError::NoClips {
            path: dir.into(),
            unmatched: if unmatched.is_empty() {
                "it holds no .wav and no .head.csv files".into()
            } else {
                unmatched.join("; ")
            },
        });
    }
    if !unmatched.is_empty() {
        eprintln!("note: {} skipped: {}", dir.display(), unmatched.join("; "));
    }
    let mut clips = Vec::with_capacity(stems.len());
    for stem in stems {
        let motion = read_head_csv(&dir.join(format!("{stem}.head.csv")))?;
        let name = audio.iter().find(|a| a.0 == stem).map_or("", |a| a.1);
        let frames = analyse_file(&dir.join(name), config)?;
        clips.push(TrainingClip::from_motion(
            &stem,
            config.frame_rate_hz,
            &frames,
            &motion,
        ));
    }
    Ok(clips)
}
