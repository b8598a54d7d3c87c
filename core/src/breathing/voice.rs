//! Breath sounds: procedural mouth and nose inhalations and user samples, played with the
//! paper's trapezoid envelope.
//!
//! # The procedural sound
//! Turbulence is modelled as seeded white noise with a slow random amplitude flutter (±20 %,
//! below ~6 Hz), shaped by a parallel bank of resonators (RBJ band-pass biquads):
//! - **mouth** (open vocal tract, as in an [h]/[ɑ] inhalation): resonances near 750, 1350, 2500,
//!   3600 and 4800 Hz plus a broad aspiration band around 3 kHz: bright;
//! - **nose** (nasal cavity): a strong nasal resonance near 290 Hz, weaker ones near 1050 and
//!   2300 Hz and a faint broad band: dark.
//!
//! Both pass a 4th-order high-pass at 180 Hz and a 4th-order low-pass at min(8 kHz, 0.45 ×
//! rate), so most energy lies between 200 Hz and 8 kHz, there is no DC, and the sound is the same
//! at every rate from 8 to 768 kHz (resonances above 0.45 × rate are left out). Every breath
//! shifts all resonances by a random factor within ±5 % (seeded), so consecutive breaths differ.
//! Each chain is normalised to unit noise power at `prepare` (from its impulse response), so
//! `gain` is the plateau RMS within about ±0.5 dB. A mix of mouth and nose uses independent noise
//! for each and weights `mouth_vs_nose` and `1 − mouth_vs_nose`, renormalised to unit power.
//!
//! # The envelope
//! The paper's trapezoid, with raised-cosine corners so it has no kinks: attack 30 % and release
//! 35 % of the length (at least 10 ms each, the plateau shrinks first), zero at both ends. A
//! [`BreathVoice::fade_out`] replaces the rest with a raised-cosine fade from the current level.
//!
//! Rendering is allocation-free after [`BreathVoice::prepare`]; an idle voice costs one branch.

use super::band_limit::{self, BandLimit};
use super::banks::{MOUTH_BANK, NOSE_BANK};
use super::filters::{Biquad, BUTTER4_Q, HIGHPASS_HZ, LOWPASS_HZ};
use super::learned::{LearnedSound, LearnedVoice};
use super::sample::fitted_at;
use super::{BreathSample, SampleSlot};
use crate::control::BreathKind;
use crate::rng::SeededRng;
use std::f64::consts::PI;

/// Length of the impulse response [`Chain::normalise`] sums. The slowest poles (the nasal
/// resonance, 290 Hz at Q 2.5, and the high-pass) decay with time constants under 3 ms, so
/// after 0.1 s a squared sample lies about 300 dB under the first ones, far below the last bit
/// of the sum: a longer response gives the same bits, and only costs time at every `prepare`
/// (a plugin prepares at every activation), in subnormal arithmetic at the end.
const IMPULSE_S: f64 = 0.1;
const CROSSFADE_S: f64 = 0.05;
const MIN_RAMP_S: f64 = 0.01;
const FLUTTER_HZ: f64 = 6.0;
const FLUTTER_DEPTH: f64 = 0.2;
/// Share of a breath's length its attack takes.
const ATTACK_SHARE: f64 = 0.30;
/// Share of a breath's length its release takes.
const RELEASE_SHARE: f64 = 0.35;

/// A resonator bank followed by the shared band limits.
#[derive(Debug, Clone)]
struct Chain<const N: usize> {
    bank: [Biquad; N],
    gains: [f64; N],
    post: [Biquad; 4],
    /// 1 / sqrt(noise power gain) at the nominal resonances.
    norm: f64,
}

impl<const N: usize> Chain<N> {
    fn new() -> Self {
        Self {
            bank: [Biquad::default(); N],
            gains: [0.0; N],
            post: [Biquad::default(); 4],
            norm: 1.0,
        }
    }

    fn design(&mut self, table: &[(f64, f64, f64); N], scale: f64, fs: f64) {
        for (i, &(f, q, g)) in table.iter().enumerate() {
            let f = f * scale;
            if f < 0.45 * fs {
                self.bank[i].bandpass(f, q, fs);
                self.gains[i] = g;
            } else {
                self.gains[i] = 0.0;
            }
        }
        let lp = LOWPASS_HZ.min(0.45 * fs);
        self.post[0].highpass(HIGHPASS_HZ, BUTTER4_Q[0], fs);
        self.post[1].highpass(HIGHPASS_HZ, BUTTER4_Q[1], fs);
        self.post[2].lowpass(lp, BUTTER4_Q[0], fs);
        self.post[3].lowpass(lp, BUTTER4_Q[1], fs);
    }

