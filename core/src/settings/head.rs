//! Head-pose synthesis: the settings of [`crate::head::HeadConfig`] (its amount, limits,
//! speed and liveliness; the seed and the unvoiced behaviour are not numbers with a range and
//! stay fields of the struct).

use super::setting::{Kind, Scope, Setting, Unit};

/// The numbers of an angle limit.
const LIMIT: Kind = Kind::Number {
    min: 0.5,
    max: 90.0,
    step: 0.5,
};

/// Why the angle limits span what they span.
const LIMIT_WHY: &str = "a limit under 0.5° freezes the axis (use the amount for that); 90° is \
                         as far as a head turns";

/// Amplitude scale of the motion.
pub static HEAD_AMOUNT: Setting = Setting {
    id: "head_amount",
    label: "Head motion",
    unit: Unit::None,
    kind: Kind::Number {
        min: 0.0,
        max: 4.0,
        step: 0.01,
    },
    default: 1.0,
    off: None,
    scope: Scope::Live,
    help: "Amplitude scale of the generated head motion (0 keeps the head still)",
    why: "1 is the model's motion; 4 times it reaches the limits on ordinary speech",
};

/// Largest |pitch|.
pub static HEAD_MAX_PITCH_DEG: Setting = Setting {
    id: "head_max_pitch_deg",
    label: "Head pitch limit",
    unit: Unit::Degrees,
    kind: LIMIT,
    default: 8.0,
    off: None,
    scope: Scope::Live,
    help: "Largest head pitch either way (nodding)",
    why: LIMIT_WHY,
};

/// Largest |yaw|.
pub static HEAD_MAX_YAW_DEG: Setting = Setting {
    id: "head_max_yaw_deg",
    label: "Head yaw limit",
    unit: Unit::Degrees,
    kind: LIMIT,
    default: 15.0,
    off: None,
    scope: Scope::Live,
    help: "Largest head yaw either way (turning)",
    why: LIMIT_WHY,
};

/// Largest |roll|.
pub static HEAD_MAX_ROLL_DEG: Setting = Setting {
    id: "head_max_roll_deg",
    label: "Head roll limit",
    unit: Unit::Degrees,
    kind: LIMIT,
    default: 12.0,
    off: None,
    scope: Scope::Live,
    help: "Largest head roll either way (tilting)",
    why: LIMIT_WHY,
};

/// Largest angular speed.
pub static HEAD_MAX_SPEED_DEG_S: Setting = Setting {
    id: "head_max_speed_deg_s",
    label: "Head speed limit",
    unit: Unit::DegreesPerSecond,
    kind: Kind::Number {
        min: 1.0,
        max: 2000.0,
        step: 1.0,
    },
    default: 240.0,
    off: None,
    scope: Scope::Live,
    help: "Largest angular speed of the head",
    why: "quick head movements reach a few hundred degrees per second; 2000 is no limit",
};

/// Seeded slow random variation.
pub static HEAD_LIVELINESS: Setting = Setting {
    id: "head_liveliness",
    label: "Head liveliness",
    unit: Unit::None,
    kind: Kind::Number {
        min: 0.0,
        max: 1.0,
        step: 0.01,
    },
    default: 0.0,
    off: None,
    scope: Scope::Live,
    help: "Seeded slow random variation added to the pose: 1 adds a wandering offset of about 2° \
           per axis with a 1.5 s time constant (0 off)",
    why: "a share of the largest variation",
};

/// The group's settings, in documentation order.
pub static SETTINGS: [&Setting; 6] = [
    &HEAD_AMOUNT,
    &HEAD_MAX_PITCH_DEG,
    &HEAD_MAX_YAW_DEG,
    &HEAD_MAX_ROLL_DEG,
    &HEAD_MAX_SPEED_DEG_S,
    &HEAD_LIVELINESS,
];
