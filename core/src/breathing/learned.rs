//! A breath voice learned from the speaker's own inhalations ([`LearnedVoice`]) and the sound
//! drawn from it ([`LearnedSound`]).
//!
//! # What is learned
//! From every real inhalation heard in a recording ([`HeardBreath`]: its third-octave band
//! powers and its length) and the recording's noise floor
//! ([`super::third_octave::FloorEstimate`]):
//! - the **spectral envelope**: the mean over the breaths of each one's third-octave shape
//!   ([`super::third_octave`], 250 Hz–6.3 kHz, dB relative to its own mean) with the floor's
//!   band powers taken out first, and per band the standard deviation of the shapes;
//! - the **level under the speech**: the median of the breaths' levels minus the speech level
//!   (the median RMS of the recording's voiced frames), and its spread. A breath's level is its
//!   mean square in the bands with the floor's band powers taken out
//!   ([`super::third_octave::band_level_db`]), the level the evaluations measure real and
//!   inserted breaths at;
//! - the **length**: median and spread (reported; the placement decides each breath's length).
//!
//! With fewer than [`MIN_FOR_SPREAD`] breaths the spreads are the priors below (the spread of
//! real breaths around their speaker's mean measured on the labelled breaths of issue 31), and
//! the level is never louder than the built-in voice's (the breath level setting's default
//! under the speech): one or two loud sounds heard as breaths in a recording whose breaths
//! were cut out are as often a scrap the gate let through, a word's end or a music bed as a
//! breath; quiet ones are this speaker's. With more, the level is never louder than
//! [`MAX_LEVEL_RE_SPEECH_DB`].
//!
//! # The sound
//! Seeded white noise, independent for each band, through one band-pass (RBJ, 0 dB peak, Q of
//! a third octave) per band and the built-in voice's band limits (4th-order high-pass at
//! 180 Hz, low-pass at min(8 kHz, 0.45 × rate)). The band weights are solved at each breath's
//! start so that the sound's band powers, as the third-octave measurement sees them (the FFT
//! bins in each band), follow the target shape, accounting for each filter's response in the
//! neighbouring bands (a fixed-point iteration on the analytic responses computed at
//! `prepare`); the output has unit power, and [`LearnedSound::rms_db`] is the RMS that puts its
//! level in the bands at the drawn level. Each breath draws its target shape as
//! the learned envelope plus, per band, a normal deviate times the learned spread, and its level
//! as the learned level plus a normal deviate times the level spread (both clamped to ±2
//! standard deviations; the level never over [`MAX_LEVEL_RE_SPEECH_DB`]). Allocation-free after
//! `prepare`.

use std::f64::consts::PI;

use super::filters::{Biquad, Phasor, BUTTER4_Q, HIGHPASS_HZ, LOWPASS_HZ};
use super::third_octave::{
    band_edge_ratio, band_level_db, band_of, frame_len, shape_db, without_floor, Bands, BANDS,
    BAND_CENTRES_HZ,
};
use crate::rng::SeededRng;
use crate::settings::breathing::MOUTH_VS_NOSE;
use crate::settings::placement::BREATH_LEVEL_DB;

/// Breaths needed before the spreads are measured rather than the priors.
pub const MIN_FOR_SPREAD: usize = 3;
/// Prior spread of a breath's shape per band, dB.
pub const SHAPE_SD_PRIOR_DB: f64 = 1.5;
/// Prior spread of a breath's level, dB.
pub const LEVEL_SD_PRIOR_DB: f64 = 2.0;
/// Loudest learned level under the speech, dB: the loud end of real speakers' breath levels
/// (issue 15's −17 to −24 dB; the eleven labelled speakers' medians lie at −38 to −21 dB, those
/// the engine hears at −34 to −19 dB). Louder "breaths" are a bed or a word heard as breaths.
pub const MAX_LEVEL_RE_SPEECH_DB: f64 = -17.0;
/// Two speech levels this far apart or more are two speakers, dB: one speaker's phrases wander a
/// few dB around their median, two voices recorded apart (an interview's quieter guest) lie
/// further. A speaker within it of the recording's speech level is its main voice: breaths are
/// measured and played against the speech level, as for one speaker; further off, against the
/// speaker's own level ([`speaker_reference_db`], the engine's speaker level).
pub const SAME_SPEAKER_DB: f64 = 6.0;

