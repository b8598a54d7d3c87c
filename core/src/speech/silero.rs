//! Silero VAD v6, the 16 kHz network, as plain Rust: the same forward pass as the ONNX model
//! `silero_vad_op18_ifless.onnx` (its `sr == 16000` branch), on the weights of
//! [`weights`](super::weights), allocation-free per chunk.
//!
//! One step takes a chunk of [`CHUNK`] samples at 16 kHz with the last [`CONTEXT`] samples of
//! the previous chunk in front and returns the probability that the chunk holds speech:
//! 1. reflection padding of 64 samples on the right (640 samples);
//! 2. an STFT as a convolution with the model's basis (258 rows: the real and imaginary parts
//!    of a 256-point DFT with a periodic Hann window), hop 128: 4 frames × 129 magnitudes;
//! 3. four convolutions, kernel 3, padding 1 (129→128 stride 1, 128→64 stride 2, 64→64
//!    stride 2, 64→128 stride 1), each followed by a ReLU: one frame of 128;
//! 4. one LSTM cell of 128 (gates i, f, g, o; both biases), state carried from chunk to chunk;
//! 5. ReLU, a 1×1 convolution to one value, sigmoid.
//!
//! A committed test holds it to onnxruntime's probabilities on a generated signal.

use std::sync::OnceLock;

use super::weights::{SileroWeights, SHIPPED};
use crate::analysis::decimator::dot;

/// The network's sample rate, Hz.
pub const SILERO_RATE_HZ: f64 = 16_000.0;
/// New samples per step (32 ms).
pub const CHUNK: usize = 512;
/// Samples of the previous chunk in front of each step.
pub const CONTEXT: usize = 64;
const N_FFT: usize = 256;
const HOP: usize = 128;
const BINS: usize = N_FFT / 2 + 1;
const FRAMES: usize = 4;
const HIDDEN: usize = 128;
/// Samples the STFT reads: context, chunk and the right padding.
const PADDED: usize = CONTEXT + CHUNK + 64;
/// The widest activation: 4 frames of 128 channels.
const WIDEST: usize = FRAMES * 128;

/// A convolution of kernel 3 and padding 1, weights rearranged to `[out][tap][in]` so that each
/// tap is one contiguous dot product over a time-major input row.
#[derive(Debug)]
struct Conv {
    cin: usize,
    cout: usize,
    stride: usize,
    weight: Vec<f32>,
    bias: Vec<f32>,
}

impl Conv {
    /// From ONNX's `[out][in][tap]` weights.
    fn new(weight: &[f32], bias: &[f32], cin: usize, cout: usize, stride: usize) -> Self {
        let mut w = vec![0.0; cout * 3 * cin];
        for o in 0..cout {
            for i in 0..cin {
                for k in 0..3 {
                    w[(o * 3 + k) * cin + i] = weight[(o * cin + i) * 3 + k];
                }
            }
        }
        Self {
            cin,
            cout,
            stride,
            weight: w,
            bias: bias.to_vec(),
        }
    }

    /// `x`: `t_in` frames of `cin` (time-major); writes the ReLU'd output frames of `cout` to
    /// `y` and returns their number.
    fn run(&self, x: &[f32], t_in: usize, y: &mut [f32]) -> usize {
        let t_out = (t_in - 1) / self.stride + 1;
        for t in 0..t_out {
            for o in 0..self.cout {
                let mut s = self.bias[o];
                for k in 0..3 {
                    let Some(ti) = (t * self.stride + k).checked_sub(1) else {
                        continue;
                    };
                    if ti >= t_in {
                        continue;
                    }
                    let w = &self.weight[(o * 3 + k) * self.cin..(o * 3 + k + 1) * self.cin];
                    s += dot(w, &x[ti * self.cin..(ti + 1) * self.cin]);
                }
                y[t * self.cout + o] = s.max(0.0);
            }
        }
        t_out
    }
}

/// The network's weights, arranged for the forward pass.
#[derive(Debug)]
struct SileroNet {
    /// `[258][256]`: real rows, then imaginary rows.
    stft: Vec<f32>,
    convs: [Conv; 4],
    /// `[512][128]` each.
    weight_ih: Vec<f32>,
    weight_hh: Vec<f32>,
    /// `bias_ih + bias_hh`.
    bias: Vec<f32>,
    out_weight: Vec<f32>,
    out_bias: f32,
}

