//! `pneuma eval breath-sounds [--data DIR] [--labels CSV] [--keele DIR] [--check]`: Pneuma's
//! inserted breaths against real inhalations labelled by hand in real speech, and the engine's
//! detection of the real ones.
//!
//! - **Labels** (`assets/labels/styletalk_breaths.csv`, format and kinds in [`crate::labels`]):
//!   a `breath` label is a broadband noise plateau above the room's floor between the end of a
//!   phrase's decay and the next onset. Every pause of at least 0.2 s in every clip was looked
//!   at on its spectrogram; a pause without a row holds no breath.
//! - **Spectrum**: the level in each third-octave band from 250 Hz to 6.3 kHz (Hann frames of
//!   512 samples, hop 256, powers averaged over the breath), as dB relative to the breath's own
//!   mean band level, so only the shape counts. A real breath's band powers have the clip's
//!   noise floor removed first (the median band power of the clip's quietest 5 % of frames,
//!   subtracted in power and never below a tenth of the measured power). An inserted breath is
//!   exactly what the engine added: output − input over the breath, from an offline render with
//!   the default settings and the whole-file lookahead, as `pneuma render` makes it.
//! - **Log-spectral distance**: the RMS over the bands of the difference of two shapes, dB. The
//!   report gives it between the mean real and the mean inserted shape, the median over the
//!   inserted breaths of each one's distance to the real mean, and for scale the median over the
//!   real breaths of each one's distance to the mean of the other real breaths.
//! - **Level** relative to the clip's speech median (the median RMS of voiced frames) and
//!   **duration**, real and inserted.
//! - **Detection**: the breaths the engine heard in the input (its existing breaths) against the
//!   labels, scored as [`crate::labels::score`] scores them.
//! - **Detection per speaker** ([`detect`]): the same scores on the
//!   styletalk and the Keele labels (`--keele`, `--keele-labels`), for the level-only rule, the
//!   default settings and the breath-shape limits fitted leave-one-speaker-out.
//!
//! The spectrum figures are printed only (the issue asks for the distance to be reported);
//! `--check` checks the detection's held-out targets.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use pneuma_core::engine::EngineConfig;
use realfft::RealFftPlanner;

pub mod detect;

use crate::breaths::render_offline;
use crate::data::{read_labels, wav_files, DataError};
use crate::labels::{score, Counts, Label, LabelKind};
use crate::stats::{median, rms_db};

/// Third-octave band centres compared, Hz (250 Hz to 6.3 kHz: where breath noise lies, above
/// mains hum and below the 16 kHz clips' Nyquist).
pub const BAND_CENTRES_HZ: [f64; 15] = [
    250.0, 315.0, 400.0, 500.0, 630.0, 800.0, 1000.0, 1250.0, 1600.0, 2000.0, 2500.0, 3150.0,
    4000.0, 5000.0, 6300.0,
];
/// Analysis frame, samples.
const FRAME: usize = 512;
/// Hop between frames, samples.
const HOP: usize = 256;

/// Arguments of `pneuma eval breath-sounds`.
#[derive(Debug, clap::Args)]
pub struct BreathSoundArgs {
    /// Folder with the labelled clips (`<clip>.wav`).
    #[arg(long, default_value = "../shared/data/styletalk")]
    pub data: PathBuf,
    /// The labels: `clip,start_s,end_s,kind` (`breath` or `unsure`).
    #[arg(long, default_value = "assets/labels/styletalk_breaths.csv")]
    pub labels: PathBuf,
    /// Folder with the Keele clips (`<clip>.wav`), the second labelled set for detection.
    #[arg(long, default_value = "../shared/data/keele")]
    pub keele: PathBuf,
    /// The Keele clips' labels.
    #[arg(long, default_value = "assets/labels/keele_breaths.csv")]
    pub keele_labels: PathBuf,
    /// Exit non-zero when a detection target is missed (see the module docs).
    #[arg(long)]
    pub check: bool,
}

