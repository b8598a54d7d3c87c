//! The one streaming [`Engine`] that the CLI and the plugin both drive: audio blocks of any size
//! in, the same audio with breaths inserted out, plus one [`ControlFrame`] per frame of the frame
//! clock.
//!
//! ## Inside one call to [`Engine::process`]
//! 1. The input is cleaned (non-finite samples become 0), mixed to mono for analysis, and written
//!    into a per-channel delay line of `latency_samples()` (lookahead mode) or none (live mode).
//! 2. The analyzer turns the mono signal into feature frames sample by sample; each frame goes to
//!    the speech decision and the phrase tracker at once, and waits in a queue until the output
//!    reaches its time, flagged by the body gate when it lies in sound that is not speech.
//! 3. Phrase events schedule breaths and breathing-cycle events on the input timeline:
//!    - lookahead: at a confirmed onset that ends a pause of at least `min_pause_s` with no breath
//!      in it, an inhalation is placed to end `gap_s` before the onset, no earlier than
//!      `after_offset_s` after the previous phrase and no earlier than the output position, and
//!      as long as the breathing model's inspiration length allows;
//!    - live (no delay, so the next onset is unknown): once a confirmed phrase end (after the
//!      tracker's hangover) lies `min_pause_s` (at least `after_offset_s`) in the past, an
//!      inhalation starts, with the breathing cycle's inspiration, unless the input is active at
//!      that sample; activity before then cancels it. A sample-level input gate (`gate`) fades
//!      a playing breath out over `live_fade_s` from the first active sample, and the cycle
//!      stops inspiring before the first frame that heard it. A real breath the tracker hears
//!      in the pause makes the pause's inhalation silent (the cycle still inspires) and fades
//!      one playing. A breath cut within its first 60 ms or never above −60 dBFS is an
//!      inaudible stub and is not reported.
//! 4. The output is the delayed input, bit for bit, plus the breath sound where a breath plays,
//!    spread over the channels in the voice's stereo image.
//! 5. Control frames are emitted when the output reaches their time, with their sample offset in
//!    the block: the breathing cycle advances by one frame, driven by the scheduled events, and
//!    the head pose is computed (at rest on a frame the body gate flagged).
//!
//! ## Parts (each with `new`, `reset` and its step; `prepare` builds them all)
//! - [`DelayLine`](delay): the per-channel delay (the lookahead).
//! - [`StereoImage`](stereo): per-channel energies and the voice's channel shares.
//! - [`InputGate`](gate): live mode's sample-level activity detector.
//! - [`Placement`](placement): phrase events → scheduled breath and cycle actions (the two
//!   policies), with the speech level and utterance estimate they use.
//! - [`BreathTrack`](breath_track): carries out breath actions, renders and records breaths.
//! - [`CycleTrack`](cycle_track): steps the breathing cycle at each emitted control frame.
//! - [`BodyGate`](body_gate): flags the frames of music, singing and noise for the body.
//! - [`output`]: runs the breath track and emits the control frames up to each frame's
//!   completing sample, in every mode.
//! - [`replay`]: a whole-file learning pass's analysis, handed out instead of the analyzer's
//!   ([`Engine::replay_analysis`]), so a render that learns first analyses its file once.
//!
//! Every decision depends on the sample sequence only (and, replayed, on the analysis recorded
//! from that sequence), so any block partition gives identical output and control frames.
//! `process` never allocates.

mod body_gate;
mod breath_track;
mod config;
mod cycle_track;
mod delay;
mod dropped;
mod gate;
pub mod offline;
mod output;
mod placement;
pub mod replay;
mod schedule;
mod speaker_level;
mod speech_track;
mod stereo;
mod stream_start;
mod timing;
pub mod voice_learning;
mod voice_track;

pub use config::{EngineConfig, EngineError, PlacementConfig, PlacementMode, OFFLINE_LOOKAHEAD_S};
pub use dropped::Dropped;
pub use placement::BREATH_LENGTH_SCALE;
pub use speech_track::{SpeechSummary, MOSTLY_OTHER_SHARE, NO_SPEECH_SHARE};
pub use voice_track::{BreathVoiceMode, VoiceStatus};

