//! The breath voice of a render ([`mode`]): learned from the recording itself before a
//! whole-file render (a first pass over the file through [`VoiceLearner`], whose analysis the
//! render then replays instead of analysing the file again), or from
//! `--breath-like FILE` (another take of the same speaker) in any mode, or built in
//! (`--built-in-breath`, or no breath heard; coloured by the whole file's speech). A render as
//! the plugin (`--lookahead-ms`, `--mode live`) or from standard input (which cannot be read
//! twice) learns as it goes, as the plugin does.

use std::path::Path;

use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::engine::replay::AnalysisRecord;
use pneuma_core::engine::voice_learning::{speech_after_silence, Learned, VoiceLearner};
use pneuma_core::engine::{BreathVoiceMode, Engine, EngineConfig, PlacementMode, SpeechSummary};
use pneuma_core::head::HeadModel;
use pneuma_io::AudioSource;

use super::error::RenderError;
use super::findings::{breath_like_finding, Finding};

/// Frames read per block of the learning pass.
const BLOCK_FRAMES: usize = 8192;

/// The breath voice of a render, and the learning pass's analysis of the input for the engine
/// to replay (a whole-file render of a file analyses it once).
#[derive(Debug)]
pub struct VoicePlan {
    /// Where inserted breaths take their voice from.
    pub mode: BreathVoiceMode,
    /// The input's analysis when a learning pass heard it.
    pub record: Option<AnalysisRecord>,
    /// What the user should know about the `--breath-like` file (it holds little speech).
    pub note: Option<Finding>,
}

/// The breath voice of a render of `input` (channel `pick` of it, or all mixed) with `config`,
/// and for a whole-file render of a file its learning pass's analysis (always: the built-in
/// voice too is coloured by the whole file's speech then): built in with `built_in`
/// (`--built-in-breath`); learned from `breath_like`
/// (`--breath-like FILE`: before a whole-file render its level is set against the input's
/// speech, otherwise held against it as the render goes, as the plugin does); learned from the
/// input before a whole-file render; learned as it goes otherwise. A file in which no breath is
/// heard gives the built-in voice.
pub fn mode(
    built_in: bool,
    breath_like: Option<&Path>,
    input: &Path,
    pick: Option<usize>,
    config: &EngineConfig,
) -> Result<VoicePlan, RenderError> {
    // The breath-like file's voice (`Some(None)`: no breath heard in it), unless it holds no
    // speech (`None`: as if it were not given).
    let (like, note) = match breath_like {
        Some(p) if !built_in => breath_like_voice(p, config)?,
        _ => (None, None),
    };
    // Live mode renders as the plugin does; standard input cannot be read twice: both learn
    // as they go.
    let whole_file = config.placement.whole_file
        && config.placement.mode == PlacementMode::Lookahead
        && input.as_os_str() != "-";
    if !whole_file {
        let mode = match like {
            _ if built_in => BreathVoiceMode::BuiltIn,
            // As the plugin with a breath-like file: the take's level under its speech, held
            // against the stream's speech as it goes.
            Some(Some(v)) => BreathVoiceMode::Like(v),
            Some(None) => BreathVoiceMode::BuiltIn,
            None => BreathVoiceMode::Learn,
        };
        return Ok(VoicePlan {
            mode,
            record: None,
            note,
        });
    }
    // A whole-file render hears the whole input first, whatever its voice: the analysis to
    // replay, and the speech that colours the built-in voice.
    let heard = learn(input, pick, config, true)?;
    let voice = match like {
        _ if built_in => None,
        Some(like) => like.map(|v| v.against_speech_db(heard.speech.speech_db)),
        None => heard.voice,
    };
    Ok(VoicePlan {
        mode: voice.map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Fixed),
        record: heard.record,
        note,
    })
}

/// A breath-like file's voice (`Some(None)`: no breath heard in it; `None`: not learned from)
/// and what to tell of its speech.
type BreathLike = (Option<Option<LearnedVoice>>, Option<Finding>);

/// The voice learned from the `--breath-like` file at `path`, unless it holds no speech, and
/// what to tell of its speech ([`breath_like_finding`]; not asked when the speech decision is
/// off, `--any-sound`).
fn breath_like_voice(path: &Path, config: &EngineConfig) -> Result<BreathLike, RenderError> {
    let note = if config.placement.speech_only {
        breath_like_finding(&speech_of(path, config)?)
    } else {
        None
    };
    if let Some(Finding::BreathLikeNotSpeech { unused: true, .. }) = note {
        return Ok((None, note));
    }
    Ok((Some(learn(path, None, config, false)?.voice), note))
}

/// The speech decision over the file at `path` (its channels mixed as the engine mixes them),
/// as a render of it with `config` judges it.
fn speech_of(path: &Path, config: &EngineConfig) -> Result<SpeechSummary, RenderError> {
    let mut source = AudioSource::open(path)?;
    let channels = usize::from(source.info().channels).max(1);
    let mut engine = Engine::new(config.clone(), HeadModel::default_model().clone())?;
    engine.prepare(
        f64::from(source.info().sample_rate_hz),
        BLOCK_FRAMES,
        channels,
    )?;
    let (mut interleaved, mut planar) = (Vec::new(), vec![Vec::new(); channels]);
    while source.read_interleaved(BLOCK_FRAMES, &mut interleaved)? > 0 {
        for (c, samples) in planar.iter_mut().enumerate() {
            samples.clear();
            samples.extend(interleaved.iter().skip(c).step_by(channels));
        }
        let mut blocks: Vec<&mut [f32]> = planar.iter_mut().map(Vec::as_mut_slice).collect();
        engine.process(&mut blocks, &mut |_, _| {});
    }
    Ok(speech_after_silence(&mut engine, channels))
}

/// What a learning pass over `path` (channel `pick` of it, or all mixed as the engine mixes
/// them) with `config`'s analysis and phrase settings hears; with `record`, its analysis too.
fn learn(
    path: &Path,
    pick: Option<usize>,
    config: &EngineConfig,
    record: bool,
) -> Result<Learned, RenderError> {
    let mut source = AudioSource::open(path)?;
    let channels = usize::from(source.info().channels).max(1);
    let rate_hz = f64::from(source.info().sample_rate_hz);
    let mut learner = if record {
        VoiceLearner::recording(config, rate_hz)?
    } else {
        VoiceLearner::new(config, rate_hz)?
    };
    learner.expect_samples(source.info().frames);
    let (mut interleaved, mut picked) = (Vec::new(), Vec::new());
    while source.read_interleaved(BLOCK_FRAMES, &mut interleaved)? > 0 {
        match pick {
            Some(k) => {
                picked.clear();
                picked.extend(interleaved.chunks_exact(channels).map(|f| f[k]));
                learner.feed_interleaved(&picked, 1)?;
            }
            None => learner.feed_interleaved(&interleaved, channels)?,
        }
    }
    Ok(learner.finish()?)
}
