//! Any stream rate (8–768 kHz) to Silero's 16 kHz, sample by sample, allocation-free.
//!
//! Two stages: the analysis's integer decimator ([`Decimator`]) by `D = ⌊rate / 16 kHz⌋` (at
//! least 1), which alone reaches 16 kHz at 16, 32, 48, 96, 192 kHz…; then, for other rates, a
//! fractional stage: a Kaiser-windowed sinc (cut-off 0.45 of the lower of the two rates,
//! [`HALF_TAPS`] taps either side, more when it decimates) read from a table of
//! [`PHASES`] phases with linear interpolation between neighbouring phases. Output sample `n`
//! lies at `n · rate₁ / 16 kHz` samples of the first stage's output, computed from the stream
//! start each time, so the output depends only on the sample sequence, never on how it was cut
//! into blocks.

use crate::analysis::decimator::{design_lowpass, dot, Decimator};

use super::silero::SILERO_RATE_HZ;

/// Taps either side of the output instant at the fractional stage's input rate (times the
/// decimation ratio when it decimates).
const HALF_TAPS: usize = 16;
/// Phases of the fractional stage's table.
const PHASES: usize = 128;
/// Cut-off (−6 dB) of the fractional stage as a fraction of the lower rate's Nyquist × 2.
const CUTOFF: f64 = 0.45;
/// Samples of history kept beyond the filter (moved back once in this many).
const HISTORY_SPAN: usize = 1024;

/// The fractional stage.
#[derive(Debug, Clone)]
struct Fractional {
    /// Input samples per output sample.
    step: f64,
    half: usize,
    /// `(PHASES + 1)` rows of `2 · half` taps.
    table: Vec<f32>,
    /// Linear history; `history[end - 1]` is input sample `taken - 1`.
    history: Vec<f32>,
    end: usize,
    taken: u64,
    produced: u64,
}

impl Fractional {
    fn new(step: f64) -> Self {
        let half = (HALF_TAPS as f64 * step.max(1.0)).ceil() as usize;
        let taps = 2 * half;
        let cutoff = CUTOFF * (1.0 / step).min(1.0);
        // The prototype at PHASES × the input rate, unit gain per phase.
        let proto = design_lowpass(taps * PHASES + 1, cutoff / PHASES as f64);
        let mut table = vec![0.0; (PHASES + 1) * taps];
        for phase in 0..=PHASES {
            for k in 0..taps {
                table[phase * taps + k] = proto[(k + 1) * PHASES - phase] * PHASES as f32;
            }
        }
        let mut f = Self {
            step,
            half,
            table,
            history: vec![0.0; taps + HISTORY_SPAN],
            end: 0,
            taken: 0,
            produced: 0,
        };
        f.reset();
        f
    }

    fn reset(&mut self) {
        self.history.fill(0.0);
        // The samples before the stream are zeros.
        self.end = 2 * self.half;
        self.taken = 0;
        self.produced = 0;
    }

    /// Takes one input sample; hands every output sample it completes to `out`.
    #[inline]
    fn push(&mut self, x: f32, out: &mut impl FnMut(f32)) {
        let taps = 2 * self.half;
        if self.end == self.history.len() {
            self.history.copy_within(self.end - taps..self.end, 0);
            self.end = taps;
        }
        self.history[self.end] = x;
        self.end += 1;
        self.taken += 1;
        loop {
            let t = self.produced as f64 * self.step;
            let i0 = t.floor();
            let last_needed = i0 as u64 + self.half as u64;
            if last_needed >= self.taken {
                return;
            }
            let p = (t - i0) * PHASES as f64;
            let phase = (p.floor() as usize).min(PHASES - 1);
            let alpha = (p - phase as f64) as f32;
            // The window ends at input sample `last_needed`.
            let stop = self.end - (self.taken - 1 - last_needed) as usize;
            let window = &self.history[stop - taps..stop];
            let row = |k: usize| &self.table[k * taps..(k + 1) * taps];
            let a = dot(window, row(phase));
            let b = dot(window, row(phase + 1));
            out(a + alpha * (b - a));
            self.produced += 1;
        }
    }
}

/// Where the resampler's output samples lie in the input stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceClock {
    step: f64,
    factor: f64,
    delay_samples: f64,
    sample_rate_hz: f64,
}

impl SourceClock {
    /// The input position (samples from the stream start, fractional) of output sample `n`.
    pub fn position(&self, n: f64) -> f64 {
        // Decimator output j is centred on input (j + 1)·D − 1 − its group delay.
        n * self.step * self.factor + (self.factor - 1.0) - self.delay_samples
    }

