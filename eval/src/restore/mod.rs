//! `pneuma eval restore [--data DIR] [--labels CSV] [--keele DIR] [--keele-labels CSV]
//! [--check]`: cut the real breaths out of real speech as an editor does, render, and measure
//! how Pneuma puts them back.
//!
//! - **Breaths**: every `breath` label (clear inhalations; `unsure` ones are left in place) of
//!   the styletalk and Keele labels ([`crate::labels`]). The speaker of a clip is
//!   [`crate::breath_sounds::detect::speaker_of`]'s.
//! - **Cuts** ([`Cut`]): gated to digital silence, attenuated by 30 dB, and gated with the
//!   span shortened by 40 % (the editors' "shorten gaps": the middle 40 % of the breath's span
//!   is removed and everything after it moves earlier).
//! - **Runs** ([`Run`]): every breath of a clip cut at once, or one breath at a time (the
//!   others stay in the recording, as a voice learned from the recording hears them).
//! - **Voices** ([`Voice`]): the built-in breath voice; the voice `pneuma render` learns from
//!   the recording it renders (cut one at a time, the breath being restored is not in the
//!   recording: a **held-out** figure); the voice learned from the uncut recording, the
//!   restored breath included (a **fitted** figure, the `--breath-like` of the raw take); the
//!   voice the plugin (and `pneuma render --lookahead-ms`) learns as the stream goes, with its
//!   default lookahead, from the breaths heard before each inserted one (held out: the breath
//!   restored is cut). Only the whole-file learned voice is checked against the targets.
//! - **Scores** ([`score`]): a cut breath is *put back* when an inserted breath overlaps its
//!   span widened by 0.15 s on each side (each inserted breath counts for one cut breath). An
//!   inserted breath that puts none back and overlaps no breath inserted in the render of the
//!   uncut clip (same voice) is *extra*. For each breath put back: its level against the real
//!   breath's, dB, both measured the same way: the mean square in the third-octave bands
//!   ([`pneuma_core::breathing::third_octave::band_level_db`]) of what the engine added (output
//!   − input) over the inserted span, and of the real breath over its label with the clip's
//!   noise floor taken out per band (what the engine adds holds no floor); its duration against
//!   the label's; the third-octave shape distance
//!   ([`pneuma_core::breathing::third_octave`], 250 Hz–6.3 kHz, each shape relative to its own
//!   mean level) of the inserted breath to the real one it replaces (the real one's band powers
//!   with the clip's noise floor taken out). For scale, per speaker: the median distance
//!   between two of the speaker's real breaths, and the spread of the inserted and of the real
//!   shapes (the median distance of each to the mean of its set).
//! - **Left in** (`left_in`): the uncut clips rendered, the real breaths heard and the
//!   inserted breaths over a labelled one (doubled).
//! - **Two voices** (`two_voices`): every pair of speakers' breaths pooled, as in an
//!   interview: the blend a learner learns from them against the built-in voice.
//! - **Interview** (`interview`, also with `--judged-only`; reported only): five pairs of
//!   Keele speakers in alternating turns, the guest level with the host and 12 dB under, every
//!   other breath of each gated: the level of the breaths put back before each speaker.
//!
//! `--check` checks the targets on the held-out figures (see [`targets`]).

use std::collections::BTreeMap;
use std::path::Path;

use pneuma_core::breathing::third_octave::{
    band_level_db, band_powers, distance_db, frame_len, noise_floor, shape_db, without_floor, Bands,
};
use pneuma_core::engine::offline::Rendered;
use pneuma_core::engine::PlacementMode;

use crate::breath_sounds::detect::speaker_of;
use crate::breaths::BuiltIn;
use crate::data::{read_labels, DataError};
pub use crate::labels::LabelledSets;
use crate::labels::{Label, LabelKind};
use crate::noise::{add_noise, Colour};
use crate::stats::median;
use pneuma_core::breathing::reference::ReferenceVoice;
use pneuma_core::engine::voice_learning::{learn_voice, VoiceLearner};
use pneuma_core::engine::EngineConfig;

