//! MIDI CC encoder: turns [`ControlFrame`]s into MIDI control-change messages (DESIGN.md,
//! "Contracts", MIDI CC). Pure and allocation-free; the plugin turns the messages into host
//! events with a sample offset.
//!
//! Default map (every controller remappable, or switched off):
//!
//! | signal | CC | value mapping |
//! |---|---|---|
//! | lung volume | 2 (Breath Controller) | 0..1 → 0..127 |
//! | head pitch | 16 | −`head_range_deg`..+`head_range_deg` → 0..127, 64 = 0° |
//! | head yaw | 17 | as head pitch |
//! | head roll | 18 | as head pitch |
//! | thorax | 19 | 0..1 |
//! | abdomen | 20 | 0..1 |
//! | nostril flare | 21 | 0..1 |
//! | mouth open | 22 | 0..1 |
//! | neck pitch | 23 | −`neck_range_deg`..+`neck_range_deg`, 64 = 0° |
//! | speaking gate | 24 | 0 (pause) or 127 (speech) |
//! | loudness | 25 | `rms_db` from `loudness_floor_db` (0) to 0 dBFS (127) |
//!
//! Resolution: 7-bit (one message per signal), or 14-bit: the MSB on controller `n` (0..31) and
//! the LSB on `n + 32`, MSB first, as the MIDI 1.0 specification pairs them. A signed signal's
//! neutral is 8192 (MSB 64, LSB 0) in 14-bit mode. Values out of range are clamped; NaN maps to
//! the neutral value.
//!
//! A message leaves only when its quantised value changed since the last one sent, and
//! [`CcEncoder::encode`] is called once per frame, so each controller changes at most once per
//! frame. After [`CcEncoder::reset`] every mapped signal is sent again on the next frame.

use crate::control::ControlFrame;
use crate::settings::output::{
    CC_14BIT, CC_HEAD_RANGE_DEG, CC_LOUDNESS_FLOOR_DB, CC_NECK_RANGE_DEG, MIDI_CHANNEL,
};
use crate::settings::setting::{check_fields, Field, SettingError};
use thiserror::Error;

/// Number of signals the map covers.
pub const SIGNAL_COUNT: usize = 11;

/// One control signal of a [`ControlFrame`] that can leave as a CC.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CcSignal {
    /// Lung volume, 0..1.
    Lung,
    /// Head pitch, degrees, signed.
    HeadPitch,
    /// Head yaw, degrees, signed.
    HeadYaw,
    /// Head roll, degrees, signed.
    HeadRoll,
    /// Thorax expansion, 0..1.
    Thorax,
    /// Abdomen expansion, 0..1.
    Abdomen,
    /// Nostril flare, 0..1.
    NostrilFlare,
    /// Mouth opening from breathing, 0..1.
    MouthOpen,
    /// Neck pitch from breathing, degrees, signed.
    NeckPitch,
    /// Speaking gate, 0 or 1.
    Speaking,
    /// Loudness (`rms_db`), dBFS.
    Loudness,
}

impl CcSignal {
    /// Every signal, in map order (the index of a signal in this array is its index in
    /// [`CcMap::controllers`]).
    pub const ALL: [CcSignal; SIGNAL_COUNT] = [
        CcSignal::Lung,
        CcSignal::HeadPitch,
        CcSignal::HeadYaw,
        CcSignal::HeadRoll,
        CcSignal::Thorax,
        CcSignal::Abdomen,
        CcSignal::NostrilFlare,
        CcSignal::MouthOpen,
        CcSignal::NeckPitch,
        CcSignal::Speaking,
        CcSignal::Loudness,
    ];

    /// The default controller numbers, in [`CcSignal::ALL`] order.
    pub const DEFAULT_CONTROLLERS: [u8; SIGNAL_COUNT] = [2, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25];

    /// Position of this signal in [`CcSignal::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }

