//! The one streaming [`Engine`] that the CLI and the plugin both drive: audio blocks of any size
//! in, the same audio with breaths inserted out, plus one [`ControlFrame`] per frame of the frame
//! clock.
//!
//! ## Inside one call to [`Engine::process`]
//! 1. The input is cleaned (non-finite samples become 0), mixed to mono for analysis, and written
//!    into a per-channel delay line of `latency_samples()` (lookahead mode) or none (live mode).
//! 2. The analyzer turns the mono signal into feature frames sample by sample; each frame goes to
//!    the head-pose synthesis and the phrase tracker at once, and waits in a queue until the
//!    output reaches its time.
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
//!      stops inspiring before the first frame that heard it. A breath cut within its first
//!      60 ms or never above −60 dBFS is an inaudible stub and is not reported.
//! 4. The output is the delayed input, bit for bit, plus the breath sound where a breath plays,
//!    spread over the channels in the voice's stereo image.
//! 5. Control frames are emitted when the output reaches their time, with their sample offset in
//!    the block: the breathing cycle advances by one frame, driven by the scheduled events.
//!
//! Every decision depends on the sample sequence only, so any block partition gives identical
//! output and control frames. `process` never allocates.

mod config;
mod gate;
pub mod offline;
mod schedule;

pub use config::{EngineConfig, EngineError, PlacementConfig, PlacementMode};

use crate::analysis::{Analyzer, FeatureFrame};
use crate::breathing::{BreathCycle, BreathSample, BreathVoice, SampleSlot};
use crate::control::{BreathEvent, BreathKind, ControlFrame, HeadAngles};
use crate::head::{HeadModel, HeadSynth};
use crate::phrase::{PhraseEvent, PhraseTracker};
use gate::InputGate;
use schedule::Queue;

/// Most channels a stream may have.
pub const MAX_CHANNELS: usize = 8;
/// Shortest inhalation worth inserting, seconds.
const MIN_BREATH_S: f64 = 0.12;
/// Prior of the utterance length before any phrase was heard, seconds.
const PRIOR_UTTERANCE_S: f32 = 2.5;
/// Weight of the newest phrase in the running utterance-length estimate.
const UTTERANCE_SMOOTHING: f32 = 0.3;
/// Live mode: a breath whose peak stayed under this, dBFS, is an inaudible stub and is not
/// reported.
const LIVE_STUB_PEAK_DB: f32 = -60.0;
/// Live mode: a breath cut by speech before it sounded this long, seconds, is a stub (still in
/// its attack, under the onset that cut it) and is not reported.
const LIVE_STUB_S: f64 = 0.06;

/// A breath action on the input timeline (sample index).
#[derive(Debug, Clone, Copy, PartialEq)]
enum BreathAction {
    /// Start an inhalation of `length` samples with plateau RMS `gain`, spread over the
    /// channels with `gains`.
    Start {
        length: usize,
        gain: f32,
        gains: [f32; MAX_CHANNELS],
    },
    /// Live mode: start an inhalation like `Start` unless the input is active at that sample,
    /// and let the breathing cycle inspire with it (`audible` false: the cycle only).
    LiveStart {
        length: usize,
        gain: f32,
        gains: [f32; MAX_CHANNELS],
        audible: bool,
        utterance_s: f32,
    },
    /// Fade the playing inhalation out.
    FadeOut,
}

/// A breathing-cycle event on the input timeline (seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
enum CycleAction {
    Inspire { length_s: f32, utterance_s: f32 },
    UtteranceStarts { utterance_s: f32 },
    SpeechStopped,
}

/// A feature frame waiting for the output to reach it.
#[derive(Debug, Clone, Copy, Default)]
struct Pending {
    frame: FeatureFrame,
    head: HeadAngles,
    /// Output sample index from which it may be emitted.
    emit_at: u64,
}

/// The breath being rendered, for `breaths.csv`.
#[derive(Debug, Clone, Copy)]
struct OpenBreath {
    start: u64,
    /// Planned end (input timeline), shortened by a fade-out.
    end: u64,
    kind: BreathKind,
    peak: f32,
    /// Where a fade-out began, if one did.
    fade_from: Option<u64>,
}

