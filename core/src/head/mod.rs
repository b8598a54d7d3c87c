//! Online GMM head pose after van Welbergen et al. (IVA 2015) and Le et al. (2012): EM
//! training of the five joint densities of (roll | pitch | yaw | velocity | acceleration,
//! f0, loudness), the model file, per-frame synthesis by BFGS, and evaluation metrics.
//!
//! Per frame the engine calls [`HeadSynth::process`] with a [`crate::FeatureFrame`]; it returns
//! [`crate::HeadAngles`] (DESIGN.md conventions) and [`angles_to_quat`] gives the quaternion.
//! The shipped model is [`HeadModel::default_model`], trained by `cargo xtask train-default`.
//!
//! Where this differs from the paper, and why:
//! - Features are speaker-normalised (f0 in semitones around the running median, level in dB
//!   around the running speech level) instead of one actress's raw Hz and RMS, so one model
//!   serves any voice; velocity and acceleration are per second (per second²), so the model
//!   works at any frame rate.
//! - The training motion (video-based face tracking) is smoothed by a 25 ms Gaussian before
//!   velocity and acceleration are taken: unsmoothed, tracking jitter makes the acceleration
//!   density's mode large and the argmax then circles tightly around the pose mode.
//! - The argmax follows the densities' modes, so it generates far less motion than the data
//!   (SD about 0.5–1° against 2.6–3.6° real on styletalk). A per-axis output gain, calibrated
//!   on the training clips so the generated SD matches the real one, restores the amplitude.
//! - The argmax moves as fast as the voice's f0 swings make its modes move: expressive voices
//!   got heads two to three times faster than real ones. A speed governor ([`governor`]) scales
//!   the output toward a target mean speed: the geometric centre of the slowest and the fastest
//!   training clip's real speed (target and time constant set on the training clips only).
//! - Before the governor, a one-pole [`smoother`] takes the busy syllable-rate part out of the
//!   argmax's motion (much speed, little amplitude), so the governor need not shrink the
//!   amplitude to half of real to reach a real speed; its time constant (0–0.25 s) is chosen on
//!   the training clips too.
//! - Unvoiced frames do not freeze the head by default: hold, a damped return toward neutral and
//!   a loudness-only model are compared leave-one-clip-out and the best is stored in the model.

// Small fixed-size matrix math reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod bfgs;
pub mod clip_eval;
pub mod em;
pub mod evaluate;
pub mod features;
pub mod gmm;
pub mod governor;
pub mod inputs;
pub mod metrics;
pub mod model_file;
pub mod paper;
pub mod real_spread;
pub mod select;
pub mod smoother;
pub mod synth;
pub mod targets;
pub mod train;
pub mod variant;

pub use em::{EmConfig, EmError, EmFit};
pub use features::{MotionTrack, TrainingClip};
pub use gmm::{Gaussian, Gmm, GmmError};
pub use governor::SpeedGovernor;
pub use model_file::{
    HeadModel, HeadModelError, Normalisation, PoseTerm, Provenance, SynthesisWeights,
    UnvoicedBehaviour,
};
pub use synth::{angles_to_quat, HeadConfig, HeadSynth};
pub use train::{TrainConfig, TrainError};
pub use variant::Variant;
