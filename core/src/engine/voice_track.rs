//! The stream part that learns the breath voice as the audio goes (the plugin, live mode and
//! `render --lookahead-ms`): every breath the phrase tracker hears in a pause is measured by a
//! [`BreathListener`] and the voice is learned again from the last [`MAX_HEARD`] of them, in
//! memory made at `prepare`. What the engine does with the voice (learn, keep one fixed, the
//! built-in one) is [`BreathVoiceMode`].

use super::replay::WholeSpeech;
use super::voice_learning::{BreathListener, MAX_HEARD};
use super::PlacementConfig;
use crate::analysis::FeatureFrame;
use crate::breathing::learned::{HeardBreath, LearnScratch, LearnedVoice};
use crate::breathing::reference::ReferenceVoice;

/// Where inserted breaths take their voice from. The fixed voice is held inline (not boxed):
/// a plugin freezes it on the audio thread, where nothing may allocate.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum BreathVoiceMode {
    /// The built-in voice ([`ReferenceVoice`], coloured by the channel as the stream goes, or
    /// by the whole input's speech when a learning pass heard it first);
    /// no breath is learned.
    BuiltIn,
    /// Learned from the stream as it goes (the built-in voice until the first breath is
    /// heard); learning restarts with the stream ([`super::Engine::reset`]).
    #[default]
    Learn,
    /// One voice, kept through resets: learned from the whole file before a render (or from
    /// another take, its level moved to the file's speech), or frozen by the user
    /// ([`super::Engine::freeze_voice`]).
    Fixed(LearnedVoice),
    /// A voice learned from another take of the speaker (`--breath-like`, the plugin's
    /// breath-like file) while streaming: its shape as learned, its level under the speech kept
    /// against this stream's speech level as it goes (the take may have been recorded louder
    /// or quieter).
    Like(LearnedVoice),
}

/// The engine's choice of breath voice: the mode and the built-in voice (`None`: the
/// procedural sound).
#[derive(Debug, Clone, Copy)]
pub(super) struct VoiceChoice {
    pub(super) mode: BreathVoiceMode,
    pub(super) reference: Option<ReferenceVoice>,
}

impl VoiceChoice {
    /// The voice is being learned ([`BreathVoiceMode::Learn`]).
    pub(super) fn learning(&self) -> bool {
        self.mode == BreathVoiceMode::Learn
    }
}

/// What the breath voice is doing, for a display.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VoiceStatus {
    /// The built-in voice, nothing learned.
    BuiltIn,
    /// Learning: `breaths` heard since the stream started (the built-in voice while 0).
    Learning {
        /// Breaths heard.
        breaths: usize,
    },
    /// A fixed voice learned from `breaths` breaths.
    Fixed {
        /// Breaths it was learned from.
        breaths: usize,
    },
}

/// See the module docs.
#[derive(Debug)]
pub(super) struct VoiceTrack {
    listener: BreathListener,
    /// The last [`MAX_HEARD`] breaths heard (a ring once full).
    heard: Vec<HeardBreath>,
    /// The breath heard in the pause before the phrase being spoken: learned from once that
    /// phrase has ended and its speaker's level is known ([`super::speaker_level`]).
    waiting: Option<HeardBreath>,
    /// Breaths heard since the last reset.
    count: usize,
    scratch: LearnScratch,
    voice: Option<LearnedVoice>,
    /// The speech of the whole stream, heard before it (a replayed learning pass): the voice's
    /// colour and level against the speech come from it, not from the speech heard so far.
    whole: Option<WholeSpeech>,
}

impl VoiceTrack {
    /// A track at `rate_hz`. Allocates.
    pub(super) fn new(rate_hz: f64) -> Self {
        Self {
            listener: BreathListener::new(rate_hz),
            heard: Vec::with_capacity(MAX_HEARD),
            waiting: None,
            count: 0,
            scratch: LearnScratch::with_capacity(MAX_HEARD),
            voice: None,
            whole: None,
        }
    }