/// Mean power per third-octave band ([`BAND_CENTRES_HZ`]) of `x` at `rate_hz`, Hann frames of
/// [`FRAME`] samples every [`HOP`] (one zero-padded frame when `x` is shorter).
pub fn band_powers(x: &[f32], rate_hz: f64) -> [f64; BAND_CENTRES_HZ.len()] {
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(FRAME);
    let window: Vec<f64> = (0..FRAME)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / FRAME as f64).cos())
        .collect();
    let mut input = fft.make_input_vec();
    let mut spectrum = fft.make_output_vec();
    let mut bands = [0.0; BAND_CENTRES_HZ.len()];
    let mut frames = 0usize;
    let mut start = 0;
    loop {
        for (i, v) in input.iter_mut().enumerate() {
            *v = x.get(start + i).map_or(0.0, |s| f64::from(*s)) * window[i];
        }
        fft.process(&mut input, &mut spectrum)
            .expect("buffers made by the plan");
        for (k, c) in spectrum.iter().enumerate() {
            let hz = k as f64 * rate_hz / FRAME as f64;
            if let Some(b) = band_of(hz) {
                bands[b] += c.norm_sqr();
            }
        }
        frames += 1;
        start += HOP;
        if start + FRAME > x.len() {
            break;
        }
    }
    bands.map(|p| p / frames as f64)
}

/// The band holding `hz`: edges at the centre × 2^(±1/6).
fn band_of(hz: f64) -> Option<usize> {
    let edge = 2f64.powf(1.0 / 6.0);
    BAND_CENTRES_HZ
        .iter()
        .position(|&c| hz >= c / edge && hz < c * edge)
}

/// Band levels as dB relative to their own mean (the shape of the spectrum).
pub fn shape_db(powers: &[f64; BAND_CENTRES_HZ.len()]) -> [f64; BAND_CENTRES_HZ.len()] {
    let db = powers.map(|p| 10.0 * p.max(1e-20).log10());
    let mean = db.iter().sum::<f64>() / db.len() as f64;
    db.map(|d| d - mean)
}

/// Log-spectral distance between two shapes: the RMS of their difference over the bands, dB.
pub fn distance_db(a: &[f64; BAND_CENTRES_HZ.len()], b: &[f64; BAND_CENTRES_HZ.len()]) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
    (sum / a.len() as f64).sqrt()
}

/// The mean of several shapes (NaN bands when there are none).
fn mean_shape(shapes: &[[f64; BAND_CENTRES_HZ.len()]]) -> [f64; BAND_CENTRES_HZ.len()] {
    let mut m = [0.0; BAND_CENTRES_HZ.len()];
    for s in shapes {
        for (a, b) in m.iter_mut().zip(s) {
            *a += b / shapes.len() as f64;
        }
    }
    if shapes.is_empty() {
        m = [f64::NAN; BAND_CENTRES_HZ.len()];
    }
    m
}

/// The noise floor's band powers: per band, the median over the quietest 5 % of the clip's
/// frames (by total power in the bands).
fn noise_floor(x: &[f32], rate_hz: f64) -> [f64; BAND_CENTRES_HZ.len()] {
    let mut frames: Vec<[f64; BAND_CENTRES_HZ.len()]> = x
        .chunks(FRAME)
        .filter(|c| c.len() == FRAME)
        .map(|c| band_powers(c, rate_hz))
        .collect();
    frames.sort_by(|a, b| a.iter().sum::<f64>().total_cmp(&b.iter().sum::<f64>()));
    let quiet = &frames[..(frames.len() / 20).max(1).min(frames.len())];
    std::array::from_fn(|b| {
        let v: Vec<f64> = quiet.iter().map(|f| f[b]).collect();
        median(&v)
    })
}

/// What one breath measured.
#[derive(Debug, Clone)]
struct Measured {
    shape: [f64; BAND_CENTRES_HZ.len()],
    duration_s: f64,
    level_re_speech_db: f64,
}

/// What a clip gave.
#[derive(Debug, Default)]
struct ClipResult {
    real: Vec<Measured>,
    inserted: Vec<Measured>,
    /// The engine's heard breaths against the labels.
    heard: Counts,
}