    /// The input time of output sample `n`, seconds from the stream start.
    pub fn seconds(&self, n: u64) -> f64 {
        self.position(n as f64) / self.sample_rate_hz
    }
}

/// A stream at any rate to 16 kHz. See the module docs.
#[derive(Debug, Clone)]
pub struct ToSileroRate {
    sample_rate_hz: f64,
    factor: usize,
    decimator: Decimator,
    fractional: Option<Fractional>,
}

impl ToSileroRate {
    /// A resampler from `sample_rate_hz` (8–768 kHz). Allocates.
    pub fn new(sample_rate_hz: f64) -> Self {
        let factor = ((sample_rate_hz / SILERO_RATE_HZ).floor() as usize).max(1);
        let stage_rate = sample_rate_hz / factor as f64;
        let fractional = ((stage_rate - SILERO_RATE_HZ).abs() > 1e-9)
            .then(|| Fractional::new(stage_rate / SILERO_RATE_HZ));
        Self {
            sample_rate_hz,
            factor,
            decimator: Decimator::new(factor),
            fractional,
        }
    }

    /// Back to the start of a stream.
    pub fn reset(&mut self) {
        self.decimator.reset();
        if let Some(f) = &mut self.fractional {
            f.reset();
        }
    }

    /// The position in the input stream (samples from its start, fractional) that 16 kHz
    /// output sample `n` stands for.
    pub fn source_position(&self, n: f64) -> f64 {
        self.clock().position(n)
    }

    /// The map from output samples to input positions, to keep apart from the resampler.
    pub fn clock(&self) -> SourceClock {
        SourceClock {
            step: self.fractional.as_ref().map_or(1.0, |f| f.step),
            factor: self.factor as f64,
            delay_samples: self.decimator.delay_samples(),
            sample_rate_hz: self.sample_rate_hz,
        }
    }

    /// Seconds of input from the moment 16 kHz output sample `n` stands for until it is
    /// produced (the resampler's latency).
    pub fn latency_s(&self) -> f64 {
        let stage = self.fractional.as_ref().map_or(0.0, |f| f.half as f64);
        (stage * self.factor as f64 + self.decimator.delay_samples()) / self.sample_rate_hz
    }

    /// Takes input samples; hands every 16 kHz output sample to `out`, in order. Never
    /// allocates.
    pub fn process(&mut self, input: &[f32], mut out: impl FnMut(f32)) {
        let mut rest = input;
        while !rest.is_empty() {
            let n = self.decimator.feed(rest, |x| x);
            rest = &rest[n..];
            while let Some((y, _)) = self.decimator.output() {
                match &mut self.fractional {
                    Some(f) => f.push(y, &mut out),
                    None => out(y),
                }
            }
        }
    }
}

