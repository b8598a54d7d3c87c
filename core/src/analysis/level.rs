//! The dBFS scale of the levels the analysis reports, with its floor.

/// Converts an RMS amplitude to dBFS with a floor of −120 dBFS.
pub fn amplitude_to_db(rms: f64) -> f32 {
    if rms <= 1e-6 {
        -120.0
    } else {
        (20.0 * rms.log10()) as f32
    }
}
