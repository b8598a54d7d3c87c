//! `pneuma eval breaths [--voice WAV] [--data DIR] [--check]`: renders the example voice and
//! every `.wav` of a data folder offline with the default settings (as `pneuma render` does) and
//! measures the body the breathing gives them, per file and over all files:
//!
//! - `empty_voiced`: the share of voiced frames inside phrases with the lung empty (< 0.05);
//! - `reserve_voiced` (printed, not a target): the share with the lung under the reserve a
//!   planned breath group ends at (`RESERVE_LUNG`, 0.12): speech past the plan, drawing on the
//!   reserve;
//! - `empty_starts`: phrases longer than 1 s that start with an empty lung (count / phrases);
//! - breath duration median and range (seconds, from the inserted breaths);
//! - `rank_corr`: Spearman rank correlation of breath duration with the length of the pause
//!   that holds the breath (the run of non-speaking frames around the breath's middle);
//! - `level_re_speech_db`: median breath level relative to the median speech level, dB; the
//!   breath level is the RMS of what the engine added (output − input) over the breath, the
//!   speech level the median RMS of voiced frames inside phrases.
//!
//! Then the targets (met / MISSED). `--check` exits non-zero when one of the targets it
//! names (comma list of `empty_voiced,empty_starts,duration,rank_corr,level`; `all` for every
//! one) is missed.

use std::path::{Path, PathBuf};

use pneuma_core::breathing::reference::ReferenceVoice;
use pneuma_core::breathing::RESERVE_LUNG;
use pneuma_core::engine::replay::AnalysisRecord;
use pneuma_core::engine::voice_learning::{learn_voice, Learned, VoiceLearner};
use pneuma_core::engine::{offline, BreathVoiceMode, Engine, EngineConfig};
use pneuma_core::head::HeadModel;
use pneuma_core::ControlFrame;
use pneuma_io::wav::read_mono;

use crate::data::{wav_files, DataError};
use crate::stats::{median, rms_db, spearman};

/// Lung volume under which the lung counts as empty.
pub const EMPTY_LUNG: f32 = 0.05;
/// Phrases at least this long count for `empty_starts`, seconds.
pub const LONG_PHRASE_S: f64 = 1.0;

/// Arguments of `pneuma eval breaths`.
#[derive(Debug, clap::Args)]
pub struct BreathArgs {
    /// The example voice (rendered first).
    #[arg(long, default_value = "assets/examples/voice.wav")]
    pub voice: PathBuf,
    /// Folder whose `.wav` files are rendered too (e.g. ../shared/data/styletalk).
    #[arg(long)]
    pub data: Option<PathBuf>,
    /// Exit non-zero when one of these targets is missed: a comma list of `empty_voiced`,
    /// `empty_starts`, `duration`, `rank_corr`, `level`, or `all`.
    #[arg(long, value_delimiter = ',')]
    pub check: Vec<String>,
    /// Render as the plugin with this lookahead, ms (300 to 2000), instead of the offline
    /// render's whole-file lookahead.
    #[arg(long)]
    pub lookahead_ms: Option<f32>,
}

/// Figures of one rendered file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BreathFigures {
    /// Voiced frames inside phrases.
    pub voiced_frames: usize,
    /// Of those, frames with the lung empty.
    pub empty_voiced_frames: usize,
    /// Of those, frames with the lung under the reserve ([`RESERVE_LUNG`]).
    pub reserve_voiced_frames: usize,
    /// Phrases longer than [`LONG_PHRASE_S`].
    pub long_phrases: usize,
    /// Of those, phrases that start with the lung empty.
    pub empty_starts: usize,
    /// Per inserted breath: (duration s, length of the pause holding it s, level re speech dB).
    pub breaths: Vec<(f64, f64, f64)>,
}

