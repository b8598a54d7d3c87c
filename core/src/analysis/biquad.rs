//! Second-order Butterworth sections (RBJ biquads, f64 state, direct form I): [`Biquad`], the
//! building block of the test-noise shaping, and [`HighPass`], the bypassable high-pass in
//! front of the pitch analysis (a corner of 0 Hz makes it a pass-through). Both give their
//! power gain at a frequency, which the breath bands divide out of the pitch spectrum.

/// |Σₖ cₖ z⁻ᵏ|² at z = e^(jw), w = 2π·`f_hz`/`rate_hz`: the power gain of an FIR filter with
/// taps `coeffs`, or of one side of a recursive one.
pub(crate) fn polynomial_power(
    coeffs: impl IntoIterator<Item = f64>,
    f_hz: f64,
    rate_hz: f64,
) -> f64 {
    let w = 2.0 * std::f64::consts::PI * f_hz / rate_hz;
    let (re, im) = coeffs
        .into_iter()
        .enumerate()
        .fold((0.0f64, 0.0f64), |(re, im), (k, c)| {
            (re + c * (w * k as f64).cos(), im - c * (w * k as f64).sin())
        });
    re * re + im * im
}

/// One RBJ biquad section with f64 state.
#[derive(Debug, Clone, Copy)]
pub struct Biquad {
    b: [f64; 3],
    a: [f64; 2],
    x: [f64; 2],
    y: [f64; 2],
}

impl Biquad {
    /// A second-order Butterworth high-pass (`high = true`) or low-pass at `corner_hz`.
    pub fn butterworth(corner_hz: f64, rate_hz: f64, high: bool) -> Self {
        let w0 = 2.0 * std::f64::consts::PI * corner_hz / rate_hz;
        let alpha = w0.sin() / (2.0 * std::f64::consts::FRAC_1_SQRT_2);
        let cos = w0.cos();
        let a0 = 1.0 + alpha;
        let b = if high {
            [(1.0 + cos) / 2.0, -(1.0 + cos), (1.0 + cos) / 2.0]
        } else {
            [(1.0 - cos) / 2.0, 1.0 - cos, (1.0 - cos) / 2.0]
        };
        Self {
            b: b.map(|v| v / a0),
            a: [-2.0 * cos / a0, (1.0 - alpha) / a0],
            x: [0.0; 2],
            y: [0.0; 2],
        }
    }

    /// The section's power gain |H|² at `f_hz` for a stream at `rate_hz`:
    /// H(e^jw) = (b0 + b1 z⁻¹ + b2 z⁻²) / (1 + a1 z⁻¹ + a2 z⁻²).
    pub(crate) fn power_gain(&self, f_hz: f64, rate_hz: f64) -> f64 {
        polynomial_power(self.b, f_hz, rate_hz)
            / polynomial_power([1.0, self.a[0], self.a[1]], f_hz, rate_hz)
    }

    /// Clears the state.
    pub(crate) fn reset(&mut self) {
        self.x = [0.0; 2];
        self.y = [0.0; 2];
    }

    /// Filters one sample.
    #[inline]
    pub fn process(&mut self, x: f64) -> f64 {
        let y = self.b[0] * x + self.b[1] * self.x[0] + self.b[2] * self.x[1]
            - self.a[0] * self.y[0]
            - self.a[1] * self.y[1];
        self.x = [x, self.x[0]];
        self.y = [y, self.y[0]];
        y
    }
}

/// `N` copies of one [`Biquad`] run in lockstep, one stream per lane: each lane's outputs are
/// bit-identical to [`Biquad::process`] on its stream (the same operations in the same order),
/// but the lanes' arithmetic vectorises and their recursions overlap.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BiquadLanes<const N: usize> {
    b: [f64; 3],
    a: [f64; 2],
    x: [[f64; N]; 2],
    y: [[f64; N]; 2],
}

impl<const N: usize> BiquadLanes<N> {
    /// Every lane a copy of `section` (its coefficients and its state).
    pub(crate) fn new(section: Biquad) -> Self {
        Self {
            b: section.b,
            a: section.a,
            x: section.x.map(|v| [v; N]),
            y: section.y.map(|v| [v; N]),
        }
    }