    /// The speech of the whole stream is `whole`, heard before it (kept through resets).
    pub(super) fn set_whole(&mut self, whole: WholeSpeech) {
        self.whole = Some(whole);
    }

    /// Forgets every breath and the room.
    pub(super) fn reset(&mut self) {
        self.listener.reset();
        self.forget_breaths();
    }

    /// Forgets the breaths learned (learning starts again), keeping the room and the speech.
    pub(super) fn forget_breaths(&mut self) {
        self.heard.clear();
        self.waiting = None;
        self.count = 0;
        self.voice = None;
    }

    /// Hears the next mono samples.
    pub(super) fn push(&mut self, mono: &[f32]) {
        self.listener.push(mono);
    }

    /// Hears one analysis frame.
    pub(super) fn frame(&mut self, f: &FeatureFrame) {
        self.listener.frame(f);
    }

    /// A breath heard at `span` (seconds), in the pause before the phrase that starts now:
    /// measured now, learned from when that phrase ends ([`VoiceTrack::phrase_ended`]).
    pub(super) fn hear(&mut self, span: (f64, f64)) {
        self.waiting = self.listener.measure(span);
    }

    /// The phrase after the breath heard last ended; its speaker's level is `speaker_db`
    /// (dBFS, NaN: not known): the voice is learned again with that breath.
    pub(super) fn phrase_ended(&mut self, speaker_db: f32) {
        let Some(mut breath) = self.waiting.take() else {
            return;
        };
        breath.speaker_level_db = f64::from(speaker_db);
        if self.heard.len() < MAX_HEARD {
            self.heard.push(breath);
        } else {
            self.heard[self.count % MAX_HEARD] = breath;
        }
        self.count += 1;
        self.voice = self.listener.learn(&self.heard, &mut self.scratch);
    }

    /// The upper edge of the recording's speech spectrum, Hz: the whole stream's when it was
    /// heard first, else that of the speech heard so far (`None` before enough of it).
    pub(super) fn upper_edge_hz(&self) -> Option<f64> {
        self.whole
            .map_or_else(|| self.listener.upper_edge_hz(), |w| w.upper_edge_hz)
    }

    /// The recording's speech level, dBFS: the whole stream's when it was heard first, else
    /// that of the speech heard so far (NaN before any).
    pub(super) fn speech_db(&self) -> f64 {
        self.whole
            .map_or_else(|| self.listener.speech_db(), |w| w.speech_db)
    }

    /// Breaths heard since the stream started.
    pub(super) fn heard(&self) -> usize {
        self.count
    }

    /// The voice learned so far.
    pub(super) fn voice(&self) -> Option<&LearnedVoice> {
        self.voice.as_ref()
    }

    /// The voice breaths take now for `choice`: a fixed one; another take's against the speech
    /// heard so far; the one learned so far; else the built-in voice coloured by the speech
    /// heard so far (the whole stream's, [`VoiceTrack::set_whole`]), at the default breath
    /// level (the user's level moves it as it moves a learned voice's; `None` before any
    /// voiced speech, or without a built-in voice: the procedural sound).
    pub(super) fn current(&self, choice: &VoiceChoice) -> Option<LearnedVoice> {
        let WholeSpeech {
            ltas_db, speech_db, ..
        } = self.whole.unwrap_or_else(|| self.listener.speech());
        match (&choice.mode, self.voice) {
            (BreathVoiceMode::Fixed(v), _) => return Some(*v),
            (BreathVoiceMode::Like(v), _) => return Some(v.against_speech_db(speech_db)),
            (BreathVoiceMode::Learn, Some(v)) => return Some(v),
            _ => {}
        }
        let r = choice.reference.as_ref()?;
        speech_db.is_finite().then(|| {
            r.coloured(
                &ltas_db,
                speech_db,
                f64::from(PlacementConfig::default().breath_level_db),
            )
        })
    }
}