use crate::analysis::{Analyzer, FeatureFrame};
use crate::breathing::band_limit;
use crate::breathing::learned::LearnedVoice;
use crate::breathing::reference::ReferenceVoice;
use crate::breathing::{BreathSample, BreathVoice, SampleSlot};
use crate::control::{BreathEvent, ControlFrame};
use crate::encode::sink::FrameSink;
use crate::head::{HeadModel, HeadSynth};
use crate::phrase::{PhraseEvent, PhraseTracker};
use crate::speech::SpeechModel;
use body_gate::BodyGate;
use breath_track::{Block, BreathTrack};
use cycle_track::CycleTrack;
use delay::DelayLine;
use dropped::Lost;
use gate::InputGate;
use placement::{EventContext, Placement};
use replay::{AnalysisRecord, Replay};
use schedule::{Pending, Queue, Schedule};
use speech_track::SpeechTrack;
use stereo::StereoImage;
use timing::Timing;
use voice_track::{VoiceChoice, VoiceTrack};

/// A sample as the engine hears it: a non-finite one (NaN, ±∞) as 0.
pub(crate) fn clean_sample(x: f32) -> f32 {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

/// Most channels a stream may have.
pub const MAX_CHANNELS: usize = 8;

/// Breaths already in the input kept for [`Engine::take_existing_breaths`].
const EXISTING_BREATHS_KEPT: usize = 16;

/// What [`Engine::set_config`] did with a new configuration.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ConfigChange {
    /// Settings that apply while playing changed and are in effect now.
    pub live: bool,
    /// Settings that size the stream changed (see [`EngineConfig::stream_differs`]); they wait
    /// for the next [`Engine::prepare`], and [`Engine::config`] keeps reporting the ones in
    /// effect until then.
    pub needs_prepare: bool,
}

/// Everything sized by `prepare`: the parts, the buffers of one block and the stream clock.
#[derive(Debug)]
struct Stream {
    sample_rate_hz: f64,
    channels: usize,
    max_block: usize,
    live: bool,
    /// Frame rate fixed at `prepare` (a new one takes effect at the next `prepare`).
    frame_rate_hz: f64,
    /// Samples from an input sample to the last frame that depends on it being emitted.
    tail: usize,
    analyzer: Analyzer,
    /// The analysis of a learning pass, handed out instead of the analyzer's
    /// ([`Engine::replay_analysis`]).
    replay: Option<Replay>,
    tracker: PhraseTracker,
    head: HeadSynth,
    delay: DelayLine,
    stereo: StereoImage,
    gate: InputGate,
    placement: Placement,
    speech: SpeechTrack,
    breaths: BreathTrack,
    cycle: CycleTrack,
    /// Learns the breath voice and the channel's colour as the stream goes (always fed, so a
    /// switch of mode mid-stream finds it in step with the stream).
    voice: VoiceTrack,
    pending: Queue<Pending>,
    /// Breaths already in the input (start, end in input seconds), heard in pauses and not yet
    /// collected by [`Engine::take_existing_breaths`].
    existing: Queue<(f64, f64)>,
    schedule: Schedule,
    /// Mono mix of the current block.
    mono: Vec<f32>,
    /// Live mode: whether the input is active at every sample of the current block.
    input_active: Vec<bool>,
    /// Frames completed in the current block with the index of the completing sample.
    completed: Vec<(FeatureFrame, usize)>,
    state: StreamState,
    lost: Lost,
}

/// What [`Engine::reset`] clears at the stream level (the parts clear their own).
#[derive(Debug, Clone, Copy, Default)]
struct StreamState {
    /// Samples taken in (input timeline) = samples given out (output timeline).
    position: u64,
    body: BodyGate,
}

/// The streaming engine. See the module docs.
#[derive(Debug)]
pub struct Engine {
    /// The settings in effect.
    config: EngineConfig,
    /// Settings waiting for the next `prepare` (a change of the stream part).
    pending: Option<EngineConfig>,
    model: HeadModel,
    samples: [Option<BreathSample>; 2],
    /// Where inserted breaths take their voice from, and the built-in voice.
    breath_voice: VoiceChoice,
    /// The speech decision's model (`None`: the shipped one).
    speech_model: Option<SpeechModel>,
    stream: Option<Stream>,
}

impl Engine {
    /// An engine with validated settings and a head model; call [`Engine::prepare`] before
    /// processing.
    pub fn new(config: EngineConfig, head_model: HeadModel) -> Result<Self, EngineError> {
        config.validate()?;
        // Fail early on a model the synthesis rejects.
        HeadSynth::new(head_model.clone(), config.head.clone())?;
        Ok(Self {
            config,
            pending: None,
            model: head_model,
            samples: [None, None],
            breath_voice: VoiceChoice {
                mode: BreathVoiceMode::default(),
                reference: Some(*ReferenceVoice::shipped()),
            },
            speech_model: None,
            stream: None,
        })
    }

