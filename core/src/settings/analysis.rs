//! The analysis front end: the settings of [`crate::analysis::AnalysisConfig`] and of its
//! speaker normalisation ([`crate::analysis::SpeakerNormConfig`]). All of them size the stream
//! (the stream part). The voicing model is a fitted file, not a setting with a range.

use super::setting::{Kind, Scope, Setting, Unit};

/// Frame rate of the frame clock.
pub static FRAME_RATE_HZ: Setting = Setting {
    id: "frame_rate_hz",
    label: "Frame rate",
    unit: Unit::Hertz,
    kind: Kind::Number {
        min: 30.0,
        max: 240.0,
        step: 1.0,
    },
    default: 120.0,
    off: None,
    scope: Scope::Stream,
    help: "Feature and control frames per second (the rate of the controls CSV, MIDI CC, OSC and \
           BVH)",
    why: "the plugin's range since its first release (saved automation keeps its meaning); 30 \
          frames per second follow syllables (4-5 a second) and head motion, and over 240 the \
          frames overlap the 20-40 ms analysis windows tenfold and only cost time",
};

/// Lowest f0 searched.
pub static F0_MIN_HZ: Setting = Setting {
    id: "f0_min_hz",
    label: "Lowest f0",
    unit: Unit::Hertz,
    kind: Kind::Number {
        min: 30.0,
        max: 600.0,
        step: 1.0,
    },
    default: 50.0,
    off: None,
    scope: Scope::Stream,
    help: "Lowest f0 searched (the analysis window holds at least two of its periods)",
    why: "30 Hz is under the lowest speaking voice (creak); over 600 Hz no room is left for the \
          highest f0 at 1.5 times it",
};

/// Highest f0 searched.
pub static F0_MAX_HZ: Setting = Setting {
    id: "f0_max_hz",
    label: "Highest f0",
    unit: Unit::Hertz,
    kind: Kind::Number {
        min: 45.0,
        max: 1000.0,
        step: 1.0,
    },
    default: 600.0,
    off: None,
    scope: Scope::Stream,
    help: "Highest f0 searched (at least 1.5 times the lowest); a voice above it has no pitch, \
           not the subharmonic that lies in range",
    why: "1.5 times the lowest f0's floor; 1000 Hz is over any speaking voice",
};

/// Pitch analysis window.
pub static WINDOW_S: Setting = Setting {
    id: "window_s",
    label: "Pitch window",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.003,
        max: 0.1,
        step: 0.001,
    },
    default: 0.04,
    off: None,
    scope: Scope::Stream,
    help: "Pitch analysis window, at least two periods of the lowest f0",
    why: "two periods of the highest lowest f0 (600 Hz) take 3.3 ms; over 100 ms a window \
          smears syllables",
};

/// Short pitch window.
pub static SHORT_WINDOW_S: Setting = Setting {
    id: "short_window_s",
    label: "Short pitch window",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.005,
        max: 0.1,
        step: 0.001,
    },
    default: 0.02,
    off: Some(0.0),
    scope: Scope::Stream,
    help: "Short pitch window centred in the long one (at most the pitch window), for a voice \
           gliding fast and at phrase edges; 0 turns it off",
    why: "5 ms holds two periods of 400 Hz; it lies inside the long window",
};

/// RMS window.
pub static RMS_WINDOW_S: Setting = Setting {
    id: "rms_window_s",
    label: "Level window",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.005,
        max: 0.1,
        step: 0.001,
    },
    default: 0.02,
    off: None,
    scope: Scope::Stream,
    help: "RMS window, centred on the frame time",
    why: "5 ms is a period of the lowest voices; over 100 ms the level smears syllables",
};

/// Key-maximum rule.
pub static KEY_MAX_RATIO: Setting = Setting {
    id: "key_max_ratio",
    label: "Key-maximum ratio",
    unit: Unit::None,
    kind: Kind::Number {
        min: 0.5,
        max: 1.0,
        step: 0.01,
    },
    default: 0.88,
    off: None,
    scope: Scope::Stream,
    help: "The first NSDF key maximum at least this fraction of the highest one is the period",
    why: "under 0.5 the rule picks subharmonics' halves; 1 takes the highest maximum",
};

/// Frames below this level are never voiced.
pub static SILENCE_DB: Setting = Setting {
    id: "silence_db",
    label: "Voicing silence",
    unit: Unit::DecibelsFs,
    kind: Kind::Number {
        min: -120.0,
        max: 0.0,
        step: 1.0,
    },
    default: -60.0,
    off: None,
    scope: Scope::Stream,
    help: "Frames below this RMS level are never voiced while the speaker's running speech \
           level lies at -30 dBFS or louder; under a quieter speaker it moves down with that \
           level",
    why: "from the 20-bit noise floor to full scale",
};

