//! The trackers compared: Pneuma (as shipped and with held-out voicing models), the
//! `pitch-detection` crate's McLeod and YIN, Praat's `To Pitch (ac)` and the Python baselines
//! ([`super::baselines`]), each put on the scoring grid.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use pitch_detection::detector::mcleod::McLeodDetector;
use pitch_detection::detector::yin::YINDetector;
use pitch_detection::detector::PitchDetector;
use pneuma_core::AnalysisConfig;

use super::args::Args;
use super::baselines as f0_baselines;
use super::score::{frame_times, grid_len, on_grid, Clip, Internals, Track};
use super::targets::LOSO_NAME;
use crate::data::analyse;
use crate::data::reference::Source;

pub(crate) fn pneuma_track(
    audio: &[f32],
    rate: u32,
    config: &AnalysisConfig,
) -> Result<(Track, Internals), String> {
    let step = 1.0 / config.frame_rate_hz;
    let frames = analyse(audio, rate as f64, config).map_err(|e| e.to_string())?;
    let track: Track = frames
        .iter()
        .map(|f| if f.voiced { f.f0_hz } else { 0.0 })
        .collect();
    let internals: Internals = frames
        .iter()
        .map(|f| [f.voicing, f.rms_db, f.level_db])
        .collect();
    let n = grid_len(audio.len() as f64 / rate as f64);
    let times = frame_times(track.len(), config.frame_rate_hz);
    Ok((
        on_grid(&times, &track, step, n),
        on_grid(&times, &internals, step, n),
    ))
}

/// A `pitch-detection` detector with windows centred on the frame times `k / frame_rate_hz`.
pub(crate) fn crate_track(audio: &[f32], rate: u32, frame_rate_hz: f64, yin: bool) -> Track {
    const SIZE: usize = 2048;
    let mut mcleod = McLeodDetector::<f32>::new(SIZE, SIZE / 2);
    let mut yin_det = YINDetector::<f32>::new(SIZE, SIZE / 2);
    let power = SIZE as f32 * 1e-6;
    let mut window = vec![0.0f32; SIZE];
    let duration_s = audio.len() as f64 / rate as f64;
    let frames = (duration_s * frame_rate_hz).ceil() as usize;
    let track: Track = (0..frames)
        .map(|k| {
            let centre = (k as f64 / frame_rate_hz * rate as f64).round() as i64;
            for (i, w) in window.iter_mut().enumerate() {
                let j = centre - SIZE as i64 / 2 + i as i64;
                *w = if j >= 0 && (j as usize) < audio.len() {
                    audio[j as usize]
                } else {
                    0.0
                };
            }
            let p = if yin {
                yin_det.get_pitch(&window, rate as usize, power, 0.85)
            } else {
                mcleod.get_pitch(&window, rate as usize, power, 0.6)
            };
            match p {
                Some(p) if (50.0..=600.0).contains(&p.frequency) => p.frequency,
                _ => 0.0,
            }
        })
        .collect();
    let times = frame_times(track.len(), frame_rate_hz);
    on_grid(&times, &track, 1.0 / frame_rate_hz, grid_len(duration_s))
}

pub(crate) const PRAAT_SCRIPT: &str = r#"form args
  sentence in
  sentence out
  sentence step
endform
s = Read from file: in$
step = number(step$)
# Praat centres its frames in the sound: silence padded to a whole number of steps puts them
# at multiples of the step, the frame times of the other trackers.
dur = Get total duration
sr = Get sampling frequency
pad = ceiling(dur / step) * step - dur
if pad > 0.5 / sr
  z = Create Sound from formula: "pad", 1, 0, pad, sr, "0"
  selectObject: s, z
  s = Concatenate
endif
selectObject: s
p = To Pitch (ac): step, 50, 15, "no", 0.03, 0.45, 0.01, 0.35, 0.14, 600
n = Get number of frames
out_text$ = ""
for i to n
  t = Get time from frame number: i
  f = Get value in frame: i, "Hertz"
  if f = undefined
    f = 0
  endif
  out_text$ = out_text$ + fixed$(t, 5) + "," + fixed$(f, 3) + newline$
endfor
writeFile: out$, out_text$
"#;