    /// The settings in effect (a stream change given to [`Engine::set_config`] shows here only
    /// after the next [`Engine::prepare`]; see [`Engine::pending_config`]).
    pub fn config(&self) -> &EngineConfig {
        &self.config
    }

    /// Settings given to [`Engine::set_config`] that wait for the next [`Engine::prepare`].
    pub fn pending_config(&self) -> Option<&EngineConfig> {
        self.pending.as_ref()
    }

    /// What was dropped since the last [`Engine::prepare`] (all zero before it).
    pub fn dropped(&self) -> Dropped {
        self.stream
            .as_ref()
            .map_or_else(Dropped::default, |s| Dropped {
                frames: s.lost.frames,
                phrase_events: s.lost.phrase_events,
                scheduled: s.pending.dropped() + s.schedule.dropped(),
                breaths: s.breaths.dropped(),
                existing_breaths: s.existing.dropped(),
                analysis_blocks: s.lost.analysis_blocks,
                unanalysed_samples: s.lost.unanalysed_samples,
            })
    }

    /// Sets a user breath sample (`None`: the procedural sound). Allocates: not for the audio
    /// thread. Takes effect at once when prepared.
    pub fn set_breath_sample(&mut self, slot: SampleSlot, sample: Option<BreathSample>) {
        let i = match slot {
            SampleSlot::Mouth => 0,
            SampleSlot::Nose => 1,
        };
        self.samples[i] = sample.clone();
        if let Some(s) = &mut self.stream {
            s.breaths.voice_mut().set_sample(slot, sample);
        }
    }

