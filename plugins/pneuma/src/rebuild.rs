//! Settings that need a new engine (mode, lookahead, frame rate, breath-sample files, the
//! breath-like recording) take effect while the plugin stays active.
//!
//! Hosts do not reliably re-activate a plugin that asks for it: Ardour 7 answers VST3's
//! `restartComponent(kLatencyChanged)` by reading the latency again, never by re-activating, and
//! a host restores a saved session into an instance that is already active. So the plugin builds
//! the new engine itself, off the audio thread, and swaps it in:
//!
//! 1. The audio thread sees that the [`Structural`] settings differ from the running engine's
//!    and asks the plugin's build thread for one engine ([`BuildWorker::request`]: an atomic
//!    flag and a thread unpark).
//! 2. [`EngineBuilder::run`] (on that thread: allocates, reads files) drops the engines the
//!    audio thread retired, builds an engine for the current parameters and the stream the
//!    plugin was activated for, and hands it over through a lock-free queue ([`Built`]). Its
//!    breath voice: the one learned from the breath-like recording ([`crate::breath_like`]),
//!    else learned as the audio goes; the frozen one when the freeze is on ([`crate::voice`]).
//! 3. The audio thread ([`EngineSlot::follow`], through [`SwapEnds`]) takes it at the start of
//!    a block, swaps it in, reports its latency to the host (VST3:
//!    `restartComponent(kLatencyChanged)`; CLAP: a restart request, as the CLAP latency
//!    extension asks) and passes the old engine back to be dropped off the audio thread.
//!    Nothing on the audio thread allocates, frees, locks or blocks — with one exception:
//! 4. Offline (the host renders without a deadline: VST3 `ProcessSetup.processMode ==
//!    kOffline`, CLAP `render` extension `CLAP_RENDER_OFFLINE`, seen by nice-plug's
//!    `BufferConfig::process_mode` at activation), the audio thread waits in [`EngineSlot::follow`]
//!    for the build it has just asked for ([`OFFLINE_BUILD_WAIT`] at most, sleeping in
//!    [`OFFLINE_WAIT_STEP`]s, still without allocating, freeing or locking) and takes the engine at
//!    that very block. So a mid-export change takes over at the block that first sees it,
//!    identically on every run, instead of a few blocks later at a point that depends on the
//!    build thread's timing. In real time nothing waits: the engine is taken when it arrives.
//!
//! The mode is known only at activation. nice-plug 0.4.2's VST3 wrapper hands `activate` the mode
//! of the `setupProcessing` call *before* the last one (it stores the buffer config before the new
//! mode): a host that calls it once with `kOffline` is seen as real time (the bounce then behaves
//! as before: not reproducible); hosts that call it again before activating (JUCE-based hosts call
//! it in every `prepareToPlay`; pedalboard activates a new instance four times) are seen right from
//! the second call on. The other way round, real-time playback set up once after an offline export
//! is seen as offline, and a structural change while playing then holds the audio thread for the
//! build (a few ms; the cap only matters for a stuck build thread). CLAP is exact: a mode set while
//! active makes nice-plug ask the host for a restart, whose activation sees it.
//!
//! [`EngineSlot`] holds all of it for the plugin: the running engine, the builder and its
//! thread, the hand-over queues, the settings the engine was built from and the latency the host
//! was told. The plugin activates the slot, lets it follow the parameters at the start of each
//! block, and runs the engine it holds.
//!
//! The new engine starts empty, as after a transport jump: in lookahead mode the track is
//! silent for the new lookahead. Each activation starts a new stream epoch; an engine built for
//! an earlier one (a build still running when the host re-activated) is never swapped in.
//!
//! The build thread is the plugin's own, not nice-plug's shared background thread: that one
//! shuts down for every instance when a task of an instance already destroyed reaches it, and
//! the host then aborts when the last instance unloads (nice-plug 0.4.2,
//! `event_loop/background_thread.rs`).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::{JoinHandle, Thread};
use std::time::{Duration, Instant};

use nice_plug::nice_error;
use nice_plug::prelude::ProcessMode;
use pneuma_core::breathing::SampleSlot;
use pneuma_core::engine::{BreathVoiceMode, Engine, EngineConfig, EngineError};
use pneuma_core::head::HeadModel;
use rtrb::{Consumer, Producer, RingBuffer};