fn samples_of(x: &[f32], rate_hz: f64, (start_s, end_s): (f64, f64)) -> &[f32] {
    let a = ((start_s * rate_hz).round() as usize).min(x.len());
    let b = ((end_s * rate_hz).round() as usize).clamp(a, x.len());
    &x[a..b]
}

/// Renders one clip and measures its labelled and inserted breaths.
fn clip(path: &Path, labels: &[Label]) -> Result<ClipResult, String> {
    let (input, rate) =
        pneuma_io::read_mono(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rate_hz = f64::from(rate);
    // As `pneuma render` renders a file: the default settings, the whole-file lookahead.
    let out = render_offline(std::slice::from_ref(&input), rate_hz, None)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let frame_s = 1.0 / EngineConfig::default().analysis.frame_rate_hz;
    let voiced_db: Vec<f64> = out
        .frames
        .iter()
        .filter(|(f, _)| f.voiced)
        .map(|(f, _)| {
            rms_db(samples_of(
                &input,
                rate_hz,
                (f.time_s - frame_s, f.time_s + frame_s),
            ))
        })
        .collect();
    let speech_db = median(&voiced_db);
    let floor = noise_floor(&input, rate_hz);
    let mut r = ClipResult::default();
    for l in labels.iter().filter(|l| l.kind == LabelKind::Breath) {
        let x = samples_of(&input, rate_hz, (l.start_s, l.end_s));
        let p = band_powers(x, rate_hz);
        let clean: [f64; BAND_CENTRES_HZ.len()] =
            std::array::from_fn(|b| (p[b] - floor[b]).max(0.1 * p[b]));
        r.real.push(Measured {
            shape: shape_db(&clean),
            duration_s: l.end_s - l.start_s,
            level_re_speech_db: rms_db(x) - speech_db,
        });
    }
    r.heard = score(labels, &out.existing_breaths);
    let added: Vec<f32> = out.audio[0]
        .iter()
        .zip(&input)
        .map(|(o, i)| o - i)
        .collect();
    for b in &out.breaths {
        let x = samples_of(&added, rate_hz, (b.start_s, b.end_s));
        if x.len() < FRAME / 2 {
            continue;
        }
        r.inserted.push(Measured {
            shape: shape_db(&band_powers(x, rate_hz)),
            duration_s: b.end_s - b.start_s,
            level_re_speech_db: rms_db(x) - speech_db,
        });
    }
    Ok(r)
}

fn summary(label: &str, m: &[Measured]) {
    let d: Vec<f64> = m.iter().map(|x| x.duration_s).collect();
    let l: Vec<f64> = m.iter().map(|x| x.level_re_speech_db).collect();
    println!(
        "{label:<9} {:>3} breaths   duration median {:.3} s ({:.2}–{:.2})   level re speech median {:+.1} dB",
        m.len(),
        median(&d),
        d.iter().copied().fold(f64::INFINITY, f64::min),
        d.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        median(&l)
    );
}

/// Runs the evaluation and prints the report.
pub fn run(args: &BreathSoundArgs) -> Result<bool, String> {
    let labels = read_labels(&args.labels)?;
    let mut clips: BTreeMap<String, PathBuf> = BTreeMap::new();
    for path in wav_files(
        &args.data,
        "the styletalk clips (--data), e.g. ../shared/data/styletalk",
    )? {
        if let Some(stem) = path.file_stem() {
            clips.insert(stem.to_string_lossy().into_owned(), path);
        }
    }
    if let Some(l) = labels.iter().find(|l| !clips.contains_key(&l.clip)) {
        return Err(DataError::UnknownClip {
            labels: args.labels.clone(),
            clip: l.clip.clone(),
            data: args.data.clone(),
        }
        .into());
    }
    let (mut real, mut inserted) = (Vec::new(), Vec::new());
    let mut heard = Counts::default();
    println!("clip                   labelled found heard(true/false) inserted");
    for (name, path) in &clips {
        let mine: Vec<Label> = labels.iter().filter(|l| &l.clip == name).cloned().collect();
        let r = clip(path, &mine)?;
        println!(
            "{name:<22} {:>8} {:>5} {:>7}/{:<9} {:>8}",
            r.heard.labelled,
            r.heard.found,
            r.heard.heard_true,
            r.heard.heard_false,
            r.inserted.len()
        );
        heard.add(r.heard);
        real.extend(r.real);
        inserted.extend(r.inserted);
    }
    println!();
    summary("real", &real);
    summary("inserted", &inserted);
    let real_shapes: Vec<_> = real.iter().map(|m| m.shape).collect();
    let ins_shapes: Vec<_> = inserted.iter().map(|m| m.shape).collect();
    let (real_mean, ins_mean) = (mean_shape(&real_shapes), mean_shape(&ins_shapes));
    println!(
        "\nthird-octave band (Hz)  {}",
        bands_row(&BAND_CENTRES_HZ, 0)
    );
    println!("real, dB re mean        {}", bands_row(&real_mean, 1));
    println!("inserted, dB re mean    {}", bands_row(&ins_mean, 1));
    let each_inserted: Vec<f64> = ins_shapes
        .iter()
        .map(|s| distance_db(s, &real_mean))
        .collect();
    let real_spread: Vec<f64> = (0..real_shapes.len())
        .map(|i| {
            let others: Vec<_> = (0..real_shapes.len())
                .filter(|&j| j != i)
                .map(|j| real_shapes[j])
                .collect();
            distance_db(&real_shapes[i], &mean_shape(&others))
        })
        .collect();
    println!(
        "\nlog-spectral distance, mean inserted vs mean real: {:.1} dB",
        distance_db(&ins_mean, &real_mean)
    );
    println!(
        "  each inserted breath vs the real mean: median {:.1} dB; each real breath vs the other real ones (for scale): median {:.1} dB",
        median(&each_inserted),
        median(&real_spread)
    );
    println!(
        "\nreal breaths heard by the engine (its existing breaths): recall {}/{} ({:.0} %), precision {}/{} ({:.0} %; heard breaths over unsure labels not counted)",
        heard.found,
        heard.labelled,
        100.0 * heard.recall(),
        heard.heard_true,
        heard.heard_true + heard.heard_false,
        100.0 * heard.precision()
    );
    detect::report(&[
        (&args.data, &args.labels),
        (&args.keele, &args.keele_labels),
    ])
}

fn bands_row(v: &[f64], decimals: usize) -> String {
    v.iter()
        .map(|x| format!("{x:>6.decimals$}"))
        .collect::<Vec<_>>()
        .join("")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tone_lands_in_its_band_and_the_shape_is_relative_to_the_mean() {
        let rate = 16_000.0;
        let x: Vec<f32> = (0..8000)
            .map(|i| (2.0 * std::f64::consts::PI * 1000.0 * i as f64 / rate).sin() as f32)
            .collect();
        let p = band_powers(&x, rate);
        let loudest = (0..p.len()).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
        assert_eq!(BAND_CENTRES_HZ[loudest], 1000.0);
        // Two bands away the Hann window's leakage is at least 40 dB down.
        assert!(10.0 * (p[loudest] / p[loudest + 2]).log10() > 40.0, "{p:?}");
        let s = shape_db(&p);
        assert!(s.iter().sum::<f64>().abs() < 1e-9);
    }

    #[test]
    fn the_distance_is_zero_for_one_shape_and_grows_with_a_tilt() {
        let flat = [0.0; BAND_CENTRES_HZ.len()];
        assert_eq!(distance_db(&flat, &flat), 0.0);
        let tilt: [f64; BAND_CENTRES_HZ.len()] = std::array::from_fn(|b| b as f64 - 7.0);
        // RMS of -7..=7: sqrt(280 / 15).
        assert!((distance_db(&tilt, &flat) - (280.0f64 / 15.0).sqrt()).abs() < 1e-12);
    }
}
