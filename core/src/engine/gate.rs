//! Live mode's input gate: marks, sample by sample, where the input is active (speech may have
//! resumed), so a live breath gives way within milliseconds, long before the analysis frames
//! confirm an onset (a frame's features only exist half an analysis window after its centre).
//!
//! The input's mean square is followed by a fast envelope (time constant
//! [`ENVELOPE_S`]) and a slow one (20 ms). The slow envelope, in dB once per millisecond, feeds a
//! minimum-statistics floor ([`NoiseFloor`], the minimum over the last [`FLOOR_WINDOW_S`]), so
//! the floor drops at once when a pause begins and stands at the pause's background within
//! its first milliseconds. A sample is active when the fast envelope stands [`MARGIN_DB`] over
//! that floor and over the silence level. Allocation-free after `prepare`.

use crate::analysis::noise_floor::NoiseFloor;

/// Time constant of the fast envelope, seconds.
pub(crate) const ENVELOPE_S: f64 = 0.002;
/// Time constant of the slow envelope that teaches the floor, seconds.
const SLOW_S: f64 = 0.02;
/// The input is active once its fast envelope stands this far over the floor, dB (quiet
/// consonants included).
pub(crate) const MARGIN_DB: f64 = 9.0;
/// The floor is the minimum of the slow envelope over this long, seconds.
const FLOOR_WINDOW_S: f64 = 1.0;
/// Floor ticks per second.
const TICK_HZ: f64 = 1000.0;
/// Floor blocks in the window.
const FLOOR_BLOCKS: usize = 10;

/// The live input gate. See the module docs.
#[derive(Debug, Clone)]
pub(crate) struct InputGate {
    env_coef: f64,
    slow_coef: f64,
    tick_samples: u32,
    /// Mean square under which the input is silence whatever the floor.
    silence_ms: f64,
    floor: NoiseFloor,
    state: GateState,
}

/// What [`InputGate::reset`] clears.
#[derive(Debug, Clone, Copy)]
struct GateState {
    env: f64,
    slow: f64,
    in_tick: u32,
    /// Mean square the fast envelope must exceed (+∞ until the floor has its first tick).
    threshold_ms: f64,
}

impl Default for GateState {
    fn default() -> Self {
        Self {
            env: 0.0,
            slow: 0.0,
            in_tick: 0,
            threshold_ms: f64::INFINITY,
        }
    }
}

impl InputGate {
    /// A gate for `sample_rate_hz` whose silence level is `silence_db` dBFS. Allocates.
    pub(crate) fn new(sample_rate_hz: f64, silence_db: f32) -> Self {
        let coef = |s: f64| 1.0 - (-1.0 / (s * sample_rate_hz)).exp();
        let tick_samples = (sample_rate_hz / TICK_HZ).round().max(1.0) as u32;
        let block_ticks = (FLOOR_WINDOW_S * TICK_HZ / FLOOR_BLOCKS as f64).round() as usize;
        Self {
            env_coef: coef(ENVELOPE_S),
            slow_coef: coef(SLOW_S),
            tick_samples,
            silence_ms: 10f64.powf(silence_db as f64 / 10.0),
            floor: NoiseFloor::with_blocks(block_ticks, FLOOR_BLOCKS),
            state: GateState::default(),
        }
    }

    /// Back to the start of a stream.
    pub(crate) fn reset(&mut self) {
        self.floor.reset();
        self.state = GateState::default();
    }

    /// Marks in `active` (as long as `mono`) every sample where the input is active.
    pub(crate) fn process(&mut self, mono: &[f32], active: &mut [bool]) {
        debug_assert_eq!(mono.len(), active.len());
        let mut s = self.state;
        for (x, a) in mono.iter().zip(active.iter_mut()) {
            let p = (*x as f64) * (*x as f64);
            s.env += self.env_coef * (p - s.env);
            s.slow += self.slow_coef * (p - s.slow);
            s.in_tick += 1;
            if s.in_tick >= self.tick_samples {
                s.in_tick = 0;
                let slow_db = (10.0 * s.slow.max(1e-30).log10()) as f32;
                let floor_db = self.floor.update(Some(slow_db)) as f64;
                s.threshold_ms = self
                    .silence_ms
                    .max(10f64.powf((floor_db + MARGIN_DB) / 10.0));
            }
            *a = s.env > s.threshold_ms;
        }
        self.state = s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(gate: &mut InputGate, x: &[f32]) -> Vec<bool> {
        let mut a = vec![false; x.len()];
        gate.process(x, &mut a);
        a
    }

    #[test]
    fn trips_within_milliseconds_of_speech_after_a_noisy_pause() {
        let sr = 16_000.0;
        let mut gate = InputGate::new(sr, -75.0);
        // 1.5 s of loud tone (a phrase), 0.5 s of noise at -40 dBFS, then the tone again.
        let tone = |n: usize| -> Vec<f32> {
            (0..n)
                .map(|i| 0.3 * (i as f32 * 0.1).sin())
                .collect::<Vec<_>>()
        };
        let noise = pneuma_testkit::signals::white_noise(8000, 0.01, 5);
        let mut x = tone(24_000);
        x.extend(&noise);
        let onset = x.len();
        x.extend(tone(4000));
        let a = run(&mut gate, &x);
        // Quiet through the pause once the phrase's decay is over.
        let pause_from = 24_000 + 800;
        let stray = a[pause_from..onset].iter().filter(|&&v| v).count();
        assert_eq!(stray, 0, "active samples in the noisy pause");
        let trip = a[onset..].iter().position(|&v| v).expect("never tripped");
        assert!(trip < 32, "tripped {trip} samples after the onset");
    }

    #[test]
    fn digital_silence_is_never_active_and_reset_forgets() {
        let mut gate = InputGate::new(48_000.0, -75.0);
        assert!(!run(&mut gate, &[0.0; 4800]).contains(&true));
        let loud = vec![0.5f32; 480];
        assert!(run(&mut gate, &loud).contains(&true));
        gate.reset();
        // Before the floor's first tick nothing is active.
        assert!(!run(&mut gate, &loud[..40]).contains(&true));
    }
}
