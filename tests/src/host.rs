//! A minimal CLAP host for tests, on `clack-host` 0.2 and `clack-extensions` 0.2.
//!
//! It loads a `.clap` bundle, instantiates the plugin with a given CLAP id, sets parameters by
//! their nice-plug string id (hashed as nice-plug does) and a value text (so the plugin converts
//! plain values itself), activates at a sample rate and maximum block size, processes blocks of
//! any size (all on the test thread, but its thread-check extension answers "audio thread" inside
//! `process`, so the plugin's main-thread tasks wait for [`Plugin::run_main_thread_callback`] as
//! they would in a host with an audio thread), collects the
//! plugin's MIDI CC output with sample offsets, reads the latency and saves/loads state.

use std::ffi::CString;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use clack_extensions::audio_ports_config::PluginAudioPortsConfig;
use clack_extensions::latency::{HostLatency, HostLatencyImpl, PluginLatency};
use clack_extensions::params::{ParamInfoBuffer, PluginParams};
use clack_extensions::state::PluginState;
use clack_extensions::thread_check::{HostThreadCheck, HostThreadCheckImpl};
use clack_host::events::event_types::{MidiEvent, ParamValueEvent, TransportEvent, TransportFlags};
use clack_host::events::io::{EventBuffer, InputEvents, OutputEvents};
use clack_host::events::{EventFlags, EventHeader, Pckn};
use clack_host::prelude::*;
use clack_host::utils::{BeatTime, SecondsTime};

/// One MIDI CC message from the plugin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CcEvent {
    /// Absolute sample position from the start of processing (block start + offset).
    pub sample: u64,
    /// Offset inside its block.
    pub offset: u32,
    /// MIDI channel 0..15.
    pub channel: u8,
    /// Controller number.
    pub controller: u8,
    /// Value 0..127.
    pub value: u8,
}

/// Host callbacks shared with the plugin.
pub struct Shared {
    restart_requested: AtomicBool,
    /// The plugin asked for its main-thread callback.
    callback_requested: AtomicBool,
    /// Inside `process`: the thread-check extension then answers "audio thread", as a host with
    /// a separate audio thread would, so the plugin defers main-thread work to the callback.
    processing: AtomicBool,
}

impl<'a> SharedHandler<'a> for Shared {
    fn request_restart(&self) {
        self.restart_requested.store(true, Ordering::SeqCst);
    }
    fn request_process(&self) {}
    fn request_callback(&self) {
        self.callback_requested.store(true, Ordering::SeqCst);
    }
}

impl HostThreadCheckImpl for Shared {
    fn is_main_thread(&self) -> bool {
        !self.processing.load(Ordering::SeqCst)
    }
    fn is_audio_thread(&self) -> bool {
        self.processing.load(Ordering::SeqCst)
    }
}

/// Host callbacks on the main thread.
#[derive(Default)]
pub struct MainThread {
    /// How many times the plugin called the latency extension's `changed`.
    latency_changed: std::cell::Cell<u32>,
    /// Calls of `changed` outside `clap_plugin::activate` (the CLAP latency extension allows
    /// it only there; clap-validator fails a plugin for it).
    latency_changed_outside_activate: std::cell::Cell<u32>,
    /// The host is inside `clap_plugin::activate`.
    activating: std::cell::Cell<bool>,
}

impl MainThreadHandler<'_> for MainThread {}

impl HostLatencyImpl for MainThread {
    fn changed(&self) {
        self.latency_changed.set(self.latency_changed.get() + 1);
        if !self.activating.get() {
            let outside = &self.latency_changed_outside_activate;
            outside.set(outside.get() + 1);
        }
    }
}

/// The host type.
pub struct TestHost;

impl HostHandlers for TestHost {
    type Shared<'a> = Shared;
    type MainThread<'a> = MainThread;
    type AudioProcessor<'a> = ();

    fn declare_extensions(builder: &mut HostExtensions<Self>, _shared: &Self::Shared<'_>) {
        builder.register::<HostLatency>();
        builder.register::<HostThreadCheck>();
    }
}

/// nice-plug's CLAP/VST3 parameter id for a string id (`nice_plug::wrapper::util::hash_param_id`).
pub fn param_hash(id: &str) -> u32 {
    let mut hash: u32 = 0;
    for b in id.bytes() {
        hash = hash.wrapping_mul(31).wrapping_add(u32::from(b));
    }
    hash & !(1 << 31)
}

