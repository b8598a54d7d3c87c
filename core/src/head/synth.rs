//! Per-frame head-pose synthesis: the argmax of the weighted product of the five conditional
//! densities given the two previous poses (van Welbergen et al. after Le et al.), found by BFGS
//! from the previous pose with analytic gradients inside box bounds; unvoiced frames follow the
//! configured [`UnvoicedBehaviour`] inside pauses; in a silence (no voiced frame for more than
//! [`REST_AFTER_S`], or none yet) the head returns to its rest pose, the speaker's mean pose
//! (0°), as [`UnvoicedBehaviour::Return`]. Allocation-free and deterministic after `new`.
//!
//! Per frame, with θ = (roll, pitch, yaw) in degrees around the neutral pose, frame rate r:
//! `J(θ) = −w_p·Σ_axes log p(θ_axis | f0, E) − w_v·log p(v | f0, E) − w_a·log p(a | f0, E)`,
//! `v = r·|θ − θ₋₁|` (°/s), `a = r²·|θ − 2θ₋₁ + θ₋₂|` (°/s²). Each p(·|f0,E) is the 1-D
//! conditional of the model's joint GMM, computed once per frame.
//!
//! Output = [`SpeedGovernor`](super::governor)([`PoseSmoother`](super::smoother)(pose × the
//! model's per-axis gain)) × amount, plus the optional liveliness offset, clamped to the limits.

use glam::{DVec3, Quat};

use super::bfgs::{minimize, BfgsConfig};
use super::gmm::{Conditioner, Mixture1};
use super::governor::SpeedGovernor;
use super::inputs::InputTracker;
use super::model_file::{HeadModel, HeadModelError, PoseTerm, UnvoicedBehaviour};
use super::smoother::PoseSmoother;
use crate::analysis::FeatureFrame;
use crate::control::HeadAngles;
use crate::rng::SeededRng;
use crate::settings::head::{
    HEAD_AMOUNT, HEAD_LIVELINESS, HEAD_MAX_PITCH_DEG, HEAD_MAX_ROLL_DEG, HEAD_MAX_SPEED_DEG_S,
    HEAD_MAX_YAW_DEG,
};
use crate::settings::setting::{check_fields, field, sanitize_fields, Field};

/// Unvoiced time after which the stretch is a silence rather than a pause, seconds: the head
/// then returns to its rest pose whatever the model's pause behaviour. Pauses inside speech
/// rarely last longer (the longest unvoiced stretch of the seven styletalk training clips is
/// 1.99 s, docs/measurements.md, 5.0), so the pause models were trained on pauses this long at
/// most and are not asked beyond their data: the loudness model, trained on pauses where heads
/// keep moving, wants motion at several °/s and in a long silence wandered to a posture degrees
/// off the mean (one leave-one-clip-out model: roll +2.26° over a minute of silence), and a hold
/// keeps the last pose for ever. The angles are relative to the speaker's mean pose, so the
/// rest pose is 0°.
pub const REST_AFTER_S: f64 = 2.0;

/// Smoothing of |Δθ| near 0 (degrees), so the norms are differentiable.
const NORM_EPS_DEG: f64 = 1e-3;
/// The unvoiced time a stream starts with and is counted up to: past [`REST_AFTER_S`] (at rest).
const AT_REST_S: f64 = 2.0 * REST_AFTER_S;
/// Time constant of the liveliness variation, seconds.
const LIVELINESS_TIME_S: f64 = 1.5;
/// Standard deviation of the liveliness variation at liveliness 1, degrees.
const LIVELINESS_SD_DEG: f64 = 2.0;
/// Most model steps one stream frame brings: a 240 Hz model in a 30 frames/s stream takes 8
/// (models are trained at a frame rate the stream can run at, checked on load, so the engine
/// never needs more); a slower stream, through this API only, has the steps beyond dropped
/// rather than take unbounded time in a frame: its head then moves in slow motion.
pub const MAX_STEPS_PER_FRAME: u64 = 8;