    fn clear(&mut self) {
        self.bank.iter_mut().for_each(Biquad::clear);
        self.post.iter_mut().for_each(Biquad::clear);
    }

    #[inline]
    fn tick(&mut self, x: f64) -> f64 {
        let mut y = 0.0;
        for (b, g) in self.bank.iter_mut().zip(self.gains.iter()) {
            if *g != 0.0 {
                y += g * b.tick(x);
            }
        }
        for p in self.post.iter_mut() {
            y = p.tick(y);
        }
        y
    }

    /// Measures the noise power gain from the impulse response (allocation-free).
    fn normalise(&mut self, fs: f64) {
        let energy = self.impulse_energy(fs, IMPULSE_S);
        self.norm = if energy > 0.0 {
            1.0 / energy.sqrt()
        } else {
            0.0
        };
    }

    /// The energy of the first `seconds` of the impulse response; leaves the chain clear.
    fn impulse_energy(&mut self, fs: f64, seconds: f64) -> f64 {
        self.clear();
        let n = (seconds * fs) as usize;
        let mut energy = 0.0;
        for i in 0..n {
            let y = self.tick(if i == 0 { 1.0 } else { 0.0 });
            energy += y * y;
        }
        self.clear();
        energy
    }
}

#[derive(Debug, Clone, Copy)]
struct Envelope {
    pos: usize,
    length: usize,
    attack: usize,
    release: usize,
    /// A fade-out: (start position, length, level at the start).
    fade: Option<(usize, usize, f64)>,
}

impl Envelope {
    /// The mean square of [`Envelope::at`] over the breath (no fade). A raised-cosine ramp of
    /// `n` samples taken at their centres sums its squares (sin⁴) to 3n/8 for n ≥ 2 (the
    /// cosine terms cancel over the samples), 1/4 for n = 1; the plateau's are 1.
    fn mean_square(&self) -> f64 {
        let ramp = |n: usize| {
            if n >= 2 {
                0.375 * n as f64
            } else {
                0.25 * n as f64
            }
        };
        let plateau = self.length.saturating_sub(self.attack + self.release);
        (ramp(self.attack) + ramp(self.release) + plateau as f64) / self.length.max(1) as f64
    }

    fn at(&self, i: usize) -> f64 {
        let ramp = |u: f64| 0.5 - 0.5 * (PI * u.clamp(0.0, 1.0)).cos();
        let base = if i < self.attack {
            ramp((i as f64 + 0.5) / self.attack as f64)
        } else if i + self.release >= self.length {
            ramp((self.length - i) as f64 / self.release as f64 - 0.5 / self.release as f64)
        } else {
            1.0
        };
        match self.fade {
            Some((start, len, level)) if i >= start => {
                let u = (i - start) as f64 / len.max(1) as f64;
                (level * (1.0 - ramp(u))).min(base)
            }
            _ => base,
        }
    }
}

#[derive(Debug, Clone, Default)]
struct SlotData {
    original: Option<BreathSample>,
    /// The sample at the stream rate (unit RMS), empty until prepared.
    fitted: Vec<f32>,
}

/// The breath-sound voice (see the module docs).
#[derive(Debug, Clone)]
pub struct BreathVoice {
    seed: u64,
    rng: SeededRng,
    rng_nose: SeededRng,
    sample_rate_hz: f64,
    mouth: Chain<6>,
    nose: Chain<4>,
    slots: [SlotData; 2],
    env: Option<Envelope>,
    weight_mouth: f64,
    weight_nose: f64,
    gain: f64,
    flutter_state: f64,
    flutter_coef: f64,
    flutter_norm: f64,
    xfade: usize,
    kind: BreathKind,
    /// The sound of a learned voice (made by [`BreathVoice::set_learned`], so a voice learned
    /// while streaming can take it over without allocating).
    learned: Option<LearnedSound>,
    /// Breaths are drawn from `learned` (a voice is in use).
    learned_on: bool,
    /// The current breath is drawn from `learned`.
    use_learned: bool,
    /// Level of a learned breath relative to the learned level, dB (the user's level).
    learned_offset_db: f64,
    /// The upper edge of the recording's spectrum, Hz, for the next breath.
    upper_edge_hz: Option<f64>,
    /// The low-pass of the current breath at that edge ([`band_limit`]).
    band_limit: BandLimit,
}