    /// A short stable name (`lung`, `head_pitch`, ...), used for parameter ids and docs.
    pub fn name(self) -> &'static str {
        match self {
            CcSignal::Lung => "lung",
            CcSignal::HeadPitch => "head_pitch",
            CcSignal::HeadYaw => "head_yaw",
            CcSignal::HeadRoll => "head_roll",
            CcSignal::Thorax => "thorax",
            CcSignal::Abdomen => "abdomen",
            CcSignal::NostrilFlare => "nostril_flare",
            CcSignal::MouthOpen => "mouth_open",
            CcSignal::NeckPitch => "neck_pitch",
            CcSignal::Speaking => "speaking",
            CcSignal::Loudness => "loudness",
        }
    }
}

/// CC value resolution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CcResolution {
    /// One 7-bit message per signal (0..127).
    #[default]
    Bits7,
    /// A 14-bit value as an MSB/LSB pair: controller `n` (0..31) and `n + 32`.
    Bits14,
}

impl CcResolution {
    /// The highest controller a signal may take: 119 for 7-bit CCs (120..127 are channel mode
    /// messages), 31 for 14-bit pairs (the LSB goes to controller + 32).
    pub const fn max_controller(self) -> u8 {
        match self {
            Self::Bits7 => 119,
            Self::Bits14 => 31,
        }
    }
}

/// A bad CC map: the message says what to change.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CcMapError {
    /// A setting of the map (channel, ranges) is out of its range.
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// A controller number is not usable.
    #[error(
        "controller {controller} for {signal} is out of range: use 0..{} for 7-bit CCs \
         (120..127 are channel mode messages) or 0..{} for 14-bit pairs (the LSB goes to \
         controller + 32)",
        CcResolution::Bits7.max_controller(),
        CcResolution::Bits14.max_controller()
    )]
    Controller {
        /// The signal's name.
        signal: &'static str,
        /// The rejected controller number.
        controller: u8,
    },
    /// Two signals share a controller (or one's LSB collides with another's controller).
    #[error("{first} and {second} both use controller {controller}: give each signal its own controller (14-bit pairs also use controller + 32)")]
    Duplicate {
        /// First signal.
        first: &'static str,
        /// Second signal.
        second: &'static str,
        /// The shared controller.
        controller: u8,
    },
}

/// Where and how each signal leaves as CC.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcMap {
    /// MIDI channel, 0..15 ([`MIDI_CHANNEL`] numbers them 1..16, as hosts show them).
    pub channel: u8,
    /// 7-bit or 14-bit values ([`CC_14BIT`]).
    pub resolution: CcResolution,
    /// Controller per signal in [`CcSignal::ALL`] order; `None` switches the signal off.
    pub controllers: [Option<u8>; SIGNAL_COUNT],
    /// Head angle that maps to the ends of the CC range, degrees ([`CC_HEAD_RANGE_DEG`]).
    pub head_range_deg: f32,
    /// Neck pitch that maps to the ends of the CC range, degrees ([`CC_NECK_RANGE_DEG`]).
    pub neck_range_deg: f32,
    /// Loudness that maps to CC value 0, dBFS; 0 dBFS maps to the top
    /// ([`CC_LOUDNESS_FLOOR_DB`]).
    pub loudness_floor_db: f32,
}

/// The settings of [`CcMap`] (all but the controllers, which [`CcSignal`] numbers) and the
/// fields holding them.
static FIELDS: [Field<CcMap>; 5] = [
    Field {
        setting: &MIDI_CHANNEL,
        get: |c| f64::from(c.channel) + 1.0,
        set: |c, v| c.channel = (v - 1.0) as u8,
    },
    Field {
        setting: &CC_14BIT,
        get: |c| {
            if c.resolution == CcResolution::Bits14 {
                1.0
            } else {
                0.0
            }
        },
        set: |c, v| {
            c.resolution = if v != 0.0 {
                CcResolution::Bits14
            } else {
                CcResolution::Bits7
            }
        },
    },
    Field {
        setting: &CC_HEAD_RANGE_DEG,
        get: |c| f64::from(c.head_range_deg),
        set: |c, v| c.head_range_deg = v as f32,
    },
    Field {
        setting: &CC_NECK_RANGE_DEG,
        get: |c| f64::from(c.neck_range_deg),
        set: |c, v| c.neck_range_deg = v as f32,
    },
    Field {
        setting: &CC_LOUDNESS_FLOOR_DB,
        get: |c| f64::from(c.loudness_floor_db),
        set: |c, v| c.loudness_floor_db = v as f32,
    },
];