/// A loaded plugin instance.
pub struct Plugin {
    instance: PluginInstance<TestHost>,
    processor: Option<StartedPluginAudioProcessor<TestHost>>,
    channels: usize,
    max_block: usize,
    pending: EventBuffer,
    output_events: EventBuffer,
    samples_done: u64,
}

/// A parameter as the host sees it.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamDesc {
    /// CLAP id.
    pub id: u32,
    /// Display name.
    pub name: String,
    /// CLAP minimum value.
    pub min: f64,
    /// CLAP maximum value.
    pub max: f64,
    /// CLAP default value.
    pub default: f64,
    /// The module (folder) the plugin files it under; empty at the top.
    pub module: String,
}

impl Plugin {
    /// Loads `clap_id` from the bundle at `path` (not activated).
    // Loading a dynamic library runs its initialisers, hence `unsafe` in clack-host; this host only
    // loads the bundle this workspace built.
    #[allow(unsafe_code)]
    pub fn load(path: &Path, clap_id: &str) -> Result<Plugin, String> {
        // SAFETY: the bundle is the one built from this workspace (nice-plug's CLAP entry).
        let entry = unsafe { PluginEntry::load(path) }
            .map_err(|e| format!("cannot load {}: {e:?}", path.display()))?;
        let host_info = HostInfo::new("pneuma-tests", "Pneuma", "https://example.invalid", "0.1")
            .map_err(|e| format!("{e:?}"))?;
        let id = CString::new(clap_id).map_err(|e| e.to_string())?;
        let instance = PluginInstance::<TestHost>::new(
            |_| Shared {
                restart_requested: AtomicBool::new(false),
                callback_requested: AtomicBool::new(false),
                processing: AtomicBool::new(false),
            },
            |_| MainThread::default(),
            &entry,
            &id,
            &host_info,
        )
        .map_err(|e| format!("cannot instantiate {clap_id}: {e:?}"))?;
        Ok(Plugin {
            instance,
            processor: None,
            channels: 0,
            max_block: 0,
            pending: EventBuffer::new(),
            output_events: EventBuffer::new(),
            samples_done: 0,
        })
    }

    fn params_ext(&mut self) -> PluginParams {
        self.instance
            .plugin_shared_handle()
            .get_extension::<PluginParams>()
            .expect("the plugin has the params extension")
    }

    /// Every parameter: CLAP id, name, range, default.
    pub fn params(&mut self) -> Vec<ParamDesc> {
        let ext = self.params_ext();
        let handle = self.instance.plugin_handle();
        let mut out = Vec::new();
        for i in 0..ext.count(&handle) {
            let mut buf = ParamInfoBuffer::new();
            if let Some(info) = ext.get_info(&handle, i, &mut buf) {
                out.push(ParamDesc {
                    id: info.id.get(),
                    name: String::from_utf8_lossy(info.name).into_owned(),
                    min: info.min_value,
                    max: info.max_value,
                    default: info.default_value,
                    module: String::from_utf8_lossy(info.module).into_owned(),
                });
            }
        }
        out
    }

    /// The CLAP value of parameter `id` (nice-plug string id).
    pub fn param_value(&mut self, id: &str) -> Option<f64> {
        let ext = self.params_ext();
        let handle = self.instance.plugin_handle();
        ext.get_value(&handle, ClapId::new(param_hash(id)))
    }

    /// Sets parameter `id` (nice-plug string id) from a value text the plugin parses (e.g.
    /// `"48"`, `"VMC"`, `"On"`). Applied now when inactive, or at the start of the next block.
    pub fn set_param(&mut self, id: &str, text: &str) -> Result<(), String> {
        let ext = self.params_ext();
        let clap_id = ClapId::new(param_hash(id));
        let ctext = CString::new(text).map_err(|e| e.to_string())?;
        let value = {
            let handle = self.instance.plugin_handle();
            ext.text_to_value(&handle, clap_id, &ctext)
                .ok_or_else(|| format!("the plugin cannot parse {text:?} for {id}"))?
        };
        let event = ParamValueEvent::new(0, clap_id, Pckn::match_all(), value);
        if self.processor.is_some() {
            self.pending.push(&event);
        } else {
            let mut events = EventBuffer::new();
            events.push(&event);
            let mut out = EventBuffer::new();
            let mut handle = self
                .instance
                .inactive_plugin_handle()
                .ok_or("the plugin is neither active nor inactive")?;
            ext.flush(
                &mut handle,
                &InputEvents::from_buffer(&events),
                &mut OutputEvents::from_buffer(&mut out),
            );
        }
        Ok(())
    }