/// Settings of the head-pose synthesis. Defaults follow the paper's motion-capture criteria;
/// each numeric field's setting (unit, range, default, why) is in [`crate::settings::head`].
#[derive(Debug, Clone, PartialEq)]
pub struct HeadConfig {
    /// Amplitude scale of the generated motion (0 keeps the head still) ([`HEAD_AMOUNT`]).
    pub amount: f32,
    /// Largest |pitch|, degrees ([`HEAD_MAX_PITCH_DEG`]).
    pub max_pitch_deg: f32,
    /// Largest |yaw|, degrees ([`HEAD_MAX_YAW_DEG`]).
    pub max_yaw_deg: f32,
    /// Largest |roll|, degrees ([`HEAD_MAX_ROLL_DEG`]).
    pub max_roll_deg: f32,
    /// Largest angular speed |Δθ|·rate, degrees per second ([`HEAD_MAX_SPEED_DEG_S`]).
    pub max_speed_deg_s: f32,
    /// Seeded slow random variation added to the pose (0 = off); 1 adds a wandering offset of
    /// about 2° SD per axis with a 1.5 s time constant ([`HEAD_LIVELINESS`]).
    pub liveliness: f32,
    /// Seed of the liveliness variation.
    pub seed: u64,
    /// Behaviour on unvoiced frames; `None` uses the model's choice (the one that matched real
    /// motion best in training).
    pub unvoiced: Option<UnvoicedBehaviour>,
}

/// The numeric settings of [`HeadConfig`] and the fields holding them.
static FIELDS: [Field<HeadConfig>; 6] = [
    field!(HEAD_AMOUNT, amount),
    field!(HEAD_MAX_PITCH_DEG, max_pitch_deg),
    field!(HEAD_MAX_YAW_DEG, max_yaw_deg),
    field!(HEAD_MAX_ROLL_DEG, max_roll_deg),
    field!(HEAD_MAX_SPEED_DEG_S, max_speed_deg_s),
    field!(HEAD_LIVELINESS, liveliness),
];

impl Default for HeadConfig {
    /// The table's defaults.
    fn default() -> Self {
        Self {
            amount: HEAD_AMOUNT.default,
            max_pitch_deg: HEAD_MAX_PITCH_DEG.default,
            max_yaw_deg: HEAD_MAX_YAW_DEG.default,
            max_roll_deg: HEAD_MAX_ROLL_DEG.default,
            max_speed_deg_s: HEAD_MAX_SPEED_DEG_S.default,
            liveliness: HEAD_LIVELINESS.default,
            seed: 0x5EED_4EAD,
            unvoiced: None,
        }
    }
}

impl HeadConfig {
    /// The numeric settings of this struct and the fields holding them.
    pub fn fields() -> &'static [Field<HeadConfig>] {
        &FIELDS
    }

    /// Checks every setting.
    pub fn validate(&self) -> Result<(), HeadModelError> {
        Ok(check_fields(self, &FIELDS)?)
    }

    /// The same settings with every out-of-range value clamped (non-finite ones set to the
    /// default), for doors that must accept anything.
    pub fn sanitized(&self) -> HeadConfig {
        let mut c = self.clone();
        sanitize_fields(&mut c, &FIELDS);
        c
    }
}

/// The online head-pose generator: one per stream.
#[derive(Debug, Clone)]
pub struct HeadSynth {
    model: HeadModel,
    config: HeadConfig,
    voiced: [Conditioner; 5],
    unvoiced: [Conditioner; 5],
    mix: [Mixture1; 5],
    inputs: InputTracker,
    bfgs: BfgsConfig,
    /// Internal pose (roll, pitch, yaw) of the last two frames, degrees around neutral.
    prev1: DVec3,
    prev2: DVec3,
    rng: SeededRng,
    live: DVec3,
    smoother: PoseSmoother,
    governor: SpeedGovernor,
    /// Governed output of the last frame before liveliness and limits, degrees.
    prev_out: DVec3,
    /// Seconds since the last voiced frame (counted up to just past [`REST_AFTER_S`]; a stream
    /// starts at rest, as after a silence).
    unvoiced_s: f64,
    /// The head's own clock: stream frames seen and model steps taken since the stream start
    /// (see [`HeadSynth::process`]).
    frames_seen: u64,
    steps_taken: u64,
    /// The output of the last step and of the step before it.
    held: HeadAngles,
    before: HeadAngles,
}

/// Model-space pose → output angles.
fn to_angles(p: DVec3) -> HeadAngles {
    HeadAngles {
        roll_deg: p.x as f32,
        pitch_deg: p.y as f32,
        yaw_deg: p.z as f32,
    }
}

