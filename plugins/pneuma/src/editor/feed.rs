//! The editor's data path: from the audio thread to the GUI without locks, waits or allocations
//! on the audio side.
//!
//! - [`ViewFrame`]: one small `Copy` record per control frame (the engine's [`ControlFrame`] and
//!   the input's peak since the frame before), and [`ViewBreath`]s for inserted breaths and for
//!   breaths already in the input, each through its own preallocated single-producer
//!   single-consumer `rtrb` ring.
//! - [`OutputStatus`]: counters and flags the audio thread stores with relaxed atomics once a
//!   block (OSC bundles sent, failed, dropped; CC messages the host lost; engine running; latency;
//!   what the breath voice does).
//! - The audio side ([`EditorFeed`]) pushes only while the editor is open
//!   ([`EditorShared::is_open`]: the egui window's own flag, or [`EditorShared::open`]; without
//!   the `editor` feature there is no window and only the latter);
//!   a full ring drops the newest record and counts it (the GUI was not drawing), never waits.
//! - The GUI side ([`EditorShared::drain`]) takes the consumers behind a mutex that only GUI
//!   threads touch; the audio side never sees it.

use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, AtomicU8, Ordering};
#[cfg(feature = "editor")]
use std::sync::OnceLock;
use std::sync::{Arc, Mutex};

#[cfg(feature = "editor")]
use nice_plug_egui::EguiEditorState;

use pneuma_core::encode::sink::FrameSink;
use pneuma_core::{BreathEvent, ControlFrame};

use pneuma_osc::worker::OscStats;

/// Ring capacity in frames: about 8.5 s at 120 Hz, so a GUI that skips a few repaints loses
/// nothing.
pub const FRAME_RING: usize = 1024;
/// Ring capacity in breaths (inserted and already there).
pub const BREATH_RING: usize = 64;

/// A breath on the timeline: one Pneuma inserted, or one the speaker took (heard in a pause of
/// the input, where nothing was inserted).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewBreath {
    /// Start, seconds of stream time.
    pub start_s: f64,
    /// End, seconds.
    pub end_s: f64,
    /// Already in the input (true) or inserted.
    pub existing: bool,
}

/// What the editor draws for one control frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ViewFrame {
    /// The engine's frame (time, f0, gates, breathing, head).
    pub control: ControlFrame,
    /// Largest |sample| of the input (first channel, before the engine) since the frame before.
    pub input_peak: f32,
}

/// Output counters and flags, written by the audio thread once a block (relaxed atomics).
#[derive(Debug, Default)]
pub struct OutputStatus {
    /// OSC bundles handed to the OS.
    pub osc_sent: AtomicU64,
    /// OSC frames not sent (unresolvable target, send error).
    pub osc_failed: AtomicU64,
    /// OSC frames dropped (queue full or stale).
    pub osc_dropped: AtomicU64,
    /// Why the last OSC frame failed ([`pneuma_osc::OscError`] code; 0: none).
    pub osc_last_error: AtomicU8,
    /// MIDI CC messages the host's event buffer refused.
    pub cc_lost: AtomicU64,
    /// View records dropped because the GUI did not read them in time.
    pub view_dropped: AtomicU64,
    /// The engine runs (false: the host's sample rate is one the analysis does not take).
    pub engine_running: AtomicBool,
    /// The latency reported at activation, samples.
    pub latency_samples: AtomicU32,
    /// The host's sample rate, Hz (rounded).
    pub sample_rate_hz: AtomicU32,
    /// What the breath voice does ([`crate::voice::VoiceShown`], stored once a block).
    pub breath_voice: AtomicU64,
}

/// The GUI's end, shared by the plugin and its editor (created once with the plugin).
#[derive(Debug)]
pub struct EditorShared {
    /// Forces the feed on without a window (tests, measurements).
    pub open: AtomicBool,
    /// The egui editor's state, once an editor was created: its open flag is read lock-free.
    #[cfg(feature = "editor")]
    pub window: OnceLock<Arc<EguiEditorState>>,
    /// Output counters and flags.
    pub status: OutputStatus,
    consumers: Mutex<Option<Consumers>>,
}

#[derive(Debug)]
struct Consumers {
    frames: rtrb::Consumer<ViewFrame>,
    breaths: rtrb::Consumer<ViewBreath>,
}

/// The audio thread's end. Owned by the plugin; every method is wait-free and allocation-free.
#[derive(Debug)]
pub struct EditorFeed {
    shared: Arc<EditorShared>,
    frames: rtrb::Producer<ViewFrame>,
    breaths: rtrb::Producer<ViewBreath>,
    /// Input peak since the last frame.
    pending_peak: f32,
    /// The editor was open at the start of this block.
    active: bool,
}

