//! The voicing cues: [`VoicingEvidence`] (what one frame offers the decision, all computed
//! causally from the audio alone) and its bounded feature vector in [`VOICING_FEATURES`] order,
//! with the level gate the decision applies.

/// Number of cues the model weighs.
pub const N_VOICING_FEATURES: usize = 19;
/// Index of `level_vs_gate` among the cues: a frame under the level gate is never voiced.
pub const LEVEL_VS_GATE: usize = 14;
/// The level gate: frames more than this many dB under the running speech level are never
/// voiced, nor frames whose band level (what the NSDF hears) lies under the band's noise floor
/// (plus [`NOISE_MARGIN_DB`]), unless their level is within [`NOISE_HEADROOM_DB`] of the
/// speech level (a stream without pauses has its "floor" at the voice itself). The margin was
/// 6 dB until stop 28, though the model has level cues of its own; at 0 dB the model judges the
/// frames between, and held out, Keele's white noise at 0 dB went from 17.67 % to 12.34 % FFE
/// with that change alone (docs/measurements.md, section 1).
const SPEECH_GATE_DB: f32 = 30.0;
const NOISE_MARGIN_DB: f32 = 0.0;
const NOISE_HEADROOM_DB: f32 = 2.0;

/// The cues, in the order of a feature vector and of the model file's `feature` lines.
pub const VOICING_FEATURES: [&str; N_VOICING_FEATURES] = [
    "long_clarity",
    "chosen_clarity",
    "short_clarity",
    "short_agrees",
    "edge_newest",
    "edge_oldest",
    "best_clarity",
    "log_unclarity",
    "level_vs_speech",
    "level_vs_floor",
    "low_band",
    "period_jump",
    "previous_clarity",
    "log_f0",
    "level_vs_gate",
    "speech_vs_floor",
    "unclarity_by_snr",
    "denoised_clarity",
    "pitch_track",
];
/// The longest pitch-track continuity the `pitch_track` cue counts, s (it reads 0–1 of this).
pub(crate) const TRACK_CAP_S: f32 = 0.1;

/// The jump from the previous frame's chosen period to this one's, octaves, at most 1 (1 when
/// either frame has none): the `period_jump` cue, and what breaks the pitch track.
pub(crate) fn period_jump_octaves(f0_hz: f32, previous_f0_hz: f32) -> f32 {
    if f0_hz > 0.0 && previous_f0_hz > 0.0 {
        (f0_hz / previous_f0_hz).log2().abs().min(1.0)
    } else {
        1.0
    }
}

/// One frame's cues as a vector, in [`VOICING_FEATURES`] order.
pub type VoicingFeatures = [f32; N_VOICING_FEATURES];

/// What one frame offers the voicing decision, before the transforms of
/// [`VoicingEvidence::features`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct VoicingEvidence {
    /// The long window's highest key maximum, 0–1.
    pub long_clarity: f32,
    /// The chosen period's clarity, 0–1.
    pub chosen_clarity: f32,
    /// The centred short window's pick's clarity (0 when it did not run).
    pub short_clarity: f32,
    /// Whether that pick is the chosen period.
    pub short_agrees: bool,
    /// Clarity of the chosen period on a short window at the newest / oldest end of the long
    /// one (0 when that window's own choice differs or the period is beyond its reach).
    pub edge_newest: f32,
    pub edge_oldest: f32,
    /// Frame level, dBFS.
    pub rms_db: f32,
    /// The running level of clearly periodic frames, dBFS.
    pub speech_db: f32,
    /// The running noise floor, dBFS (+∞ before it is known).
    pub floor_db: f32,
    /// The pitch window's level as the NSDF hears it (mean removed, behind the low-pass), dB.
    pub band_db: f32,
    /// The running noise floor of that band level, dB (+∞ before it is known).
    pub band_floor_db: f32,
    /// The long-window clarity the background alone gives (running mean at the band floor).
    pub noise_clarity: f32,
    /// Share of the voice band's energy in its low band (80 Hz–1 kHz of 80 Hz–4 kHz), behind
    /// the low-pass.
    pub low_band: f32,
    /// The chosen f0 of this and of the previous frame, Hz (0 = none).
    pub f0_hz: f32,
    pub previous_f0_hz: f32,
    /// The previous frame's long-window clarity.
    pub previous_clarity: f32,
    /// How long the chosen period has moved smoothly from frame to frame up to this one, s
    /// (0 when it jumped; at most [`TRACK_CAP_S`]).
    pub track_s: f32,
}

