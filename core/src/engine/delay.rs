//! The engine's delay line: one power-of-two ring per channel, written with the cleaned input
//! and read `latency` samples later (the lookahead; 0 in live mode), like a plugin's dry path.

/// Per-channel delay rings. Allocation-free after `new`.
#[derive(Debug, Clone)]
pub(crate) struct DelayLine {
    rings: Vec<Vec<f32>>,
    mask: usize,
    latency: usize,
}

impl DelayLine {
    /// Rings for `channels` channels delaying by `latency` samples, for blocks of at most
    /// `max_block`. Allocates.
    pub(crate) fn new(channels: usize, latency: usize, max_block: usize) -> Self {
        let ring = (latency + max_block + 1).next_power_of_two();
        Self {
            rings: vec![vec![0.0; ring]; channels],
            mask: ring - 1,
            latency,
        }
    }

    /// The delay, samples.
    pub(crate) fn latency(&self) -> usize {
        self.latency
    }

    /// Silence in every ring.
    pub(crate) fn reset(&mut self) {
        self.rings.iter_mut().for_each(|r| r.fill(0.0));
    }

    /// Writes `input` (already cleaned) of channel `c` at stream position `base`.
    pub(crate) fn write(&mut self, c: usize, base: u64, input: impl Iterator<Item = f32>) {
        let (ring, mask) = (&mut self.rings[c], self.mask);
        for (i, x) in input.enumerate() {
            ring[(base as usize + i) & mask] = x;
        }
    }

    /// Overwrites `out` with channel `c` as written `latency` samples before stream position
    /// `base` onwards.
    pub(crate) fn read(&self, c: usize, base: u64, out: &mut [f32]) {
        let (ring, mask) = (&self.rings[c], self.mask);
        for (i, y) in out.iter_mut().enumerate() {
            *y = ring[(base as usize + i + mask + 1 - self.latency) & mask];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delays_by_the_latency_across_blocks() {
        let mut d = DelayLine::new(1, 5, 4);
        let input: Vec<f32> = (1..=12).map(|i| i as f32).collect();
        let mut out = Vec::new();
        for (k, block) in input.chunks(4).enumerate() {
            let base = (k * 4) as u64;
            d.write(0, base, block.iter().copied());
            let mut y = vec![-1.0; block.len()];
            d.read(0, base, &mut y);
            out.extend(y);
        }
        let expected: Vec<f32> = [0; 5].into_iter().chain(1..=7).map(|x| x as f32).collect();
        assert_eq!(out, expected);
        d.reset();
        let mut y = vec![-1.0; 4];
        d.read(0, 12, &mut y);
        assert_eq!(y, vec![0.0; 4]);
    }
}