/// Creates the two ends. Allocates: call it off the audio thread (plugin construction).
pub fn channel() -> (EditorFeed, Arc<EditorShared>) {
    let (frames, frame_rx) = rtrb::RingBuffer::new(FRAME_RING);
    let (breaths, breath_rx) = rtrb::RingBuffer::new(BREATH_RING);
    let shared = Arc::new(EditorShared {
        open: AtomicBool::new(false),
        #[cfg(feature = "editor")]
        window: OnceLock::new(),
        status: OutputStatus::default(),
        consumers: Mutex::new(Some(Consumers {
            frames: frame_rx,
            breaths: breath_rx,
        })),
    });
    (
        EditorFeed {
            shared: shared.clone(),
            frames,
            breaths,
            pending_peak: 0.0,
            active: false,
        },
        shared,
    )
}

impl EditorFeed {
    /// Starts a block: notes whether the editor is open and the peak of the input's first
    /// channel (read before the engine changes the samples in place).
    pub fn begin_block(&mut self, audio: &[&mut [f32]]) {
        self.active = self.shared.is_open();
        if !self.active {
            self.pending_peak = 0.0;
            return;
        }
        if let Some(first) = audio.first() {
            let peak = first
                .iter()
                .filter(|s| s.is_finite())
                .fold(0.0f32, |m, s| m.max(s.abs()));
            self.pending_peak = self.pending_peak.max(peak);
        }
    }