/// Measures one render: its control frames (one per analysis frame, in order), the input and
/// output audio (mono) at `rate_hz` and the inserted breaths as (start s, end s).
pub fn measure(
    frames: &[ControlFrame],
    input: &[f32],
    output: &[f32],
    rate_hz: f64,
    breaths: &[(f64, f64)],
) -> BreathFigures {
    let mut fig = BreathFigures::default();
    let speech: Vec<f64> = frames
        .iter()
        .filter(|f| f.speaking && f.voiced)
        .map(|f| f.rms_db as f64)
        .collect();
    let speech_median_db = median(&speech);
    for f in frames.iter().filter(|f| f.speaking && f.voiced) {
        fig.voiced_frames += 1;
        if f.breathing.lung < EMPTY_LUNG {
            fig.empty_voiced_frames += 1;
        }
        if f.breathing.lung < RESERVE_LUNG - 1e-3 {
            fig.reserve_voiced_frames += 1;
        }
    }
    // Phrases: runs of speaking frames.
    let mut i = 0;
    while i < frames.len() {
        if !frames[i].speaking {
            i += 1;
            continue;
        }
        let mut j = i;
        while j + 1 < frames.len() && frames[j + 1].speaking {
            j += 1;
        }
        if frames[j].time_s - frames[i].time_s >= LONG_PHRASE_S {
            fig.long_phrases += 1;
            if frames[i].breathing.lung < EMPTY_LUNG {
                fig.empty_starts += 1;
            }
        }
        i = j + 1;
    }
    for &(start, end) in breaths {
        let mid = 0.5 * (start + end);
        let k = frames
            .partition_point(|f| f.time_s < mid)
            .min(frames.len().saturating_sub(1));
        let pause_s = if frames.is_empty() {
            0.0
        } else {
            let mut a = k;
            while a > 0 && !frames[a - 1].speaking {
                a -= 1;
            }
            let mut b = k;
            while b + 1 < frames.len() && !frames[b + 1].speaking {
                b += 1;
            }
            frames[b].time_s - frames[a].time_s
        };
        let s0 = ((start * rate_hz).max(0.0) as usize).min(output.len());
        let s1 = ((end * rate_hz).max(0.0) as usize).clamp(s0, output.len());
        let added: Vec<f32> = output[s0..s1]
            .iter()
            .zip(&input[s0..s1])
            .map(|(o, i)| o - i)
            .collect();
        fig.breaths
            .push((end - start, pause_s, rms_db(&added) - speech_median_db));
    }
    fig
}

/// Renders `input` (one `Vec` per channel, at `rate_hz`) offline with the default settings,
/// the built-in breath voice and `lookahead_ms` (`None`: the offline render's whole-file
/// lookahead, as `pneuma render` without `--lookahead-ms`).
pub fn render_offline(
    input: &[Vec<f32>],
    rate_hz: f64,
    lookahead_ms: Option<f32>,
) -> Result<offline::Rendered, String> {
    let mut config = EngineConfig::default();
    config.placement.whole_file = lookahead_ms.is_none();
    if let Some(ms) = lookahead_ms {
        config.placement.lookahead_s = ms / 1000.0;
    }
    // A whole-file render hears the file first (`pneuma render --built-in-breath`).
    let record = match lookahead_ms {
        None => heard(&config, input, rate_hz)?.record,
        Some(_) => None,
    };
    render_in(
        config,
        input,
        rate_hz,
        (BreathVoiceMode::BuiltIn, record),
        &BuiltIn::Shipped,
    )
}

/// What a whole-file render's learning pass hears of `input` (one `Vec` per channel, mixed
/// as the engine mixes them), with its analysis recorded for the render to replay.
fn heard(config: &EngineConfig, input: &[Vec<f32>], rate_hz: f64) -> Result<Learned, String> {
    let mut l = VoiceLearner::recording(config, rate_hz).map_err(|e| e.to_string())?;
    let channels = input.len().max(1);
    let len = input.iter().map(Vec::len).min().unwrap_or(0);
    let interleaved: Vec<f32> = (0..len)
        .flat_map(|i| input.iter().map(move |c| c[i]))
        .collect();
    l.feed_interleaved(&interleaved, channels)
        .map_err(|e| e.to_string())?;
    l.finish().map_err(|e| e.to_string())
}

