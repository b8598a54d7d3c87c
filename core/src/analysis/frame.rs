//! [`FeatureFrame`], what the analysis gives per frame of the frame clock.

use super::breath_band::BandLevels;

/// The analysis of one frame of the frame clock.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FeatureFrame {
    /// Frame number from the start of the stream (0, 1, 2, ...).
    pub index: u64,
    /// Time of the frame's centre in seconds from the start of the stream (`index / frame_rate_hz`).
    pub time_s: f64,
    /// Fundamental frequency in Hz; 0 when the frame is unvoiced.
    pub f0_hz: f32,
    /// Voiced decision.
    pub voiced: bool,
    /// Voicing confidence, 0..1: the height of the normalised square-difference peak at the chosen
    /// period (1 = perfectly periodic), faded to 0 for frames near digital silence.
    pub voicing: f32,
    /// RMS level of the frame (AC part, window centred on `time_s`) in dBFS; floor −120 dBFS.
    pub rms_db: f32,
    /// f0 in semitones around the speaker's running median f0; 0 when unvoiced.
    pub f0_st: f32,
    /// Level in dB around the speaker's running speech level (`rms_db` − `speech_level_db`).
    pub level_db: f32,
    /// The speaker's running speech level, dBFS: the mean `rms_db` of the voiced frames so far
    /// (this one included) from a prior, forgetting with a half-life in seconds of speech
    /// ([`crate::analysis::SpeakerNormConfig`]). The phrase tracker and the breath placement
    /// measure against it.
    pub speech_level_db: f32,
    /// RMS level of the voice band in dBFS: the pitch window (about 40 ms, centred on `time_s`)
    /// after the 120 Hz high-pass and the decimation (so up to 4–8 kHz). Rumble (traffic, car,
    /// handling noise) hardly reaches it; the phrase tracker decides speech / pause on it.
    pub band_db: f32,
    /// Levels in three bands (100–400 Hz, 0.5–2.5 kHz, 2.5–3.5 kHz) over the pitch window
    /// (about 40 ms centred on `time_s`), dBFS, read from the pitch analysis's spectrum: the
    /// spectral shape the phrase tracker uses to tell a breath from a sibilant, a decaying tail
    /// or room noise (see [`BandLevels`]).
    pub bands: BandLevels,
}