impl HeadSynth {
    /// A generator for `model` with `config` (validated).
    pub fn new(model: HeadModel, config: HeadConfig) -> Result<HeadSynth, HeadModelError> {
        config.validate()?;
        let voiced = [0, 1, 2, 3, 4].map(|k| model.voiced()[k].conditioner());
        let unvoiced = [0, 1, 2, 3, 4].map(|k| model.unvoiced()[k].conditioner());
        let rng = SeededRng::new(config.seed);
        let inputs = model.normalisation.input_tracker();
        let smoother = PoseSmoother::new(model.synthesis.smoothing_s);
        let governor = SpeedGovernor::new(
            model.synthesis.speed_target_deg_s,
            model.synthesis.speed_time_s,
        );
        Ok(Self {
            model,
            config,
            voiced,
            unvoiced,
            mix: [Mixture1::default(); 5],
            inputs,
            bfgs: BfgsConfig::default(),
            prev1: DVec3::ZERO,
            prev2: DVec3::ZERO,
            rng,
            live: DVec3::ZERO,
            smoother,
            governor,
            prev_out: DVec3::ZERO,
            unvoiced_s: AT_REST_S,
            frames_seen: 0,
            steps_taken: 0,
            held: HeadAngles::default(),
            before: HeadAngles::default(),
        })
    }

    /// Back to the neutral pose and the start of the liveliness sequence.
    pub fn reset(&mut self) {
        self.prev1 = DVec3::ZERO;
        self.prev2 = DVec3::ZERO;
        self.inputs.reset();
        self.rng = SeededRng::new(self.config.seed);
        self.live = DVec3::ZERO;
        self.smoother.reset();
        self.governor.reset();
        self.prev_out = DVec3::ZERO;
        self.unvoiced_s = AT_REST_S;
        self.frames_seen = 0;
        self.steps_taken = 0;
        self.held = HeadAngles::default();
        self.before = HeadAngles::default();
    }

    /// Changes the settings between frames (out-of-range values are clamped, see
    /// [`HeadConfig::sanitized`]); the pose continues smoothly. A new seed restarts the
    /// liveliness sequence.
    pub fn set_config(&mut self, config: HeadConfig) {
        let config = config.sanitized();
        if config.seed != self.config.seed {
            self.rng = SeededRng::new(config.seed);
        }
        self.config = config;
    }

    /// The current settings.
    pub fn config(&self) -> &HeadConfig {
        &self.config
    }

    /// The model in use.
    pub fn model(&self) -> &HeadModel {
        &self.model
    }

    /// The head pose for a frame of sound that is not this speaker's speech (music, singing,
    /// noise, as the speech decision judged it): the head returns to its rest pose as in a long
    /// silence, whatever it hears (the output smoothing carries it on for a few tenths of a
    /// second first, as when speech stops). Never allocates.
    pub fn process_other_sound(&mut self, frame: &FeatureFrame, frame_rate_hz: f64) -> HeadAngles {
        // Its level is heard as a pause's: a bed under the speech is heard so in the pauses.
        let unvoiced = FeatureFrame {
            voiced: false,
            ..*frame
        };
        self.advance(&unvoiced, frame_rate_hz, true)
    }

    /// The head pose for one feature frame of a stream at `frame_rate_hz` frames per second.
    /// Never allocates; non-finite features count as an unvoiced frame at the lowest level, and
    /// a non-finite or non-positive frame rate counts as 120 Hz.
    ///
    /// The head steps at the rate its model was trained at ([`HeadSynth::step_rate_hz`]), not
    /// at the stream's: the objective's velocity and acceleration terms, the argmax's
    /// frame-to-frame trajectory, the smoother and the governor are all per step, so a head
    /// stepped at another rate moves differently (docs/measurements.md, stop 70). Frame `i` of
    /// the stream (at `i / frame_rate_hz` seconds) brings the steps due by then, each on this
    /// frame's features (at most [`MAX_STEPS_PER_FRAME`]). At the model's own rate this is one
    /// step per frame, exactly as before; at 30 frames/s with a 120 Hz model, four steps per
    /// frame, the frame showing the last; at 240, a step every second frame, and the frames
    /// between glide from the step before to the last one (the output lags by one step less
    /// one frame, 4 ms), so no frame moves further than a step does.
    pub fn process(&mut self, frame: &FeatureFrame, frame_rate_hz: f64) -> HeadAngles {
        self.advance(frame, frame_rate_hz, false)
    }