    /// Draws inserted breaths from `voice`, learned from the speaker's recording
    /// ([`voice_learning`]): [`BreathVoiceMode::Fixed`]; `None`: [`BreathVoiceMode::BuiltIn`].
    pub fn set_learned_voice(&mut self, voice: Option<LearnedVoice>) {
        self.set_voice_mode(voice.map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Fixed));
    }

    /// Where inserted breaths take their voice from, from the next breath on. Switching to
    /// [`BreathVoiceMode::Learn`] starts learning afresh. Allocation-free once prepared (the
    /// plugin switches on the audio thread).
    pub fn set_voice_mode(&mut self, mode: BreathVoiceMode) {
        let was_learning = self.breath_voice.learning();
        self.breath_voice.mode = mode;
        if let Some(s) = &mut self.stream {
            // Into learning: the breaths learned before are forgotten, the room and the speech
            // heard so far are kept.
            if self.breath_voice.learning() && !was_learning {
                s.voice.forget_breaths();
            }
            s.refresh_voice(&self.breath_voice);
        }
    }

    /// The built-in voice: `Some` (the shipped [`ReferenceVoice`] by default, coloured by the
    /// channel) or `None` (the procedural sound of earlier versions). For evaluations that
    /// judge a voice fitted without the speakers they score; a plugin or a user never needs
    /// it. Allocation-free.
    pub fn set_reference_voice(&mut self, reference: Option<ReferenceVoice>) {
        self.breath_voice.reference = reference;
        if let Some(s) = &mut self.stream {
            s.refresh_voice(&self.breath_voice);
        }
    }

    /// Where inserted breaths take their voice from.
    pub fn voice_mode(&self) -> &BreathVoiceMode {
        &self.breath_voice.mode
    }

    /// Freezes the voice learned so far: it becomes [`BreathVoiceMode::Fixed`], kept through
    /// resets, and is returned (to be saved); with nothing learned yet the built-in voice is
    /// kept fixed (`None`). Another take's voice ([`BreathVoiceMode::Like`]) is fixed at its
    /// level against the speech heard so far. A fixed or built-in voice stays as it is.
    /// Allocation-free.
    pub fn freeze_voice(&mut self) -> Option<LearnedVoice> {
        match self.breath_voice.mode {
            BreathVoiceMode::Learn => {
                let learned = self.stream.as_ref().and_then(|s| s.voice.voice().copied());
                self.set_voice_mode(
                    learned.map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Fixed),
                );
                learned
            }
            BreathVoiceMode::Fixed(v) => Some(v),
            BreathVoiceMode::Like(v) => {
                // Its level as it stands against this stream's speech.
                let anchored = self
                    .stream
                    .as_ref()
                    .and_then(|s| s.voice.current(&self.breath_voice))
                    .unwrap_or(v);
                self.set_voice_mode(BreathVoiceMode::Fixed(anchored));
                Some(anchored)
            }
            BreathVoiceMode::BuiltIn => None,
        }
    }

    /// What the breath voice is doing (learning and how many breaths it heard, fixed, built in).
    pub fn voice_status(&self) -> VoiceStatus {
        match &self.breath_voice.mode {
            BreathVoiceMode::BuiltIn => VoiceStatus::BuiltIn,
            BreathVoiceMode::Fixed(v) | BreathVoiceMode::Like(v) => {
                VoiceStatus::Fixed { breaths: v.breaths }
            }
            BreathVoiceMode::Learn => VoiceStatus::Learning {
                breaths: self.stream.as_ref().map_or(0, |s| s.voice.heard()),
            },
        }
    }

    /// Judges speech with `model` instead of the shipped one (`None`: the shipped one) from the
    /// next [`Engine::prepare`] on. For evaluations that render with a model fitted without the
    /// material they judge; a plugin or a user never needs it.
    pub fn set_speech_model(&mut self, model: Option<SpeechModel>) {
        self.speech_model = model;
    }

    /// The learned breath voice in use, if any (fixed, or learned so far).
    pub fn learned_voice(&self) -> Option<&LearnedVoice> {
        match &self.breath_voice.mode {
            BreathVoiceMode::Fixed(v) | BreathVoiceMode::Like(v) => Some(v),
            BreathVoiceMode::Learn => self.stream.as_ref().and_then(|s| s.voice.voice()),
            BreathVoiceMode::BuiltIn => None,
        }
    }

    /// Allocates everything for a stream at `sample_rate_hz` (8–768 kHz) with blocks of at most
    /// `max_block` samples and `channels` channels (1–8), takes in settings waiting for it, and
    /// resets.
    pub fn prepare(
        &mut self,
        sample_rate_hz: f64,
        max_block: usize,
        channels: usize,
    ) -> Result<(), EngineError> {
        if channels == 0 || channels > MAX_CHANNELS {
            return Err(EngineError::Channels(channels));
        }
        if max_block == 0 || max_block > 65_536 {
            return Err(EngineError::MaxBlock(max_block));
        }
        if let Some(pending) = self.pending.take() {
            self.config = pending;
        }
        let c = &self.config;
        let mut analyzer = Analyzer::new(c.analysis.clone())?;
        analyzer.prepare(sample_rate_hz, max_block)?;
        let frame_rate_hz = c.analysis.frame_rate_hz;
        let tracker = PhraseTracker::new(c.phrase, frame_rate_hz)?;
        let head = HeadSynth::new(self.model.clone(), c.head.clone())?;
        let mut voice = BreathVoice::new(c.seed);
        voice.prepare(sample_rate_hz, max_block);
        for (slot, sample) in [SampleSlot::Mouth, SampleSlot::Nose]
            .into_iter()
            .zip(self.samples.iter())
        {
            voice.set_sample(slot, sample.clone());
        }
        voice.set_learned(match self.breath_voice.mode {
            BreathVoiceMode::Fixed(v) => Some(v),
            _ => None,
        });
        let mode = c.placement.mode;
        let live = mode == PlacementMode::Live;
        let analysis_latency_s = analyzer.latency_s().unwrap_or(0.05);
        let Timing { latency, tail } = Timing::of(c, sample_rate_hz, analysis_latency_s);
        let frames_per_block =
            (max_block as f64 * frame_rate_hz / sample_rate_hz).ceil() as usize + 4;
        let max_pending = ((latency as f64 / sample_rate_hz + analysis_latency_s + 0.1)
            * frame_rate_hz
            + max_block as f64 / sample_rate_hz * frame_rate_hz)
            .ceil() as usize
            + 8;
        // The tracker reports at most one end and one start per frame; actions wait at most the
        // latency plus a block.
        let max_actions = 2 * max_pending + 16;
        self.stream = Some(Stream {
            sample_rate_hz,
            channels,
            max_block,
            live,
            frame_rate_hz,
            tail,
            analyzer,
            replay: None,
            tracker,
            head,
            delay: DelayLine::new(channels, latency, max_block),
            stereo: StereoImage::new(sample_rate_hz, channels, max_block),
            gate: InputGate::new(sample_rate_hz, c.phrase.silence_db),
            placement: Placement::new(mode, latency, sample_rate_hz, frame_rate_hz),
            speech: SpeechTrack::new(
                c.placement.speech_only.then(|| {
                    self.speech_model
                        .clone()
                        .unwrap_or_else(|| SpeechModel::shipped().clone())
                }),
                sample_rate_hz,
                frame_rate_hz,
                (c.phrase.silence_db, c.phrase.activity_margin_db),
            ),
            breaths: BreathTrack::new(voice, sample_rate_hz, latency, live, max_block),
            cycle: CycleTrack::new(&c.breathing.map(), sample_rate_hz, frame_rate_hz, live),
            voice: VoiceTrack::new(sample_rate_hz),
            pending: Queue::with_capacity(max_pending),
            existing: Queue::with_capacity(EXISTING_BREATHS_KEPT),
            schedule: Schedule::new(max_actions),
            mono: vec![0.0; max_block],
            input_active: vec![false; max_block],
            completed: vec![(FeatureFrame::default(), 0); frames_per_block],
            state: StreamState::default(),
            lost: Lost::default(),
        });
        self.reset();
        Ok(())
    }

    /// Clears all state (a transport jump, a re-activation): silence in the delay line, the
    /// analysis, the phrase tracker, the cycle and the head back to their start.
    pub fn reset(&mut self) {
        if let Some(s) = &mut self.stream {
            s.analyzer.reset();
            if let Some(r) = &mut s.replay {
                r.reset();
            }
            s.tracker.reset();
            s.head.reset();
            s.delay.reset();
            s.stereo.reset();
            s.gate.reset();
            s.placement.reset();
            s.speech.reset();
            s.breaths.reset();
            s.cycle.reset();
            // Learning (and the channel's colour) restarts with the stream; a fixed voice stays.
            s.voice.reset();
            s.refresh_voice(&self.breath_voice);
            s.pending.clear();
            s.existing.clear();
            s.schedule.reset();
            s.input_active.fill(false);
            s.state = StreamState::default();
        }
    }

    /// The delay the engine adds, in samples: the lookahead in lookahead mode, 0 in live mode
    /// (0 before `prepare`).
    pub fn latency_samples(&self) -> u32 {
        self.stream.as_ref().map_or(0, |s| s.delay.latency() as u32)
    }

    /// Silence to feed after the end of a stream so every frame of it is emitted and every
    /// breath scheduled in it has played: the latency plus the analysis delay and one frame,
    /// in samples (0 before `prepare`). Offline renders feed this much and drop what lies past
    /// the end.
    pub fn tail_samples(&self) -> u64 {
        self.stream.as_ref().map_or(0, |s| s.tail as u64)
    }

    /// Replays `record` (a whole-file learning pass's analysis of this stream, see
    /// [`replay`]) instead of analysing the stream again, from the stream's start (and again
    /// after each [`Engine::reset`]), until the next [`Engine::prepare`]. The output is the
    /// same as without it when the record was made from the same input with this engine's
    /// settings and rate; samples past its end are not analysed
    /// ([`Dropped::unanalysed_samples`]), and [`Engine::replay_verified`] says whether the
    /// stream heard exactly the recorded samples. The built-in voice is coloured by the whole
    /// input's speech the record carries, and breaths stay under its band edge, from the first
    /// breath on, and unless the mode is
    /// [`BreathVoiceMode::Learn`] the voice track does not listen (an offline render keeps
    /// its voice from start to end: a switch into learning later would hear the stream only
    /// from the switch on). A [`Engine::reset`] rewinds the replay to the stream's start: only
    /// for a stream that starts the same input again. Does nothing before `prepare`; a record
    /// of another sample or frame rate is refused.
    pub fn replay_analysis(&mut self, record: AnalysisRecord) -> Result<(), EngineError> {
        let Some(s) = &mut self.stream else {
            return Ok(());
        };
        let (record_hz, record_fps) = record.rates();
        if record_hz != s.sample_rate_hz || record_fps != s.frame_rate_hz {
            return Err(EngineError::ReplayMismatch {
                record_hz,
                record_fps,
                stream_hz: s.sample_rate_hz,
                stream_fps: s.frame_rate_hz,
            });
        }
        s.voice.set_whole(record.speech());
        s.replay = Some(Replay::new(record));
        s.refresh_voice(&self.breath_voice);
        Ok(())
    }

    /// With a replayed analysis: whether the stream, from its start, heard exactly the samples
    /// the record was made from (the input and its tail: a render checks it at the end, and a
    /// file changed between the learning pass and the render fails it). `None` without one.
    pub fn replay_verified(&self) -> Option<bool> {
        let s = self.stream.as_ref()?;
        s.replay.as_ref().map(Replay::verified)
    }

    /// What the speech decision heard since the last [`Engine::prepare`] or
    /// [`Engine::reset`] (all zero before `prepare`): frames with sound, frames and phrases
    /// judged speech. With `speech_only` off every frame and phrase counts as speech.
    pub fn speech_summary(&self) -> SpeechSummary {
        self.stream
            .as_ref()
            .map_or_else(SpeechSummary::default, |s| s.speech.summary())
    }

    /// The corner of the low-pass every inserted breath passes through to stay inside the
    /// recording's bandwidth (a call converted up, a telephone line), Hz, as it stands now;
    /// `None` without a limit, before it is read, or before `prepare` ([`band_limit`]).
    pub fn breath_band_limit_hz(&self) -> Option<f64> {
        let s = self.stream.as_ref()?;
        band_limit::corner_hz(s.voice.upper_edge_hz(), s.sample_rate_hz)
    }

    /// The prepared sample rate.
    pub fn sample_rate_hz(&self) -> Option<f64> {
        self.stream.as_ref().map(|s| s.sample_rate_hz)
    }

    /// New settings. Before the first [`Engine::prepare`] all of them apply at once. After it,
    /// the live part (breath level, insertion on/off, minimum pause, gap, live fade, breathing
    /// parameters, head settings) applies at once, and a change of the stream part (mode,
    /// lookahead, analysis, phrase tracker, seed) waits for the next `prepare`. Says which
    /// happened. Never allocates.
    pub fn set_config(&mut self, config: &EngineConfig) -> Result<ConfigChange, EngineError> {
        config.validate()?;
        let Some(s) = &mut self.stream else {
            let change = ConfigChange {
                live: config.live_differs(&self.config),
                needs_prepare: false,
            };
            self.config = config.clone();
            self.pending = None;
            return Ok(change);
        };
        let change = ConfigChange {
            live: config.live_differs(&self.config),
            needs_prepare: config.stream_differs(&self.config),
        };
        if change.live {
            s.cycle.set_params(&config.breathing.map());
            if config.head != self.config.head {
                s.head.set_config(config.head.clone());
            }
            self.config.set_live_part(config);
        }
        self.pending = change.needs_prepare.then(|| config.clone());
        Ok(change)
    }

    /// Hands every finished inserted breath to `on_breath` (oldest first) and forgets them. Up
    /// to 64 are kept between calls (older ones are dropped and counted in
    /// [`Engine::dropped`]).
    pub fn take_breaths(&mut self, on_breath: impl FnMut(&BreathEvent)) {
        if let Some(s) = &mut self.stream {
            s.breaths.take(on_breath);
        }
    }

    /// Hands every breath heard in the input's pauses since the last call (start and end,
    /// seconds of input time: the time of the control frames) to `on_breath`, oldest first, and
    /// forgets them. These are the breaths no sound was inserted over. Up to
    /// `EXISTING_BREATHS_KEPT` (16) are kept between calls; older ones are dropped. Never
    /// allocates.
    pub fn take_existing_breaths(&mut self, mut on_breath: impl FnMut(f64, f64)) {
        if let Some(s) = &mut self.stream {
            while let Some((start_s, end_s)) = s.existing.pop_front() {
                on_breath(start_s, end_s);
            }
        }
    }

    /// Ends a stream: closes a breath still playing so that [`Engine::take_breaths`] reports it.
    pub fn finish(&mut self) {
        if let Some(s) = &mut self.stream {
            s.breaths.close_breath();
        }
    }

    /// [`Engine::process`] one block into a [`FrameSink`]: every control frame due in it, at
    /// `origin` + its sample offset in the block, then every inserted breath that finished and
    /// every breath heard in the input ([`Engine::take_breaths`],
    /// [`Engine::take_existing_breaths`]). Never allocates itself (the sink decides).
    pub fn process_into(
        &mut self,
        audio: &mut [&mut [f32]],
        origin: u64,
        sink: &mut impl FrameSink,
    ) {
        self.process(audio, &mut |frame, offset| {
            sink.frame(frame, origin + offset as u64)
        });
        self.take_breaths(|b| sink.breath(b));
        self.take_existing_breaths(|start_s, end_s| sink.existing_breath(start_s, end_s));
    }

    /// Processes one block in place: `audio` holds one slice per channel (as many as prepared or
    /// fewer), all of the same length (at most the prepared maximum; longer blocks are processed
    /// in pieces). Calls `on_control` for every control frame due in this block with its sample
    /// offset. Never allocates. Does nothing before `prepare`.
    pub fn process(
        &mut self,
        audio: &mut [&mut [f32]],
        on_control: &mut dyn FnMut(&ControlFrame, usize),
    ) {
        let Some(s) = &mut self.stream else {
            return;
        };
        let len = audio.iter().map(|c| c.len()).min().unwrap_or(0);
        let channels = audio.len().min(s.channels);
        if channels == 0 {
            return;
        }
        let mut done = 0;
        while done < len {
            let n = (len - done).min(s.max_block);
            let block = Block {
                base: s.state.position,
                start: done,
                n,
                channels,
            };
            s.process_block(&self.config, &self.breath_voice, audio, block, on_control);
            done += n;
        }
    }
}

