//! Breath placement: turns phrase events into scheduled breath and breathing-cycle actions, with
//! the two policies of [`PlacementMode`] (see the engine's module docs for the rules). It also
//! keeps what the decisions need: the running speech level, the level of the last phrase and
//! the breath-group plan.
//!
//! ## Breath groups
//! A breath serves the speech until the next breath (its *group*), not one phrase. In lookahead
//! mode a pause is decided as late as possible, when the output reaches it (or, when the phrase
//! after it is too little heard to tell speech from music, as late as a breath still fits), so
//! the decision sees as much of the coming speech as the lookahead holds (a whole-file render
//! looks 8 s ahead); live mode decides at once, with the running estimate.
//! - A *usable* pause (at least `min_pause_s`) gets a breath sized for the coming group: the
//!   speech until the next usable pause as far as it is known, at least the running estimate of
//!   a group's speech while its end is not in sight, at most two full breaths' utterance
//!   (`2 · length_utterance_s`). Its length grows with the pause and the group
//!   ([`breath_length_s`]).
//! - A shorter pause gets a *catch breath* (`catch_breath_min_s`–`catch_breath_max_s`, with
//!   narrower margins) when the air planned for the group would run out: the speech already
//!   known to follow exceeds the speech the group has left, or the plan is used up.
//! - Every phrase onset tells the cycle how much speech its group has left, so the lung falls
//!   over the whole group and ends it at the reserve, and a pause inside a group holds the
//!   breath.
//! - A breath already in the pause (the phrase tracker's `Pause::breath_s`) is the group's
//!   breath: the inspiration lies on it, at its time and length, and no sound is inserted.
//! - A stream that starts in speech starts with the lung filled for the first group (the
//!   speaker breathed in before it), or inspires up to its first onset; so does a stream that
//!   starts inside sound ([`StreamStart`]: an edit cut into a word), with no breath inserted
//!   and no heard breath taken before its first phrase. Live mode inspires with a breath it
//!   hears before the first phrase, and fills the lung at the first phrase's confirmation
//!   when it heard none.
//! - Live mode takes no catch breaths under `min_pause_s` (it cannot know a pause's length
//!   before the pause is over, and a breath started earlier lands on the next word); it sizes
//!   each breath for the running estimate of a group instead.

mod live;
mod pauses;

use super::schedule::{BreathAction, CycleAction, Pending, Queue, Schedule};
use super::speaker_level::{PhraseLevels, VoicedLevels, MIN_VOICED_FRAMES};
use super::speech_track::{SpeechTrack, SILERO_SHOWS_SPEECH_S};
use super::stream_start::StreamStart;
use super::{EngineConfig, PlacementConfig, PlacementMode, MAX_CHANNELS};
use crate::analysis::FeatureFrame;
use crate::breathing::learned::speaker_reference_db;
use crate::breathing::{LowLevelParams, MIN_LUNG_VOLUME};
use crate::phrase::{Pause, PhraseEvent};
use crate::speech::JUDGE_WINDOW_S;
use pauses::{pause_across, quiet_between, rest_of_cut_breath};

/// Shortest inhalation worth inserting, seconds.
const MIN_BREATH_S: f64 = 0.12;
/// Prior of a breath group's speech before any group was heard, seconds.
pub(crate) const PRIOR_GROUP_S: f32 = 2.5;
/// Weight of the newest group in the running estimate of a group's speech (and of the newest
/// pause in live mode's estimate of the speaker's pauses).
const GROUP_SMOOTHING: f32 = 0.3;
/// Prior of live mode's estimate of a pause the speaker breathes in (from the end of the
/// phrase to the next onset), seconds, before any was heard: about what a read speaker's
/// breath pauses last (Keele's f1: median 0.43 s over its nine pauses of 0.25 s or more).
const PRIOR_BREATH_PAUSE_S: f32 = 0.5;
/// Speech a group must have spoken before a catch breath may end it, seconds.
const MIN_SPOKEN_BEFORE_CATCH_S: f32 = 1.0;
/// How much more known speech than planned air a group tolerates before a catch breath, s.
const CATCH_SLACK_S: f32 = 0.3;
/// Margins of a catch breath after the phrase end and before the onset, seconds.
const CATCH_MARGIN_S: f64 = 0.01;
/// Least speech left that an onset plans its expiration over, seconds.
const MIN_LEFT_S: f32 = 0.5;