impl Default for CcMap {
    /// The design map ([`CcSignal::DEFAULT_CONTROLLERS`]) with the table's defaults.
    fn default() -> Self {
        let mut controllers = [None; SIGNAL_COUNT];
        for (slot, cc) in controllers.iter_mut().zip(CcSignal::DEFAULT_CONTROLLERS) {
            *slot = Some(cc);
        }
        let mut map = Self {
            channel: 0,
            resolution: CcResolution::Bits7,
            controllers,
            head_range_deg: 0.0,
            neck_range_deg: 0.0,
            loudness_floor_db: 0.0,
        };
        for f in &FIELDS {
            (f.set)(&mut map, f64::from(f.setting.default));
        }
        map
    }
}

impl CcMap {
    /// The settings of the map and the fields holding them.
    pub fn fields() -> &'static [Field<CcMap>] {
        &FIELDS
    }

    /// Checks the settings (channel, ranges), the controller numbers and their collisions.
    pub fn validate(&self) -> Result<(), CcMapError> {
        check_fields(self, &FIELDS)?;
        let limit = self.resolution.max_controller();
        // Controllers each signal occupies (MSB and, in 14-bit mode, LSB).
        let mut used: [Option<&'static str>; 128] = [None; 128];
        for (signal, cc) in CcSignal::ALL.iter().zip(self.controllers) {
            let Some(cc) = cc else { continue };
            if cc > limit {
                return Err(CcMapError::Controller {
                    signal: signal.name(),
                    controller: cc,
                });
            }
            let lsb = (self.resolution == CcResolution::Bits14).then_some(cc + 32);
            for c in std::iter::once(cc).chain(lsb) {
                if let Some(first) = used[c as usize] {
                    return Err(CcMapError::Duplicate {
                        first,
                        second: signal.name(),
                        controller: c,
                    });
                }
                used[c as usize] = Some(signal.name());
            }
        }
        Ok(())
    }

    /// The signal's value as a fraction 0..1 of the CC range (0.5 = neutral for signed signals).
    /// NaN gives the neutral value (0 for unsigned signals).
    pub fn normalized(&self, signal: CcSignal, frame: &ControlFrame) -> f32 {
        let signed = |deg: f32, range: f32| 0.5 + 0.5 * deg / range;
        let b = &frame.breathing;
        let x = match signal {
            CcSignal::Lung => b.lung,
            CcSignal::HeadPitch => signed(frame.head.pitch_deg, self.head_range_deg),
            CcSignal::HeadYaw => signed(frame.head.yaw_deg, self.head_range_deg),
            CcSignal::HeadRoll => signed(frame.head.roll_deg, self.head_range_deg),
            CcSignal::Thorax => b.thorax,
            CcSignal::Abdomen => b.abdomen,
            CcSignal::NostrilFlare => b.nostril_flare,
            CcSignal::MouthOpen => b.mouth_open,
            CcSignal::NeckPitch => signed(b.neck_pitch_deg, self.neck_range_deg),
            CcSignal::Speaking => f32::from(u8::from(frame.speaking)),
            CcSignal::Loudness => 1.0 - frame.rms_db / self.loudness_floor_db,
        };
        if x.is_nan() {
            match signal {
                CcSignal::HeadPitch
                | CcSignal::HeadYaw
                | CcSignal::HeadRoll
                | CcSignal::NeckPitch => 0.5,
                _ => 0.0,
            }
        } else {
            x.clamp(0.0, 1.0)
        }
    }

    /// The quantised value of `signal`: 0..127 (7-bit) or 0..16383 (14-bit). A normalised 0.5
    /// gives 64 or 8192 exactly.
    pub fn quantize(&self, signal: CcSignal, frame: &ControlFrame) -> u16 {
        let x = self.normalized(signal, frame);
        let (scale, top) = match self.resolution {
            CcResolution::Bits7 => (128.0, 127.0),
            CcResolution::Bits14 => (16384.0, 16383.0),
        };
        (x * scale).round().min(top) as u16
    }
}

