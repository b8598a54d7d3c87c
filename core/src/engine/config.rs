//! Settings of the [`super::Engine`]: analysis, phrase tracking, breath placement, breathing and
//! head pose, and the errors they can raise.

use thiserror::Error;

use crate::analysis::{AnalysisConfig, AnalysisError};
use crate::breathing::{BreathingError, BreathingParams};
use crate::head::{HeadConfig, HeadModelError};
use crate::phrase::{PhraseConfig, PhraseError};

/// How breaths are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum PlacementMode {
    /// The audio is delayed by `lookahead_s` (reported as latency in a plugin, removed by offline
    /// rendering): the next phrase onset is known before the output reaches the pause, so the
    /// inhalation ends just before it.
    #[default]
    Lookahead,
    /// No delay: the inhalation starts once a pause is confirmed and fades out fast if speech
    /// resumes.
    Live,
}

impl PlacementMode {
    /// `lookahead` or `live`.
    pub fn as_str(self) -> &'static str {
        match self {
            PlacementMode::Lookahead => "lookahead",
            PlacementMode::Live => "live",
        }
    }

    /// Parses `lookahead` or `live`.
    pub fn from_name(name: &str) -> Result<Self, EngineError> {
        match name {
            "lookahead" => Ok(PlacementMode::Lookahead),
            "live" => Ok(PlacementMode::Live),
            other => Err(EngineError::Mode(other.to_string())),
        }
    }
}

/// Where and how loud breaths go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacementConfig {
    /// Lookahead or live placement.
    pub mode: PlacementMode,
    /// Delay of the audio in lookahead mode, seconds (0.3–2, default 0.5). The longest breath
    /// that fits is about this minus the onset confirmation (~60 ms) and `gap_s`; under 0.3 s
    /// too little would fit.
    pub lookahead_s: f32,
    /// Pauses shorter than this get no breath, seconds (0.1–5, default 0.25).
    pub min_pause_s: f32,
    /// Silence left between the end of an inhalation and the next phrase onset, seconds
    /// (0–0.3, default 0.04).
    pub gap_s: f32,
    /// Silence kept after the end of a phrase before an inhalation may start, seconds (0–0.5,
    /// default 0.06).
    pub after_offset_s: f32,
    /// Breath level (plateau RMS) relative to the running speech level, dB, for the neutral
    /// breathing preset (−60 to −6, default −22); other presets scale it by their breathing-sound
    /// amplitude. Never more than −6 dB: a breath is never louder than the speech.
    pub breath_level_db: f32,
    /// Insert breaths into the audio (off: the audio passes unchanged, the controls still follow
    /// the breathing cycle).
    pub insert_breaths: bool,
    /// Fade applied when speech resumes during a live-mode breath, seconds (0.002–0.1, default
    /// 0.015).
    pub live_fade_s: f32,
    /// Shortest catch breath, seconds (0.05–0.5, default 0.15): when the air of a breath group
    /// would run out before its next usable pause, a quick inhalation goes into a shorter pause
    /// (also under `min_pause_s`) if at least this much fits.
    pub catch_breath_min_s: f32,
    /// Longest catch breath, seconds (0.1–1, at least `catch_breath_min_s`, default 0.25).
    pub catch_breath_max_s: f32,
    /// Offline render of a whole file (lookahead mode): the engine looks ahead
    /// [`OFFLINE_LOOKAHEAD_S`] (or `lookahead_s` if longer), so it sees the coming breath group
    /// and gives long pauses long, deep breaths. A plugin leaves it off and keeps its bounded
    /// `lookahead_s` (default off).
    pub whole_file: bool,
    /// Breaths only into pauses of speech (the speech decision, [`crate::speech`]): no breath
    /// before (lookahead: the next phrase, offline judged by its first half second; or after,
    /// live: the finished phrase) music, singing or noise. Off: every pause, as the phrase
    /// tracker finds them (signals that are not speech, a user who wants breaths in singing).
    /// Stream part (the decision is built at `prepare`).
    pub speech_only: bool,
}

/// Lookahead of an offline render ([`PlacementConfig::whole_file`]), seconds: longer than a
/// breath group and the pause before it.
pub const OFFLINE_LOOKAHEAD_S: f32 = 8.0;

impl Default for PlacementConfig {
    fn default() -> Self {
        Self {
            mode: PlacementMode::Lookahead,
            lookahead_s: 0.5,
            min_pause_s: 0.25,
            gap_s: 0.04,
            after_offset_s: 0.06,
            breath_level_db: -22.0,
            insert_breaths: true,
            live_fade_s: 0.015,
            catch_breath_min_s: 0.15,
            catch_breath_max_s: 0.25,
            whole_file: false,
            speech_only: true,
        }
    }
}

impl PlacementConfig {
    /// The delay of lookahead mode, seconds: `lookahead_s`, or at least [`OFFLINE_LOOKAHEAD_S`]
    /// for a whole-file render.
    pub fn effective_lookahead_s(&self) -> f32 {
        if self.whole_file {
            self.lookahead_s.max(OFFLINE_LOOKAHEAD_S)
        } else {
            self.lookahead_s
        }
    }

