//! The breath voice of a whole-file render: learned from the recording itself before the
//! render (a first pass over the file through [`VoiceLearner`]), or from `--breath-like FILE`
//! (another take of the same speaker), or none (`--built-in-breath`, a render as the plugin
//! with `--lookahead-ms`, or standard input, which cannot be read twice): then the built-in
//! voice.

use std::path::Path;

use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::engine::voice_learning::VoiceLearner;
use pneuma_core::engine::EngineConfig;
use pneuma_io::AudioSource;

use super::error::RenderError;

/// Frames read per block of the learning pass.
const BLOCK_FRAMES: usize = 8192;

/// Where the voice of a render of `input` with `config` is learned from (`None`: built in):
/// `breath_like` (`--breath-like FILE`) or the input itself, unless `built_in`
/// (`--built-in-breath`).
pub fn source<'a>(
    built_in: bool,
    breath_like: Option<&'a Path>,
    input: &'a Path,
    config: &EngineConfig,
) -> Option<&'a Path> {
    if built_in || !config.placement.whole_file {
        return None;
    }
    match breath_like {
        Some(p) => Some(p),
        None if input.as_os_str() == "-" => None,
        None => Some(input),
    }
}

/// Learns the breath voice from `path` with `config`'s analysis and phrase settings for a
/// render of `input`: from another recording, the level under the speech is then taken
/// against `input`'s own speech level. `None` when no breath was heard.
pub fn learn(
    path: &Path,
    config: &EngineConfig,
    input: &Path,
) -> Result<Option<LearnedVoice>, RenderError> {
    let voice = learn_file(path, config)?;
    if path == input {
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