use crate::breath_like::VoiceCache;
use crate::load_breath_sample;
use crate::params::{ChangeFlags, PneumaParams};

/// Largest block the engine is prepared for; longer host blocks are processed in pieces.
pub const MAX_ENGINE_BLOCK: usize = 8192;

/// Engines in flight between the builder and the audio thread, each way. One build runs at a
/// time per epoch; the slack covers builds of earlier epochs still finishing after re-activations.
const QUEUE_ENGINES: usize = 8;

/// What an engine is built from that needs a new engine (and maybe a new latency) when it
/// changes: the engine settings' stream part (core's
/// [`pneuma_core::engine::EngineConfig::stream_differs`] decides, the one list of those fields)
/// and the files (breath samples, the breath-like recording). Two are equal when neither differs. The audio thread compares
/// them only when a structural parameter raised its change flag, a build came back, or a
/// sample path changed (building an `EngineConfig` does not allocate).
#[derive(Debug, Clone)]
pub struct Structural {
    /// The engine settings (only their stream part counts).
    pub config: EngineConfig,
    /// Changes of the file paths (the files are read when an engine is built).
    pub sample_generation: u64,
}

impl PartialEq for Structural {
    fn eq(&self, other: &Self) -> bool {
        self.sample_generation == other.sample_generation
            && !self.config.stream_differs(&other.config)
    }
}

impl Structural {
    /// The structural settings the parameters hold now (lock-free, allocation-free).
    pub fn of(p: &PneumaParams) -> Self {
        Self {
            config: p.engine_config(),
            sample_generation: sample_generation(p),
        }
    }
}

/// The file paths' change count: breath samples and the breath-like recording (lock-free).
pub fn sample_generation(p: &PneumaParams) -> u64 {
    p.breath_sample_mouth.generation()
        + p.breath_sample_nose.generation()
        + p.breath_like.generation()
}

/// The stream the plugin was activated for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreamSpec {
    /// Host sample rate, Hz.
    pub sample_rate_hz: f64,
    /// Largest block the engine is prepared for (the host's maximum, within 1..=8192).
    pub max_block: usize,
    /// Output channels.
    pub channels: usize,
    /// Activation count: engines built for another epoch are not used.
    pub epoch: u64,
}

impl StreamSpec {
    /// The stream for a host's sample rate, maximum block size and channel count: a host that
    /// reports 0 or a huge maximum block still gets an engine (it splits longer blocks).
    pub fn new(sample_rate_hz: f64, host_max_block: u32, channels: usize, epoch: u64) -> Self {
        Self {
            sample_rate_hz,
            max_block: (host_max_block as usize).clamp(1, MAX_ENGINE_BLOCK),
            channels,
            epoch,
        }
    }
}

/// An engine built off the audio thread, with what it was built from.
pub struct Built {
    /// The engine, or `None` where it cannot run (a sample rate the analysis does not take):
    /// the audio then passes untouched.
    pub engine: Option<Box<Engine>>,
    /// The structural settings it was built with.
    pub structural: Structural,
    /// Its breath voice without the freeze: the breath-like file's, or learning.
    pub voice: BreathVoiceMode,
    /// The activation it was built for.
    pub epoch: u64,
}

/// Builds engines for the plugin's parameters, at activation (main thread) and on the build
/// thread ([`EngineBuilder::run`]).
pub struct EngineBuilder {
    params: Arc<PneumaParams>,
    stream: Mutex<Option<StreamSpec>>,
    done: Mutex<Producer<Built>>,
    retired: Mutex<Consumer<Box<Engine>>>,
    /// The voice learned from the breath-like file, kept across builds (the instance's cache,
    /// shared with its editor's file check).
    breath_like: Arc<VoiceCache>,
}

/// The audio thread's ends of the hand-over queues.
pub struct SwapEnds {
    /// Engines the builder finished.
    pub built: Consumer<Built>,
    /// Engines the audio thread no longer uses, to be dropped by the builder.
    pub retire: Producer<Box<Engine>>,
}

