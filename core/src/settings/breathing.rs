//! The breathing model's controls (Bernardet et al., Table 1, and the independent ones): the
//! settings of [`crate::breathing::BreathingParams`]. The ranges are the model's: Table 1's
//! where it gives one, else the span over which Equation 1 (as read in
//! `core/src/breathing/params.rs`) gives a breathing a person could do.

use super::setting::{Kind, Scope, Setting, Unit};

/// The numbers of a 0..1 control shown in hundredths.
const FRACTION: Kind = Kind::Number {
    min: 0.0,
    max: 1.0,
    step: 0.01,
};

/// Chest vs stomach breathing.
pub static THORAX_VS_ABDOMEN: Setting = Setting {
    id: "thorax_vs_abdomen",
    label: "Thorax vs abdomen",
    unit: Unit::None,
    kind: FRACTION,
    default: 0.5,
    off: None,
    scope: Scope::Live,
    help: "Balance of chest vs stomach breathing: 0 thorax only, 1 abdomen only",
    why: "a share: Table 1's ThoraxVsAbdomen",
};

/// Overall lung capacity.
pub static CAPACITY_LUNG: Setting = Setting {
    id: "capacity_lung",
    label: "Lung capacity",
    unit: Unit::Percent,
    kind: Kind::Number {
        min: 10.0,
        max: 100.0,
        step: 1.0,
    },
    default: 60.0,
    off: None,
    scope: Scope::Live,
    help: "Overall lung capacity, percent of a large adult lung",
    why: "Table 1's CapacityLung; under 10 % no breath group is left",
};

/// Nose vs mouth breathing.
pub static MOUTH_VS_NOSE: Setting = Setting {
    id: "mouth_vs_nose",
    label: "Mouth vs nose",
    unit: Unit::None,
    kind: FRACTION,
    default: 0.5,
    off: None,
    scope: Scope::Live,
    help: "Breathing through nose vs mouth: 0 nose only, 1 mouth only (the breath sound \
           darker or brighter than the speaker's own at 0.5; the nostrils or the mouth open)",
    why: "a share: Table 1's MouthVsNose (read as the mouth's share)",
};

/// How audible the breathing is.
pub static BREATH_SOUND: Setting = Setting {
    id: "breath_sound",
    label: "Breath sound",
    unit: Unit::None,
    kind: FRACTION,
    default: 0.35,
    off: None,
    scope: Scope::Live,
    help: "How audible the breathing sounds are: 0 silent, 1 loudest (scales the breath level)",
    why: "Table 1's AmplitudeBreathingSound",
};

/// How far nostrils and mouth open.
pub static OPENING: Setting = Setting {
    id: "opening",
    label: "Channel opening",
    unit: Unit::None,
    kind: FRACTION,
    default: 0.5,
    off: None,
    scope: Scope::Live,
    help: "How far nostrils and mouth open while breathing in",
    why: "Table 1's OpeningInspirationChannels",
};

/// How loud the speech is.
pub static SPEAKING_LOUDNESS: Setting = Setting {
    id: "speaking_loudness",
    label: "Speaking loudness",
    unit: Unit::None,
    kind: Kind::Number {
        min: 0.05,
        max: 1.0,
        step: 0.01,
    },
    default: 0.5,
    off: None,
    scope: Scope::Live,
    help: "How loud the speech is: louder speech uses air faster (shorter breath groups); the \
           speech synthesiser's amplitude in `pneuma speak`",
    why: "Table 1's SpeakingLoudness; Equation 1 divides by it, so it stays above 0.05",
};

/// Speaking-rate multiplier.
pub static PROSODY_RATE: Setting = Setting {
    id: "prosody_rate",
    label: "Speaking rate",
    unit: Unit::None,
    kind: Kind::Number {
        min: 0.5,
        max: 2.0,
        step: 0.01,
    },
    default: 1.0,
    off: None,
    scope: Scope::Live,
    help: "Speaking-rate multiplier of the syllable rate (and of the speech synthesiser)",
    why: "half to twice conversational speed",
};

/// Inspiration length of a full lung.
pub static INSPIRATION_LENGTH_S: Setting = Setting {
    id: "inspiration_length_s",
    label: "Inspiration length",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.2,
        max: 3.0,
        step: 0.01,
    },
    default: 1.0,
    off: None,
    scope: Scope::Live,
    help: "Inspiration length of a full (100 %) lung; a smaller lung fills faster",
    why: "speech inhalations last 0.2-1 s; 3 s is a deep sigh",
};

/// Head pitch at full lungs.
pub static NECK_AMPLITUDE_DEG: Setting = Setting {
    id: "neck_amplitude_deg",
    label: "Neck motion",
    unit: Unit::Degrees,
    kind: Kind::Number {
        min: 0.0,
        max: 15.0,
        step: 0.1,
    },
    default: 3.0,
    off: None,
    scope: Scope::Live,
    help: "Head pitch at full lungs (chin up)",
    why: "breathing tilts the head a few degrees; over 15° it is a nod, not a breath",
};

/// Equation 1's `norm_syllables`.
pub static NORM_SYLLABLES: Setting = Setting {
    id: "norm_syllables",
    label: "Syllables per breath",
    unit: Unit::Syllables,
    kind: Kind::Number {
        min: 0.2,
        max: 5.0,
        step: 0.1,
    },
    default: 1.4,
    off: None,
    scope: Scope::Live,
    help: "Equation 1's norm_syllables factor: neutral settings give about 15 syllables (a 3.8 s \
           breath group) at 1.4",
    why: "at the neutral lung and loudness 0.2 gives 2 syllables per breath and 5 gives 55; 1.4 \
          gives conversational breath groups",
};

/// Period of the resting breath.
pub static REST_PERIOD_S: Setting = Setting {
    id: "rest_period_s",
    label: "Rest period",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 1.5,
        max: 12.0,
        step: 0.1,
    },
    default: 4.0,
    off: None,
    scope: Scope::Live,
    help: "Period of the resting (tidal) breath",
    why: "5 to 40 breaths a minute",
};

/// Depth of the resting breath.
pub static REST_DEPTH: Setting = Setting {
    id: "rest_depth",
    label: "Rest depth",
    unit: Unit::None,
    kind: Kind::Number {
        min: 0.0,
        max: 0.5,
        step: 0.01,
    },
    default: 0.12,
    off: None,
    scope: Scope::Live,
    help: "Depth of the resting breath, fraction of the lung",
    why: "a tidal breath moves about a tenth of the lung; half is already deep breathing",
};

/// The group's settings, in documentation order.
pub static SETTINGS: [&Setting; 12] = [
    &THORAX_VS_ABDOMEN,
    &CAPACITY_LUNG,
    &MOUTH_VS_NOSE,
    &BREATH_SOUND,
    &OPENING,
    &SPEAKING_LOUDNESS,
    &PROSODY_RATE,
    &INSPIRATION_LENGTH_S,
    &NECK_AMPLITUDE_DEG,
    &NORM_SYLLABLES,
    &REST_PERIOD_S,
    &REST_DEPTH,
];