    /// Hands a control frame to the GUI (with the input peak since the frame before).
    pub fn push_frame(&mut self, frame: &ControlFrame) {
        if !self.active {
            return;
        }
        let view = ViewFrame {
            control: *frame,
            input_peak: self.pending_peak,
        };
        self.pending_peak = 0.0;
        if self.frames.push(view).is_err() {
            self.shared
                .status
                .view_dropped
                .fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Hands an inserted breath to the GUI.
    pub fn push_breath(&mut self, breath: &BreathEvent) {
        self.push_view_breath(ViewBreath {
            start_s: breath.start_s,
            end_s: breath.end_s,
            existing: false,
        });
    }

    /// Hands a breath already in the input (start and end, seconds) to the GUI.
    pub fn push_existing_breath(&mut self, start_s: f64, end_s: f64) {
        self.push_view_breath(ViewBreath {
            start_s,
            end_s,
            existing: true,
        });
    }

    fn push_view_breath(&mut self, breath: ViewBreath) {
        if self.active && self.breaths.push(breath).is_err() {
            self.shared
                .status
                .view_dropped
                .fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Ends a block: copies the OSC counters (when the sender runs) and counts a lost CC
    /// message. Relaxed atomic stores only.
    pub fn end_block(&mut self, osc: Option<&OscStats>, cc_lost: bool) {
        let status = &self.shared.status;
        if let Some(osc) = osc {
            let load = |a: &AtomicU64| a.load(Ordering::Relaxed);
            status.osc_sent.store(load(&osc.sent), Ordering::Relaxed);
            status
                .osc_failed
                .store(load(&osc.failed), Ordering::Relaxed);
            status
                .osc_last_error
                .store(osc.last_error.load(Ordering::Relaxed), Ordering::Relaxed);
            status.osc_dropped.store(
                load(&osc.dropped_full) + load(&osc.dropped_stale),
                Ordering::Relaxed,
            );
        }
        if cc_lost {
            status.cc_lost.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Records an activation: whether the engine runs, its latency and the sample rate.
    pub fn activated(&mut self, engine_running: bool, latency_samples: u32, sample_rate_hz: f32) {
        let status = &self.shared.status;
        status
            .engine_running
            .store(engine_running, Ordering::Relaxed);
        status
            .latency_samples
            .store(latency_samples, Ordering::Relaxed);
        status
            .sample_rate_hz
            .store(sample_rate_hz.round() as u32, Ordering::Relaxed);
        self.pending_peak = 0.0;
    }

    /// The shared status the audio side writes (relaxed atomics).
    pub fn status(&self) -> &OutputStatus {
        &self.shared.status
    }
}

/// The editor as one of the engine's sinks: frames, inserted breaths and breaths heard in the
/// input go to the GUI's queues.
impl FrameSink for EditorFeed {
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        self.push_frame(frame);
    }
    fn breath(&mut self, breath: &BreathEvent) {
        self.push_breath(breath);
    }
    fn existing_breath(&mut self, start_s: f64, end_s: f64) {
        self.push_existing_breath(start_s, end_s);
    }
}

impl EditorShared {
    /// The editor window is open (or the feed is forced on). Lock-free.
    pub fn is_open(&self) -> bool {
        #[cfg(feature = "editor")]
        if self.window.get().is_some_and(|w| w.is_open()) {
            return true;
        }
        self.open.load(Ordering::Relaxed)
    }

    /// GUI side: hands every waiting frame and breath to the callbacks, oldest first. Returns
    /// false when another GUI thread is draining at the same moment (nothing lost: the records
    /// wait for the next call).
    pub fn drain(
        &self,
        mut on_frame: impl FnMut(&ViewFrame),
        mut on_breath: impl FnMut(&ViewBreath),
    ) -> bool {
        let Ok(mut guard) = self.consumers.try_lock() else {
            return false;
        };
        let Some(c) = guard.as_mut() else {
            return false;
        };
        while let Ok(f) = c.frames.pop() {
            on_frame(&f);
        }
        while let Ok(b) = c.breaths.pop() {
            on_breath(&b);
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::BreathKind;

    fn frame(index: u64) -> ControlFrame {
        ControlFrame {
            index,
            time_s: index as f64 / 120.0,
            f0_hz: 100.0 + index as f32,
            voiced: index.is_multiple_of(2),
            ..ControlFrame::default()
        }
    }

    /// The audio side runs on its own thread under the allocation guard while the GUI side holds
    /// its consumer lock the whole time: pushing neither allocates nor waits for that lock, and
    /// the GUI reads every frame in order afterwards.
    #[test]
    fn audio_side_pushes_without_allocating_or_locking_and_the_gui_reads_everything() {
        let (mut feed, shared) = channel();
        shared.open.store(true, Ordering::Relaxed);
        let gui_lock = shared.consumers.lock().unwrap();
        let audio = std::thread::spawn(move || {
            let mut left = [0.0f32; 64];
            left[7] = -0.5;
            let mut right = [0.25f32; 64];
            nice_assert_no_alloc::assert_no_alloc(|| {
                for i in 0..200u64 {
                    feed.begin_block(&[&mut left[..], &mut right[..]]);
                    feed.push_frame(&frame(i));
                    if i == 120 {
                        feed.push_existing_breath(0.9, 1.25);
                    }
                    if i.is_multiple_of(50) {
                        feed.push_breath(&BreathEvent {
                            start_s: i as f64 / 120.0,
                            end_s: i as f64 / 120.0 + 0.3,
                            kind: BreathKind::Nose,
                            peak_db: -30.0,
                        });
                    }
                    feed.status().osc_sent.fetch_add(1, Ordering::Relaxed);
                }
            });
            feed
        });
        // The audio thread must finish while the GUI holds its lock.
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(20);
        while !audio.is_finished() {
            assert!(
                std::time::Instant::now() < deadline,
                "the audio side waited for the GUI's lock"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        drop(gui_lock);
        let _feed = audio.join().expect("no allocation on the audio side");
        let (mut frames, mut breaths) = (Vec::new(), Vec::new());
        assert!(shared.drain(|f| frames.push(*f), |b| breaths.push(*b)));
        assert_eq!(frames.len(), 200);
        assert!(frames
            .iter()
            .enumerate()
            .all(|(i, f)| f.control == frame(i as u64)));
        assert_eq!(frames[0].input_peak, 0.5, "first channel's peak");
        assert_eq!(breaths.len(), 5, "four inserted and one already there");
        assert_eq!(
            breaths[3],
            ViewBreath {
                start_s: 0.9,
                end_s: 1.25,
                existing: true
            }
        );
        assert!(!breaths[4].existing);
        assert_eq!(breaths[4].start_s, 150.0 / 120.0);
        assert_eq!(shared.status.osc_sent.load(Ordering::Relaxed), 200);
        assert_eq!(shared.status.view_dropped.load(Ordering::Relaxed), 0);
    }

    #[test]
    fn the_osc_counters_and_last_error_reach_the_status() {
        let (mut feed, shared) = channel();
        let osc = OscStats::default();
        osc.sent.store(7, Ordering::Relaxed);
        osc.failed.store(3, Ordering::Relaxed);
        osc.last_error
            .store(pneuma_osc::OscError::Refused as u8, Ordering::Relaxed);
        feed.end_block(Some(&osc), false);
        let status = &shared.status;
        assert_eq!(status.osc_sent.load(Ordering::Relaxed), 7);
        assert_eq!(status.osc_failed.load(Ordering::Relaxed), 3);
        let error = pneuma_osc::OscError::from_code(status.osc_last_error.load(Ordering::Relaxed));
        assert_eq!(error, Some(pneuma_osc::OscError::Refused));
    }

    #[test]
    fn closed_editor_gets_nothing_and_a_full_ring_drops_and_counts() {
        let (mut feed, shared) = channel();
        feed.begin_block(&[]);
        feed.push_frame(&frame(0));
        assert!(shared.drain(|_| panic!("editor closed"), |_| panic!("editor closed")));
        shared.open.store(true, Ordering::Relaxed);
        feed.begin_block(&[]);
        for i in 0..(FRAME_RING as u64 + 10) {
            feed.push_frame(&frame(i));
        }
        assert_eq!(shared.status.view_dropped.load(Ordering::Relaxed), 10);
        let mut last = None;
        shared.drain(|f| last = Some(f.control.index), |_| {});
        assert_eq!(
            last,
            Some(FRAME_RING as u64 - 1),
            "the oldest frames are kept"
        );
    }
}