/// The level a breath of a speaker at `speaker_level_db` is measured and played under: the
/// speech level `speech_db` for the main voice ([`SAME_SPEAKER_DB`]) and an unknown speaker
/// (NaN), else the speaker's own level, dBFS.
pub fn speaker_reference_db(speaker_level_db: f64, speech_db: f64) -> f64 {
    if speaker_level_db.is_finite() && (speaker_level_db - speech_db).abs() >= SAME_SPEAKER_DB {
        speaker_level_db
    } else {
        speech_db
    }
}
/// Largest spread per band or of the level, dB (a floor-dominated band is not a breath's).
const MAX_SD_DB: f64 = 4.0;
/// Deviates are clamped to this many standard deviations.
const MAX_DEVIATE: f64 = 2.0;
/// Iterations of the band-weight solve.
const SOLVE_ITERATIONS: usize = 40;
/// The Hann window's power response is followed this many bins either side of a bin.
const KERNEL_BINS: f64 = 3.0;
/// Steps of the window's power response on each side.
const KERNEL_STEPS: i32 = 30;
/// Frequency steps of the analytic total power.
const STEPS_TOTAL: usize = 4096;

/// One real inhalation heard in a recording.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeardBreath {
    /// Mean power per third-octave band ([`super::third_octave::BandAnalyzer::powers`]).
    pub powers: Bands,
    /// Length, seconds.
    pub length_s: f64,
    /// The level of its speaker (the one who spoke next), dBFS (NaN: not known): its level is
    /// measured against [`speaker_reference_db`].
    pub speaker_level_db: f64,
}

/// A breath voice learned from a recording (see the module docs). Plain data: saved with a
/// plugin's state when the user freezes it (serde).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct LearnedVoice {
    /// Breaths it was learned from.
    pub breaths: usize,
    /// Mean shape per band, dB relative to the bands' mean.
    pub shape_db: Bands,
    /// Spread of the shapes per band, dB.
    pub shape_sd_db: Bands,
    /// Median level of the breaths under the speech level, dB.
    pub level_re_speech_db: f64,
    /// Spread of the level, dB.
    pub level_sd_db: f64,
    /// The speech level it was measured against (median RMS of voiced frames), dBFS.
    pub speech_db: f64,
    /// Median length, seconds.
    pub length_s: f64,
    /// Spread of the length, seconds.
    pub length_sd_s: f64,
}

/// The median of `v` (NaN when empty), sorting it in place.
pub(crate) fn median(v: &mut [f64]) -> f64 {
    // Unstable sort: in place, no allocation (the median is the same).
    v.sort_unstable_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

fn sd(v: impl Iterator<Item = f64> + Clone) -> f64 {
    let n = v.clone().count() as f64;
    let m = v.clone().sum::<f64>() / n;
    (v.map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt()
}

/// Working memory of [`LearnedVoice::learn_with`] for up to `capacity` breaths: made once, so
/// a stream can learn again at every breath without allocating.
#[derive(Debug, Clone, Default)]
pub struct LearnScratch {
    shapes: Vec<Bands>,
    levels: Vec<f64>,
    lengths: Vec<f64>,
}

impl LearnScratch {
    /// Room for `capacity` breaths. Allocates.
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            shapes: Vec::with_capacity(capacity),
            levels: Vec::with_capacity(capacity),
            lengths: Vec::with_capacity(capacity),
        }
    }
}

