//! Breathing parameters: the six high-level controls of Bernardet et al.'s Table 1, the
//! independent ones, and their mapping to the low-level parameters by Equation 1.
//!
//! # How Equation 1 is read here (the paper's text is garbled in places)
//! - `ThoraxVsAbdomen` 0..1: 0 = all chest (thorax) breathing, 1 = all stomach breathing, exactly
//!   as the equation writes it (`volume_abdomen = ThoraxVsAbdomen · capacity_lung / 100`).
//! - `MouthVsNose` 0..1: **0 = nose, 1 = mouth**, the reading of the name (the share of the
//!   mouth). The paper's equation pairs `MouthVsNose` with the nose
//!   (`amplitude_sound_nose = MouthVsNose · amplitude_breathing_sound`); we swap it so that one
//!   convention holds everywhere in Pneuma (also [`super::BreathVoice::start`]):
//!   `amplitude_sound_mouth = MouthVsNose · a`, `amplitude_sound_nose = (1 − MouthVsNose) · a`,
//!   and likewise mouth opening and nostril flare.
//! - `capacity_lung` is in percent (10..100) of a large adult lung; `/100` makes the thorax and
//!   abdomen volumes fractions 0..1.
//! - `length_utterance = sqrt(capacity_lung / speaking_loudness) · norm_syllables` is a number
//!   of **syllables** (the chunker steps through syllables to reach it). With the prosody rate it
//!   also gives seconds: `length_utterance_s = syllables / (BASE_SYLLABLE_RATE_HZ · prosody_rate)`.
//! - `length_inspiration = capacity_lung / 100` is read as a *scale*: the independent
//!   `inspiration_length_s` is the inspiration of a full (100 %) lung, and
//!   `length_inspiration_s = inspiration_length_s · capacity_lung / 100` (a smaller lung fills
//!   faster), floored at [`MIN_INSPIRATION_S`]. This keeps both the equation's proportionality
//!   and the text's statement that inspiration length is an independent parameter.
//! - `urgency_limit = 2 · length_utterance` is in **characters**: the flow chart compares the
//!   positions of pause markers "in number of characters" with it.

use super::BreathingError;
use crate::settings::breathing::{
    BREATH_SOUND, CAPACITY_LUNG, INSPIRATION_LENGTH_S, MOUTH_VS_NOSE, NECK_AMPLITUDE_DEG,
    NORM_SYLLABLES, OPENING, PROSODY_RATE, REST_DEPTH, REST_PERIOD_S, SPEAKING_LOUDNESS,
    THORAX_VS_ABDOMEN,
};
use crate::settings::setting::{check_fields, field, Field};

/// Syllables per second of speech at prosody rate 1 (conversational English is about 4–5).
pub const BASE_SYLLABLE_RATE_HZ: f32 = 4.0;
/// The shortest mapped inspiration, seconds.
pub const MIN_INSPIRATION_S: f32 = 0.15;
/// Breath-sound plateau RMS relative to the speech RMS at a total breathing-sound amplitude of 1
/// (linear; 0.2 = −14 dB). A neutral amplitude of 0.35 gives about −23 dB re speech, the range
/// reported for audible speech inhalations.
pub const BREATH_RMS_RE_SPEECH_AT_FULL: f32 = 0.2;