impl SwapEnds {
    /// Passes an engine back to be dropped off the audio thread. Never allocates or frees: if
    /// the queue is full (more re-activations during one build than it holds, which the
    /// one-build-at-a-time rule prevents) the engine is leaked rather than freed here.
    pub fn retire(&mut self, engine: Option<Box<Engine>>) {
        if let Some(engine) = engine {
            if let Err(rtrb::PushError::Full(engine)) = self.retire.push(engine) {
                debug_assert!(false, "the engine retire queue is full");
                std::mem::forget(engine);
            }
        }
    }
}

impl EngineBuilder {
    /// A builder for `params`, learning breath-like files through `voices`, and the audio
    /// thread's ends of its queues.
    pub fn new(params: Arc<PneumaParams>, voices: Arc<VoiceCache>) -> (Arc<Self>, SwapEnds) {
        let (done, built) = RingBuffer::new(QUEUE_ENGINES);
        let (retire, retired) = RingBuffer::new(QUEUE_ENGINES);
        let builder = Arc::new(Self {
            params,
            stream: Mutex::new(None),
            done: Mutex::new(done),
            retired: Mutex::new(retired),
            breath_like: voices,
        });
        (builder, SwapEnds { built, retire })
    }

    /// An engine for the current parameters, breath samples and breath voice, prepared for
    /// `stream`, with the structural settings it was built from and its voice without the
    /// freeze. Allocates and reads files: not for the audio thread. A breath sample or
    /// breath-like file that cannot be used is logged and the procedural breath, or learning as
    /// the audio goes, stays.
    pub fn build(
        &self,
        stream: &StreamSpec,
    ) -> (Result<Engine, EngineError>, Structural, BreathVoiceMode) {
        // Read before the settings: a change in between only causes one more build.
        let structural = Structural::of(&self.params);
        let config = self.params.engine_config();
        let voice = self.breath_like_voice(&config);
        let engine = (|| {
            let mut engine = Engine::new(config, HeadModel::default_model().clone())?;
            engine.set_voice_mode(crate::voice::build_mode(&self.params, voice));
            for (slot, path) in [
                (SampleSlot::Mouth, &self.params.breath_sample_mouth),
                (SampleSlot::Nose, &self.params.breath_sample_nose),
            ] {
                match load_breath_sample(&path.get()) {
                    Ok(sample) => engine.set_breath_sample(slot, sample),
                    Err(e) => nice_error!("Pneuma: breath sample not used: {e}"),
                }
            }
            engine.prepare(stream.sample_rate_hz, stream.max_block, stream.channels)?;
            Ok(engine)
        })();
        (engine, structural, voice)
    }

    /// The voice learned from the breath-like file (the built-in one when no breath is heard
    /// in it), or learning as the audio goes without one or when it cannot be used (logged).
    fn breath_like_voice(&self, config: &EngineConfig) -> BreathVoiceMode {
        let path = self.params.breath_like.get();
        if path.trim().is_empty() {
            return BreathVoiceMode::Learn;
        }
        match self.breath_like.learn(path.trim(), config) {
            Ok(like) => like
                .voice
                .map_or(BreathVoiceMode::BuiltIn, BreathVoiceMode::Like),
            Err(e) => {
                nice_error!("Pneuma: {e}");
                BreathVoiceMode::Learn
            }
        }
    }

    /// Remembers the stream of a new activation (background builds prepare for it).
    pub fn set_stream(&self, stream: StreamSpec) {
        if let Ok(mut s) = self.stream.lock() {
            *s = Some(stream);
        }
    }

    /// Drops the engines the audio thread retired (any thread but the audio thread).
    pub fn drop_retired(&self) {
        if let Ok(mut retired) = self.retired.lock() {
            while retired.pop().is_ok() {}
        }
    }

    /// [`EngineBuilder::build`], boxed; an engine that cannot run is logged and `None`.
    pub fn build_boxed(&self, stream: &StreamSpec) -> Built {
        let (engine, structural, voice) = self.build(stream);
        let engine = match engine {
            Ok(engine) => Some(Box::new(engine)),
            Err(e) => {
                nice_error!("Pneuma: audio passes untouched and the controls rest: {e}");
                None
            }
        };
        Built {
            engine,
            structural,
            voice,
            epoch: stream.epoch,
        }
    }

