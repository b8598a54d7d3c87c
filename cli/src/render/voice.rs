//! The breath voice of a render ([`mode`]): learned from the recording itself before a
//! whole-file render (a first pass over the file through [`VoiceLearner`]), or from
//! `--breath-like FILE` (another take of the same speaker) in any mode, or built in
//! (`--built-in-breath`, or no breath heard). A render as the plugin (`--lookahead-ms`, `--live`)
//! or from standard input (which cannot be read twice) learns as it goes, as the plugin does.

use std::path::Path;

use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::engine::voice_learning::VoiceLearner;
use pneuma_core::engine::{BreathVoiceMode, EngineConfig};
use pneuma_io::AudioSource;

use super::error::RenderError;

/// Frames read per block of the learning pass.
const BLOCK_FRAMES: usize = 8192;

/// The breath voice of a render of `input` with `config`: built in with `built_in`
/// (`--built-in-breath`); learned from `breath_like` (`--breath-like FILE`: before a
/// whole-file render its level is set against the input's speech, otherwise held against it as
/// the render goes, as the plugin does); learned from the input before a whole-file render;
/// learned as it goes otherwise. A file in which no breath is heard gives the built-in voice.
pub fn mode(
    built_in: bool,
    breath_like: Option<&Path>,
    input: &Path,
    config: &EngineConfig,
) -> Result<BreathVoiceMode, RenderError> {
    let from = match breath_like {
        _ if built_in => return Ok(BreathVoiceMode::BuiltIn),
        // As the plugin with a breath-like file: the take's level under its speech, held
        // against the stream's speech as it goes.
        Some(p) if !config.placement.whole_file => {
            return Ok(
                learn_file(p, config)?.map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Like)
            )
        }
        Some(p) => p,
        None if config.placement.whole_file && input.as_os_str() != "-" => input,
        None => return Ok(BreathVoiceMode::Learn),
    };
    Ok(learn(from, config, input)?.map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Fixed))
}

/// Learns the breath voice from `path` with `config`'s analysis and phrase settings for a
/// render of `input`: from another recording, the level under the speech is then taken
/// against `input`'s own speech level (not for standard input). `None` when no breath was heard.
pub fn learn(
    path: &Path,
    config: &EngineConfig,
    input: &Path,
) -> Result<Option<LearnedVoice>, RenderError> {
    let voice = learn_file(path, config)?;
    // Standard input cannot be read twice: the voice keeps the other take's speech level.
    if path == input || input.as_os_str() == "-" {
        return Ok(voice);
    }
    let speech_db = learn_file_speech_db(input, config)?;
    Ok(voice.map(|v| v.against_speech_db(speech_db)))
}

/// The speech level of `input` as the learner measures it.
fn learn_file_speech_db(input: &Path, config: &EngineConfig) -> Result<f64, RenderError> {
    Ok(feed_file(input, config)?.speech_db())
}

fn learn_file(path: &Path, config: &EngineConfig) -> Result<Option<LearnedVoice>, RenderError> {
    Ok(feed_file(path, config)?.finish()?)
}

/// `path` (mixed to mono, as the engine mixes it) through a learner.
fn feed_file(path: &Path, config: &EngineConfig) -> Result<VoiceLearner, RenderError> {
    let mut source = AudioSource::open(path)?;
    let channels = usize::from(source.info().channels).max(1);
    let rate_hz = f64::from(source.info().sample_rate_hz);
    let mut learner = VoiceLearner::new(config, rate_hz)?;
    let (mut interleaved, mut mono) = (Vec::new(), Vec::with_capacity(BLOCK_FRAMES));
    while source.read_interleaved(BLOCK_FRAMES, &mut interleaved)? > 0 {
        mono.clear();
        mono.extend(
            interleaved
                .chunks_exact(channels)
                .map(|f| f.iter().sum::<f32>() / channels as f32),
        );
        learner.feed(&mono)?;
    }
    Ok(learner)
}
