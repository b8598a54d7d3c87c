//! Settings of the phrase tracker: [`PhraseConfig`], bound to the table's phrase settings
//! ([`crate::settings::phrase`]: units, ranges, defaults and why).

use thiserror::Error;

use crate::settings::phrase::{
    ACTIVITY_MARGIN_DB, BREATH_MARGIN_DB, BREATH_MAX_HIGH_OVER_MID_DB, BREATH_MAX_LOW_OVER_MID_DB,
    BREATH_MIN_S, EDGE_EXTEND_S, EDGE_MARGIN_DB, HANGOVER_S, OFFSET_EXTEND_S, ONSET_VOICED_S,
    PHRASE_SILENCE_DB, RUN_GAP_S, UNVOICED_DROP_DB,
};
use crate::settings::setting::{check_fields, field, set_field_text, Field, SettingError};

/// Errors of the phrase tracker's settings (and of the frame rate it is given).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PhraseError {
    /// A setting is out of its range or not a value.
    #[error(transparent)]
    Setting(#[from] SettingError),
}

/// Settings of the [`super::PhraseTracker`]; each field's setting (unit, range, default, why)
/// is in [`crate::settings::phrase`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhraseConfig {
    /// Silence of the phrase after which it ends, seconds ([`HANGOVER_S`]).
    pub hangover_s: f32,
    /// Voiced time a run of active frames needs to count as a phrase, seconds
    /// ([`ONSET_VOICED_S`]).
    pub onset_voiced_s: f32,
    /// Longest inactive gap inside a candidate onset run, seconds ([`RUN_GAP_S`]).
    pub run_gap_s: f32,
    /// Margin over the noise floor an unvoiced frame needs to be speech, dB
    /// ([`ACTIVITY_MARGIN_DB`]).
    pub activity_margin_db: f32,
    /// How far under the running speech level an unvoiced frame may be and still be speech,
    /// dB ([`UNVOICED_DROP_DB`]).
    pub unvoiced_drop_db: f32,
    /// Margin over the noise floor of phrase edges and breath bursts, dB ([`EDGE_MARGIN_DB`]).
    pub edge_margin_db: f32,
    /// How far a phrase onset may be moved back over edge frames, seconds ([`EDGE_EXTEND_S`]).
    pub edge_extend_s: f32,
    /// How far a phrase offset may be moved forward over edge frames, seconds
    /// ([`OFFSET_EXTEND_S`]).
    pub offset_extend_s: f32,
    /// Shortest breath-like burst in a pause that counts as a breath already there, seconds
    /// ([`BREATH_MIN_S`]).
    pub breath_min_s: f32,
    /// Frames under this level are silence whatever the floor, dBFS ([`PHRASE_SILENCE_DB`]).
    pub silence_db: f32,
    /// Margin over the noise floor a frame of a breath run needs, dB ([`BREATH_MARGIN_DB`]).
    pub breath_margin_db: f32,
    /// Spectral shape of a breath: the limit of 2.5–3.5 kHz over 0.5–2.5 kHz, the room's own
    /// band levels ([`crate::analysis::BandLevels`]) taken out, dB
    /// ([`BREATH_MAX_HIGH_OVER_MID_DB`]).
    pub breath_max_high_over_mid_db: f32,
    /// Spectral shape of a breath: the limit of 100–400 Hz over 0.5–2.5 kHz, the room taken
    /// out, dB ([`BREATH_MAX_LOW_OVER_MID_DB`]).
    ///
    /// Both shape defaults are the fit of `pneuma eval breath-sounds` on all hand-labelled
    /// speakers (styletalk and Keele: the pooled F1 over a 10 × 10 grid); its
    /// leave-one-speaker-out figures are the honest ones (docs/measurements.md, section 4, "Breaths already there").
    pub breath_max_low_over_mid_db: f32,
}

/// The settings of [`PhraseConfig`] and the fields holding them.
static FIELDS: [Field<PhraseConfig>; 13] = [
    field!(HANGOVER_S, hangover_s),
    field!(ONSET_VOICED_S, onset_voiced_s),
    field!(RUN_GAP_S, run_gap_s),
    field!(ACTIVITY_MARGIN_DB, activity_margin_db),
    field!(UNVOICED_DROP_DB, unvoiced_drop_db),
    field!(EDGE_MARGIN_DB, edge_margin_db),
    field!(EDGE_EXTEND_S, edge_extend_s),
    field!(OFFSET_EXTEND_S, offset_extend_s),
    field!(BREATH_MIN_S, breath_min_s),
    field!(PHRASE_SILENCE_DB, silence_db),
    field!(BREATH_MARGIN_DB, breath_margin_db),
    field!(BREATH_MAX_HIGH_OVER_MID_DB, breath_max_high_over_mid_db),
    field!(BREATH_MAX_LOW_OVER_MID_DB, breath_max_low_over_mid_db),
];

impl Default for PhraseConfig {
    /// The table's defaults.
    fn default() -> Self {
        Self {
            hangover_s: HANGOVER_S.default,
            onset_voiced_s: ONSET_VOICED_S.default,
            run_gap_s: RUN_GAP_S.default,
            activity_margin_db: ACTIVITY_MARGIN_DB.default,
            unvoiced_drop_db: UNVOICED_DROP_DB.default,
            edge_margin_db: EDGE_MARGIN_DB.default,
            edge_extend_s: EDGE_EXTEND_S.default,
            offset_extend_s: OFFSET_EXTEND_S.default,
            breath_min_s: BREATH_MIN_S.default,
            silence_db: PHRASE_SILENCE_DB.default,
            breath_margin_db: BREATH_MARGIN_DB.default,
            breath_max_high_over_mid_db: BREATH_MAX_HIGH_OVER_MID_DB.default,
            breath_max_low_over_mid_db: BREATH_MAX_LOW_OVER_MID_DB.default,
        }
    }
}

impl PhraseConfig {
    /// The settings of this struct and the fields holding them.
    pub fn fields() -> &'static [Field<PhraseConfig>] {
        &FIELDS
    }

    /// Sets one setting by its id from text (for evaluation tools and the command line).
    pub fn set(&mut self, id: &str, text: &str) -> Result<(), PhraseError> {
        Ok(set_field_text(self, &FIELDS, id, text)?)
    }

    /// Checks every setting against its range.
    pub fn validate(&self) -> Result<(), PhraseError> {
        Ok(check_fields(self, &FIELDS)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_string_setter_names_what_is_wrong() {
        let mut c = PhraseConfig::default();
        assert_eq!(c.set("hangover_s", "0.2"), Ok(()));
        assert_eq!(c.hangover_s, 0.2);
        let e = c.set("hangover_s", "long").unwrap_err();
        assert_eq!(
            e.to_string(),
            "hangover_s: `long` is not a number: use 0.05 to 1 s"
        );
        let e = c.set("hangover_s", "3").unwrap_err();
        assert_eq!(
            e.to_string(),
            "hangover_s 3 s is out of range: use 0.05 to 1 s"
        );
        // The phrase tracker's silence has its own id (the analysis has a `silence_db` too).
        c.set("phrase_silence_db", "-80").unwrap();
        assert_eq!(c.silence_db, -80.0);
        let e = c.set("hangover", "0.2").unwrap_err();
        assert_eq!(
            e,
            PhraseError::Setting(SettingError::Unknown("hangover".into()))
        );
        assert_eq!(c.hangover_s, 0.2, "a refused value changes nothing");
    }
}
