//! The dBFS scale of the levels the analysis reports, with its floor.

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