mod cut;
mod interview;
mod left_in;
mod length_fit;
mod lung;
pub mod reference;
mod report;
mod two_voices;

pub use cut::Cut;
use left_in::UncutRender;
use report::{print_table, targets};

/// How near a cut breath an inserted one must lie to put it back, seconds (each side).
pub const PUT_BACK_S: f64 = 0.15;

/// Arguments of `pneuma eval restore`.
#[derive(Debug, clap::Args)]
pub struct RestoreArgs {
    /// The labelled clips.
    #[command(flatten)]
    pub sets: LabelledSets,
    /// Exit non-zero when a held-out target is missed.
    #[arg(long)]
    pub check: bool,
    /// Only the held-out rows the targets judge (the learned voice cut three ways, the plugin's
    /// voice learned as it goes, the built-in voice fitted without the speaker, the breaths left
    /// in) and the interview restore (reported only): about half the time. Leaves out the fitted
    /// and earlier voices, the two-voice comparison and the length grid.
    #[arg(long)]
    pub judged_only: bool,
    /// Record every clip in a noisier room first: seeded pink noise this many dB under the
    /// clip's speech level (the median level of its voiced frames, which breath levels are
    /// measured against) is mixed in before anything is cut or learned.
    #[arg(long, value_name = "DB")]
    pub room_db: Option<f64>,
}

/// Which breaths are cut in one render.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Run {
    /// Every labelled breath of the clip.
    AllAtOnce,
    /// One breath per render; the others stay.
    OneAtATime,
}

/// The breath voice a render uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Voice {
    /// The shipped built-in voice (fitted on every labelled speaker, the one scored included).
    BuiltIn,
    /// The built-in voice fitted without the speaker scored, coloured by the channel (held
    /// out).
    BuiltInHeldOut,
    /// The same, not coloured.
    BuiltInHeldOutPlain,
    /// The procedural built-in voice of earlier versions.
    Procedural,
    /// Learned from the recording rendered (as `pneuma render` does).
    Learned,
    /// Learned from the uncut recording (the breath restored included: fitted).
    FromUncut,
    /// Learned as the stream goes, as the plugin and `pneuma render --lookahead-ms` do (the
    /// default lookahead): from the breaths heard before each inserted one (held out).
    AsItGoes,
}

impl Voice {
    /// A voice of the held-out rows `--judged-only` keeps.
    fn is_judged(self) -> bool {
        matches!(
            self,
            Voice::Learned | Voice::AsItGoes | Voice::BuiltInHeldOut
        )
    }
}

/// A row `--judged-only` keeps: a judged voice, but not the voice learned from a file with every
/// breath cut (a row of earlier work).
fn is_judged_row(run: Run, voice: Voice) -> bool {
    voice.is_judged() && (run, voice) != (Run::AllAtOnce, Voice::Learned)
}

/// One labelled clip.
pub struct Clip {
    name: String,
    speaker: String,
    rate_hz: f64,
    audio: Vec<f32>,
    /// Its speech level as the engine's learner measures it, dBFS.
    speech_db: f64,
    /// Its voiced speech's long-term third-octave spectrum, dB per band.
    speech_ltas_db: Bands,
    /// The clear breaths, in time order.
    breaths: Vec<(f64, f64)>,
    /// The unsure labels (breath-like noise that may be a breath), in time order.
    unsure: Vec<(f64, f64)>,
    /// Each breath's shape, floor taken out.
    real_shapes: Vec<Bands>,
    /// Each breath's level (floor taken out), dBFS.
    real_levels_db: Vec<f64>,
    /// The level of its noise floor (the room) measured as the breaths' levels are, dBFS.
    room_level_db: f64,
}

