//! The breath voice learned from another recording of the speaker (the persisted path
//! `breath_like`, the plugin's `render --breath-like`): read and learned off the audio thread
//! when an engine is built ([`crate::rebuild`]) and by the editor's file check.
//!
//! The whole file streams through core's [`learn_voice`] with the engine's analysis and phrase
//! settings, so the breaths heard are the ones the engine would hear. The voice keeps the file's
//! level under its speech (the stream's speech is not known before it plays). A file in which no
//! breath is heard gives the built-in voice, as the CLI's `--breath-like` does; a file that
//! cannot be read gives an error (the engine then learns as the audio goes).
//!
//! As `render --breath-like`, the engine's speech decision hears the file first (unless it is
//! off, "any sound"): a file with no speech in it (music, noise) is not learned from, an error
//! that says so (learning as the audio goes, as without the file), and one mostly of other sound
//! is learned from with a note ([`LikeVoice::speech_share`]).
//!
//! [`VoiceCache`] keeps the last voices learned, so engines rebuilt for other settings (mode,
//! lookahead), re-activations and the editor's file check (one cache per plugin instance,
//! shared by its engine builder and its editor) do not read the file again: it is read again
//! only when the path, the file's modification time, the analysis or phrase settings or the
//! speech decision's switch change.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::SystemTime;

use pneuma_core::analysis::AnalysisConfig;
use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::engine::voice_learning::{learn_voice, speech_of};
use pneuma_core::engine::EngineConfig;
use pneuma_core::phrase::PhraseConfig;

/// Why no voice was learned from a breath-like file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BreathLikeError {
    /// The file could not be read or decoded.
    #[error(
        "breath-like file {path}: {reason}. Choose a recording of the same speaker (WAV, FLAC, \
         …), or clear the field to learn the voice as the audio goes"
    )]
    Read {
        /// The path.
        path: String,
        /// What went wrong.
        reason: String,
    },
    /// The speech decision hears no speech in the file: no speaker's breath to learn.
    #[error(
        "breath-like file {path} holds no speech (speech in {percent:.0} % of its time with \
         sound): the voice is learned as the audio goes, as without it. \
         Choose a raw take of the same speaker, breaths and all; for a voice the speech \
         decision does not take for speech (sung, through a voice changer), turn off Speech \
         pauses only"
    )]
    NotSpeech {
        /// The path.
        path: String,
        /// Share of its frames with sound that are speech, %.
        percent: f64,
    },
    /// The engine's analysis does not take the file's sample rate.
    #[error("breath-like file {path}: cannot analyse it: {reason}")]
    Analysis {
        /// The path.
        path: String,
        /// What went wrong.
        reason: String,
    },
}

/// What a breath-like file gives.
#[derive(Debug, Clone, PartialEq)]
pub struct LikeVoice {
    /// The voice learned from it (`None`: no breath heard in it: the built-in voice).
    pub voice: Option<LearnedVoice>,
    /// Share of its frames with sound that are speech, 0..1, when that is under
    /// [`pneuma_core::engine::MOSTLY_OTHER_SHARE`] (mostly music or other sound: its breaths
    /// may not be the speaker's); `None` when it is mostly speech or the decision is off.
    pub speech_share: Option<f64>,
}

/// The voice of the recording at `path` with `config`'s analysis and phrase settings, after
/// its speech decision (see the module docs). Reads the whole file: not for the audio thread.
pub fn learn(path: &str, config: &EngineConfig) -> Result<LikeVoice, BreathLikeError> {
    let (mono, rate_hz) =
        pneuma_io::read_mono(Path::new(path)).map_err(|e| BreathLikeError::Read {
            path: path.to_owned(),
            reason: e.to_string(),
        })?;
    let rate_hz = f64::from(rate_hz);
    let analysis = |e: pneuma_core::engine::EngineError| BreathLikeError::Analysis {
        path: path.to_owned(),
        reason: e.to_string(),
    };
    let mut speech_share = None;
    if config.placement.speech_only {
        let speech = speech_of(config, &mono, rate_hz).map_err(analysis)?;
        if speech.holds_no_speech() {
            return Err(BreathLikeError::NotSpeech {
                path: path.to_owned(),
                percent: 100.0 * speech.speech_share(),
            });
        }
        speech_share = speech.mostly_other().then(|| speech.speech_share());
    }
    Ok(LikeVoice {
        voice: learn_voice(config, &mono, rate_hz).map_err(analysis)?,
        speech_share,
    })
}