impl LearnedVoice {
    /// The voice of `breaths` (measured at `rate_hz`) in a room whose floor has band powers
    /// `floor_powers`, against speech at `speech_db`; `None` without a breath.
    pub fn learn(
        breaths: &[HeardBreath],
        floor_powers: &Bands,
        speech_db: f64,
        rate_hz: f64,
    ) -> Option<Self> {
        let mut scratch = LearnScratch::with_capacity(breaths.len());
        Self::learn_with(breaths, floor_powers, speech_db, rate_hz, &mut scratch)
    }

    /// [`LearnedVoice::learn`] in `scratch`: allocation-free while `breaths` fits its capacity.
    pub fn learn_with(
        breaths: &[HeardBreath],
        floor_powers: &Bands,
        speech_db: f64,
        rate_hz: f64,
        scratch: &mut LearnScratch,
    ) -> Option<Self> {
        if breaths.is_empty() || !speech_db.is_finite() {
            return None;
        }
        let LearnScratch {
            shapes,
            levels,
            lengths,
        } = scratch;
        shapes.clear();
        levels.clear();
        lengths.clear();
        for b in breaths {
            let clean = without_floor(&b.powers, floor_powers);
            shapes.push(shape_db(&clean));
            let reference_db = speaker_reference_db(b.speaker_level_db, speech_db);
            levels.push(band_level_db(&clean, rate_hz) - reference_db);
            lengths.push(b.length_s);
        }
        let n = breaths.len();
        let mean: Bands =
            std::array::from_fn(|k| shapes.iter().map(|s| s[k]).sum::<f64>() / n as f64);
        let spread = n >= MIN_FOR_SPREAD;
        let shape_sd_db: Bands = std::array::from_fn(|k| {
            if spread {
                sd(shapes.iter().map(|s| s[k])).min(MAX_SD_DB)
            } else {
                SHAPE_SD_PRIOR_DB
            }
        });
        let level_sd_db = if spread {
            sd(levels.iter().copied()).min(MAX_SD_DB)
        } else {
            LEVEL_SD_PRIOR_DB
        };
        let length_sd_s = if spread {
            sd(lengths.iter().copied())
        } else {
            0.2 * lengths[0]
        };
        let level_re_speech_db = median(levels).min(if spread {
            MAX_LEVEL_RE_SPEECH_DB
        } else {
            f64::from(BREATH_LEVEL_DB.default)
        });
        Some(Self {
            breaths: n,
            shape_db: mean,
            shape_sd_db,
            level_re_speech_db,
            level_sd_db,
            speech_db,
            length_s: median(lengths),
            length_sd_s,
        })
    }

    /// The same voice for a recording whose speech lies at `speech_db` (a voice learned from
    /// another take keeps its level under the speech); unchanged when `speech_db` is not finite.
    pub fn against_speech_db(self, speech_db: f64) -> Self {
        if speech_db.is_finite() {
            Self { speech_db, ..self }
        } else {
            self
        }
    }

    /// The learned level of a breath (its mean square in the bands over its length), dBFS.
    pub fn level_db(&self) -> f64 {
        self.speech_db + self.level_re_speech_db
    }
}

/// Power response of a Hann window at `d` bins from a bin's centre (the window's transform:
/// half a Dirichlet kernel at the centre and a quarter either side one bin away, in the sinc
/// approximation), 1 at the centre.
fn hann_power(d: f64) -> f64 {
    let sinc = |x: f64| {
        if x.abs() < 1e-9 {
            1.0
        } else {
            (PI * x).sin() / (PI * x)
        }
    };
    (0.5 * sinc(d) + 0.25 * sinc(d - 1.0) + 0.25 * sinc(d + 1.0)).powi(2) / 0.25
}

/// Power gain of the 4th-order band limits at the frequency of `p`.
fn post_power(post: &[Biquad; 4], p: &Phasor) -> f64 {
    post.iter().map(|b| b.power_gain_at(p)).product()
}

