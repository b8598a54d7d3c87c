//! The voicing decision in one place. [`VoicingEvidence`] gathers the cues one frame offers
//! (periodicity of the long window, of a short centred window and of short windows at either
//! end, their agreement, the low band's share of the energy, the level against the running
//! speech level and the noise floors, how noisy the recording is and the long window's clarity
//! with the background's share taken out, continuity with the previous frame's period and how
//! long the period has moved smoothly, and the period itself), all computed causally from the
//! audio alone, never from earlier decisions, so the same cues can be gathered once and any
//! model fitted on them. [`VoicingModel`] is a
//! score over those cues ([`VOICING_FEATURES`]: a logistic regression, regression trees, or
//! both added) with two thresholds on its score
//! (hysteresis: a higher score to start voicing than to keep it), read from a versioned text
//! file (`assets/models/voicing.txt`, embedded) that `cargo xtask train-voicing` fits
//! leave-one-speaker-out and regenerates bit for bit. [`VoicingRule`] applies the model with
//! its hysteresis state and a fixed silence gate.
//!
//! The rooms: [`cues`] (the evidence and its features), [`model`] (the scorers and the model),
//! [`model_file`] (the embedded model and the versioned text format), [`rule`] (the decision
//! with its hysteresis and silence gate).

mod cues;
mod model;
mod model_file;
mod rule;

pub(crate) use cues::{period_jump_octaves, VoicingEvidence, TRACK_CAP_S};
pub use cues::{VoicingFeatures, LEVEL_VS_GATE, N_VOICING_FEATURES, VOICING_FEATURES};
pub use model::{InvalidVoicingModel, VoicingModel, VoicingModelError};
pub(crate) use rule::VoicingRule;
