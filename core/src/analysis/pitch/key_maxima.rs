//! Key maxima of an NSDF curve: the highest point of each positive lobe after the first
//! negative-going zero crossing, refined by a parabola, within the f0 range.

/// One period candidate: a key maximum of the NSDF.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PitchEstimate {
    /// Frequency in Hz (0 when there is no candidate).
    pub f0_hz: f32,
    /// Interpolated NSDF peak height, 0..1 (periodicity).
    pub clarity: f32,
}

/// Key maxima of one NSDF curve (at least `last + 2` lags long) up to lag `last`, shortest lag
/// first, into `out` (count in `count`); a maximum whose refined lag lies outside `lag_range`
/// (the f0 range) is no candidate, and the returned value is the highest clarity among those
/// above the range (shorter than its shortest period; 0 if none); when `out` is full the
/// weakest kept lobe gives way to a stronger one.
pub(super) fn key_maxima(
    n: &[f32],
    rate_hz: f64,
    lag_range: (f64, f64),
    last: usize,
    out: &mut [PitchEstimate],
    count: &mut usize,
) -> f32 {
    let mut above_range = 0.0f32;
    // Every lag read below is at most `last + 1`: with the curve cut there, the reads need no
    // bounds checks.
    let n = &n[..last + 2];
    // Skip the lobe around lag 0: start after the first negative-going zero crossing.
    let mut tau = 1;
    while tau <= last && n[tau] > 0.0 {
        tau += 1;
    }
    while tau <= last {
        // Skip the negative region.
        while tau <= last && n[tau] <= 0.0 {
            tau += 1;
        }
        // Highest point of this positive lobe.
        let mut peak_tau = 0;
        let mut peak = f32::MIN;
        while tau <= last && n[tau] > 0.0 {
            if n[tau] > peak {
                peak = n[tau];
                peak_tau = tau;
            }
            tau += 1;
        }
        // Lobes before the shortest period searched still tell of a voice above the range.
        if peak_tau == 0 {
            continue;
        }
        // A lobe cut off by the end of the search range is only a candidate if its highest
        // point is a true local maximum.
        if n[peak_tau + 1] > n[peak_tau] {
            continue;
        }
        let (a, b, c) = (n[peak_tau - 1], n[peak_tau], n[peak_tau + 1]);
        let denom = a - 2.0 * b + c;
        let (delta, height) = if denom < 0.0 {
            let d = (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
            (d, b - 0.25 * (a - c) * d)
        } else {
            (0.0, b)
        };
        let lag = peak_tau as f64 + delta as f64;
        let clarity = height.clamp(0.0, 1.0);
        if lag < lag_range.0 {
            above_range = above_range.max(clarity);
            continue;
        }
        if lag > lag_range.1 {
            continue;
        }
        let candidate = PitchEstimate {
            f0_hz: (rate_hz / lag) as f32,
            clarity,
        };
        if *count == out.len() {
            // Full (very low f0 with a bright spectrum has many lobes): drop the weakest
            // kept lobe if this one is stronger, keeping the lag order.
            let (weakest, w) = out.iter().enumerate().fold((0, f32::MAX), |m, (i, c)| {
                if c.clarity < m.1 {
                    (i, c.clarity)
                } else {
                    m
                }
            });
            if clarity <= w {
                continue;
            }
            out.copy_within(weakest + 1.., weakest);
            *count -= 1;
        }
        out[*count] = candidate;
        *count += 1;
    }
    above_range
}