impl VoicingEvidence {
    /// The model's inputs: the cues, bounded, in [`VOICING_FEATURES`] order.
    pub(crate) fn features(&self) -> VoicingFeatures {
        let best = self
            .long_clarity
            .max(if self.short_agrees {
                self.short_clarity
            } else {
                0.0
            })
            .max(self.edge_newest)
            .max(self.edge_oldest)
            .clamp(0.0, 1.0);
        // While no background has been heard, the floor cues read 0 (the cautious reading, as
        // deep in noise), and nothing is taken out of the clarity.
        let level_vs_floor = if self.band_floor_db.is_finite() {
            ((self.band_db - self.band_floor_db) / 10.0).clamp(0.0, 6.0)
        } else {
            0.0
        };
        let period_jump = period_jump_octaves(self.f0_hz, self.previous_f0_hz);
        let log_f0 = if self.f0_hz > 0.0 {
            (self.f0_hz / 150.0).log2().clamp(-2.0, 2.0)
        } else {
            0.0
        };
        // The gate: at most SPEECH_GATE_DB under the speech level, and either at or above the
        // noise floor in the pitch window's band (what the NSDF hears: a rumble under the
        // high-pass does not hide the voice) or near the speech level itself.
        let over_speech_gate = (self.rms_db - (self.speech_db - SPEECH_GATE_DB)) / 10.0;
        let over_noise_gate = if self.band_floor_db.is_finite() {
            ((self.band_db - (self.band_floor_db + NOISE_MARGIN_DB)) / 10.0)
                .max((self.rms_db - (self.speech_db - NOISE_HEADROOM_DB)) / 10.0)
        } else {
            f32::INFINITY
        };
        // How far the running speech level stands above the noise floor, 0–6 (tens of dB; 0
        // while the floor is unknown): lets the model trust a middling clarity in a clean
        // recording that it must doubt in noise, and its product with the unclarity lets the
        // clarity it asks for move with the noise.
        let speech_vs_floor = if self.floor_db.is_finite() {
            ((self.speech_db - self.floor_db) / 10.0).clamp(0.0, 6.0)
        } else {
            0.0
        };
        let log_unclarity = -(1.001 - best).ln();
        // The share of the window's band energy the background is taken to make up, and the
        // long-window clarity with the background's part taken out: noise adds energy to the
        // NSDF's norm, not to its periodic peak, so a voice in steady noise reads less clear
        // by about that share. The division at most doubles the clarity left, so a noise
        // frame's chance peak at the floor does not read as a clear voice.
        let noise_share = if self.band_floor_db.is_finite() {
            10f32.powf(-(self.band_db - self.band_floor_db).max(0.0) / 10.0)
        } else {
            0.0
        };
        let denoised_clarity = ((self.long_clarity - noise_share * self.noise_clarity)
            / (1.0 - noise_share).max(0.5))
        .clamp(0.0, 1.0);
        [
            self.long_clarity,
            self.chosen_clarity,
            self.short_clarity,
            f32::from(u8::from(self.short_agrees)),
            self.edge_newest,
            self.edge_oldest,
            best,
            log_unclarity,
            ((self.rms_db - self.speech_db) / 10.0).clamp(-4.0, 2.0),
            level_vs_floor,
            self.low_band,
            period_jump,
            self.previous_clarity,
            log_f0,
            over_speech_gate.min(over_noise_gate).clamp(-3.0, 3.0),
            speech_vs_floor,
            log_unclarity * speech_vs_floor / 6.0,
            denoised_clarity,
            (self.track_s / TRACK_CAP_S).clamp(0.0, 1.0),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Evidence of a frame at `band_over_floor_db` over the band's noise floor, whose long
    /// window reads `long_clarity` where the background alone reads `noise_clarity`.
    fn in_noise(long_clarity: f32, band_over_floor_db: f32, noise_clarity: f32) -> VoicingFeatures {
        VoicingEvidence {
            long_clarity,
            chosen_clarity: long_clarity,
            rms_db: -20.0,
            speech_db: -20.0,
            floor_db: -20.0 - band_over_floor_db,
            band_db: -20.0,
            band_floor_db: -20.0 - band_over_floor_db,
            noise_clarity,
            ..Default::default()
        }
        .features()
    }

    #[test]
    fn the_background_is_taken_out_of_the_clarity() {
        let denoised = VOICING_FEATURES
            .iter()
            .position(|&n| n == "denoised_clarity")
            .unwrap();
        // A perfectly periodic voice (clarity 1) mixed with as much noise (its own clarity
        // 0.2): the NSDF peak of the mix is the power-weighted mean of the two, 0.6, and the
        // band level is 3 dB over the floor. Taking the background out finds the voice's 1.
        let half = 10.0 * 2f32.log10();
        let f = in_noise(0.5 * 1.0 + 0.5 * 0.2, half, 0.2);
        assert!((f[denoised] - 1.0).abs() < 1e-3, "{}", f[denoised]);
        // A voice of clarity 0.8 with a third of the band's power noise of clarity 0.3.
        let third = 10.0 * 3f32.log10();
        let f = in_noise(2.0 / 3.0 * 0.8 + 1.0 / 3.0 * 0.3, third, 0.3);
        assert!((f[denoised] - 0.8).abs() < 1e-3, "{}", f[denoised]);
        // The background alone (at the floor, as clear as the background) has no voice left,
        // and far over the floor nothing is taken out.
        let f = in_noise(0.3, 0.0, 0.3);
        assert!(f[denoised].abs() < 1e-3, "{}", f[denoised]);
        let f = in_noise(0.7, 60.0, 0.3);
        assert!((f[denoised] - 0.7).abs() < 1e-3, "{}", f[denoised]);
    }
}