/// Window of the noise-floor tracker.
pub static NOISE_WINDOW_S: Setting = Setting {
    id: "noise_window_s",
    label: "Noise window",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.5,
        max: 30.0,
        step: 0.1,
    },
    default: 3.0,
    off: None,
    scope: Scope::Stream,
    help: "Window of the noise-floor tracker: the floor is the lowest level of the not clearly \
           periodic frames over that window",
    why: "it must span a pause (0.5 s) and follow a changing room (30 s)",
};

/// High-pass before the pitch analysis.
pub static HIGHPASS_HZ: Setting = Setting {
    id: "highpass_hz",
    label: "High-pass",
    unit: Unit::Hertz,
    kind: Kind::Number {
        min: 0.0,
        max: 400.0,
        step: 1.0,
    },
    default: 120.0,
    off: None,
    scope: Scope::Stream,
    help: "High-pass corner before the pitch analysis (0 off): takes rumble (traffic, car, \
           handling noise) out of the periodicity measure",
    why: "over 400 Hz it takes the fundamentals of most voices",
};

/// Low-pass of the periodicity measure.
pub static LOWPASS_HZ: Setting = Setting {
    id: "lowpass_hz",
    label: "Low-pass",
    unit: Unit::Hertz,
    kind: Kind::Number {
        min: 500.0,
        max: 3500.0,
        step: 10.0,
    },
    default: 1800.0,
    off: Some(0.0),
    scope: Scope::Stream,
    help: "Corner of the low-pass the periodicity measure (NSDF) hears its windows through \
           (0 off): the voice's periodicity lives in its lower harmonics, broadband noise does \
           not",
    why: "over the voice's fundamentals (500 Hz) and under the lowest internal Nyquist \
          frequency (4 kHz)",
};

/// Half-life of the speaker statistics.
pub static SPEAKER_HALF_LIFE_S: Setting = Setting {
    id: "speaker_half_life_s",
    label: "Speaker half-life",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 1.0,
        max: 36_000.0,
        step: 1.0,
    },
    default: 30.0,
    off: None,
    scope: Scope::Stream,
    help: "Half-life of the running speaker statistics, in seconds of voiced speech",
    why: "from a second to ten hours of speech (never forget)",
};

/// Prior median f0.
pub static SPEAKER_PRIOR_F0_HZ: Setting = Setting {
    id: "speaker_prior_f0_hz",
    label: "Speaker prior f0",
    unit: Unit::Hertz,
    kind: Kind::Number {
        min: 40.0,
        max: 900.0,
        step: 1.0,
    },
    default: 150.0,
    off: None,
    scope: Scope::Stream,
    help: "Median f0 assumed before the speaker is heard",
    why: "the speaking voices' span",
};

/// Prior speech level.
pub static SPEAKER_PRIOR_LEVEL_DB: Setting = Setting {
    id: "speaker_prior_level_db",
    label: "Speaker prior level",
    unit: Unit::DecibelsFs,
    kind: Kind::Number {
        min: -100.0,
        max: 0.0,
        step: 1.0,
    },
    default: -26.0,
    off: None,
    scope: Scope::Stream,
    help: "Speech level assumed before the speaker is heard",
    why: "from near silence to full scale",
};

/// Weight of the priors.
pub static SPEAKER_PRIOR_WEIGHT_S: Setting = Setting {
    id: "speaker_prior_weight_s",
    label: "Speaker prior weight",
    unit: Unit::Seconds,
    kind: Kind::Number {
        min: 0.0,
        max: 60.0,
        step: 0.1,
    },
    default: 1.0,
    off: None,
    scope: Scope::Stream,
    help: "Weight of the priors, in seconds of voiced speech",
    why: "none to a minute of speech",
};

/// The analysis settings, in documentation order.
pub static SETTINGS: [&Setting; 11] = [
    &FRAME_RATE_HZ,
    &F0_MIN_HZ,
    &F0_MAX_HZ,
    &WINDOW_S,
    &SHORT_WINDOW_S,
    &RMS_WINDOW_S,
    &KEY_MAX_RATIO,
    &SILENCE_DB,
    &NOISE_WINDOW_S,
    &HIGHPASS_HZ,
    &LOWPASS_HZ,
];

/// The speaker normalisation's settings, in documentation order.
pub static SPEAKER_SETTINGS: [&Setting; 4] = [
    &SPEAKER_HALF_LIFE_S,
    &SPEAKER_PRIOR_F0_HZ,
    &SPEAKER_PRIOR_LEVEL_DB,
    &SPEAKER_PRIOR_WEIGHT_S,
];