/// Renders `input` offline with `config` (the default head model, blocks of 1024), the breath
/// voice `mode` and the built-in voice `built_in`.
fn render_in(
    config: EngineConfig,
    input: &[Vec<f32>],
    rate_hz: f64,
    (mode, record): (BreathVoiceMode, Option<AnalysisRecord>),
    built_in: &BuiltIn,
) -> Result<offline::Rendered, String> {
    let mut engine =
        Engine::new(config, HeadModel::default_model().clone()).map_err(|e| e.to_string())?;
    engine.set_voice_mode(mode);
    built_in.apply(&mut engine);
    engine
        .prepare(rate_hz, 1024, input.len())
        .map_err(|e| e.to_string())?;
    if let Some(record) = record {
        engine.replay_analysis(record).map_err(|e| e.to_string())?;
    }
    let out = offline::render(&mut engine, input, &[1024]);
    if engine.replay_verified() == Some(false) {
        return Err("the replayed analysis is not of this input".into());
    }
    Ok(out)
}

/// The built-in breath voice of a render.
#[derive(Debug, Clone, PartialEq)]
pub enum BuiltIn {
    /// The shipped one.
    Shipped,
    /// This one (fitted without the speakers scored).
    Given(Box<ReferenceVoice>),
    /// The procedural sound of earlier versions.
    Procedural,
}

impl BuiltIn {
    /// Gives `engine` this built-in voice.
    fn apply(&self, engine: &mut Engine) {
        match self {
            BuiltIn::Shipped => {}
            BuiltIn::Given(r) => engine.set_reference_voice(Some(**r)),
            BuiltIn::Procedural => engine.set_reference_voice(None),
        }
    }
}

/// Renders mono-or-more `input` as `pneuma render` does (the whole-file lookahead, the input
/// heard first and its analysis replayed, so the built-in voice is coloured by the whole
/// input's speech) with `config` (`EngineConfig::default()`: the default settings), the breath
/// voice learned from `learn_from` (`None`: the built-in voice) and the engine's seed moved by
/// `seed_offset`.
pub fn render_with_voice(
    config: &EngineConfig,
    input: &[Vec<f32>],
    rate_hz: f64,
    learn_from: Option<&[f32]>,
    built_in: &BuiltIn,
    seed_offset: u64,
) -> Result<offline::Rendered, String> {
    let mut config = config.clone();
    config.placement.whole_file = true;
    config.seed = config.seed.wrapping_add(seed_offset);
    let heard = heard(&config, input, rate_hz)?;
    let voice = match learn_from {
        Some(mono) => learn_voice(&config, mono, rate_hz).map_err(|e| e.to_string())?,
        None => None,
    };
    let mode = voice.map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Fixed);
    render_in(config, input, rate_hz, (mode, heard.record), built_in)
}

/// Renders mono-or-more `input` as the plugin does (`pneuma render --lookahead-ms`, `config`'s
/// lookahead): the breath voice learned as the stream goes, from the breaths heard before each
/// inserted one (`built_in` before the first); the engine's seed moved by `seed_offset`.
pub fn render_learning_as_it_goes(
    config: &EngineConfig,
    input: &[Vec<f32>],
    rate_hz: f64,
    built_in: &BuiltIn,
    seed_offset: u64,
) -> Result<offline::Rendered, String> {
    let mut config = config.clone();
    config.placement.whole_file = false;
    config.seed = config.seed.wrapping_add(seed_offset);
    render_in(
        config,
        input,
        rate_hz,
        (BreathVoiceMode::Learn, None),
        built_in,
    )
}

/// Renders `path` offline with the default settings and `lookahead_ms` (see
/// [`render_offline`]) and measures it.
pub fn render_and_measure(path: &Path, lookahead_ms: Option<f32>) -> Result<BreathFigures, String> {
    let (input, rate) = read_mono(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let out = render_offline(std::slice::from_ref(&input), rate as f64, lookahead_ms)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let frames: Vec<ControlFrame> = out.frames.iter().map(|(f, _)| *f).collect();
    let breaths: Vec<(f64, f64)> = out.breaths.iter().map(|b| (b.start_s, b.end_s)).collect();
    Ok(measure(
        &frames,
        &input,
        &out.audio[0],
        rate as f64,
        &breaths,
    ))
}

/// The figures printed per file and overall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Share of voiced phrase frames with the lung empty, 0..1.
    pub empty_voiced: f64,
    /// Share of voiced phrase frames with the lung under the reserve, 0..1.
    pub reserve_voiced: f64,
    /// Long phrases starting empty / long phrases.
    pub empty_starts: (usize, usize),
    /// Breaths inserted.
    pub breaths: usize,
    /// Breath duration median, min, max, seconds.
    pub duration_s: [f64; 3],
    /// Spearman correlation of duration with pause length.
    pub rank_corr: f64,
    /// Median breath level relative to the median speech level, dB.
    pub level_db: f64,
}

