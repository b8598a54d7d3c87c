//! The types every part of the engine shares: one [`ControlFrame`] per frame of the frame clock,
//! the breathing phase and state, the head angles, and inserted-breath events.
//!
//! These are the data of the DESIGN.md contracts (controls CSV, breaths CSV, MIDI CC, OSC, BVH);
//! the encoders in [`crate::encode`] and the doors read them, the models write them.

/// The breathing phase of the speech-breathing cycle (Bernardet et al.).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub enum Phase {
    /// Neither inhaling for speech nor speaking.
    #[default]
    Rest,
    /// Breathing in before an utterance.
    Inspiration,
    /// Breathing out while speaking.
    Expiration,
}

impl Phase {
    /// The contract's name: `rest`, `inspiration` or `expiration`.
    pub fn as_str(self) -> &'static str {
        match self {
            Phase::Rest => "rest",
            Phase::Inspiration => "inspiration",
            Phase::Expiration => "expiration",
        }
    }
}

/// The body's breathing state at one frame. Every 0..1 field is a fraction of its maximum.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BreathingState {
    /// The current phase.
    pub phase: Phase,
    /// Lung volume, 0..1 of the lung capacity.
    pub lung: f32,
    /// Thorax expansion, 0..1.
    pub thorax: f32,
    /// Abdomen expansion, 0..1.
    pub abdomen: f32,
    /// Neck pitch from breathing, degrees (positive = chin up).
    pub neck_pitch_deg: f32,
    /// Nostril flare, 0..1.
    pub nostril_flare: f32,
    /// Mouth opening from breathing, 0..1.
    pub mouth_open: f32,
}

/// Head orientation in degrees, right-handed, per DESIGN.md: pitch positive = chin up, yaw
/// positive = looking to the character's left, roll positive = head tilted to its left.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HeadAngles {
    /// Pitch (nod), degrees, positive = chin up.
    pub pitch_deg: f32,
    /// Yaw (turn), degrees, positive = looking to the character's left.
    pub yaw_deg: f32,
    /// Roll (tilt), degrees, positive = head tilted to the character's left.
    pub roll_deg: f32,
}

impl HeadAngles {
    /// The angles a share `toward` (0..1) of the way from these to `to`: exactly `to` at 1
    /// (the one interpolation of head angles: a frame between two head steps, a frame easing to
    /// the rest pose, a BVH instant between two frames).
    pub fn toward(&self, to: &HeadAngles, toward: f32) -> HeadAngles {
        let keep = 1.0 - toward.clamp(0.0, 1.0);
        HeadAngles {
            pitch_deg: lerp_toward(self.pitch_deg, to.pitch_deg, keep),
            yaw_deg: lerp_toward(self.yaw_deg, to.yaw_deg, keep),
            roll_deg: lerp_toward(self.roll_deg, to.roll_deg, keep),
        }
    }
}

/// `to` with a share `keep` (0..1) of the way back to `from`: `to` exactly when `keep` is 0.
fn lerp_toward(from: f32, to: f32, keep: f32) -> f32 {
    to + (from - to) * keep
}

/// Everything Pneuma computed for one frame of the frame clock.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ControlFrame {
    /// Frame number from the start of the stream.
    pub index: u64,
    /// Time of the frame's centre in seconds from the start of the stream (input time: the
    /// lookahead delay of a plugin is not included).
    pub time_s: f64,
    /// Fundamental frequency in Hz; 0 when unvoiced.
    pub f0_hz: f32,
    /// Voiced decision.
    pub voiced: bool,
    /// RMS level in dBFS (floor −120).
    pub rms_db: f32,
    /// Level in dB around the speaker's running speech level.
    pub level_db: f32,
    /// Inside a phrase of speech: the phrase tracker's phrase, judged speech by the speech
    /// decision (0 in a pause, and in music, singing or noise).
    pub speaking: bool,
    /// Breathing state.
    pub breathing: BreathingState,
    /// Head orientation.
    pub head: HeadAngles,
}

impl ControlFrame {
    /// The rest pose, frame `index` at `time_s`: silence (levels at the floor,
    /// [`crate::analysis::LEVEL_FLOOR_DB`]), not speaking, head straight, breathing at rest;
    /// what the outputs show when the controls stop following a voice (a plugin bypassed, a
    /// stream's end). The default frame is not it: its 0 dBFS is full scale (loudness CC 127).
    pub fn rest(index: u64, time_s: f64) -> Self {
        Self {
            index,
            time_s,
            rms_db: crate::analysis::LEVEL_FLOOR_DB,
            level_db: crate::analysis::LEVEL_FLOOR_DB,
            ..Self::default()
        }
    }

    /// A frame on the way from this one to the rest pose, frame `index` at `time_s`, a share
    /// `toward` (0..1) of the way there: the body (head angles and the breathing's continuous
    /// values) moves that share of the way, while the voice is the rest's at once (silent, not
    /// speaking: nothing is heard any more); the breathing's phase is the rest's. At 1 it is
    /// [`ControlFrame::rest`].
    pub fn toward_rest(&self, index: u64, time_s: f64, toward: f32) -> Self {
        self.body_toward(&Self::rest(index, time_s), toward)
    }

    /// `to` with its body (head angles and the breathing's continuous values) a share `toward`
    /// (0..1) of the way from this frame's to its own: 0 gives this frame's body, 1 `to`
    /// itself. Everything else (index, time, voice, phase) is `to`'s.
    pub fn body_toward(&self, to: &ControlFrame, toward: f32) -> Self {
        let keep = 1.0 - toward.clamp(0.0, 1.0);
        let rest = *to;
        let mix = |from: f32, to: f32| lerp_toward(from, to, keep);
        let (b, r) = (&self.breathing, &rest.breathing);
        Self {
            breathing: BreathingState {
                lung: mix(b.lung, r.lung),
                thorax: mix(b.thorax, r.thorax),
                abdomen: mix(b.abdomen, r.abdomen),
                neck_pitch_deg: mix(b.neck_pitch_deg, r.neck_pitch_deg),
                nostril_flare: mix(b.nostril_flare, r.nostril_flare),
                mouth_open: mix(b.mouth_open, r.mouth_open),
                ..*r
            },
            head: self.head.toward(&rest.head, toward),
            ..rest
        }
    }
}

/// Which breath sound was inserted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BreathKind {
    /// Procedural inhalation through the mouth.
    Mouth,
    /// Procedural inhalation through the nose.
    Nose,
    /// A mix of mouth and nose (MouthVsNose between the extremes).
    Mixed,
    /// A user breath sample.
    Sample,
}

impl BreathKind {
    /// The name written to `breaths.csv`.
    pub fn as_str(self) -> &'static str {
        match self {
            BreathKind::Mouth => "mouth",
            BreathKind::Nose => "nose",
            BreathKind::Mixed => "mixed",
            BreathKind::Sample => "sample",
        }
    }
}

/// One inserted breath (a row of `breaths.csv`: `start_s,end_s,kind,peak_db`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BreathEvent {
    /// Start of the breath sound, seconds from the start of the stream.
    pub start_s: f64,
    /// End of the breath sound, seconds.
    pub end_s: f64,
    /// The sound used.
    pub kind: BreathKind,
    /// Peak sample level of the inserted sound, dBFS.
    pub peak_db: f32,
}