    /// [`HeadSynth::process`], each step taken as in a long silence when `other_sound`.
    fn advance(
        &mut self,
        frame: &FeatureFrame,
        frame_rate_hz: f64,
        other_sound: bool,
    ) -> HeadAngles {
        let stream_hz = if frame_rate_hz.is_finite() && frame_rate_hz > 0.0 {
            frame_rate_hz.clamp(1.0, 10_000.0)
        } else {
            120.0
        };
        let step_hz = self.step_rate_hz();
        // This frame's time in steps, and the steps due by then: every step at
        // k / step_hz ≤ i / stream_hz (for whole rates the product is exact and a whole
        // quotient floors to itself).
        let at_step = self.frames_seen as f64 * step_hz / stream_hz;
        let due = at_step.floor() as u64 + 1;
        self.frames_seen += 1;
        let steps = due
            .saturating_sub(self.steps_taken)
            .min(MAX_STEPS_PER_FRAME);
        for _ in 0..steps {
            if other_sound {
                self.unvoiced_s = AT_REST_S;
            }
            self.before = self.held;
            self.held = self.step(frame, step_hz);
        }
        self.steps_taken = due;
        // Between steps: the share of the way from the step before to the last one, reaching
        // the last one a frame before the next step (1 whenever a frame brings a step of its
        // own or more).
        let share = (at_step.fract() + step_hz / stream_hz).min(1.0);
        if share >= 1.0 {
            return self.held;
        }
        self.before.toward(&self.held, share as f32)
    }

    /// The rate the head steps at, Hz: its model's training frame rate.
    pub fn step_rate_hz(&self) -> f64 {
        self.model.provenance.frame_rate_hz
    }

    /// One step of the head at `rate` steps per second on `frame`'s features.
    fn step(&mut self, frame: &FeatureFrame, rate: f64) -> HeadAngles {
        let input = self.inputs.next(frame, rate);
        let (voiced, f0, level) = (input.voiced, input.f0_st, input.level_db);
        let cfg = &self.config;
        let amount = cfg.amount as f64;
        // Output = governed (smoothed (internal pose × gain per axis, from the model)) × amount.
        let model_gain = DVec3::from_array(self.model.synthesis.output_gain);
        let gain = model_gain * amount;
        let limits = DVec3::new(
            cfg.max_roll_deg as f64,
            cfg.max_pitch_deg as f64,
            cfg.max_yaw_deg as f64,
        );
        let search = DVec3::splat(self.model.synthesis.bound_deg);
        let bound = if amount > 1e-6 {
            (limits / gain).min(search)
        } else {
            search.min(limits)
        };

        self.unvoiced_s = if voiced {
            0.0
        } else {
            (self.unvoiced_s + 1.0 / rate).min(AT_REST_S)
        };
        let behaviour = if voiced {
            None
        } else if self.unvoiced_s > REST_AFTER_S {
            Some(UnvoicedBehaviour::Return)
        } else {
            Some(cfg.unvoiced.unwrap_or(self.model.unvoiced_behaviour))
        };
        let mut next = match behaviour {
            Some(UnvoicedBehaviour::Hold) => self.prev1,
            Some(UnvoicedBehaviour::Return) => {
                self.prev1 * (-1.0 / (rate * self.model.return_time_s)).exp()
            }
            None | Some(UnvoicedBehaviour::LoudnessModel) => {
                let conds = if voiced { &self.voiced } else { &self.unvoiced };
                let given = [f0, level];
                let given: &[f64] = if voiced { &given } else { &given[1..] };
                for (c, m) in conds.iter().zip(self.mix.iter_mut()) {
                    c.condition(given, m);
                }
                self.argmax(rate, bound)
            }
        };
        if !next.is_finite() {
            next = self.prev1;
        }
        next = next.clamp(-bound, bound);
        // Speed limit on the output (scaled) motion.
        let max_step = if amount > 1e-6 {
            cfg.max_speed_deg_s as f64 / rate / gain.max_element()
        } else {
            f64::INFINITY
        };
        let step = next - self.prev1;
        let len = step.length();
        if len > max_step {
            next = self.prev1 + step * (max_step / len);
        }
        self.prev2 = self.prev1;
        self.prev1 = next;

        let smooth = self.smoother.apply(next * model_gain, rate);
        let mut out = self.governor.apply(smooth, voiced, rate) * amount;
        // The speed limit again on the governed output (the governor may scale up to ×2).
        let out_step = out - self.prev_out;
        let out_max = cfg.max_speed_deg_s as f64 / rate;
        if out_step.length() > out_max {
            out = self.prev_out + out_step * (out_max / out_step.length());
        }
        if out.is_finite() {
            self.prev_out = out;
        }
        if cfg.liveliness > 0.0 {
            let a = (-1.0 / (rate * LIVELINESS_TIME_S)).exp();
            let sd = LIVELINESS_SD_DEG * cfg.liveliness as f64 * amount;
            let k = sd * (1.0 - a * a).sqrt();
            let noise = DVec3::new(self.rng.normal(), self.rng.normal(), self.rng.normal());
            self.live = self.live * a + noise * k;
            out += self.live;
        }
        let out = out.clamp(-limits, limits);
        to_angles(if out.is_finite() { out } else { DVec3::ZERO })
    }

