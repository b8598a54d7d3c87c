//! Online GMM head pose after van Welbergen et al. (IVA 2015) and Le et al. (2012): EM
//! training of the five joint densities of (roll | pitch | yaw | velocity | acceleration,
//! f0, loudness), the model file, per-frame synthesis by BFGS, and evaluation metrics.
//!
//! Per frame the engine calls [`HeadSynth::process`] with a [`crate::FeatureFrame`]; it returns
//! [`crate::HeadAngles`] (DESIGN.md conventions) and [`angles_to_quat`] gives the quaternion.
//! The shipped model is [`HeadModel::default_model`], trained by `cargo xtask train-default`.

// Small fixed-size matrix math reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub mod bfgs;
pub mod em;
pub mod features;
pub mod gmm;
pub mod metrics;
pub mod model_file;
pub mod synth;
pub mod train;

pub use em::{EmConfig, EmError, EmFit};
pub use features::{MotionTrack, TrainingClip};
pub use gmm::{Gaussian, Gmm, GmmError};
pub use model_file::{
    HeadModel, HeadModelError, Normalisation, Provenance, SynthesisWeights, UnvoicedBehaviour,
};
pub use synth::{angles_to_quat, HeadConfig, HeadSynth};
pub use train::{TrainConfig, TrainError};