    /// The build thread's task: drops retired engines, then builds one for the current
    /// parameters and the last activation's stream and hands it to the audio thread. Does
    /// nothing before the first activation.
    pub fn run(&self) {
        self.drop_retired();
        let Some(stream) = self.stream.lock().ok().and_then(|s| *s) else {
            return;
        };
        let built = self.build_boxed(&stream);
        if let Ok(mut done) = self.done.lock() {
            // A full queue means the audio thread stopped taking engines (deactivated): this
            // one is dropped here.
            if done.push(built).is_err() {
                nice_error!("Pneuma: an engine was built for nobody (queue full)");
            }
        }
    }
}

/// How long the build thread sleeps between looks at its request flag when nobody wakes it.
const BUILD_POLL: Duration = Duration::from_millis(50);

/// Stack of the build thread. An engine is about 55 kB inline and is built by value; hosts call
/// `activate` on threads with small stacks (Ardour 7 from its process thread, where building
/// there overflowed the stack), so activation builds here too.
const BUILD_STACK_BYTES: usize = 8 << 20;

/// The longest `activate` waits for the build thread before building on its own thread.
const ACTIVATE_WAIT: Duration = Duration::from_secs(10);

/// The plugin's build thread: runs [`EngineBuilder::run`] once per request. Stops and joins on
/// drop (after the build in progress, if any).
pub struct BuildWorker {
    requested: Arc<AtomicBool>,
    stop: Arc<AtomicBool>,
    thread: Thread,
    handle: Option<JoinHandle<()>>,
}

impl BuildWorker {
    /// Starts the thread for `builder`.
    pub fn start(builder: Arc<EngineBuilder>) -> std::io::Result<Self> {
        let requested = Arc::new(AtomicBool::new(false));
        let stop = Arc::new(AtomicBool::new(false));
        let handle = std::thread::Builder::new()
            .name("pneuma-engine-build".into())
            .stack_size(BUILD_STACK_BYTES)
            .spawn({
                let requested = requested.clone();
                let stop = stop.clone();
                move || {
                    while !stop.load(Ordering::Acquire) {
                        if requested.swap(false, Ordering::AcqRel) {
                            builder.run();
                        }
                        std::thread::park_timeout(BUILD_POLL);
                    }
                    builder.drop_retired();
                }
            })?;
        Ok(Self {
            requested,
            stop,
            thread: handle.thread().clone(),
            handle: Some(handle),
        })
    }

    /// Asks for one build (audio thread: an atomic store and a futex wake; no allocation, no
    /// lock, no waiting).
    pub fn request(&self) {
        self.requested.store(true, Ordering::Release);
        self.thread.unpark();
    }
}

impl BuildWorker {
    /// Activation (not the audio thread): builds an engine for `epoch` on the build thread and
    /// waits for it; engines of earlier epochs met on the way are dropped here. `None` if the
    /// thread gave no engine within [`ACTIVATE_WAIT`].
    pub fn build_and_wait(&self, swap: &mut SwapEnds, epoch: u64) -> Option<Built> {
        let start = std::time::Instant::now();
        self.request();
        loop {
            while let Ok(built) = swap.built.pop() {
                if built.epoch == epoch {
                    return Some(built);
                }
            }
            if start.elapsed() > ACTIVATE_WAIT {
                return None;
            }
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}

impl Drop for BuildWorker {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        self.thread.unpark();
        if let Some(handle) = self.handle.take() {
            if handle.join().is_err() {
                nice_error!("Pneuma: the engine build thread panicked");
            }
        }
    }
}

/// Seconds of processed audio after which an unanswered build is asked for again.
const BUILD_RETRY_S: f64 = 2.0;

/// Offline, the longest the audio thread waits for the build it asked for; after it the block
/// goes on with the running engine and the build is taken when it arrives, as in real time.
pub const OFFLINE_BUILD_WAIT: Duration = ACTIVATE_WAIT;

/// Offline, how long the audio thread sleeps between looks at the hand-over queue while it waits
/// for a build (a sleep is a system call: no allocation, no lock).
pub const OFFLINE_WAIT_STEP: Duration = Duration::from_micros(250);

/// What a block's look at the [`EngineSlot`] asks of the host and the editor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SlotEvent {
    /// A newly built engine runs now (`running`), or none where it cannot run at this rate:
    /// report its latency to the host (VST3: `restartComponent(kLatencyChanged)`) and show it.
    Swapped {
        /// The new engine's latency, samples (0 without an engine).
        latency: u32,
        /// An engine runs (false: the audio passes untouched and the controls rest).
        running: bool,
        /// The stream's sample rate, Hz.
        sample_rate_hz: f32,
    },
    /// A built engine would change the latency, which the host hears of only while
    /// activating (CLAP): ask the host for a restart; the running engine keeps going until
    /// then, and the re-activation builds from the new settings.
    RestartWanted,
}

