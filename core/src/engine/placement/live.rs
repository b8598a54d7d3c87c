//! Live mode's placement: a phrase's start and end (the breath planned after speech, sized to
//! the pauses this speaker takes), and its answers to what the input does in a pause: activity
//! (speech may have resumed), a breath of the speaker's under way or heard, and the speaker's
//! own breath the breathing cycle inspires with.

use super::{
    breath_length_s, group_volume, live_wait_s, EventContext, Placement, GROUP_SMOOTHING,
    MIN_BREATH_S,
};
use crate::engine::schedule::{BreathAction, CycleAction, Schedule};
use crate::engine::EngineConfig;
use crate::phrase::Pause;

impl Placement {
    /// Live mode: a phrase starts at `onset_s` after `pause`: the pause's estimate learns its
    /// length, the stream's first phrase gets its filled lung when nothing inspired before it,
    /// and the cycle expires the group; the onset is activity.
    pub(super) fn live_phrase_started(
        &mut self,
        ctx: &EventContext,
        onset_s: f64,
        pause: Pause,
        schedule: &mut Schedule,
    ) {
        let config = ctx.config;
        let p = &config.placement;
        let rate = self.sample_rate_hz;
        // The pause a breath was planned in ends: the speaker's pauses are known
        // better (those long enough for a breath). A pause longer than twice the estimate
        // counts as twice it: a long silence is not a breath pause, and one would otherwise
        // lengthen the breaths of the next several pauses past what fits them.
        if let Some(from_s) = self.state.live_pause_from_s.take() {
            let pause_s = (onset_s - from_s) as f32;
            if pause_s >= p.min_pause_s {
                let est = &mut self.state.breath_pause_s;
                *est += GROUP_SMOOTHING * (pause_s.min(2.0 * *est) - *est);
            }
        }
        // The stream's first phrase, with no breath of the speaker's heard before
        // it (the cycle inspired with none): the speaker breathed in before it, as
        // a lookahead render says. Live mode learns of it at the phrase's
        // confirmation: a stream that starts in speech (no room for a breath
        // before), or a breath too quiet or too short to hear in the silence before.
        if pause.leading && self.state.group_planned_s <= 0.0 {
            let group_s = self.new_group(config, self.state.group_estimate_s);
            schedule
                .cycle
                .insert_sorted((onset_s, CycleAction::BreathedIn { group_s }));
        } else if self.state.live_after_other {
            // After a phrase of other sound (a song, a sting): no breath was planned in its
            // pause; if this phrase speaks, its speaker breathed in under that sound (as a
            // lookahead render fills the lung before it), for a group of the running
            // estimate. The group plan is left as it is: this phrase may be more music.
            let group_s = self.state.group_estimate_s;
            schedule
                .cycle
                .insert_sorted((onset_s, CycleAction::BreathOwed { group_s }));
        }
        let left_s = self.group_left_s();
        schedule
            .cycle
            .insert_sorted((onset_s, CycleAction::UtteranceStarts { left_s }));
        // The onset may lie before the first active frame (a quiet consonant).
        self.live_activity(ctx, (onset_s * rate).round() as u64, schedule);
    }

    /// Live mode: the phrase at `(onset_s, offset_s)` ended: after speech, a breath is planned
    /// for the pause (see below).
    pub(super) fn live_phrase_ended(
        &mut self,
        ctx: &EventContext,
        (onset_s, offset_s): (f64, f64),
        schedule: &mut Schedule,
    ) {
        let config = ctx.config;
        let p = &config.placement;
        let rate = self.sample_rate_hz;
        let now = ctx.now;
        self.state.live_breath_heard = false;
        // Live: a breath only after speech (the finished phrase's last half second).
        self.state.live_after_other = !ctx.speech.tail_is_speech(onset_s, offset_s);
        if self.state.live_after_other {
            return;
        }
        self.state.group_spoken_s += (offset_s - onset_s).max(0.0) as f32;
        // The inhalation (sound and cycle) starts once the pause has lasted the minimum
        // pause and `after_offset_s`, unless the input is active then; activity before
        // then cancels it (`live_activity`), activity while it plays fades it out (the
        // gate, in the breath track). Live mode takes no catch breaths under the
        // minimum pause: with nothing known of the pause's length, a breath started
        // earlier would often land on the next word. It plans each group from the
        // running estimate instead (a deeper breath when groups run long), and sizes
        // the breath as a lookahead render would for the pause this speaker usually
        // takes, within what is left of it after the wait: an inhalation that fits
        // fills the lung before the next word, where one of the preset's length was
        // cut short by it and left the lung shallow.
        let wait_s = live_wait_s(p);
        let level_db = self.local_speech_level_db(ctx.pending, None);
        let st = &self.state;
        self.state.live_group_undo =
            Some((st.group_estimate_s, st.group_planned_s, st.group_spoken_s));
        let group_s = self.new_group(config, self.state.group_estimate_s);
        let length_s = self.live_breath_s(config, group_s);
        let start =
            ((((offset_s + wait_s) * rate).round() as u64).max(now)).max(self.state.breath_end);
        let length = (length_s * rate).round() as usize;
        self.state.live_pause_from_s = Some(offset_s);
        schedule.breath.insert_sorted((
            start,
            BreathAction::LiveStart {
                length,
                gain: Self::breath_gain(config, level_db),
                speaker_db: self.breath_speaker_db(ctx, None),
                gains: ctx.gains,
                edge_hz: ctx.upper_edge_hz,
                audible: p.insert_breaths,
                group_s,
            },
        ));
        self.state.breath_end = start + length as u64;
        self.state.live_group_s = Some(group_s);
    }