    /// Checks every setting against its range.
    pub fn validate(&self) -> Result<(), EngineError> {
        let checks: [(&'static str, f32, f32, f32); 8] = [
            ("lookahead_s", self.lookahead_s, 0.3, 2.0),
            ("min_pause_s", self.min_pause_s, 0.1, 5.0),
            ("gap_s", self.gap_s, 0.0, 0.3),
            ("after_offset_s", self.after_offset_s, 0.0, 0.5),
            ("breath_level_db", self.breath_level_db, -60.0, -6.0),
            ("live_fade_s", self.live_fade_s, 0.002, 0.1),
            ("catch_breath_min_s", self.catch_breath_min_s, 0.05, 0.5),
            (
                "catch_breath_max_s",
                self.catch_breath_max_s,
                self.catch_breath_min_s.clamp(0.1, 1.0),
                1.0,
            ),
        ];
        for (name, value, min, max) in checks {
            if !(value.is_finite() && (min..=max).contains(&value)) {
                return Err(EngineError::OutOfRange {
                    name,
                    value,
                    min,
                    max,
                });
            }
        }
        Ok(())
    }
}

/// Everything the engine needs to know.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineConfig {
    /// The analysis front end (frame rate, f0 range, gates).
    pub analysis: AnalysisConfig,
    /// The phrase tracker.
    pub phrase: PhraseConfig,
    /// Breath placement and level.
    pub placement: PlacementConfig,
    /// The breathing model's parameters (a preset or custom).
    pub breathing: BreathingParams,
    /// Head-pose synthesis settings.
    pub head: HeadConfig,
    /// Seed of every random source (breath noise, liveliness).
    pub seed: u64,
}

impl Default for EngineConfig {
    fn default() -> Self {
        Self {
            analysis: AnalysisConfig::default(),
            phrase: PhraseConfig::default(),
            placement: PlacementConfig::default(),
            breathing: BreathingParams::default(),
            head: HeadConfig::default(),
            seed: 1,
        }
    }
}

impl EngineConfig {
    /// True when `other` differs in the stream part, which sizes and seeds the stream and so
    /// only takes effect at [`super::Engine::prepare`]: the analysis, the phrase tracker, the
    /// placement mode, the lookahead (and whole-file rendering) and the seed.
    pub fn stream_differs(&self, other: &EngineConfig) -> bool {
        let mut stream = self.clone();
        stream.set_stream_part(other);
        stream != *self
    }

    /// True when `other` differs in the live part, which applies while playing: every placement
    /// setting but the mode and the lookahead, the breathing parameters, the head settings.
    pub fn live_differs(&self, other: &EngineConfig) -> bool {
        let mut live = other.clone();
        live.set_stream_part(self);
        live != *self
    }

    /// Takes the live part (see [`EngineConfig::live_differs`]) from `other`.
    pub fn set_live_part(&mut self, other: &EngineConfig) {
        let mut next = other.clone();
        next.set_stream_part(self);
        *self = next;
    }

    /// Takes the stream part from `from`: the one list of the stream part's fields, which
    /// [`EngineConfig::stream_differs`] and [`EngineConfig::live_differs`] both use.
    fn set_stream_part(&mut self, from: &EngineConfig) {
        self.analysis = from.analysis.clone();
        self.phrase = from.phrase;
        self.placement.mode = from.placement.mode;
        self.placement.lookahead_s = from.placement.lookahead_s;
        self.placement.whole_file = from.placement.whole_file;
        self.placement.speech_only = from.placement.speech_only;
        self.seed = from.seed;
    }

    /// Checks every part.
    pub fn validate(&self) -> Result<(), EngineError> {
        self.analysis.validate()?;
        self.phrase.validate()?;
        self.placement.validate()?;
        self.breathing.validate()?;
        self.head.validate()?;
        Ok(())
    }
}

/// Errors of the engine.
#[derive(Debug, Error)]
pub enum EngineError {
    /// An analysis setting or the sample rate.
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// A phrase-tracker setting.
    #[error(transparent)]
    Phrase(#[from] PhraseError),
    /// A breathing setting.
    #[error(transparent)]
    Breathing(#[from] BreathingError),
    /// A head-pose setting or model.
    #[error(transparent)]
    Head(#[from] HeadModelError),
    /// A placement setting is out of range.
    #[error("placement setting `{name}` = {value} is out of range: use {min}..={max}")]
    OutOfRange {
        /// The setting.
        name: &'static str,
        /// The value given.
        value: f32,
        /// Lowest allowed.
        min: f32,
        /// Highest allowed.
        max: f32,
    },
    /// Unknown placement mode.
    #[error("unknown placement mode `{0}`: use `lookahead` or `live`")]
    Mode(String),
    /// Channel count.
    #[error("{0} channels are not supported: use 1 (mono) to 8 channels")]
    Channels(usize),
    /// Block size.
    #[error("maximum block size {0} is not supported: use 1..=65536 samples")]
    MaxBlock(usize),
}