/// Everything sized by `prepare`.
#[derive(Debug)]
struct Stream {
    sample_rate_hz: f64,
    channels: usize,
    max_block: usize,
    mode: PlacementMode,
    /// Frame rate fixed at `prepare` (a new one takes effect at the next `prepare`).
    frame_rate_hz: f64,
    latency: usize,
    /// Samples from an input sample to the last frame that depends on it being emitted.
    tail: usize,
    analyzer: Analyzer,
    tracker: PhraseTracker,
    head: HeadSynth,
    cycle: BreathCycle,
    voice: BreathVoice,
    /// Per-channel delay rings (power-of-two length).
    delay: Vec<Vec<f32>>,
    delay_mask: usize,
    breath: Vec<f32>,
    pending: Queue<Pending>,
    breath_actions: Queue<(u64, BreathAction)>,
    cycle_actions: Queue<(f64, CycleAction)>,
    finished_breaths: Queue<BreathEvent>,
    open_breath: Option<OpenBreath>,
    /// Samples taken in (input timeline) = samples given out (output timeline).
    position: u64,
    /// Running mean square per channel over voiced frames, for the stereo image.
    channel_ms: [f64; MAX_CHANNELS],
    /// Per-channel mean square smoothed over about 20 ms, sample by sample.
    short_ms: [f64; MAX_CHANNELS],
    /// `short_ms` at every sample of the current block, per channel.
    ms_trace: Vec<Vec<f64>>,
    energy_smoothing: f64,
    /// Mono mix of the current block.
    mono: Vec<f32>,
    /// Frames completed in the current block with the index of the completing sample.
    completed: Vec<(FeatureFrame, usize)>,
    speech_level_db: f32,
    /// Power sum and count of the voiced frames of the phrase being spoken.
    phrase_power: f64,
    phrase_voiced: u32,
    /// Level of the last complete phrase, dBFS.
    last_phrase_level_db: Option<f32>,
    /// Channel gains of the breath playing.
    breath_gains: [f32; MAX_CHANNELS],
    utterance_s: f32,
    speaking: bool,
    /// Start (s) and expected length (s) of the utterance being spoken.
    utterance_start_s: f64,
    utterance_expected_s: f64,
    breath_end: u64,
    /// Live mode: the input gate and whether the input is active at every sample of the
    /// current block.
    gate: InputGate,
    input_active: Vec<bool>,
    /// Live mode: the last input sample where the input was active (gate or tracker) that the
    /// breathing cycle has not yet been told about.
    activity_unseen: Option<u64>,
    /// Live mode: the playing breath is already fading out.
    fading: bool,
    /// Losses counted since `prepare` (see [`Dropped`]).
    lost: Lost,
}

/// Losses [`Dropped`] reports besides the queues' own counts.
#[derive(Debug, Clone, Copy, Default)]
struct Lost {
    frames: u64,
    phrase_events: u64,
    analysis_blocks: u64,
}

/// What the engine had to drop since the last [`Engine::prepare`], counted so that no loss is
/// silent. Every count but `breaths` stays 0 unless an internal bound is wrong (debug builds
/// assert it); `breaths` grows when a caller lets more than 64 finished breaths pile up
/// without [`Engine::take_breaths`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Dropped {
    /// Feature frames completed in one block beyond the block's frame buffer.
    pub frames: u64,
    /// Phrase events beyond three reported at one frame.
    pub phrase_events: u64,
    /// Control frames, breath actions and breathing-cycle actions pushed out of full queues.
    pub scheduled: u64,
    /// Finished breaths pushed out before [`Engine::take_breaths`] collected them.
    pub breaths: u64,
    /// Blocks the analysis refused (it is prepared for every block `process` hands it).
    pub analysis_blocks: u64,
}

impl Dropped {
    /// True when nothing was dropped.
    pub fn is_none(&self) -> bool {
        *self == Self::default()
    }
}

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

