//! A recorded analysis: the feature frames a whole-file learning pass
//! ([`super::voice_learning::VoiceLearner::recording`]) computed, each with the stream sample
//! that completed it ([`AnalysisRecord`]), handed to the render's engine
//! ([`super::Engine::replay_analysis`]) so that a render that learns the voice from the whole
//! file first analyses the file once, not twice.
//!
//! The learning pass hears what the engine would: the same mono mix
//! ([`super::voice_learning::mix_to_mono`]), the same analysis settings and rate, the input
//! followed by the engine's tail of silence ([`super::Engine::tail_samples`]). The analysis is
//! the same for any block partition, so the replayed frames are the ones the engine's own
//! analyzer would compute, bit for bit, and so is the render.
//!
//! The record also carries the speech of the whole input ([`WholeSpeech`]): a replayed render
//! colours the built-in voice with it instead of listening as it goes.
//!
//! Memory: one frame per analysis frame of the file, 72 bytes each (about 31 MB per hour at
//! the default 120 frames/s), reserved at once when the file announces its length.

use crate::analysis::FeatureFrame;
use crate::breathing::third_octave::{Bands, BANDS};

/// The frames of one stream's analysis, in order, each with the index of the stream sample
/// that completed it (the input's samples, then its tail of silence).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AnalysisRecord {
    /// The stream's sample rate and analysis frame rate.
    rate_hz: f64,
    frame_rate_hz: f64,
    /// The samples heard, in order ([`SampleHash`]).
    hash: SampleHash,
    frames: Vec<(FeatureFrame, u64)>,
    /// Samples heard in all: the input and its tail of silence.
    samples: u64,
    /// The speech of the whole input as the learning pass heard it.
    speech: WholeSpeech,
}

/// The speech of a whole input, heard before it is rendered: what colours the built-in voice
/// ([`crate::breathing::reference::ReferenceVoice::coloured`]) and sets a voice's level
/// against the speech when the render does not listen as it goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WholeSpeech {
    /// The long-term third-octave spectrum of the voiced speech, dB per band (NaN without).
    pub ltas_db: Bands,
    /// The median level of the voiced frames, dBFS (NaN without any).
    pub speech_db: f64,
    /// The upper edge of the voiced speech's spectrum, Hz (`None` with too little speech):
    /// inserted breaths stay under it ([`crate::breathing::band_limit`]).
    pub upper_edge_hz: Option<f64>,
}

impl Default for WholeSpeech {
    fn default() -> Self {
        Self {
            ltas_db: [f64::NAN; BANDS],
            speech_db: f64::NAN,
            upper_edge_hz: None,
        }
    }
}

/// A running FNV-1a hash of samples (their bits), the same for any partition: tells a replay
/// whether the engine hears the samples its record was made from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct SampleHash(u64);

