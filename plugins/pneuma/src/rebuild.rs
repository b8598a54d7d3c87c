//! Settings that need a new engine (mode, lookahead, frame rate, breath-sample files) take
//! effect while the plugin stays active.
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
//!    plugin was activated for, and hands it over through a lock-free queue ([`Built`]).
//! 3. The audio thread ([`SwapEnds`]) takes it at the start of a block, swaps it in, reports its
//!    latency to the host (VST3: `restartComponent(kLatencyChanged)`; CLAP: a restart request,
//!    as the CLAP latency extension asks) and passes the old engine back to be dropped off the
//!    audio thread. Nothing on the audio thread allocates, frees, locks or blocks.
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
use std::time::Duration;

use nice_plug::nice_error;
use pneuma_core::breathing::SampleSlot;
use pneuma_core::engine::{Engine, EngineConfig, EngineError};
use pneuma_core::head::HeadModel;
use rtrb::{Consumer, Producer, RingBuffer};

use crate::load_breath_sample;
use crate::params::PneumaParams;

/// Largest block the engine is prepared for; longer host blocks are processed in pieces.
pub const MAX_ENGINE_BLOCK: usize = 8192;

/// Engines in flight between the builder and the audio thread, each way. One build runs at a
/// time per epoch; the slack covers builds of earlier epochs still finishing after re-activations.
const QUEUE_ENGINES: usize = 8;

/// What an engine is built from that needs a new engine (and maybe a new latency) when it
/// changes: the engine settings' stream part (core's
/// [`pneuma_core::engine::EngineConfig::stream_differs`] decides, the one list of those fields)
/// and the breath-sample files. Two are equal when neither differs. The audio thread compares
/// them only when a structural parameter raised its change flag, a build came back, or a
/// sample path changed (building an `EngineConfig` does not allocate).
#[derive(Debug, Clone)]
pub struct Structural {
    /// The engine settings (only their stream part counts).
    pub config: EngineConfig,
    /// Changes of the breath-sample paths (the files are read when an engine is built).
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

/// The breath-sample paths' change count (lock-free).
pub fn sample_generation(p: &PneumaParams) -> u64 {
    p.breath_sample_mouth.generation() + p.breath_sample_nose.generation()
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
    /// A builder for `params` and the audio thread's ends of its queues.
    pub fn new(params: Arc<PneumaParams>) -> (Arc<Self>, SwapEnds) {
        let (done, built) = RingBuffer::new(QUEUE_ENGINES);
        let (retire, retired) = RingBuffer::new(QUEUE_ENGINES);
        let builder = Arc::new(Self {
            params,
            stream: Mutex::new(None),
            done: Mutex::new(done),
            retired: Mutex::new(retired),
        });
        (builder, SwapEnds { built, retire })
    }

    /// An engine for the current parameters and breath samples, prepared for `stream`, with the
    /// structural settings it was built from. Allocates and reads files: not for the audio
    /// thread. A breath sample that cannot be used is logged and the procedural breath stays.
    pub fn build(&self, stream: &StreamSpec) -> (Result<Engine, EngineError>, Structural) {
        // Read before the settings: a change in between only causes one more build.
        let structural = Structural::of(&self.params);
        let engine = (|| {
            let mut engine = Engine::new(
                self.params.engine_config(),
                HeadModel::default_model().clone(),
            )?;
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
        (engine, structural)
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
        let (engine, structural) = self.build(stream);
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

#[cfg(test)]
// nice-plug's `ParamPtr` setters are `unsafe`: the parameters outlive every call.
#[allow(unsafe_code)]
mod tests {
    use super::*;
    use crate::params::ChangeFlags;
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