/// The plugin's engine and everything about replacing it: the running engine, the builder and
/// its thread, the hand-over queues, the structural settings the engine was built from, the
/// latency reported to the host and the build asked for. The plugin activates it, looks at it
/// at the start of every block ([`EngineSlot::follow`]) and runs the engine it holds.
pub struct EngineSlot {
    params: Arc<PneumaParams>,
    /// `None` before activation and where the engine cannot run at the host's sample rate.
    /// Boxed so that swapping engines on the audio thread moves a pointer and frees nothing.
    engine: Option<Box<Engine>>,
    /// The running engine's breath voice without the freeze ([`Built::voice`]).
    voice: BreathVoiceMode,
    /// Builds engines: at activation, and on `worker` when structural settings change.
    builder: Arc<EngineBuilder>,
    /// The build thread (started at the first activation).
    worker: Option<BuildWorker>,
    /// The audio thread's ends of the engine hand-over.
    swap: SwapEnds,
    /// The running engine's structural settings.
    prepared: Option<Structural>,
    /// Structural settings whose engine was built but held back for a latency change; not built
    /// again until the settings move on or the plugin is re-activated.
    held: Option<Structural>,
    /// The latency last reported to the host, samples.
    reported_latency: u32,
    /// The host hears of a latency change only while activating (CLAP): a built engine whose
    /// latency differs from the reported one then waits for the next activation.
    latency_only_at_activation: bool,
    /// The host renders offline (no deadline): the audio thread waits for the builds it asks for
    /// ([`EngineSlot::follow`]).
    offline: bool,
    /// The current activation's stream (its epoch tells builds for it from older ones).
    stream: Option<StreamSpec>,
    /// Samples processed since a background build was asked for (`None`: none pending).
    build_pending_samples: Option<u64>,
    /// The structural settings may differ from the running engine's: a structural parameter
    /// raised its flag, a build came back or a sample path changed. Compared (and cleared) at
    /// the next block instead of diffing the settings every block.
    structure_stale: bool,
    /// The breath-sample change count last seen.
    seen_sample_generation: u64,
}

impl EngineSlot {
    /// An empty slot for `params` (no engine until [`EngineSlot::activate`]), learning
    /// breath-like files through `voices`.
    pub fn new(params: Arc<PneumaParams>, voices: Arc<VoiceCache>) -> Self {
        let (builder, swap) = EngineBuilder::new(params.clone(), voices);
        Self {
            params,
            engine: None,
            voice: BreathVoiceMode::default(),
            builder,
            worker: None,
            swap,
            prepared: None,
            held: None,
            reported_latency: 0,
            latency_only_at_activation: false,
            offline: false,
            stream: None,
            build_pending_samples: None,
            structure_stale: true,
            seen_sample_generation: 0,
        }
    }

    /// The running engine.
    pub fn engine_mut(&mut self) -> Option<&mut Engine> {
        self.engine.as_deref_mut()
    }

    /// The running engine and its breath voice without the freeze ([`Built::voice`]).
    pub fn engine_and_voice(&mut self) -> (Option<&mut Engine>, &BreathVoiceMode) {
        (self.engine.as_deref_mut(), &self.voice)
    }

    /// Whether an engine runs (none before activation or at a rate it cannot run at).
    pub fn is_running(&self) -> bool {
        self.engine.is_some()
    }

    /// The running engine's latency, samples (0 without one).
    pub fn latency_samples(&self) -> u32 {
        self.engine.as_ref().map_or(0, |e| e.latency_samples())
    }

    /// Clears the running engine's stream state (no allocation).
    pub fn reset(&mut self) {
        if let Some(engine) = self.engine_mut() {
            engine.reset();
        }
    }

