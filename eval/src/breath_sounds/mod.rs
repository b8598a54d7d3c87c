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

pub mod detect;

use crate::breaths::render_offline;
use crate::data::{read_labels, wav_files, DataError};
use crate::labels::{score, Counts, Label, LabelKind, LabelledSets};
use crate::stats::{median, rms_db};
use pneuma_core::breathing::third_octave::{
    band_powers, distance_db, frame_len, mean_shape, noise_floor, shape_db, without_floor, Bands,
    BAND_CENTRES_HZ,
};

/// Arguments of `pneuma eval breath-sounds`.
#[derive(Debug, clap::Args)]
pub struct BreathSoundArgs {
    /// The labelled clips.
    #[command(flatten)]
    pub sets: LabelledSets,
    /// Exit non-zero when a detection target is missed (see the module docs).
    #[arg(long)]
    pub check: bool,
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
        let clean = without_floor(&p, &floor);
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
        if x.len() < frame_len(rate_hz) / 2 {
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
    let labels = read_labels(&args.sets.labels)?;
    let mut clips: BTreeMap<String, PathBuf> = BTreeMap::new();
    for path in wav_files(
        &args.sets.data,
        "the styletalk clips (--data), e.g. ../shared/data/styletalk",
    )? {
        if let Some(stem) = path.file_stem() {
            clips.insert(stem.to_string_lossy().into_owned(), path);
        }
    }
    if let Some(l) = labels.iter().find(|l| !clips.contains_key(&l.clip)) {
        return Err(DataError::UnknownClip {
            labels: args.sets.labels.clone(),
            clip: l.clip.clone(),
            data: args.sets.data.clone(),
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
    let real_spread = to_the_others_db(&real_shapes);
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
        (&args.sets.data, &args.sets.labels),
        (&args.sets.keele, &args.sets.keele_labels),
    ])
}

/// The distance of each of `shapes` to the mean of the others, dB.
pub fn to_the_others_db(shapes: &[Bands]) -> Vec<f64> {
    (0..shapes.len())
        .map(|i| {
            let others: Vec<Bands> = (0..shapes.len())
                .filter(|&j| j != i)
                .map(|j| shapes[j])
                .collect();
            distance_db(&shapes[i], &mean_shape(&others))
        })
        .collect()
}

fn bands_row(v: &[f64], decimals: usize) -> String {
    v.iter()
        .map(|x| format!("{x:>6.decimals$}"))
        .collect::<Vec<_>>()
        .join("")
}