/// A whole signal at `sample_rate_hz` to 16 kHz, aligned: output sample `n` stands for input
/// time `n / 16 kHz` (within half an output sample), `⌊len · 16 kHz / rate⌉` samples long. For
/// offline tools (allocates).
pub fn resample_to_16k(x: &[f32], sample_rate_hz: f64) -> Vec<f32> {
    let mut r = ToSileroRate::new(sample_rate_hz);
    let ratio = SILERO_RATE_HZ / sample_rate_hz;
    let want = (x.len() as f64 * ratio).round() as usize;
    // Output n stands for input source_position(n): skip the outputs before input 0.
    let skip = (-r.source_position(0.0) * ratio).round().max(0.0) as usize;
    let flush = vec![
        0.0;
        (r.latency_s() * sample_rate_hz).ceil() as usize
            + 2 * SILERO_RATE_HZ as usize / 1000
    ];
    let mut out = Vec::with_capacity(want + skip + 64);
    r.process(x, |y| out.push(y));
    r.process(&flush, |y| out.push(y));
    out.drain(..skip.min(out.len()));
    out.resize(want, 0.0);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn resample(rate: f64, x: &[f32]) -> Vec<f32> {
        let mut r = ToSileroRate::new(rate);
        let mut out = Vec::new();
        r.process(x, |y| out.push(y));
        out
    }

    fn tone(rate: f64, f_hz: f64, secs: f64) -> Vec<f32> {
        (0..(rate * secs) as usize)
            .map(|i| (2.0 * std::f64::consts::PI * f_hz * i as f64 / rate).sin() as f32 * 0.5)
            .collect()
    }

    /// Amplitude of `f_hz` in `y` (16 kHz) and the residual after fitting it, over the middle.
    fn fit(y: &[f32], f_hz: f64) -> (f64, f64) {
        let y = &y[y.len() / 4..3 * y.len() / 4];
        let w = 2.0 * std::f64::consts::PI * f_hz / SILERO_RATE_HZ;
        let (mut s, mut c) = (0.0, 0.0);
        for (i, v) in y.iter().enumerate() {
            s += *v as f64 * (w * i as f64).sin();
            c += *v as f64 * (w * i as f64).cos();
        }
        let (a, b) = (2.0 * s / y.len() as f64, 2.0 * c / y.len() as f64);
        let resid: f64 = y
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let m = a * (w * i as f64).sin() + b * (w * i as f64).cos();
                (*v as f64 - m).powi(2)
            })
            .sum::<f64>()
            / y.len() as f64;
        ((a * a + b * b).sqrt(), resid.sqrt())
    }

    #[test]
    fn every_rate_keeps_speech_band_tones_and_rejects_what_would_alias() {
        for rate in [
            8_000.0, 11_025.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 768_000.0,
        ] {
            let secs = 0.5;
            let y = resample(rate, &tone(rate, 1000.0, secs));
            let want = (secs * SILERO_RATE_HZ) as isize;
            assert!(
                (y.len() as isize - want).abs()
                    <= 1 + (ToSileroRate::new(rate).latency_s() * 16e3) as isize,
                "{rate}: {} samples",
                y.len()
            );
            let (amp, resid) = fit(&y, 1000.0);
            assert!((amp - 0.5).abs() < 0.01, "{rate}: 1 kHz amplitude {amp}");
            assert!(resid < 0.005, "{rate}: residual {resid}");
            if rate >= 22_050.0 {
                // 10 kHz would fold to 6 kHz: at least 40 dB down.
                let y = resample(rate, &tone(rate, 10_000.0, secs));
                let (amp, _) = fit(&y, 6000.0);
                assert!(amp < 0.005, "{rate}: 10 kHz leaks as {amp}");
            }
        }
    }

    #[test]
    fn output_lies_where_source_position_says() {
        // A click at input sample k comes out centred at the output sample whose source
        // position is k.
        for rate in [8_000.0, 22_050.0, 44_100.0, 48_000.0] {
            let k = (0.1 * rate) as usize;
            let mut x = vec![0.0f32; (0.2 * rate) as usize];
            x[k] = 1.0;
            let y = resample(rate, &x);
            let r = ToSileroRate::new(rate);
            // The centre of mass of the (symmetric) response.
            let (mut m0, mut m1) = (0.0, 0.0);
            for (n, v) in y.iter().enumerate() {
                let w = (*v as f64).powi(2);
                m0 += w;
                m1 += w * r.source_position(n as f64);
            }
            let at = m1 / m0;
            assert!(
                (at - k as f64).abs() < 0.05 * rate / 16_000.0 + 0.5,
                "{rate}: {at} vs {k}"
            );
        }
    }

    #[test]
    fn a_whole_signal_comes_out_aligned_and_as_long_as_its_duration() {
        for rate in [8_000.0, 20_000.0, 44_100.0, 48_000.0] {
            let k = (0.1 * rate) as usize;
            let mut x = vec![0.0f32; (0.25 * rate) as usize];
            x[k] = 1.0;
            let y = resample_to_16k(&x, rate);
            assert_eq!(y.len(), 4000, "{rate}");
            let peak = (0..y.len())
                .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
                .unwrap_or(0);
            assert!(
                (peak as f64 - 1600.0).abs() <= 1.0,
                "{rate}: click at {peak}"
            );
        }
    }

    #[test]
    fn any_partition_gives_the_same_samples() {
        for rate in [8_000.0, 44_100.0, 48_000.0, 192_000.0] {
            let x = tone(rate, 440.0, 0.3);
            let whole = resample(rate, &x);
            let mut r = ToSileroRate::new(rate);
            let mut cut = Vec::new();
            let mut at = 0;
            let mut size = 1;
            while at < x.len() {
                let n = size.min(x.len() - at);
                r.process(&x[at..at + n], |y| cut.push(y));
                at += n;
                size = size * 7 % 1031 + 1;
            }
            assert_eq!(whole, cut, "{rate}");
            r.reset();
            let mut again = Vec::new();
            r.process(&x, |y| again.push(y));
            assert_eq!(whole, again, "{rate}: reset");
        }
    }
}