    /// Applies the parameters' live settings to the running engine at once (allocation-free);
    /// a stream part waits for the build that the structure flag asks for.
    pub fn apply_live_settings(&mut self) {
        let config = self.params.engine_config();
        if let Some(engine) = self.engine_mut() {
            // Every parameter is in range, so the settings are valid.
            if let Err(e) = engine.set_config(&config) {
                debug_assert!(false, "the parameters' engine settings are valid: {e}");
            }
        }
    }

    /// Activation (not the audio thread): an engine for the parameters and this stream,
    /// built on the build thread (a known stack; here only if that thread is missing or stuck),
    /// replaces the running one; the latency to report to the host. Never fails: where the
    /// engine cannot run at `sample_rate_hz` the slot holds none (latency 0).
    /// `latency_only_at_activation`: the host hears of latency changes only here (CLAP).
    /// `process_mode`: offline, the audio thread waits for the engines it asks for (see the
    /// module docs); real time and buffered (VST3 prefetch, which has a deadline too), never.
    pub fn activate(
        &mut self,
        sample_rate_hz: f32,
        host_max_block: u32,
        channels: usize,
        latency_only_at_activation: bool,
        process_mode: ProcessMode,
    ) -> u32 {
        let epoch = self.stream.map_or(0, |s| s.epoch) + 1;
        let stream = StreamSpec::new(f64::from(sample_rate_hz), host_max_block, channels, epoch);
        self.stream = Some(stream);
        self.builder.set_stream(stream);
        // Engines from builds of earlier activations are dropped here, off the audio thread.
        while self.swap.built.pop().is_ok() {}
        self.builder.drop_retired();
        self.build_pending_samples = None;
        if self.worker.is_none() {
            match BuildWorker::start(self.builder.clone()) {
                Ok(worker) => self.worker = Some(worker),
                // Structural changes then wait for the next activation.
                Err(e) => nice_error!("Pneuma: cannot start the engine build thread: {e}"),
            }
        }
        let built = self
            .worker
            .as_ref()
            .and_then(|w| w.build_and_wait(&mut self.swap, epoch))
            .unwrap_or_else(|| self.builder.build_boxed(&stream));
        self.engine = built.engine;
        self.voice = built.voice;
        self.reported_latency = self.latency_samples();
        self.latency_only_at_activation = latency_only_at_activation;
        self.offline = process_mode == ProcessMode::Offline;
        self.held = None;
        self.prepared = Some(built.structural);
        // Settings may have moved while it was built.
        self.structure_stale = true;
        self.reported_latency
    }

    /// Deactivation (not the audio thread): drops the engines the audio thread handed back.
    pub fn deactivate(&self) {
        self.builder.drop_retired();
    }

    /// Audio thread, start of a block of `block` samples: swaps in an engine the builder
    /// finished for this activation (telling `on` what the host must hear), and asks for a
    /// build when the structural settings differ from the running engine's. Never allocates,
    /// frees or locks. Blocks only offline: a build asked for here is waited for and taken now
    /// ([`EngineSlot::wait_for_build`]); in real time it is taken at a later block.
    pub fn follow(&mut self, block: usize, mut on: impl FnMut(SlotEvent)) {
        let Some(stream) = self.stream else {
            return;
        };
        self.take_built(stream, &mut on);
        self.notice_structure_changes();
        if self.ask_for_build(block, stream) && self.offline {
            self.wait_for_build(stream, &mut on);
        }
    }

    /// Takes every engine the builder handed over: one of this activation is swapped in (or
    /// held back for a restart), older ones go back to be dropped off the audio thread.
    fn take_built(&mut self, stream: StreamSpec, on: &mut impl FnMut(SlotEvent)) {
        while let Ok(built) = self.swap.built.pop() {
            if built.epoch == stream.epoch {
                self.take(built, stream, on);
            } else {
                self.swap.retire(built.engine);
            }
        }
    }

    /// Offline only (no deadline): waits until the build just asked for comes back, then takes
    /// it as [`EngineSlot::take_built`] does, so it runs from this block on. Sleeps in
    /// [`OFFLINE_WAIT_STEP`]s without allocating, freeing or locking (the builder holds no lock
    /// the audio thread takes); gives up after [`OFFLINE_BUILD_WAIT`], leaving the build to be
    /// taken when it arrives, as in real time.
    fn wait_for_build(&mut self, stream: StreamSpec, on: &mut impl FnMut(SlotEvent)) {
        let start = Instant::now();
        while self.build_pending_samples.is_some() && start.elapsed() < OFFLINE_BUILD_WAIT {
            std::thread::sleep(OFFLINE_WAIT_STEP);
            self.take_built(stream, on);
        }
    }

