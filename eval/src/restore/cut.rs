//! The three ways an editor takes a breath out ([`Cut`]), and where the labels and the times of
//! the uncut recording land afterwards.

/// Attenuation of [`Cut::Attenuated`], dB.
const ATTENUATION_DB: f32 = -30.0;
/// Share of a breath's span [`Cut::Shortened`] removes (from its middle).
const SHORTEN: f64 = 0.4;

/// How a breath is taken out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// Gated to digital silence.
    Gated,
    /// Attenuated by 30 dB.
    Attenuated,
    /// Gated, and the middle 40 % of the span removed (later audio moves earlier).
    Shortened,
}

impl Cut {
    /// The name in the report.
    pub fn name(self) -> &'static str {
        match self {
            Cut::Gated => "gated",
            Cut::Attenuated => "-30 dB",
            Cut::Shortened => "gated, shortened 40 %",
        }
    }

    /// Seconds removed from breath `span` (0 unless shortened).
    fn removed_s(self, (start_s, end_s): (f64, f64)) -> f64 {
        match self {
            Cut::Shortened => SHORTEN * (end_s - start_s),
            _ => 0.0,
        }
    }

    /// `x` with the breaths `which` (indices into `spans`, seconds, in time order) cut.
    pub fn apply(self, x: &[f32], rate_hz: f64, spans: &[(f64, f64)], which: &[usize]) -> Vec<f32> {
        let at = |t: f64| ((t * rate_hz).round().max(0.0) as usize).min(x.len());
        let mut out = x.to_vec();
        for &i in which {
            let (a, b) = (at(spans[i].0), at(spans[i].1));
            let gain = match self {
                Cut::Attenuated => 10f32.powf(ATTENUATION_DB / 20.0),
                _ => 0.0,
            };
            out[a..b].iter_mut().for_each(|v| *v *= gain);
        }
        if self == Cut::Shortened {
            // Remove the middle of each span, latest first so earlier indices stay valid.
            for &i in which.iter().rev() {
                let (s, e) = spans[i];
                let mid = 0.5 * (s + e);
                let half = 0.5 * self.removed_s(spans[i]);
                out.drain(at(mid - half)..at(mid + half));
            }
        }
        out
    }

    /// Where time `t` of the uncut recording lies after cutting the breaths `which`.
    pub fn map_time(self, spans: &[(f64, f64)], which: &[usize], t: f64) -> f64 {
        let mut shift = 0.0;
        for &i in which {
            let (s, e) = spans[i];
            let removed = self.removed_s(spans[i]);
            let (a, b) = (0.5 * (s + e) - 0.5 * removed, 0.5 * (s + e) + 0.5 * removed);
            if t >= b {
                shift += removed;
            } else if t > a {
                shift += t - a;
            }
        }
        t - shift
    }

    /// The spans of the breaths `which` after the cut.
    pub fn moved_spans(self, spans: &[(f64, f64)], which: &[usize]) -> Vec<(f64, f64)> {
        which
            .iter()
            .map(|&i| {
                let (s, e) = spans[i];
                (
                    self.map_time(spans, which, s),
                    self.map_time(spans, which, e),
                )
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gating_silences_attenuating_lowers_and_shortening_moves_later_audio() {
        let rate = 100.0;
        let x: Vec<f32> = (0..1000).map(|i| 1.0 + i as f32).collect();
        let spans = [(1.0, 2.0), (5.0, 6.0)];
        let g = Cut::Gated.apply(&x, rate, &spans, &[1]);
        assert_eq!((g[499], g[500], g[599], g[600]), (500.0, 0.0, 0.0, 601.0));
        assert_eq!(g[150], 151.0, "an uncut breath stays");
        let a = Cut::Attenuated.apply(&x, rate, &spans, &[0]);
        assert!((a[150] / 151.0 - 10f32.powf(-1.5)).abs() < 1e-6);
        let s = Cut::Shortened.apply(&x, rate, &spans, &[0, 1]);
        // 0.4 s removed from each span.
        assert_eq!(s.len(), 1000 - 80);
        assert_eq!(s[100..160], [0.0; 60]);
        // Audio after the first span comes 0.4 s earlier, after the second 0.8 s.
        assert_eq!(s[200 - 40], 201.0);
        assert_eq!(s[700 - 80], 701.0);
        let t = Cut::Shortened.map_time(&spans, &[0, 1], 7.0);
        assert!((t - 6.2).abs() < 1e-9, "{t}");
        let m = Cut::Shortened.moved_spans(&spans, &[0, 1]);
        assert!(
            (m[1].0 - 4.6).abs() < 1e-9 && (m[1].1 - 5.2).abs() < 1e-9,
            "{m:?}"
        );
        assert_eq!(Cut::Gated.moved_spans(&spans, &[1]), vec![(5.0, 6.0)]);
    }
}
