//! Test-only: the real [`Plugin::process`] never allocates after [`Plugin::activate`]. A test
//! host context (transport, CC events into a preallocated list) drives the plugin; `process` runs
//! under nice-plug's allocation guard (`assert_no_alloc`, the global allocator
//! `assert_process_allocs` installs in debug builds), which aborts the test binary on any
//! allocation inside the guarded closure. Parameter changes between blocks go through the same
//! change flags a host's automation raises.
//!
//! A guard that is not there (a release build, where nice-plug disables it; a feature dropped)
//! would let every allocation pass silently, so the test first proves it is active: this test
//! binary runs [`the_guard_catches_an_allocation`] again in a child process with [`PROBE_ENV`]
//! set, where it allocates under the guard, and the child must die of it.

// nice-plug's `Buffer::set_slices` and `ParamPtr` setters are `unsafe`: the slices and parameters
// outlive every call here.
#![allow(unsafe_code)]

use std::num::NonZeroU32;
use std::sync::OnceLock;

use nice_plug::context::process::SendEventError;
use nice_plug::prelude::*;

use crate::Pneuma;

/// What the host context saw: CC events (preallocated), latency changes and restart requests.
pub(crate) struct Host {
    api: PluginApi,
    pub(crate) transport: Transport,
    cc_events: Vec<(u32, u8)>,
    latency: std::cell::Cell<Option<u32>>,
    restart_requests: std::cell::Cell<u32>,
}

impl Host {
    /// A host for `api` at `rate_hz`, the transport playing.
    pub(crate) fn playing(api: PluginApi, rate_hz: f32) -> Self {
        let mut transport = Transport::new(rate_hz);
        transport.playing = true;
        Self {
            api,
            transport,
            cc_events: Vec::with_capacity(1 << 16),
            latency: None.into(),
            restart_requests: 0.into(),
        }
    }
}

impl ProcessContext<Pneuma> for Host {
    fn plugin_api(&self) -> PluginApi {
        self.api
    }
    fn execute_background(&self, _task: ()) {}
    fn execute_gui(&self, _task: ()) {}
    fn transport(&self) -> &Transport {
        &self.transport
    }
    fn next_event(&mut self) -> Option<PluginNoteEvent<Pneuma>> {
        None
    }
    fn try_send_event(
        &mut self,
        event: PluginNoteEvent<Pneuma>,
    ) -> Result<(), (PluginNoteEvent<Pneuma>, SendEventError)> {
        if self.cc_events.len() == self.cc_events.capacity() {
            return Err((event, SendEventError::HostBufferFull));
        }
        if let NoteEvent::MidiCC { timing, cc, .. } = event {
            self.cc_events.push((timing, cc));
        }
        Ok(())
    }
    fn set_latency_samples(&self, samples: u32) {
        self.latency.set(Some(samples));
    }
    fn request_restart(&self) {
        self.restart_requests.set(self.restart_requests.get() + 1);
    }
    fn set_current_voice_capacity(&self, _capacity: u32) {}
}

pub(crate) struct Activation {
    pub(crate) api: PluginApi,
    pub(crate) latency: std::cell::Cell<u32>,
}

impl ActivateContext<Pneuma> for Activation {
    fn plugin_api(&self) -> PluginApi {
        self.api
    }
    fn execute(&self, _task: ()) {}
    fn set_latency_samples(&self, samples: u32) {
        self.latency.set(samples);
    }
    fn set_current_voice_capacity(&self, _capacity: u32) {}
}

/// Set in the child process: [`the_guard_catches_an_allocation`] allocates under the guard.
const PROBE_ENV: &str = "PNEUMA_ALLOC_GUARD_PROBE";

/// The probe's full test name (the child runs exactly it).
const PROBE_TEST: &str = "alloc_test::the_guard_catches_an_allocation";

/// Runs the probe in a child process once per test binary; `Err` says why the guard did not
/// catch its allocation.
pub(crate) fn guard_catches_allocations() -> Result<(), String> {
    static VERDICT: OnceLock<Result<(), String>> = OnceLock::new();
    VERDICT
        .get_or_init(|| {
            let exe = std::env::current_exe().map_err(|e| e.to_string())?;
            let out = std::process::Command::new(exe)
                .args([PROBE_TEST, "--exact", "--nocapture", "--test-threads=1"])
                .env(PROBE_ENV, "1")
                .output()
                .map_err(|e| format!("cannot run the probe: {e}"))?;
            let stdout = String::from_utf8_lossy(&out.stdout);
            let stderr = String::from_utf8_lossy(&out.stderr);
            if !stdout.contains("running 1 test") {
                return Err(format!("the probe did not run: {stdout}{stderr}"));
            }
            if out.status.success() || stdout.contains("PROBE SURVIVED") {
                return Err(format!(
                    "an allocation under nice-plug's guard went unnoticed (a release build, or \
                     `assert_process_allocs` off?): {stdout}{stderr}"
                ));
            }
            if !stderr.contains("memory allocation of 64 bytes failed") {
                return Err(format!(
                    "the probe failed, but not on its allocation: {stderr}"
                ));
            }
            Ok(())
        })
        .clone()
}

/// In the parent: the child running this test with [`PROBE_ENV`] set dies of its allocation.
/// In that child: allocates under the guard, which must abort the process before it returns.
#[test]
fn the_guard_catches_an_allocation() {
    if std::env::var_os(PROBE_ENV).is_some() {
        nice_assert_no_alloc::assert_no_alloc(|| {
            std::hint::black_box(vec![0u8; 64]);
        });
        println!("PROBE SURVIVED: the allocation guard let an allocation pass");
        return;
    }
    if let Err(e) = guard_catches_allocations() {
        panic!("{e}");
    }
}

