//! The seam where a new engine takes over while playing ([`crate::rebuild`]: a mode, lookahead
//! or frame-rate change). The new engine starts empty: in lookahead mode its output is silence
//! for the new latency and then the input from the swap on; in live mode the undelayed input
//! at once. Both ends of that seam were steps in the waveform, heard as clicks. [`Seam`] makes
//! them ramps of [`SEAM_S`]: the old engine's last output sample falls to the new output with a
//! raised cosine, and (when the new engine delays its output) the input it hears rises from 0
//! with the complementary one, so its output starts from 0 too when it comes out of the delay.
//! A live engine's output is the input itself, already continuous: its input is left alone.
//!
//! Only a swap that replaces an engine that already played since activation is smoothed: the
//! first engine of an activation, a stream restart (transport start, jump, pre-roll: the ramps
//! stop there) and every block without a swap pass untouched, so the plugin stays equal to
//! `pneuma render`. Never allocates.

use std::f64::consts::PI;

/// Length of the ramps, seconds: longer than a period of the lowest voice (about 10 ms at
/// 100 Hz), short enough not to be heard as a fade.
pub const SEAM_S: f64 = 0.005;

/// Channels the seam follows (the plugin's layouts have at most two).
const CHANNELS: usize = 2;

/// See the module docs.
#[derive(Debug, Clone, Copy, Default)]
pub struct Seam {
    /// Ramp length, samples (0 before `activate`).
    len: usize,
    /// The last output sample of each channel.
    last: [f32; CHANNELS],
    /// Output has been produced since activation.
    played: bool,
    /// Samples of the ramps done, while they run.
    at: Option<usize>,
    /// The old output's last samples less the new output's first, per channel.
    offset: [f32; CHANNELS],
    /// A swap happened at the start of this block.
    armed: bool,
    /// The input ramps too (the new engine delays its output).
    ramp_input: bool,
}

impl Seam {
    /// A new activation at `sample_rate_hz`: nothing played yet.
    pub fn activate(sample_rate_hz: f32) -> Self {
        Self {
            len: (SEAM_S * f64::from(sample_rate_hz)).round().max(1.0) as usize,
            ..Self::default()
        }
    }

    /// An engine with `latency` samples was swapped in at the start of this block.
    pub fn swapped(&mut self, latency: u32) {
        self.armed = self.played && self.len > 0;
        self.ramp_input = latency > 0;
    }

    /// The stream starts afresh in this block (a transport jump, a pre-roll's end): no seam, and
    /// ramps still running stop.
    pub fn restart(&mut self) {
        self.armed = false;
        self.at = None;
    }

    /// Raised cosine from 1 (at 0) to 0 (at `len`).
    fn falling(&self, k: usize) -> f32 {
        (0.5 * (1.0 + (PI * k as f64 / self.len as f64).cos())) as f32
    }

    /// Before the engine runs the block: the input rises from 0 after a swap.
    pub fn before(&mut self, audio: &mut [&mut [f32]]) {
        if self.armed {
            self.at = Some(0);
        }
        let (Some(at), true) = (self.at, self.ramp_input) else {
            return;
        };
        for channel in audio.iter_mut().take(CHANNELS) {
            for (k, x) in channel.iter_mut().take(self.len - at).enumerate() {
                *x *= 1.0 - self.falling(at + k);
            }
        }
    }