/// The sound drawn from a [`LearnedVoice`] (see the module docs).
#[derive(Debug, Clone)]
pub struct LearnedSound {
    voice: LearnedVoice,
    seed: u64,
    rng: SeededRng,
    bank: [Biquad; BANDS],
    post: [Biquad; 4],
    /// `response[i][j]`: power in band `i` of filter `j` (with the band limits) for unit white
    /// noise.
    response: [[f64; BANDS]; BANDS],
    /// Total power of filter `j` (with the band limits) for unit white noise.
    total: Bands,
    /// Bands the rate can hold.
    usable: [bool; BANDS],
    /// Amplitude of each band's noise for the current breath.
    gains: Bands,
    /// The current breath's level offset from the learned level, dB.
    level_offset_db: f64,
    /// Share of the current breath's power in the bands.
    band_share: f64,
    /// The procedural mouth sound's tilt over the nose sound's, dB per band
    /// ([`super::banks::mouth_over_nose_tilt_db`]).
    mouth_over_nose_tilt_db: Bands,
}

impl LearnedSound {
    /// The sound of `voice`, its noise seeded by `seed`; call [`LearnedSound::prepare`].
    pub fn new(voice: LearnedVoice, seed: u64) -> Self {
        Self {
            voice,
            seed,
            rng: SeededRng::new(seed),
            bank: [Biquad::default(); BANDS],
            post: [Biquad::default(); 4],
            response: [[0.0; BANDS]; BANDS],
            total: [0.0; BANDS],
            usable: [false; BANDS],
            gains: [0.0; BANDS],
            level_offset_db: 0.0,
            band_share: 1.0,
            mouth_over_nose_tilt_db: super::banks::mouth_over_nose_tilt_db(),
        }
    }

    /// The voice it draws from.
    pub fn voice(&self) -> &LearnedVoice {
        &self.voice
    }

    /// Draws from `voice` from the next breath on (a voice learned further while streaming).
    /// Allocation-free; the noise goes on where it was.
    pub fn set_voice(&mut self, voice: LearnedVoice) {
        self.voice = voice;
    }

    /// Designs the filters for `fs` Hz and computes their band responses; resets.
    pub fn prepare(&mut self, fs: f64) {
        let edge = band_edge_ratio();
        let q = 1.0 / (edge - 1.0 / edge);
        for (j, &c) in BAND_CENTRES_HZ.iter().enumerate() {
            self.usable[j] = c * edge < 0.45 * fs;
            self.bank[j].bandpass(c, q, fs);
        }
        let lp = LOWPASS_HZ.min(0.45 * fs);
        self.post[0].highpass(HIGHPASS_HZ, BUTTER4_Q[0], fs);
        self.post[1].highpass(HIGHPASS_HZ, BUTTER4_Q[1], fs);
        self.post[2].lowpass(lp, BUTTER4_Q[0], fs);
        self.post[3].lowpass(lp, BUTTER4_Q[1], fs);
        // Unit white noise has power 2 / fs per Hz up to fs / 2. The band powers are those the
        // third-octave measurement sees: the FFT bins that fall in each band.
        let density = 2.0 / fs;
        let w_of = |hz: f64| 2.0 * PI * hz / fs;
        let frame = frame_len(fs);
        let bin_hz = fs / frame as f64;
        self.response = [[0.0; BANDS]; BANDS];
        // Each bin sees the spectrum through the Hann window's power response (±3 bins).
        let kernel: Vec<(f64, f64)> = (-KERNEL_STEPS..=KERNEL_STEPS)
            .map(|s| {
                let d = s as f64 * KERNEL_BINS / KERNEL_STEPS as f64;
                (d, hann_power(d))
            })
            .collect();
        let kernel_sum: f64 = kernel.iter().map(|(_, p)| p).sum();
        // Only the bins inside the bands count: the cost stays the same at every rate. One
        // phasor per frequency serves the band limits and every band's filter.
        let lowest = (BAND_CENTRES_HZ[0] / edge / bin_hz).floor() as usize;
        let highest = (BAND_CENTRES_HZ[BANDS - 1] * edge / bin_hz).ceil() as usize;
        for k in lowest..=highest.min(frame / 2) {
            let Some(i) = band_of(k as f64 * bin_hz) else {
                continue;
            };
            for &(d, weight) in &kernel {
                let hz = (k as f64 + d) * bin_hz;
                if !(0.0..=0.5 * fs).contains(&hz) {
                    continue;
                }
                let at = Phasor::at(w_of(hz));
                let post = post_power(&self.post, &at);
                for j in 0..BANDS {
                    self.response[i][j] += self.bank[j].power_gain_at(&at) * post * weight
                        / kernel_sum
                        * bin_hz
                        * density;
                }
            }
        }
        let df = 0.5 * fs / STEPS_TOTAL as f64;
        let steps: Vec<(Phasor, f64)> = (0..STEPS_TOTAL)
            .map(|s| {
                let at = Phasor::at(w_of((s as f64 + 0.5) * df));
                (at, post_power(&self.post, &at))
            })
            .collect();
        for j in 0..BANDS {
            self.total[j] = steps
                .iter()
                .map(|(at, post)| self.bank[j].power_gain_at(at) * post)
                .sum::<f64>()
                * df
                * density;
        }
        self.reset();
    }

