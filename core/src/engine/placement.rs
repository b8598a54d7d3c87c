//! Breath placement: turns phrase events into scheduled breath and breathing-cycle actions, with
//! the two policies of [`PlacementMode`] (see the engine's module docs for the rules). It also
//! keeps what the decisions need: the running speech level, the level of the last phrase and
//! the expected utterance length. Breath-group planning belongs here too.

use super::schedule::{BreathAction, CycleAction, Queue, Schedule};
use super::{EngineConfig, Pending, PlacementMode, MAX_CHANNELS};
use crate::analysis::FeatureFrame;
use crate::phrase::PhraseEvent;

/// Shortest inhalation worth inserting, seconds.
const MIN_BREATH_S: f64 = 0.12;
/// Prior of the utterance length before any phrase was heard, seconds.
pub(crate) const PRIOR_UTTERANCE_S: f32 = 2.5;
/// Weight of the newest phrase in the running utterance-length estimate.
const UTTERANCE_SMOOTHING: f32 = 0.3;
/// Speech level assumed before the first voiced frame, dBFS.
const PRIOR_SPEECH_LEVEL_DB: f32 = -26.0;

/// What a phrase event is decided with.
pub(crate) struct EventContext<'a> {
    pub(crate) config: &'a EngineConfig,
    /// The input sample whose arrival completed the frame that reported the event.
    pub(crate) now: u64,
    /// Per-channel gains of a breath placed now (the stereo image).
    pub(crate) gains: [f32; MAX_CHANNELS],
    /// A breath is playing and not fading out yet.
    pub(crate) breath_playing: bool,
    /// Frames analysed but not yet emitted (the lookahead's view of the upcoming phrase).
    pub(crate) pending: &'a Queue<Pending>,
}

/// See the module docs.
#[derive(Debug, Clone)]
pub(crate) struct Placement {
    mode: PlacementMode,
    latency: u64,
    sample_rate_hz: f64,
    state: PlacementState,
}

/// What [`Placement::reset`] clears.
#[derive(Debug, Clone, Copy)]
struct PlacementState {
    speech_level_db: f32,
    /// Power sum and count of the voiced frames of the phrase being spoken.
    phrase_power: f64,
    phrase_voiced: u32,
    /// Level of the last complete phrase, dBFS.
    last_phrase_level_db: Option<f32>,
    /// Running estimate of the utterance length, seconds.
    utterance_s: f32,
    /// End of the last scheduled breath (input sample).
    breath_end: u64,
}

impl Default for PlacementState {
    fn default() -> Self {
        Self {
            speech_level_db: PRIOR_SPEECH_LEVEL_DB,
            phrase_power: 0.0,
            phrase_voiced: 0,
            last_phrase_level_db: None,
            utterance_s: PRIOR_UTTERANCE_S,
            breath_end: 0,
        }
    }
}

impl Placement {
    /// A policy for `mode` with the delay line's `latency` (samples).
    pub(crate) fn new(mode: PlacementMode, latency: usize, sample_rate_hz: f64) -> Self {
        Self {
            mode,
            latency: latency as u64,
            sample_rate_hz,
            state: PlacementState::default(),
        }
    }

    /// Back to the start of a stream.
    pub(crate) fn reset(&mut self) {
        self.state = PlacementState::default();
    }

    /// Learns from one analysis frame; true when it is voiced speech with a finite level (the
    /// frames the stereo image learns from too).
    pub(crate) fn on_frame(&mut self, f: &FeatureFrame) -> bool {
        let voiced = f.voiced && f.rms_db.is_finite() && f.level_db.is_finite();
        if voiced {
            let s = &mut self.state;
            s.speech_level_db = f.rms_db - f.level_db;
            s.phrase_power += 10f64.powf(f.rms_db as f64 / 10.0);
            s.phrase_voiced += 1;
        }
        voiced
    }

    /// Level of the speech around a breath, dBFS: the phrase just spoken (its voiced frames'
    /// mean power), or, before the first phrase has ended, the loudest voiced frame of the
    /// upcoming phrase already analysed (lookahead; only its first tens of milliseconds are
    /// known, still rising, so their loudest frame stands for the phrase), or the running
    /// speech level.
    fn local_speech_level_db(&self, pending: &Queue<Pending>, onset_s: Option<f64>) -> f32 {
        if let Some(db) = self.state.last_phrase_level_db {
            return db;
        }
        if let Some(onset_s) = onset_s {
            let loudest = pending
                .iter()
                .filter(|p| {
                    p.frame.time_s >= onset_s && p.frame.voiced && p.frame.rms_db.is_finite()
                })
                .map(|p| p.frame.rms_db)
                .fold(f32::NEG_INFINITY, f32::max);
            if loudest.is_finite() {
                return loudest;
            }
        }
        self.state.speech_level_db
    }

    /// Plateau RMS (linear) of a breath near speech at `speech_level_db`.
    fn breath_gain(config: &EngineConfig, speech_level_db: f32) -> f32 {
        let neutral = crate::breathing::BreathingParams::default()
            .map()
            .breath_rms_re_speech();
        let ours = config.breathing.map().breath_rms_re_speech();
        let preset_db = if neutral > 0.0 && ours > 0.0 {
            20.0 * (ours / neutral).log10()
        } else if ours <= 0.0 {
            -200.0
        } else {
            0.0
        };
        let rel_db = (config.placement.breath_level_db + preset_db).min(-6.0);
        10f32.powf((speech_level_db + rel_db) / 20.0)
    }

