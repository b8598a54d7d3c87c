//! Learning the speaker's breath voice from a recording: what the whole-file learner
//! ([`VoiceLearner`], before a render) and the stream's learner (the engine's voice track, as
//! it goes) share is the [`BreathListener`], which hears the recording's third-octave band
//! powers on a fixed grid of frames, the room's floor, the speech level and the voiced speech's
//! long-term spectrum (which colours the built-in voice,
//! [`crate::breathing::reference::ReferenceVoice`]), and measures a breath the phrase tracker
//! reports (`Pause::breath_clean_s`: the breath without a loud blip it spans) from the frames
//! of its span.
//!
//! Memory is bounded by the listener's ring of band powers ([`RING_S`]), the floor's and the
//! level's histograms and, offline, one record per heard breath (the stream keeps the last
//! [`MAX_HEARD`]).

use super::replay::{AnalysisRecord, WholeSpeech};
use super::speaker_level::PhraseLevels;
use super::{clean_sample, Engine, EngineConfig, EngineError, SpeechSummary, Timing};
use crate::analysis::{Analyzer, FeatureFrame};
use crate::breathing::band_limit;
use crate::breathing::learned::{HeardBreath, LearnScratch, LearnedVoice};
use crate::breathing::third_octave::{BandAnalyzer, Bands, FloorEstimate, BANDS};
use crate::phrase::{PhraseEvent, PhraseTracker};

/// How far back a breath can be measured once the tracker reports it, seconds.
pub const RING_S: f64 = 30.0;
/// Breaths a stream learns from: the last this many heard.
pub const MAX_HEARD: usize = 64;
/// Block the whole-file learner feeds the analysis in.
const BLOCK: usize = 4096;
/// Speech-level histogram: 0.1 dB bins from −120 to 0 dBFS.
const LEVEL_BINS: usize = 1200;
/// Voiced frames under which the speech level is the loudest of them, not their median (the
/// first frames of a stream's first phrase are its rising onset; as the placement's rule).
const EARLY_VOICED_FRAMES: u64 = 50;

/// The recording as a breath learner hears it (see the module docs). Frame `k` of the grid
/// covers samples `k·hop .. k·hop + frame` (hop = half a frame, Hann window,
/// [`BandAnalyzer`]); the even frames, back to back, feed the floor. Allocation-free after
/// [`BreathListener::new`]; any block partition hears the same.
#[derive(Debug)]
pub struct BreathListener {
    rate_hz: f64,
    bands: BandAnalyzer,
    hop: usize,
    /// The frame being filled, in order: its first `filled` samples are heard.
    window: Vec<f32>,
    filled: usize,
    /// Samples heard.
    fed: u64,
    /// Band powers of the last grid frames (a ring indexed by frame).
    powers: Vec<Bands>,
    /// Grid frames completed.
    frames: u64,
    floor: FloorEstimate,
    voiced_levels: Vec<u64>,
    /// The last analysis frame heard was voiced: grid frames completed now count towards the
    /// speech's long-term spectrum.
    voiced_now: bool,
    /// Sum of the band powers of the grid frames completed while voiced, and their count.
    speech_sum: Bands,
    speech_frames: u64,
    /// Sum of the same frames' FFT bin powers (the whole spectrum: its upper edge,
    /// [`crate::breathing::band_limit`]).
    speech_bins: Vec<f64>,
    /// That edge, read again at each voiced grid frame, Hz.
    edge_hz: Option<f64>,
}

impl BreathListener {
    /// A listener at `rate_hz`. Allocates.
    pub fn new(rate_hz: f64) -> Self {
        let bands = BandAnalyzer::new(rate_hz);
        let frame = bands.frame();
        let hop = frame / 2;
        Self {
            rate_hz,
            hop,
            window: vec![0.0; frame],
            filled: 0,
            fed: 0,
            powers: vec![[0.0; BANDS]; (RING_S * rate_hz / hop as f64).ceil() as usize + 1],
            frames: 0,
            floor: FloorEstimate::default(),
            voiced_levels: vec![0; LEVEL_BINS],
            voiced_now: false,
            speech_sum: [0.0; BANDS],
            speech_frames: 0,
            speech_bins: vec![0.0; frame / 2 + 1],
            edge_hz: None,
            bands,
        }
    }