    /// Silence; the noise restarts from the seed.
    pub fn reset(&mut self) {
        self.rng = SeededRng::new(self.seed);
        self.bank.iter_mut().for_each(Biquad::clear);
        self.post.iter_mut().for_each(Biquad::clear);
    }

    /// Band weights (powers of each filter's noise) whose band powers follow `target` (band
    /// powers, any scale), normalised to unit total power.
    fn solve(&self, target: &Bands) -> Bands {
        let mut w: Bands = std::array::from_fn(|j| if self.usable[j] { target[j] } else { 0.0 });
        for _ in 0..SOLVE_ITERATIONS {
            for j in 0..BANDS {
                if !self.usable[j] {
                    continue;
                }
                let got: f64 = (0..BANDS).map(|k| self.response[j][k] * w[k]).sum();
                if got > 0.0 {
                    w[j] *= target[j] / got;
                }
            }
        }
        let total: f64 = (0..BANDS).map(|j| w[j] * self.total[j]).sum();
        w.map(|x| if total > 0.0 { x / total } else { 0.0 })
    }

    /// A normal deviate clamped to ±[`MAX_DEVIATE`].
    fn deviate(&mut self) -> f64 {
        self.rng.normal().clamp(-MAX_DEVIATE, MAX_DEVIATE)
    }

    /// Starts a breath: draws its shape and level (see the module docs), coloured towards a
    /// breath through the mouth or the nose by `mouth_share` (0 nose .. 1 mouth). At the
    /// default `mouth_vs_nose` the learned shape is as learned (a speaker's breaths are their
    /// own mix of the two); else it moves by the share's distance from that default times the
    /// procedural mouth sound's tilt over the nose sound's. Allocation-free.
    pub fn start(&mut self, mouth_share: f64) {
        let colour = mouth_share.clamp(0.0, 1.0) - f64::from(MOUTH_VS_NOSE.default);
        let mut target = [0.0; BANDS];
        for (k, t) in target.iter_mut().enumerate() {
            let db = self.voice.shape_db[k]
                + colour * self.mouth_over_nose_tilt_db[k]
                + self.voice.shape_sd_db[k] * self.deviate();
            *t = 10f64.powf(db / 10.0);
        }
        // Varied within the spread, never over the loud end of real breaths.
        self.level_offset_db = (self.voice.level_sd_db * self.deviate())
            .min(MAX_LEVEL_RE_SPEECH_DB - self.voice.level_re_speech_db);
        let weights = self.solve(&target);
        let in_bands: f64 = (0..BANDS)
            .map(|i| {
                (0..BANDS)
                    .map(|j| self.response[i][j] * weights[j])
                    .sum::<f64>()
            })
            .sum();
        self.band_share = if in_bands > 0.0 { in_bands } else { 1.0 };
        self.gains = weights.map(f64::sqrt);
    }