/// The user-facing breathing controls: the six high-level parameters of Table 1 and the
/// independent ones. Map them with [`BreathingParams::map`]. Each field's setting (unit, range,
/// default, why) is in [`crate::settings::breathing`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BreathingParams {
    /// Balance of chest vs stomach breathing (0 = thorax only, 1 = abdomen only)
    /// ([`THORAX_VS_ABDOMEN`]).
    pub thorax_vs_abdomen: f32,
    /// Overall lung capacity, percent ([`CAPACITY_LUNG`]).
    pub capacity_lung: f32,
    /// Breathing through nose vs mouth (0 = nose only, 1 = mouth only) ([`MOUTH_VS_NOSE`]).
    pub mouth_vs_nose: f32,
    /// How audible the breathing sounds are (0 = silent) ([`BREATH_SOUND`]).
    pub amplitude_breathing_sound: f32,
    /// How far nostrils and mouth open while breathing in ([`OPENING`]).
    pub opening_inspiration_channels: f32,
    /// How loud the speech is (louder speech uses air faster: shorter utterances)
    /// ([`SPEAKING_LOUDNESS`]).
    pub speaking_loudness: f32,
    /// Independent: speaking-rate multiplier of the TTS / the syllable rate
    /// ([`PROSODY_RATE`]).
    pub prosody_rate: f32,
    /// Independent: inspiration length of a full (100 %) lung, seconds
    /// ([`INSPIRATION_LENGTH_S`]).
    pub inspiration_length_s: f32,
    /// Independent: head pitch at full lungs, degrees (chin up) ([`NECK_AMPLITUDE_DEG`]).
    pub neck_motion_amplitude_deg: f32,
    /// Independent: the `norm_syllables` factor of Equation 1, syllables ([`NORM_SYLLABLES`];
    /// neutral settings then give about 15 syllables, a 3.8 s breath group).
    pub norm_syllables: f32,
    /// Independent: period of the resting (tidal) breath, seconds ([`REST_PERIOD_S`]).
    pub rest_period_s: f32,
    /// Independent: depth of the resting breath, fraction of the lung ([`REST_DEPTH`]).
    pub rest_depth: f32,
}

/// The settings of [`BreathingParams`] and the fields holding them.
static FIELDS: [Field<BreathingParams>; 12] = [
    field!(THORAX_VS_ABDOMEN, thorax_vs_abdomen),
    field!(CAPACITY_LUNG, capacity_lung),
    field!(MOUTH_VS_NOSE, mouth_vs_nose),
    field!(BREATH_SOUND, amplitude_breathing_sound),
    field!(OPENING, opening_inspiration_channels),
    field!(SPEAKING_LOUDNESS, speaking_loudness),
    field!(PROSODY_RATE, prosody_rate),
    field!(INSPIRATION_LENGTH_S, inspiration_length_s),
    field!(NECK_AMPLITUDE_DEG, neck_motion_amplitude_deg),
    field!(NORM_SYLLABLES, norm_syllables),
    field!(REST_PERIOD_S, rest_period_s),
    field!(REST_DEPTH, rest_depth),
];

impl Default for BreathingParams {
    /// The table's defaults.
    fn default() -> Self {
        Self {
            thorax_vs_abdomen: THORAX_VS_ABDOMEN.default,
            capacity_lung: CAPACITY_LUNG.default,
            mouth_vs_nose: MOUTH_VS_NOSE.default,
            amplitude_breathing_sound: BREATH_SOUND.default,
            opening_inspiration_channels: OPENING.default,
            speaking_loudness: SPEAKING_LOUDNESS.default,
            prosody_rate: PROSODY_RATE.default,
            inspiration_length_s: INSPIRATION_LENGTH_S.default,
            neck_motion_amplitude_deg: NECK_AMPLITUDE_DEG.default,
            norm_syllables: NORM_SYLLABLES.default,
            rest_period_s: REST_PERIOD_S.default,
            rest_depth: REST_DEPTH.default,
        }
    }
}

/// The low-level parameters that drive the cycle, the breath sound and the chunker
/// (the top half of Table 1). Produced by [`BreathingParams::map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LowLevelParams {
    /// Maximum thorax expansion, 0..1 (at full lungs).
    pub volume_thorax: f32,
    /// Maximum abdomen expansion, 0..1 (at full lungs).
    pub volume_abdomen: f32,
    /// Audibility of the mouth inhalation, 0..1.
    pub amplitude_sound_mouth: f32,
    /// Audibility of the nose inhalation, 0..1.
    pub amplitude_sound_nose: f32,
    /// Maximum nostril flare during an inspiration, 0..1.
    pub amplitude_nostril_flare: f32,
    /// Maximum mouth opening during an inspiration, 0..1.
    pub amplitude_mouth_open: f32,
    /// Utterance length one full breath sustains, syllables.
    pub length_utterance_syllables: f32,
    /// Utterance length one full breath sustains, seconds (syllables at the prosody rate).
    pub length_utterance_s: f32,
    /// Length of an inspiration, seconds.
    pub length_inspiration_s: f32,
    /// How far (characters) the chunker may move a breath from its syllable target to reach a
    /// pause marker.
    pub urgency_limit: f32,
    /// Head pitch at full lungs, degrees.
    pub amplitude_neck_motion_deg: f32,
    /// Speaking-rate multiplier (TTS), 0.5..2.
    pub prosody_rate: f32,
    /// Speech loudness, 0.05..1 (TTS amplitude).
    pub speaking_loudness: f32,
    /// Period of the resting breath, seconds.
    pub rest_period_s: f32,
    /// Depth of the resting breath, fraction of the lung.
    pub rest_depth: f32,
}