impl SileroNet {
    fn new(w: SileroWeights) -> Self {
        let t = &w.tensors;
        Self {
            convs: [
                Conv::new(&t[1], &t[2], BINS, 128, 1),
                Conv::new(&t[3], &t[4], 128, 64, 2),
                Conv::new(&t[5], &t[6], 64, 64, 2),
                Conv::new(&t[7], &t[8], 64, 128, 1),
            ],
            weight_ih: t[9].clone(),
            weight_hh: t[10].clone(),
            bias: t[11].iter().zip(&t[12]).map(|(a, b)| a + b).collect(),
            out_weight: t[13].clone(),
            out_bias: t[14][0],
            stft: w.tensors.into_iter().next().unwrap_or_default(),
        }
    }

    /// The embedded weights (a unit test checks that they load).
    fn shipped() -> &'static SileroNet {
        static NET: OnceLock<SileroNet> = OnceLock::new();
        NET.get_or_init(|| {
            SileroNet::new(SileroWeights::parse(SHIPPED).expect("the embedded Silero weights load"))
        })
    }
}

fn sigmoid(z: f32) -> f32 {
    1.0 / (1.0 + (-z).exp())
}

/// The network with its state (LSTM state and the previous chunk's context) and scratch
/// buffers: `step` never allocates.
#[derive(Debug, Clone)]
pub struct Silero {
    net: &'static SileroNet,
    h: [f32; HIDDEN],
    c: [f32; HIDDEN],
    context: [f32; CONTEXT],
    x: [f32; PADDED],
    mag: [f32; FRAMES * BINS],
    a: [f32; WIDEST],
    b: [f32; WIDEST],
    gates: [f32; 4 * HIDDEN],
}

impl Default for Silero {
    fn default() -> Self {
        Self::new()
    }
}

impl Silero {
    /// The network on the embedded weights, at the start of a stream.
    pub fn new() -> Self {
        Self {
            net: SileroNet::shipped(),
            h: [0.0; HIDDEN],
            c: [0.0; HIDDEN],
            context: [0.0; CONTEXT],
            x: [0.0; PADDED],
            mag: [0.0; FRAMES * BINS],
            a: [0.0; WIDEST],
            b: [0.0; WIDEST],
            gates: [0.0; 4 * HIDDEN],
        }
    }

    /// Back to the start of a stream (state and context zero).
    pub fn reset(&mut self) {
        self.h = [0.0; HIDDEN];
        self.c = [0.0; HIDDEN];
        self.context = [0.0; CONTEXT];
    }

    /// The speech probability of the next 32 ms chunk (16 kHz). Never allocates.
    pub fn step(&mut self, chunk: &[f32; CHUNK]) -> f32 {
        let net = self.net;
        let n = CONTEXT + CHUNK;
        self.x[..CONTEXT].copy_from_slice(&self.context);
        self.x[CONTEXT..n].copy_from_slice(chunk);
        self.context.copy_from_slice(&self.x[n - CONTEXT..n]);
        for j in 0..PADDED - n {
            self.x[n + j] = self.x[n - 2 - j];
        }
        for t in 0..FRAMES {
            let frame = &self.x[t * HOP..t * HOP + N_FFT];
            for f in 0..BINS {
                let re = dot(&net.stft[f * N_FFT..(f + 1) * N_FFT], frame);
                let im = dot(&net.stft[(BINS + f) * N_FFT..(BINS + f + 1) * N_FFT], frame);
                self.mag[t * BINS + f] = (re * re + im * im).sqrt();
            }
        }
        let t1 = net.convs[0].run(&self.mag, FRAMES, &mut self.a);
        let t2 = net.convs[1].run(&self.a, t1, &mut self.b);
        let t3 = net.convs[2].run(&self.b, t2, &mut self.a);
        net.convs[3].run(&self.a, t3, &mut self.b);
        let x = &self.b[..HIDDEN];
        for (r, g) in self.gates.iter_mut().enumerate() {
            let row = r * HIDDEN..(r + 1) * HIDDEN;
            *g = net.bias[r]
                + dot(&net.weight_ih[row.clone()], x)
                + dot(&net.weight_hh[row], &self.h);
        }
        let mut z = net.out_bias;
        for k in 0..HIDDEN {
            let i = sigmoid(self.gates[k]);
            let f = sigmoid(self.gates[HIDDEN + k]);
            let g = self.gates[2 * HIDDEN + k].tanh();
            let o = sigmoid(self.gates[3 * HIDDEN + k]);
            self.c[k] = f * self.c[k] + i * g;
            self.h[k] = o * self.c[k].tanh();
            z += net.out_weight[k] * self.h[k].max(0.0);
        }
        sigmoid(z)
    }
}