    /// Swaps in an engine built for this activation, or holds it back for a restart.
    fn take(&mut self, built: Built, stream: StreamSpec, on: &mut impl FnMut(SlotEvent)) {
        self.build_pending_samples = None;
        // The parameters may have moved on while it was built.
        self.structure_stale = true;
        let latency = built.engine.as_ref().map_or(0, |e| e.latency_samples());
        if self.latency_only_at_activation && latency != self.reported_latency {
            // CLAP lets a plugin report a new latency only inside `activate`; reporting it
            // from here races the host's deactivation (nice-plug then tells the host outside
            // `activate`). Ask for the restart instead: the settings take effect at that
            // activation, which builds its engine from them and reports its latency.
            self.held = Some(built.structural);
            self.swap.retire(built.engine);
            on(SlotEvent::RestartWanted);
            return;
        }
        let old = std::mem::replace(&mut self.engine, built.engine);
        self.swap.retire(old);
        self.voice = built.voice;
        self.prepared = Some(built.structural);
        // Live settings that changed while it was built.
        self.apply_live_settings();
        on(SlotEvent::Swapped {
            latency,
            running: self.engine.is_some(),
            sample_rate_hz: stream.sample_rate_hz as f32,
        });
        self.reported_latency = latency;
    }

    /// Marks the structure stale when a structural parameter raised its flag or a breath
    /// sample path changed.
    fn notice_structure_changes(&mut self) {
        if ChangeFlags::take(&self.params.changes.structure) {
            self.structure_stale = true;
        }
        let generation = sample_generation(&self.params);
        if generation != self.seen_sample_generation {
            self.seen_sample_generation = generation;
            self.structure_stale = true;
        }
    }

    /// Asks the build thread for an engine when the structural settings are stale and differ
    /// from the running (or held-back) engine's; again after [`BUILD_RETRY_S`] unanswered.
    /// Whether it asked (now).
    fn ask_for_build(&mut self, block: usize, stream: StreamSpec) -> bool {
        let retry = (BUILD_RETRY_S * stream.sample_rate_hz) as u64;
        match self.build_pending_samples.as_mut() {
            Some(waited) if *waited < retry => *waited += block as u64,
            _ if !self.structure_stale => self.build_pending_samples = None,
            _ => {
                let wanted = Some(Structural::of(&self.params));
                if self.prepared != wanted && self.held != wanted {
                    // Stays stale: the built engine is compared again when it comes back, or
                    // the build is asked for again after the retry time.
                    if let Some(worker) = &self.worker {
                        self.build_pending_samples = Some(0);
                        worker.request();
                        return true;
                    }
                } else {
                    self.build_pending_samples = None;
                    self.structure_stale = false;
                }
            }
        }
        false
    }

    /// A build was asked for and has not come back yet (tests).
    #[cfg(test)]
    pub(crate) fn build_pending(&self) -> bool {
        self.build_pending_samples.is_some()
    }

    /// A built engine waits to be taken at the next block (tests).
    #[cfg(test)]
    pub(crate) fn built_waiting(&self) -> bool {
        self.swap.built.slots() > 0
    }
}

#[cfg(test)]
// nice-plug's `ParamPtr` setters are `unsafe`: the parameters outlive every call.
#[allow(unsafe_code)]
mod tests {
    use super::*;
    use crate::alloc_test::set_on as set;
    use nice_plug::prelude::Params;

