//! Phrase tracking (speech, pauses, breaths already in the input): the settings of
//! [`crate::phrase::PhraseConfig`]. All of them size the stream (the stream part).

use super::setting::{Kind, Scope, Setting, Unit};

/// A phrase-tracker time in seconds between `min` and `max`, shown in milliseconds' steps.
const fn seconds(min: f32, max: f32) -> Kind {
    Kind::Number {
        min,
        max,
        step: 0.005,
    }
}

/// A margin in decibels between `min` and `max`.
const fn decibels(min: f32, max: f32) -> Kind {
    Kind::Number {
        min,
        max,
        step: 0.5,
    }
}

/// Silence after which a phrase ends.
pub static HANGOVER_S: Setting = Setting {
    id: "hangover_s",
    label: "Phrase hangover",
    unit: Unit::Seconds,
    kind: seconds(0.05, 1.0),
    default: 0.15,
    off: None,
    scope: Scope::Stream,
    help: "Silence of the phrase after which it ends: pauses shorter than this never split a \
           phrase",
    why: "stop closures last up to 50 ms; a second of silence is always a pause",
};

/// Voiced time an onset needs.
pub static ONSET_VOICED_S: Setting = Setting {
    id: "onset_voiced_s",
    label: "Onset voicing",
    unit: Unit::Seconds,
    kind: seconds(0.01, 0.2),
    default: 0.03,
    off: None,
    scope: Scope::Stream,
    help: "Voiced time a run of active frames needs before it counts as a phrase (unvoiced noise \
           bursts never start one)",
    why: "a frame or two up to a syllable's vowel",
};

/// Longest inactive gap inside a candidate onset.
pub static RUN_GAP_S: Setting = Setting {
    id: "run_gap_s",
    label: "Onset gap",
    unit: Unit::Seconds,
    kind: seconds(0.01, 0.2),
    default: 0.06,
    off: None,
    scope: Scope::Stream,
    help: "Longest inactive gap inside a candidate onset run",
    why: "a frame up to a stop closure",
};

/// Margin over the floor an unvoiced frame needs to be speech.
pub static ACTIVITY_MARGIN_DB: Setting = Setting {
    id: "activity_margin_db",
    label: "Activity margin",
    unit: Unit::Decibels,
    kind: decibels(3.0, 30.0),
    default: 8.0,
    off: None,
    scope: Scope::Stream,
    help: "Margin over the noise floor an unvoiced frame needs to be speech",
    why: "under 3 dB the floor's own spread counts as speech",
};

/// How far under the speech level an unvoiced frame may be.
pub static UNVOICED_DROP_DB: Setting = Setting {
    id: "unvoiced_drop_db",
    label: "Unvoiced drop",
    unit: Unit::Decibels,
    kind: decibels(6.0, 40.0),
    default: 12.0,
    off: None,
    scope: Scope::Stream,
    help: "How far under the running speech level an unvoiced frame may be and still be speech \
           (breaths sit 20-30 dB under speech and stay out)",
    why: "consonants lie 6-40 dB under the vowels",
};

/// Margin of phrase edges and breath bursts.
pub static EDGE_MARGIN_DB: Setting = Setting {
    id: "edge_margin_db",
    label: "Edge margin",
    unit: Unit::Decibels,
    kind: decibels(2.0, 20.0),
    default: 6.0,
    off: None,
    scope: Scope::Stream,
    help: "Margin over the noise floor of phrase edges (quiet consonants, decays) and of breath \
           bursts",
    why: "over the floor's spread, under the activity margin's top",
};

/// How far an onset may move back.
pub static EDGE_EXTEND_S: Setting = Setting {
    id: "edge_extend_s",
    label: "Onset extension",
    unit: Unit::Seconds,
    kind: seconds(0.0, 0.4),
    default: 0.15,
    off: None,
    scope: Scope::Stream,
    help: "How far a phrase onset may be moved back over edge frames",
    why: "a leading consonant cluster lasts up to 0.4 s",
};

