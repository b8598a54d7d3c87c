//! The breath cycle: rest ⇄ inspiration ⇄ expiration, driven by events.
//!
//! - **Inspiration** ([`BreathCycle::inspire`]): the lung rises linearly with slope
//!   `volume_lung / length_inspiration` (the paper's LF) from where it is, for `length_s`
//!   seconds (stopping at 1). `volume_lung` comes from the upcoming utterance
//!   ([`BreathCycle::lung_volume_for`]). Nostrils flare and the mouth opens with a smooth
//!   trapezoid over the inspiration (amplitudes `amplitude_nostril_flare`, `amplitude_mouth_open`).
//! - **Expiration** ([`BreathCycle::utterance_starts`]): the lung falls linearly with slope
//!   `lung_at_onset / utterance_s`, which is the paper's `volume_lung / length_speech` after a
//!   complete inspiration from empty lungs, and in every case empties the breath exactly at the
//!   expected end of the utterance. If speech goes on longer the lung stays at 0.
//! - **Breath groups** (the engine's planning; [`BreathCycle::inspire_to`],
//!   [`BreathCycle::expire_group`], [`BreathCycle::pause_in_group`]): an inspiration fills the
//!   lung up to a target planned for the speech until the next breath, each phrase spends the
//!   air left over the speech left in the group and ends it at a reserve ([`RESERVE_LUNG`]; a
//!   speaker never talks the lung empty), speech past the plan draws the reserve down slowly
//!   ([`RESERVE_DECAY_S`]), and the short pauses inside a group hold the breath.
//! - **Rest** (documented choice; the paper leaves it open): after speech stops, or after an
//!   inspiration that no speech followed (the breath is held for [`HOLD_S`] first), the lung
//!   relaxes (time constant [`REST_RELAX_S`]) onto a gentle tidal breath
//!   `rest_depth · (1 − cos 2πt/rest_period_s) / 2` that starts at its bottom, so avatars keep
//!   breathing when nobody speaks. Nostrils flare slightly (30 % of their amplitude) while the
//!   tidal breath rises; the mouth stays closed.
//!
//! Outputs per frame: `lung` 0..1, `thorax = lung · volume_thorax`,
//! `abdomen = lung · volume_abdomen`, `neck_pitch_deg = lung · amplitude_neck_motion_deg`.
//! No allocation anywhere.

use super::LowLevelParams;
use crate::control::{BreathingState, Phase};
use std::f32::consts::PI;

/// The smallest lung volume chosen for an utterance (short phrases still get a visible breath).
pub const MIN_LUNG_VOLUME: f32 = 0.2;
/// How long a breath is held when no speech follows an inspiration, seconds.
pub const HOLD_S: f32 = 1.0;
/// Time constant of the relaxation into the resting breath, seconds.
pub const REST_RELAX_S: f32 = 0.6;
/// Lung volume a planned breath group ends at (the air kept in reserve).
pub const RESERVE_LUNG: f32 = 0.12;
/// Time constant with which speech past the plan draws the reserve down, seconds.
pub const RESERVE_DECAY_S: f32 = 5.0;
/// Fraction of the inspiration spent opening (and, at the end, closing) nostrils and mouth.
const CHANNEL_RAMP: f32 = 0.3;

#[derive(Debug, Clone, Copy, PartialEq)]
enum State {
    Rest {
        time_s: f32,
        hold_s: f32,
    },
    Inspiration {
        elapsed_s: f32,
        length_s: f32,
        slope_per_s: f32,
    },
    /// The lung falls with `slope_per_s` down to `floor`, then decays with [`RESERVE_DECAY_S`].
    Expiration {
        slope_per_s: f32,
        floor: f32,
    },
}

/// The event-driven breath cycle (see the module docs). Allocation-free.
#[derive(Debug, Clone)]
pub struct BreathCycle {
    params: LowLevelParams,
    state: State,
    lung: f32,
}

impl BreathCycle {
    /// A cycle at rest with empty lungs.
    pub fn new(params: &LowLevelParams) -> Self {
        Self {
            params: *params,
            state: State::Rest {
                time_s: 0.0,
                hold_s: 0.0,
            },
            lung: 0.0,
        }
    }

