//! The breath voices' filters: one biquad section (RBJ band-pass, high-pass, low-pass, direct
//! form II transposed, f64) and the band limits every breath passes through, shared by the
//! built-in voice (`voice.rs`) and the learned one (`learned.rs`).

use std::f64::consts::PI;

/// High-pass corner of every breath voice, Hz.
pub(super) const HIGHPASS_HZ: f64 = 180.0;
/// Low-pass corner of every breath voice, Hz (at most 0.45 × the rate).
pub(super) const LOWPASS_HZ: f64 = 8000.0;

/// One biquad section.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Biquad {
    b0: f64,
    b1: f64,
    b2: f64,
    a1: f64,
    a2: f64,
    z1: f64,
    z2: f64,
}

impl Biquad {
    fn set(&mut self, b: [f64; 3], a: [f64; 3]) {
        self.b0 = b[0] / a[0];
        self.b1 = b[1] / a[0];
        self.b2 = b[2] / a[0];
        self.a1 = a[1] / a[0];
        self.a2 = a[2] / a[0];
    }
    /// RBJ band-pass with 0 dB peak gain.
    pub(super) fn bandpass(&mut self, f_hz: f64, q: f64, fs: f64) {
        let w = 2.0 * PI * f_hz / fs;
        let alpha = w.sin() / (2.0 * q);
        self.set(
            [alpha, 0.0, -alpha],
            [1.0 + alpha, -2.0 * w.cos(), 1.0 - alpha],
        );
    }
    pub(super) fn highpass(&mut self, f_hz: f64, q: f64, fs: f64) {
        let w = 2.0 * PI * f_hz / fs;
        let (c, alpha) = (w.cos(), w.sin() / (2.0 * q));
        self.set(
            [(1.0 + c) / 2.0, -(1.0 + c), (1.0 + c) / 2.0],
            [1.0 + alpha, -2.0 * c, 1.0 - alpha],
        );
    }
    pub(super) fn lowpass(&mut self, f_hz: f64, q: f64, fs: f64) {
        let w = 2.0 * PI * f_hz / fs;
        let (c, alpha) = (w.cos(), w.sin() / (2.0 * q));
        self.set(
            [(1.0 - c) / 2.0, 1.0 - c, (1.0 - c) / 2.0],
            [1.0 + alpha, -2.0 * c, 1.0 - alpha],
        );
    }
    #[inline]
    pub(super) fn tick(&mut self, x: f64) -> f64 {
        let y = self.b0 * x + self.z1;
        self.z1 = self.b1 * x - self.a1 * y + self.z2;
        self.z2 = self.b2 * x - self.a2 * y;
        y
    }
    pub(super) fn clear(&mut self) {
        self.z1 = 0.0;
        self.z2 = 0.0;
    }
    /// H's numerator and denominator at the frequency of `p`, each (real, imaginary):
    /// H = (b0 + b1 z⁻¹ + b2 z⁻²) / (1 + a1 z⁻¹ + a2 z⁻²) at z⁻¹ = cos w − j sin w.
    fn polynomials_at(&self, p: &Phasor) -> ((f64, f64), (f64, f64)) {
        let Phasor { c1, s1, c2, s2 } = *p;
        (
            (
                self.b0 + self.b1 * c1 + self.b2 * c2,
                -(self.b1 * s1 + self.b2 * s2),
            ),
            (
                1.0 + self.a1 * c1 + self.a2 * c2,
                -(self.a1 * s1 + self.a2 * s2),
            ),
        )
    }

    /// Complex response H (real, imaginary) at the frequency of `p`: what a parallel bank of
    /// sections fed the same input sums.
    pub(super) fn response_at(&self, p: &Phasor) -> (f64, f64) {
        let ((nr, ni), (dr, di)) = self.polynomials_at(p);
        let den = dr * dr + di * di;
        ((nr * dr + ni * di) / den, (ni * dr - nr * di) / den)
    }

    /// Power gain |H|² at the frequency of `p` (computed once for a bank of filters).
    pub(super) fn power_gain_at(&self, p: &Phasor) -> f64 {
        let ((nr, ni), (dr, di)) = self.polynomials_at(p);
        (nr.powi(2) + ni.powi(2)) / (dr.powi(2) + di.powi(2))
    }
}

/// cos and sin of `w` and `2w` at one frequency `w` (radians per sample): what
/// [`Biquad::power_gain_at`] needs, so a bank of filters shares one set of sines.
#[derive(Debug, Clone, Copy)]
pub(super) struct Phasor {
    c1: f64,
    s1: f64,
    c2: f64,
    s2: f64,
}

impl Phasor {
    /// The phasor at `w` radians per sample.
    pub(super) fn at(w: f64) -> Self {
        Self {
            c1: w.cos(),
            s1: w.sin(),
            c2: (2.0 * w).cos(),
            s2: (2.0 * w).sin(),
        }
    }
}

/// Butterworth Q values of a 4th-order section pair.
pub(super) const BUTTER4_Q: [f64; 2] = [0.541_196_1, 1.306_563];
