//! [`PhraseTracker`]: the per-frame decision (active, over the floor, breath-like), the history
//! ring of those facts ([`super::facts`]), and the phrase and candidate state that turns them into events. The
//! breath runs of a pause ([`super::breath_run`]) and the room's band levels
//! ([`super::floor_bands`]) have rooms of their own.

use super::breath_run::{
    BreathRules, PauseBreaths, BREATH_HOLD_SHARE, BREATH_MIN_FLATNESS, BREATH_UNDER_WAY_S,
    TAIL_CLOSED_S,
};
use super::config::{PhraseConfig, PhraseError};
use super::events::{Pause, PhraseEvent};
use super::facts::FrameFacts;
use super::floor_bands::{
    FloorBands, FLOOR_BAND_TAU_S, FLOOR_BAND_UNDER_SPEECH_DB, FLOOR_BAND_WITHIN_DB,
};
use super::silent_run::{
    SilentRuns, CUT_CEILING_DB, GATED_DB, ROOM_HEARD_S, TOUCH_S, UNDER_ROOM_DB, UNDER_ROOM_MAX_S,
};
use crate::analysis::noise_floor::NoiseFloor;
use crate::analysis::{quiet_shift_db, FeatureFrame};

/// Number of half-second blocks the noise floor looks back over.
const FLOOR_BLOCKS: usize = 6;
/// Length of one block of the noise floor's minimum ring, seconds.
const FLOOR_BLOCK_S: f32 = 0.5;

/// The settings' durations as frame counts.
#[derive(Debug, Clone, Copy)]
struct FrameCounts {
    onset_voiced: u32,
    hangover: u64,
    edge: u64,
    offset: u64,
    run_gap: u64,
    /// [`TOUCH_S`]: a breath run and digital silence this close touch.
    touch: u64,
    /// [`UNDER_ROOM_MAX_S`]: the longest time under the room taken as an editor's.
    under_room_max: u32,
    /// [`ROOM_HEARD_S`]: frames at the room in a row that hear it again.
    room_heard: u32,
}

/// The phrase being spoken, or the last one.
#[derive(Debug, Clone, Copy, Default)]
struct PhraseState {
    /// Inside a phrase (between a confirmed onset and a confirmed offset).
    inside: bool,
    onset: u64,
    last_active: u64,
    /// The offset of the last phrase (`None` before the first).
    last_offset: Option<u64>,
}

/// A run of active frames in a pause that may become a phrase.
#[derive(Debug, Clone, Copy, Default)]
struct Candidate {
    /// Its first frame (`None` = no run going on).
    start: Option<u64>,
    last_active: u64,
    /// Voiced frames in it.
    voiced: u32,
}

/// What [`PhraseTracker::reset`] clears.
#[derive(Debug, Clone, Copy)]
struct TrackerState {
    /// The noise floor's latest value, dBFS.
    floor_db: f32,
    /// A frame that is not digital silence (over [`GATED_DB`]) has been heard.
    heard_sound: bool,
    /// Frames in a row [`UNDER_ROOM_DB`] or more under the room.
    under_room_frames: u32,
    /// Frames under the room since it was last heard (across phrases; digital silence not
    /// counted).
    under_room_total: u32,
    /// The lowest level among them, dBFS.
    under_room_low_db: f32,
    /// Frames in a row at the room.
    at_room_frames: u32,
    /// The room: the noise floor as the last quiet frame of a pause after a phrase (not
    /// active, not a cut) left it, dBFS (−∞ before any).
    room_db: f32,
    /// The room's band levels.
    floor_bands: FloorBands,
    frames_seen: u64,
    phrase: PhraseState,
    candidate: Candidate,
    /// Last active frame of a run in this pause that did not become a phrase.
    pause_last_active: Option<u64>,
    /// That run's first frame, and the last active frame of the runs before it in this pause,
    /// when it held no voiced frame (a consonant's burst).
    pause_last_run: Option<(u64, Option<u64>)>,
    /// Breath detection inside the current pause.
    breaths: PauseBreaths,
    /// The current pause's silent stretches.
    silent: SilentRuns,
}

