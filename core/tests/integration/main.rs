//! pneuma-core's integration tests, one module per subject, in one test binary (one build and
//! one link instead of sixteen; `cargo test -p pneuma-core --test integration engine::` runs one
//! subject). The golden digests keep their own binary (`--test golden`, re-blessed on its own).
//!
//! Shared: [`support`] (a counting global allocator for the "no allocation" checks; it counts
//! only on threads that ask, so the other tests run as usual) and [`generated_phrases`].

mod generated_phrases;
mod support;

mod analysis_signals;
mod band_limit;
mod breath_groups;
mod breath_shape;
mod breathing_chunker;
mod breathing_model;
mod breathing_syllables;
mod breathing_voice;
mod engine;
mod existing_breaths;
mod head_em;
mod head_model_file;
mod head_synth;
mod head_train;
mod learned_voice;
mod live_mode;
mod no_alloc;
mod replayed_analysis;
mod speech_decision;
mod speech_silero;
mod voicing_signals;