impl Default for SampleHash {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

impl SampleHash {
    fn add(&mut self, samples: &[f32]) {
        for x in samples {
            self.0 = (self.0 ^ u64::from(x.to_bits())).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

impl AnalysisRecord {
    /// An empty record of a stream at `rate_hz` analysed at `frame_rate_hz`.
    pub(super) fn new(rate_hz: f64, frame_rate_hz: f64) -> Self {
        Self {
            rate_hz,
            frame_rate_hz,
            ..Self::default()
        }
    }

    /// The stream's sample rate and analysis frame rate.
    pub fn rates(&self) -> (f64, f64) {
        (self.rate_hz, self.frame_rate_hz)
    }

    /// Samples the record covers: the input and its tail of silence.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Frames recorded.
    pub fn frames(&self) -> usize {
        self.frames.len()
    }

    /// The speech of the whole input.
    pub fn speech(&self) -> WholeSpeech {
        self.speech
    }

    /// The learning pass heard `speech` in the whole input.
    pub(super) fn set_speech(&mut self, speech: WholeSpeech) {
        self.speech = speech;
    }

    /// Makes room for the frames of `samples` more samples (a file's announced length): the
    /// record then grows once, not by doubling. Allocates.
    pub(super) fn reserve_for(&mut self, samples: u64) {
        let frames = (samples as f64 * self.frame_rate_hz / self.rate_hz.max(1.0)).ceil();
        self.frames.reserve(frames as usize + 1);
    }

    /// Records `frame`, completed by stream sample `at` (not before the last one's).
    pub(super) fn push(&mut self, frame: FeatureFrame, at: u64) {
        debug_assert!(self.frames.last().is_none_or(|&(_, last)| last <= at));
        self.frames.push((frame, at));
    }

    /// More `samples` heard (the input's, then its tail of silence).
    pub(super) fn heard(&mut self, samples: &[f32]) {
        self.hash.add(samples);
        self.samples += samples.len() as u64;
    }
}

/// The engine's place in a record: the next frame to hand out.
#[derive(Debug)]
pub(super) struct Replay {
    record: AnalysisRecord,
    next: usize,
    /// The samples the engine heard since the stream's start, and how many.
    heard: SampleHash,
    samples: u64,
}

impl Replay {
    pub(super) fn new(record: AnalysisRecord) -> Self {
        Self {
            record,
            next: 0,
            heard: SampleHash::default(),
            samples: 0,
        }
    }

    /// Back to the stream's start.
    pub(super) fn reset(&mut self) {
        self.next = 0;
        self.heard = SampleHash::default();
        self.samples = 0;
    }

    /// The engine heard `mono` (the mix the analysis would hear).
    pub(super) fn hear(&mut self, mono: &[f32]) {
        self.heard.add(mono);
        self.samples += mono.len() as u64;
    }

    /// Whether the engine has heard, from the stream's start, exactly the samples the record
    /// was made from (its input and tail, no more, no fewer).
    pub(super) fn verified(&self) -> bool {
        self.samples == self.record.samples && self.heard == self.record.hash
    }

    /// The frames completed by the samples `base..base + n` of the stream, each with its
    /// sample's offset in the block. Returns how many of those samples lie past the record
    /// (they get no frames). Never allocates.
    pub(super) fn block(
        &mut self,
        base: u64,
        n: usize,
        mut on_frame: impl FnMut(&FeatureFrame, usize),
    ) -> u64 {
        let end = base + n as u64;
        while let Some((f, at)) = self.record.frames.get(self.next) {
            if *at >= end {
                break;
            }
            if *at >= base {
                on_frame(f, (*at - base) as usize);
            }
            self.next += 1;
        }
        end.saturating_sub(self.record.samples.max(base))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hash_knows_the_samples_in_any_partition() {
        let x: Vec<f32> = (0..1000).map(|i| (i as f32 * 0.01).sin()).collect();
        let mut r = AnalysisRecord::new(16_000.0, 100.0);
        r.heard(&x);
        for blocks in [vec![1000], vec![3, 500, 497], vec![1; 1000]] {
            let mut replay = Replay::new(r.clone());
            let mut at = 0;
            for n in blocks {
                replay.hear(&x[at..at + n]);
                at += n;
            }
            assert!(replay.verified());
        }
        let mut other = x.clone();
        other[500] += 1e-6;
        let mut replay = Replay::new(r.clone());
        replay.hear(&other);
        assert!(!replay.verified(), "one sample changed");
        let mut short = Replay::new(r);
        short.hear(&x[..999]);
        assert!(!short.verified(), "one sample missing");
    }

    fn frame(index: u64) -> FeatureFrame {
        FeatureFrame {
            index,
            ..FeatureFrame::default()
        }
    }

    #[test]
    fn hands_out_each_frame_once_at_its_offset_in_any_partition() {
        let mut r = AnalysisRecord::default();
        for (k, at) in [3u64, 9, 10, 25].into_iter().enumerate() {
            r.push(frame(k as u64), at);
        }
        r.heard(&[0.5; 20]);
        r.heard(&[0.0; 10]);
        assert_eq!((r.samples(), r.frames()), (30, 4));
        for blocks in [vec![30], vec![1, 7, 2, 20], vec![10, 10, 10]] {
            let mut replay = Replay::new(r.clone());
            let (mut got, mut base) = (Vec::new(), 0u64);
            for n in blocks {
                let past = replay.block(base, n, |f, i| got.push((f.index, base + i as u64)));
                assert_eq!(past, 0);
                base += n as u64;
            }
            assert_eq!(got, vec![(0, 3), (1, 9), (2, 10), (3, 25)]);
            replay.reset();
            let mut again = 0;
            replay.block(0, 30, |_, _| again += 1);
            assert_eq!(again, 4, "reset rewinds to the start");
        }
    }

    #[test]
    fn counts_the_samples_past_the_record() {
        let mut r = AnalysisRecord::default();
        r.heard(&[0.1; 100]);
        let mut replay = Replay::new(r);
        assert_eq!(replay.block(0, 64, |_, _| {}), 0);
        assert_eq!(replay.block(64, 64, |_, _| {}), 28);
        assert_eq!(replay.block(128, 64, |_, _| {}), 64);
    }
}
