//! The speech decision: is what the engine hears a speaking voice, or music, singing, noise or
//! silence? Breaths go only into pauses of speech.
//!
//! ## Parts
//! - [`resample`]: any stream rate to 16 kHz ([`resample::ToSileroRate`]).
//! - [`silero`]: Silero VAD v6 (16 kHz) in plain Rust on the embedded weights of [`weights`]:
//!   a speech probability per 32 ms chunk.
//! - [`cues`]: the decision's own cues per analysis frame (voicing near, level dips).
//! - [`model`]: the stacked logistic model over Silero's logit and the cues
//!   (`assets/models/speech.txt`), which sets Silero's threshold for this use (Silero is
//!   near-certain on speech and lukewarm on singing and noise) and lets the cues veto music
//!   and singing Silero takes for speech.
//! - [`detector`]: the three together, fed the stream's mono samples and its analysis frames:
//!   a [`SpeechFrame`] per frame.
//! - [`judge`]: a tracker phrase is speech when the mean speech probability of its first half
//!   second reaches the model's threshold; a Silero segment is speech from its first half
//!   second that does.
//! - [`segments`]: Silero's segments (the package's hysteresis) judged that way: the frame
//!   decision `pneuma eval podcast` scores.
//!
//! Everything is causal, allocation-free after `new`, and depends on the sample sequence only
//! (chunk boundaries count from the stream start), so any block partition gives the same
//! decisions.

pub mod cues;
pub mod detector;
pub mod judge;
pub mod model;
pub mod resample;
pub mod segments;
pub mod silero;
pub mod weights;

pub use detector::{SpeechDetector, SpeechFrame};
pub use judge::{speech_from, RecentSpeech, SpanJudge, JUDGE_WINDOW_S};
pub use model::{SpeechFeatures, SpeechModel, SpeechModelError, SPEECH_FEATURES};
pub use segments::SegmentTrack;

use crate::analysis::{AnalysisConfig, AnalysisError, Analyzer, FeatureFrame};

/// A whole signal through the analysis and the speech decision, as the engine runs them.
#[derive(Debug, Clone, Default)]
pub struct SpeechAnalysis {
    /// Every analysis frame.
    pub frames: Vec<FeatureFrame>,
    /// The decision's view of each frame.
    pub speech: Vec<SpeechFrame>,
    /// Silero's probability of every completed chunk.
    pub chunks: Vec<f32>,
}

/// Runs `samples` (mono, `sample_rate_hz`) through an [`Analyzer`] with `config` and a
/// [`SpeechDetector`] with `model` in the engine's order: the samples that complete a frame,
/// then the frame. For training and evaluation (allocates).
pub fn analyse(
    config: &AnalysisConfig,
    model: &SpeechModel,
    samples: &[f32],
    sample_rate_hz: f64,
) -> Result<SpeechAnalysis, AnalysisError> {
    const BLOCK: usize = 4096;
    let mut analyzer = Analyzer::new(config.clone())?;
    analyzer.prepare(sample_rate_hz, BLOCK)?;
    let mut detector = SpeechDetector::new(model.clone(), sample_rate_hz, config.frame_rate_hz);
    let mut out = SpeechAnalysis::default();
    let mut completed = Vec::new();
    for block in samples.chunks(BLOCK) {
        completed.clear();
        analyzer.process_indexed(block, |f, i| completed.push((*f, i)))?;
        let mut fed = 0;
        for &(f, i) in &completed {
            detector.push(&block[fed..=i], |_, p| out.chunks.push(p));
            fed = i + 1;
            out.speech.push(detector.frame(f.voiced, f.rms_db));
            out.frames.push(f);
        }
        detector.push(&block[fed..], |_, p| out.chunks.push(p));
    }
    Ok(out)
}
