//! [`Analyzer`]: the streaming analysis front end that owns the frame clock, the decimator, the
//! pitch estimator, the level meter, the voicing tracker and the speaker normalisation.
//!
//! Every sum runs over the samples in their order, whatever runs they arrive in, so the frames
//! depend only on the sample sequence, never on how it was cut into blocks: any partition gives
//! bit-identical frames.
//! Samples before the start of the stream count as zeros; a frame is emitted as soon as the last
//! sample of its analysis window has arrived (see [`Analyzer::latency_s`]).

use super::biquad::{Biquad, HighPass};
use super::clock::FrameClock;
use super::config::{check_sample_rate, AnalysisConfig};
use super::decimator::{factor_for, Decimator};
use super::error::AnalysisError;
use super::frame::FeatureFrame;
use super::level::amplitude_to_db;
use super::noise_floor::NoiseFloor;
use super::pitch::{FrameAnalysis, NsdfPitch};
use super::speaker_norm::{quiet_shift_db, SpeakerNorm};
use super::tracking::Tracker;
use super::voicing::{
    period_jump_octaves, VoicingEvidence, VoicingFeatures, VoicingRule, TRACK_CAP_S,
};

/// Input samples beyond this magnitude are clamped for analysis (+60 dBFS).
const INPUT_LIMIT: f32 = 1000.0;
/// Frames at least this periodic are voice, not background: they do not teach the noise floor.
const FLOOR_MAX_PERIODICITY: f32 = 0.9;
/// Nor do frames less than this many dB under the running speech level.
const BACKGROUND_HEADROOM_DB: f32 = 3.0;
/// Frames whose band level is within this many dB of the band's noise floor teach
/// [`State::noise_clarity`].
const NOISE_CLARITY_MARGIN_DB: f32 = 3.0;
/// Weight of one such frame in that running mean.
const NOISE_CLARITY_RATE: f32 = 0.05;
/// The clarity noise alone is taken to give before any noise frame was heard.
const NOISE_CLARITY_START: f32 = 0.3;
/// A frame continues the pitch track when its chosen f0 lies within this many octaves of the
/// previous frame's (a quarter octave, +19 %/−16 %: a voice glides less than that from one
/// frame to the next, also a creaky one with its irregular periods; a tenth of an octave lost
/// the low voice m1 0.5 FFE points held out, 9.62 → 10.08, measured before the cue was made
/// monotone). Noise's chance periods jump further.
const TRACK_STEP_OCTAVES: f32 = 0.25;

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
    noise_floor: NoiseFloor,
    /// The noise floor of the pitch window's band level (what the NSDF hears).
    band_floor: NoiseFloor,
    /// Running mean of the long-window clarity on frames at the band floor: the clarity the
    /// background alone gives.
    noise_clarity: f32,
    /// The running level of clearly periodic frames, for the voicing cues (fed from the audio
    /// alone, never from the decisions, unlike `speaker`).
    periodic_level: SpeakerNorm,
    /// The previous frame's chosen f0 (0 = none) and long-window clarity.
    previous_f0_hz: f32,
    previous_clarity: f32,
    /// How long the chosen period has moved smoothly from frame to frame, s (capped at
    /// [`TRACK_CAP_S`]; 0 after a jump or a frame without one).
    track_s: f32,
    pitch: NsdfPitch,
    tracker: Tracker,
    speaker: SpeakerNorm,
    /// Decimated signal, indexed by decimated sample number & mask.
    ring: Vec<f32>,
    /// Per decimated slot: sum and sum of squares of the `factor` raw input samples in it.
    bin_sum: Vec<f64>,
    bin_sq: Vec<f64>,
    mask: usize,
    silence_db: f32,
    /// Decimated samples (and completed bins) so far.
    produced: u64,
    window: Vec<f32>,
    rms_bins: usize,
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
            noise_floor: NoiseFloor::new(c.noise_window_s as f64, c.frame_rate_hz),
            band_floor: NoiseFloor::new(c.noise_window_s as f64, c.frame_rate_hz),
            noise_clarity: NOISE_CLARITY_START,
            periodic_level: SpeakerNorm::new(c.speaker.clone(), c.frame_rate_hz),
            previous_f0_hz: 0.0,
            previous_clarity: 0.0,
            track_s: 0.0,
            pitch: NsdfPitch::with_short_window(
                internal_rate_hz,
                window_len,
                (c.short_window_s as f64 * internal_rate_hz).round() as usize,
                c.f0_min_hz,
                c.f0_max_hz,
                c.key_max_ratio,
            ),
            tracker: Tracker::new(VoicingRule::new(c.voicing_model.clone(), c.silence_db)),
            speaker: SpeakerNorm::new(c.speaker.clone(), c.frame_rate_hz),
            ring: vec![0.0; cap],
            bin_sum: vec![0.0; cap],
            bin_sq: vec![0.0; cap],
            mask: cap - 1,
            silence_db: c.silence_db,
            produced: 0,
            window: vec![0.0; window_len],
            rms_bins,
            samples_in: 0,
            next_frame: 0,
            next_start: 0,
            next_bin: 0,
            next_ready: 0,
        };
        let (decimator, highpass) = (&state.decimator, &state.highpass);
        state.pitch.measure_bands(|f_hz| {
            decimator.power_gain(f_hz, sample_rate_hz) * highpass.power_gain(f_hz, internal_rate_hz)
        });
        if c.lowpass_hz > 0.0 {
            state.pitch.low_pass(Biquad::butterworth(
                c.lowpass_hz as f64,
                internal_rate_hz,
                false,
            ));
        }
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
        s.push_block(block, &mut |f: &FeatureFrame, _: &VoicingFeatures, _| {
            on_frame(f)
        });
        s.samples_in += block.len() as u64;
        Ok(())
    }

    /// Like [`Analyzer::process`], but also gives `on_frame` each frame's voicing cues (in
    /// [`crate::analysis::VOICING_FEATURES`] order), for fitting voicing models
    /// (`cargo xtask train-voicing`). Never allocates.
    pub fn process_with_features(
        &mut self,
        block: &[f32],
        mut on_frame: impl FnMut(&FeatureFrame, &VoicingFeatures),
    ) -> Result<(), AnalysisError> {
        let s = self.state.as_mut().ok_or(AnalysisError::NotPrepared)?;
        s.push_block(block, &mut |f: &FeatureFrame, v: &VoicingFeatures, _| {
            on_frame(f, v)
        });
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
        s.push_block(block, &mut |f: &FeatureFrame, _: &VoicingFeatures, i| {
            on_frame(f, i)
        });
        s.samples_in += block.len() as u64;
        Ok(())
    }

    /// Ends the stream: emits the remaining frames whose centres lie inside the audio given so
    /// far (feeding silence past its end). Call [`Analyzer::reset`] before reusing.
    pub fn finish(&mut self, mut on_frame: impl FnMut(&FeatureFrame)) -> Result<(), AnalysisError> {
        self.finish_with_features(|f, _| on_frame(f))
    }

    /// Like [`Analyzer::finish`], with each frame's voicing cues as in
    /// [`Analyzer::process_with_features`].
    pub fn finish_with_features(
        &mut self,
        mut on_frame: impl FnMut(&FeatureFrame, &VoicingFeatures),
    ) -> Result<(), AnalysisError> {
        let s = self.state.as_mut().ok_or(AnalysisError::NotPrepared)?;
        let total = s.clock.frames_in(s.samples_in);
        while s.next_frame < total {
            s.push_block(&[0.0], &mut |f: &FeatureFrame, v: &VoicingFeatures, _| {
                if f.index < total {
                    on_frame(f, v)
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
        self.noise_floor.reset();
        self.band_floor.reset();
        self.noise_clarity = NOISE_CLARITY_START;
        self.periodic_level.reset();
        self.previous_f0_hz = 0.0;
        self.previous_clarity = 0.0;
        self.track_s = 0.0;
        self.tracker.reset();
        self.speaker.reset();
        self.ring.fill(0.0);
        self.bin_sum.fill(0.0);
        self.bin_sq.fill(0.0);
        self.produced = 0;
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

    /// Takes `block`; calls `on_frame` with each completed frame and the index in `block` of
    /// the sample that completed it. The samples go into the decimator's history in runs as
    /// long as it holds (clamped on the way, a pass that vectorises); each decimated sample
    /// then takes its level sums over its own input samples there, in their order: the same
    /// sums as sample by sample, for any cutting of the input into blocks.
    #[inline]
    fn push_block(
        &mut self,
        block: &[f32],
        on_frame: &mut impl FnMut(&FeatureFrame, &VoicingFeatures, usize),
    ) {
        let mut done = 0;
        while done < block.len() {
            // The fed samples' offsets (from 1) that complete a decimated sample.
            let mut completes = self.decimator.until_output();
            let n = self.decimator.feed(&block[done..], |x| {
                if x.is_finite() {
                    x.clamp(-INPUT_LIMIT, INPUT_LIMIT)
                } else {
                    0.0
                }
            });
            while let Some((y, inputs)) = self.decimator.output() {
                let (mut sum, mut sq) = (0.0f64, 0.0f64);
                for &x in inputs {
                    sum += x as f64;
                    sq += (x as f64) * (x as f64);
                }
                let at = done + completes - 1;
                self.close_slot(y, sum, sq, &mut |f: &FeatureFrame, v: &VoicingFeatures| {
                    on_frame(f, v, at)
                });
                completes += self.factor;
            }
            done += n;
        }
    }

    /// Stores decimated sample `y` and the level sums of its input samples, and emits the
    /// frames it completes.
    fn close_slot(
        &mut self,
        y: f32,
        sum: f64,
        sq: f64,
        on_frame: &mut impl FnMut(&FeatureFrame, &VoicingFeatures),
    ) {
        let slot = self.produced as usize & self.mask;
        self.ring[slot] = self.highpass.process(y);
        self.bin_sum[slot] = sum;
        self.bin_sq[slot] = sq;
        self.produced += 1;
        while self.produced as i64 >= self.next_ready {
            let (frame, features) = self.analyse_next();
            on_frame(&frame, &features);
            self.next_frame += 1;
            self.plan_next();
        }
    }

    fn analyse_next(&mut self) -> (FeatureFrame, VoicingFeatures) {
        // Samples before the stream are zeros; the rest is at most two runs of the ring.
        let lead = (-self.next_start).clamp(0, self.window.len() as i64) as usize;
        let (zeros, rest) = self.window.split_at_mut(lead);
        zeros.fill(0.0);
        let from = (self.next_start.max(0) as usize) & self.mask;
        let first = rest.len().min(self.ring.len() - from);
        let (a, b) = rest.split_at_mut(first);
        a.copy_from_slice(&self.ring[from..from + first]);
        b.copy_from_slice(&self.ring[..b.len()]);
        let FrameAnalysis {
            chosen,
            edge_newest,
            edge_oldest,
            square_sum: band_sq,
            heard_energy,
        } = self.pitch.analyse_frame(&self.window);
        // The band level the phrase tracker reads (the window as it is), and the level the
        // NSDF hears (behind the low-pass), which the voicing cues and their floor use.
        let band_db = amplitude_to_db((band_sq / self.window.len() as f64).sqrt());
        let heard_db = amplitude_to_db((heard_energy / self.window.len() as f64).sqrt());
        // The level sums over the frame's slots (two independent sums in one loop).
        let (mut sum, mut sq) = (0.0f64, 0.0f64);
        for b in self.next_bin.max(0)..self.next_bin + self.rms_bins as i64 {
            let b = b as usize & self.mask;
            sum += self.bin_sum[b];
            sq += self.bin_sq[b];
        }
        let n = (self.rms_bins * self.factor) as f64;
        let mean = sum / n;
        let rms_db = amplitude_to_db((sq / n - mean * mean).max(0.0).sqrt());
        let periodicity = self.pitch.periodicity();
        let long_clarity = self.pitch.long_periodicity();
        // Background is what is heard in the pauses: frames that are not clearly periodic and
        // not as loud as the voice (a glide or a change of pitch inside a phrase reads as
        // aperiodic too). A stream without pauses has no floor until one comes.
        let speech_db = self.periodic_level.speech_level_db();
        let background =
            long_clarity < FLOOR_MAX_PERIODICITY && rms_db < speech_db - BACKGROUND_HEADROOM_DB;
        let floor_db = self.noise_floor.update(background.then_some(rms_db));
        let band_floor_db = self.band_floor.update(background.then_some(heard_db));
        if band_floor_db.is_finite() && heard_db <= band_floor_db + NOISE_CLARITY_MARGIN_DB {
            self.noise_clarity += NOISE_CLARITY_RATE * (long_clarity - self.noise_clarity);
        }
        // Every cue comes from the audio alone (never from earlier decisions), so a model can
        // be fitted on cues gathered once. At a voice onset the voice fills only the newest
        // part of the window, at an offset only the oldest: the short windows at both ends
        // hear the phrase edges the long window dilutes. Still no look-ahead beyond the window.
        let (short, short_agrees) = self.pitch.short_window_pick();
        // A voice holds a smooth pitch track through a vowel; noise's chance periods jump.
        let continues = period_jump_octaves(chosen.f0_hz, self.previous_f0_hz) < TRACK_STEP_OCTAVES;
        self.track_s = if continues {
            let frame_s = (1.0 / self.clock.frame_rate_hz()) as f32;
            (self.track_s + frame_s).min(TRACK_CAP_S)
        } else {
            0.0
        };
        let evidence = VoicingEvidence {
            long_clarity,
            chosen_clarity: chosen.clarity,
            short_clarity: short.clarity,
            short_agrees,
            edge_newest: edge_newest.unwrap_or(0.0),
            edge_oldest: edge_oldest.unwrap_or(0.0),
            rms_db,
            speech_db,
            floor_db,
            band_db: heard_db,
            band_floor_db,
            noise_clarity: self.noise_clarity,
            low_band: self.pitch.low_band(),
            f0_hz: chosen.f0_hz,
            previous_f0_hz: self.previous_f0_hz,
            previous_clarity: self.previous_clarity,
            track_s: self.track_s,
        };
        let features = evidence.features();
        // A quiet speaker's silence gate lies this much lower (the speech level before this
        // frame), for the periodic level and the voicing.
        let shift_db = quiet_shift_db(self.speaker.speech_level_db());
        self.periodic_level.update(
            long_clarity >= FLOOR_MAX_PERIODICITY && rms_db >= self.silence_db + shift_db,
            chosen.f0_hz,
            rms_db,
        );
        self.previous_f0_hz = chosen.f0_hz;
        self.previous_clarity = long_clarity;
        // The tracker's silence gate is `silence_db` as set: a quiet speaker's frames are
        // judged against it that much louder, so their soft syllables stay voice.
        let t = self.tracker.update(
            chosen,
            self.pitch.candidates(),
            rms_db - shift_db,
            &features,
            periodicity,
            evidence.edge_newest,
        );
        self.speaker.update(t.voiced, t.f0_hz, rms_db);
        let speech_level_db = self.speaker.speech_level_db();
        let frame = FeatureFrame {
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
            level_db: rms_db - speech_level_db,
            speech_level_db,
            band_db,
            bands: self.pitch.band_levels(),
        };
        (frame, features)
    }
}