    /// Forgets everything heard.
    pub fn reset(&mut self) {
        self.filled = 0;
        self.fed = 0;
        self.frames = 0;
        self.floor.clear();
        self.voiced_levels.fill(0);
        self.voiced_now = false;
        self.speech_sum = [0.0; BANDS];
        self.speech_frames = 0;
        self.speech_bins.fill(0.0);
        self.edge_hz = None;
    }

    /// Hears the next mono samples (non-finite ones as 0).
    pub fn push(&mut self, mono: &[f32]) {
        let (frame, hop) = (self.window.len(), self.hop);
        let mut rest = mono;
        while !rest.is_empty() {
            let n = (frame - self.filled).min(rest.len());
            for (w, &x) in self.window[self.filled..self.filled + n]
                .iter_mut()
                .zip(&rest[..n])
            {
                *w = clean_sample(x);
            }
            self.filled += n;
            self.fed += n as u64;
            rest = &rest[n..];
            if self.filled == frame {
                self.complete_frame();
                // The next frame starts a hop later.
                self.window.copy_within(hop.., 0);
                self.filled = frame - hop;
            }
        }
    }

    /// The window holds grid frame `self.frames`: its band powers to the ring, the floor (even
    /// frames) and the speech spectrum (while voiced).
    fn complete_frame(&mut self) {
        let p = self.bands.powers(&self.window);
        if self.frames.is_multiple_of(2) {
            self.floor.add(&p);
        }
        if self.voiced_now {
            for (s, x) in self.speech_sum.iter_mut().zip(&p) {
                *s += x;
            }
            for (s, x) in self
                .speech_bins
                .iter_mut()
                .zip(self.bands.last_bin_powers())
            {
                *s += x;
            }
            self.speech_frames += 1;
            let heard_s = (self.speech_frames * self.hop as u64) as f64 / self.rate_hz;
            self.edge_hz = (heard_s >= band_limit::MIN_EDGE_SPEECH_S)
                .then(|| {
                    let bin_hz = self.rate_hz / self.window.len() as f64;
                    band_limit::upper_edge_hz(&self.speech_bins, bin_hz)
                })
                .flatten();
        }
        let n = self.powers.len() as u64;
        self.powers[(self.frames % n) as usize] = p;
        self.frames += 1;
    }

    /// Hears one analysis frame: a voiced frame's level counts towards the speech level, and
    /// the grid frames completed until the next one towards the speech's long-term spectrum.
    pub fn frame(&mut self, f: &FeatureFrame) {
        self.voiced_now = f.voiced;
        if f.voiced && f.rms_db.is_finite() {
            let bin = ((f64::from(f.rms_db) + 120.0) * 10.0).clamp(0.0, LEVEL_BINS as f64 - 1.0);
            self.voiced_levels[bin as usize] += 1;
        }
    }

    /// The breath at `(start_s, end_s)`: the mean band powers of the grid frames whose centre
    /// lies in the span (the frame nearest its middle when none does), of those completed and
    /// still held. `None` when none is.
    pub fn measure(&self, (start_s, end_s): (f64, f64)) -> Option<HeardBreath> {
        let half = (self.window.len() / 2) as f64;
        let hop = self.hop as f64;
        let (a, b) = (start_s * self.rate_hz - half, end_s * self.rate_hz - half);
        let mut lo = (a / hop).ceil().max(0.0) as u64;
        let mut hi = ((b / hop).ceil().max(0.0) as u64).max(lo);
        if hi == lo {
            lo = ((0.5 * (a + b) / hop).round().max(0.0)) as u64;
            hi = lo + 1;
        }
        let held_from = self.frames.saturating_sub(self.powers.len() as u64);
        let (lo, hi) = (lo.max(held_from), hi.min(self.frames));
        if hi <= lo {
            return None;
        }
        let n = self.powers.len() as u64;
        let mut sum = [0.0; BANDS];
        for k in lo..hi {
            for (s, p) in sum.iter_mut().zip(&self.powers[(k % n) as usize]) {
                *s += p;
            }
        }
        Some(HeardBreath {
            powers: sum.map(|s| s / (hi - lo) as f64),
            length_s: end_s - start_s,
            speaker_level_db: f64::NAN,
        })
    }