pub(crate) fn set(plugin: &Pneuma, id: &str, normalized: f32) {
    set_on(&plugin.params, id, normalized);
}

/// Sets the parameter `id` of `params` to `normalized`, as a host's automation does (the
/// parameter's callbacks raise the change flags).
pub(crate) fn set_on(params: &crate::PneumaParams, id: &str, normalized: f32) {
    let ptr = params
        .param_map()
        .into_iter()
        .find(|(pid, _, _)| pid == id)
        .map(|(_, ptr, _)| ptr)
        .expect("a parameter id");
    // SAFETY: the caller's `params` outlive the call.
    unsafe { ptr._internal_set_normalized_value(normalized) };
}

#[test]
fn the_real_process_never_allocates_after_activate_as_vst3() {
    real_process_never_allocates(PluginApi::Vst3);
}

#[test]
fn the_real_process_never_allocates_after_activate_as_clap() {
    real_process_never_allocates(PluginApi::Clap);
}

/// Runs the real `process` under the guard through automation, bypass and a mode change, as
/// `api` (which decides how the mode change's latency reaches the host).
fn real_process_never_allocates(api: PluginApi) {
    // A silent guard would prove nothing below.
    if let Err(e) = guard_catches_allocations() {
        panic!("{e}");
    }
    let mut plugin = Pneuma::default();
    set(&plugin, "osc_enabled", 1.0);
    // The editor is open: its feed runs inside the guard too.
    plugin
        .editor_shared()
        .open
        .store(true, std::sync::atomic::Ordering::Relaxed);
    let layout = AudioIOLayout {
        main_input_channels: NonZeroU32::new(2),
        main_output_channels: NonZeroU32::new(2),
        ..AudioIOLayout::const_default()
    };
    let config = BufferConfig {
        sample_rate: 48_000.0,
        min_buffer_size: None,
        max_buffer_size: 512,
        process_mode: ProcessMode::Realtime,
    };
    let activation = Activation {
        api,
        latency: 0.into(),
    };
    assert!(plugin.activate(&layout, &config, &mut activation_ctx(&activation)));
    assert_eq!(
        activation.latency.get(),
        24_000,
        "lookahead latency reported"
    );

    let mut host = Host::playing(api, 48_000.0);
    let mut left = vec![0.0f32; 512];
    let mut right = vec![0.0f32; 512];
    let mut phase = 0.0f32;
    let mut pos = 0i64;
    for block in 0..400 {
        // Automation between blocks: live settings, the CC map, bypass on and off, a mode change.
        match block {
            50 => set(&plugin, "breath_level_db", 0.8),
            100 => set(&plugin, "cc_head_yaw", 0.0),
            150 => set(&plugin, "bypass", 1.0),
            200 => set(&plugin, "bypass", 0.0),
            250 => set(&plugin, "mode", 1.0),
            _ => {}
        }
        let n = 1 + (block * 37) % 512;
        for i in 0..n {
            phase += 2.0 * std::f32::consts::PI * 150.0 / 48_000.0;
            let on = (block / 60) % 2 == 0;
            left[i] = if on { 0.3 * phase.sin() } else { 0.0 };
            right[i] = if i == 3 { f32::NAN } else { left[i] };
        }
        host.transport.pos_samples = Some(pos);
        pos += n as i64;
        // Built (and its slice list allocated) outside the guard, as a host wrapper does.
        let mut buffer = Buffer::default();
        // SAFETY: the slices live until the end of this iteration, past `process`.
        unsafe {
            buffer.set_slices(n, |slices| {
                slices.clear();
                slices.push(&mut left[..n]);
                slices.push(&mut right[..n]);
            });
        }
        let mut aux = AuxiliaryBuffers {
            inputs: &mut [],
            outputs: &mut [],
        };
        nice_assert_no_alloc::assert_no_alloc(|| {
            plugin.process(&mut buffer, &mut aux, &mut host);
        });
        drop(buffer);
        assert!(left[..n].iter().chain(&right[..n]).all(|s| s.is_finite()));
        // The build thread makes the engine the mode change asked for; the next `process`
        // swaps it in under the guard.
        if plugin.slot.build_pending() {
            let start = std::time::Instant::now();
            while !plugin.slot.built_waiting() {
                assert!(start.elapsed().as_secs() < 10, "no engine built in 10 s");
                std::thread::sleep(std::time::Duration::from_millis(1));
            }
        }
    }
    assert!(
        host.cc_events.len() > 20,
        "the path did work: {} CC messages",
        host.cc_events.len()
    );
    if api == PluginApi::Clap {
        // CLAP: a new latency only inside `activate`; the plugin asks for the restart.
        assert_eq!(host.latency.get(), None, "no latency report from process");
        assert_eq!(host.restart_requests.get(), 1, "the mode change asked once");
    } else {
        assert_eq!(
            host.latency.get(),
            Some(0),
            "the mode change swapped in a live engine and reported its latency"
        );
        assert_eq!(host.restart_requests.get(), 0, "no restart needed");
    }
    let mut view_frames = 0;
    plugin.editor_shared().drain(|_| view_frames += 1, |_| {});
    assert!(view_frames > 100, "the editor got {view_frames} frames");
}

/// The activation context by value (the trait takes `&mut impl ActivateContext`).
pub(crate) fn activation_ctx(a: &Activation) -> ActivationRef<'_> {
    ActivationRef(a)
}

pub(crate) struct ActivationRef<'a>(&'a Activation);

impl ActivateContext<Pneuma> for ActivationRef<'_> {
    fn plugin_api(&self) -> PluginApi {
        self.0.api
    }
    fn execute(&self, _task: ()) {}
    fn set_latency_samples(&self, samples: u32) {
        self.0.set_latency_samples(samples);
    }
    fn set_current_voice_capacity(&self, _capacity: u32) {}
}