    /// Activates for `channels` channels (1 or 2) at `sample_rate` Hz with blocks of at most
    /// `max_block`. The plugin's audio-ports configuration is selected first: Pneuma's
    /// configuration ids follow its layouts, 0 = stereo, 1 = mono.
    pub fn activate(
        &mut self,
        sample_rate: f64,
        max_block: usize,
        channels: usize,
    ) -> Result<(), String> {
        self.deactivate();
        let config_id = match channels {
            2 => 0,
            1 => 1,
            n => return Err(format!("{n} channels: Pneuma is mono or stereo")),
        };
        let ports = self
            .instance
            .plugin_shared_handle()
            .get_extension::<PluginAudioPortsConfig>()
            .ok_or("the plugin has no audio-ports-config extension")?;
        let handle = self.instance.plugin_handle();
        ports
            .select(&handle, ClapId::new(config_id))
            .map_err(|e| format!("selecting the {channels}-channel layout failed: {e:?}"))?;
        let config = PluginAudioConfiguration {
            sample_rate,
            min_frames_count: 1,
            max_frames_count: max_block as u32,
        };
        self.instance.access_handler(|m| m.activating.set(true));
        let stopped = self.instance.activate(|_, _| (), config);
        self.instance.access_handler(|m| m.activating.set(false));
        let stopped =
            stopped.map_err(|e| format!("activation at {sample_rate} Hz failed: {e:?}"))?;
        let started = stopped
            .start_processing()
            .map_err(|e| format!("start_processing failed: {e:?}"))?;
        self.processor = Some(started);
        self.channels = channels;
        self.max_block = max_block;
        self.samples_done = 0;
        self.instance
            .access_shared_handler(|s| s.restart_requested.store(false, Ordering::SeqCst));
        Ok(())
    }

    /// Stops and deactivates (no-op when inactive).
    pub fn deactivate(&mut self) {
        if let Some(p) = self.processor.take() {
            let stopped = p.stop_processing();
            self.instance.deactivate(stopped);
        }
    }

    /// Whether the plugin asked for a restart since the last activation.
    pub fn restart_requested(&self) -> bool {
        self.instance
            .access_shared_handler(|s| s.restart_requested.load(Ordering::SeqCst))
    }

    /// How many times the plugin told the host (latency extension) that its latency changed.
    pub fn latency_changes(&self) -> u32 {
        self.instance.access_handler(|m| m.latency_changed.get())
    }

    /// How many of those calls came outside `clap_plugin::activate` (a CLAP rule violation).
    pub fn latency_changes_outside_activate(&self) -> u32 {
        self.instance
            .access_handler(|m| m.latency_changed_outside_activate.get())
    }

    /// Runs the plugin's main-thread callback, as a host does after `request_callback` (the
    /// plugin's queued main-thread tasks run there).
    pub fn run_main_thread_callback(&mut self) {
        self.instance
            .access_shared_handler(|s| s.callback_requested.store(false, Ordering::SeqCst));
        self.instance.call_on_main_thread_callback();
    }

    /// Whether the plugin asked for its main-thread callback since it last ran.
    pub fn callback_requested(&self) -> bool {
        self.instance
            .access_shared_handler(|s| s.callback_requested.load(Ordering::SeqCst))
    }

    /// The latency the plugin reports, samples.
    pub fn latency(&mut self) -> u32 {
        let ext = self
            .instance
            .plugin_shared_handle()
            .get_extension::<PluginLatency>()
            .expect("the plugin has the latency extension");
        let handle = self.instance.plugin_handle();
        ext.get(&handle)
    }

    /// Replaces `from` by `to` inside a saved state (nice-plug's CLAP state is a little-endian u64
    /// length followed by JSON), fixing the length.
    pub fn edit_state(state: &[u8], from: &str, to: &str) -> Vec<u8> {
        let json = std::str::from_utf8(&state[8..]).expect("the state after the length is JSON");
        let edited = json.replace(from, to);
        let mut out = (edited.len() as u64).to_le_bytes().to_vec();
        out.extend_from_slice(edited.as_bytes());
        out
    }

    /// The JSON part of a saved state.
    pub fn state_json(state: &[u8]) -> &str {
        std::str::from_utf8(&state[8..]).expect("the state after the length is JSON")
    }

