//! The cycle track: drives the [`BreathCycle`] frame by frame from the scheduled cycle actions
//! as the output reaches each control frame, keeps the speaking flag, re-spreads the air of a
//! phrase that runs longer than expected, and in live mode stops an inspiration when the input
//! wakes up.

use super::schedule::{CycleAction, Schedule};
use super::Pending;
use crate::breathing::{BreathCycle, LowLevelParams};
use crate::control::BreathingState;

/// See the module docs. Allocation-free.
#[derive(Debug, Clone)]
pub(crate) struct CycleTrack {
    cycle: BreathCycle,
    sample_rate_hz: f64,
    dt_s: f32,
    live: bool,
    state: CycleState,
}

/// What [`CycleTrack::reset`] clears (besides the cycle itself).
#[derive(Debug, Clone, Copy, Default)]
struct CycleState {
    speaking: bool,
    /// Start (s) and expected length (s) of the utterance being spoken.
    utterance_start_s: f64,
    utterance_expected_s: f64,
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
            state: CycleState::default(),
        }
    }

    /// Back to rest with empty lungs, not speaking.
    pub(crate) fn reset(&mut self) {
        self.cycle.reset();
        self.state = CycleState::default();
    }

    /// New breathing parameters (from the next event; amplitudes at once).
    pub(crate) fn set_params(&mut self, params: &LowLevelParams) {
        self.cycle.set_params(params);
    }

    /// Whether the frame last stepped lies in an utterance.
    pub(crate) fn speaking(&self) -> bool {
        self.state.speaking
    }

    /// Steps the cycle to frame `p`, applying the cycle actions due by its time.
    pub(crate) fn step(&mut self, p: &Pending, schedule: &mut Schedule) -> BreathingState {
        if self.live {
            // Activity in the input up to the sample that completed this frame stops an
            // inspiration (and cancels one not begun yet) before the frame is emitted.
            if let Some(at) = schedule.activity_unseen.take() {
                let at_s = at as f64 / self.sample_rate_hz;
                schedule
                    .cycle
                    .retain(|&(t, a)| !(t <= at_s && matches!(a, CycleAction::Inspire { .. })));
                self.cycle.interrupt();
            }
        }
        let s = &mut self.state;
        while let Some(&(t, action)) = schedule.cycle.front() {
            if t > p.frame.time_s + 1e-9 {
                break;
            }
            schedule.cycle.pop_front();
            match action {
                CycleAction::Inspire {
                    length_s,
                    utterance_s,
                } => self.cycle.inspire(length_s, utterance_s),
                CycleAction::UtteranceStarts { utterance_s } => {
                    s.speaking = true;
                    self.cycle.utterance_starts(utterance_s);
                    s.utterance_start_s = t;
                    s.utterance_expected_s = utterance_s as f64;
                }
                CycleAction::SpeechStopped => {
                    s.speaking = false;
                    self.cycle.speech_stopped();
                }
            }
        }
        // A phrase longer than expected: spread the rest of the air over a new estimate, so the
        // lung keeps falling smoothly instead of sitting empty while speaking.
        if s.speaking {
            let spoken_s = p.frame.time_s - s.utterance_start_s;
            if spoken_s >= 0.9 * s.utterance_expected_s {
                let extra_s = (0.5 * s.utterance_expected_s).max(1.0);
                self.cycle.utterance_starts(extra_s as f32);
                s.utterance_expected_s = spoken_s + extra_s;
            }
        }
        self.cycle.advance(self.dt_s)
    }
}