/// The streaming engine. See the module docs.
#[derive(Debug)]
pub struct Engine {
    /// The settings in effect.
    config: EngineConfig,
    /// Settings waiting for the next `prepare` (a change of the stream part).
    pending: Option<EngineConfig>,
    model: HeadModel,
    samples: [Option<BreathSample>; 2],
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
                scheduled: s.pending.dropped()
                    + s.breath_actions.dropped()
                    + s.cycle_actions.dropped(),
                breaths: s.finished_breaths.dropped(),
                analysis_blocks: s.lost.analysis_blocks,
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
            s.voice.set_sample(slot, sample);
        }
    }

    /// Allocates everything for a stream at `sample_rate_hz` (8–768 kHz) with blocks of at most
    /// `max_block` samples and `channels` channels (1–8), and resets.
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
        let low = c.breathing.map();
        let cycle = BreathCycle::new(&low);
        let mut voice = BreathVoice::new(c.seed);
        voice.prepare(sample_rate_hz, max_block);
        for (slot, sample) in [SampleSlot::Mouth, SampleSlot::Nose]
            .into_iter()
            .zip(self.samples.iter())
        {
            voice.set_sample(slot, sample.clone());
        }
        let latency = match c.placement.mode {
            PlacementMode::Lookahead => {
                (c.placement.lookahead_s as f64 * sample_rate_hz).round() as usize
            }
            PlacementMode::Live => 0,
        };
        let ring = (latency + max_block + 1).next_power_of_two();
        let frames_per_block =
            (max_block as f64 * frame_rate_hz / sample_rate_hz).ceil() as usize + 4;
        let analysis_latency_s = analyzer.latency_s().unwrap_or(0.05);
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
            mode: c.placement.mode,
            frame_rate_hz,
            latency,
            tail: latency
                + (analysis_latency_s * sample_rate_hz).ceil() as usize
                + (sample_rate_hz / frame_rate_hz).ceil() as usize
                + 1,
            analyzer,
            tracker,
            head,
            cycle,
            voice,
            delay: vec![vec![0.0; ring]; channels],
            delay_mask: ring - 1,
            breath: vec![0.0; max_block],
            pending: Queue::with_capacity(max_pending),
            breath_actions: Queue::with_capacity(max_actions),
            cycle_actions: Queue::with_capacity(max_actions),
            finished_breaths: Queue::with_capacity(64),
            open_breath: None,
            position: 0,
            channel_ms: [0.0; MAX_CHANNELS],
            short_ms: [0.0; MAX_CHANNELS],
            ms_trace: vec![vec![0.0; max_block]; channels],
            mono: vec![0.0; max_block],
            completed: vec![(FeatureFrame::default(), 0); frames_per_block],
            energy_smoothing: 1.0 - (-1.0 / (0.02 * sample_rate_hz)).exp(),
            speech_level_db: -26.0,
            phrase_power: 0.0,
            phrase_voiced: 0,
            last_phrase_level_db: None,
            breath_gains: [1.0; MAX_CHANNELS],
            utterance_s: PRIOR_UTTERANCE_S,
            speaking: false,
            utterance_start_s: 0.0,
            utterance_expected_s: PRIOR_UTTERANCE_S as f64,
            breath_end: 0,
            gate: InputGate::new(sample_rate_hz, c.phrase.silence_db),
            input_active: vec![false; max_block],
            activity_unseen: None,
            fading: false,
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
            s.tracker.reset();
            s.head.reset();
            s.cycle.reset();
            s.voice.reset();
            s.delay.iter_mut().for_each(|d| d.fill(0.0));
            s.pending.clear();
            s.breath_actions.clear();
            s.cycle_actions.clear();
            s.finished_breaths.clear();
            s.open_breath = None;
            s.position = 0;
            s.channel_ms = [0.0; MAX_CHANNELS];
            s.short_ms = [0.0; MAX_CHANNELS];
            s.speech_level_db = -26.0;
            s.phrase_power = 0.0;
            s.phrase_voiced = 0;
            s.last_phrase_level_db = None;
            s.breath_gains = [1.0; MAX_CHANNELS];
            s.utterance_s = PRIOR_UTTERANCE_S;
            s.speaking = false;
            s.utterance_start_s = 0.0;
            s.utterance_expected_s = PRIOR_UTTERANCE_S as f64;
            s.breath_end = 0;
            s.gate.reset();
            s.input_active.fill(false);
            s.activity_unseen = None;
            s.fading = false;
        }
    }

    /// The delay the engine adds, in samples: the lookahead in lookahead mode, 0 in live mode
    /// (0 before `prepare`).
    pub fn latency_samples(&self) -> u32 {
        self.stream.as_ref().map_or(0, |s| s.latency as u32)
    }

    /// Silence to feed after the end of a stream so every frame of it is emitted and every
    /// breath scheduled in it has played: the latency plus the analysis delay and one frame,
    /// in samples (0 before `prepare`). Offline renders feed this much and drop what lies past
    /// the end.
    pub fn tail_samples(&self) -> u64 {
        self.stream.as_ref().map_or(0, |s| s.tail as u64)
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
    /// to 64 are kept between calls.
    pub fn take_breaths(&mut self, mut on_breath: impl FnMut(&BreathEvent)) {
        if let Some(s) = &mut self.stream {
            while let Some(b) = s.finished_breaths.pop_front() {
                on_breath(&b);
            }
        }
    }

    /// Ends a stream: closes a breath still playing so that [`Engine::take_breaths`] reports it.
    pub fn finish(&mut self) {
        if let Some(s) = &mut self.stream {
            s.close_breath();
        }
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
            s.process_piece(&self.config, audio, channels, done, n, on_control);
            done += n;
        }
    }
}

