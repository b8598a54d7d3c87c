//! Learning the speaker's breath voice from a recording before a whole-file render
//! ([`VoiceLearner`]): the recording streams through the engine's analysis and phrase tracker
//! (the same settings, so the breaths heard are the ones the render will hear), every breath
//! heard in a pause (`Pause::breath_s`) is measured in third-octave bands from a ring of the
//! last [`RING_S`] seconds of audio, the room's floor is estimated frame by frame, and the
//! speech level is the median RMS of the voiced frames. [`VoiceLearner::finish`] turns them
//! into a [`LearnedVoice`] (none when no breath was heard: the built-in voice stays).
//!
//! Memory is bounded by the ring, the floor's histogram and one record per heard breath.
//! Allocates: offline only (the plugin and `render --lookahead-ms` keep the built-in voice).

use super::{EngineConfig, EngineError};
use crate::analysis::{Analyzer, FeatureFrame};
use crate::breathing::learned::{HeardBreath, LearnedVoice};
use crate::breathing::third_octave::{BandAnalyzer, FloorEstimate};
use crate::phrase::{PhraseEvent, PhraseTracker};

/// Audio kept to measure a breath once the tracker reports it, seconds.
pub const RING_S: f64 = 30.0;
/// Block the analysis is fed in.
const BLOCK: usize = 4096;
/// Speech-level histogram: 0.1 dB bins from −120 to 0 dBFS.
const LEVEL_BINS: usize = 1200;

/// See the module docs.
#[derive(Debug)]
pub struct VoiceLearner {
    rate_hz: f64,
    analyzer: Analyzer,
    tracker: PhraseTracker,
    bands: BandAnalyzer,
    floor: FloorEstimate,
    ring: Vec<f32>,
    /// Samples fed so far.
    fed: u64,
    /// The floor's frame being filled.
    chunk: Vec<f32>,
    heard: Vec<HeardBreath>,
    voiced_levels: Vec<u64>,
    scratch: Vec<f32>,
}

impl VoiceLearner {
    /// A learner with the analysis and phrase settings of `config` at `rate_hz`.
    pub fn new(config: &EngineConfig, rate_hz: f64) -> Result<Self, EngineError> {
        let mut analyzer = Analyzer::new(config.analysis.clone())?;
        analyzer.prepare(rate_hz, BLOCK)?;
        let tracker = PhraseTracker::new(config.phrase, config.analysis.frame_rate_hz)?;
        let bands = BandAnalyzer::new(rate_hz);
        Ok(Self {
            rate_hz,
            analyzer,
            tracker,
            chunk: Vec::with_capacity(bands.frame()),
            bands,
            floor: FloorEstimate::default(),
            ring: vec![0.0; (RING_S * rate_hz).ceil() as usize],
            fed: 0,
            heard: Vec::new(),
            voiced_levels: vec![0; LEVEL_BINS],
            scratch: Vec::new(),
        })
    }

    /// Feeds the next mono samples of the recording.
    pub fn feed(&mut self, mono: &[f32]) -> Result<(), EngineError> {
        for block in mono.chunks(BLOCK) {
            for &x in block {
                let x = if x.is_finite() { x } else { 0.0 };
                let n = self.ring.len() as u64;
                self.ring[(self.fed % n) as usize] = x;
                self.fed += 1;
                self.chunk.push(x);
                if self.chunk.len() == self.bands.frame() {
                    let p = self.bands.powers(&self.chunk);
                    self.floor.add(&p);
                    self.chunk.clear();
                }
            }
            let mut frames: Vec<FeatureFrame> = Vec::new();
            self.analyzer
                .process(block, |f| frames.push(*f))
                .map_err(EngineError::from)?;
            for f in &frames {
                self.on_frame(f);
            }
        }
        Ok(())
    }

    fn on_frame(&mut self, f: &FeatureFrame) {
        if f.voiced && f.rms_db.is_finite() {
            let bin = ((f64::from(f.rms_db) + 120.0) * 10.0).clamp(0.0, LEVEL_BINS as f64 - 1.0);
            self.voiced_levels[bin as usize] += 1;
        }
        let mut spans: [Option<(f64, f64)>; 3] = [None; 3];
        let mut k = 0;
        self.tracker.update(f, |e| {
            if let PhraseEvent::Start { pause, .. } = e {
                if k < spans.len() {
                    spans[k] = pause.breath_s;
                    k += 1;
                }
            }
        });
        for span in spans.into_iter().flatten() {
            self.measure(span);
        }
    }

    /// Measures the breath at `(start_s, end_s)` if the ring still holds it.
    fn measure(&mut self, (start_s, end_s): (f64, f64)) {
        let a = (start_s * self.rate_hz).round().max(0.0) as u64;
        let b = ((end_s * self.rate_hz).round() as u64).min(self.fed);
        let n = self.ring.len() as u64;
        if b <= a || self.fed - a > n {
            return;
        }
        self.scratch.clear();
        self.scratch
            .extend((a..b).map(|i| self.ring[(i % n) as usize]));
        self.heard.push(HeardBreath {
            powers: self.bands.powers(&self.scratch),
            length_s: end_s - start_s,
        });
    }

    /// Breaths heard so far.
    pub fn heard(&self) -> usize {
        self.heard.len()
    }

    /// Ends the recording and learns the voice (`None`: no breath was heard).
    pub fn finish(mut self) -> Result<Option<LearnedVoice>, EngineError> {
        let mut frames: Vec<FeatureFrame> = Vec::new();
        self.analyzer
            .finish(|f| frames.push(*f))
            .map_err(EngineError::from)?;
        for f in &frames {
            self.on_frame(f);
        }
        Ok(LearnedVoice::learn(
            &self.heard,
            &self.floor.floor(),
            self.speech_db(),
            self.rate_hz,
        ))
    }

    /// The median level of the voiced frames so far, dBFS (NaN before any).
    pub fn speech_db(&self) -> f64 {
        let total: u64 = self.voiced_levels.iter().sum();
        let mut seen = 0;
        for (bin, c) in self.voiced_levels.iter().enumerate() {
            seen += c;
            if total > 0 && 2 * seen >= total {
                return bin as f64 / 10.0 - 120.0 + 0.05;
            }
        }
        f64::NAN
    }
}

/// The voice learned from the whole of `mono` at `rate_hz` with `config`'s analysis and phrase
/// settings (see [`VoiceLearner`]).
pub fn learn_voice(
    config: &EngineConfig,
    mono: &[f32],
    rate_hz: f64,
) -> Result<Option<LearnedVoice>, EngineError> {
    let mut l = VoiceLearner::new(config, rate_hz)?;
    l.feed(mono)?;
    l.finish()
}
