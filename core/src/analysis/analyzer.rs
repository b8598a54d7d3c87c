//! [`Analyzer`]: the streaming analysis front end that owns the frame clock, the decimator, the
//! pitch estimator, the level meter, the voicing tracker and the speaker normalisation.
//!
//! Samples go in one by one (a block is a loop), so the frames depend only on the sample
//! sequence, never on how it was cut into blocks: any partition gives bit-identical frames.
//! Samples before the start of the stream count as zeros; a frame is emitted as soon as the last
//! sample of its analysis window has arrived (see [`Analyzer::latency_s`]).

use super::breath_band::BandMeter;
use super::clock::FrameClock;
use super::config::{check_sample_rate, AnalysisConfig, AnalysisError};
use super::decimator::{factor_for, Decimator};
use super::highpass::HighPass;
use super::noise_floor::NoiseFloor;
use super::pitch::NsdfPitch;
use super::speaker_norm::SpeakerNorm;
use super::tracking::Tracker;
use super::voicing::{VoicingEvidence, VoicingRule};
use super::{amplitude_to_db, FeatureFrame};

/// Input samples beyond this magnitude are clamped for analysis (+60 dBFS).
const INPUT_LIMIT: f32 = 1000.0;
/// Frames at least this periodic are voice, not background: they do not teach the noise floor.
const FLOOR_MAX_PERIODICITY: f32 = 0.9;

/// The streaming analysis front end. See the module docs.
#[derive(Debug)]
pub struct Analyzer {
    config: AnalysisConfig,
    state: Option<State>,
}

#[derive(Debug)]
struct State {
    sample_rate_hz: f64,
    max_block: usize,
    clock: FrameClock,
    factor: usize,
    internal_rate_hz: f64,
    decimator: Decimator,
    highpass: HighPass,
    bands: BandMeter,
    noise_floor: NoiseFloor,
    noise_margin_db: f32,
    noise_headroom_db: f32,
    pitch: NsdfPitch,
    tracker: Tracker,
    speaker: SpeakerNorm,
    /// Decimated signal, indexed by decimated sample number & mask.
    ring: Vec<f32>,
    /// Per decimated slot: sum and sum of squares of the `factor` raw input samples in it.
    bin_sum: Vec<f64>,
    bin_sq: Vec<f64>,
    mask: usize,
    /// Decimated samples (and completed bins) so far.
    produced: u64,
    acc_sum: f64,
    acc_sq: f64,
    window: Vec<f32>,
    rms_bins: usize,
    speech_gate_db: f32,
    level_weight: f32,
    samples_in: u64,
    next_frame: u64,
    /// Geometry of the next frame, cached: first window sample, first rms bin, ready index.
    next_start: i64,
    next_bin: i64,
    next_ready: i64,
}

impl Analyzer {
    /// An analyzer with validated settings; call [`Analyzer::prepare`] before processing.
    pub fn new(config: AnalysisConfig) -> Result<Self, AnalysisError> {
        config.validate()?;
        Ok(Self {
            config,
            state: None,
        })
    }

    /// The settings.
    pub fn config(&self) -> &AnalysisConfig {
        &self.config
    }

    /// Allocates everything for a stream at `sample_rate_hz` (8–768 kHz) with blocks of up to
    /// `max_block` samples, and resets. Blocks larger than `max_block` are still handled.
    pub fn prepare(&mut self, sample_rate_hz: f64, max_block: usize) -> Result<(), AnalysisError> {
        check_sample_rate(sample_rate_hz)?;
        let c = &self.config;
        let factor = factor_for(sample_rate_hz);
        let internal_rate_hz = sample_rate_hz / factor as f64;
        let window_len = (c.window_s as f64 * internal_rate_hz).round() as usize;
        let rms_bins = ((c.rms_window_s as f64 * internal_rate_hz).round() as usize).max(1);
        let cap = (2 * window_len.max(rms_bins) + 64).next_power_of_two();
        let mut state = State {
            sample_rate_hz,
            max_block: max_block.max(1),
            clock: FrameClock::new(c.frame_rate_hz, sample_rate_hz),
            factor,
            internal_rate_hz,
            decimator: Decimator::new(factor),
            highpass: HighPass::new(c.highpass_hz as f64, internal_rate_hz),
            bands: BandMeter::new(sample_rate_hz, cap),
            noise_floor: NoiseFloor::new(c.noise_window_s as f64, c.frame_rate_hz),
            noise_margin_db: c.noise_margin_db,
            noise_headroom_db: c.noise_headroom_db,
            pitch: NsdfPitch::with_short_window(
                internal_rate_hz,
                window_len,
                (c.short_window_s as f64 * internal_rate_hz).round() as usize,
                c.f0_min_hz,
                c.f0_max_hz,
                c.key_max_ratio,
            ),
            tracker: Tracker::new(VoicingRule::new(c.voicing_on, c.voicing_off, c.silence_db)),
            speaker: SpeakerNorm::new(c.speaker.clone(), c.frame_rate_hz),
            ring: vec![0.0; cap],
            bin_sum: vec![0.0; cap],
            bin_sq: vec![0.0; cap],
            mask: cap - 1,
            produced: 0,
            acc_sum: 0.0,
            acc_sq: 0.0,
            window: vec![0.0; window_len],
            rms_bins,
            speech_gate_db: c.speech_gate_db,
            level_weight: c.level_weight,
            samples_in: 0,
            next_frame: 0,
            next_start: 0,
            next_bin: 0,
            next_ready: 0,
        };
        state.reset();
        self.state = Some(state);
        Ok(())
    }

