//! Named presets that give the papers' "future work" (mood through breathing) a home.
//!
//! | preset  | chest/belly | capacity % | mouth share | sound | opening | loudness | rate | insp. (full lung) s | neck ° | rest period s | rest depth |
//! |---------|------------:|-----------:|------------:|------:|--------:|---------:|-----:|------------:|-------:|------:|-----:|
//! | neutral | 0.50 | 60 | 0.50 | 0.35 | 0.50 | 0.50 | 1.00 | 1.00 | 3.0 | 4.0 | 0.12 |
//! | calm    | 0.80 | 90 | 0.15 | 0.25 | 0.35 | 0.40 | 0.85 | 1.35 | 2.0 | 6.0 | 0.15 |
//! | anxious | 0.15 | 35 | 0.85 | 0.60 | 0.85 | 0.65 | 1.30 | 0.80 | 4.0 | 2.2 | 0.10 |
//! | tired   | 0.60 | 45 | 0.70 | 0.50 | 0.55 | 0.30 | 0.80 | 1.80 | 1.5 | 5.0 | 0.18 |
//! | excited | 0.30 | 80 | 0.85 | 0.55 | 0.90 | 0.85 | 1.20 | 0.70 | 5.0 | 3.0 | 0.12 |
//!
//! Calm: long, deep, abdominal nose breaths, long breath groups (≈ 21 syllables), slow rest.
//! Anxious: fast, shallow chest breaths through the mouth, short groups (≈ 10 syllables), quick
//! gasps (0.28 s). Tired: slow, audible, sighing mouth breaths (0.81 s). Excited: loud, fast
//! speech, big quick mouth breaths with strong neck motion.

use super::{BreathingError, BreathingParams};

/// A named set of [`BreathingParams`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Preset {
    /// Everyday speech.
    Neutral,
    /// Long, deep, abdominal, nasal.
    Calm,
    /// Fast, shallow, thoracic, mouth gasps.
    Anxious,
    /// Slow, sighing, audible.
    Tired,
    /// Loud, fast, big quick breaths.
    Excited,
}

impl Preset {
    /// Every preset, in documentation order.
    pub const ALL: [Preset; 5] = [
        Preset::Neutral,
        Preset::Calm,
        Preset::Anxious,
        Preset::Tired,
        Preset::Excited,
    ];

    /// Every preset's name, in the order of [`Preset::ALL`] (for option parsers, e.g. clap's
    /// `PossibleValuesParser`, and messages).
    pub const NAMES: [&'static str; Preset::ALL.len()] = {
        let mut names = [""; Preset::ALL.len()];
        let mut i = 0;
        while i < names.len() {
            names[i] = Preset::ALL[i].name();
            i += 1;
        }
        names
    };

    /// The lower-case name (`neutral`, `calm`, `anxious`, `tired`, `excited`).
    pub const fn name(self) -> &'static str {
        match self {
            Preset::Neutral => "neutral",
            Preset::Calm => "calm",
            Preset::Anxious => "anxious",
            Preset::Tired => "tired",
            Preset::Excited => "excited",
        }
    }

    /// The preset named `s` (case-insensitive).
    pub fn from_name(s: &str) -> Result<Preset, BreathingError> {
        let lower = s.trim().to_ascii_lowercase();
        Preset::ALL
            .into_iter()
            .find(|p| p.name() == lower)
            .ok_or_else(|| BreathingError::UnknownPreset(s.to_owned()))
    }

    /// The preset's parameters (see the table in the module docs).
    pub fn params(self) -> BreathingParams {
        let base = BreathingParams::default();
        match self {
            Preset::Neutral => base,
            Preset::Calm => BreathingParams {
                thorax_vs_abdomen: 0.8,
                capacity_lung: 90.0,
                mouth_vs_nose: 0.15,
                amplitude_breathing_sound: 0.25,
                opening_inspiration_channels: 0.35,
                speaking_loudness: 0.4,
                prosody_rate: 0.85,
                inspiration_length_s: 1.35,
                neck_motion_amplitude_deg: 2.0,
                rest_period_s: 6.0,
                rest_depth: 0.15,
                ..base
            },
            Preset::Anxious => BreathingParams {
                thorax_vs_abdomen: 0.15,
                capacity_lung: 35.0,
                mouth_vs_nose: 0.85,
                amplitude_breathing_sound: 0.6,
                opening_inspiration_channels: 0.85,
                speaking_loudness: 0.65,
                prosody_rate: 1.3,
                inspiration_length_s: 0.8,
                neck_motion_amplitude_deg: 4.0,
                rest_period_s: 2.2,
                rest_depth: 0.10,
                ..base
            },
            Preset::Tired => BreathingParams {
                thorax_vs_abdomen: 0.6,
                capacity_lung: 45.0,
                mouth_vs_nose: 0.7,
                amplitude_breathing_sound: 0.5,
                opening_inspiration_channels: 0.55,
                speaking_loudness: 0.3,
                prosody_rate: 0.8,
                inspiration_length_s: 1.8,
                neck_motion_amplitude_deg: 1.5,
                rest_period_s: 5.0,
                rest_depth: 0.18,
                ..base
            },
            Preset::Excited => BreathingParams {
                thorax_vs_abdomen: 0.3,
                capacity_lung: 80.0,
                mouth_vs_nose: 0.85,
                amplitude_breathing_sound: 0.55,
                opening_inspiration_channels: 0.9,
                speaking_loudness: 0.85,
                prosody_rate: 1.2,
                inspiration_length_s: 0.7,
                neck_motion_amplitude_deg: 5.0,
                rest_period_s: 3.0,
                rest_depth: 0.12,
                ..base
            },
        }
    }
}

impl std::fmt::Display for Preset {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_parses_back_and_the_error_lists_them_all() {
        assert_eq!(Preset::NAMES.len(), Preset::ALL.len());
        for (p, name) in Preset::ALL.into_iter().zip(Preset::NAMES) {
            assert_eq!(p.name(), name);
            assert_eq!(Preset::from_name(&name.to_uppercase()).unwrap(), p);
        }
        let e = Preset::from_name("sleepy").unwrap_err().to_string();
        assert!(
            e.ends_with("use one of neutral, calm, anxious, tired, excited"),
            "{e}"
        );
    }
}