impl Stream {
    fn process_piece(
        &mut self,
        config: &EngineConfig,
        audio: &mut [&mut [f32]],
        channels: usize,
        start: usize,
        n: usize,
        on_control: &mut dyn FnMut(&ControlFrame, usize),
    ) {
        let base = self.position;
        // 1. Per sample: clean input, delay line, energies smoothed over ~20 ms per channel
        // (kept per sample for step 2), mono mix.
        let smooth = self.energy_smoothing;
        let mask = self.delay_mask;
        for (c, chan) in audio.iter().take(channels).enumerate() {
            let mut ms = self.short_ms[c];
            let delay = &mut self.delay[c];
            let trace = &mut self.ms_trace[c];
            let mono = &mut self.mono;
            for (i, &x) in chan[start..start + n].iter().enumerate() {
                let x = if x.is_finite() { x } else { 0.0 };
                delay[(base as usize + i) & mask] = x;
                ms += smooth * ((x as f64) * (x as f64) - ms);
                trace[i] = ms;
                if c == 0 {
                    mono[i] = x;
                } else {
                    mono[i] += x;
                }
            }
            self.short_ms[c] = ms;
        }
        if channels > 1 {
            let inv = 1.0 / channels as f32;
            self.mono[..n].iter_mut().for_each(|m| *m *= inv);
        }
        let live = self.mode == PlacementMode::Live;
        if live {
            self.gate
                .process(&self.mono[..n], &mut self.input_active[..n]);
        }
        // 2. Analysis; each frame goes to the head pose, the phrase tracker and the scheduler
        // as of the sample that completed it, so any partition gives the same decisions.
        let mut count = 0;
        let mut beyond = 0u64;
        let completed = &mut self.completed;
        let analysed = self.analyzer.process_indexed(&self.mono[..n], |f, i| {
            if count < completed.len() {
                completed[count] = (*f, i);
                count += 1;
            } else {
                beyond += 1;
            }
        });
        // The analyzer is prepared for this block size and `completed` holds every frame a
        // block can complete: neither loss can happen unless a bound is wrong.
        debug_assert!(analysed.is_ok(), "analysis refused a block: {analysed:?}");
        debug_assert_eq!(beyond, 0, "frames beyond the block's frame buffer");
        self.lost.analysis_blocks += u64::from(analysed.is_err());
        self.lost.frames += beyond;
        for k in 0..count {
            let (f, i) = self.completed[k];
            self.on_frame(config, &f, base + i as u64, i, channels);
        }
        // 3. Output: the delayed input.
        for (chan, delay) in audio.iter_mut().zip(&self.delay).take(channels) {
            let out = &mut chan[start..start + n];
            for (i, y) in out.iter_mut().enumerate() {
                *y = delay[(base as usize + i + mask + 1 - self.latency) & mask];
            }
        }
        // 4. Breaths.
        self.render_breaths(config, audio, channels, start, n);
        // 5. Control frames due in this block.
        let end = base + n as u64;
        let dt_s = (1.0 / self.frame_rate_hz) as f32;
        let mut checked = 0;
        while let Some(p) = self.pending.front().copied() {
            if p.emit_at >= end {
                break;
            }
            self.pending.pop_front();
            if live {
                // Live: activity in the input up to the sample that completed this frame stops
                // an inspiration (and cancels one not begun yet) before the frame is emitted.
                let upto = (p.emit_at.max(base) - base) as usize;
                if upto >= checked {
                    self.note_activity(base, checked, upto + 1);
                    checked = upto + 1;
                }
                if let Some(at) = self.activity_unseen.take() {
                    let at_s = at as f64 / self.sample_rate_hz;
                    self.cycle_actions
                        .retain(|&(t, a)| !(t <= at_s && matches!(a, CycleAction::Inspire { .. })));
                    self.cycle.interrupt();
                }
            }
            while let Some(&(t, action)) = self.cycle_actions.front() {
                if t > p.frame.time_s + 1e-9 {
                    break;
                }
                self.cycle_actions.pop_front();
                match action {
                    CycleAction::Inspire {
                        length_s,
                        utterance_s,
                    } => self.cycle.inspire(length_s, utterance_s),
                    CycleAction::UtteranceStarts { utterance_s } => {
                        self.speaking = true;
                        self.cycle.utterance_starts(utterance_s);
                        self.utterance_start_s = t;
                        self.utterance_expected_s = utterance_s as f64;
                    }
                    CycleAction::SpeechStopped => {
                        self.speaking = false;
                        self.cycle.speech_stopped();
                    }
                }
            }
            // A phrase longer than expected: spread the rest of the air over a new estimate, so
            // the lung keeps falling smoothly instead of sitting empty while speaking.
            if self.speaking {
                let spoken_s = p.frame.time_s - self.utterance_start_s;
                if spoken_s >= 0.9 * self.utterance_expected_s {
                    let extra_s = (0.5 * self.utterance_expected_s).max(1.0);
                    self.cycle.utterance_starts(extra_s as f32);
                    self.utterance_expected_s = spoken_s + extra_s;
                }
            }
            let breathing = self.cycle.advance(dt_s);
            let f = &p.frame;
            let frame = ControlFrame {
                index: f.index,
                time_s: f.time_s,
                f0_hz: f.f0_hz,
                voiced: f.voiced,
                rms_db: f.rms_db,
                level_db: f.level_db,
                speaking: self.speaking,
                breathing,
                head: p.head,
            };
            let offset = p.emit_at.max(base) - base;
            on_control(&frame, start + offset as usize);
        }
        if live {
            self.note_activity(base, checked, n);
        }
        self.position = end;
    }

