//! [`FrameFacts`]: what the phrase tracker keeps of each frame in its history ring, for moving
//! a phrase's edges back over quiet consonants and forward over tails, and for the breath runs.

/// Per-frame facts kept in the history ring.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct FrameFacts {
    pub(super) active: bool,
    pub(super) over_floor: bool,
    pub(super) voiced: bool,
    /// The voice-band level the decisions use, dBFS.
    pub(super) level_db: f32,
    /// The level of the breath's own bands (0.5–3.5 kHz), dBFS.
    pub(super) breath_bands_db: f32,
    /// Over the floor by `breath_margin_db` (and not silence): loud enough for a breath run.
    pub(super) breath_level: bool,
    /// Over the floor by [`super::breath_run::BREATH_HOLD_SHARE`] of `breath_margin_db`: loud
    /// enough to carry on a breath run that has begun.
    pub(super) breath_held: bool,
    /// The frame's high band over its mid band, dB ([`crate::analysis::BandLevels`]).
    pub(super) high_over_mid_db: f32,
    /// The frame's low band over its mid band, dB.
    pub(super) low_over_mid_db: f32,
    /// The spectral flatness of its mid band ([`crate::analysis::BandLevels::mid_flatness`]).
    pub(super) mid_flatness: f32,
    /// Digital silence ([`super::silent_run::GATED_DB`]) or a cut's dither
    /// ([`super::silent_run::CUT_CEILING_DB`]): a cut or a closed gate, not a room.
    pub(super) gated: bool,
}