/// How far an offset may move forward.
pub static OFFSET_EXTEND_S: Setting = Setting {
    id: "offset_extend_s",
    label: "Offset extension",
    unit: Unit::Seconds,
    kind: seconds(0.0, 0.4),
    default: 0.08,
    off: None,
    scope: Scope::Stream,
    help: "How far a phrase offset may be moved forward over edge frames",
    why: "a trailing consonant or decay lasts up to 0.4 s",
};

/// Shortest breath already in a pause.
pub static BREATH_MIN_S: Setting = Setting {
    id: "breath_min_s",
    label: "Shortest heard breath",
    unit: Unit::Seconds,
    kind: seconds(0.05, 1.0),
    default: 0.12,
    off: None,
    scope: Scope::Stream,
    help: "Shortest breath-like burst inside a pause that counts as a breath already there",
    why: "real inhalations last 0.1-1 s",
};

/// Frames under this level are silence.
pub static PHRASE_SILENCE_DB: Setting = Setting {
    id: "phrase_silence_db",
    label: "Phrase silence",
    unit: Unit::DecibelsFs,
    kind: decibels(-140.0, -30.0),
    default: -75.0,
    off: None,
    scope: Scope::Stream,
    help: "Frames under this level are silence whatever the noise floor (for a speaker at a \
           normal level; under a quiet speaker it moves down with the speech level)",
    why: "from under 24-bit silence to a quiet voice's level",
};

/// Margin of a breath run's frames.
pub static BREATH_MARGIN_DB: Setting = Setting {
    id: "breath_margin_db",
    label: "Breath margin",
    unit: Unit::Decibels,
    kind: decibels(2.0, 20.0),
    default: 6.0,
    off: None,
    scope: Scope::Stream,
    help: "Margin over the noise floor a frame of a breath run needs",
    why: "over the floor's spread, under a breath's level over a quiet room",
};

/// Spectral shape of a breath: high band over mid band.
pub static BREATH_MAX_HIGH_OVER_MID_DB: Setting = Setting {
    id: "breath_max_high_over_mid_db",
    label: "Breath high/mid limit",
    unit: Unit::Decibels,
    kind: decibels(-40.0, 40.0),
    default: 0.0,
    off: None,
    scope: Scope::Stream,
    help: "Spectral shape of a breath: the run's mean level of 2.5-3.5 kHz over 0.5-2.5 kHz, the \
           room's own band levels taken out, must not exceed this (40 = no limit); breath noise \
           sits under 0, /s/ and /sh/ well above. Fitted by `pneuma eval breath-sounds`",
    why: "band ratios of breaths and fricatives lie within ±40 dB; 40 turns the limit off",
};

/// Spectral shape of a breath: low band over mid band.
pub static BREATH_MAX_LOW_OVER_MID_DB: Setting = Setting {
    id: "breath_max_low_over_mid_db",
    label: "Breath low/mid limit",
    unit: Unit::Decibels,
    kind: decibels(-40.0, 40.0),
    default: -1.5,
    off: None,
    scope: Scope::Stream,
    help: "Spectral shape of a breath: the run's mean level of 100-400 Hz over 0.5-2.5 kHz, the \
           room taken out, must not exceed this (40 = no limit); vowel tails, hum and rumble lie \
           high. Fitted by `pneuma eval breath-sounds`",
    why: "band ratios of breaths and vowel tails lie within ±40 dB; 40 turns the limit off",
};

/// The group's settings, in documentation order.
pub static SETTINGS: [&Setting; 13] = [
    &HANGOVER_S,
    &ONSET_VOICED_S,
    &RUN_GAP_S,
    &ACTIVITY_MARGIN_DB,
    &UNVOICED_DROP_DB,
    &EDGE_MARGIN_DB,
    &EDGE_EXTEND_S,
    &OFFSET_EXTEND_S,
    &BREATH_MIN_S,
    &PHRASE_SILENCE_DB,
    &BREATH_MARGIN_DB,
    &BREATH_MAX_HIGH_OVER_MID_DB,
    &BREATH_MAX_LOW_OVER_MID_DB,
];