    /// The argmax of the frame's objective by BFGS from the previous pose.
    fn argmax(&self, rate: f64, bound: DVec3) -> DVec3 {
        let w = &self.model.synthesis;
        let (wp, wv, wa) = (w.pose_weight, w.velocity_weight, w.acceleration_weight);
        let p1 = self.prev1;
        let p2 = self.prev2;
        let mix = &self.mix;
        let eps2 = NORM_EPS_DEG * NORM_EPS_DEG;
        // Per axis (mean, 1 / variance) of the conditional pose density, for the Gaussian term.
        let moments = [0, 1, 2].map(|i| {
            let (m, v) = mix[i].mean_variance();
            (m, 1.0 / v.max(1e-9))
        });
        let pose_term = w.pose_term;
        let objective = |x: DVec3| {
            let mut j = 0.0;
            let mut g = DVec3::ZERO;
            for i in 0..3 {
                let (lp, d) = match pose_term {
                    PoseTerm::Mixture => mix[i].log_pdf_grad(x[i]),
                    PoseTerm::ConditionalMean => {
                        let (m, inv_var) = moments[i];
                        let dx = x[i] - m;
                        (-0.5 * dx * dx * inv_var, -dx * inv_var)
                    }
                };
                j -= wp * lp;
                g[i] -= wp * d;
            }
            let dv = x - p1;
            let rv = (dv.length_squared() + eps2).sqrt();
            let (lv, dlv) = mix[3].log_pdf_grad(rate * rv);
            j -= wv * lv;
            g -= dv * (wv * dlv * rate / rv);
            let da = x - 2.0 * p1 + p2;
            let ra = (da.length_squared() + eps2).sqrt();
            let (la, dla) = mix[4].log_pdf_grad(rate * rate * ra);
            j -= wa * la;
            g -= da * (wa * dla * rate * rate / ra);
            (j, g)
        };
        minimize(objective, p1, -bound, bound, &self.bfgs).x
    }
}