pub(crate) fn praat_available() -> bool {
    Command::new("praat")
        .arg("--version")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Praat's `To Pitch (ac)` at a time step of `1 / frame_rate_hz` (its own frame times).
pub(crate) fn praat_track(
    wav: &Path,
    duration_s: f64,
    frame_rate_hz: f64,
    scratch: &Path,
) -> Result<Track, String> {
    let script = scratch.join("pitch.praat");
    if !script.exists() {
        std::fs::write(&script, PRAAT_SCRIPT).map_err(|e| e.to_string())?;
    }
    let out = scratch.join("praat_out.csv");
    // Praat resolves relative paths against the script's folder.
    let wav = std::fs::canonicalize(wav).map_err(|e| format!("{}: {e}", wav.display()))?;
    let status = Command::new("praat")
        .arg("--run")
        .arg(&script)
        .arg(&wav)
        .arg(&out)
        .arg(format!("{:.9}", 1.0 / frame_rate_hz))
        .output()
        .map_err(|e| format!("cannot run praat: {e}"))?;
    if !status.status.success() {
        return Err(format!(
            "praat failed on {}: {}",
            wav.display(),
            String::from_utf8_lossy(&status.stderr)
        ));
    }
    let text = std::fs::read_to_string(&out).map_err(|e| e.to_string())?;
    let (times, f0) = f0_baselines::parse_track(&text).map_err(|line| {
        format!(
            "praat wrote an unreadable line for {}: {line:?}",
            wav.display()
        )
    })?;
    // Each Praat frame at its own time.
    Ok(on_grid(
        &times,
        &f0,
        1.0 / frame_rate_hz,
        grid_len(duration_s),
    ))
}

/// The trackers compared, in table order: Pneuma (and its held-out column) first, then the
/// `pitch-detection` baselines, swift-f0 and pYIN when their Python runs, Praat last when present.
pub(crate) fn tracker_names(args: &Args, loso: bool, python: bool) -> (Vec<&'static str>, bool) {
    let use_praat = !args.no_praat && praat_available();
    if !args.no_praat && !use_praat {
        eprintln!("note: praat not found (Debian package `praat`); comparing without it");
    }
    let mut names = vec!["pneuma"];
    if loso {
        names.push(LOSO_NAME);
    }
    if !args.no_baselines {
        names.extend(["pd-mcleod", "pd-yin"]);
    }
    if python {
        names.push(f0_baselines::SWIFT_F0);
        if args.pyin {
            names.push(f0_baselines::PYIN);
        }
    }
    if use_praat {
        names.push("praat");
    }
    (names, use_praat)
}

/// The swift-f0/pYIN worker, when its Python is given or at the default place; a given one
/// that does not work is an error, a missing default a note.
pub(crate) fn start_python_baselines(
    args: &Args,
    scratch: &Path,
) -> Result<Option<f0_baselines::Baselines>, String> {
    let modules: &[&str] = if args.pyin {
        &["swift_f0", "librosa", "soundfile", "soxr"]
    } else {
        &["swift_f0", "soundfile", "soxr"]
    };
    match &args.baselines_python {
        Some(p) => f0_baselines::Baselines::start(p, scratch, modules).map(Some),
        None => {
            let p = Path::new(f0_baselines::DEFAULT_PYTHON);
            match f0_baselines::Baselines::start(p, scratch, modules) {
                Ok(b) => Ok(Some(b)),
                Err(e) => {
                    eprintln!("note: swift-f0/pYIN baselines left out: {e}");
                    Ok(None)
                }
            }
        }
    }
}

/// The trackers run as other programs: Praat, and the Python worker for swift-f0 and pYIN.
pub(crate) struct External {
    pub(crate) praat: bool,
    pub(crate) python: Option<f0_baselines::Baselines>,
}

/// Runs every tracker on one clip (Pneuma also with `held_out`, the voicing model fitted
/// without this clip's speaker, when given); adds each tracker's time to `seconds`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn evaluate(
    source: Source,
    data_set: usize,
    config: &AnalysisConfig,
    held_out: Option<&AnalysisConfig>,
    args: &Args,
    external: &mut External,
    scratch: &Path,
    seconds: &mut [f64],
) -> Result<Clip, String> {
    let frame_rate_hz = config.frame_rate_hz;
    let duration_s = source.audio.len() as f64 / source.rate as f64;
    let t = Instant::now();
    let (ours, internals) = pneuma_track(&source.audio, source.rate, config)?;
    seconds[0] += t.elapsed().as_secs_f64();
    let mut tracks = vec![ours];
    if let Some(held_out) = held_out {
        let t = Instant::now();
        tracks.push(pneuma_track(&source.audio, source.rate, held_out)?.0);
        seconds[1] += t.elapsed().as_secs_f64();
    }
    if !args.no_baselines {
        for yin in [false, true] {
            let t = Instant::now();
            tracks.push(crate_track(&source.audio, source.rate, frame_rate_hz, yin));
            seconds[tracks.len() - 1] += t.elapsed().as_secs_f64();
        }
    }
    // Praat and the Python baselines read files.
    let wav = match (&source.wav, external.praat || external.python.is_some()) {
        (Some(w), _) => Some(w.clone()),
        (None, true) => Some(write_scratch_wav(scratch, &source.audio, source.rate)?),
        (None, false) => None,
    };
    if let (Some(worker), Some(wav)) = (external.python.as_mut(), &wav) {
        let names: &[&str] = if args.pyin {
            &[f0_baselines::SWIFT_F0, f0_baselines::PYIN]
        } else {
            &[f0_baselines::SWIFT_F0]
        };
        for name in names {
            let t = Instant::now();
            let (times, f0) = worker.track(name, wav, 1.0 / frame_rate_hz)?;
            let step_s = times.get(1).zip(times.first()).map_or(0.01, |(b, a)| b - a);
            tracks.push(on_grid(&times, &f0, step_s, grid_len(duration_s)));
            seconds[tracks.len() - 1] += t.elapsed().as_secs_f64();
        }
    }
    if let (true, Some(wav)) = (external.praat, &wav) {
        let t = Instant::now();
        tracks.push(praat_track(wav, duration_s, frame_rate_hz, scratch)?);
        seconds[tracks.len() - 1] += t.elapsed().as_secs_f64();
    }
    Ok(Clip {
        name: source.name,
        data_set,
        speaker: source.speaker,
        condition: source.condition,
        internals,
        reference: source.reference,
        tracks,
    })
}

/// Writes generated audio (32-bit float) for Praat into the scratch folder.
pub(crate) fn write_scratch_wav(
    scratch: &Path,
    audio: &[f32],
    rate: u32,
) -> Result<PathBuf, String> {
    let path = scratch.join("generated.wav");
    crate::data::write_mono_wav(&path, audio, rate)?;
    Ok(path)
}