/// What one cut breath gave.
#[derive(Debug, Clone, Copy)]
pub struct Restored {
    /// Level of the inserted breath minus the real one's, dB.
    pub level_db: f64,
    /// Duration of the inserted breath over the real one's.
    pub duration_ratio: f64,
    /// The inserted breath's shape.
    pub shape: Bands,
    /// Its distance to the real breath it replaces, dB.
    pub distance_db: f64,
    /// Its start minus the real one's (where the cut left it), seconds: positive is later.
    pub start_offset_s: f64,
    /// Its end minus the real one's, seconds.
    pub end_offset_s: f64,
}

/// What a set of renders gave for one speaker.
#[derive(Debug, Clone, Default)]
pub struct SpeakerResult {
    /// Breaths cut.
    pub cut: usize,
    /// Per cut breath: what was put back (`None`: nothing).
    pub restored: Vec<Option<Restored>>,
    /// Inserted breaths that put no breath back and are not in the uncut render.
    pub extra: usize,
    /// The cut breaths nothing put back: clip, labelled span (seconds, uncut clip).
    pub missed: Vec<(String, (f64, f64))>,
    /// The speaker's real shapes.
    pub real_shapes: Vec<Bands>,
    /// The speaker's real breath levels, each against its clip's speech level, dB.
    pub real_levels_re_speech_db: Vec<f64>,
}

/// The quietest room `--room-db` takes, dB under the speech: quieter rooms add nothing the
/// clips' own floors do not hold.
const ROOM_DB_MAX: f64 = 80.0;
/// Seed of a clip's room noise (`--room-db`), plus the clip's place in its set and the set's
/// offset ([`ROOM_SEED_SET_STEP`] for the second).
const ROOM_SEED: u64 = 31;
/// How far apart the two sets' room seeds start (more clips than any set holds).
const ROOM_SEED_SET_STEP: u64 = 1_000;

/// The voice learner of a whole-file render (`pneuma render`'s) fed the clip `name`'s `audio`.
fn whole_file_learner(audio: &[f32], rate_hz: f64, name: &str) -> Result<VoiceLearner, String> {
    let mut config = EngineConfig::default();
    config.placement.whole_file = true;
    let mut learner = VoiceLearner::new(&config, rate_hz).map_err(|e| format!("{name}: {e}"))?;
    learner.feed(audio).map_err(|e| format!("{name}: {e}"))?;
    Ok(learner)
}

