//! The built-in breath voice ([`ReferenceVoice`]): a [`LearnedVoice`] fitted to the real,
//! labelled inhalations of several speakers (`cargo xtask train-breath-voice`, written to
//! `assets/models/breath_voice.json`: figures, no audio), used where no breath of the speaker
//! was heard, and **coloured by the recording chain**: the long-term third-octave spectrum of
//! the recording's voiced speech against the fitting recordings' mean ([`speech_ltas_db`]) tells
//! how the microphone, room and EQ tilt the sound, and the breath's shape is tilted the same
//! way ([`ReferenceVoice::coloured`]).
//!
//! It plays at the user's breath level under the speech (`breath_level_db`, default −22 dB,
//! the level issue 15 asks of inserted breaths), not at the fitted one: the fitting speakers'
//! own levels range from −15 to −38 dB (median −28 dB, kept in the file as a documented
//! figure), so no one level fits a speaker nobody heard, and the setting is the user's.
//!
//! The colouring is one number, the least-squares slope of the difference over the bands (dB
//! per third octave, clamped to ±[`MAX_TILT_DB_PER_BAND`]): speech and breath share the
//! channel but not the source, so finer detail of the speech spectrum (its formants, the
//! speaker's voice) says nothing about the breath; a tilt is the sturdy part.
//!
//! [`speech_ltas_db`]: ReferenceVoice::speech_ltas_db

use std::sync::OnceLock;

use super::learned::LearnedVoice;
use super::third_octave::{Bands, BANDS};

/// The shipped reference voice file (embedded).
const SHIPPED: &str = include_str!("../../../assets/models/breath_voice.json");
/// The file format's version.
pub const VERSION: u32 = 1;
/// Largest tilt the colouring applies, dB per third-octave band (set before any measurement:
/// ±7 dB from the middle band to either end).
pub const MAX_TILT_DB_PER_BAND: f64 = 1.0;
/// Fewest bands holding speech for a tilt.
pub const MIN_TILT_BANDS: usize = 5;

/// See the module docs.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReferenceVoice {
    /// [`VERSION`].
    pub version: u32,
    /// The breath: mean shape over the speakers, the breaths' spread around their speaker's
    /// mean, the median level under the speech (its `speech_db` is 0: the stream's own speech
    /// level is used).
    pub voice: LearnedVoice,
    /// Mean over the fitting speakers of their voiced speech's long-term third-octave shape,
    /// dB relative to its mean.
    pub speech_ltas_db: Bands,
    /// Speakers and breaths it was fitted on.
    pub speakers: usize,
    /// Whether [`ReferenceVoice::coloured`] follows the channel (evaluations compare both).
    pub colour_by_channel: bool,
}