    /// New parameters; they apply from the next event (amplitudes at once).
    pub fn set_params(&mut self, params: &LowLevelParams) {
        self.params = *params;
    }

    /// The parameters in use.
    pub fn params(&self) -> &LowLevelParams {
        &self.params
    }

    /// Back to rest with empty lungs.
    pub fn reset(&mut self) {
        self.state = State::Rest {
            time_s: 0.0,
            hold_s: 0.0,
        };
        self.lung = 0.0;
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        match self.state {
            State::Rest { .. } => Phase::Rest,
            State::Inspiration { .. } => Phase::Inspiration,
            State::Expiration { .. } => Phase::Expiration,
        }
    }

    /// The current lung volume, 0..1.
    pub fn lung(&self) -> f32 {
        self.lung
    }

    /// The lung volume (0..1) to take in for an utterance of `utterance_s` seconds: the share of
    /// a full breath's utterance (`length_utterance_s`) it needs, at least [`MIN_LUNG_VOLUME`],
    /// at most 1.
    pub fn lung_volume_for(&self, utterance_s: f32) -> f32 {
        let full = self.params.length_utterance_s.max(1e-3);
        let u = if utterance_s.is_finite() {
            utterance_s.max(0.0)
        } else {
            0.0
        };
        (u / full).clamp(MIN_LUNG_VOLUME, 1.0)
    }

    /// An inspiration of `length_s` seconds starts now, for an utterance of
    /// `upcoming_utterance_s` seconds (its volume: [`BreathCycle::lung_volume_for`]).
    pub fn inspire(&mut self, length_s: f32, upcoming_utterance_s: f32) {
        let length_s = if length_s.is_finite() {
            length_s.max(1e-3)
        } else {
            self.params.length_inspiration_s.max(1e-3)
        };
        let volume = self.lung_volume_for(upcoming_utterance_s);
        self.state = State::Inspiration {
            elapsed_s: 0.0,
            length_s,
            slope_per_s: volume / length_s,
        };
    }

    /// Speech (expiration) starts now; `utterance_s` is its expected length in seconds.
    pub fn utterance_starts(&mut self, utterance_s: f32) {
        let u = if utterance_s.is_finite() {
            utterance_s.max(0.05)
        } else {
            self.params.length_utterance_s.max(0.05)
        };
        self.state = State::Expiration {
            slope_per_s: self.lung / u,
            floor: 0.0,
        };
    }

    /// An inspiration of `length_s` seconds starts now and fills the lung up to `target_lung`
    /// (0..1; a target under the current lung keeps the lung where it is while the channels
    /// open).
    pub fn inspire_to(&mut self, length_s: f32, target_lung: f32) {
        let length_s = if length_s.is_finite() {
            length_s.max(1e-3)
        } else {
            self.params.length_inspiration_s.max(1e-3)
        };
        let target = if target_lung.is_finite() {
            target_lung.clamp(0.0, 1.0)
        } else {
            self.lung
        };
        self.state = State::Inspiration {
            elapsed_s: 0.0,
            length_s,
            slope_per_s: (target - self.lung).max(0.0) / length_s,
        };
    }

    /// The speaker breathed in before the stream began (it starts in speech): the lung is at
    /// `target_lung` (0..1) at once and held there until the speech starts.
    pub fn breathed_in(&mut self, target_lung: f32) {
        if target_lung.is_finite() {
            self.lung = target_lung.clamp(0.0, 1.0);
        }
        self.state = State::Rest {
            time_s: 0.0,
            hold_s: HOLD_S,
        };
    }

    /// A phrase of a breath group starts now with `left_s` seconds of speech left in the group:
    /// the lung falls linearly to [`RESERVE_LUNG`] (or stays where it is when already under it)
    /// at the planned end, then decays slowly.
    pub fn expire_group(&mut self, left_s: f32) {
        let left_s = if left_s.is_finite() {
            left_s.max(0.05)
        } else {
            self.params.length_utterance_s.max(0.05)
        };
        let floor = RESERVE_LUNG.min(self.lung);
        self.state = State::Expiration {
            slope_per_s: (self.lung - floor) / left_s,
            floor,
        };
    }

