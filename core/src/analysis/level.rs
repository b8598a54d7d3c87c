//! The dBFS scale of the levels the analysis reports, with its floor, and how loud an input's
//! peak must be for its speech to be heard in full ([`quiet_peak_db`]) or to hold any signal
//! at all ([`no_signal_peak_db`]).

use crate::settings::analysis::SILENCE_DB;

/// The floor of the levels, dBFS (silence).
pub const LEVEL_FLOOR_DB: f32 = -120.0;

/// Converts an RMS amplitude to dBFS with a floor of [`LEVEL_FLOOR_DB`].
pub fn amplitude_to_db(rms: f64) -> f32 {
    if rms <= 1e-6 {
        LEVEL_FLOOR_DB
    } else {
        (20.0 * rms.log10()) as f32
    }
}

/// The highest band level a power is taken from, dB (above full scale: a clipped or
/// mis-scaled input never turns into an infinite power).
const MAX_BAND_DB: f32 = 40.0;

/// The power of a band level in dB, the level clamped to [`LEVEL_FLOOR_DB`]..40 dB (NaN stays
/// NaN: callers that meet non-finite levels check them first).
pub(crate) fn band_power(db: f32) -> f64 {
    10f64.powf(f64::from(db.clamp(LEVEL_FLOOR_DB, MAX_BAND_DB)) / 10.0)
}

/// The RMS amplitude of `x` (0 for no samples).
pub fn rms(x: &[f32]) -> f64 {
    (x.iter().map(|&v| v as f64 * v as f64).sum::<f64>() / x.len().max(1) as f64).sqrt()
}

/// An input whose peak lies less than this over the voicing's silence level (`silence_db`:
/// frames under it are never voiced) is quiet, dB. A voice's peak stands 15–21 dB over the
/// median RMS of its voiced frames on the speech of `../shared/data`, so at this margin the
/// median voiced frame lies about 10 dB over the silence level and the softer ones under it.
pub const SPEECH_CREST_DB: f64 = 30.0;

/// The quietest peak at which speech is heard in full, dBFS (at the default silence level).
pub fn quiet_peak_db() -> f64 {
    f64::from(SILENCE_DB.default) + SPEECH_CREST_DB
}

/// A 16-bit file's least step, full scale.
const STEP_16_BIT: f64 = 1.0 / 32768.0;
/// Peaks under this many 16-bit steps are dither: an export of silence with TPDF dither
/// rounds to one step (sox's default, −90 dBFS) or two (−84 dBFS); four leave 6 dB over that
/// and lie 26 dB under the quietest speech the measurements render (a Keele take 30 dB down,
/// peak −52 dBFS). A 24-bit or float file that low may hold a real signal, 78 dB under full
/// scale.
const DITHER_PEAK_STEPS: f64 = 4.0;

/// The peak under which an input holds no signal (silence or dither only), dBFS: −78 dBFS.
/// Normalising such an input would raise its dither to full-scale noise.
pub fn no_signal_peak_db() -> f64 {
    20.0 * (DITHER_PEAK_STEPS * STEP_16_BIT).log10()
}