impl ReferenceVoice {
    /// The voice in `assets/models/breath_voice.json`.
    pub fn shipped() -> &'static ReferenceVoice {
        static VOICE: OnceLock<ReferenceVoice> = OnceLock::new();
        VOICE.get_or_init(|| {
            let v: ReferenceVoice =
                serde_json::from_str(SHIPPED).expect("the embedded breath voice parses");
            assert_eq!(v.version, VERSION, "the embedded breath voice's version");
            v
        })
    }

    /// The tilt of `speech_ltas_db` (a recording's voiced speech, dB per band, any offset)
    /// against the reference's, dB per band, over the bands that hold speech (at 8 kHz the top
    /// ones lie above the Nyquist frequency); 0 without colouring, before any speech, or with
    /// fewer than [`MIN_TILT_BANDS`] bands.
    pub fn tilt_db_per_band(&self, speech_ltas_db: &Bands) -> f64 {
        let bands = || {
            speech_ltas_db
                .iter()
                .zip(&self.speech_ltas_db)
                .enumerate()
                .filter(|(_, (a, _))| a.is_finite())
                .map(|(k, (a, r))| (k as f64, a - r))
        };
        let n = bands().count();
        if !self.colour_by_channel || n < MIN_TILT_BANDS {
            return 0.0;
        }
        let mid = bands().map(|(x, _)| x).sum::<f64>() / n as f64;
        let (num, den) = bands().fold((0.0, 0.0), |(num, den), (x, d)| {
            (num + (x - mid) * d, den + (x - mid).powi(2))
        });
        (num / den).clamp(-MAX_TILT_DB_PER_BAND, MAX_TILT_DB_PER_BAND)
    }

    /// The breath voice for a recording whose voiced speech has the long-term shape
    /// `speech_ltas_db` and lies at `speech_db` dBFS, `level_re_speech_db` under it: the
    /// reference shape tilted as the speech is (see the module docs). Allocation-free.
    pub fn coloured(
        &self,
        speech_ltas_db: &Bands,
        speech_db: f64,
        level_re_speech_db: f64,
    ) -> LearnedVoice {
        let tilt = self.tilt_db_per_band(speech_ltas_db);
        let mid = (BANDS as f64 - 1.0) / 2.0;
        let mut shape_db = self.voice.shape_db;
        for (k, s) in shape_db.iter_mut().enumerate() {
            *s += tilt * (k as f64 - mid);
        }
        LearnedVoice {
            breaths: 0,
            shape_db,
            speech_db,
            level_re_speech_db,
            ..self.voice
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_voice_parses_and_lies_in_real_ranges() {
        let v = ReferenceVoice::shipped();
        assert!(v.speakers >= 5, "{} speakers", v.speakers);
        assert!(v.voice.breaths >= 20, "{} breaths", v.voice.breaths);
        // Real inhalations: 15–40 dB under the speech, 0.2–0.8 s.
        assert!((-40.0..=-15.0).contains(&v.voice.level_re_speech_db));
        assert!((0.2..=0.8).contains(&v.voice.length_s));
        assert!(v.colour_by_channel);
    }

    #[test]
    fn the_colour_is_the_speech_tilt_against_the_reference_and_nothing_else() {
        let v = ReferenceVoice::shipped();
        let mid = (BANDS as f64 - 1.0) / 2.0;
        // The same speech spectrum: no colour; a 0.5 dB/band tilt plus a bump: the tilt alone.
        assert!(v.tilt_db_per_band(&v.speech_ltas_db).abs() < 1e-12);
        let mut tilted = v.speech_ltas_db;
        for (k, d) in tilted.iter_mut().enumerate() {
            *d += 7.0 + 0.5 * (k as f64 - mid) + if k == 7 { 6.0 } else { 0.0 };
        }
        assert!((v.tilt_db_per_band(&tilted) - 0.5).abs() < 1e-9);
        let c = v.coloured(&tilted, -20.0, -22.0);
        for k in 0..BANDS {
            let want = v.voice.shape_db[k] + 0.5 * (k as f64 - mid);
            assert!((c.shape_db[k] - want).abs() < 1e-9, "band {k}");
        }
        assert_eq!(c.speech_db, -20.0);
        assert_eq!(c.level_re_speech_db, -22.0);
        assert_eq!(c.shape_sd_db, v.voice.shape_sd_db);
        // A huge tilt is clamped; no speech yet, or colouring off: none.
        let steep: Bands = std::array::from_fn(|k| 10.0 * k as f64);
        assert_eq!(v.tilt_db_per_band(&steep), MAX_TILT_DB_PER_BAND);
        assert_eq!(v.tilt_db_per_band(&[f64::NAN; BANDS]), 0.0);
        // At 8 kHz the top bands hold nothing: the tilt of the others.
        let mut low = v.speech_ltas_db;
        for (k, d) in low.iter_mut().enumerate() {
            *d = if k < BANDS - 3 {
                *d + 0.5 * k as f64
            } else {
                f64::NAN
            };
        }
        assert!((v.tilt_db_per_band(&low) - 0.5).abs() < 1e-9);
        let plain = ReferenceVoice {
            colour_by_channel: false,
            ..*v
        };
        assert_eq!(plain.tilt_db_per_band(&tilted), 0.0);
    }
}