impl Default for TrackerState {
    fn default() -> Self {
        Self {
            floor_db: f32::NEG_INFINITY,
            heard_sound: false,
            under_room_frames: 0,
            under_room_total: 0,
            under_room_low_db: f32::INFINITY,
            at_room_frames: 0,
            room_db: f32::NEG_INFINITY,
            floor_bands: FloorBands::default(),
            frames_seen: 0,
            phrase: PhraseState::default(),
            candidate: Candidate::default(),
            pause_last_active: None,
            pause_last_run: None,
            breaths: PauseBreaths::default(),
            silent: SilentRuns::default(),
        }
    }
}

/// The phrase tracker. Feed it every feature frame in order with [`PhraseTracker::update`].
#[derive(Debug, Clone)]
pub struct PhraseTracker {
    config: PhraseConfig,
    frame_rate_hz: f64,
    counts: FrameCounts,
    breath_rules: BreathRules,
    /// Noise floor (minimum statistics).
    floor: NoiseFloor,
    /// Noise floor of the breath bands alone (minimum statistics, the same window).
    breath_floor: NoiseFloor,
    /// Weight of one frame in the room's band levels (from [`FLOOR_BAND_TAU_S`]).
    floor_band_weight: f64,
    /// History ring of the last `history.len()` frames.
    history: Vec<FrameFacts>,
    state: TrackerState,
}

impl PhraseTracker {
    /// Creates a tracker for frames at `frame_rate_hz`.
    pub fn new(config: PhraseConfig, frame_rate_hz: f64) -> Result<Self, PhraseError> {
        config.validate()?;
        crate::settings::analysis::FRAME_RATE_HZ.check(frame_rate_hz)?;
        let frames = |s: f32| ((s as f64) * frame_rate_hz).round().max(1.0) as u64;
        let edge_frames = frames(config.edge_extend_s);
        let frames = |s: f32| ((s as f64) * frame_rate_hz).round() as u64;
        let hangover_frames = frames(config.hangover_s);
        let history_len = (edge_frames.max(hangover_frames) + frames(1.0)) as usize;
        let frames = |s: f32| ((s as f64) * frame_rate_hz).round().max(1.0) as u64;
        Ok(Self {
            counts: FrameCounts {
                onset_voiced: frames(config.onset_voiced_s) as u32,
                hangover: hangover_frames,
                edge: edge_frames,
                offset: frames(config.offset_extend_s),
                run_gap: frames(config.run_gap_s),
                touch: frames(TOUCH_S as f32),
                under_room_max: frames(UNDER_ROOM_MAX_S) as u32,
                room_heard: frames(ROOM_HEARD_S) as u32,
            },
            breath_rules: BreathRules {
                min_frames: frames(config.breath_min_s) as u32,
                under_way_frames: frames(BREATH_UNDER_WAY_S) as u32,
                tail_closed_frames: frames(TAIL_CLOSED_S) as u32,
                max_high_over_mid_db: config.breath_max_high_over_mid_db,
                max_low_over_mid_db: config.breath_max_low_over_mid_db,
                min_flatness: BREATH_MIN_FLATNESS,
            },
            floor: NoiseFloor::with_blocks(frames(FLOOR_BLOCK_S) as usize, FLOOR_BLOCKS),
            breath_floor: NoiseFloor::with_blocks(frames(FLOOR_BLOCK_S) as usize, FLOOR_BLOCKS),
            config,
            frame_rate_hz,
            floor_band_weight: 1.0 / (FLOOR_BAND_TAU_S * frame_rate_hz).max(1.0),
            history: vec![FrameFacts::default(); history_len],
            state: TrackerState::default(),
        })
    }

    /// Clears all state (start of a new stream).
    pub fn reset(&mut self) {
        self.floor.reset();
        self.breath_floor.reset();
        self.history
            .iter_mut()
            .for_each(|f| *f = FrameFacts::default());
        self.state = TrackerState::default();
    }

