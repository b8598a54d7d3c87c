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

/// Syllables per second of speech at prosody rate 1 (conversational English is about 4–5).
pub const BASE_SYLLABLE_RATE_HZ: f32 = 4.0;
/// The shortest mapped inspiration, seconds.
pub const MIN_INSPIRATION_S: f32 = 0.15;
/// Breath-sound plateau RMS relative to the speech RMS at a total breathing-sound amplitude of 1
/// (linear; 0.2 = −14 dB). A neutral amplitude of 0.35 gives about −23 dB re speech, the range
/// reported for audible speech inhalations.
pub const BREATH_RMS_RE_SPEECH_AT_FULL: f32 = 0.2;

/// The user-facing breathing controls: the six high-level parameters of Table 1 and the
/// independent ones. Map them with [`BreathingParams::map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BreathingParams {
    /// Balance of chest vs stomach breathing, 0..1 (0 = thorax only, 1 = abdomen only).
    /// Default 0.5.
    pub thorax_vs_abdomen: f32,
    /// Overall lung capacity, percent 10..100. Default 60.
    pub capacity_lung: f32,
    /// Breathing through nose vs mouth, 0..1 (0 = nose only, 1 = mouth only). Default 0.5.
    pub mouth_vs_nose: f32,
    /// How audible the breathing sounds are, 0..1 (0 = silent). Default 0.35.
    pub amplitude_breathing_sound: f32,
    /// How far nostrils and mouth open while breathing in, 0..1. Default 0.5.
    pub opening_inspiration_channels: f32,
    /// How loud the speech is, 0.05..1 (louder speech uses air faster: shorter utterances).
    /// Default 0.5.
    pub speaking_loudness: f32,
    /// Independent: speaking-rate multiplier of the TTS / the syllable rate, 0.5..2. Default 1.
    pub prosody_rate: f32,
    /// Independent: inspiration length of a full (100 %) lung, seconds, 0.2..3. Default 1.0.
    pub inspiration_length_s: f32,
    /// Independent: head pitch at full lungs, degrees, 0..15 (chin up). Default 3.
    pub neck_motion_amplitude_deg: f32,
    /// Independent: the `norm_syllables` factor of Equation 1, syllables, 0.2..5. Default 1.4
    /// (neutral settings then give about 15 syllables, a 3.8 s breath group).
    pub norm_syllables: f32,
    /// Independent: period of the resting (tidal) breath, seconds, 1.5..12. Default 4.
    pub rest_period_s: f32,
    /// Independent: depth of the resting breath, fraction of the lung, 0..0.5. Default 0.12.
    pub rest_depth: f32,
}

impl Default for BreathingParams {
    fn default() -> Self {
        Self {
            thorax_vs_abdomen: 0.5,
            capacity_lung: 60.0,
            mouth_vs_nose: 0.5,
            amplitude_breathing_sound: 0.35,
            opening_inspiration_channels: 0.5,
            speaking_loudness: 0.5,
            prosody_rate: 1.0,
            inspiration_length_s: 1.0,
            neck_motion_amplitude_deg: 3.0,
            norm_syllables: 1.4,
            rest_period_s: 4.0,
            rest_depth: 0.12,
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

fn check(name: &'static str, value: f32, lo: f32, hi: f32) -> Result<(), BreathingError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(BreathingError::OutOfRange {
            name,
            value,
            min: lo,
            max: hi,
        })
    }
}

impl BreathingParams {
    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<(), BreathingError> {
        check("thorax_vs_abdomen", self.thorax_vs_abdomen, 0.0, 1.0)?;
        check("capacity_lung", self.capacity_lung, 10.0, 100.0)?;
        check("mouth_vs_nose", self.mouth_vs_nose, 0.0, 1.0)?;
        check(
            "amplitude_breathing_sound",
            self.amplitude_breathing_sound,
            0.0,
            1.0,
        )?;
        check(
            "opening_inspiration_channels",
            self.opening_inspiration_channels,
            0.0,
            1.0,
        )?;
        check("speaking_loudness", self.speaking_loudness, 0.05, 1.0)?;
        check("prosody_rate", self.prosody_rate, 0.5, 2.0)?;
        check("inspiration_length_s", self.inspiration_length_s, 0.2, 3.0)?;
        check(
            "neck_motion_amplitude_deg",
            self.neck_motion_amplitude_deg,
            0.0,
            15.0,
        )?;
        check("norm_syllables", self.norm_syllables, 0.2, 5.0)?;
        check("rest_period_s", self.rest_period_s, 1.5, 12.0)?;
        check("rest_depth", self.rest_depth, 0.0, 0.5)?;
        Ok(())
    }

    /// Equation 1 (as read in the module docs): the low-level parameters. Call
    /// [`BreathingParams::validate`] first; out-of-range inputs are clamped here.
    pub fn map(&self) -> LowLevelParams {
        let tva = self.thorax_vs_abdomen.clamp(0.0, 1.0);
        let cap = self.capacity_lung.clamp(10.0, 100.0);
        let mvn = self.mouth_vs_nose.clamp(0.0, 1.0);
        let amp = self.amplitude_breathing_sound.clamp(0.0, 1.0);
        let open = self.opening_inspiration_channels.clamp(0.0, 1.0);
        let loud = self.speaking_loudness.clamp(0.05, 1.0);
        let rate = self.prosody_rate.clamp(0.5, 2.0);
        let syllables = (cap / loud).sqrt() * self.norm_syllables.clamp(0.2, 5.0);
        LowLevelParams {
            volume_thorax: (1.0 - tva) * cap / 100.0,
            volume_abdomen: tva * cap / 100.0,
            amplitude_sound_mouth: mvn * amp,
            amplitude_sound_nose: (1.0 - mvn) * amp,
            amplitude_nostril_flare: (1.0 - mvn) * open,
            amplitude_mouth_open: mvn * open,
            length_utterance_syllables: syllables,
            length_utterance_s: syllables / (BASE_SYLLABLE_RATE_HZ * rate),
            length_inspiration_s: (self.inspiration_length_s.clamp(0.2, 3.0) * cap / 100.0)
                .max(MIN_INSPIRATION_S),
            urgency_limit: 2.0 * syllables,
            amplitude_neck_motion_deg: self.neck_motion_amplitude_deg.clamp(0.0, 15.0),
            prosody_rate: rate,
            speaking_loudness: loud,
            rest_period_s: self.rest_period_s.clamp(1.5, 12.0),
            rest_depth: self.rest_depth.clamp(0.0, 0.5),
        }
    }
}

impl Default for LowLevelParams {
    fn default() -> Self {
        BreathingParams::default().map()
    }
}