/// What a learned voice depends on.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    path: String,
    modified: Option<SystemTime>,
    analysis: AnalysisConfig,
    phrase: PhraseConfig,
    speech_only: bool,
}

impl Key {
    fn of(path: &str, config: &EngineConfig) -> Self {
        Self {
            path: path.to_owned(),
            modified: std::fs::metadata(path).and_then(|m| m.modified()).ok(),
            analysis: config.analysis.clone(),
            phrase: config.phrase,
            speech_only: config.placement.speech_only,
        }
    }
}

type Learned = Result<LikeVoice, BreathLikeError>;

/// Voices kept by a [`VoiceCache`]: the file being checked or loaded and the one before it
/// (a check of a new file does not make the engine read the file it still uses again).
const KEPT_VOICES: usize = 2;

/// The last voices learned from breath-like files (see the module docs).
#[derive(Debug, Default)]
pub struct VoiceCache {
    /// The most recent first.
    kept: Mutex<[Option<(Key, Learned)>; KEPT_VOICES]>,
    /// Files read and learned, or tried (not answered from the cache).
    reads: AtomicU64,
}

impl VoiceCache {
    /// [`learn`], or the voice learned before from the same file and settings. The lock is not
    /// held while a file is read: a check of a long take never holds up an engine's build (two
    /// callers that miss at once both read it).
    pub fn learn(&self, path: &str, config: &EngineConfig) -> Learned {
        let key = Key::of(path, config);
        let lock = || self.kept.lock().unwrap_or_else(|p| p.into_inner());
        {
            let mut kept = lock();
            let found = kept
                .iter()
                .position(|e| e.as_ref().is_some_and(|(k, _)| *k == key));
            if let Some(i) = found {
                // The voice used last goes first: the one kept longest unused goes next.
                kept[..=i].rotate_right(1);
                if let Some((_, learned)) = &kept[0] {
                    return learned.clone();
                }
            }
        }
        let learned = learn(path, config);
        self.reads.fetch_add(1, Ordering::Relaxed);
        let mut kept = lock();
        if !kept.iter().flatten().any(|(k, _)| *k == key) {
            kept.rotate_right(1);
            kept[0] = Some((key, learned.clone()));
        }
        learned
    }

    /// How many times a file was read and learned (or tried) rather than answered from the
    /// cache.
    pub fn reads(&self) -> u64 {
        self.reads.load(Ordering::Relaxed)
    }
}

/// The editor's check of the breath-like file at `path`: what the engine will learn from it
/// with `config` (through `cache`, so the engine built next does not read it again), as a
/// line for the user, or why it cannot be used.
pub fn check(cache: &VoiceCache, path: &str, config: &EngineConfig) -> Result<String, String> {
    if path.is_empty() {
        return Ok("none: the voice is learned as the audio goes".to_owned());
    }
    let like = cache.learn(path, config).map_err(|e| e.to_string())?;
    let what = match like.voice {
        Some(v) => format!("voice learned from {} breaths", v.breaths),
        None => "no breath heard in it: the built-in voice".to_owned(),
    };
    let note = like.speech_share.map_or(String::new(), |share| {
        format!(
            "; but it is mostly music or other sound (speech in {:.0} % of its time with \
             sound), so breaths heard between its sounds went into the voice: a raw take of \
             the speaker gives the speaker's own",
            100.0 * share
        )
    });
    Ok(format!("{what}{note}"))
}