/// One MIDI control-change message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CcMessage {
    /// MIDI channel, 0..15.
    pub channel: u8,
    /// Controller number, 0..127.
    pub controller: u8,
    /// Value, 0..127.
    pub value: u8,
}

impl CcMessage {
    /// The three MIDI bytes (status `0xB0 | channel`, controller, value).
    pub fn to_bytes(self) -> [u8; 3] {
        [
            0xB0 | (self.channel & 0x0F),
            self.controller & 0x7F,
            self.value & 0x7F,
        ]
    }
}

/// Stateful encoder: remembers the last value sent per signal so only changes leave.
#[derive(Debug, Clone)]
pub struct CcEncoder {
    map: CcMap,
    last: [Option<u16>; SIGNAL_COUNT],
}

impl CcEncoder {
    /// An encoder for a validated map.
    pub fn new(map: CcMap) -> Result<Self, CcMapError> {
        map.validate()?;
        Ok(Self {
            map,
            last: [None; SIGNAL_COUNT],
        })
    }

    /// The current map.
    pub fn map(&self) -> &CcMap {
        &self.map
    }

    /// Replaces the map (allocation-free). If anything changed, every signal is sent again on the
    /// next frame. On error the old map stays.
    pub fn set_map(&mut self, map: CcMap) -> Result<(), CcMapError> {
        if map != self.map {
            map.validate()?;
            self.map = map;
            self.reset();
        }
        Ok(())
    }

    /// Forgets the values sent, so the next frame sends every mapped signal.
    pub fn reset(&mut self) {
        self.last = [None; SIGNAL_COUNT];
    }