impl LowLevelParams {
    /// The mouth share of the breath sound, 0 (nose) .. 1 (mouth), for
    /// [`super::BreathVoice::start`]; 0.5 when both amplitudes are 0.
    pub fn mouth_share(&self) -> f32 {
        let total = self.amplitude_sound_mouth + self.amplitude_sound_nose;
        if total <= 0.0 {
            0.5
        } else {
            self.amplitude_sound_mouth / total
        }
    }

    /// Plateau RMS of the breath sound relative to the speech RMS (linear): the total breathing
    /// sound amplitude times [`BREATH_RMS_RE_SPEECH_AT_FULL`]. Multiply by the speech RMS to get
    /// the `gain` of [`super::BreathVoice::start`].
    pub fn breath_rms_re_speech(&self) -> f32 {
        (self.amplitude_sound_mouth + self.amplitude_sound_nose) * BREATH_RMS_RE_SPEECH_AT_FULL
    }
}

impl BreathingParams {
    /// The settings of this struct and the fields holding them.
    pub fn fields() -> &'static [Field<BreathingParams>] {
        &FIELDS
    }

    /// Checks every field against its range.
    pub fn validate(&self) -> Result<(), BreathingError> {
        Ok(check_fields(self, &FIELDS)?)
    }

    /// Equation 1 (as read in the module docs): the low-level parameters. Call
    /// [`BreathingParams::validate`] first; out-of-range inputs are clamped here.
    pub fn map(&self) -> LowLevelParams {
        let tva = THORAX_VS_ABDOMEN.clamp(self.thorax_vs_abdomen);
        let cap = CAPACITY_LUNG.clamp(self.capacity_lung);
        let mvn = MOUTH_VS_NOSE.clamp(self.mouth_vs_nose);
        let amp = BREATH_SOUND.clamp(self.amplitude_breathing_sound);
        let open = OPENING.clamp(self.opening_inspiration_channels);
        let loud = SPEAKING_LOUDNESS.clamp(self.speaking_loudness);
        let rate = PROSODY_RATE.clamp(self.prosody_rate);
        let syllables = (cap / loud).sqrt() * NORM_SYLLABLES.clamp(self.norm_syllables);
        LowLevelParams {
            volume_thorax: (1.0 - tva) * cap / 100.0,
            volume_abdomen: tva * cap / 100.0,
            amplitude_sound_mouth: mvn * amp,
            amplitude_sound_nose: (1.0 - mvn) * amp,
            amplitude_nostril_flare: (1.0 - mvn) * open,
            amplitude_mouth_open: mvn * open,
            length_utterance_syllables: syllables,
            length_utterance_s: syllables / (BASE_SYLLABLE_RATE_HZ * rate),
            length_inspiration_s: (INSPIRATION_LENGTH_S.clamp(self.inspiration_length_s) * cap
                / 100.0)
                .max(MIN_INSPIRATION_S),
            urgency_limit: 2.0 * syllables,
            amplitude_neck_motion_deg: NECK_AMPLITUDE_DEG.clamp(self.neck_motion_amplitude_deg),
            prosody_rate: rate,
            speaking_loudness: loud,
            rest_period_s: REST_PERIOD_S.clamp(self.rest_period_s),
            rest_depth: REST_DEPTH.clamp(self.rest_depth),
        }
    }
}

impl Default for LowLevelParams {
    fn default() -> Self {
        BreathingParams::default().map()
    }
}