impl Stream {
    /// Sets the breath voice `choice` gives now: fixed, or the track's current one.
    fn refresh_voice(&mut self, choice: &VoiceChoice) {
        let v = self.voice.current(choice);
        self.breaths.voice_mut().use_learned(v.as_ref());
    }

    /// One block of at most `max_block` samples (see the module docs for the steps).
    fn process_block(
        &mut self,
        config: &EngineConfig,
        breath_voice: &VoiceChoice,
        audio: &mut [&mut [f32]],
        block: Block,
        on_control: &mut dyn FnMut(&ControlFrame, usize),
    ) {
        let Block {
            base,
            start,
            n,
            channels,
        } = block;
        // 1. Clean input into the delay line and the stereo image; mono mix; live input gate.
        let clean = |x: &f32| clean_sample(*x);
        for (c, chan) in audio.iter().take(channels).enumerate() {
            let input = &chan[start..start + n];
            self.delay.write(c, base, input.iter().map(clean));
            self.stereo.track(c, input.iter().map(clean));
            for (m, x) in self.mono[..n].iter_mut().zip(input.iter().map(clean)) {
                if c == 0 {
                    *m = x;
                } else {
                    *m += x;
                }
            }
        }
        if channels > 1 {
            let inv = 1.0 / channels as f32;
            self.mono[..n].iter_mut().for_each(|m| *m *= inv);
        }
        if self.live {
            self.gate
                .process(&self.mono[..n], &mut self.input_active[..n]);
        }
        // 2. Analysis; each frame goes to the speech decision, the phrase tracker, the placement
        // and the body gate as of the sample that completed it, so any partition gives the same
        // decisions.
        let mut count = 0;
        let mut beyond = 0u64;
        let completed = &mut self.completed;
        let mut keep = |f: &FeatureFrame, i: usize| {
            if count < completed.len() {
                completed[count] = (*f, i);
                count += 1;
            } else {
                beyond += 1;
            }
        };
        let analysed = match &mut self.replay {
            Some(r) => {
                r.hear(&self.mono[..n]);
                self.lost.unanalysed_samples += r.block(base, n, &mut keep);
                Ok(())
            }
            None => self.analyzer.process_indexed(&self.mono[..n], &mut keep),
        };
        // The analyzer is prepared for this block size and `completed` holds every frame a
        // block can complete: neither loss can happen unless a bound is wrong.
        debug_assert!(analysed.is_ok(), "analysis refused a block: {analysed:?}");
        debug_assert_eq!(beyond, 0, "frames beyond the block's frame buffer");
        self.lost.analysis_blocks += u64::from(analysed.is_err());
        self.lost.frames += beyond;
        // 3. Output: the delayed input (breaths are added to it below).
        for (c, chan) in audio.iter_mut().take(channels).enumerate() {
            self.delay.read(c, base, &mut chan[start..start + n]);
        }
        // 4–5. Breaths and control frames are carried out up to the sample that completes each
        // frame before the frame is heard, the rest after it: whatever the block partition,
        // a frame's events meet the breath playing and the actions scheduled as of its own
        // sample, and a frame is emitted after the events of every frame completed by its
        // emission sample and of none after (live mode emits a frame at the sample that
        // completes it).
        // The speech decision hears the samples that complete each frame, then the frame.
        // A replayed stream learns nothing as it goes: the learning pass heard the speech
        // that colours a voice (see `Engine::replay_analysis`).
        let listen = self.replay.is_none() || breath_voice.learning();
        let mut fed = 0;
        let mut out = output::Output {
            block,
            done: 0,
            checked: 0,
        };
        for k in 0..count {
            let (f, i) = self.completed[k];
            self.output(config, audio, &mut out, i, on_control);
            self.speech.push(&self.mono[fed..=i]);
            if listen {
                self.voice.push(&self.mono[fed..=i]);
            }
            fed = i + 1;
            self.speech.frame(&f, self.tracker.noise_floor_db());
            self.on_frame(config, breath_voice, &f, base + i as u64, i, channels);
        }
        self.speech.push(&self.mono[fed..n]);
        if listen {
            self.voice.push(&self.mono[fed..n]);
        }
        self.output(config, audio, &mut out, n, on_control);
        if self.live {
            self.note_activity(base, out.checked, n);
        }
        self.state.position = base + n as u64;
    }