/// How long a breath is against the breathing parameters' inspiration (see
/// [`breath_length_s`]): chosen leave-one-speaker-out on the labelled real breaths of
/// `../shared/data` (`pneuma eval restore`, its breath-length fit: cut, restored, duration
/// against the real breath), from ×1.0 to ×1.6, where a breath after a long pause reaches
/// [`MAX_BREATH_S`].
pub const BREATH_LENGTH_SCALE: f64 = 1.6;
/// Longest breath, in inspiration lengths of the breathing parameters.
const MAX_BREATH_INSPIRATIONS: f64 = 2.5;
/// Longest breath, seconds: real inhalations are rarely longer (median about 0.35 s), however
/// long the silence before the phrase.
pub(crate) const MAX_BREATH_S: f64 = 0.8;
/// A pause longer than this makes the breath no longer, seconds: after a long silence the
/// speaker takes a normal inhalation before speaking, not a sigh.
const LONGEST_PAUSE_EFFECT_S: f64 = 2.0;
/// Speech level assumed before the first voiced frame, dBFS.
const PRIOR_SPEECH_LEVEL_DB: f32 = -26.0;
/// A breath takes the stereo image of the phrase after it (the speaker who inhales), as the
/// image stands this long into that phrase, seconds (or when the breath is decided, if that
/// comes first): the image's running shares (5 % per voiced frame) then lie about 90 % on a new
/// speaker's side at 120 frames per second.
const IMAGE_INTO_PHRASE_S: f64 = 0.6;

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
    /// The speech decision's judgements of the phrases.
    pub(crate) speech: &'a SpeechTrack,
    /// The upper edge of the recording's spectrum as heard so far, Hz.
    pub(crate) upper_edge_hz: Option<f64>,
    /// The recording's speech level as the breath voice knows it (the whole recording's, or
    /// heard so far), dBFS; NaN before any.
    pub(crate) speech_db: f64,
}

/// A phrase the tracker reported whose pause (the one before it) is not decided yet.
#[derive(Debug, Clone, Copy)]
struct Seen {
    onset_s: f64,
    /// Where its speech began by Silero ([`SpeechTrack::speech_onset_s`]) or by its lead-in
    /// (`Pause::lead_in_s`: a leading consonant heard apart), at or before `onset_s`: breaths
    /// end before it.
    speech_onset_s: f64,
    /// Its offset once its end was reported.
    offset_s: Option<f64>,
    pause: Pause,
    gains: [f32; MAX_CHANNELS],
    level_db: f32,
    /// Its own median level once it ended ([`PhraseLevels::end`]), dBFS.
    own_db: Option<f32>,
    /// Its speech judgement once it ended (its first half second heard, unless all its voiced
    /// frames said otherwise: [`SpeechTrack::unsaid`]).
    speech: Option<bool>,
    /// Judged not speech, it turned to speech to its end ([`SpeechTrack::last_ended_turned_s`]).
    turned: bool,
}

impl Default for Seen {
    fn default() -> Self {
        Self {
            onset_s: 0.0,
            speech_onset_s: 0.0,
            offset_s: None,
            pause: Pause {
                start_s: 0.0,
                end_s: 0.0,
                leading: true,
                has_breath: false,
                breath_s: None,
                breath_clean_s: None,
                last_activity_end_s: None,
                lead_in_s: None,
                gated_s: None,
            },
            gains: [1.0; MAX_CHANNELS],
            level_db: PRIOR_SPEECH_LEVEL_DB,
            own_db: None,
            speech: None,
            turned: false,
        }
    }
}

/// Length of a full breath, seconds: the breathing parameters' inspiration (scaled by
/// [`BREATH_LENGTH_SCALE`]), longer in longer
/// pauses (up to `LONGEST_PAUSE_EFFECT_S`) and for longer coming groups (`volume` 0..1 of the
/// lung), at most `MAX_BREATH_INSPIRATIONS` inspirations and `MAX_BREATH_S`. Whatever fits in
/// the pause is used of it.
pub(crate) fn breath_length_s(inspiration_s: f64, pause_s: f64, volume: f64) -> f64 {
    let v = volume.clamp(0.0, 1.0);
    let pause_s = pause_s.clamp(0.0, LONGEST_PAUSE_EFFECT_S);
    (BREATH_LENGTH_SCALE * inspiration_s * (0.5 + 0.3 * pause_s) * (0.75 + 0.25 * v))
        .min(MAX_BREATH_INSPIRATIONS * inspiration_s)
        .min(MAX_BREATH_S)
}

/// The lung volume (0..1) a breath takes in for a group of `group_s` seconds of speech: its
/// share of a full breath's utterance, at least [`MIN_LUNG_VOLUME`] (as the breathing cycle's
/// [`crate::breathing::BreathCycle::lung_volume_for`]).
fn group_volume(map: &LowLevelParams, group_s: f32) -> f32 {
    (group_s / map.length_utterance_s.max(1e-3)).clamp(MIN_LUNG_VOLUME, 1.0)
}

/// How long live mode waits after a phrase's end before a breath may start, seconds: the
/// minimum pause (a shorter one gets none) and the silence kept after a phrase.
fn live_wait_s(p: &PlacementConfig) -> f64 {
    f64::from(p.min_pause_s.max(p.after_offset_s))
}