    /// Live mode: speech (or something like it) began in the pause, reported at `ctx.now` with
    /// its first active frame at input sample `from`: nothing more starts in this pause, a
    /// breath playing fades out (if the gate has not faded it already), and the breathing cycle
    /// stops inspiring (nor will it inspire with a breath heard after the activity).
    pub(super) fn live_activity(&mut self, ctx: &EventContext, from: u64, schedule: &mut Schedule) {
        let planned = schedule.breath.len();
        schedule
            .breath
            .retain(|&(t, a)| !(t >= from && matches!(a, BreathAction::LiveStart { .. })));
        // A breath cancelled before it began ended no group: the speech goes on in the one
        // before (a short pause inside a group, as a lookahead render keeps it). One that
        // began did.
        let undo = self.state.live_group_undo.take();
        if let Some((estimate_s, planned_s, spoken_s)) =
            undo.filter(|_| schedule.breath.len() < planned)
        {
            let s = &mut self.state;
            (s.group_estimate_s, s.group_planned_s, s.group_spoken_s) =
                (estimate_s, planned_s, spoken_s);
        }
        self.state.breath_end = self.state.breath_end.min(from);
        self.state.live_group_s = None;
        if ctx.breath_playing {
            schedule
                .breath
                .insert_sorted((ctx.now, BreathAction::FadeOut));
        }
        schedule.note_activity(ctx.now);
    }

    /// Live mode: the phrase tracker hears a real breath in the pause going on (the speaker
    /// breathes in): the breath placed in this pause stays silent (the breathing cycle still
    /// inspires with it), and one playing fades out. Once per pause; the engine calls it in
    /// live mode only.
    pub(crate) fn live_breath_heard(&mut self, ctx: &EventContext, schedule: &mut Schedule) {
        if self.state.live_breath_heard {
            return;
        }
        self.state.live_breath_heard = true;
        Self::give_way(ctx, schedule, u64::MAX);
    }

    /// Live mode: breath-like sound is going on in the pause at `ctx.now`, not yet confirmed a
    /// breath ([`crate::phrase::PhraseTracker::breath_under_way_in_pause`]): the speaker may be
    /// breathing in. A breath due to start before the next frame stays silent (the breathing
    /// cycle still inspires with it), and one playing fades out: an inserted breath never
    /// starts, nor goes on, over a real one the detector is still hearing. A breath due later
    /// is judged again when its time comes.
    pub(crate) fn live_breath_under_way(&mut self, ctx: &EventContext, schedule: &mut Schedule) {
        let next_frame = ctx.now + (self.hop_s * self.sample_rate_hz).ceil() as u64;
        Self::give_way(ctx, schedule, next_frame);
    }

    /// A real breath keeps the live breaths off it: those due before input sample `due_before`
    /// stay silent (the breathing cycle still inspires with them), and one playing fades out.
    fn give_way(ctx: &EventContext, schedule: &mut Schedule, due_before: u64) {
        for (t, action) in schedule.breath.iter_mut() {
            if let BreathAction::LiveStart { audible, .. } = action {
                if *t < due_before {
                    *audible = false;
                }
            }
        }
        if ctx.breath_playing {
            schedule
                .breath
                .insert_sorted((ctx.now, BreathAction::FadeOut));
        }
    }

    /// Live mode: the speaker is breathing in, in the pause
    /// ([`crate::phrase::PhraseTracker::breathing_in_pause`]): the breathing cycle inspires
    /// with the breath from this frame, for the group planned for this pause's breath (once
    /// per pause, and only in a pause after speech whose live breath was planned and no
    /// activity has cancelled), or, in the silence before the stream's first phrase, for a
    /// group of the running estimate (once: the first phrase then needs no filled start). The
    /// pause's live breath not begun yet goes (it is silent already, the breath being heard,
    /// and its own inspiration would start this one over). The breath's activity does not
    /// stop the inspiration ([`Schedule::breathing_in`]); a word after it does.
    pub(crate) fn live_inspire_with_breath(&mut self, ctx: &EventContext, schedule: &mut Schedule) {
        let leading = self.state.start.before_first_phrase() && self.state.group_planned_s <= 0.0;
        let group_s = match self.state.live_group_s.take() {
            Some(group_s) => group_s,
            None if leading => self.new_group(ctx.config, self.state.group_estimate_s),
            None => return,
        };
        // The speaker breathes: the group began.
        self.state.live_group_undo = None;
        schedule
            .breath
            .retain(|&(_, a)| !matches!(a, BreathAction::LiveStart { .. }));
        self.state.breath_end = self.state.breath_end.min(ctx.now);
        let length_s = self.live_breath_s(ctx.config, group_s) as f32;
        schedule.cycle.insert_sorted((
            ctx.now as f64 / self.sample_rate_hz,
            CycleAction::Inspire { length_s, group_s },
        ));
    }

    /// Live mode: how long a breath for a group of `group_s` seconds lasts, seconds: as a
    /// lookahead render sizes it ([`breath_length_s`]) for the pause this speaker usually
    /// breathes in (the running estimate), within what is left of that pause after live
    /// mode's wait and before the next onset's gap; at least [`MIN_BREATH_S`]. An inhalation
    /// of the preset's length was cut short by the next word and left the lung shallow.
    pub(super) fn live_breath_s(&self, config: &EngineConfig, group_s: f32) -> f64 {
        let p = &config.placement;
        let map = config.breathing.map();
        let pause_s = f64::from(self.state.breath_pause_s);
        let wait_s = live_wait_s(p);
        let volume = f64::from(group_volume(&map, group_s));
        breath_length_s(f64::from(map.length_inspiration_s), pause_s, volume)
            .min(pause_s - wait_s - f64::from(p.gap_s))
            .max(MIN_BREATH_S)
    }
}
