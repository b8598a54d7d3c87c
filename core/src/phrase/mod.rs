//! Phrase tracking on the feature frames: speech / pause, phrase onsets and offsets, pause
//! lengths, and whether a pause already holds a breath.
//!
//! ## The decision, per frame
//! - Levels are the voice-band level of the frame ([`FeatureFrame::band_db`], above 120 Hz),
//!   so low rumble does not look like speech.
//! - An adaptive noise floor follows the frame level by minimum statistics (the minimum of the
//!   last few half-second blocks), so it tracks stationary noise and rises within seconds when
//!   the noise gets louder.
//! - A frame is **active** when it is voiced, or when its level is both `activity_margin_db` over
//!   the noise floor and no more than `unvoiced_drop_db` under the running speech level (so
//!   fricatives count as speech, breaths and room noise do not).
//! - A phrase **starts** once a run of active frames holds `onset_voiced_s` of voiced frames. Its
//!   onset is then moved back over the contiguous frames just before it that stand
//!   `edge_margin_db` over the floor (an initial /s/ or /f/), at most `edge_extend_s`.
//! - A phrase **ends** after `hangover_s` without an active frame; its offset is the end of the
//!   last active frame, moved forward the same way over a decaying tail.
//! - Inside a pause, a **breath** is a run of at least `breath_min_s` of unvoiced frames that stand
//!   `breath_margin_db` over the floor but are not active (a noise burst well under the speech
//!   level) and that has a breath's spectral shape: with the room's band levels (an average of
//!   [`FeatureFrame::bands`] over frames at the floor and over `silence_db`) taken out of each
//!   frame's band powers, the run's mean high-over-mid level is at most
//!   `breath_max_high_over_mid_db` (not a sibilant) and its low-over-mid at most
//!   `breath_max_low_over_mid_db` (not a vowel's tail or rumble), and it is noise: its mean
//!   mid-band spectral flatness is at least [`breath_run::BREATH_MIN_FLATNESS`] (a music bed
//!   swelling in a pause, a chord or a sung note is tonal). A run that starts at the
//!   phrase's offset must also rise 3 dB over its lowest point, in the voice band or in the
//!   breath's own bands (a reverberant tail only falls).
//!   In a noisy room a breath dips under the margin now and then: failing such a run, a *held*
//!   run that carries on through frames over half the margin marks a breath already there
//!   (nothing to learn from; never one that continues the phrase's decay), see
//!   [`breath_run`].
//!
//! Events are reported when they are certain, with the times they refer to (which lie in the
//! past): a consumer with lookahead (the engine's delay line) places breaths exactly, a live
//! consumer acts on them at once. Everything is causal and allocation-free after `new`.
//!
//! The rooms: [`tracker`] (the per-frame decisions and the phrase state), [`facts`] (what is
//! kept of each frame), [`breath_run`] (the breaths already in a pause), [`floor_bands`] (the
//! room's band levels), [`events`] (what the tracker reports), [`config`] (the settings).
//!
//! [`FeatureFrame::band_db`]: crate::analysis::FeatureFrame::band_db
//! [`FeatureFrame::bands`]: crate::analysis::FeatureFrame::bands

mod breath_run;
mod config;
mod events;
mod facts;
mod floor_bands;
mod silent_run;
#[cfg(test)]
mod tests;
mod tracker;

pub use breath_run::BREATH_UNDER_WAY_S;
pub use config::{PhraseConfig, PhraseError};
pub use events::{Pause, PhraseEvent};
pub use tracker::PhraseTracker;