    /// Live mode: speech (or something like it) began in the pause, reported at `ctx.now` with
    /// its first active frame at input sample `from`: nothing more starts in this pause, a
    /// breath playing fades out (if the gate has not faded it already), and the breathing cycle
    /// stops inspiring.
    fn live_activity(&mut self, ctx: &EventContext, from: u64, schedule: &mut Schedule) {
        schedule
            .breath
            .retain(|&(t, a)| !(t >= from && matches!(a, BreathAction::LiveStart { .. })));
        self.state.breath_end = self.state.breath_end.min(from);
        if ctx.breath_playing {
            schedule
                .breath
                .insert_sorted((ctx.now, BreathAction::FadeOut));
        }
        schedule.note_activity(ctx.now);
    }

    /// Schedules what phrase event `e` calls for.
    pub(crate) fn on_event(&mut self, ctx: &EventContext, e: PhraseEvent, schedule: &mut Schedule) {
        let config = ctx.config;
        let p = &config.placement;
        let rate = self.sample_rate_hz;
        let now = ctx.now;
        let live = self.mode == PlacementMode::Live;
        let inspiration_s = config.breathing.map().length_inspiration_s as f64;
        match e {
            PhraseEvent::Activity { time_s } => {
                if live {
                    self.live_activity(ctx, (time_s * rate).round() as u64, schedule);
                }
            }
            PhraseEvent::Start { onset_s, pause } => {
                let utterance_s = self.state.utterance_s;
                self.state.phrase_power = 0.0;
                self.state.phrase_voiced = 0;
                schedule
                    .cycle
                    .insert_sorted((onset_s, CycleAction::UtteranceStarts { utterance_s }));
                if live {
                    // The onset may lie before the first active frame (a quiet consonant).
                    self.live_activity(ctx, (onset_s * rate).round() as u64, schedule);
                    return;
                }
                if onset_s - pause.start_s < p.min_pause_s as f64 {
                    return;
                }
                let end_s = onset_s - p.gap_s as f64;
                // Never over activity inside the pause, never in the past (the output has
                // reached input sample `now - latency`), never before the previous breath ended.
                let after_s = pause
                    .last_activity_end_s
                    .map_or(pause.start_s, |a| a.max(pause.start_s));
                let after_s = if pause.leading && pause.last_activity_end_s.is_none() {
                    after_s
                } else {
                    after_s + p.after_offset_s as f64
                };
                let earliest = ((now + 1).saturating_sub(self.latency)).max(self.state.breath_end)
                    as f64
                    / rate;
                let start_s = (end_s - inspiration_s).max(after_s).max(earliest);
                if end_s - start_s < MIN_BREATH_S {
                    return;
                }
                let start = (start_s * rate).round() as u64;
                let length = ((end_s - start_s) * rate).round() as usize;
                // The body breathes in whether or not a sound is inserted (a breath already in
                // the pause, or insertion switched off).
                schedule.cycle.insert_sorted((
                    start_s,
                    CycleAction::Inspire {
                        length_s: (end_s - start_s) as f32,
                        utterance_s,
                    },
                ));
                if !p.insert_breaths || pause.has_breath {
                    return;
                }
                let level_db = self.local_speech_level_db(ctx.pending, Some(onset_s));
                schedule.breath.insert_sorted((
                    start,
                    BreathAction::Start {
                        length,
                        gain: Self::breath_gain(config, level_db),
                        gains: ctx.gains,
                    },
                ));
                self.state.breath_end = start + length as u64;
            }
            PhraseEvent::End { onset_s, offset_s } => {
                let s = &mut self.state;
                let length_s = (offset_s - onset_s).max(0.0) as f32;
                s.utterance_s += UTTERANCE_SMOOTHING * (length_s - s.utterance_s);
                if s.phrase_voiced >= 3 {
                    s.last_phrase_level_db =
                        Some((10.0 * (s.phrase_power / s.phrase_voiced as f64).log10()) as f32);
                }
                schedule
                    .cycle
                    .insert_sorted((offset_s, CycleAction::SpeechStopped));
                if live {
                    // The inhalation (sound and cycle) starts once the pause has lasted the
                    // minimum pause and `after_offset_s`, unless the input is active then;
                    // activity before then cancels it (`live_activity`), activity while it
                    // plays fades it out (the gate, in the breath track).
                    let wait_s = (p.min_pause_s as f64).max(p.after_offset_s as f64);
                    let start = ((((offset_s + wait_s) * rate).round() as u64).max(now))
                        .max(self.state.breath_end);
                    let length = (inspiration_s * rate).round() as usize;
                    let level_db = self.local_speech_level_db(ctx.pending, None);
                    schedule.breath.insert_sorted((
                        start,
                        BreathAction::LiveStart {
                            length,
                            gain: Self::breath_gain(config, level_db),
                            gains: ctx.gains,
                            audible: p.insert_breaths,
                            utterance_s: self.state.utterance_s,
                        },
                    ));
                    self.state.breath_end = start + length as u64;
                }
            }
        }
    }
}