    /// Encodes one frame: calls `out` for every message whose value changed, in
    /// [`CcSignal::ALL`] order (14-bit: MSB then LSB). Returns the number of messages. Never
    /// allocates.
    pub fn encode(&mut self, frame: &ControlFrame, mut out: impl FnMut(CcMessage)) -> usize {
        let mut sent = 0;
        let channel = self.map.channel;
        for signal in CcSignal::ALL {
            let i = signal.index();
            let Some(cc) = self.map.controllers[i] else {
                continue;
            };
            let value = self.map.quantize(signal, frame);
            if self.last[i] == Some(value) {
                continue;
            }
            self.last[i] = Some(value);
            match self.map.resolution {
                CcResolution::Bits7 => {
                    out(CcMessage {
                        channel,
                        controller: cc,
                        value: value as u8,
                    });
                    sent += 1;
                }
                CcResolution::Bits14 => {
                    out(CcMessage {
                        channel,
                        controller: cc,
                        value: (value >> 7) as u8,
                    });
                    out(CcMessage {
                        channel,
                        controller: cc + 32,
                        value: (value & 0x7F) as u8,
                    });
                    sent += 2;
                }
            }
        }
        sent
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{BreathingState, HeadAngles};

    fn frame(lung: f32, pitch_deg: f32) -> ControlFrame {
        ControlFrame {
            rms_db: -30.0,
            breathing: BreathingState {
                lung,
                ..Default::default()
            },
            head: HeadAngles {
                pitch_deg,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    fn collect(enc: &mut CcEncoder, f: &ControlFrame) -> Vec<CcMessage> {
        let mut v = Vec::new();
        enc.encode(f, |m| v.push(m));
        v
    }

    #[test]
    fn defaults_follow_the_design_table() {
        let map = CcMap::default();
        map.validate().unwrap();
        let want = [
            (CcSignal::Lung, 2),
            (CcSignal::HeadPitch, 16),
            (CcSignal::HeadYaw, 17),
            (CcSignal::HeadRoll, 18),
            (CcSignal::Thorax, 19),
            (CcSignal::Abdomen, 20),
            (CcSignal::NostrilFlare, 21),
            (CcSignal::MouthOpen, 22),
            (CcSignal::NeckPitch, 23),
            (CcSignal::Speaking, 24),
            (CcSignal::Loudness, 25),
        ];
        for (signal, cc) in want {
            assert_eq!(map.controllers[signal.index()], Some(cc), "{signal:?}");
        }
    }

    #[test]
    fn values_map_as_documented() {
        let map = CcMap::default();
        let mut f = frame(0.5, 0.0);
        assert_eq!(
            map.quantize(CcSignal::HeadPitch, &f),
            64,
            "neutral head is 64"
        );
        assert_eq!(map.quantize(CcSignal::Lung, &f), 64);
        f.head.pitch_deg = 30.0;
        assert_eq!(map.quantize(CcSignal::HeadPitch, &f), 127);
        f.head.pitch_deg = -30.0;
        assert_eq!(map.quantize(CcSignal::HeadPitch, &f), 0);
        f.head.pitch_deg = 15.0; // 0.75 * 128 = 96
        assert_eq!(map.quantize(CcSignal::HeadPitch, &f), 96);
        f.head.pitch_deg = 400.0;
        assert_eq!(map.quantize(CcSignal::HeadPitch, &f), 127, "clamped");
        f.head.pitch_deg = f32::NAN;
        assert_eq!(map.quantize(CcSignal::HeadPitch, &f), 64, "NaN is neutral");
        f.rms_db = -30.0; // half way from -60 to 0
        assert_eq!(map.quantize(CcSignal::Loudness, &f), 64);
        f.rms_db = -120.0;
        assert_eq!(map.quantize(CcSignal::Loudness, &f), 0);
        f.speaking = true;
        assert_eq!(map.quantize(CcSignal::Speaking, &f), 127);
        f.breathing.lung = 1.0;
        assert_eq!(map.quantize(CcSignal::Lung, &f), 127);
    }

    #[test]
    fn the_rest_pose_is_silent_still_and_straight() {
        let map = CcMap::default();
        let rest = ControlFrame::rest(7, 1.5);
        assert_eq!(map.quantize(CcSignal::Loudness, &rest), 0, "silent");
        assert_eq!(map.quantize(CcSignal::Speaking, &rest), 0);
        assert_eq!(map.quantize(CcSignal::HeadPitch, &rest), 64, "straight");
        assert_eq!(map.quantize(CcSignal::HeadYaw, &rest), 64);
        assert_eq!((rest.index, rest.time_s), (7, 1.5));
    }

    #[test]
    fn only_changes_are_sent_and_reset_resends() {
        let mut enc = CcEncoder::new(CcMap::default()).unwrap();
        let first = collect(&mut enc, &frame(0.25, 0.0));
        assert_eq!(first.len(), SIGNAL_COUNT, "first frame sends every signal");
        assert_eq!(
            first[0],
            CcMessage {
                channel: 0,
                controller: 2,
                value: 32
            }
        );
        assert!(
            collect(&mut enc, &frame(0.25, 0.0)).is_empty(),
            "no change, no message"
        );
        // A change below one CC step is no change.
        assert!(collect(&mut enc, &frame(0.252, 0.0)).is_empty());
        let changed = collect(&mut enc, &frame(0.5, 0.0));
        assert_eq!(
            changed,
            vec![CcMessage {
                channel: 0,
                controller: 2,
                value: 64
            }]
        );
        enc.reset();
        assert_eq!(collect(&mut enc, &frame(0.5, 0.0)).len(), SIGNAL_COUNT);
    }

    #[test]
    fn fourteen_bit_pairs_are_msb_then_lsb() {
        let map = CcMap {
            resolution: CcResolution::Bits14,
            channel: 3,
            ..CcMap::default()
        };
        let mut enc = CcEncoder::new(map).unwrap();
        let mut f = frame(0.0, 0.0);
        let msgs = collect(&mut enc, &f);
        assert_eq!(msgs.len(), 2 * SIGNAL_COUNT);
        // Head pitch neutral: 8192 = MSB 64, LSB 0 on CC 16 and 48.
        let head: Vec<_> = msgs.iter().filter(|m| m.controller % 32 == 16).collect();
        assert_eq!(head.len(), 2);
        assert_eq!((head[0].controller, head[0].value), (16, 64));
        assert_eq!((head[1].controller, head[1].value), (48, 0));
        assert!(msgs.iter().all(|m| m.channel == 3));
        // A change smaller than a 7-bit step still leaves in 14-bit mode.
        f.breathing.lung = 0.3;
        let msgs = collect(&mut enc, &f);
        let v = (u16::from(msgs[0].value) << 7) | u16::from(msgs[1].value);
        assert_eq!((msgs[0].controller, msgs[1].controller), (2, 34));
        assert_eq!(v, (0.3_f32 * 16384.0).round() as u16);
        f.breathing.lung = 0.3 + 1.0 / 16384.0 * 1.1;
        let msgs = collect(&mut enc, &f);
        assert_eq!(msgs.len(), 2, "one 14-bit step changes the pair");
        assert_eq!(msgs[0].to_bytes()[0], 0xB3);
    }

    #[test]
    fn bad_maps_are_refused_with_the_reason() {
        let mut map = CcMap {
            channel: 16,
            ..CcMap::default()
        };
        let err = map.validate().unwrap_err();
        assert!(matches!(err, CcMapError::Setting(_)), "{err:?}");
        assert!(
            err.to_string()
                .starts_with("midi_channel 17 is out of range: use 1 to 16"),
            "{err}"
        );
        map.channel = 0;
        map.controllers[CcSignal::HeadYaw.index()] = Some(16);
        assert!(matches!(
            map.validate(),
            Err(CcMapError::Duplicate { controller: 16, .. })
        ));
        map.controllers[CcSignal::HeadYaw.index()] = Some(120);
        let err = map.validate().unwrap_err();
        assert!(
            matches!(
                err,
                CcMapError::Controller {
                    controller: 120,
                    ..
                }
            ),
            "{err:?}"
        );
        assert!(
            err.to_string().contains("use 0..119 for 7-bit CCs")
                && err.to_string().contains("0..31 for 14-bit pairs"),
            "{err}"
        );
        // 14-bit: controller 40 cannot be an MSB, and 2 + 32 = 34 collides with a 7-bit user of 34.
        let mut map = CcMap {
            resolution: CcResolution::Bits14,
            ..CcMap::default()
        };
        map.controllers[CcSignal::Thorax.index()] = Some(40);
        assert!(map.validate().is_err());
        map.controllers[CcSignal::Thorax.index()] = None;
        map.validate().unwrap();
        map.head_range_deg = 0.0;
        assert!(matches!(map.validate(), Err(CcMapError::Setting(_))));
        // set_map keeps the old map on error.
        let mut enc = CcEncoder::new(CcMap::default()).unwrap();
        assert!(enc.set_map(map).is_err());
        assert_eq!(enc.map(), &CcMap::default());
    }

    #[test]
    fn switched_off_signals_are_silent() {
        let mut map = CcMap {
            controllers: [None; SIGNAL_COUNT],
            ..CcMap::default()
        };
        map.controllers[CcSignal::Speaking.index()] = Some(64);
        let mut enc = CcEncoder::new(map).unwrap();
        let mut f = frame(0.7, 10.0);
        f.speaking = true;
        assert_eq!(
            collect(&mut enc, &f),
            vec![CcMessage {
                channel: 0,
                controller: 64,
                value: 127
            }]
        );
    }
}