    /// Saves the state.
    pub fn save_state(&mut self) -> Vec<u8> {
        let ext = self
            .instance
            .plugin_shared_handle()
            .get_extension::<PluginState>()
            .expect("the plugin has the state extension");
        let mut out = Vec::new();
        let handle = self.instance.plugin_handle();
        ext.save(&handle, &mut out).expect("state saves");
        out
    }

    /// Loads a state.
    pub fn load_state(&mut self, state: &[u8]) -> Result<(), String> {
        let ext = self
            .instance
            .plugin_shared_handle()
            .get_extension::<PluginState>()
            .expect("the plugin has the state extension");
        let handle = self.instance.plugin_handle();
        ext.load(&handle, &mut &state[..])
            .map_err(|e| format!("state load failed: {e:?}"))
    }

    /// Processes one block in place (`audio[channel][sample]`, every channel the same length, at
    /// most the activation's maximum) without transport information; returns the CC messages
    /// the plugin sent in it.
    pub fn process(&mut self, audio: &mut [Vec<f32>]) -> Vec<CcEvent> {
        self.process_at(audio, None)
    }

    /// As [`Plugin::process`], with a playing transport at `pos_s` seconds (the song position of
    /// the block's first sample) when given.
    pub fn process_at(&mut self, audio: &mut [Vec<f32>], pos_s: Option<f64>) -> Vec<CcEvent> {
        let transport = pos_s.map(|pos| TransportEvent {
            header: EventHeader::new_core(0, EventFlags::empty()),
            flags: TransportFlags::HAS_SECONDS_TIMELINE | TransportFlags::IS_PLAYING,
            song_pos_beats: BeatTime::from_float(0.0),
            song_pos_seconds: SecondsTime::from_float(pos),
            tempo: 120.0,
            tempo_inc: 0.0,
            loop_start_beats: BeatTime::from_float(0.0),
            loop_end_beats: BeatTime::from_float(0.0),
            loop_start_seconds: SecondsTime::from_float(0.0),
            loop_end_seconds: SecondsTime::from_float(0.0),
            bar_start: BeatTime::from_float(0.0),
            bar_number: 0,
            time_signature_numerator: 4,
            time_signature_denominator: 4,
        });
        assert_eq!(
            audio.len(),
            self.channels,
            "channel count of the activation"
        );
        let n = audio[0].len();
        assert!(
            n <= self.max_block,
            "block of {n} over the maximum {}",
            self.max_block
        );
        let mut input: Vec<Vec<f32>> = audio.to_vec();
        let processor = self.processor.as_mut().expect("activated");
        let mut in_ports = AudioPorts::with_capacity(self.channels, 1);
        let mut out_ports = AudioPorts::with_capacity(self.channels, 1);
        let input_audio = in_ports.with_input_buffers([AudioPortBuffer {
            latency: 0,
            channels: AudioPortBufferType::f32_input_only(
                input
                    .iter_mut()
                    .map(|b| InputChannel::variable(b.as_mut_slice())),
            ),
        }]);
        let mut output_audio = out_ports.with_output_buffers([AudioPortBuffer {
            latency: 0,
            channels: AudioPortBufferType::f32_output_only(
                audio.iter_mut().map(|b| b.as_mut_slice()),
            ),
        }]);
        self.output_events.clear();
        self.instance
            .access_shared_handler(|s| s.processing.store(true, Ordering::SeqCst));
        let processed = processor.process(
            &input_audio,
            &mut output_audio,
            &InputEvents::from_buffer(&self.pending),
            &mut OutputEvents::from_buffer(&mut self.output_events),
            Some(self.samples_done),
            transport.as_ref(),
        );
        self.instance
            .access_shared_handler(|s| s.processing.store(false, Ordering::SeqCst));
        processed.expect("process succeeds");
        self.pending.clear();
        let start = self.samples_done;
        self.samples_done += n as u64;
        self.output_events
            .iter()
            .filter_map(|e| e.as_event::<MidiEvent>())
            .filter(|m| m.data()[0] & 0xF0 == 0xB0)
            .map(|m| {
                let [status, controller, value] = m.data();
                let offset = m.header().time();
                CcEvent {
                    sample: start + u64::from(offset),
                    offset,
                    channel: status & 0x0F,
                    controller,
                    value,
                }
            })
            .collect()
    }
}

impl Drop for Plugin {
    fn drop(&mut self) {
        self.deactivate();
    }
}