    /// Clears all stream state (keeps allocations): the next sample is time 0 again.
    pub fn reset(&mut self) {
        if let Some(s) = &mut self.state {
            s.reset();
        }
    }

    /// The host sample rate given to `prepare`, if prepared.
    pub fn sample_rate_hz(&self) -> Option<f64> {
        self.state.as_ref().map(|s| s.sample_rate_hz)
    }

    /// The largest block given to `prepare`, if prepared.
    pub fn max_block(&self) -> Option<usize> {
        self.state.as_ref().map(|s| s.max_block)
    }

    /// The internal analysis rate in Hz (host rate divided by an integer, 8–16 kHz), if prepared.
    pub fn internal_rate_hz(&self) -> Option<f64> {
        self.state.as_ref().map(|s| s.internal_rate_hz)
    }

    /// Algorithmic latency in seconds: the longest time from a frame's centre to the arrival of
    /// the last input sample it needs (half the analysis window plus the decimation filter).
    pub fn latency_s(&self) -> Option<f64> {
        self.state.as_ref().map(|s| {
            let half = s.window.len().max(s.rms_bins) as f64 / 2.0 + 1.0;
            (half * s.factor as f64 + s.decimator.delay_samples() + s.factor as f64)
                / s.sample_rate_hz
        })
    }

    /// Input samples consumed since the last reset.
    pub fn samples_in(&self) -> u64 {
        self.state.as_ref().map_or(0, |s| s.samples_in)
    }

    /// Analyses one mono block of any length; calls `on_frame` for every frame completed by it.
    /// Non-finite samples count as silence. Never allocates.
    pub fn process(
        &mut self,
        block: &[f32],
        mut on_frame: impl FnMut(&FeatureFrame),
    ) -> Result<(), AnalysisError> {
        let s = self.state.as_mut().ok_or(AnalysisError::NotPrepared)?;
        for &x in block {
            s.push(x, &mut on_frame);
        }
        s.samples_in += block.len() as u64;
        Ok(())
    }

    /// Like [`Analyzer::process`], but tells `on_frame` the index in `block` of the sample that
    /// completed each frame (for callers that act at that exact sample). Never allocates.
    pub fn process_indexed(
        &mut self,
        block: &[f32],
        mut on_frame: impl FnMut(&FeatureFrame, usize),
    ) -> Result<(), AnalysisError> {
        let s = self.state.as_mut().ok_or(AnalysisError::NotPrepared)?;
        for (i, &x) in block.iter().enumerate() {
            s.push(x, &mut |f: &FeatureFrame| on_frame(f, i));
        }
        s.samples_in += block.len() as u64;
        Ok(())
    }

    /// Ends the stream: emits the remaining frames whose centres lie inside the audio given so
    /// far (feeding silence past its end). Call [`Analyzer::reset`] before reusing.
    pub fn finish(&mut self, mut on_frame: impl FnMut(&FeatureFrame)) -> Result<(), AnalysisError> {
        let s = self.state.as_mut().ok_or(AnalysisError::NotPrepared)?;
        let total = s.clock.frames_in(s.samples_in);
        while s.next_frame < total {
            s.push(0.0, &mut |f: &FeatureFrame| {
                if f.index < total {
                    on_frame(f)
                }
            });
        }
        Ok(())
    }
}

impl State {
    fn reset(&mut self) {
        self.decimator.reset();
        self.highpass.reset();
        self.bands.reset();
        self.noise_floor.reset();
        self.tracker.reset();
        self.speaker.reset();
        self.ring.fill(0.0);
        self.bin_sum.fill(0.0);
        self.bin_sq.fill(0.0);
        self.produced = 0;
        self.acc_sum = 0.0;
        self.acc_sq = 0.0;
        self.samples_in = 0;
        self.next_frame = 0;
        self.plan_next();
    }

    /// Computes where the next frame's windows lie in decimated samples.
    fn plan_next(&mut self) {
        let centre = self.clock.sample_pos(self.next_frame);
        let d = self.factor as f64;
        // Decimated sample j stands for input time (j + 1)·D − 1 − delay.
        let j_centre = (centre + self.decimator.delay_samples() + 1.0) / d - 1.0;
        let w = self.window.len() as f64;
        self.next_start = (j_centre - (w - 1.0) / 2.0 + 0.5).floor() as i64;
        // Bin b covers raw input samples b·D .. (b+1)·D.
        let half_rms = self.rms_bins as f64 * d / 2.0;
        self.next_bin = ((centre - half_rms) / d + 0.5).floor() as i64;
        self.next_ready =
            (self.next_start + self.window.len() as i64).max(self.next_bin + self.rms_bins as i64);
    }