    /// The settings.
    pub fn config(&self) -> &PhraseConfig {
        &self.config
    }

    /// The current noise-floor estimate in dBFS (−∞ before the first frame).
    pub fn noise_floor_db(&self) -> f32 {
        self.state.floor_db
    }

    /// True while inside a phrase (between a confirmed onset and a confirmed offset).
    pub fn in_phrase(&self) -> bool {
        self.state.phrase.inside
    }

    /// How far in the past (seconds) an event may refer at most when it is reported: the
    /// hangover for offsets, the onset confirmation plus the edge extension for onsets.
    pub fn max_report_delay_s(&self) -> f64 {
        let n = &self.counts;
        let onset = n.edge + n.run_gap * 4 + n.onset_voiced as u64;
        onset.max(n.hangover) as f64 / self.frame_rate_hz
    }

    fn time_s(&self, index: u64) -> f64 {
        index as f64 / self.frame_rate_hz
    }

    fn facts(&self, index: u64) -> FrameFacts {
        self.history[(index % self.history.len() as u64) as usize]
    }

    /// In a pause after a phrase (not before the first one).
    fn after_phrase(&self) -> bool {
        !self.state.phrase.inside && self.state.phrase.last_offset.is_some()
    }

    /// In a pause after a phrase, with no activity heard since the breath run going on began
    /// (a candidate phrase ends what the run may be).
    fn quiet_after_phrase(&self) -> bool {
        self.after_phrase() && self.quiet_in_pause()
    }

    /// In a pause (the silence before the first phrase included), with no activity heard since
    /// the breath run going on began.
    fn quiet_in_pause(&self) -> bool {
        !self.state.phrase.inside && self.state.candidate.start.is_none()
    }

    /// A breath has been heard in the pause going on (after a phrase) so far: the speaker is
    /// breathing in, or did. Live mode reads it to keep an inserted breath off a real one.
    pub fn breath_heard_in_pause(&self) -> bool {
        self.after_phrase() && self.state.breaths.heard_so_far(&self.breath_rules)
    }

    /// Breath-like sound is going on in the pause after a phrase (see
    /// [`super::breath_run::BREATH_UNDER_WAY_S`]), and no activity since it began: the speaker
    /// may be breathing in, and the detector has not confirmed it yet. Live mode starts no
    /// breath over it.
    pub fn breath_under_way_in_pause(&self) -> bool {
        self.quiet_after_phrase() && self.state.breaths.under_way(&self.breath_rules)
    }

    /// The speaker is breathing in now, in a pause (after a phrase, or in the silence before
    /// the first one): a strict breath run going on counts as a breath already (its length,
    /// `breath_min_s`, and its shape), and no activity since it began. Live mode's breathing
    /// cycle inspires with it.
    pub fn breathing_in_pause(&self) -> bool {
        self.quiet_in_pause() && self.state.breaths.breathing_in(&self.breath_rules)
    }

    /// Feeds one frame (in order). Calls `on_event` for what became certain at this frame: at
    /// most an end, an activity and a start.
    pub fn update(&mut self, frame: &FeatureFrame, mut on_event: impl FnMut(PhraseEvent)) {
        let i = self.state.frames_seen;
        let facts = self.frame_facts(frame);
        let len = self.history.len() as u64;
        self.history[(i % len) as usize] = facts;
        self.state.frames_seen += 1;
        if self.state.phrase.inside {
            self.in_phrase_frame(i, facts.active, &mut on_event);
        } else {
            self.in_pause_frame(i, facts, &mut on_event);
        }
    }