/// See the module docs.
#[derive(Debug, Clone)]
pub(crate) struct Placement {
    mode: PlacementMode,
    latency: u64,
    sample_rate_hz: f64,
    /// Duration of one analysis frame, seconds.
    hop_s: f64,
    /// Phrases whose pause waits for its decision, oldest first.
    seen: Queue<Seen>,
    state: PlacementState,
}

/// What [`Placement::reset`] clears.
#[derive(Debug, Clone, Copy)]
struct PlacementState {
    speech_level_db: f32,
    /// The phrase being spoken and the recent phrases' levels.
    levels: PhraseLevels,
    /// Level of the last complete phrase, dBFS.
    last_phrase_level_db: Option<f32>,
    /// The level of the speaker of the phrase that ended at the last end event, dBFS (NaN: the
    /// phrase had too few voiced frames; [`PhraseLevels::speaker_of`]).
    ended_speaker_db: f32,
    /// Running estimate of a breath group's speech, seconds.
    group_estimate_s: f32,
    /// Speech planned for the current group and spoken in it so far, seconds.
    group_planned_s: f32,
    group_spoken_s: f32,
    /// Onset of the last phrase decided (its speech counts once the next one is decided).
    last_onset_s: Option<f64>,
    /// End of the last scheduled breath (input sample).
    breath_end: u64,
    /// The speech judgement of the last phrase decided and ended (lookahead mode).
    prev_speech: Option<bool>,
    /// That phrase, judged not speech, turned to speech to its end.
    prev_turned: bool,
    /// Whether the stream starts inside sound.
    start: StreamStart,
    /// Live mode: a real breath was heard in the pause since the last phrase ended.
    live_breath_heard: bool,
    /// Live mode: the last phrase that ended was judged other sound by its tail.
    live_after_other: bool,
    /// Live mode: the group planned for the breath of the pause going on, until the speaker's
    /// own breath in it has started the cycle's inspiration.
    live_group_s: Option<f32>,
    /// Live mode: where the pause going on began, when a breath was planned in it (after
    /// speech).
    live_pause_from_s: Option<f64>,
    /// Live mode: running estimate of the pauses the speaker breathes in, seconds.
    breath_pause_s: f32,
    /// Live mode: the group's plan before the breath planned in the pause going on started a
    /// new group (estimate, planned, spoken, seconds), until that breath starts; speech
    /// before it cancels it, and the group goes on.
    live_group_undo: Option<(f32, f32, f32)>,
}

impl Default for PlacementState {
    fn default() -> Self {
        Self {
            speech_level_db: PRIOR_SPEECH_LEVEL_DB,
            levels: PhraseLevels::default(),
            last_phrase_level_db: None,
            ended_speaker_db: f32::NAN,
            group_estimate_s: PRIOR_GROUP_S,
            group_planned_s: 0.0,
            group_spoken_s: 0.0,
            last_onset_s: None,
            breath_end: 0,
            prev_speech: None,
            prev_turned: false,
            start: StreamStart::default(),
            live_breath_heard: false,
            live_after_other: false,
            live_group_s: None,
            live_pause_from_s: None,
            breath_pause_s: PRIOR_BREATH_PAUSE_S,
            live_group_undo: None,
        }
    }
}

impl Placement {
    /// A policy for `mode` with the delay line's `latency` (samples) and frames at
    /// `frame_rate_hz`. Allocates.
    pub(crate) fn new(
        mode: PlacementMode,
        latency: usize,
        sample_rate_hz: f64,
        frame_rate_hz: f64,
    ) -> Self {
        // A phrase and its pause last at least a few frames; room for every one the lookahead
        // can hold (a full queue decides its oldest pause early).
        let capacity = (latency as f64 / sample_rate_hz * frame_rate_hz / 8.0).ceil() as usize + 8;
        Self {
            mode,
            latency: latency as u64,
            sample_rate_hz,
            hop_s: 1.0 / frame_rate_hz,
            seen: Queue::with_capacity(capacity),
            state: PlacementState::default(),
        }
    }

    /// Back to the start of a stream.
    pub(crate) fn reset(&mut self) {
        self.seen.clear();
        self.state = PlacementState::default();
    }

    /// Learns from one analysis frame; true when it is voiced speech with a finite level (the
    /// frames the stereo image learns from too).
    pub(crate) fn on_frame(&mut self, f: &FeatureFrame) -> bool {
        self.state.start.frame(f.time_s, f.rms_db);
        let voiced = self.state.levels.frame(f);
        if voiced {
            self.state.speech_level_db = f.speech_level_db;
        }
        voiced
    }