    /// Live mode: remembers the last active input sample of `input_active[from..to]` (block
    /// starting at input sample `base`) for the breathing cycle.
    fn note_activity(&mut self, base: u64, from: usize, to: usize) {
        if let Some(k) = self.input_active[from..to].iter().rposition(|&a| a) {
            let at = base + (from + k) as u64;
            self.activity_unseen = Some(self.activity_unseen.map_or(at, |u| u.max(at)));
        }
    }

    /// Live mode: whatever is scheduled to start at or after input sample `from` is dropped
    /// (speech came back before the pause was long enough), with its inspiration.
    fn cancel_live_breaths_from(&mut self, from: u64) {
        self.breath_actions
            .retain(|&(t, a)| !(t >= from && matches!(a, BreathAction::LiveStart { .. })));
        self.breath_end = self.breath_end.min(from);
    }

    /// Live mode: speech (or something like it) began in the pause, reported by the tracker at
    /// input sample `now` with its first active frame at `from`: nothing more starts in this
    /// pause, a breath playing fades out (if the gate has not faded it already), and the
    /// breathing cycle stops inspiring.
    fn live_activity(&mut self, from: u64, now: u64) {
        self.cancel_live_breaths_from(from);
        if self.voice.is_active() && !self.fading {
            self.breath_actions
                .insert_sorted((now, BreathAction::FadeOut));
        }
        self.activity_unseen = Some(self.activity_unseen.map_or(now, |u| u.max(now)));
    }