    /// The long-term third-octave spectrum of the voiced speech so far, dB per band (NaN
    /// before any).
    pub fn speech_ltas_db(&self) -> Bands {
        let n = self.speech_frames as f64;
        self.speech_sum.map(|p| {
            if n > 0.0 && p > 0.0 {
                10.0 * (p / n).log10()
            } else {
                f64::NAN
            }
        })
    }

    /// The upper edge of the voiced speech's spectrum so far, Hz
    /// ([`band_limit::upper_edge_hz`]); `None` before [`band_limit::MIN_EDGE_SPEECH_S`] of it.
    pub fn upper_edge_hz(&self) -> Option<f64> {
        self.edge_hz
    }

    /// The speech heard so far: its long-term spectrum, level and upper edge.
    pub fn speech(&self) -> WholeSpeech {
        WholeSpeech {
            ltas_db: self.speech_ltas_db(),
            speech_db: self.speech_db(),
            upper_edge_hz: self.upper_edge_hz(),
        }
    }

    /// The room's floor: band powers.
    pub fn floor(&self) -> Bands {
        self.floor.floor()
    }

    /// The median level of the voiced frames so far, dBFS (NaN before any); while there are
    /// fewer than [`EARLY_VOICED_FRAMES`], the loudest.
    pub fn speech_db(&self) -> f64 {
        // A bin's centre, dBFS.
        let db = |bin: usize| bin as f64 / 10.0 - 120.0 + 0.05;
        let total: u64 = self.voiced_levels.iter().sum();
        if total > 0 && total < EARLY_VOICED_FRAMES {
            let top = self.voiced_levels.iter().rposition(|&c| c > 0).unwrap_or(0);
            return db(top);
        }
        let mut seen = 0;
        for (bin, c) in self.voiced_levels.iter().enumerate() {
            seen += c;
            if total > 0 && 2 * seen >= total {
                return db(bin);
            }
        }
        f64::NAN
    }

    /// The voice of `heard` in this room against this speech level.
    pub fn learn(&self, heard: &[HeardBreath], scratch: &mut LearnScratch) -> Option<LearnedVoice> {
        LearnedVoice::learn_with(
            heard,
            &self.floor(),
            self.speech_db(),
            self.rate_hz,
            scratch,
        )
    }
}

/// Learns the voice of a whole recording before a render: the recording streams through the
/// engine's analysis and phrase tracker (the same settings, so the breaths heard are the ones
/// the render will hear) and a [`BreathListener`], fed as the engine feeds its own (the samples
/// that complete each frame, then the frame). At the end the analysis and the tracker hear the
/// engine's tail of silence, as the render's engine does. Made with
/// [`VoiceLearner::recording`], it keeps the analysis for the render to replay
/// ([`super::Engine::replay_analysis`]). Allocates.
#[derive(Debug)]
pub struct VoiceLearner {
    analyzer: Analyzer,
    tracker: PhraseTracker,
    listener: BreathListener,
    heard: Vec<HeardBreath>,
    /// The breath heard before the phrase being spoken, until that phrase's level is known.
    waiting: Option<HeardBreath>,
    /// The phrases' levels, as the engine's placement keeps them.
    levels: PhraseLevels,
    frames: Vec<(FeatureFrame, usize)>,
    /// Samples fed so far (input, then tail).
    fed: u64,
    /// The engine's tail of silence after the input, samples.
    tail: u64,
    /// The mono mix of an interleaved block.
    mono: Vec<f32>,
    record: Option<AnalysisRecord>,
}

/// What a [`VoiceLearner`] learned from a whole recording.
#[derive(Debug, Clone)]
pub struct Learned {
    /// The voice of the breaths heard (`None`: none was).
    pub voice: Option<LearnedVoice>,
    /// The speech of the whole recording (its median voiced level, dBFS: NaN without any).
    pub speech: WholeSpeech,
    /// The analysis, for a learner made with [`VoiceLearner::recording`].
    pub record: Option<AnalysisRecord>,
}