    /// The stereo image after voiced frame `time_s`: within [`IMAGE_INTO_PHRASE_S`] of the
    /// onset of the phrase heard last, the breath in the pause before it takes it while it is
    /// undecided (a render decides it well after that; the plugin's 500 ms lookahead when the
    /// output reaches the pause, having heard little or none of the phrase).
    pub(crate) fn follow_image(&mut self, time_s: f64, gains: [f32; MAX_CHANNELS]) {
        if let Some(ph) = self.seen.back_mut() {
            if time_s >= ph.onset_s && time_s - ph.onset_s <= IMAGE_INTO_PHRASE_S {
                ph.gains = gains;
            }
        }
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

    /// Mean power of the voiced frames of the phrase being spoken, dBFS, once it has at least
    /// `frames` of them.
    fn spoken_level_db(&self, frames: u32) -> Option<f32> {
        self.state.levels.spoken(frames).map(|l| l.mean_db)
    }

    /// The level of the speaker of the phrase that ended at the last end event, dBFS (NaN:
    /// not known).
    pub(crate) fn ended_speaker_db(&self) -> f32 {
        self.state.ended_speaker_db
    }

    /// How far over its level a breath voice plays before phrase `ph` (the one after the
    /// pause), dB: its speaker's level ([`speaker_reference_db`]) less the recording's speech
    /// level. The speaker's from the phrase's own level once it ended, else from its voiced
    /// frames analysed so far once they span the speech decision's window (a lookahead that
    /// holds that much of it before its breath: a render's 8 s), else from the last phrase's
    /// (live mode, and a lookahead too short to hear [`JUDGE_WINDOW_S`] of the phrase before
    /// its breath, as the plugin's default 500 ms: it has heard the phrase's rising onset only,
    /// whose median lies several dB under the phrase's and would make the speaker's own breath
    /// another, quieter speaker's); 0 before any.
    fn breath_speaker_db(&self, ctx: &EventContext, ph: Option<&Seen>) -> f32 {
        let speaker = self.speaker_of(ctx.pending, ph);
        if !(speaker.is_finite() && ctx.speech_db.is_finite()) {
            return 0.0;
        }
        (speaker_reference_db(f64::from(speaker), ctx.speech_db) - ctx.speech_db) as f32
    }

    /// The level of the speaker of phrase `ph` (see [`Placement::breath_speaker_db`]), dBFS;
    /// NaN before any phrase.
    fn speaker_of(&self, pending: &Queue<Pending>, ph: Option<&Seen>) -> f32 {
        // The phrase's frames in the lookahead, up to its offset once it is known (a phrase
        // that ended with too few voiced frames for a level of its own: not the pause's nor
        // the next phrase's).
        let visible = |ph: &Seen| {
            let end_s = ph.offset_s.unwrap_or(f64::INFINITY);
            let mut levels = VoicedLevels::default();
            let mut heard_to_s = None;
            for p in pending
                .iter()
                .filter(|p| p.frame.time_s >= ph.onset_s && p.frame.time_s < end_s)
            {
                levels.add(&p.frame);
                heard_to_s = Some(p.frame.time_s);
            }
            if heard_to_s.is_none_or(|t| t - ph.onset_s < JUDGE_WINDOW_S) {
                return None;
            }
            levels.level(MIN_VOICED_FRAMES).map(|l| l.median_db)
        };
        ph.and_then(|ph| ph.own_db.or_else(|| visible(ph)))
            .or(self.state.levels.last_db())
            .map_or(f32::NAN, |db| self.state.levels.speaker_level_db(db))
    }

    /// The level of the speech measured so far, dBFS: the last complete phrase's, else the
    /// voiced frames of the one being spoken; `None` before any.
    fn measured_phrase_level_db(&self) -> Option<f32> {
        self.state
            .last_phrase_level_db
            .or_else(|| self.spoken_level_db(1))
    }

    /// Plateau RMS (linear) of a breath near speech at `speech_level_db`.
    fn breath_gain(config: &EngineConfig, speech_level_db: f32) -> f32 {
        10f32.powf((speech_level_db + config.breath_level_re_speech_db()) / 20.0)
    }

    /// Schedules what phrase event `e` calls for (lookahead mode: remembers a phrase start for
    /// [`Placement::decide_due`]).
    pub(crate) fn on_event(&mut self, ctx: &EventContext, e: PhraseEvent, schedule: &mut Schedule) {
        let rate = self.sample_rate_hz;
        let live = self.mode == PlacementMode::Live;
        match e {
            PhraseEvent::Activity { time_s } => {
                if live {
                    self.live_activity(ctx, (time_s * rate).round() as u64, schedule);
                }
            }
            PhraseEvent::Start { onset_s, pause } => {
                self.state.start.close();
                self.state.live_group_s = None;
                self.state.levels.start();
                if live {
                    self.live_phrase_started(ctx, onset_s, pause, schedule);
                    return;
                }
                if self.seen.is_full() {
                    self.decide_front(ctx, schedule);
                }
                let level_db = self.local_speech_level_db(ctx.pending, Some(onset_s));
                self.seen.push_back(Seen {
                    onset_s,
                    speech_onset_s: ctx
                        .speech
                        .speech_onset_s(pause.start_s, onset_s)
                        .min(pause.lead_in_s.unwrap_or(onset_s)),
                    offset_s: None,
                    pause,
                    gains: ctx.gains,
                    level_db,
                    own_db: None,
                    speech: None,
                    turned: false,
                });
            }
            PhraseEvent::End { onset_s, offset_s } => {
                let ended = self.state.levels.end();
                let own_db = ended.map(|l| l.median_db);
                self.state.ended_speaker_db = self.state.levels.speaker_of(ended);
                if let Some(l) = ended {
                    self.state.last_phrase_level_db = Some(l.mean_db);
                }
                schedule
                    .cycle
                    .insert_sorted((offset_s, CycleAction::SpeechStopped));
                if !live {
                    // The phrase that ended is the last one seen, or, decided already, the
                    // one before the next pause.
                    // A phrase judged speech by its first window whose voiced frames, all of
                    // them, are not speech (a sung line that starts like speech) is not: the
                    // body's judgement of it, so no breath is taken for a song.
                    let unsaid = ctx.speech.last_ended_unsaid();
                    let speech = ctx.speech.last_ended().map(|speech| speech && !unsaid);
                    let turned = ctx.speech.last_ended_turned_s().is_some();
                    match self.seen.back_mut() {
                        Some(last) => {
                            last.offset_s = Some(offset_s);
                            last.own_db = own_db;
                            last.speech = speech;
                            last.turned = turned;
                        }
                        None => (self.state.prev_speech, self.state.prev_turned) = (speech, turned),
                    }
                    return;
                }
                self.live_phrase_ended(ctx, (onset_s, offset_s), schedule);
            }
        }
    }

    /// Lookahead mode: decides every pause whose time has come (the output is about to reach
    /// it, and the phrase after it does not [`Placement::waits`]), after the events of frame
    /// `ctx.now`.
    pub(crate) fn decide_due(&mut self, ctx: &EventContext, schedule: &mut Schedule) {
        if self.mode == PlacementMode::Live {
            return;
        }
        // Negative while the output has not started (the delay line is filling).
        let out_s = ((ctx.now + 1) as f64 - self.latency as f64) / self.sample_rate_hz;
        while let Some(front) = self.seen.front() {
            // A phrase judged speech after other sound is decided a breath earlier: its
            // speaker may have breathed in under the sound's end ([`Placement::decide_front`]).
            let lead_s = if self.state.prev_speech == Some(false) && front.speech == Some(true) {
                MAX_BREATH_S
            } else {
                0.0
            };
            if out_s + 2.0 * self.hop_s < front.pause.start_s - lead_s {
                break;
            }
            if self.waits(ctx, front, out_s) {
                break;
            }
            self.decide_front(ctx, schedule);
        }
    }

    /// Whether the front phrase `ph` waits to be decided, the output being at `out_s`: too
    /// little of it has been heard to tell speech from music ([`SILERO_SHOWS_SPEECH_S`]:
    /// Silero needs a few chunks), and the shortest breath of either kind the pause may get
    /// (an inhalation, a catch breath) still fits before it. The breath gets shorter; the
    /// pause before music gets none ([`SpeechTrack::heard_no_speech`]). A pause holding a heard
    /// breath does not wait (the inspiration lies on that breath, where it is), nor does one
    /// whose lookahead cannot hear that much of the phrase before the last moment.
    fn waits(&self, ctx: &EventContext, ph: &Seen, out_s: f64) -> bool {
        if ph.speech.is_some()
            || ph.pause.breath_s.is_some()
            || !ctx.speech.too_early_to_tell(ph.onset_s)
        {
            return false;
        }
        let p = &ctx.config.placement;
        let shortest_s =
            (p.gap_s as f64 + MIN_BREATH_S).max(CATCH_MARGIN_S + p.catch_breath_min_s as f64);
        let last_start_s = ph.speech_onset_s.min(ph.onset_s) - shortest_s - 2.0 * self.hop_s;
        // The input runs ahead of the output by the latency.
        let heard_then_s = last_start_s + self.latency as f64 / self.sample_rate_hz - ph.onset_s;
        heard_then_s >= SILERO_SHOWS_SPEECH_S && out_s < last_start_s
    }

    /// Speech the current group has left, seconds (at least `MIN_LEFT_S`).
    fn group_left_s(&self) -> f32 {
        (self.state.group_planned_s - self.state.group_spoken_s).max(MIN_LEFT_S)
    }

    /// A breath starts a group planned for `coming_s` seconds of speech (at most two full
    /// breaths' utterance); the group that ends feeds the running estimate. Returns the plan.
    fn new_group(&mut self, config: &EngineConfig, coming_s: f32) -> f32 {
        let s = &mut self.state;
        if s.group_spoken_s > 0.0 {
            s.group_estimate_s += GROUP_SMOOTHING * (s.group_spoken_s - s.group_estimate_s);
        }
        let max_s = 2.0 * config.breathing.map().length_utterance_s.max(0.5);
        s.group_planned_s = coming_s.clamp(0.0, max_s);
        s.group_spoken_s = 0.0;
        s.group_planned_s
    }

    /// Speech known from the oldest undecided phrase on until the next usable pause, seconds,
    /// and whether that pause is known (else the speech goes on past what was analysed). A
    /// quiet sound between phrases of speech ([`quiet_between`]) with a phrase after it is
    /// part of the pause around it, as [`Placement::absorb_quiet_front`] will take it.
    fn known_group_s(&self, now_s: f64, min_pause_s: f64) -> (f64, bool) {
        let mut known = 0.0;
        let mut last_offset = None;
        let mut speech_before = None;
        // The start of the pause and the speech level before the quiet sounds taken into it.
        let mut absorbed: Option<(f64, f32)> = None;
        let count = self.seen.len();
        for (k, ph) in self.seen.iter().enumerate() {
            let (pause_start_s, speech_db) = absorbed.unwrap_or((ph.pause.start_s, ph.level_db));
            if k > 0 && k + 1 < count && quiet_between(ph, speech_before, speech_db) {
                absorbed = Some((pause_start_s, speech_db));
                continue;
            }
            absorbed = None;
            if k > 0 && ph.onset_s - pause_start_s >= min_pause_s {
                return (known, true);
            }
            speech_before = ph.speech;
            match ph.offset_s {
                Some(off) => {
                    known += (off - ph.onset_s).max(0.0);
                    last_offset = Some(off);
                }
                None => return (known + (now_s - ph.onset_s).max(0.0), false),
            }
        }
        let ended = last_offset.is_some_and(|off| now_s - off >= min_pause_s);
        (known, ended)
    }

    /// Lookahead mode: whether the pause before phrase `ph` (just taken from the front) is a
    /// pause of speech, so that a breath may go into it. The phrase after it is judged by its
    /// first half second once that has been heard (and by all its voiced frames so far when
    /// those say it is not speech, [`SpeechTrack::unsaid`]; offline: unless the pause is longer than
    /// the 8 s lookahead). While less of it is
    /// visible (the plugin's short lookahead), the pause counts when what is visible is speech
    /// or the phrase before the pause was speech, unless what is visible is long enough to
    /// have shown speech and did not ([`SpeechTrack::heard_no_speech`]: music after the last
    /// words); before any phrase has been judged (the stream's first), when Silero alone took
    /// the visible start for speech.
    fn pause_of_speech(&self, ctx: &EventContext, ph: &Seen) -> bool {
        if let Some(speech) = ph.speech {
            return speech;
        }
        // A phrase not yet ended is the one being spoken: the speech track's current judge,
        // and, when it is speech, its voiced frames so far (as at its end, above).
        let visible = match ctx.speech.current() {
            Some((speech, true)) => return speech && !ctx.speech.unsaid(),
            Some((speech, false)) => speech,
            None => false,
        };
        if ctx.speech.heard_no_speech() {
            return false;
        }
        match self.state.prev_speech {
            Some(before) => visible || before,
            None => visible || ctx.speech.silero_heard(),
        }
    }

    /// Lookahead mode: whether phrase `ph` itself (just taken from the front) is speech, so that
    /// a stream that starts with it starts with a breath taken: its judgement once it ended or
    /// its window was heard; while less of it is visible, when what is visible is speech or
    /// Silero heard speech in it (a voice under a bed is not taken for the bed).
    fn phrase_is_speech(ctx: &EventContext, ph: &Seen) -> bool {
        match (ph.speech, ctx.speech.current()) {
            (Some(speech), _) | (None, Some((speech, true))) => speech,
            (None, Some((visible, false))) => visible || ctx.speech.silero_heard(),
            (None, None) => ctx.speech.silero_heard(),
        }
    }

    /// Lookahead mode: when the oldest undecided phrase is a sound between phrases of speech
    /// rather than a phrase ([`quiet_between`]) and a phrase follows it, its pause and the next
    /// phrase's become one pause ([`pause_across`]), decided with the next phrase: a music
    /// bed's note alone in a gated gap does not split the speaker's pause into one before a
    /// phrase that is not speech and one too short for a breath. The next phrase takes the
    /// speech level before the sound, so a second quiet sound in the same pause is measured
    /// against that speech too. The judgement of the speech before the pause stays the last
    /// phrase's decided. True when it did.
    fn absorb_quiet_front(&mut self) -> bool {
        let Some(&quiet) = self.seen.front() else {
            return false;
        };
        if self.seen.len() < 2 || !quiet_between(&quiet, self.state.prev_speech, quiet.level_db) {
            return false;
        }
        self.seen.pop_front();
        if let Some(next) = self.seen.front_mut() {
            next.pause = pause_across(&quiet.pause, &next.pause);
            // The speech around the pause is the one before it, not the quiet sound.
            next.level_db = quiet.level_db;
        }
        true
    }

    /// Decides the pause of the oldest undecided phrase: a breath, a catch breath or none, and
    /// the phrase's share of its group.
    fn decide_front(&mut self, ctx: &EventContext, schedule: &mut Schedule) {
        if self.absorb_quiet_front() {
            return;
        }
        let Some(ph) = self.seen.front().copied() else {
            return;
        };
        let config = ctx.config;
        let p = &config.placement;
        let rate = self.sample_rate_hz;
        let map = config.breathing.map();
        let inspiration_s = map.length_inspiration_s as f64;
        let now_s = ctx.now as f64 / rate;
        let (onset_s, pause) = (ph.onset_s, ph.pause);
        if let Some(prev) = self.state.last_onset_s {
            self.state.group_spoken_s += (pause.start_s - prev).max(0.0) as f32;
        }
        self.state.last_onset_s = Some(onset_s);
        let spoken = Self::phrase_is_speech(ctx, &ph);
        let (known_s, complete) = self.known_group_s(now_s, p.min_pause_s as f64);
        self.seen.pop_front();
        let coming_s = if complete {
            known_s as f32
        } else {
            (known_s as f32).max(self.state.group_estimate_s)
        };
        let pause_s = onset_s - pause.start_s;
        // A stream that starts inside sound has no pause before its first phrase: the tracker
        // cannot tell a cut word's end from a room before it has heard the room.
        let in_sound = pause.leading
            && pause.last_activity_end_s.is_none()
            && self
                .state
                .start
                .in_sound(self.measured_phrase_level_db().unwrap_or(ph.level_db));
        let usable = pause_s >= p.min_pause_s as f64 && !in_sound;
        let speech = self.pause_of_speech(ctx, &ph);
        // The phrase before this one was judged other sound (a song, a sting, noise), and
        // did not turn to speech to its end (the body spoke on that tail: no inspiration
        // may lie on it).
        let after_other = self.state.prev_speech == Some(false) && !self.state.prev_turned;
        if ph.speech.is_some() {
            self.state.prev_speech = ph.speech;
            self.state.prev_turned = ph.turned;
        }
        let air_left_s = self.state.group_planned_s - self.state.group_spoken_s;
        let short_of_air = pause.leading
            || (self.state.group_spoken_s >= MIN_SPOKEN_BEFORE_CATCH_S
                && (known_s as f32 > air_left_s + CATCH_SLACK_S || air_left_s <= MIN_LEFT_S));
        // Never over activity inside the pause, never in the past (the output has reached
        // input sample `now - latency`), never before the previous breath ended.
        let quiet_from_s = pause
            .last_activity_end_s
            .map_or(pause.start_s, |a| a.max(pause.start_s));
        let earliest_s =
            ((ctx.now + 1).saturating_sub(self.latency)).max(self.state.breath_end) as f64 / rate;
        let volume = group_volume(&map, coming_s);
        let mut window = None;
        // A breath already in a pause of speech drives the cycle: the inspiration lies on it
        // (and no sound is inserted, below), whatever the pause's length.
        if let (true, Some((from_s, to_s))) = (speech && !in_sound, pause.breath_s) {
            let start_s = from_s.max(earliest_s);
            if to_s - start_s >= self.hop_s {
                window = Some((start_s, to_s));
            }
        }
        // Breaths end before the speech, where Silero heard it start if the tracker's onset is
        // late (a soft onset in noise or under a bed).
        let speech_onset_s = ph.speech_onset_s.min(onset_s);
        let want_s = breath_length_s(inspiration_s, pause_s, volume as f64);
        let after_s = if pause.leading && pause.last_activity_end_s.is_none() {
            quiet_from_s
        } else {
            quiet_from_s + p.after_offset_s as f64
        };
        // A breath heard beside a gated stretch is what a cut or a gate left of a longer one:
        // the rest goes back into the stretch, beside it (the sound inserted is that part only;
        // the inspiration covers both).
        let mut sound = None;
        if let (true, Some(heard), Some(gated)) = (usable && speech, pause.breath_s, pause.gated_s)
        {
            let end_limit_s = speech_onset_s - p.gap_s as f64;
            sound = rest_of_cut_breath(heard, gated, want_s, (after_s, end_limit_s), earliest_s);
            window = match (sound, window) {
                (Some((a, b)), Some((start_s, end_s))) => Some((start_s.min(a), end_s.max(b))),
                (sound, window) => window.or(sound),
            };
        }
        if usable && speech && window.is_none() {
            let end_s = speech_onset_s - p.gap_s as f64;
            let start_s = (end_s - want_s).max(after_s).max(earliest_s);
            if end_s - start_s >= MIN_BREATH_S {
                window = Some((start_s, end_s));
            }
        }
        if window.is_none() && short_of_air {
            let end_s = speech_onset_s - CATCH_MARGIN_S;
            let after_s = quiet_from_s + if pause.leading { 0.0 } else { CATCH_MARGIN_S };
            let start_s = (end_s - p.catch_breath_max_s as f64)
                .max(after_s)
                .max(earliest_s);
            if speech && !in_sound && end_s - start_s >= p.catch_breath_min_s as f64 - 1e-9 {
                window = Some((start_s, end_s));
            } else if pause.leading && spoken && self.state.group_planned_s <= 0.0 {
                // Speech from the very start of the stream: the speaker breathed before it
                // (an inspiration shorter than a breath would be a twitch of the controls).
                let group_s = self.new_group(config, coming_s);
                let at_s = earliest_s.min(onset_s).max(0.0);
                let action = if onset_s - at_s >= MIN_BREATH_S {
                    CycleAction::Inspire {
                        length_s: (onset_s - at_s) as f32,
                        group_s,
                    }
                } else {
                    CycleAction::BreathedIn { group_s }
                };
                schedule.cycle.insert_sorted((at_s, action));
            }
        }
        // No breath before a phrase after other sound (or, not speech, at the stream's start):
        // its speaker breathed in under that sound. Speech right after it (a host who speaks
        // as the song ends) starts a group, its lung filled before its onset (no sound). When
        // that lies in the past, the phrase is not judged speech yet (Silero takes singing for
        // speech), or it is other sound itself (speech may run on from it: `BodyGate`), the
        // lung is owed to its first speaking frame, for a group of the running estimate, and
        // the group plan is left as it is (a song must not end it).
        let owes = if spoken {
            after_other && !pause.leading
        } else {
            after_other || pause.leading
        };
        if window.is_none() && owes {
            // Judged speech implies `spoken` ([`Placement::phrase_is_speech`]): other sound is
            // always owed.
            let judged = matches!(
                (ph.speech, ctx.speech.current()),
                (Some(true), _) | (None, Some((true, true)))
            ) && (ph.speech.is_some() || !ctx.speech.unsaid());
            let at_s = (onset_s - want_s).max(earliest_s).min(onset_s);
            let action = if judged && onset_s - at_s >= MIN_BREATH_S {
                let group_s = self.new_group(config, coming_s);
                let length_s = (onset_s - at_s) as f32;
                (at_s, CycleAction::Inspire { length_s, group_s })
            } else {
                let group_s = self.state.group_estimate_s;
                (onset_s, CycleAction::BreathOwed { group_s })
            };
            schedule.cycle.insert_sorted(action);
        }
        if let Some((start_s, end_s)) = window {
            let group_s = self.new_group(config, coming_s);
            // A breath the speaker took (heard in the pause) fills the lung as far as its
            // length says, the share of the engine's own full breath for this pause, and at
            // least as far as the coming group needs: a long real inhalation before a short
            // group is still a deep one.
            let fill_s = match pause.breath_s {
                Some((from_s, to_s)) if speech && !in_sound => {
                    let full_s = breath_length_s(inspiration_s, pause_s, 1.0).max(self.hop_s);
                    let share = ((to_s - from_s) / full_s).min(1.0) as f32;
                    group_s.max(share * map.length_utterance_s)
                }
                _ => group_s,
            };
            // The body breathes in whether or not a sound is inserted (a breath already in the
            // pause, or insertion switched off).
            schedule.cycle.insert_sorted((
                start_s,
                CycleAction::Inspire {
                    length_s: (end_s - start_s) as f32,
                    group_s: fill_s,
                },
            ));
            if p.insert_breaths && (!pause.has_breath || sound.is_some()) {
                let (start_s, end_s) = sound.unwrap_or((start_s, end_s));
                let start = (start_s * rate).round() as u64;
                let length = ((end_s - start_s) * rate).round() as usize;
                schedule.breath.insert_sorted((
                    start,
                    BreathAction::Start {
                        length,
                        gain: Self::breath_gain(config, ph.level_db),
                        speaker_db: self.breath_speaker_db(ctx, Some(&ph)),
                        gains: ph.gains,
                        edge_hz: ctx.upper_edge_hz,
                    },
                ));
                self.state.breath_end = start + length as u64;
            }
        }
        let left_s = self.group_left_s();
        schedule
            .cycle
            .insert_sorted((onset_s, CycleAction::UtteranceStarts { left_s }));
    }
}

#[cfg(test)]
mod tests;