    /// The current breath's level (its mean square in the bands over its length), dBFS.
    pub fn level_db(&self) -> f64 {
        self.voice.level_db() + self.level_offset_db
    }

    /// The RMS over its length (all of the sound, in and out of the bands) that puts the
    /// current breath at [`LearnedSound::level_db`], dBFS.
    pub fn rms_db(&self) -> f64 {
        self.level_db() - 10.0 * self.band_share.log10()
    }

    /// The next sample (unit power).
    #[inline]
    pub fn tick(&mut self) -> f64 {
        let mut y = 0.0;
        for j in 0..BANDS {
            if self.gains[j] > 0.0 {
                let n = (self.rng.uniform() * 2.0 - 1.0) * 3f64.sqrt();
                y += self.gains[j] * self.bank[j].tick(n);
            }
        }
        for p in self.post.iter_mut() {
            y = p.tick(y);
        }
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::breathing::third_octave::{band_powers, distance_db};

    fn voice(shape_db: Bands, sd_db: f64) -> LearnedVoice {
        LearnedVoice {
            breaths: 5,
            shape_db,
            shape_sd_db: [sd_db; BANDS],
            level_re_speech_db: -25.0,
            level_sd_db: 0.0,
            speech_db: -20.0,
            length_s: 0.4,
            length_sd_s: 0.05,
        }
    }

    fn render(sound: &mut LearnedSound, n: usize) -> Vec<f32> {
        sound.start(f64::from(MOUTH_VS_NOSE.default));
        (0..n).map(|_| sound.tick() as f32).collect()
    }

    #[test]
    fn the_sound_follows_a_target_shape_within_a_db_per_band_and_has_unit_power() {
        let fs = 16_000.0;
        // A dark shape with a hump at 500 Hz and a slope down above.
        let target: Bands = std::array::from_fn(|k| {
            let x = k as f64;
            6.0 * (-(x - 3.0).powi(2) / 6.0).exp() - 0.8 * x
        });
        let target = shape_db(&target.map(|d| 10f64.powf(d / 10.0)));
        let mut s = LearnedSound::new(voice(target, 0.0), 7);
        s.prepare(fs);
        let x = render(&mut s, 8 * fs as usize);
        let got = shape_db(&band_powers(&x, fs));
        for k in 0..BANDS {
            assert!(
                (got[k] - target[k]).abs() < 1.0,
                "band {k}: {got:?} vs {target:?}"
            );
        }
        let p = x.iter().map(|v| (*v as f64).powi(2)).sum::<f64>() / x.len() as f64;
        assert!((10.0 * p.log10()).abs() < 0.5, "power {p}");
    }

    #[test]
    fn the_mouth_share_colours_the_learned_shape_brighter_or_darker() {
        // The procedural banks' tilt: the nose dark, the mouth bright.
        let colour = super::super::banks::mouth_over_nose_tilt_db();
        assert!(colour[0] < -6.0 && colour[BANDS - 1] > 6.0, "{colour:?}");
        // Sounds drawn at a mouth share of 1 and 0 differ by half that colour each way from
        // the learned shape (flat here), band by band.
        let fs = 16_000.0;
        let shape = |share: f64| {
            let mut s = LearnedSound::new(voice([0.0; BANDS], 0.0), 7);
            s.prepare(fs);
            s.start(share);
            let x: Vec<f32> = (0..8 * fs as usize).map(|_| s.tick() as f32).collect();
            shape_db(&band_powers(&x, fs))
        };
        let (mouth, nose) = (shape(1.0), shape(0.0));
        let want = shape_db(&colour.map(|d| 10f64.powf(d / 10.0)));
        for k in 0..BANDS {
            let got = mouth[k] - nose[k];
            assert!(
                (got - want[k]).abs() < 2.0,
                "band {k}: {got:.1} vs {:.1}",
                want[k]
            );
        }
        let neutral = shape(f64::from(MOUTH_VS_NOSE.default));
        assert!(neutral.iter().all(|d| d.abs() < 1.5), "{neutral:?}");
    }

    #[test]
    fn breaths_vary_within_the_learned_spread_and_repeat_from_the_seed() {
        let fs = 16_000.0;
        let mut s = LearnedSound::new(voice([0.0; BANDS], 1.5), 3);
        s.prepare(fs);
        let shapes: Vec<Bands> = (0..8)
            .map(|_| shape_db(&band_powers(&render(&mut s, fs as usize), fs)))
            .collect();
        let d = distance_db(&shapes[0], &shapes[1]);
        assert!(d > 0.8 && d < 5.0, "{d}");
        let mut again = LearnedSound::new(voice([0.0; BANDS], 1.5), 3);
        again.prepare(fs);
        assert_eq!(render(&mut again, 1000), {
            let mut first = LearnedSound::new(voice([0.0; BANDS], 1.5), 3);
            first.prepare(fs);
            render(&mut first, 1000)
        });
    }

    #[test]
    fn learning_takes_the_floor_out_and_falls_back_to_the_priors_with_few_breaths() {
        let fs = 16_000.0;
        // A tilted breath about 25 dB under speech at -20 dBFS, over a floor 6-20 dB under it.
        let tilt: Bands = std::array::from_fn(|k| 1e-4 * 10f64.powf(-(k as f64) / 10.0));
        let floor = [1e-6; BANDS];
        let b = HeardBreath {
            powers: std::array::from_fn(|k| tilt[k] + floor[k]),
            length_s: 0.5,
            speaker_level_db: f64::NAN,
        };
        let v = LearnedVoice::learn(&[b, b], &floor, -20.0, fs).expect("two breaths");
        let want = shape_db(&tilt);
        assert!(distance_db(&v.shape_db, &want) < 1e-9, "{:?}", v.shape_db);
        assert_eq!(v.shape_sd_db, [SHAPE_SD_PRIOR_DB; BANDS]);
        // The level is the tilt's alone, in the bands (quieter than the built-in voice's).
        let level = band_level_db(&tilt, fs) + 20.0;
        assert!(
            (v.level_re_speech_db - level).abs() < 1e-9,
            "{} vs {level}",
            v.level_re_speech_db
        );
        assert!(LearnedVoice::learn(&[], &floor, -20.0, fs).is_none());
    }

    #[test]
    fn drawn_levels_vary_but_never_over_the_loud_end_of_real_breaths() {
        // A voice learned from a bed: level 4.4 dB under the cap, spread at its largest.
        let v = LearnedVoice {
            level_re_speech_db: MAX_LEVEL_RE_SPEECH_DB - 4.4,
            level_sd_db: MAX_SD_DB,
            ..voice([0.0; BANDS], 1.5)
        };
        let mut s = LearnedSound::new(v, 11);
        s.prepare(16_000.0);
        let levels: Vec<f64> = (0..200)
            .map(|_| {
                s.start(f64::from(MOUTH_VS_NOSE.default));
                s.level_db() - v.speech_db
            })
            .collect();
        let loudest = levels.iter().copied().fold(f64::MIN, f64::max);
        let quietest = levels.iter().copied().fold(f64::MAX, f64::min);
        assert!(loudest <= MAX_LEVEL_RE_SPEECH_DB + 1e-9, "{loudest}");
        assert!(
            quietest < v.level_re_speech_db - 4.0,
            "still varied: {quietest}"
        );
    }

    #[test]
    fn one_or_two_loud_sounds_heard_as_breaths_never_make_loud_breaths() {
        // A recording whose breaths were gated out: what is heard as breaths is a scrap of a
        // word or a music bed, 6 dB under the speech. One or two of them give at most the
        // built-in level; more give at most the loud end of real breaths.
        let fs = 16_000.0;
        let floor = [1e-9; BANDS];
        let speech_db = -20.0;
        let loud = HeardBreath {
            powers: [1.0; BANDS],
            length_s: 0.2,
            speaker_level_db: f64::NAN,
        };
        let scale = 10f64.powf((speech_db - 6.0 - band_level_db(&loud.powers, fs)) / 10.0);
        let loud = HeardBreath {
            powers: loud.powers.map(|p| p * scale),
            ..loud
        };
        let heard_db = band_level_db(&loud.powers, fs) - speech_db;
        assert!((heard_db + 6.0).abs() < 1e-6, "{heard_db}");
        for n in 1..=5 {
            let v = LearnedVoice::learn(&vec![loud; n], &floor, speech_db, fs).expect("breaths");
            let want = if n < MIN_FOR_SPREAD {
                f64::from(BREATH_LEVEL_DB.default)
            } else {
                MAX_LEVEL_RE_SPEECH_DB
            };
            assert_eq!(v.level_re_speech_db, want, "{n} heard");
        }
    }

    #[test]
    fn a_breath_is_learned_at_the_level_its_own_sound_has_in_the_bands() {
        // A recording whose quiet frames hold rumble under 250 Hz as loud as the breaths (the
        // Keele clips): a breath is a third-octave noise 30 dB over the floor in every band.
        // Learned from its samples, its level is that of the same noise alone.
        let fs = 16_000.0;
        let mut rng = SeededRng::new(9);
        let mut noise = |n: usize, amp: f64| -> Vec<f32> {
            (0..n)
                .map(|_| ((rng.uniform() * 2.0 - 1.0) * amp) as f32)
                .collect()
        };
        let breath = noise(8000, 1e-2);
        let floor_bands: Bands = band_powers(&noise(8000, 1e-2 * 10f64.powf(-1.5)), fs);
        let rumble: Vec<f32> = (0..8000)
            .map(|i| (0.02 * (2.0 * PI * 40.0 * i as f64 / fs).sin()) as f32)
            .collect();
        let heard: Vec<f32> = breath.iter().zip(&rumble).map(|(b, r)| b + r).collect();
        let b = HeardBreath {
            powers: band_powers(&heard, fs),
            length_s: 0.5,
            speaker_level_db: f64::NAN,
        };
        let v = LearnedVoice::learn(&[b; 3], &floor_bands, -20.0, fs).expect("breaths");
        let alone = band_level_db(&band_powers(&breath, fs), fs) + 20.0;
        assert!(
            (v.level_re_speech_db - alone).abs() < 0.3,
            "learned {} vs the breath alone {alone}",
            v.level_re_speech_db
        );
    }

    #[test]
    fn a_drawn_breath_has_the_learned_level_in_the_bands() {
        // A dark voice (much of its power under 250 Hz and over 6.3 kHz is outside the bands).
        let fs = 16_000.0;
        let shape: Bands = std::array::from_fn(|k| -1.5 * k as f64);
        let mut s = LearnedSound::new(
            voice(shape_db(&shape.map(|d| 10f64.powf(d / 10.0))), 0.0),
            4,
        );
        s.prepare(fs);
        let x = render(&mut s, 4 * fs as usize);
        let gain = 10f64.powf(s.rms_db() / 20.0);
        let scaled: Vec<f32> = x.iter().map(|v| (f64::from(*v) * gain) as f32).collect();
        let got = band_level_db(&band_powers(&scaled, fs), fs);
        assert!(
            (got - s.level_db()).abs() < 0.5,
            "{got} vs the drawn level {}",
            s.level_db()
        );
    }
}
