//! Settings of the phrase tracker, with their units, ranges and defaults.

use thiserror::Error;

/// Errors of the phrase tracker's settings.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum PhraseError {
    /// A setting is out of its range.
    #[error("phrase setting `{name}` = {value} is out of range: use {range}")]
    OutOfRange {
        /// The setting.
        name: &'static str,
        /// The value given.
        value: f32,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// The frame rate is out of range.
    #[error("phrase tracker frame rate {0} Hz is out of range: use 10–1000 Hz")]
    FrameRate(f64),
    /// A text value given to [`PhraseConfig::set`] that is not a number.
    #[error("`{value}` is not a number (setting `{name}`)")]
    NotANumber {
        /// The setting.
        name: String,
        /// The text given.
        value: String,
    },
    /// A name given to [`PhraseConfig::set`] that is no phrase setting.
    #[error("unknown phrase setting `{0}`")]
    UnknownSetting(String),
}

/// Settings of the [`super::PhraseTracker`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhraseConfig {
    /// Silence of the phrase after which it ends, seconds (0.05–1, default 0.15). Pauses shorter
    /// than this never split a phrase.
    pub hangover_s: f32,
    /// Voiced time a run of active frames needs before it counts as a phrase, seconds (0.01–0.2,
    /// default 0.03). Unvoiced noise bursts never start a phrase.
    pub onset_voiced_s: f32,
    /// Longest inactive gap inside a candidate onset run, seconds (0.01–0.2, default 0.06).
    pub run_gap_s: f32,
    /// Margin over the noise floor an unvoiced frame needs to be speech, dB (3–30, default 8).
    pub activity_margin_db: f32,
    /// How far under the running speech level an unvoiced frame may be and still be speech, dB
    /// (6–40, default 12). Breaths sit 20–30 dB under speech and stay out; quieter consonants
    /// are bridged by the hangover and the edge extension.
    pub unvoiced_drop_db: f32,
    /// Margin over the noise floor of phrase edges (quiet consonants, decays) and of breath
    /// bursts, dB (2–20, default 6).
    pub edge_margin_db: f32,
    /// How far a phrase onset may be moved back over such frames, seconds (0–0.4, default 0.15).
    pub edge_extend_s: f32,
    /// How far a phrase offset may be moved forward over such frames, seconds (0–0.4, default
    /// 0.08).
    pub offset_extend_s: f32,
    /// Shortest breath-like burst inside a pause that counts as a breath already there, seconds
    /// (0.05–1, default 0.12).
    pub breath_min_s: f32,
    /// Frames under this level are silence whatever the floor, dBFS (−140 to −30, default −75).
    pub silence_db: f32,
    /// Margin over the noise floor a frame of a breath run needs, dB (2–20, default 6).
    pub breath_margin_db: f32,
    /// Spectral shape of a breath: the run's mean level of 2.5–3.5 kHz over 0.5–2.5 kHz, with
    /// the room's own band levels taken out ([`crate::analysis::BandLevels`]), must not exceed
    /// this, dB (−40 to 40; 40 = no limit; default 0). Breath noise sits under 0; /s/ and /sh/
    /// lie well above.
    pub breath_max_high_over_mid_db: f32,
    /// Spectral shape of a breath: the run's mean level of 100–400 Hz over 0.5–2.5 kHz, the
    /// room taken out, must not exceed this, dB (−40 to 40; 40 = no limit; default −1.5). Vowel
    /// tails, hum and rumble lie high.
    ///
    /// Both defaults are the fit of `pneuma eval breath-sounds` on all hand-labelled speakers
    /// (styletalk and Keele: the pooled F1 over a 10 × 10 grid); its leave-one-speaker-out
    /// figures are the honest ones (README, "Breaths already there").
    pub breath_max_low_over_mid_db: f32,
}

impl Default for PhraseConfig {
    fn default() -> Self {
        Self {
            hangover_s: 0.15,
            onset_voiced_s: 0.03,
            run_gap_s: 0.06,
            activity_margin_db: 8.0,
            unvoiced_drop_db: 12.0,
            edge_margin_db: 6.0,
            edge_extend_s: 0.15,
            offset_extend_s: 0.08,
            breath_min_s: 0.12,
            silence_db: -75.0,
            breath_margin_db: 6.0,
            breath_max_high_over_mid_db: 0.0,
            breath_max_low_over_mid_db: -1.5,
        }
    }
}