impl VoiceLearner {
    /// A learner with the analysis and phrase settings of `config` at `rate_hz`.
    pub fn new(config: &EngineConfig, rate_hz: f64) -> Result<Self, EngineError> {
        let mut analyzer = Analyzer::new(config.analysis.clone())?;
        analyzer.prepare(rate_hz, BLOCK)?;
        let tracker = PhraseTracker::new(config.phrase, config.analysis.frame_rate_hz)?;
        let tail = Timing::of(config, rate_hz, analyzer.latency_s().unwrap_or(0.05)).tail;
        Ok(Self {
            analyzer,
            tracker,
            listener: BreathListener::new(rate_hz),
            heard: Vec::new(),
            waiting: None,
            levels: PhraseLevels::default(),
            frames: Vec::new(),
            fed: 0,
            tail: tail as u64,
            mono: Vec::new(),
            record: None,
        })
    }

    /// A learner that also keeps its analysis ([`Learned::record`]) for an engine prepared
    /// with `config` at `rate_hz` to replay.
    pub fn recording(config: &EngineConfig, rate_hz: f64) -> Result<Self, EngineError> {
        Ok(Self {
            record: Some(AnalysisRecord::new(rate_hz, config.analysis.frame_rate_hz)),
            ..Self::new(config, rate_hz)?
        })
    }

    /// The recording holds `samples` samples (a file's announced length): a recording learner
    /// makes room for its analysis at once (with the tail) instead of growing it by doubling,
    /// which at its last step held twice the frames. A hint only: any length is taken.
    pub fn expect_samples(&mut self, samples: u64) {
        let tail = self.tail;
        if let Some(r) = &mut self.record {
            r.reserve_for(samples + tail);
        }
    }

    /// Feeds the next mono samples of the recording.
    pub fn feed(&mut self, mono: &[f32]) -> Result<(), EngineError> {
        for block in mono.chunks(BLOCK) {
            self.feed_block(block, false)?;
        }
        Ok(())
    }

    /// Feeds the next `channels`-interleaved samples of the recording, mixed to mono as the
    /// engine mixes them ([`mix_to_mono`]).
    pub fn feed_interleaved(
        &mut self,
        interleaved: &[f32],
        channels: usize,
    ) -> Result<(), EngineError> {
        let mut mono = std::mem::take(&mut self.mono);
        mix_to_mono(interleaved, channels, &mut mono);
        let fed = self.feed(&mono);
        self.mono = mono;
        fed
    }

    /// One block of at most [`BLOCK`] samples: the input (heard by the listener too) or the
    /// tail of silence after it (`tail`: the analysis and the tracker only, so the silence
    /// does not pull the room's floor down).
    fn feed_block(&mut self, block: &[f32], tail: bool) -> Result<(), EngineError> {
        self.frames.clear();
        let frames = &mut self.frames;
        self.analyzer
            .process_indexed(block, |f, i| frames.push((*f, i)))
            .map_err(EngineError::from)?;
        let mut fed = 0;
        for k in 0..self.frames.len() {
            let (f, i) = self.frames[k];
            if !tail {
                self.listener.push(&block[fed..=i]);
            }
            fed = i + 1;
            if let Some(r) = &mut self.record {
                r.push(f, self.fed + i as u64);
            }
            self.on_frame(&f);
        }
        if !tail {
            self.listener.push(&block[fed..]);
        }
        if let Some(r) = &mut self.record {
            r.heard(block);
        }
        self.fed += block.len() as u64;
        Ok(())
    }

    /// One frame, heard as the engine hears it: its level joins the phrase's (placement),
    /// then the tracker's events; a breath heard before a phrase is learned from, against its
    /// speaker's level, once that phrase has ended (the stream's voice track does the same).
    fn on_frame(&mut self, f: &FeatureFrame) {
        self.listener.frame(f);
        self.levels.frame(f);
        let mut events: [Option<PhraseEvent>; 3] = [None; 3];
        let mut k = 0;
        self.tracker.update(f, |e| {
            if k < events.len() {
                events[k] = Some(e);
                k += 1;
            }
        });
        for e in events.into_iter().flatten() {
            match e {
                PhraseEvent::Start { pause, .. } => {
                    self.levels.start();
                    self.waiting = pause
                        .breath_clean_s
                        .and_then(|span| self.listener.measure(span));
                }
                PhraseEvent::End { .. } => {
                    let ended = self.levels.end();
                    if let Some(mut b) = self.waiting.take() {
                        b.speaker_level_db = f64::from(self.levels.speaker_of(ended));
                        self.heard.push(b);
                    }
                }
                PhraseEvent::Activity { .. } => {}
            }
        }
    }