/// Summarises the figures of one or more files together.
pub fn summarise(figs: &[&BreathFigures]) -> Summary {
    let voiced: usize = figs.iter().map(|f| f.voiced_frames).sum();
    let empty: usize = figs.iter().map(|f| f.empty_voiced_frames).sum();
    let reserve: usize = figs.iter().map(|f| f.reserve_voiced_frames).sum();
    let share = |n: usize| {
        if voiced > 0 {
            n as f64 / voiced as f64
        } else {
            0.0
        }
    };
    let all: Vec<(f64, f64, f64)> = figs.iter().flat_map(|f| f.breaths.clone()).collect();
    let d: Vec<f64> = all.iter().map(|b| b.0).collect();
    let p: Vec<f64> = all.iter().map(|b| b.1).collect();
    let l: Vec<f64> = all.iter().map(|b| b.2).collect();
    Summary {
        empty_voiced: share(empty),
        reserve_voiced: share(reserve),
        empty_starts: (
            figs.iter().map(|f| f.empty_starts).sum(),
            figs.iter().map(|f| f.long_phrases).sum(),
        ),
        breaths: all.len(),
        duration_s: [
            median(&d),
            d.iter().copied().fold(f64::NAN, f64::min),
            d.iter().copied().fold(f64::NAN, f64::max),
        ],
        rank_corr: spearman(&d, &p),
        level_db: median(&l),
    }
}

/// The targets on the overall summary and on every file: (name, description, met).
pub fn targets(per_file: &[(String, Summary)], all: &Summary) -> Vec<(&'static str, String, bool)> {
    let mut t = Vec::new();
    for (name, s) in per_file {
        t.push((
            "empty_voiced",
            format!(
                "{name}: lung empty on under 5 % of voiced frames: {:.1} %",
                100.0 * s.empty_voiced
            ),
            s.empty_voiced < 0.05,
        ));
        t.push((
            "empty_starts",
            format!(
                "{name}: no phrase over 1 s starts with an empty lung: {} of {}",
                s.empty_starts.0, s.empty_starts.1
            ),
            s.empty_starts.0 == 0,
        ));
    }
    let [med, _, _] = all.duration_s;
    t.push((
        "duration",
        format!("breath duration median within 0.3–0.5 s: {med:.3} s"),
        (0.3..=0.5).contains(&med),
    ));
    t.push((
        "rank_corr",
        format!(
            "longer breaths in longer pauses, rank correlation > 0.5: {:.2}",
            all.rank_corr
        ),
        all.rank_corr > 0.5,
    ));
    t.push((
        "level",
        format!(
            "breath level median 17–24 dB under the speech median: {:.1} dB",
            all.level_db
        ),
        (-24.0..=-17.0).contains(&all.level_db),
    ));
    t
}

fn row(name: &str, s: &Summary) {
    println!(
        "{name},{:.2},{:.2},{},{},{},{:.3},{:.3},{:.3},{:.2},{:.1}",
        100.0 * s.empty_voiced,
        100.0 * s.reserve_voiced,
        s.empty_starts.0,
        s.empty_starts.1,
        s.breaths,
        s.duration_s[0],
        s.duration_s[1],
        s.duration_s[2],
        s.rank_corr,
        s.level_db
    );
}