    #[inline]
    fn push(&mut self, x: f32, on_frame: &mut impl FnMut(&FeatureFrame)) {
        let x = if x.is_finite() {
            x.clamp(-INPUT_LIMIT, INPUT_LIMIT)
        } else {
            0.0
        };
        self.acc_sum += x as f64;
        self.acc_sq += (x as f64) * (x as f64);
        self.bands.push(x);
        let Some(y) = self.decimator.push(x) else {
            return;
        };
        let slot = self.produced as usize & self.mask;
        self.ring[slot] = self.highpass.process(y);
        self.bin_sum[slot] = self.acc_sum;
        self.bin_sq[slot] = self.acc_sq;
        self.bands.close_slot(slot);
        self.acc_sum = 0.0;
        self.acc_sq = 0.0;
        self.produced += 1;
        while self.produced as i64 >= self.next_ready {
            let frame = self.analyse_next();
            on_frame(&frame);
            self.next_frame += 1;
            self.plan_next();
        }
    }

    fn analyse_next(&mut self) -> FeatureFrame {
        for (i, w) in self.window.iter_mut().enumerate() {
            let j = self.next_start + i as i64;
            *w = if j < 0 {
                0.0
            } else {
                self.ring[j as usize & self.mask]
            };
        }
        let chosen = self.pitch.analyse(&self.window);
        let band_sq: f64 = self.window.iter().map(|&w| (w as f64) * (w as f64)).sum();
        let band_db = amplitude_to_db((band_sq / self.window.len() as f64).sqrt());
        let (mut sum, mut sq) = (0.0f64, 0.0f64);
        for b in self.next_bin..self.next_bin + self.rms_bins as i64 {
            if b >= 0 {
                sum += self.bin_sum[b as usize & self.mask];
                sq += self.bin_sq[b as usize & self.mask];
            }
        }
        let n = (self.rms_bins * self.factor) as f64;
        let mean = sum / n;
        let rms_db = amplitude_to_db((sq / n - mean * mean).max(0.0).sqrt());
        // The noise gate sits `noise_margin_db` above the floor, but never closer than
        // `noise_headroom_db` under the speech level: a stream without pauses (a sustained
        // vowel, a tone) has its "floor" at the voice itself.
        let periodicity = self.pitch.periodicity();
        let floor_db = self
            .noise_floor
            .update((periodicity < FLOOR_MAX_PERIODICITY).then_some(rms_db));
        let speech_db = self.speaker.speech_level_db();
        let noise_gate_db = if floor_db.is_finite() {
            (floor_db + self.noise_margin_db).min(speech_db - self.noise_headroom_db)
        } else {
            f32::NEG_INFINITY
        };
        let gate_db = (speech_db - self.speech_gate_db).max(noise_gate_db);
        let level_rel_db = (rms_db - self.speaker.speech_level_db()).clamp(-10.0, 10.0);
        let level_bonus = self.level_weight * level_rel_db / 10.0;
        // At a voice onset the voice fills only the newest part of the window, at an offset
        // only the oldest: when the window's periodicity alone would leave a loud enough frame
        // unvoiced, the decision also hears the short window at that end (its clarity at the
        // chosen period, when its own choice agrees), so phrase edges are not clipped by the
        // long window's dilution. Still no look-ahead beyond the window.
        let mut evidence = VoicingEvidence {
            periodicity,
            edge_periodicity: 0.0,
            rms_db,
            gate_db,
            level_bonus,
        };
        if self.tracker.rule().wants_more_evidence(&evidence) {
            let newest = !self.tracker.rule().is_voiced();
            evidence.edge_periodicity = self
                .pitch
                .edge_clarity(&self.window, chosen, newest)
                .unwrap_or(0.0);
        }
        let t = self
            .tracker
            .update(chosen, self.pitch.candidates(), &evidence);
        // Strongly periodic frames teach the speaker statistics even when the decision (which
        // leans on the level relative to the speaker's level) said unvoiced: otherwise a voice
        // far quieter than the prior level would never be voiced and never teach the level.
        let (learn, learn_f0_hz) = if t.voiced {
            (true, t.f0_hz)
        } else {
            (
                periodicity >= FLOOR_MAX_PERIODICITY && rms_db >= gate_db,
                chosen.f0_hz,
            )
        };
        self.speaker.update(learn, learn_f0_hz, rms_db);
        FeatureFrame {
            index: self.next_frame,
            time_s: self.clock.time_s(self.next_frame),
            f0_hz: t.f0_hz,
            voiced: t.voiced,
            voicing: t.voicing,
            rms_db,
            f0_st: if t.voiced {
                self.speaker.f0_st(t.f0_hz)
            } else {
                0.0
            },
            level_db: rms_db - self.speaker.speech_level_db(),
            band_db,
            bands: self.bands.levels(self.next_bin, self.rms_bins, n as usize),
        }
    }
}