    /// The decisions on one frame; updates the noise floor and the room's band levels.
    fn frame_facts(&mut self, frame: &FeatureFrame) -> FrameFacts {
        let c = self.config;
        let s = &mut self.state;
        // Decisions use the voice-band level (rumble stays out), against the speaker's
        // running speech level (full band).
        let rms_db = if frame.band_db.is_finite() {
            frame.band_db
        } else {
            crate::analysis::LEVEL_FLOOR_DB
        };
        // Digital silence (under [`GATED_DB`]: an edit's zeros, a closed gate; never a room)
        // does not teach the floor once sound has been heard: the floor holds, and the room
        // after a cut is measured against the rooms before it. A floor learnt from the silence
        // put a room tone that follows it over the floor for the window's length, and a
        // phrase's edges ran over the whole pause. (The tracker's silence level would also
        // take a quiet room's pauses for silence and lift the floor over them.)
        let gated = rms_db <= GATED_DB;
        // Levels set for speech at `QUIET_SPEECH_DB` or louder (the silence level, a cut's
        // ceiling) move down with a quieter speaker's running speech level: in a raw take or at
        // a low gain they lie as far under the speech as they would there, so soft breaths and
        // consonants stay sound and the room stays a room as the gain goes down.
        let shift_db = quiet_shift_db(frame.speech_level_db);
        // A cut that left a 16-bit export's dither (or a gate's residue) under the ceiling, once
        // sound has been heard. It only marks the pause's silent stretches (what a cut left of
        // a breath); the floor learns from it as from any room.
        let cut = s.heard_sound && rms_db <= CUT_CEILING_DB + shift_db;
        // A frame far under the room (a breath an editor attenuated rather than gated) marks
        // the pause's silent stretches as a cut does, and, like digital silence, does not
        // teach the floor, for as long as an edit lasts; then it is the room's new level.
        // The room is the floor as the last quiet frame of a pause after a phrase left it
        // (after a long phrase the floor's window holds only the phrase; before the first
        // phrase ends, the floor may still sit at the voice). A stretch begins
        // [`UNDER_ROOM_DB`] under it and goes on at half that (the edit's own ripple, the
        // room's tail fading into it). How long an edit lasts is counted since the room was
        // last heard, not per stretch: a room that fell under the voice (a bed that stopped)
        // leaves every later pause short of an edit's length, but not their sum.
        let going = s.under_room_frames > 0;
        let low = rms_db <= s.room_db - if going { 0.5 } else { 1.0 } * UNDER_ROOM_DB;
        s.under_room_frames = if low { s.under_room_frames + 1 } else { 0 };
        // Digital silence is no room's level: it neither counts nor sets the lowest level (the
        // floor never learns it).
        if low && !gated {
            s.under_room_total = s.under_room_total.saturating_add(1);
            s.under_room_low_db = s.under_room_low_db.min(rms_db);
        }
        let under_room = s.heard_sound && low && s.under_room_total <= self.counts.under_room_max;
        if !(under_room || gated && s.heard_sound) {
            // Once the time under the room is past an edit's, the floor learns the lowest of
            // it at once: the room's new level, not what comes next (a breath).
            let level_db = if low {
                rms_db.min(s.under_room_low_db)
            } else {
                rms_db
            };
            s.floor_db = self.floor.update(Some(level_db));
        }
        s.heard_sound |= !gated;
        let speech_level_db = if frame.speech_level_db.is_finite() {
            frame.speech_level_db
        } else {
            rms_db
        };
        let silence_db = c.silence_db + shift_db;
        let over_floor = rms_db >= s.floor_db + c.edge_margin_db && rms_db > silence_db;
        let loud = rms_db >= s.floor_db + c.activity_margin_db
            && rms_db >= speech_level_db - c.unvoiced_drop_db
            && rms_db > silence_db;
        let voiced = frame.voiced && rms_db > silence_db;
        let active = voiced || loud;
        let in_pause = !s.phrase.inside && s.phrase.last_offset.is_some();
        if in_pause && !active && !gated && !cut && !under_room {
            s.room_db = s.floor_db;
        }
        let at_room = !low && !active && !gated && !cut;
        s.at_room_frames = if at_room {
            s.at_room_frames.saturating_add(1)
        } else {
            0
        };
        if s.at_room_frames >= self.counts.room_heard {
            s.under_room_total = 0;
            s.under_room_low_db = f32::INFINITY;
        }
        // The room's own band levels, learnt on frames at the floor, are taken out of the
        // frame's band powers: what is left is the shape of the sound over the room.
        // A frame whose breath bands stand out over their own running minimum does not teach
        // the room: where hum carries the full-band level, a breath lies within the full-band
        // floor's margin and would otherwise be learnt as the room. Silence (under the
        // tracker's silence level: a pause an editor gated, or a room too quiet to colour a
        // breath) teaches it nothing either: a room learnt as silent from a gated pause
        // leaves its hiss in the next breath's shape once the sound comes back. Nor does a
        // stretch under the room (an edit's): its shape is what the editor left, not the room.
        let breath_bands_db = frame.bands.breath_bands_db();
        let breath_floor_db = self.breath_floor.update(Some(breath_bands_db));
        if !voiced
            && !under_room
            && rms_db > silence_db
            && rms_db <= s.floor_db + FLOOR_BAND_WITHIN_DB
            && rms_db <= speech_level_db - FLOOR_BAND_UNDER_SPEECH_DB
            && breath_bands_db < breath_floor_db + c.breath_margin_db
        {
            s.floor_bands.learn(&frame.bands, self.floor_band_weight);
        }
        let (high_over_mid_db, low_over_mid_db) = s.floor_bands.excess_shape_db(&frame.bands);
        // A breath is loud enough over the room in the full band, or in its own bands: where
        // hum or rumble carries the room's level, a breath adds little to the full band.
        let over_room_db =
            (rms_db - s.floor_db).max(s.floor_bands.breath_bands_over_room_db(&frame.bands));
        let breath_level = over_room_db >= c.breath_margin_db && rms_db > silence_db;
        let breath_held =
            over_room_db >= c.breath_margin_db * BREATH_HOLD_SHARE && rms_db > silence_db;
        FrameFacts {
            active,
            over_floor,
            voiced,
            level_db: rms_db,
            breath_bands_db,
            breath_level,
            breath_held,
            high_over_mid_db,
            low_over_mid_db,
            mid_flatness: frame.bands.mid_flatness,
            gated: gated || cut || under_room,
        }
    }