    /// One analysis frame, completed by input sample `now` (index `i` in the block).
    #[allow(clippy::too_many_arguments)]
    fn on_frame(
        &mut self,
        config: &EngineConfig,
        breath_voice: &VoiceChoice,
        f: &FeatureFrame,
        now: u64,
        i: usize,
        channels: usize,
    ) {
        self.voice.frame(f);
        if self.placement.on_frame(f) {
            self.stereo.learn(i, channels);
            let gains = self.stereo.gains(channels);
            self.placement.follow_image(f.time_s, gains);
        }
        let frame_pos = (f.time_s * self.sample_rate_hz).round() as u64;
        let emit_at = (frame_pos + self.delay.latency() as u64).max(now);
        self.pending.push_back(Pending {
            frame: *f,
            other_sound: false,
            emit_at,
        });
        // The tracker reports at most an end, an activity and a start per frame.
        let mut events: [Option<PhraseEvent>; 3] = [None; 3];
        let mut count = 0;
        self.tracker.update(f, |e| {
            if count < events.len() {
                events[count] = Some(e);
            }
            count += 1;
        });
        debug_assert!(count <= events.len(), "{count} phrase events at one frame");
        self.lost.phrase_events += count.saturating_sub(events.len()) as u64;
        // The speech decision judges the phrases first (an end's judgement is kept apart from
        // the phrase a start in the same frame begins), then the body gate flags the frames.
        let mut ended = None;
        for e in events.iter().flatten() {
            match *e {
                PhraseEvent::Start { onset_s, .. } => self.speech.phrase_started(onset_s),
                PhraseEvent::End { onset_s, offset_s } => {
                    let speech = self.speech.phrase_ended(onset_s, offset_s);
                    ended = Some((onset_s, offset_s, speech));
                }
                PhraseEvent::Activity { .. } => {}
            }
        }
        self.state
            .body
            .frame(&self.speech, ended, &mut self.pending, now, self.live);
        let ctx = EventContext {
            config,
            now,
            gains: self.stereo.gains(channels),
            breath_playing: self.breaths.playing(),
            pending: &self.pending,
            speech: &self.speech,
            upper_edge_hz: self.voice.upper_edge_hz(),
            speech_db: self.voice.speech_db(),
        };
        for e in events.into_iter().flatten() {
            if let PhraseEvent::Start {
                pause:
                    crate::phrase::Pause {
                        breath_s: Some(span),
                        breath_clean_s,
                        ..
                    },
                ..
            } = e
            {
                self.existing.push_back(span);
                if let (true, Some(clean)) = (breath_voice.learning(), breath_clean_s) {
                    self.voice.hear(clean);
                }
            }
            // Before the placement hears of a new phrase: the voice as learned, or coloured by
            // the speech, so far.
            if !matches!(breath_voice.mode, BreathVoiceMode::Fixed(_))
                && matches!(e, PhraseEvent::Start { .. })
            {
                let v = self.voice.current(breath_voice);
                self.breaths.voice_mut().use_learned(v.as_ref());
            }
            self.placement.on_event(&ctx, e, &mut self.schedule);
            if matches!(e, PhraseEvent::End { .. }) {
                // The breath before this phrase is learned against its speaker's level.
                self.voice.phrase_ended(self.placement.ended_speaker_db());
            }
        }
        if self.live {
            if self.tracker.breath_heard_in_pause() {
                self.placement.live_breath_heard(&ctx, &mut self.schedule);
            } else if self.tracker.breath_under_way_in_pause() {
                self.placement
                    .live_breath_under_way(&ctx, &mut self.schedule);
            }
            let breathing_in = self.tracker.breathing_in_pause();
            if breathing_in {
                self.placement
                    .live_inspire_with_breath(&ctx, &mut self.schedule);
            }
            self.schedule.breathing_in = breathing_in;
        }
        self.placement.decide_due(&ctx, &mut self.schedule);
    }
}
