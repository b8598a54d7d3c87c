//! Integer decimation with a Kaiser-windowed sinc low-pass, so the pitch analysis runs at a rate
//! between 8 and 16 kHz whatever the host rate. The filter is linear-phase; its group delay is
//! reported so frame times can be compensated exactly.

use super::biquad::polynomial_power;

/// Taps per output sample (filter length is `TAPS_PER_PHASE * factor + 1`).
const TAPS_PER_PHASE: usize = 16;
/// Cut-off (−6 dB) as a fraction of the output rate.
const CUTOFF_OF_OUTPUT_RATE: f64 = 0.4;
/// Kaiser β for about 60 dB stop-band attenuation.
const KAISER_BETA: f64 = 5.65;
/// Internal analysis rates lie in [`TARGET_MIN_RATE_HZ`], 2 × that).
pub(crate) const TARGET_MIN_RATE_HZ: f64 = 8_000.0;

/// The decimation factor for a host rate: the largest integer keeping the rate ≥ 8 kHz.
pub(crate) fn factor_for(sample_rate_hz: f64) -> usize {
    ((sample_rate_hz / TARGET_MIN_RATE_HZ).floor() as usize).max(1)
}

/// Input samples the history holds beyond the filter's length: the newest `taps.len()`
/// samples are one contiguous slice, and once in this many samples the filter's worth is moved
/// back to the start.
const HISTORY_SPAN: usize = 2048;

/// Streaming decimator by an integer factor. Samples go in as whole runs ([`Decimator::feed`],
/// mapped on their way into the history in one pass that vectorises); the outputs they complete
/// are then taken one by one ([`Decimator::output`]), each with the `factor` input samples that
/// completed it.
#[derive(Debug, Clone)]
pub(crate) struct Decimator {
    factor: usize,
    taps: Vec<f32>,
    /// Linear history; `history[end - taps.len()..end]` are the newest samples, oldest first.
    history: Vec<f32>,
    end: usize,
    /// Where the next output's inputs end in `history` (`end < next_end` once every output fed
    /// so far has been taken).
    next_end: usize,
}

impl Decimator {
    /// A decimator by `factor` (1 = pass-through). Allocates.
    pub(crate) fn new(factor: usize) -> Self {
        let factor = factor.max(1);
        let taps = if factor == 1 {
            vec![1.0]
        } else {
            design_lowpass(
                TAPS_PER_PHASE * factor + 1,
                CUTOFF_OF_OUTPUT_RATE / factor as f64,
            )
        };
        let len = taps.len();
        Self {
            factor,
            taps,
            history: vec![0.0; len - 1 + HISTORY_SPAN],
            end: len - 1,
            next_end: len - 1 + factor,
        }
    }

    /// Clears the history.
    pub(crate) fn reset(&mut self) {
        self.history.fill(0.0);
        self.end = self.taps.len() - 1;
        self.next_end = self.end + self.factor;
    }

    /// Group delay in input samples.
    pub(crate) fn delay_samples(&self) -> f64 {
        (self.taps.len() - 1) as f64 / 2.0
    }

    /// The filter's power gain |H|² at `f_hz` for an input at `rate_hz` (1 for factor 1).
    pub(crate) fn power_gain(&self, f_hz: f64, rate_hz: f64) -> f64 {
        polynomial_power(self.taps.iter().map(|&h| h as f64), f_hz, rate_hz)
    }

    /// Input samples still to come before the next output (1..=factor, when every output fed
    /// so far has been taken).
    #[inline]
    pub(crate) fn until_output(&self) -> usize {
        self.next_end.saturating_sub(self.end)
    }

    /// Feeds one input sample; returns an output sample every `factor` inputs (the first on the
    /// `factor`-th input, so output `j` ends at input `(j + 1) * factor - 1`).
    #[cfg(test)]
    pub(crate) fn push(&mut self, x: f32) -> Option<f32> {
        self.feed(&[x], |x| x);
        self.output().map(|(y, _)| y)
    }

    /// Takes samples from the start of `xs` into the history, each mapped through `each` (in
    /// order, once), as many as the history holds before its next move (at least one for a
    /// non-empty `xs`); returns how many it took. Take the outputs they complete
    /// ([`Decimator::output`]) before the next call: the history's move keeps only what the
    /// next output needs. The same outputs for any cutting of the input into runs.
    #[inline]
    pub(crate) fn feed(&mut self, xs: &[f32], each: impl Fn(f32) -> f32) -> usize {
        debug_assert!(self.end < self.next_end, "outputs left untaken before feed");
        if self.end == self.history.len() {
            // Full: keep the next output's inputs fed so far (fewer than taps.len()), at the
            // start (HISTORY_SPAN ≥ factor, so a whole output's run fits after them).
            let from = self.next_end - self.taps.len();
            self.history.copy_within(from..self.end, 0);
            self.end -= from;
            self.next_end -= from;
        }
        let n = xs.len().min(self.history.len() - self.end);
        for (h, &x) in self.history[self.end..self.end + n]
            .iter_mut()
            .zip(&xs[..n])
        {
            *h = each(x);
        }
        self.end += n;
        n
    }