    /// Frame `i` inside a phrase: the phrase ends after the hangover without an active frame.
    fn in_phrase_frame(&mut self, i: u64, active: bool, on_event: &mut impl FnMut(PhraseEvent)) {
        let p = &mut self.state.phrase;
        if active {
            p.last_active = i;
            return;
        }
        if i - p.last_active < self.counts.hangover {
            return;
        }
        // The phrase ended: extend the offset forward over a decaying tail.
        let last_active = p.last_active;
        let mut offset = last_active + 1;
        while offset < i
            && offset - last_active <= self.counts.offset
            && self.facts(offset).over_floor
        {
            offset += 1;
        }
        let s = &mut self.state;
        s.phrase.inside = false;
        s.phrase.last_offset = Some(offset);
        s.candidate.start = None;
        s.candidate.voiced = 0;
        s.pause_last_active = None;
        s.pause_last_run = None;
        // Breath detection restarts from the offset (frames since are in the ring).
        s.breaths.restart();
        s.silent.restart();
        for k in offset..=i {
            let f = self.facts(k);
            let s = &mut self.state;
            s.breaths
                .track(k, f, s.phrase.last_offset, &self.breath_rules);
            s.silent.track(k, f.gated);
        }
        on_event(PhraseEvent::End {
            onset_s: self.time_s(self.state.phrase.onset),
            offset_s: self.time_s(offset),
        });
    }