/// Runs `pneuma eval breaths`; returns whether every checked target was met.
pub fn run(args: &BreathArgs) -> Result<bool, String> {
    for c in &args.check {
        if ![
            "all",
            "empty_voiced",
            "empty_starts",
            "duration",
            "rank_corr",
            "level",
        ]
        .contains(&c.as_str())
        {
            return Err(format!("--check {c} is not a target: use empty_voiced, empty_starts, duration, rank_corr, level or all"));
        }
    }
    let mut files = vec![args.voice.clone()];
    if let Some(dir) = &args.data {
        let wavs = wav_files(dir, ".wav files (--data), e.g. ../shared/data/styletalk")?;
        if wavs.is_empty() {
            return Err(DataError::Empty {
                path: dir.clone(),
                what: ".wav files",
            }
            .into());
        }
        files.extend(wavs);
    }
    match args.lookahead_ms {
        None => println!(
            "offline renders, default settings (lookahead mode, whole-file lookahead, neutral preset)"
        ),
        Some(ms) => println!(
            "renders as the plugin, default settings (lookahead mode, {ms} ms lookahead, neutral preset)"
        ),
    }
    println!("file,empty_voiced_pct,reserve_voiced_pct,empty_starts,long_phrases,breaths,duration_median_s,duration_min_s,duration_max_s,rank_corr,level_re_speech_db");
    let mut figs = Vec::new();
    for f in &files {
        let fig = render_and_measure(f, args.lookahead_ms)?;
        let name = f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        row(&name, &summarise(&[&fig]));
        figs.push((name, fig));
    }
    let all = summarise(&figs.iter().map(|(_, f)| f).collect::<Vec<_>>());
    row("all", &all);
    let per_file: Vec<(String, Summary)> = figs
        .iter()
        .map(|(n, f)| (n.clone(), summarise(&[f])))
        .collect();
    println!("targets:");
    let mut ok = true;
    for (name, what, met) in targets(&per_file, &all) {
        let checked = args.check.iter().any(|c| c == name || c == "all");
        println!("  [{}] {what}", if met { "met" } else { "MISSED" });
        ok &= met || !checked;
    }
    Ok(ok)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(i: u64, speaking: bool, lung: f32) -> ControlFrame {
        let mut f = ControlFrame {
            index: i,
            time_s: i as f64 / 100.0,
            voiced: speaking,
            speaking,
            rms_db: -20.0,
            ..ControlFrame::default()
        };
        f.breathing.lung = lung;
        f
    }

    #[test]
    fn empty_lung_phrases_pauses_and_breath_level() {
        // 0–2 s speech with a full lung, 2–3 s pause with a breath 2.4–2.8 s, 3–5 s speech
        // whose second half has an empty lung, 5–5.2 s pause, 5.2–6.5 s speech starting empty.
        let frames: Vec<ControlFrame> = (0..650u64)
            .map(|i| match i {
                0..200 => frame(i, true, 0.8),
                200..300 => frame(i, false, 0.5),
                300..400 => frame(i, true, 0.5),
                400..500 => frame(i, true, 0.0),
                500..520 => frame(i, false, 0.0),
                _ => frame(i, true, 0.0),
            })
            .collect();
        let rate = 1000.0;
        let input = vec![0.0f32; 6500];
        let mut output = input.clone();
        // A breath of RMS 0.01 (−40 dBFS), 20 dB under the −20 dB speech.
        for (k, s) in output[2400..2800].iter_mut().enumerate() {
            *s = if k % 2 == 0 { 0.01 } else { -0.01 };
        }
        let fig = measure(&frames, &input, &output, rate, &[(2.4, 2.8)]);
        assert_eq!(fig.voiced_frames, 530);
        assert_eq!(fig.empty_voiced_frames, 100 + 130);
        // Under the 0.12 reserve: the same frames (the others hold 0.5 and 0.8).
        assert_eq!(fig.reserve_voiced_frames, 100 + 130);
        assert_eq!((fig.empty_starts, fig.long_phrases), (1, 3));
        assert_eq!(fig.breaths.len(), 1);
        let (d, p, l) = fig.breaths[0];
        assert!((d - 0.4).abs() < 1e-9 && (p - 0.99).abs() < 1e-9, "{d} {p}");
        assert!((l + 20.0).abs() < 0.01, "{l}");
        // A lung at 0.1 is drawing on the reserve, not empty.
        let low: Vec<ControlFrame> = (0..10u64).map(|i| frame(i, true, 0.1)).collect();
        let fig = measure(&low, &[0.0; 100], &[0.0; 100], 1000.0, &[]);
        assert_eq!(
            (fig.empty_voiced_frames, fig.reserve_voiced_frames),
            (0, 10)
        );
    }
}
