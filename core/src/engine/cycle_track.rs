//! The cycle track: drives the [`BreathCycle`] frame by frame from the scheduled cycle actions
//! as the output reaches each control frame, keeps the speaking flag, and in live mode stops an
//! inspiration when the input wakes up. The actions carry the placement's breath-group plan: an
//! inspiration fills the lung for its group, each phrase spends the air left over the speech
//! left in the group, and a pause inside a group holds the breath. A phrase speaks (and spends
//! air) only on its frames the body gate does not flag as other sound
//! ([`Pending::other_sound`]): music, singing or noise inside a phrase neither speaks nor
//! breathes out, and a phrase judged speech late starts speaking then.

use super::schedule::{CycleAction, Pending, Schedule};
use crate::breathing::{BreathCycle, LowLevelParams};
use crate::control::BreathingState;

/// See the module docs. Allocation-free.
#[derive(Debug, Clone)]
pub(crate) struct CycleTrack {
    cycle: BreathCycle,
    sample_rate_hz: f64,
    dt_s: f32,
    live: bool,
    /// Inside a phrase (from its `UtteranceStarts` to its `SpeechStopped`).
    in_phrase: bool,
    /// The phrase's speech left in its group, seconds, for its expiration.
    left_s: f32,
    speaking: bool,
    /// The lung a phrase that starts speaking fills first (`CycleAction::BreathOwed`), the
    /// group's seconds of speech; dropped by an inspiration and at the phrase's end.
    owed_group_s: Option<f32>,
}

impl CycleTrack {
    /// A cycle with `params`, one step per frame at `frame_rate_hz`.
    pub(crate) fn new(
        params: &LowLevelParams,
        sample_rate_hz: f64,
        frame_rate_hz: f64,
        live: bool,
    ) -> Self {
        Self {
            cycle: BreathCycle::new(params),
            sample_rate_hz,
            dt_s: (1.0 / frame_rate_hz) as f32,
            live,
            in_phrase: false,
            left_s: 0.0,
            speaking: false,
            owed_group_s: None,
        }
    }

    /// Back to rest with empty lungs, not speaking.
    pub(crate) fn reset(&mut self) {
        self.cycle.reset();
        self.in_phrase = false;
        self.speaking = false;
        self.owed_group_s = None;
    }

    /// New breathing parameters (from the next event; amplitudes at once).
    pub(crate) fn set_params(&mut self, params: &LowLevelParams) {
        self.cycle.set_params(params);
    }

    /// Whether the frame last stepped lies in an utterance.
    pub(crate) fn speaking(&self) -> bool {
        self.speaking
    }

    /// Steps the cycle to frame `p`, applying the cycle actions due by its time.
    pub(crate) fn step(&mut self, p: &Pending, schedule: &mut Schedule) -> BreathingState {
        if self.live {
            // Activity in the input up to the sample that completed this frame stops an
            // inspiration (and cancels one not begun yet) before the frame is emitted.
            // The speaker's own breath is activity too, and what it inspires with.
            let at = schedule.activity_unseen.take();
            if let Some(at) = at.filter(|_| !schedule.breathing_in) {
                let at_s = at as f64 / self.sample_rate_hz;
                schedule
                    .cycle
                    .retain(|&(t, a)| !(t <= at_s && matches!(a, CycleAction::Inspire { .. })));
                self.cycle.interrupt();
            }
        }
        while let Some(&(t, action)) = schedule.cycle.front() {
            if t > p.frame.time_s + 1e-9 {
                break;
            }
            schedule.cycle.pop_front();
            match action {
                CycleAction::Inspire { length_s, group_s } => {
                    self.owed_group_s = None;
                    let target = self.cycle.lung_volume_for(group_s);
                    self.cycle.inspire_to(length_s, target);
                }
                CycleAction::BreathedIn { group_s } => {
                    self.owed_group_s = None;
                    let target = self.cycle.lung_volume_for(group_s);
                    self.cycle.breathed_in(target);
                }
                CycleAction::BreathOwed { group_s } => self.owed_group_s = Some(group_s),
                CycleAction::UtteranceStarts { left_s } => {
                    self.in_phrase = true;
                    self.left_s = left_s;
                    self.speaking = !p.other_sound;
                    if self.speaking {
                        self.start_speaking();
                    }
                }
                CycleAction::SpeechStopped => {
                    self.in_phrase = false;
                    self.speaking = false;
                    self.owed_group_s = None;
                    self.cycle.pause_in_group();
                }
            }
        }
        // The body gate's flag changed inside a phrase: speech resumes or stops.
        let speaking = self.in_phrase && !p.other_sound;
        match (self.speaking, speaking) {
            (false, true) => self.start_speaking(),
            (true, false) => self.cycle.pause_in_group(),
            _ => {}
        }
        self.speaking = speaking;
        self.cycle.advance(self.dt_s)
    }

    /// The phrase starts (or resumes) speaking: its group's expiration, from the lung it owed
    /// first when it follows other sound, then spent over that owed group (the group plan
    /// the phrase started with counts the sound as spoken: its air would be gone at once).
    fn start_speaking(&mut self) {
        if let Some(group_s) = self.owed_group_s.take() {
            let target = self.cycle.lung_volume_for(group_s);
            self.cycle.breathed_in(target);
            self.left_s = group_s;
        }
        self.cycle.expire_group(self.left_s);
    }
}
