//! The outputs' settings: the MIDI CC map ([`crate::encode::midi_cc::CcMap`]; the controller of
//! each signal comes from [`crate::encode::midi_cc::CcSignal`]) and the OSC target's port and
//! address space (the encoder is core's; the socket and the host belong to the doors).

use super::setting::{Kind, Scope, Setting, Unit};

/// MIDI channel of the CC messages.
pub static MIDI_CHANNEL: Setting = Setting {
    id: "midi_channel",
    label: "MIDI channel",
    unit: Unit::None,
    kind: Kind::Integer { min: 1, max: 16 },
    default: 1.0,
    off: None,
    scope: Scope::Live,
    help: "MIDI channel of the CC messages, as hosts number them",
    why: "MIDI's 16 channels",
};

/// 14-bit CC pairs.
pub static CC_14BIT: Setting = Setting {
    id: "cc_14bit",
    label: "CC 14-bit",
    unit: Unit::None,
    kind: Kind::Switch,
    default: 0.0,
    off: None,
    scope: Scope::Live,
    help: "14-bit CC pairs (MSB on controller n, LSB on n + 32; controllers 1-31) instead of \
           7-bit values",
    why: "on or off",
};

/// Head angle at the ends of the CC range.
pub static CC_HEAD_RANGE_DEG: Setting = Setting {
    id: "cc_head_range_deg",
    label: "CC head range",
    unit: Unit::Degrees,
    kind: Kind::Number {
        min: 1.0,
        max: 90.0,
        step: 0.5,
    },
    default: 30.0,
    off: None,
    scope: Scope::Live,
    help: "Head angle at the ends of the CC range (64 is straight ahead)",
    why: "the plugin's range since its first release; the head limits reach 90°",
};

/// Neck pitch at the ends of the CC range.
pub static CC_NECK_RANGE_DEG: Setting = Setting {
    id: "cc_neck_range_deg",
    label: "CC neck range",
    unit: Unit::Degrees,
    kind: Kind::Number {
        min: 1.0,
        max: 90.0,
        step: 0.5,
    },
    default: 10.0,
    off: None,
    scope: Scope::Live,
    help: "Neck pitch at the ends of the CC range",
    why: "as the head range",
};

/// Loudness at CC value 0.
pub static CC_LOUDNESS_FLOOR_DB: Setting = Setting {
    id: "cc_loudness_floor_db",
    label: "CC loudness floor",
    unit: Unit::DecibelsFs,
    kind: Kind::Number {
        min: -140.0,
        max: -6.0,
        step: 1.0,
    },
    default: -60.0,
    off: None,
    scope: Scope::Live,
    help: "Loudness that maps to CC value 0 (0 dBFS maps to the top)",
    why: "from under 24-bit silence to a span of at least 6 dB",
};

/// OSC UDP port.
pub static OSC_PORT: Setting = Setting {
    id: "osc_port",
    label: "OSC port",
    unit: Unit::None,
    kind: Kind::Integer { min: 1, max: 65535 },
    default: 39539.0,
    off: None,
    scope: Scope::Live,
    help: "UDP port the OSC bundles go to (39539: the VMC marionette port most avatar apps \
           listen on)",
    why: "every UDP port but 0",
};

/// OSC address space.
pub static OSC_FORMAT: Setting = Setting {
    id: "osc_format",
    label: "OSC format",
    unit: Unit::None,
    kind: Kind::Choice(&["pneuma", "vmc"]),
    default: 0.0,
    off: None,
    scope: Scope::Live,
    help: "OSC address space: pneuma (/pneuma/...) or vmc (the VMC protocol avatar apps speak)",
    why: "the two address spaces (docs/DESIGN.md, OSC)",
};

/// The MIDI CC settings, in documentation order.
pub static MIDI_SETTINGS: [&Setting; 5] = [
    &MIDI_CHANNEL,
    &CC_14BIT,
    &CC_HEAD_RANGE_DEG,
    &CC_NECK_RANGE_DEG,
    &CC_LOUDNESS_FLOOR_DB,
];

/// The OSC settings, in documentation order.
pub static OSC_SETTINGS: [&Setting; 2] = [&OSC_PORT, &OSC_FORMAT];