    /// The next output, if its inputs have all been fed, and those `factor` inputs (as
    /// mapped by [`Decimator::feed`]), oldest first.
    #[inline(always)]
    pub(crate) fn output(&mut self) -> Option<(f32, &[f32])> {
        let end = self.next_end;
        if end > self.end {
            return None;
        }
        self.next_end += self.factor;
        let inputs = &self.history[end - self.factor..end];
        let y = if self.factor == 1 {
            inputs[0]
        } else {
            // The taps are symmetric, so their order against the samples does not matter.
            dot(&self.history[end - self.taps.len()..end], &self.taps)
        };
        Some((y, inputs))
    }
}

/// Dot product in sixteen lanes (four groups of four) so it vectorises and its additions
/// overlap (four independent vector chains, each a quarter of the taps long); the summation
/// order is fixed, so the result is the same on every call with the same data. Lane `k` takes
/// the products `16·i + k`; the lanes are added as `((g0 + g1) + (g2 + g3))` per position in a
/// group, then the four positions pairwise, then the products past the last whole sixteen.
#[inline]
pub(crate) fn dot(a: &[f32], b: &[f32]) -> f32 {
    let mut acc = [0.0f32; 16];
    let (xs, ys) = (a.chunks_exact(16), b.chunks_exact(16));
    let mut tail = 0.0;
    for (x, y) in xs.remainder().iter().zip(ys.remainder()) {
        tail += x * y;
    }
    for (x, y) in xs.zip(ys) {
        for k in 0..16 {
            acc[k] += x[k] * y[k];
        }
    }
    // Kept from the reduction's view, so the loop keeps four whole vectors of four lanes.
    let acc = std::hint::black_box(acc);
    let lane = |l: usize| (acc[l] + acc[4 + l]) + (acc[8 + l] + acc[12 + l]);
    ((lane(0) + lane(1)) + (lane(2) + lane(3))) + tail
}

/// Kaiser-windowed sinc low-pass of odd length `len`, cut-off `cutoff` in cycles per sample,
/// normalised to unit DC gain.
pub(crate) fn design_lowpass(len: usize, cutoff: f64) -> Vec<f32> {
    let mid = (len - 1) as f64 / 2.0;
    let i0_beta = bessel_i0(KAISER_BETA);
    let mut taps: Vec<f64> = (0..len)
        .map(|n| {
            let t = n as f64 - mid;
            let sinc = if t == 0.0 {
                2.0 * cutoff
            } else {
                (2.0 * std::f64::consts::PI * cutoff * t).sin() / (std::f64::consts::PI * t)
            };
            let r = t / mid;
            let w = bessel_i0(KAISER_BETA * (1.0 - r * r).max(0.0).sqrt()) / i0_beta;
            sinc * w
        })
        .collect();
    let sum: f64 = taps.iter().sum();
    taps.iter_mut().for_each(|t| *t /= sum);
    taps.into_iter().map(|t| t as f32).collect()
}

