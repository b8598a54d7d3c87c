//! Where and how loud breaths go: the settings of [`crate::engine::PlacementConfig`].

use super::setting::{Kind, Scope, Setting, Unit};

/// Lookahead or live placement.
pub static MODE: Setting = Setting {
    id: "mode",
    label: "Mode",
    unit: Unit::None,
    kind: Kind::Choice(&["lookahead", "live"]),
    default: 0.0,
    off: None,
    scope: Scope::Stream,
    help: "Placement: lookahead delays the audio and ends each breath just before the next \
           phrase; live has no delay and starts a breath once a pause is confirmed",
    why: "the two placement policies (docs/DESIGN.md, Placement policies)",
};

/// Delay of the audio in lookahead mode.
pub static LOOKAHEAD_S: Setting = Setting {
    id: "lookahead_s",
    label: "Lookahead",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.3,
        max: 2.0,
        step: 0.01,
    },
    default: 0.5,
    off: None,
    scope: Scope::Stream,
    help: "Delay of the audio in lookahead mode (the plugin's latency): the longest breath that \
           fits is about this minus the onset confirmation (~60 ms) and the gap",
    why: "under 0.3 s too little of a breath fits before the onset; over 2 s the latency is \
          longer than any breath group's pause needs",
};

/// Offline render of a whole file.
pub static WHOLE_FILE: Setting = Setting {
    id: "whole_file",
    label: "Whole-file lookahead",
    unit: Unit::None,
    kind: Kind::Switch,
    default: 0.0,
    off: None,
    scope: Scope::Stream,
    help: "Offline render of a whole file (lookahead mode): the engine looks 8 s ahead (or the \
           lookahead if longer), so it sees the coming breath group and gives long pauses long, \
           deep breaths",
    why: "on or off",
};

/// Breaths only into pauses of speech.
pub static SPEECH_ONLY: Setting = Setting {
    id: "speech_only",
    label: "Speech pauses only",
    unit: Unit::None,
    kind: Kind::Switch,
    default: 1.0,
    off: None,
    scope: Scope::Stream,
    help: "Breaths only into pauses of speech: the speech decision (Silero VAD and two cues of \
           Pneuma's own) keeps them out of music, singing, noise and silence with no speech \
           beside them, and the body does not talk along with those (no speaking flag, no \
           breathing out, the head at rest). Off: every pause the phrase tracker finds \
           (breaths between sung phrases, generated test signals); `pneuma render --any-sound`",
    why: "on or off",
};

/// Shortest pause that gets a full breath and ends a breath group (shorter ones may get a
/// catch breath).
pub static MIN_PAUSE_S: Setting = Setting {
    id: "min_pause_s",
    label: "Minimum pause",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.1,
        max: 2.0,
        step: 0.01,
    },
    default: 0.25,
    off: None,
    scope: Scope::Live,
    help: "Shortest pause that gets a full breath and ends a breath group. A shorter pause \
           gets no breath unless the group's air runs out before its next such pause; then \
           (lookahead mode) a catch breath goes into it (`catch_breath_min_s` to \
           `catch_breath_max_s`, 0.15-0.25 s by default). Raising it makes \
           longer groups: fewer full breaths, and more short catch breaths in short pauses",
    why: "the plugin's range since its first release (saved automation keeps its meaning); a \
          breath needs at least 0.1 s, and pauses over 2 s always get one",
};

/// Silence between the end of an inhalation and the next onset.
pub static GAP_S: Setting = Setting {
    id: "gap_s",
    label: "Gap before onset",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.0,
        max: 0.3,
        step: 0.005,
    },
    default: 0.04,
    off: None,
    scope: Scope::Live,
    help: "Silence left between the end of an inhalation and the next phrase onset",
    why: "a speaker's closure before an onset lasts up to a few hundred milliseconds",
};

/// Silence kept after a phrase before an inhalation.
pub static AFTER_OFFSET_S: Setting = Setting {
    id: "after_offset_s",
    label: "Gap after phrase",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.0,
        max: 0.5,
        step: 0.005,
    },
    default: 0.06,
    off: None,
    scope: Scope::Live,
    help: "Silence kept after the end of a phrase before an inhalation may start",
    why: "decays and releases last up to half a second",
};

/// Breath level relative to the speech.
pub static BREATH_LEVEL_DB: Setting = Setting {
    id: "breath_level_db",
    label: "Breath level",
    unit: Unit::Decibels,
    kind: Kind::Number {
        min: -40.0,
        max: -6.0,
        step: 0.1,
    },
    default: -22.0,
    off: None,
    scope: Scope::Live,
    help: "Breath level (plateau RMS) relative to the running speech level, for the neutral \
           breathing preset; other presets scale it by their breathing-sound amplitude",
    why: "the plugin's range since its first release (saved automation keeps its meaning); real \
          inhalations lie 15-30 dB under speech, under -40 dB a breath is inaudible (turn \
          insertion off instead), and a breath is never louder than -6 dB re the speech",
};

/// Insert breaths into the audio.
pub static INSERT_BREATHS: Setting = Setting {
    id: "insert_breaths",
    label: "Insert breaths",
    unit: Unit::None,
    kind: Kind::Switch,
    default: 1.0,
    off: None,
    scope: Scope::Live,
    help: "Insert breaths into the audio (off: the audio passes unchanged, the controls still \
           follow the breathing cycle)",
    why: "on or off",
};

/// Fade of a live-mode breath when speech resumes.
pub static LIVE_FADE_S: Setting = Setting {
    id: "live_fade_s",
    label: "Live fade",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.002,
        max: 0.1,
        step: 0.001,
    },
    default: 0.015,
    off: None,
    scope: Scope::Live,
    help: "Fade applied when speech resumes during a live-mode breath",
    why: "under 2 ms the cut clicks; over 100 ms the breath is heard over the speech",
};

/// Shortest catch breath.
pub static CATCH_BREATH_MIN_S: Setting = Setting {
    id: "catch_breath_min_s",
    label: "Shortest catch breath",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.05,
        max: 0.5,
        step: 0.01,
    },
    default: 0.15,
    off: None,
    scope: Scope::Live,
    help: "Shortest catch breath: when a breath group's air would run out before its next \
           usable pause, a quick inhalation goes into a shorter pause if at least this much fits",
    why: "a quick catch breath lasts 0.05-0.5 s",
};

/// Longest catch breath.
pub static CATCH_BREATH_MAX_S: Setting = Setting {
    id: "catch_breath_max_s",
    label: "Longest catch breath",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.1,
        max: 1.0,
        step: 0.01,
    },
    default: 0.25,
    off: None,
    scope: Scope::Live,
    help: "Longest catch breath (at least the shortest)",
    why: "longer than 1 s is a full breath, not a catch breath",
};

/// The group's settings, in documentation order.
pub static SETTINGS: [&Setting; 12] = [
    &MODE,
    &LOOKAHEAD_S,
    &WHOLE_FILE,
    &SPEECH_ONLY,
    &MIN_PAUSE_S,
    &GAP_S,
    &AFTER_OFFSET_S,
    &BREATH_LEVEL_DB,
    &INSERT_BREATHS,
    &LIVE_FADE_S,
    &CATCH_BREATH_MIN_S,
    &CATCH_BREATH_MAX_S,
];