    /// Filters one sample of each lane's stream.
    #[inline(always)]
    pub(crate) fn process(&mut self, x: [f64; N]) -> [f64; N] {
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let mut y = [0.0; N];
        for k in 0..N {
            y[k] = b0 * x[k] + b1 * self.x[0][k] + b2 * self.x[1][k]
                - a1 * self.y[0][k]
                - a2 * self.y[1][k];
        }
        self.x = [x, self.x[0]];
        self.y = [y, self.y[0]];
        y
    }

    /// Lane `k` as a single section, to run on alone.
    pub(crate) fn lane(&self, k: usize) -> Biquad {
        Biquad {
            b: self.b,
            a: self.a,
            x: [self.x[0][k], self.x[1][k]],
            y: [self.y[0][k], self.y[1][k]],
        }
    }
}

/// A Butterworth high-pass on f32 samples, or a pass-through (`None`).
#[derive(Debug, Clone)]
pub(crate) struct HighPass(Option<Biquad>);

impl HighPass {
    /// A high-pass at `corner_hz` for a stream at `rate_hz` (0 Hz = pass-through).
    pub(crate) fn new(corner_hz: f64, rate_hz: f64) -> Self {
        Self((corner_hz > 0.0).then(|| Biquad::butterworth(corner_hz, rate_hz, true)))
    }

    /// The power gain |H|² at `f_hz` for a stream at `rate_hz` (1 for the pass-through).
    pub(crate) fn power_gain(&self, f_hz: f64, rate_hz: f64) -> f64 {
        self.0.as_ref().map_or(1.0, |s| s.power_gain(f_hz, rate_hz))
    }

    /// Clears the state.
    pub(crate) fn reset(&mut self) {
        self.0.iter_mut().for_each(Biquad::reset);
    }

    /// Filters one sample.
    #[inline]
    pub fn process(&mut self, x: f32) -> f32 {
        match &mut self.0 {
            Some(section) => section.process(x as f64) as f32,
            None => x,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gain(hp: &mut HighPass, f: f64, rate: f64) -> f64 {
        hp.reset();
        let n = rate as usize;
        let mut acc = 0.0;
        for i in 0..n {
            let y = hp.process((2.0 * std::f64::consts::PI * f * i as f64 / rate).sin() as f32);
            if i > n / 2 {
                acc += (y as f64).powi(2);
            }
        }
        (acc / (n / 2) as f64 * 2.0).sqrt()
    }

    #[test]
    fn lanes_give_each_stream_what_one_section_gives_it() {
        let section = Biquad::butterworth(1800.0, 8000.0, false);
        let mut lanes = BiquadLanes::<3>::new(section);
        let mut one = [section; 3];
        for i in 0..200 {
            let x = [0, 1, 2].map(|k| ((i * 7919 + k * 104_729) % 1013) as f64 / 1013.0 - 0.5);
            let got = lanes.process(x);
            for k in 0..3 {
                assert_eq!(got[k].to_bits(), one[k].process(x[k]).to_bits(), "{i} {k}");
            }
        }
        // A lane taken out runs on from the same state.
        let mut alone = lanes.lane(1);
        assert_eq!(
            alone.process(0.25).to_bits(),
            one[1].process(0.25).to_bits()
        );
    }

    #[test]
    fn butterworth_corner_and_bands() {
        let mut hp = HighPass::new(80.0, 8000.0);
        assert!((gain(&mut hp, 80.0, 8000.0) - std::f64::consts::FRAC_1_SQRT_2).abs() < 0.01);
        assert!(gain(&mut hp, 20.0, 8000.0) < 0.07);
        assert!((gain(&mut hp, 500.0, 8000.0) - 1.0).abs() < 0.02);
        let mut off = HighPass::new(0.0, 8000.0);
        assert_eq!(off.process(0.25), 0.25);
        assert_eq!(off.power_gain(50.0, 8000.0), 1.0);
    }

    #[test]
    fn the_power_gain_is_the_measured_gain_squared() {
        let mut hp = HighPass::new(120.0, 8820.0);
        for f in [60.0, 100.0, 120.0, 200.0, 400.0, 3000.0] {
            let want = gain(&mut hp, f, 8820.0).powi(2);
            let got = hp.power_gain(f, 8820.0);
            assert!((got / want - 1.0).abs() < 0.01, "{f} Hz: {got} vs {want}");
        }
    }
}