impl PhraseConfig {
    /// Sets one setting by its field name from text (for evaluation tools and the command line).
    pub fn set(&mut self, name: &str, value: &str) -> Result<(), PhraseError> {
        let v: f32 = value.parse().map_err(|_| PhraseError::NotANumber {
            name: name.to_string(),
            value: value.to_string(),
        })?;
        let field = match name {
            "hangover_s" => &mut self.hangover_s,
            "onset_voiced_s" => &mut self.onset_voiced_s,
            "run_gap_s" => &mut self.run_gap_s,
            "activity_margin_db" => &mut self.activity_margin_db,
            "unvoiced_drop_db" => &mut self.unvoiced_drop_db,
            "edge_margin_db" => &mut self.edge_margin_db,
            "edge_extend_s" => &mut self.edge_extend_s,
            "offset_extend_s" => &mut self.offset_extend_s,
            "breath_min_s" => &mut self.breath_min_s,
            "silence_db" => &mut self.silence_db,
            "breath_margin_db" => &mut self.breath_margin_db,
            "breath_max_high_over_mid_db" => &mut self.breath_max_high_over_mid_db,
            "breath_max_low_over_mid_db" => &mut self.breath_max_low_over_mid_db,
            _ => return Err(PhraseError::UnknownSetting(name.to_string())),
        };
        *field = v;
        Ok(())
    }

    /// Checks every setting against its range.
    pub fn validate(&self) -> Result<(), PhraseError> {
        let checks: [(&'static str, f32, f32, f32, &'static str); 13] = [
            ("hangover_s", self.hangover_s, 0.05, 1.0, "0.05–1 s"),
            (
                "onset_voiced_s",
                self.onset_voiced_s,
                0.01,
                0.2,
                "0.01–0.2 s",
            ),
            ("run_gap_s", self.run_gap_s, 0.01, 0.2, "0.01–0.2 s"),
            (
                "activity_margin_db",
                self.activity_margin_db,
                3.0,
                30.0,
                "3–30 dB",
            ),
            (
                "unvoiced_drop_db",
                self.unvoiced_drop_db,
                6.0,
                40.0,
                "6–40 dB",
            ),
            ("edge_margin_db", self.edge_margin_db, 2.0, 20.0, "2–20 dB"),
            ("edge_extend_s", self.edge_extend_s, 0.0, 0.4, "0–0.4 s"),
            ("offset_extend_s", self.offset_extend_s, 0.0, 0.4, "0–0.4 s"),
            ("breath_min_s", self.breath_min_s, 0.05, 1.0, "0.05–1 s"),
            (
                "silence_db",
                self.silence_db,
                -140.0,
                -30.0,
                "−140 to −30 dBFS",
            ),
            (
                "breath_margin_db",
                self.breath_margin_db,
                2.0,
                20.0,
                "2–20 dB",
            ),
            (
                "breath_max_high_over_mid_db",
                self.breath_max_high_over_mid_db,
                -40.0,
                40.0,
                "−40 to 40 dB",
            ),
            (
                "breath_max_low_over_mid_db",
                self.breath_max_low_over_mid_db,
                -40.0,
                40.0,
                "−40 to 40 dB",
            ),
        ];
        for (name, value, lo, hi, range) in checks {
            if !(value.is_finite() && (lo..=hi).contains(&value)) {
                return Err(PhraseError::OutOfRange { name, value, range });
            }
        }
        Ok(())
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
            e,
            PhraseError::NotANumber {
                name: "hangover_s".into(),
                value: "long".into()
            }
        );
        assert_eq!(
            e.to_string(),
            "`long` is not a number (setting `hangover_s`)"
        );
        let e = c.set("hangover", "0.2").unwrap_err();
        assert_eq!(e, PhraseError::UnknownSetting("hangover".into()));
        assert_eq!(e.to_string(), "unknown phrase setting `hangover`");
        assert_eq!(c.hangover_s, 0.2, "a refused value changes nothing");
    }
}