impl BreathVoice {
    /// A voice whose noise is seeded by `seed`. Call [`BreathVoice::prepare`] before rendering.
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            rng: SeededRng::new(seed),
            rng_nose: SeededRng::new(seed ^ 0x6E6F_7365_6E6F_7365),
            sample_rate_hz: 0.0,
            mouth: Chain::new(),
            nose: Chain::new(),
            slots: [SlotData::default(), SlotData::default()],
            env: None,
            weight_mouth: 0.0,
            weight_nose: 0.0,
            gain: 0.0,
            flutter_state: 0.0,
            flutter_coef: 0.0,
            flutter_norm: 1.0,
            xfade: 0,
            kind: BreathKind::Mixed,
            learned: None,
            learned_on: false,
            use_learned: false,
            learned_offset_db: 0.0,
            upper_edge_hz: None,
            band_limit: BandLimit::default(),
        }
    }

    /// Designs the filters for `sample_rate_hz` (8–768 kHz) and fits user samples to it. Any block
    /// size works with [`BreathVoice::render_add`]; `max_block` is accepted for the common
    /// life-cycle and not needed.
    pub fn prepare(&mut self, sample_rate_hz: f64, _max_block: usize) {
        let fs = sample_rate_hz.clamp(8_000.0, 768_000.0);
        self.sample_rate_hz = fs;
        self.mouth.design(&MOUTH_BANK, 1.0, fs);
        self.mouth.normalise(fs);
        self.nose.design(&NOSE_BANK, 1.0, fs);
        self.nose.normalise(fs);
        self.flutter_coef = (-2.0 * PI * FLUTTER_HZ / fs).exp();
        let a = self.flutter_coef;
        self.flutter_norm = ((1.0 + a) / (1.0 - a)).sqrt();
        self.xfade = (CROSSFADE_S * fs) as usize;
        for slot in self.slots.iter_mut() {
            slot.fitted = slot
                .original
                .as_ref()
                .map(|s| s.resampled(fs))
                .unwrap_or_default();
        }
        if let Some(l) = self.learned.as_mut() {
            l.prepare(fs);
        }
        self.reset();
    }

    /// Silences the voice and restarts its noise from the seed.
    pub fn reset(&mut self) {
        self.rng = SeededRng::new(self.seed);
        self.rng_nose = SeededRng::new(self.seed ^ 0x6E6F_7365_6E6F_7365);
        self.env = None;
        self.flutter_state = 0.0;
        self.mouth.clear();
        self.nose.clear();
        if let Some(l) = self.learned.as_mut() {
            l.reset();
        }
        self.upper_edge_hz = None;
        self.band_limit.set(None, self.sample_rate_hz);
    }

    /// The recording's spectrum ends at `edge_hz` (`None`: not known): breaths from the next
    /// one on stay under it when it is a band limit ([`band_limit::corner_hz`]), whatever their
    /// source (built-in, learned or a user's sample). Allocation-free.
    pub fn set_upper_edge_hz(&mut self, edge_hz: Option<f64>) {
        self.upper_edge_hz = edge_hz;
    }

    /// Draws breaths from `voice` (learned from the recording) instead of the procedural sound
    /// (`None`: back to it); a user sample still wins. Makes the learned sound either way, so
    /// [`BreathVoice::use_learned`] can switch voices later without allocating; call it off
    /// the audio thread.
    pub fn set_learned(&mut self, voice: Option<LearnedVoice>) {
        let mut l = LearnedSound::new(voice.unwrap_or_default(), self.seed ^ 0x6C65_6172_6E65_6421);
        if self.sample_rate_hz > 0.0 {
            l.prepare(self.sample_rate_hz);
        }
        self.learned = Some(l);
        self.learned_on = voice.is_some();
    }

    /// Draws breaths from `voice` from the next breath on (`None`: the procedural sound), in
    /// the sound [`BreathVoice::set_learned`] made (without it, nothing changes).
    /// Allocation-free: for a voice learned while streaming.
    pub fn use_learned(&mut self, voice: Option<&LearnedVoice>) {
        if let Some(l) = self.learned.as_mut() {
            if let Some(v) = voice {
                l.set_voice(*v);
            }
            self.learned_on = voice.is_some();
        }
    }

    /// The learned voice in use, if any.
    pub fn learned(&self) -> Option<&LearnedVoice> {
        self.learned
            .as_ref()
            .filter(|_| self.learned_on)
            .map(LearnedSound::voice)
    }

    /// Level of learned breaths relative to the learned level, dB (the user's breath level
    /// relative to its default). Applies from the next breath.
    pub fn set_learned_offset_db(&mut self, db: f64) {
        self.learned_offset_db = db;
    }

    /// Uses `sample` instead of the procedural sound of `kind` (`None` goes back to procedural).
    /// Allocates (resamples to the stream rate): call it off the audio thread.
    pub fn set_sample(&mut self, kind: SampleSlot, sample: Option<BreathSample>) {
        let slot = &mut self.slots[kind as usize];
        slot.fitted = match (&sample, self.sample_rate_hz > 0.0) {
            (Some(s), true) => s.resampled(self.sample_rate_hz),
            _ => Vec::new(),
        };
        slot.original = sample;
    }

    /// Starts a breath now: `mouth_vs_nose` 0 (nose) .. 1 (mouth), `length_samples` long,
    /// `gain` = linear RMS of the envelope plateau. A breath already playing is replaced (its
    /// filters keep their state, so there is no click beyond the new envelope's onset).
    pub fn start(&mut self, mouth_vs_nose: f32, length_samples: usize, gain: f32) {
        if self.sample_rate_hz <= 0.0 || length_samples == 0 {
            self.env = None;
            return;
        }
        let m = if mouth_vs_nose.is_finite() {
            mouth_vs_nose.clamp(0.0, 1.0) as f64
        } else {
            0.5
        };
        let (wm, wn) = (m, 1.0 - m);
        let norm = (wm * wm + wn * wn).sqrt();
        self.weight_mouth = wm / norm;
        self.weight_nose = wn / norm;
        self.gain = if gain.is_finite() {
            gain.max(0.0) as f64
        } else {
            0.0
        };
        let fs = self.sample_rate_hz;
        self.band_limit
            .set(band_limit::corner_hz(self.upper_edge_hz, fs), fs);
        let scale = 0.95 + 0.1 * self.rng.uniform();
        self.mouth.design(&MOUTH_BANK, scale, fs);
        self.nose.design(&NOSE_BANK, scale, fs);
        let min_ramp = ((MIN_RAMP_S * fs) as usize).max(1);
        let mut attack = ((ATTACK_SHARE * length_samples as f64) as usize).max(min_ramp);
        let mut release = ((RELEASE_SHARE * length_samples as f64) as usize).max(min_ramp);
        if attack + release > length_samples {
            attack = length_samples / 2;
            release = length_samples - attack;
        }
        self.env = Some(Envelope {
            pos: 0,
            length: length_samples,
            attack: attack.max(1),
            release: release.max(1),
            fade: None,
        });
        // A user's sample plays its share of every breath and beats a learned voice, whichever
        // of the two sounds it is (a nose sample with an even mouth share was once left out).
        let sampled = [(SampleSlot::Mouth, wm), (SampleSlot::Nose, wn)]
            .iter()
            .any(|&(slot, w)| w > 0.0 && !self.slots[slot as usize].fitted.is_empty());
        self.use_learned = false;
        if let (Some(l), false, true) = (self.learned.as_mut(), sampled, self.learned_on) {
            l.start(m);
            self.use_learned = true;
            // The learned level is the breath's level over its length: the plateau is louder by
            // the envelope's mean square (in closed form: no loop over the breath on the audio
            // thread, which at 768 kHz was a million cosines in one block).
            let rms = 10f64.powf((l.rms_db() + self.learned_offset_db) / 20.0);
            let env = self.env.as_ref().expect("set above");
            self.gain = rms / env.mean_square().max(1e-6).sqrt();
        }
        self.kind = if sampled {
            BreathKind::Sample
        } else if m >= 0.75 {
            BreathKind::Mouth
        } else if m <= 0.25 {
            BreathKind::Nose
        } else {
            BreathKind::Mixed
        };
    }

    /// Fades the current breath out over `length_samples` (raised cosine from its current
    /// level); it ends no later than its own end. No effect when idle.
    pub fn fade_out(&mut self, length_samples: usize) {
        if let Some(env) = self.env.as_mut() {
            let level = env.at(env.pos);
            let len = length_samples.max(1);
            env.fade = Some((env.pos, len, level));
            if env.pos + len < env.length {
                // The fade alone shapes the end; the trapezoid's release no longer applies.
                env.length = env.pos + len;
                env.release = 1;
            }
        }
    }

    /// Whether a breath is playing.
    pub fn is_active(&self) -> bool {
        self.env.is_some()
    }

    /// The kind of the current (or last) breath.
    pub fn kind(&self) -> BreathKind {
        self.kind
    }

    /// Adds the breath into `out` (mono, stream rate). Allocation-free; returns at once when
    /// idle.
    pub fn render_add(&mut self, out: &mut [f32]) {
        let Some(mut env) = self.env else {
            return;
        };
        let [mouth_slot, nose_slot] = &self.slots;
        let (wm, wn) = (self.weight_mouth, self.weight_nose);
        for o in out.iter_mut() {
            if env.pos >= env.length {
                self.env = None;
                return;
            }
            let e = env.at(env.pos);
            // Flutter: one-pole low-passed noise, unit variance.
            let x = (self.rng.uniform() * 2.0 - 1.0) * 3f64.sqrt();
            self.flutter_state =
                self.flutter_coef * self.flutter_state + (1.0 - self.flutter_coef) * x;
            let flutter =
                1.0 + FLUTTER_DEPTH * (self.flutter_state * self.flutter_norm).clamp(-3.0, 3.0);
            let mut v = 0.0;
            if self.use_learned {
                if let Some(l) = self.learned.as_mut() {
                    v = l.tick() * flutter;
                }
            } else if wm > 0.0 {
                v += wm
                    * if mouth_slot.fitted.is_empty() {
                        let n = (self.rng.uniform() * 2.0 - 1.0) * 3f64.sqrt();
                        self.mouth.tick(n) * self.mouth.norm * flutter
                    } else {
                        fitted_at(&mouth_slot.fitted, env.pos, env.length, self.xfade) as f64
                    };
            }
            if wn > 0.0 && !self.use_learned {
                v += wn
                    * if nose_slot.fitted.is_empty() {
                        let n = (self.rng_nose.uniform() * 2.0 - 1.0) * 3f64.sqrt();
                        self.nose.tick(n) * self.nose.norm * flutter
                    } else {
                        fitted_at(&nose_slot.fitted, env.pos, env.length, self.xfade) as f64
                    };
            }
            *o += self.band_limit.tick(v * e * self.gain) as f32;
            env.pos += 1;
        }
        self.env = Some(env);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_envelopes_mean_square_in_closed_form_is_the_sum_of_its_samples() {
        for (length, attack, release) in [(1000, 300, 200), (48_000, 14_400, 9_600), (3, 1, 1)]
            .into_iter()
            .chain([(10, 2, 8), (7, 3, 2), (2, 1, 1)])
        {
            let env = Envelope {
                pos: 0,
                length,
                attack,
                release,
                fade: None,
            };
            let summed = (0..length).map(|i| env.at(i).powi(2)).sum::<f64>() / length as f64;
            assert!(
                (env.mean_square() - summed).abs() < 1e-9,
                "{length}/{attack}/{release}: {} vs {summed}",
                env.mean_square()
            );
        }
    }

    #[test]
    fn a_longer_impulse_response_gives_the_same_normalisation_at_every_rate() {
        for fs in [8_000.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0, 768_000.0] {
            let mut mouth = Chain::new();
            mouth.design(&MOUTH_BANK, 1.0, fs);
            let mut nose = Chain::new();
            nose.design(&NOSE_BANK, 0.95, fs);
            for (name, short, long) in [
                (
                    "mouth",
                    mouth.impulse_energy(fs, IMPULSE_S),
                    mouth.impulse_energy(fs, 1.0),
                ),
                (
                    "nose",
                    nose.impulse_energy(fs, IMPULSE_S),
                    nose.impulse_energy(fs, 1.0),
                ),
            ] {
                assert!(short > 0.0, "{name} at {fs} Hz");
                assert_eq!(short.to_bits(), long.to_bits(), "{name} at {fs} Hz");
            }
        }
    }
}