    /// Frame `i` in a pause: look for a candidate phrase, and for breaths.
    fn in_pause_frame(&mut self, i: u64, f: FrameFacts, on_event: &mut impl FnMut(PhraseEvent)) {
        let s = &mut self.state;
        s.silent.track(i, f.gated);
        if f.active {
            if s.candidate.start.is_none() {
                s.breaths.blip(i);
                s.candidate.start = Some(i);
                s.candidate.voiced = 0;
                on_event(PhraseEvent::Activity {
                    time_s: self.time_s(i),
                });
            }
            let s = &mut self.state;
            s.candidate.last_active = i;
            if f.voiced {
                s.candidate.voiced += 1;
            }
        } else if let Some(start) = s.candidate.start {
            if i - s.candidate.last_active > self.counts.run_gap {
                // The run died out without enough voicing: noise or a word too short to
                // confirm. Nothing may be placed over it. A breath run it interrupted ends
                // where it began if it held voicing (a voice is never part of an inhalation);
                // an unvoiced blip (a breath's own loudest moment) leaves the breath whole.
                if s.candidate.voiced > 0 {
                    s.breaths.close(start, &self.breath_rules);
                }
                s.pause_last_run =
                    (s.candidate.voiced == 0).then_some((start, s.pause_last_active));
                s.pause_last_active = Some(s.candidate.last_active);
                s.candidate.start = None;
                s.candidate.voiced = 0;
            }
        }
        let s = &mut self.state;
        if s.candidate.start.is_none() {
            s.breaths
                .track(i, f, s.phrase.last_offset, &self.breath_rules);
        }
        if let Some(start) = s.candidate.start {
            if s.candidate.voiced >= self.counts.onset_voiced {
                self.start_phrase(i, start, on_event);
            }
        }
    }

    /// A phrase starts at frame `i` from the candidate run that began at `start`: move the
    /// onset back over a quiet consonant and report the pause it ends.
    fn start_phrase(&mut self, i: u64, start: u64, on_event: &mut impl FnMut(PhraseEvent)) {
        let len = self.history.len() as u64;
        let s = &self.state;
        let limit = s
            .phrase
            .last_offset
            .unwrap_or(0)
            .max(s.pause_last_active.map_or(0, |k| k + 1))
            .max(start.saturating_sub(self.counts.edge))
            .max(i.saturating_sub(len - 1));
        let mut onset = start;
        while onset > limit && self.facts(onset - 1).over_floor {
            onset -= 1;
        }
        // A leading consonant heard as a run of its own (an /s/ whose stop closure, or a
        // gate's zeros in it, outlasts the run gap) begins the phrase's speech: the last run of
        // the pause, unvoiced, is its lead-in when the onset reaches back to within a run gap
        // of its end and it began within the onset extension of the onset. The onset stays
        // (the speech decision judges the phrase from it: moving it moved the judgement of a
        // phrase under a bed); a breath ends before the lead-in, where the run, as the pause's
        // last activity, left it no room.
        let mut last_active = s.pause_last_active;
        let mut lead_in = None;
        if let (Some(end), Some((run_start, before))) = (s.pause_last_active, s.pause_last_run) {
            let earliest = onset
                .saturating_sub(self.counts.edge)
                .max(i.saturating_sub(len - 1));
            if onset <= end + 1 + self.counts.run_gap && run_start >= earliest {
                lead_in = Some(run_start);
                last_active = before;
            }
        }
        // A breath run still going counts only with the part before the onset.
        let heard = s.breaths.at_onset(onset, &self.breath_rules);
        let breath = heard.map(|h| h.span);
        let seconds = |(a, b): (u64, u64)| (self.time_s(a), self.time_s(b));
        let pause = Pause {
            start_s: self.time_s(s.phrase.last_offset.unwrap_or(0)),
            end_s: self.time_s(onset),
            leading: s.phrase.last_offset.is_none(),
            has_breath: breath.is_some(),
            breath_s: breath.map(seconds),
            breath_clean_s: heard.and_then(|h| h.clean).map(seconds),
            last_activity_end_s: last_active.map(|k| self.time_s(k + 1)),
            lead_in_s: lead_in.map(|k| self.time_s(k)),
            gated_s: breath
                .and_then(|b| s.silent.beside(b, onset, self.counts.touch))
                .map(seconds),
        };
        let s = &mut self.state;
        s.phrase.inside = true;
        s.phrase.onset = onset;
        s.phrase.last_active = i;
        s.candidate.start = None;
        s.pause_last_active = None;
        s.pause_last_run = None;
        on_event(PhraseEvent::Start {
            onset_s: self.time_s(onset),
            pause,
        });
    }
}