    /// Breaths heard so far (the one before the phrase being spoken included).
    pub fn heard(&self) -> usize {
        self.heard.len() + usize::from(self.waiting.is_some())
    }

    /// Ends the recording (the engine's tail of silence through the analysis and the tracker)
    /// and learns the voice.
    pub fn finish(mut self) -> Result<Learned, EngineError> {
        let zeros = vec![0.0; BLOCK];
        let mut left = self.tail;
        while left > 0 {
            let n = left.min(BLOCK as u64) as usize;
            self.feed_block(&zeros[..n], true)?;
            left -= n as u64;
        }
        // A phrase the stream ended inside (the tail ends every phrase): its breath is
        // measured against the recording's speech level.
        self.heard.extend(self.waiting.take());
        let mut scratch = LearnScratch::with_capacity(self.heard.len());
        let speech = self.listener.speech();
        if let Some(r) = &mut self.record {
            r.set_speech(speech);
        }
        Ok(Learned {
            voice: self.listener.learn(&self.heard, &mut scratch),
            speech,
            record: self.record,
        })
    }

    /// The median level of the voiced frames so far, dBFS (NaN before any).
    pub fn speech_db(&self) -> f64 {
        self.listener.speech_db()
    }

    /// The long-term third-octave spectrum of the voiced speech so far, dB per band.
    pub fn speech_ltas_db(&self) -> Bands {
        self.listener.speech_ltas_db()
    }
}

/// Mixes `channels`-interleaved samples to mono into `out` (replaced) exactly as the engine
/// mixes its input for analysis: non-finite samples as 0, the channels summed in order, then
/// scaled by `1 / channels`. A learning pass whose analysis a render replays must hear the
/// same samples bit for bit.
pub fn mix_to_mono(interleaved: &[f32], channels: usize, out: &mut Vec<f32>) {
    let channels = channels.max(1);
    let inv = 1.0 / channels as f32;
    out.clear();
    out.extend(interleaved.chunks_exact(channels).map(|frame| {
        let mut m = clean_sample(frame[0]);
        for &x in &frame[1..] {
            m += clean_sample(x);
        }
        if channels > 1 {
            m *= inv;
        }
        m
    }));
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
    Ok(l.finish()?.voice)
}

/// What the speech decision of an engine with `config` hears in the whole of `mono` at
/// `rate_hz` (a breath-like recording checked before its voice is learned: a file of music
/// teaches no speaker's breath). Allocates; runs the whole engine, head and breaths included.
pub fn speech_of(
    config: &EngineConfig,
    mono: &[f32],
    rate_hz: f64,
) -> Result<SpeechSummary, EngineError> {
    let mut engine = Engine::new(
        config.clone(),
        crate::head::HeadModel::default_model().clone(),
    )?;
    engine.prepare(rate_hz, BLOCK, 1)?;
    let mut block = Vec::with_capacity(BLOCK);
    for chunk in mono.chunks(BLOCK) {
        block.clear();
        block.extend_from_slice(chunk);
        engine.process(&mut [block.as_mut_slice()], &mut |_, _| {});
    }
    Ok(speech_after_silence(&mut engine, 1))
}

/// Silence after the end of a file, seconds, beyond the engine's tail: a take that ends on a
/// word ends its last phrase, so that phrase is judged (a trimmed one-sentence take had no
/// phrase judged speech).
const END_SILENCE_S: f64 = 1.0;

/// `engine`'s speech summary once [`END_SILENCE_S`] of silence and its tail have followed what
/// it was fed (`channels` as prepared). Allocates.
pub fn speech_after_silence(engine: &mut Engine, channels: usize) -> SpeechSummary {
    let rate_hz = engine.sample_rate_hz().unwrap_or(0.0);
    let total = engine.tail_samples() as usize + (END_SILENCE_S * rate_hz).ceil() as usize;
    let mut silence = vec![vec![0.0f32; BLOCK]; channels.max(1)];
    let mut left = total;
    while left > 0 {
        let n = left.min(BLOCK);
        let mut blocks: Vec<&mut [f32]> = silence.iter_mut().map(|c| &mut c[..n]).collect();
        engine.process(&mut blocks, &mut |_, _| {});
        left -= n;
    }
    engine.speech_summary()
}