    /// One analysis frame, produced while taking in input sample `now`.
    fn on_frame(
        &mut self,
        config: &EngineConfig,
        f: &FeatureFrame,
        now: u64,
        i: usize,
        channels: usize,
    ) {
        let head = self.head.process(f, self.frame_rate_hz);
        if f.voiced && f.rms_db.is_finite() && f.level_db.is_finite() {
            self.speech_level_db = f.rms_db - f.level_db;
            self.phrase_power += 10f64.powf(f.rms_db as f64 / 10.0);
            self.phrase_voiced += 1;
            // The voice's stereo image: the channels' share of the recent energy, averaged over
            // voiced frames.
            let total: f64 = (0..channels).map(|c| self.ms_trace[c][i]).sum();
            if total > 0.0 {
                for c in 0..channels {
                    self.channel_ms[c] += 0.05 * (self.ms_trace[c][i] / total - self.channel_ms[c]);
                }
            }
        }
        let frame_pos = (f.time_s * self.sample_rate_hz).round() as u64;
        let emit_at = (frame_pos + self.latency as u64).max(now);
        self.pending.push_back(Pending {
            frame: *f,
            head,
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
        for e in events.into_iter().flatten() {
            self.on_phrase_event(config, e, now, channels);
        }
    }

    /// Level of the speech around a breath, dBFS: the phrase just spoken (its voiced frames'
    /// mean power), or, before the first phrase has ended, the loudest voiced frame of the
    /// upcoming phrase already analysed (lookahead; only its first tens of milliseconds are
    /// known, still rising, so their loudest frame stands for the phrase), or the running
    /// speech level.
    fn local_speech_level_db(&self, onset_s: Option<f64>) -> f32 {
        if let Some(db) = self.last_phrase_level_db {
            return db;
        }
        if let Some(onset_s) = onset_s {
            let loudest = self
                .pending
                .iter()
                .filter(|p| {
                    p.frame.time_s >= onset_s && p.frame.voiced && p.frame.rms_db.is_finite()
                })
                .map(|p| p.frame.rms_db)
                .fold(f32::NEG_INFINITY, f32::max);
            if loudest.is_finite() {
                return loudest;
            }
        }
        self.speech_level_db
    }

    /// Per-channel gains of a breath: the voice's share of energy in each channel, so a
    /// centred voice gets the breath at full level in every channel. Fixed when the breath is
    /// scheduled.
    fn channel_gains(&self, channels: usize) -> [f32; MAX_CHANNELS] {
        let mut g = [0.0f32; MAX_CHANNELS];
        let total: f64 = self.channel_ms[..channels].iter().sum();
        for (c, gc) in g.iter_mut().enumerate().take(channels) {
            *gc = if channels == 1 || total <= 0.0 {
                1.0
            } else {
                ((self.channel_ms[c] / total) * channels as f64).sqrt() as f32
            };
        }
        g
    }

    fn breath_gain(&self, config: &EngineConfig, speech_level_db: f32) -> f32 {
        let neutral = crate::breathing::BreathingParams::default()
            .map()
            .breath_rms_re_speech();
        let ours = config.breathing.map().breath_rms_re_speech();
        let preset_db = if neutral > 0.0 && ours > 0.0 {
            20.0 * (ours / neutral).log10()
        } else if ours <= 0.0 {
            -200.0
        } else {
            0.0
        };
        let rel_db = (config.placement.breath_level_db + preset_db).min(-6.0);
        10f32.powf((speech_level_db + rel_db) / 20.0)
    }

    fn on_phrase_event(
        &mut self,
        config: &EngineConfig,
        e: PhraseEvent,
        now: u64,
        channels: usize,
    ) {
        let p = &config.placement;
        let rate = self.sample_rate_hz;
        let inspiration_s = config.breathing.map().length_inspiration_s as f64;
        match e {
            PhraseEvent::Activity { time_s } => {
                // Live: a breath not started yet is dropped; one playing gives way (the gate
                // has usually faded it already).
                if self.mode == PlacementMode::Live {
                    self.live_activity((time_s * rate).round() as u64, now);
                }
            }
            PhraseEvent::Start { onset_s, pause } => {
                let utterance_s = self.utterance_s;
                self.phrase_power = 0.0;
                self.phrase_voiced = 0;
                self.cycle_actions
                    .insert_sorted((onset_s, CycleAction::UtteranceStarts { utterance_s }));
                if self.mode == PlacementMode::Live {
                    // The onset may lie before the first active frame (a quiet consonant).
                    self.live_activity((onset_s * rate).round() as u64, now);
                    return;
                }
                if onset_s - pause.start_s < p.min_pause_s as f64 {
                    return;
                }
                let end_s = onset_s - p.gap_s as f64;
                // Never over activity inside the pause, never in the past (the output has
                // reached input sample `now - latency`), never before the previous breath ended.
                let after_s = pause
                    .last_activity_end_s
                    .map_or(pause.start_s, |a| a.max(pause.start_s));
                let after_s = if pause.leading && pause.last_activity_end_s.is_none() {
                    after_s
                } else {
                    after_s + p.after_offset_s as f64
                };
                let earliest = ((now + 1).saturating_sub(self.latency as u64)).max(self.breath_end)
                    as f64
                    / rate;
                let start_s = (end_s - inspiration_s).max(after_s).max(earliest);
                if end_s - start_s < MIN_BREATH_S {
                    return;
                }
                let start = (start_s * rate).round() as u64;
                let length = ((end_s - start_s) * rate).round() as usize;
                // The body breathes in whether or not a sound is inserted (a breath already in
                // the pause, or insertion switched off).
                self.cycle_actions.insert_sorted((
                    start_s,
                    CycleAction::Inspire {
                        length_s: (end_s - start_s) as f32,
                        utterance_s,
                    },
                ));
                if !p.insert_breaths || pause.has_breath {
                    return;
                }
                let gain = self.breath_gain(config, self.local_speech_level_db(Some(onset_s)));
                let gains = self.channel_gains(channels);
                self.breath_actions.insert_sorted((
                    start,
                    BreathAction::Start {
                        length,
                        gain,
                        gains,
                    },
                ));
                self.breath_end = start + length as u64;
            }
            PhraseEvent::End { onset_s, offset_s } => {
                let length_s = (offset_s - onset_s).max(0.0) as f32;
                self.utterance_s += UTTERANCE_SMOOTHING * (length_s - self.utterance_s);
                if self.phrase_voiced >= 3 {
                    self.last_phrase_level_db = Some(
                        (10.0 * (self.phrase_power / self.phrase_voiced as f64).log10()) as f32,
                    );
                }
                self.cycle_actions
                    .insert_sorted((offset_s, CycleAction::SpeechStopped));
                if self.mode == PlacementMode::Live {
                    // The inhalation (sound and cycle) starts once the pause has lasted the
                    // minimum pause and `after_offset_s`, unless the input is active then;
                    // activity before then cancels it (`live_activity`), activity while it
                    // plays fades it out (the gate in `render_breaths`).
                    let wait_s = (p.min_pause_s as f64).max(p.after_offset_s as f64);
                    let start = ((((offset_s + wait_s) * rate).round() as u64).max(now))
                        .max(self.breath_end);
                    let length = (inspiration_s * rate).round() as usize;
                    let gain = self.breath_gain(config, self.local_speech_level_db(None));
                    let gains = self.channel_gains(channels);
                    self.breath_actions.insert_sorted((
                        start,
                        BreathAction::LiveStart {
                            length,
                            gain,
                            gains,
                            audible: p.insert_breaths,
                            utterance_s: self.utterance_s,
                        },
                    ));
                    self.breath_end = start + length as u64;
                }
            }
        }
    }

    /// Renders the breath sound for the output block and adds it to the channels.
    fn render_breaths(
        &mut self,
        config: &EngineConfig,
        audio: &mut [&mut [f32]],
        channels: usize,
        start: usize,
        n: usize,
    ) {
        let base = self.position;
        let end = base + n as u64;
        // Output sample o plays input sample o - latency.
        let in_base = base.saturating_sub(self.latency as u64);
        let warm = (self.latency as u64).saturating_sub(base).min(n as u64) as usize;
        if !self.voice.is_active()
            && self
                .breath_actions
                .front()
                .is_none_or(|&(t, _)| t + self.latency as u64 >= end)
        {
            return;
        }
        // Taken out for the loop (no allocation) and put back at the end.
        let mut breath = std::mem::take(&mut self.breath);
        let buf = &mut breath[..n];
        buf.fill(0.0);
        let mut pos = warm;
        let mut active_from = n;
        let mut active_to = 0;
        let live = self.mode == PlacementMode::Live;
        loop {
            let mut next = self
                .breath_actions
                .front()
                .map(|&(t, a)| ((t.max(in_base) - in_base) as usize + warm, a))
                .filter(|&(off, _)| off < n);
            // Live: the first active input sample under a breath not yet fading fades it.
            let mut gated = false;
            if live && self.voice.is_active() && !self.fading {
                let until = next.map_or(n, |(off, _)| off);
                if let Some(k) = self.input_active[pos..until].iter().position(|&a| a) {
                    next = Some((pos + k, BreathAction::FadeOut));
                    gated = true;
                }
            }
            let stop = next.map_or(n, |(off, _)| off);
            if self.voice.is_active() && stop > pos {
                active_from = active_from.min(pos);
                active_to = stop;
                self.voice.render_add(&mut buf[pos..stop]);
            }
            pos = stop;
            let Some((_, action)) = next else { break };
            if !gated {
                self.breath_actions.pop_front();
            }
            let at = in_base + pos as u64 - warm as u64;
            let action = match action {
                // Live: speech is back where the breath was due: neither sound nor inspiration.
                BreathAction::LiveStart { .. } if self.input_active[pos] => continue,
                BreathAction::LiveStart {
                    length,
                    gain,
                    gains,
                    audible,
                    utterance_s,
                } => {
                    let rate = self.sample_rate_hz;
                    self.cycle_actions.insert_sorted((
                        at as f64 / rate,
                        CycleAction::Inspire {
                            length_s: (length as f64 / rate) as f32,
                            utterance_s,
                        },
                    ));
                    if !audible {
                        continue;
                    }
                    BreathAction::Start {
                        length,
                        gain,
                        gains,
                    }
                }
                other => other,
            };
            match action {
                BreathAction::Start {
                    length,
                    gain,
                    gains,
                } => {
                    // Close the previous breath's record before the new one starts.
                    if self.open_breath.is_some() {
                        let peak = buf[active_from.min(pos)..pos]
                            .iter()
                            .fold(0.0f32, |m, x| m.max(x.abs()));
                        let g_max = self.max_channel_gain(channels);
                        if let Some(b) = &mut self.open_breath {
                            b.peak = b.peak.max(peak * g_max);
                        }
                        self.close_breath();
                    }
                    {
                        let mouth = config.breathing.map().mouth_share();
                        self.fading = false;
                        self.voice.start(mouth, length, gain);
                        self.breath_gains = gains;
                        self.open_breath = Some(OpenBreath {
                            start: at,
                            end: at + length as u64,
                            kind: self.voice.kind(),
                            peak: 0.0,
                            fade_from: None,
                        });
                        active_from = active_from.min(pos);
                    }
                }
                BreathAction::FadeOut if self.fading => {}
                BreathAction::FadeOut => {
                    self.fading = true;
                    let fade = (config.placement.live_fade_s as f64 * self.sample_rate_hz)
                        .round()
                        .max(1.0) as usize;
                    self.voice.fade_out(fade);
                    if let Some(b) = &mut self.open_breath {
                        b.end = b.end.min(at + fade as u64);
                        b.fade_from.get_or_insert(at);
                    }
                }
                BreathAction::LiveStart { .. } => unreachable!("turned into Start above"),
            }
        }
        if active_from < active_to {
            let peak = buf[active_from..active_to]
                .iter()
                .fold(0.0f32, |m, x| m.max(x.abs()));
            let g_max = self.max_channel_gain(channels);
            if let Some(b) = &mut self.open_breath {
                b.peak = b.peak.max(peak * g_max);
            }
            for (c, chan) in audio.iter_mut().take(channels).enumerate() {
                let g = self.breath_gains[c];
                let out = &mut chan[start + active_from..start + active_to];
                for (y, b) in out.iter_mut().zip(&buf[active_from..active_to]) {
                    // Only where the breath sounds: adding 0 would turn −0.0 into +0.0.
                    if *b != 0.0 {
                        *y += g * b;
                    }
                }
            }
        }
        self.breath = breath;
        if !self.voice.is_active() {
            self.close_breath();
        }
    }

    fn max_channel_gain(&self, channels: usize) -> f32 {
        self.breath_gains[..channels]
            .iter()
            .fold(0.0, |m, g| m.max(*g))
    }

    /// Files the current breath (if any) as finished, with its planned (or faded) end.
    fn close_breath(&mut self) {
        if let Some(b) = self.open_breath.take() {
            let peak_db = crate::analysis::amplitude_to_db(b.peak as f64);
            let rate = self.sample_rate_hz;
            let sounded_s = (b.fade_from.unwrap_or(b.end).saturating_sub(b.start)) as f64 / rate;
            if self.mode == PlacementMode::Live
                && (peak_db.is_nan() || peak_db < LIVE_STUB_PEAK_DB || sounded_s < LIVE_STUB_S)
            {
                return;
            }
            self.finished_breaths.push_back(BreathEvent {
                start_s: b.start as f64 / rate,
                end_s: b.end.max(b.start) as f64 / rate,
                kind: b.kind,
                peak_db,
            });
        }
    }
}