    /// Speech paused inside a breath group: the breath is held ([`HOLD_S`]) until the group
    /// goes on (or an inspiration comes), then the lung relaxes as at rest. Ignored outside
    /// expiration.
    pub fn pause_in_group(&mut self) {
        if let State::Expiration { .. } = self.state {
            self.state = State::Rest {
                time_s: 0.0,
                hold_s: HOLD_S,
            };
        }
    }

    /// Speech (or something that may be speech) came back during an inspiration: the
    /// inspiration stops where it is and the breath is held ([`HOLD_S`]) until the utterance
    /// starts. Ignored outside inspiration. Live placement calls it, since it cannot know
    /// beforehand how long a pause lasts.
    pub fn interrupt(&mut self) {
        if let State::Inspiration { .. } = self.state {
            self.state = State::Rest {
                time_s: 0.0,
                hold_s: HOLD_S,
            };
        }
    }

    /// Speech ended: the cycle goes to rest (see the module docs). Ignored outside expiration.
    pub fn speech_stopped(&mut self) {
        if let State::Expiration { .. } = self.state {
            self.state = State::Rest {
                time_s: 0.0,
                hold_s: 0.0,
            };
        }
    }

    /// Advances by `dt_s` seconds and returns the state at the end of the step.
    pub fn advance(&mut self, dt_s: f32) -> BreathingState {
        let dt = if dt_s.is_finite() { dt_s.max(0.0) } else { 0.0 };
        let p = self.params;
        let mut nostril = 0.0;
        let mut mouth = 0.0;
        match &mut self.state {
            State::Inspiration {
                elapsed_s,
                length_s,
                slope_per_s,
            } => {
                let step = dt.min((*length_s - *elapsed_s).max(0.0));
                *elapsed_s += dt;
                self.lung = (self.lung + *slope_per_s * step).min(1.0);
                let e = channel_envelope(*elapsed_s / *length_s);
                nostril = p.amplitude_nostril_flare * e;
                mouth = p.amplitude_mouth_open * e;
                if *elapsed_s >= *length_s {
                    self.state = State::Rest {
                        time_s: 0.0,
                        hold_s: HOLD_S,
                    };
                }
            }
            State::Expiration { slope_per_s, floor } => {
                if self.lung > *floor {
                    self.lung = (self.lung - *slope_per_s * dt).max(*floor);
                } else {
                    self.lung -= self.lung * (1.0 - (-dt / RESERVE_DECAY_S).exp());
                }
            }
            State::Rest { time_s, hold_s } => {
                if *hold_s > 0.0 {
                    *hold_s -= dt;
                } else {
                    *time_s += dt;
                    let w = 2.0 * PI * *time_s / p.rest_period_s.max(0.1);
                    let tidal = p.rest_depth * 0.5 * (1.0 - w.cos());
                    let k = 1.0 - (-dt / REST_RELAX_S).exp();
                    self.lung += (tidal - self.lung) * k;
                    nostril = 0.3 * p.amplitude_nostril_flare * w.sin().max(0.0);
                    // Keep the tidal clock bounded (no precision loss on long rests).
                    let period = p.rest_period_s.max(0.1);
                    if *time_s >= period {
                        *time_s -= period;
                    }
                }
            }
        }
        self.state_now(nostril, mouth)
    }

    fn state_now(&self, nostril: f32, mouth: f32) -> BreathingState {
        let lung = self.lung.clamp(0.0, 1.0);
        BreathingState {
            phase: self.phase(),
            lung,
            thorax: (lung * self.params.volume_thorax).clamp(0.0, 1.0),
            abdomen: (lung * self.params.volume_abdomen).clamp(0.0, 1.0),
            neck_pitch_deg: lung * self.params.amplitude_neck_motion_deg,
            nostril_flare: nostril.clamp(0.0, 1.0),
            mouth_open: mouth.clamp(0.0, 1.0),
        }
    }
}

/// Smooth trapezoid 0..1 over an inspiration's progress `x` 0..1 (raised-cosine ramps).
fn channel_envelope(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    let ramp = |u: f32| 0.5 - 0.5 * (PI * u.clamp(0.0, 1.0)).cos();
    if x < CHANNEL_RAMP {
        ramp(x / CHANNEL_RAMP)
    } else if x > 1.0 - CHANNEL_RAMP {
        ramp((1.0 - x) / CHANNEL_RAMP)
    } else {
        1.0
    }
}