    /// Every parameter, set to several values: where core says the engine config's stream part
    /// changed, the parameter raised the structure flag (the audio thread compares structural
    /// settings only then, so a change without it would keep an engine prepared for old
    /// settings).
    #[test]
    fn every_stream_change_core_knows_raises_the_structure_flag() {
        let mut checked_stream_changes = 0;
        for value in [0.0f32, 0.37, 1.0] {
            let reference = PneumaParams::default();
            let ids: Vec<String> = reference
                .param_map()
                .into_iter()
                .map(|(id, _, _)| id)
                .collect();
            for id in ids {
                let params = PneumaParams::default();
                ChangeFlags::take(&params.changes.structure);
                let before = params.engine_config();
                let ptr = params
                    .param_map()
                    .into_iter()
                    .find(|(pid, _, _)| *pid == id)
                    .map(|(_, ptr, _)| ptr)
                    .expect("the id is listed");
                // SAFETY: `params` outlives the call.
                unsafe { ptr._internal_set_normalized_value(value) };
                if before.stream_differs(&params.engine_config()) {
                    checked_stream_changes += 1;
                    assert!(
                        ChangeFlags::take(&params.changes.structure),
                        "{id} = {value} changes the engine's stream part without raising the \
                         structure flag"
                    );
                }
            }
        }
        assert!(
            checked_stream_changes >= 3,
            "mode, lookahead and frame rate change the stream part ({checked_stream_changes} \
             changes seen)"
        );
    }

    /// A slot activated in `mode` at 48 kHz, stereo, 512-sample blocks, as VST3 (latency
    /// reported from the audio thread), with one block followed (nothing to build yet).
    fn activated(mode: ProcessMode) -> (Arc<PneumaParams>, EngineSlot) {
        let params = Arc::new(PneumaParams::default());
        let mut slot = EngineSlot::new(params.clone(), Arc::default());
        let latency = slot.activate(48_000.0, 512, 2, false, mode);
        assert_eq!(latency, 24_000, "the default lookahead, 0.5 s");
        slot.follow(512, |e| panic!("nothing changed, yet {e:?}"));
        assert!(!slot.build_pending());
        (params, slot)
    }

    /// The latency of the engine swapped in by one `follow` (`None`: none was), run under the
    /// allocation guard (debug builds): waiting for a build must not allocate either.
    fn follow_once(slot: &mut EngineSlot) -> Option<u32> {
        let mut swapped = None;
        nice_assert_no_alloc::assert_no_alloc(|| {
            slot.follow(512, |event| match event {
                SlotEvent::Swapped { latency, .. } => swapped = Some(latency),
                SlotEvent::RestartWanted => panic!("VST3 reports latency from the audio thread"),
            });
        });
        swapped
    }

    #[test]
    fn offline_a_structural_change_takes_over_at_the_block_that_sees_it() {
        let (params, mut slot) = activated(ProcessMode::Offline);
        // Lookahead to 2 s (a new latency), then the frame rate (the same latency).
        set(&params, "lookahead_s", 1.0);
        assert_eq!(
            follow_once(&mut slot),
            Some(96_000),
            "swapped in by the same block"
        );
        assert!(!slot.build_pending() && !slot.built_waiting());
        set(&params, "frame_rate_hz", 0.0);
        assert_eq!(
            follow_once(&mut slot),
            Some(96_000),
            "swapped in by the same block"
        );
        assert_eq!(follow_once(&mut slot), None, "nothing more to build");
        assert!(!slot.build_pending());
    }

    #[test]
    fn in_real_time_a_structural_change_is_not_waited_for() {
        for mode in [ProcessMode::Realtime, ProcessMode::Buffered] {
            let (params, mut slot) = activated(mode);
            set(&params, "lookahead_s", 1.0);
            let start = Instant::now();
            // Waiting would have swapped the engine in here.
            assert_eq!(
                follow_once(&mut slot),
                None,
                "{mode:?}: asked for, not waited for"
            );
            assert!(slot.build_pending(), "{mode:?}");
            // The build arrives in the background and is taken at a later block.
            while !slot.built_waiting() {
                assert!(start.elapsed() < ACTIVATE_WAIT, "{mode:?}: no engine built");
                std::thread::sleep(Duration::from_millis(1));
            }
            assert_eq!(follow_once(&mut slot), Some(96_000), "{mode:?}");
        }
    }

    #[test]
    fn structural_settings_are_equal_unless_the_stream_part_or_a_sample_differs() {
        let params = PneumaParams::default();
        let a = Structural::of(&params);
        let mut b = a.clone();
        b.config.breathing.capacity_lung += 0.1; // live part
        assert_eq!(a, b);
        b.config.placement.lookahead_s += 0.1; // stream part
        assert_ne!(a, b);
        let mut c = a.clone();
        c.sample_generation += 1;
        assert_ne!(a, c);
    }
}