/// The clip `name` at `path`, mono, in a room `room_db` under its speech level when given
/// (seeded with `seed`), and its rate.
fn read_clip(
    path: &Path,
    name: &str,
    room_db: Option<f64>,
    seed: u64,
) -> Result<(Vec<f32>, f64), String> {
    let (audio, rate) =
        pneuma_io::read_mono(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let rate_hz = f64::from(rate);
    let Some(room_db) = room_db else {
        return Ok((audio, rate_hz));
    };
    let speech_db = whole_file_learner(&audio, rate_hz, name)?.speech_db();
    if !speech_db.is_finite() {
        return Err(format!(
            "{name}: no voiced frame to set the room's level by (--room-db needs speech)"
        ));
    }
    let noise_rms = 10f64.powf((speech_db - room_db) / 20.0);
    Ok((add_noise(&audio, noise_rms, Colour::Pink, seed), rate_hz))
}

/// The labelled clips of one set; `room`: the room's level under the speech and the set's first
/// seed.
fn load(data: &Path, labels_path: &Path, room: (Option<f64>, u64)) -> Result<Vec<Clip>, String> {
    let (room_db, seed) = room;
    let labels = read_labels(labels_path)?;
    let mut by_clip: BTreeMap<String, Vec<Label>> = BTreeMap::new();
    for l in labels {
        by_clip.entry(l.clip.clone()).or_default().push(l);
    }
    by_clip
        .into_iter()
        .filter(|(_, ls)| ls.iter().any(|l| l.kind == LabelKind::Breath))
        .enumerate()
        .map(|(k, (name, ls))| {
            let span = |l: &Label| (l.start_s, l.end_s);
            let mut unsure: Vec<(f64, f64)> = ls
                .iter()
                .filter(|l| l.kind == LabelKind::Unsure)
                .map(span)
                .collect();
            unsure.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut ls: Vec<Label> = ls
                .into_iter()
                .filter(|l| l.kind == LabelKind::Breath)
                .collect();
            let path = data.join(format!("{name}.wav"));
            if !path.exists() {
                return Err(DataError::UnknownClip {
                    labels: labels_path.into(),
                    clip: name,
                    data: data.into(),
                }
                .into());
            }
            let (audio, rate_hz) = read_clip(&path, &name, room_db, seed + k as u64)?;
            ls.sort_by(|a, b| a.start_s.total_cmp(&b.start_s));
            let floor = noise_floor(&audio, rate_hz);
            let breaths: Vec<(f64, f64)> = ls.iter().map(|l| (l.start_s, l.end_s)).collect();
            let real_powers: Vec<Bands> = breaths
                .iter()
                .map(|&span| {
                    let p = band_powers(samples_of(&audio, rate_hz, span), rate_hz);
                    without_floor(&p, &floor)
                })
                .collect();
            let real_shapes = real_powers.iter().map(shape_db).collect();
            let real_levels_db = real_powers
                .iter()
                .map(|p| band_level_db(p, rate_hz))
                .collect();
            let learner = whole_file_learner(&audio, rate_hz, &name)?;
            Ok(Clip {
                speech_db: learner.speech_db(),
                speech_ltas_db: learner.speech_ltas_db(),
                speaker: speaker_of(&name),
                name,
                rate_hz,
                audio,
                breaths,
                unsure,
                real_shapes,
                real_levels_db,
                room_level_db: band_level_db(&floor, rate_hz),
            })
        })
        .collect()
}

/// The samples of `x` in `span` (seconds), clamped to `x`.
pub fn samples_of(x: &[f32], rate_hz: f64, (start_s, end_s): (f64, f64)) -> &[f32] {
    let a = ((start_s * rate_hz).round().max(0.0) as usize).min(x.len());
    let b = ((end_s * rate_hz).round().max(0.0) as usize).clamp(a, x.len());
    &x[a..b]
}

/// Renders `input` as `pneuma render` does with `config`, with `voice` (`uncut`: the recording
/// before the cut, for [`Voice::FromUncut`]; `held_out`: the built-in voice fitted without the
/// clip's speaker) and the engine's seed moved by `seed_offset`.
#[allow(clippy::too_many_arguments)]
fn render(
    config: &EngineConfig,
    input: &[f32],
    uncut: &[f32],
    rate_hz: f64,
    voice: Voice,
    held_out: &ReferenceVoice,
    seed_offset: u64,
) -> Result<Rendered, String> {
    let built_in = match voice {
        Voice::BuiltInHeldOut => BuiltIn::Given(Box::new(*held_out)),
        Voice::BuiltInHeldOutPlain => BuiltIn::Given(Box::new(ReferenceVoice {
            colour_by_channel: false,
            ..*held_out
        })),
        Voice::Procedural => BuiltIn::Procedural,
        // The shipped built-in voice is fitted on every speaker, the one scored included: only
        // its own row uses it. Every other voice falls back (nothing heard yet, or at all) on
        // the built-in voice fitted without the speaker.
        Voice::BuiltIn => BuiltIn::Shipped,
        _ => BuiltIn::Given(Box::new(*held_out)),
    };
    let learn_from = match voice {
        Voice::BuiltIn | Voice::BuiltInHeldOut | Voice::BuiltInHeldOutPlain | Voice::Procedural => {
            None
        }
        Voice::Learned => Some(input),
        Voice::FromUncut => Some(uncut),
        Voice::AsItGoes => {
            return crate::breaths::render_learning_as_it_goes(
                config,
                std::slice::from_ref(&input.to_vec()),
                rate_hz,
                &built_in,
                seed_offset,
            )
        }
    };
    crate::breaths::render_with_voice(
        config,
        std::slice::from_ref(&input.to_vec()),
        rate_hz,
        learn_from,
        &built_in,
        seed_offset,
    )
}

/// The lung of every control frame, at the frame's time in the input.
fn lung_of(out: &Rendered) -> Vec<(f64, f32)> {
    out.frames
        .iter()
        .map(|(f, _)| (f.time_s, f.breathing.lung))
        .collect()
}

/// What the engine added to `input` in the render `out` (output − input, first channel).
fn added(out: &Rendered, input: &[f32]) -> Vec<f32> {
    out.audio[0].iter().zip(input).map(|(o, i)| o - i).collect()
}

/// The inserted breath of `out` that puts back the cut breath spanning `(s, e)` (seconds): of
/// those not `used` yet that overlap the span widened by [`PUT_BACK_S`] on each side, the one
/// overlapping it most, marked used; `None` when there is none.
fn put_back(out: &Rendered, used: &mut [bool], (s, e): (f64, f64)) -> Option<usize> {
    let overlap = |j: usize| out.breaths[j].end_s.min(e) - out.breaths[j].start_s.max(s);
    let j = (0..out.breaths.len())
        .filter(|&j| {
            let b = &out.breaths[j];
            !used[j] && b.start_s < e + PUT_BACK_S && s - PUT_BACK_S < b.end_s
        })
        .max_by(|&a, &b| overlap(a).total_cmp(&overlap(b)))?;
    used[j] = true;
    Some(j)
}

/// Scores one render of `clip` cut at the breaths `cut_idx` with `cut`: adds to `result`.
#[allow(clippy::too_many_arguments)]
fn score(
    clip: &Clip,
    cut: Cut,
    cut_idx: &[usize],
    cut_input: &[f32],
    out: &Rendered,
    uncut_inserted: &[(f64, f64)],
    result: &mut SpeakerResult,
) {
    let rate = clip.rate_hz;
    let spans: Vec<(f64, f64)> = cut_idx.iter().map(|&i| clip.breaths[i]).collect();
    let moved = cut.moved_spans(&clip.breaths, cut_idx);
    let added = added(out, cut_input);
    let mut used = vec![false; out.breaths.len()];
    for (k, &i) in cut_idx.iter().enumerate() {
        let (s, e) = moved[k];
        result.cut += 1;
        let Some(j) = put_back(out, &mut used, (s, e)) else {
            result.restored.push(None);
            result.missed.push((clip.name.clone(), clip.breaths[i]));
            continue;
        };
        let b = &out.breaths[j];
        let x = samples_of(&added, rate, (b.start_s, b.end_s));
        let powers = band_powers(x, rate);
        let shape = if x.len() >= frame_len(rate) / 2 {
            shape_db(&powers)
        } else {
            [f64::NAN; pneuma_core::breathing::third_octave::BANDS]
        };
        result.restored.push(Some(Restored {
            level_db: band_level_db(&powers, rate) - clip.real_levels_db[i],
            duration_ratio: (b.end_s - b.start_s) / (spans[k].1 - spans[k].0),
            shape,
            distance_db: distance_db(&shape, &clip.real_shapes[i]),
            start_offset_s: b.start_s - s,
            end_offset_s: b.end_s - e,
        }));
    }
    let uncut_moved: Vec<(f64, f64)> = uncut_inserted
        .iter()
        .map(|&(s, e)| {
            (
                cut.map_time(&clip.breaths, cut_idx, s),
                cut.map_time(&clip.breaths, cut_idx, e),
            )
        })
        .collect();
    result.extra += out
        .breaths
        .iter()
        .zip(&used)
        .filter(|(b, u)| {
            !**u && !uncut_moved
                .iter()
                .any(|&(s, e)| b.start_s < e && s < b.end_s)
        })
        .count();
}

/// Renders (with `config`) and scores every clip for one (cut, run, voice): results per
/// speaker.
fn experiment(
    config: &EngineConfig,
    clips: &[Clip],
    cut: Cut,
    run: Run,
    voice: Voice,
    uncut_renders: &BTreeMap<(String, Voice), Vec<(f64, f64)>>,
    held_out: &BTreeMap<String, ReferenceVoice>,
) -> Result<BTreeMap<String, SpeakerResult>, String> {
    let mut per: BTreeMap<String, SpeakerResult> = BTreeMap::new();
    for clip in clips {
        let r = per.entry(clip.speaker.clone()).or_default();
        r.real_shapes.extend_from_slice(&clip.real_shapes);
        r.real_levels_re_speech_db
            .extend(clip.real_levels_db.iter().map(|l| l - clip.speech_db));
        let uncut = &uncut_renders[&(clip.name.clone(), voice)];
        let sets: Vec<Vec<usize>> = match run {
            Run::AllAtOnce => vec![(0..clip.breaths.len()).collect()],
            Run::OneAtATime => (0..clip.breaths.len()).map(|i| vec![i]).collect(),
        };
        // One render per breath: each its own seed, so the breaths restored one at a time
        // vary as breaths within one render do.
        for (k, set) in sets.into_iter().enumerate() {
            let input = cut.apply(&clip.audio, clip.rate_hz, &clip.breaths, &set);
            let h = &held_out[&clip.speaker];
            let out = render(
                config,
                &input,
                &clip.audio,
                clip.rate_hz,
                voice,
                h,
                k as u64,
            )
            .map_err(|e| format!("{}: {e}", clip.name))?;
            score(clip, cut, &set, &input, &out, uncut, r);
        }
    }
    Ok(per)
}

/// Prints the voice learned from `clip` (uncut) beside its labelled breaths.
fn print_voice(clip: &Clip) -> Result<(), String> {
    let mut config = EngineConfig::default();
    config.placement.whole_file = true;
    let v = learn_voice(&config, &clip.audio, clip.rate_hz).map_err(|e| e.to_string())?;
    let lengths: Vec<f64> = clip.breaths.iter().map(|(s, e)| e - s).collect();
    match v {
        Some(v) => println!(
            "  {:<14} heard {:>2}: {:+6.1} dB, {:.2} s   labelled {:>2}: {:+6.1} dB, {:.2} s",
            clip.name,
            v.breaths,
            v.level_re_speech_db,
            v.length_s,
            clip.breaths.len(),
            median(&clip.real_levels_db) - v.speech_db,
            median(&lengths)
        ),
        None => println!("  {:<14} heard none: built-in voice", clip.name),
    }
    Ok(())
}

/// Every labelled clip of `sets`, in a room `room_db` under its speech level when given.
pub fn load_all(sets: &LabelledSets, room_db: Option<f64>) -> Result<Vec<Clip>, String> {
    let mut clips = load(&sets.data, &sets.labels, (room_db, ROOM_SEED))?;
    let keele_seed = ROOM_SEED + ROOM_SEED_SET_STEP;
    clips.extend(load(
        &sets.keele,
        &sets.keele_labels,
        (room_db, keele_seed),
    )?);
    Ok(clips)
}

/// For each speaker, the built-in voice fitted on the others.
fn held_out_references(clips: &[Clip]) -> Result<BTreeMap<String, ReferenceVoice>, String> {
    let mut out = BTreeMap::new();
    for c in clips {
        if !out.contains_key(&c.speaker) {
            let r = reference::fit(clips.iter().filter(|o| o.speaker != c.speaker))
                .ok_or("no other speaker's breath to fit the built-in voice on")?;
            out.insert(c.speaker.clone(), r);
        }
    }
    Ok(out)
}

/// Prints each clip's channel tilt against its held-out reference.
fn print_reference(clips: &[Clip], held_out: &BTreeMap<String, ReferenceVoice>) {
    println!("
channel colouring of the built-in voice (speech tilt against the speakers it was fitted on, dB per third octave):");
    for c in clips {
        let r = &held_out[&c.speaker];
        println!(
            "  {:<14} {:+.2}   (fitted on {} speakers, {} breaths: level {:+.1} dB re speech)",
            c.name,
            r.tilt_db_per_band(&c.speech_ltas_db),
            r.speakers,
            r.voice.breaths,
            r.voice.level_re_speech_db
        );
    }
}

/// `items` joined by commas, or "none".
fn none_or_list(items: &[String]) -> String {
    if items.is_empty() {
        "none".into()
    } else {
        items.join(", ")
    }
}

/// Runs the evaluation and prints the report; `Ok(false)` when a held-out target is missed.
pub fn run(args: &RestoreArgs) -> Result<bool, String> {
    if let Some(db) = args.room_db.filter(|db| !(0.0..=ROOM_DB_MAX).contains(db)) {
        return Err(format!(
            "--room-db {db}: give how far under the speech the room lies, 0 to {ROOM_DB_MAX} dB \
             (a home studio's room lies 30-40 dB under)"
        ));
    }
    let clips = load_all(&args.sets, args.room_db)?;
    let breaths: usize = clips.iter().map(|c| c.breaths.len()).sum();
    if let Some(room_db) = args.room_db {
        println!("every clip in a room: seeded pink noise {room_db} dB under its speech level");
    }
    println!(
        "{breaths} clear labelled breaths in {} clips; put back = an inserted breath within {PUT_BACK_S} s",
        clips.len()
    );
    println!("\nvoice learned from each uncut clip (breaths heard; level re speech; length) vs its labelled breaths (level re the same speech level; length):");
    let config = EngineConfig::default();
    let held_out = held_out_references(&clips)?;
    print_reference(&clips, &held_out);
    let mut uncut: BTreeMap<(String, Voice), Vec<(f64, f64)>> = BTreeMap::new();
    let mut left: BTreeMap<(String, Voice), UncutRender> = BTreeMap::new();
    // Live mode (the app's default, the plugin's live mode) learns as it goes.
    let mut left_live: BTreeMap<(String, Voice), UncutRender> = BTreeMap::new();
    let mut live = config.clone();
    live.placement.mode = PlacementMode::Live;
    for clip in &clips {
        print_voice(clip)?;
        for voice in [
            Voice::BuiltIn,
            Voice::BuiltInHeldOut,
            Voice::BuiltInHeldOutPlain,
            Voice::Procedural,
            Voice::Learned,
            Voice::FromUncut,
            Voice::AsItGoes,
        ] {
            if args.judged_only && !voice.is_judged() {
                continue;
            }
            let h = &held_out[&clip.speaker];
            let out = render(&config, &clip.audio, &clip.audio, clip.rate_hz, voice, h, 0)?;
            let spans: Vec<(f64, f64)> = out.breaths.iter().map(|b| (b.start_s, b.end_s)).collect();
            left.insert(
                (clip.name.clone(), voice),
                UncutRender {
                    inserted: spans.clone(),
                    heard: out.existing_breaths.clone(),
                    lung: lung_of(&out),
                },
            );
            uncut.insert((clip.name.clone(), voice), spans);
            if voice == Voice::AsItGoes {
                let out = render(&live, &clip.audio, &clip.audio, clip.rate_hz, voice, h, 0)?;
                left_live.insert(
                    (clip.name.clone(), voice),
                    UncutRender {
                        inserted: out.breaths.iter().map(|b| (b.start_s, b.end_s)).collect(),
                        heard: out.existing_breaths.clone(),
                        lung: lung_of(&out),
                    },
                );
            }
        }
    }
    let plan = [
        (
            Cut::Gated,
            Run::AllAtOnce,
            Voice::Procedural,
            "procedural voice (before)",
        ),
        (
            Cut::Gated,
            Run::AllAtOnce,
            Voice::BuiltInHeldOutPlain,
            "built-in voice fitted without the speaker, not coloured, HELD OUT",
        ),
        (
            Cut::Gated,
            Run::AllAtOnce,
            Voice::BuiltInHeldOut,
            "built-in voice fitted without the speaker, coloured by the channel, HELD OUT",
        ),
        (
            Cut::Gated,
            Run::AllAtOnce,
            Voice::BuiltIn,
            "built-in voice as shipped (fitted on all, FITTED)",
        ),
        (
            Cut::Attenuated,
            Run::AllAtOnce,
            Voice::BuiltIn,
            "built-in voice as shipped (FITTED)",
        ),
        (
            Cut::Shortened,
            Run::AllAtOnce,
            Voice::BuiltIn,
            "built-in voice as shipped (FITTED)",
        ),
        (
            Cut::Gated,
            Run::OneAtATime,
            Voice::BuiltIn,
            "built-in voice as shipped (FITTED)",
        ),
        (
            Cut::Gated,
            Run::OneAtATime,
            Voice::Learned,
            "learned, HELD OUT",
        ),
        (
            Cut::Attenuated,
            Run::OneAtATime,
            Voice::Learned,
            "learned, HELD OUT",
        ),
        (
            Cut::Shortened,
            Run::OneAtATime,
            Voice::Learned,
            "learned, HELD OUT",
        ),
        (
            Cut::Gated,
            Run::OneAtATime,
            Voice::AsItGoes,
            "learned as it goes (plugin, lookahead), HELD OUT",
        ),
        (
            Cut::Attenuated,
            Run::OneAtATime,
            Voice::AsItGoes,
            "learned as it goes (plugin, lookahead), HELD OUT",
        ),
        (
            Cut::Gated,
            Run::AllAtOnce,
            Voice::Learned,
            "learned from the cut file",
        ),
        (
            Cut::Gated,
            Run::AllAtOnce,
            Voice::FromUncut,
            "learned on itself, FITTED",
        ),
    ];
    let mut all_met = true;
    let mut shipped_length = None;
    for (cut, run, voice, what) in plan {
        if args.judged_only && !is_judged_row(run, voice) {
            continue;
        }
        let per = experiment(&config, &clips, cut, run, voice, &uncut, &held_out)?;
        let run_name = match run {
            Run::AllAtOnce => "all cut at once",
            Run::OneAtATime => "one cut at a time",
        };
        println!("\n== {} , {run_name}, {what}", cut.name());
        let overall = print_table(&per);
        if voice == Voice::Learned && run == Run::OneAtATime {
            let missed: Vec<String> = per
                .values()
                .flat_map(|r| &r.missed)
                .map(|(clip, (a, b))| format!("{clip} {a:.2}–{b:.2} s"))
                .collect();
            println!("  not put back: {}", none_or_list(&missed));
            for (name, ok, text) in targets(&overall, cut) {
                println!(
                    "  target {name}: {text} {}",
                    if ok { "met" } else { "MISSED" }
                );
                all_met &= ok;
            }
        }
        if (cut, run, voice) == length_fit::RENDERS {
            shipped_length = Some(per);
        }
    }
    for (renders, voice, what) in [
        (&left, Voice::Learned, "voice learned from the whole file"),
        (
            &left,
            Voice::AsItGoes,
            "learned as it goes (plugin, lookahead)",
        ),
        (
            &left_live,
            Voice::AsItGoes,
            "live mode (the app's default; learned as it goes)",
        ),
    ] {
        let overall = left_in::print(&clips, renders, voice, what);
        lung::print(&clips, renders, voice);
        for (name, ok, text) in left_in::targets(&overall) {
            println!(
                "  target {name}: {text} {}",
                if ok { "met" } else { "MISSED" }
            );
            all_met &= ok || voice != Voice::Learned;
        }
    }
    interview::report(&config, &clips)?;
    if args.judged_only {
        return Ok(all_met || !args.check);
    }
    two_voices::report(&clips)?;
    let shipped_length = shipped_length.expect("the plan renders the length fit's case");
    length_fit::run(&clips, &uncut, &held_out, &shipped_length)?;
    Ok(all_met || !args.check)
}