/// The head rotation as a quaternion in a right-handed character frame with x = the
/// character's left, y = up, z = forward (the direction the character faces; glTF/VRM
/// convention): `q = Rz(−roll) · Ry(yaw) · Rx(−pitch)` (roll applied last, as the source data's
/// Rz·Ry·Rx). So pitch > 0 turns the forward axis up (chin up), yaw > 0 turns it to the
/// character's left, roll > 0 tilts the up axis to the character's left.
pub fn angles_to_quat(angles: &HeadAngles) -> Quat {
    let r = (-angles.roll_deg).to_radians();
    let y = angles.yaw_deg.to_radians();
    let p = (-angles.pitch_deg).to_radians();
    Quat::from_rotation_z(r) * Quat::from_rotation_y(y) * Quat::from_rotation_x(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn voiced(i: u64, f0_st: f32, level_db: f32) -> FeatureFrame {
        FeatureFrame {
            index: i,
            time_s: i as f64 / 120.0,
            f0_hz: 150.0 * (f0_st / 12.0).exp2(),
            voiced: true,
            voicing: 0.9,
            rms_db: -20.0 + level_db,
            f0_st,
            level_db,
            speech_level_db: -20.0,
            band_db: -20.0,
            bands: Default::default(),
        }
    }

    #[test]
    fn other_sound_sends_the_head_back_to_rest_whatever_it_hears() {
        let mut s =
            HeadSynth::new(HeadModel::default_model().clone(), HeadConfig::default()).unwrap();
        let away = |a: HeadAngles| a.pitch_deg.hypot(a.yaw_deg).hypot(a.roll_deg);
        let mut last = 0.0;
        for i in 0..360 {
            last = away(s.process(&voiced(i, 4.0 * (i as f32 * 0.05).sin(), 0.0), 120.0));
        }
        assert!(last > 0.5, "the speech moved the head {last}° only");
        // Loud voiced music with a moving pitch: the head only settles back, once the output
        // smoothing has carried it on (as when speech stops: a few tenths of a second).
        let start = last;
        for i in 360..960 {
            let music = voiced(i, 6.0 * (i as f32 * 0.2).sin(), 6.0);
            let now = away(s.process_other_sound(&music, 120.0));
            if i < 420 {
                assert!(now <= start + 2.0, "frame {i}: {now}° from {start}°");
            } else {
                assert!(now <= last + 1e-4, "frame {i}: {now}° after {last}°");
            }
            last = now;
        }
        assert!(last < 0.1, "{last}° from rest after 5 s");
    }

    /// A voice whose f0 and level wander, `n` frames of it at 120 Hz.
    fn wandering_voice(n: u64) -> Vec<FeatureFrame> {
        (0..n)
            .map(|i| {
                let t = i as f32 / 120.0;
                let f0 = 3.0 * (t * 1.3).sin() + 1.5 * (t * 3.1).cos();
                let mut f = voiced(i, f0, 3.0 * (t * 0.7).sin());
                f.voiced = t % 3.0 < 2.4;
                f
            })
            .collect()
    }

    fn run(frames: impl Iterator<Item = FeatureFrame>, rate_hz: f64) -> Vec<HeadAngles> {
        let mut s =
            HeadSynth::new(HeadModel::default_model().clone(), HeadConfig::default()).unwrap();
        frames.map(|f| s.process(&f, rate_hz)).collect()
    }

    #[test]
    fn the_head_steps_at_its_model_rate_in_a_faster_stream() {
        assert_eq!(HeadModel::default_model().provenance.frame_rate_hz, 120.0);
        let voice = wandering_voice(1200);
        let at_120 = run(voice.iter().copied(), 120.0);
        // The same voice at 240 frames/s: its even frames are the 120 Hz frames.
        let at_240 = run(voice.iter().flat_map(|f| [*f, *f]), 240.0);
        assert!(at_120[600] != at_120[0], "the voice moved the head");
        let mut before = HeadAngles::default();
        for (i, a) in at_120.iter().enumerate() {
            // Each step's pose a frame after its step, halfway from the step before on it.
            assert_eq!(at_240[2 * i + 1], *a, "frame {i}");
            let half = |x: f32, y: f32| x + (y - x) * 0.5;
            let mid = HeadAngles {
                roll_deg: half(before.roll_deg, a.roll_deg),
                pitch_deg: half(before.pitch_deg, a.pitch_deg),
                yaw_deg: half(before.yaw_deg, a.yaw_deg),
            };
            let g = at_240[2 * i];
            let off = (g.roll_deg - mid.roll_deg)
                .abs()
                .max((g.pitch_deg - mid.pitch_deg).abs())
                .max((g.yaw_deg - mid.yaw_deg).abs());
            assert!(off < 1e-5, "frame {i}: {g:?}, halfway {mid:?}");
            before = *a;
        }
        // So no frame moves further than a step: the speed limit holds per frame.
        let largest_step = |p: &[HeadAngles]| {
            p.windows(2)
                .map(|w| (w[1].pitch_deg - w[0].pitch_deg).hypot(w[1].yaw_deg - w[0].yaw_deg))
                .fold(0.0f32, f32::max)
        };
        assert!(largest_step(&at_240) <= 0.5 * largest_step(&at_120) + 1e-6);
    }

    #[test]
    fn the_head_steps_at_its_model_rate_in_a_slower_stream() {
        // At 30 frames/s frame i (at 4i / 120 s) brings the four 120 Hz steps since the last
        // frame, on its features: the pose of a 120 Hz stream that holds each frame for the
        // four steps up to it, at its own step.
        let voice: Vec<FeatureFrame> = wandering_voice(1200).into_iter().step_by(4).collect();
        let at_30 = run(voice.iter().copied(), 30.0);
        let held = run(
            std::iter::once(voice[0]).chain(voice[1..].iter().flat_map(|f| [*f; 4])),
            120.0,
        );
        assert!(at_30[150] != at_30[0], "the voice moved the head");
        for (i, a) in at_30.iter().enumerate() {
            assert_eq!(*a, held[4 * i], "frame {i}");
        }
        // A rate the steps do not divide (50 frames/s: 2 or 3 steps a frame) keeps time: by
        // the frame at 10 s the head has taken its steps at 0, 1/120, …, 10 s, as at 120 Hz.
        let mut s =
            HeadSynth::new(HeadModel::default_model().clone(), HeadConfig::default()).unwrap();
        for f in wandering_voice(501) {
            s.process(&f, 50.0);
        }
        assert_eq!(s.steps_taken, 1201);
    }

    #[test]
    fn default_model_moves_stays_finite_and_within_limits() {
        let mut s =
            HeadSynth::new(HeadModel::default_model().clone(), HeadConfig::default()).unwrap();
        let mut last = HeadAngles::default();
        let mut moved = 0;
        for i in 0..600 {
            let f0 = 4.0 * (i as f32 * 0.05).sin();
            let a = s.process(&voiced(i, f0, 0.0), 120.0);
            assert!(
                a.pitch_deg.abs() <= 8.0 && a.yaw_deg.abs() <= 15.0 && a.roll_deg.abs() <= 12.0
            );
            if a != last {
                moved += 1;
            }
            last = a;
        }
        assert!(moved > 500, "moved on {moved} of 600 frames");
        let nan = FeatureFrame {
            f0_st: f32::NAN,
            level_db: f32::INFINITY,
            ..voiced(600, 0.0, 0.0)
        };
        let a = s.process(&nan, f64::NAN);
        assert!(a.pitch_deg.is_finite() && a.yaw_deg.is_finite() && a.roll_deg.is_finite());
    }

    /// Mean angular speed of the default model's head over the last 20 s of a 30 s voiced
    /// stretch whose f0 swings ±`swing_st` semitones at `f_hz` (level swinging with it).
    fn speed_for_voice(model: &HeadModel, swing_st: f32, f_hz: f32) -> f64 {
        let mut s = HeadSynth::new(model.clone(), HeadConfig::default()).unwrap();
        let pose: Vec<[f64; 3]> = (0..3600u64)
            .map(|i| {
                let w = std::f32::consts::TAU * f_hz * i as f32 / 120.0;
                let a = s.process(&voiced(i, swing_st * w.sin(), 4.0 * w.cos()), 120.0);
                [a.roll_deg as f64, a.pitch_deg as f64, a.yaw_deg as f64]
            })
            .collect();
        crate::head::metrics::mean_speed(&pose[1200..], 120.0)
    }

    #[test]
    fn the_model_smoother_slows_the_ungoverned_motion() {
        let mut raw = HeadModel::default_model().clone();
        let mut w = raw.synthesis;
        w.speed_target_deg_s = 0.0;
        w.smoothing_s = 0.0;
        raw.set_synthesis(w).unwrap();
        let mut smoothed = raw.clone();
        w.smoothing_s = 0.25;
        smoothed.set_synthesis(w).unwrap();
        // A fast syllable-rate f0 wobble: busy motion, which the smoother takes out.
        let (r, s) = (
            speed_for_voice(&raw, 3.0, 5.0),
            speed_for_voice(&smoothed, 3.0, 5.0),
        );
        assert!(s < 0.6 * r, "smoothed {s:.1} °/s against raw {r:.1} °/s");
    }

    /// The default model with the speed governor on (target 18 °/s, 1 s: the shipped model
    /// runs without it, the governor tests use its densities).
    fn governed_default() -> HeadModel {
        let mut model = HeadModel::default_model().clone();
        let mut w = model.synthesis;
        w.speed_target_deg_s = 18.0;
        w.speed_time_s = 1.0;
        model.set_synthesis(w).unwrap();
        model
    }

    #[test]
    fn expressive_and_flat_voices_move_at_believable_speeds() {
        let model = governed_default();
        let target = model.synthesis.speed_target_deg_s;
        let mut ungoverned = model.clone();
        let mut w = model.synthesis;
        w.speed_target_deg_s = 0.0;
        w.smoothing_s = 0.0;
        ungoverned.set_synthesis(w).unwrap();
        let voices = [(9.0, 2.0), (1.5, 0.4)];
        // Premise: the raw argmax (no smoother, no governor) moves these voices far faster
        // than real heads.
        let raw = voices.map(|(a, f)| speed_for_voice(&ungoverned, a, f));
        assert!(
            raw.iter().all(|r| r / target > 1.4),
            "ungoverned speeds {raw:?}, target {target}"
        );
        for (a, f) in voices {
            let got = speed_for_voice(&model, a, f);
            assert!(
                (0.7..=1.4).contains(&(got / target)),
                "f0 ±{a} st at {f} Hz: {got:.1} °/s against the target {target:.1} °/s (ungoverned {raw:?})"
            );
        }
    }

    /// The governed default model's head with `unvoiced` behaviour over 20 s of voice (f0 ±3 st at
    /// 1 Hz, level with it), a pause of `pause_s` (unvoiced, quiet) and 20 s of the same voice:
    /// (mean speed over the last 10 s before the pause, mean speed over the first 3 s after
    /// it), °/s.
    fn speeds_around_a_pause(pause_s: f64, unvoiced: UnvoicedBehaviour) -> (f64, f64) {
        let config = HeadConfig {
            unvoiced: Some(unvoiced),
            ..HeadConfig::default()
        };
        let mut s = HeadSynth::new(governed_default(), config).unwrap();
        let voice_n = 20 * 120;
        let pause_n = (pause_s * 120.0) as usize;
        let pose: Vec<[f64; 3]> = (0..2 * voice_n + pause_n)
            .map(|i| {
                let w = std::f32::consts::TAU * i as f32 / 120.0;
                let frame = if (voice_n..voice_n + pause_n).contains(&i) {
                    FeatureFrame {
                        f0_hz: 0.0,
                        voiced: false,
                        voicing: 0.0,
                        rms_db: -60.0,
                        f0_st: f32::NAN,
                        level_db: -30.0,
                        ..voiced(i as u64, 0.0, 0.0)
                    }
                } else {
                    voiced(i as u64, 3.0 * w.sin(), 4.0 * w.cos())
                };
                let a = s.process(&frame, 120.0);
                [a.roll_deg as f64, a.pitch_deg as f64, a.yaw_deg as f64]
            })
            .collect();
        let speed = |a: usize, b: usize| crate::head::metrics::mean_speed(&pose[a..b], 120.0);
        let resumed = voice_n + pause_n;
        (
            speed(voice_n - 1200, voice_n),
            speed(resumed, resumed + 360),
        )
    }

    #[test]
    fn after_a_long_pause_the_head_resumes_at_its_speaking_speed() {
        for unvoiced in [UnvoicedBehaviour::Return, UnvoicedBehaviour::LoudnessModel] {
            for pause_s in [3.0, 8.0] {
                let (before, after) = speeds_around_a_pause(pause_s, unvoiced);
                assert!(
                    (0.7..=1.3).contains(&(after / before)),
                    "{unvoiced:?}, {pause_s} s pause: {after:.1} °/s in the 3 s after it, {before:.1} °/s before it"
                );
            }
        }
    }

    #[test]
    fn quaternion_axes_follow_the_conventions() {
        let fwd = glam::Vec3::Z;
        let up = glam::Vec3::Y;
        let chin_up = angles_to_quat(&HeadAngles {
            pitch_deg: 10.0,
            ..Default::default()
        });
        assert!((chin_up * fwd).y > 0.1);
        let left = angles_to_quat(&HeadAngles {
            yaw_deg: 10.0,
            ..Default::default()
        });
        assert!((left * fwd).x > 0.1, "x is the character's left");
        let tilt = angles_to_quat(&HeadAngles {
            roll_deg: 10.0,
            ..Default::default()
        });
        assert!((tilt * up).x > 0.1);
    }
}