    /// After the engine ran the block: the old output's last sample falls to the new output.
    pub fn after(&mut self, audio: &mut [&mut [f32]]) {
        if self.armed {
            self.armed = false;
            for (c, channel) in audio.iter().enumerate().take(CHANNELS) {
                self.offset[c] = self.last[c] - channel.first().copied().unwrap_or(0.0);
            }
        }
        let n = audio.first().map_or(0, |c| c.len());
        if let Some(at) = self.at {
            for (c, channel) in audio.iter_mut().enumerate().take(CHANNELS) {
                let ramped_len = (self.len - at).min(channel.len());
                let ramped = &mut channel[..ramped_len];
                for (k, y) in ramped.iter_mut().enumerate() {
                    *y += self.offset[c] * self.falling(at + k);
                }
                // Never a subnormal where the ramp ends on silence (hosts refuse them).
                crate::sanitize_in_place(ramped);
            }
            self.at = Some(at + n).filter(|&a| a < self.len);
        }
        for (c, channel) in audio.iter().enumerate().take(CHANNELS) {
            if let Some(&y) = channel.last() {
                self.last[c] = y;
            }
        }
        self.played |= n > 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_swap_turns_both_steps_into_ramps_and_nothing_else_changes() {
        let mut seam = Seam::activate(48_000.0);
        let len = (SEAM_S * 48_000.0) as usize;
        // A block before the swap ends at 0.5; blocks without a swap pass untouched.
        let mut block = vec![0.5f32; 64];
        seam.before(&mut [&mut block[..]]);
        seam.after(&mut [&mut block[..]]);
        assert!(block.iter().all(|&x| x == 0.5));
        seam.swapped(24_000);
        // The new engine hears a constant 0.8 and (lookahead) puts out silence.
        let mut input = vec![0.8f32; 2 * len];
        seam.before(&mut [&mut input[..]]);
        assert_eq!(input[0], 0.0, "the input starts from 0");
        assert!(input.windows(2).all(|w| w[1] >= w[0]) && input[len] == 0.8);
        let mut output = vec![0.0f32; 2 * len];
        seam.after(&mut [&mut output[..]]);
        assert_eq!(
            output[0], 0.5,
            "the output starts where the old engine's ended"
        );
        assert!(output.windows(2).all(|w| w[1] <= w[0]) && output[len] == 0.0);
        let step = output
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f32::max);
        assert!(
            step < 0.5 * PI as f32 / len as f32 * 1.01,
            "largest step {step}"
        );
        // The first engine of an activation is not smoothed.
        let mut fresh = Seam::activate(48_000.0);
        fresh.swapped(24_000);
        let mut block = [0.8f32; 8];
        fresh.before(&mut [&mut block[..]]);
        fresh.after(&mut [&mut block[..]]);
        assert!(block.iter().all(|&x| x == 0.8));
    }

    #[test]
    fn the_ramps_carry_on_across_short_blocks() {
        let mut seam = Seam::activate(48_000.0);
        let len = (SEAM_S * 48_000.0) as usize;
        let mut last = [-0.3f32; 4];
        seam.after(&mut [&mut last[..]]);
        seam.swapped(24_000);
        let (mut heard, mut out) = (Vec::new(), Vec::new());
        for _ in 0..(2 * len / 7) {
            let mut block = [0.6f32; 7];
            seam.before(&mut [&mut block[..]]);
            heard.extend(block);
            // The new engine's output: silence (its lookahead).
            let mut silent = [0.0f32; 7];
            seam.after(&mut [&mut silent[..]]);
            out.extend(silent);
        }
        assert_eq!((heard[0], out[0]), (0.0, -0.3));
        assert!(
            heard.windows(2).all(|w| w[1] >= w[0]),
            "a rising ramp, in pieces"
        );
        assert!(
            out.windows(2).all(|w| w[1] >= w[0]),
            "a falling ramp, in pieces"
        );
        assert!(heard[len..].iter().all(|&x| x == 0.6));
        assert!(out[len..].iter().all(|&x| x == 0.0));
    }

    #[test]
    fn a_live_engine_hears_its_input_and_a_restart_ends_the_seam() {
        let mut seam = Seam::activate(48_000.0);
        let mut last = [0.4f32; 4];
        seam.after(&mut [&mut last[..]]);
        seam.swapped(0);
        let mut input = [0.5f32; 8];
        seam.before(&mut [&mut input[..]]);
        assert!(
            input.iter().all(|&x| x == 0.5),
            "the live input is already continuous"
        );
        seam.after(&mut [&mut input[..]]);
        assert!((input[0] - 0.4).abs() < 1e-6, "{input:?}");
        // A jump in the middle of the ramps: the fresh stream passes untouched.
        seam.restart();
        let mut block = [0.5f32; 8];
        seam.before(&mut [&mut block[..]]);
        seam.after(&mut [&mut block[..]]);
        assert!(block.iter().all(|&x| x == 0.5));
    }
}