/// Modified Bessel function of the first kind, order 0 (power series).
fn bessel_i0(x: f64) -> f64 {
    let mut sum = 1.0;
    let mut term = 1.0;
    let q = x * x / 4.0;
    for k in 1..50 {
        term *= q / (k * k) as f64;
        sum += term;
        if term < 1e-16 * sum {
            break;
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gain_at(factor: usize, freq_hz: f64, sr: f64) -> f64 {
        let mut d = Decimator::new(factor);
        let n = (sr * 0.5) as usize;
        let mut out = Vec::new();
        for i in 0..n {
            let x = (2.0 * std::f64::consts::PI * freq_hz * i as f64 / sr).sin() as f32;
            if let Some(y) = d.push(x) {
                out.push(y as f64);
            }
        }
        let tail = &out[out.len() / 2..];
        (tail.iter().map(|y| y * y).sum::<f64>() / tail.len() as f64 * 2.0).sqrt()
    }

    #[test]
    fn factors_keep_the_internal_rate_between_8_and_16_khz() {
        for sr in [
            8_000.0, 11_025.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0,
            352_800.0, 384_000.0, 705_600.0, 768_000.0,
        ] {
            let f = factor_for(sr);
            let internal = sr / f as f64;
            assert!(
                (8_000.0..16_000.0).contains(&internal),
                "{sr} -> {internal}"
            );
        }
    }

    #[test]
    fn passes_speech_band_and_rejects_aliases() {
        let sr = 48_000.0;
        // Output rate 8 kHz: 300 Hz passes, 1.5 kHz passes, 6 kHz (would alias to 2 kHz) is cut.
        assert!((gain_at(6, 300.0, sr) - 1.0).abs() < 0.01);
        assert!((gain_at(6, 1_500.0, sr) - 1.0).abs() < 0.02);
        assert!(gain_at(6, 6_000.0, sr) < 0.003);
        assert!(gain_at(6, 4_400.0, sr) < 0.05);
    }

    #[test]
    fn the_power_gain_is_the_measured_gain_squared() {
        for (factor, sr) in [(2, 16_000.0), (5, 44_100.0), (6, 48_000.0)] {
            let d = Decimator::new(factor);
            for f in [300.0, 2_500.0, 3_200.0, 3_500.0] {
                let want = gain_at(factor, f, sr).powi(2);
                let got = d.power_gain(f, sr);
                assert!(
                    (got / want - 1.0).abs() < 0.02,
                    "{sr} {f} Hz: {got} vs {want}"
                );
            }
        }
        assert_eq!(Decimator::new(1).power_gain(3_000.0, 8_000.0), 1.0);
    }

    #[test]
    fn outputs_are_the_filter_over_the_newest_samples_across_history_moves() {
        // Long enough for several moves of the history back to its start.
        for factor in [2, 5, 24] {
            let mut d = Decimator::new(factor);
            let len = d.taps.len();
            let x: Vec<f32> = (0..5 * HISTORY_SPAN)
                .map(|i| ((i * 7919) % 1013) as f32 / 1013.0 - 0.5)
                .collect();
            let mut padded = vec![0.0f32; len - 1];
            padded.extend_from_slice(&x);
            for (i, &v) in x.iter().enumerate() {
                let got = d.push(v);
                let want = ((i + 1) % factor == 0).then(|| dot(&padded[i..i + len], &d.taps));
                assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits), "sample {i}");
            }
        }
    }

    #[test]
    fn runs_give_the_outputs_of_samples_one_by_one() {
        for factor in [1, 3, 6] {
            let x: Vec<f32> = (0..3 * HISTORY_SPAN + 17)
                .map(|i| ((i * 7919) % 1013) as f32 / 1013.0 - 0.5)
                .collect();
            let mut one = Decimator::new(factor);
            let want: Vec<u32> = x
                .iter()
                .filter_map(|&v| one.push(v))
                .map(f32::to_bits)
                .collect();
            let mut runs = Decimator::new(factor);
            let (mut got, mut rest, mut k) = (Vec::new(), &x[..], 0usize);
            let mut fed = Vec::new();
            while !rest.is_empty() {
                // Runs of 1, 2, 3, ..., 7 and 1000 samples.
                k += 1;
                let n = if k % 8 == 0 { 1000 } else { k % 8 }.min(rest.len());
                let taken = runs.feed(&rest[..n], |v| 2.0 * v);
                assert!(taken >= 1 && taken <= n);
                fed.extend_from_slice(&rest[..taken]);
                while let Some((y, inputs)) = runs.output() {
                    got.push(y);
                    // The inputs of output j are inputs j·factor .. (j + 1)·factor, mapped.
                    let j = got.len() - 1;
                    let want_in: Vec<f32> = fed[j * factor..(j + 1) * factor]
                        .iter()
                        .map(|v| 2.0 * v)
                        .collect();
                    assert_eq!(inputs, &want_in[..], "factor {factor} output {j}");
                }
                rest = &rest[taken..];
            }
            // Mapped by 2 (exact in binary), so the outputs are twice the plain ones.
            let got: Vec<u32> = got.into_iter().map(|y| (y / 2.0).to_bits()).collect();
            assert_eq!(got, want, "factor {factor}");
        }
    }

    #[test]
    fn reset_restores_the_initial_state() {
        let mut d = Decimator::new(3);
        let first: Vec<_> = (0..30).filter_map(|i| d.push(i as f32)).collect();
        d.reset();
        let again: Vec<_> = (0..30).filter_map(|i| d.push(i as f32)).collect();
        assert_eq!(first, again);
        assert_eq!(d.delay_samples(), 24.0);
    }
}
