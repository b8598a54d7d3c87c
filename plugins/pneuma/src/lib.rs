//! Pneuma as a CLAP and VST3 plugin, built on nice-plug.
//!
//! - Audio: stereo (default) or mono, in place, through [`pneuma_core::engine::Engine`]: breaths
//!   are mixed into the output exactly as `pneuma render` does for the same settings. Non-finite
//!   input never reaches the output, and subnormal output samples become 0.
//! - Breath samples: the persisted paths (`breath_sample_mouth`, `breath_sample_nose`) are
//!   loaded when an engine is built (WAV, mixed to mono); a file that cannot be used is logged and
//!   the procedural breath stays. A path changed while active (a project or preset loaded) builds
//!   a new engine with the new file ([`rebuild`]).
//! - Breath voice: learned as the audio goes (as `pneuma render --lookahead-ms`), restarting
//!   with the stream; or learned from the persisted `breath_like` recording when an engine is
//!   built ([`breath_like`], as `render --breath-like`). The `freeze_breath_voice` switch keeps
//!   the voice learned so far for every playback after it, saved in the state as
//!   `breath_voice` ([`voice`]); the editor shows what the voice does.
//! - Activation never fails, at any sample rate a host uses (1 Hz … 768 kHz, odd rates): where
//!   the engine cannot run at that rate, the audio passes untouched (latency 0) and the controls
//!   go to rest once ([`send_rest_pose`]: one CC message per controller, one OSC frame).
//! - Bypass (the host's switch, parameter `bypass`): the audio still passes through the delay
//!   line (the latency stays, so the track stays aligned), no breaths, controls at rest.
//! - Latency: the engine's (`mode` = lookahead: the lookahead delay; live: none), reported at
//!   activation. Changing `mode`, `lookahead_s` or `frame_rate_hz` while active (by hand,
//!   automation or a restored state) builds a new engine off the audio thread and swaps it in
//!   ([`rebuild`]). As VST3 (and standalone), the new latency is reported from the audio thread:
//!   no re-activation by the host is needed. As CLAP, whose hosts may hear of a latency change
//!   only inside `activate`, an engine that would change the latency is not swapped in: the
//!   plugin asks the host for a restart (the running engine keeps going until then) and the
//!   re-activation builds from the new settings; latency-neutral changes swap in at once.
//! - Parameter changes reach the audio thread through [`ChangeFlags`] raised by the parameters'
//!   callbacks: the engine settings and the CC map are rebuilt only after a change.
//! - Reset (engine, MIDI CC memory, OSC time anchor) on re-activation, on the host's reset, when
//!   the transport first plays after an activation, and on a transport jump (a position that is
//!   not where the previous block ended, while playing). So playback and exports start from a
//!   fresh engine, as `pneuma render` does, whatever ran through the plugin while stopped.
//! - MIDI output: CC per the DESIGN.md map ([`pneuma_core::encode::midi_cc`]), sent only on change,
//!   at most once per frame, at the sample offset inside the block where the frame became
//!   available. No MIDI input (on VST3 it adds ~2 000 hidden parameters).
//! - OSC output: [`pneuma_osc::worker`] (the crate the CLI sends from too): a preallocated
//!   `rtrb` queue to a worker thread that sends UDP bundles (pneuma or VMC) to a numeric address
//!   (no DNS); the target can change while playing; network trouble never reaches the audio
//!   thread or holds up unloading.
//! - Parameters and persisted settings: [`params`]; a parameter of core's settings table takes
//!   its name, range, default, unit and step from it, and hosts file it under the table's group
//!   (VST3 units, CLAP modules): Breathing, Breaths & timing, Head, Analysis, MIDI CC, OSC
//!   ([`params::unit_of`]). CLAP remote-control pages (a layout for hardware controllers): one
//!   per group, in the same order, eight controls to a page, every parameter but bypass
//!   ([`params::remote`]).
//!
//! Real-time: `process()` never allocates, locks, blocks, logs or does I/O; the one wait is
//! offline (the host renders without a deadline), for an engine the settings asked for, so a
//! mid-export change takes over at the block that sees it on every run ([`rebuild`]). The crate
//! enables nice-plug's `assert_process_allocs` (debug builds abort on an allocation in
//! `process()`) and `unsafe_flush_denormals` (flush-to-zero while processing).

// No `#![allow(unsafe_code)]` needed: the unsafe entry points come from nice-plug's export macros
// (`nice_export_clap!`, `nice_export_vst3!`), and the lint is not reported inside external macros.

#[cfg(test)]
mod alloc_test;
#[cfg(test)]
mod automation_compat;
pub mod breath_like;
mod declick;
pub mod editor;
pub mod params;
pub mod rebuild;
mod transport;
pub mod voice;
#[cfg(test)]
mod voice_test;

use std::num::NonZeroU32;
use std::sync::Arc;

use nice_plug::prelude::*;
use pneuma_core::encode::midi_cc::{CcEncoder, CcMessage};
use pneuma_core::encode::osc::OscFormat;
use pneuma_core::encode::sink::{CcSink, FrameSink};

use breath_like::VoiceCache;
use editor::feed::{EditorFeed, EditorShared};
pub use params::{ChangeFlags, PneumaParams, PARAM_IDS};
use pneuma_core::breathing::BreathSample;
use pneuma_core::engine::Engine;
use pneuma_core::ControlFrame;
use pneuma_osc::worker::{self as osc_sender, OscFeed, OscSettings, OscStats, OscWorker};
use rebuild::{EngineSlot, SlotEvent};
use transport::{JumpDetector, PreRoll};
use voice::{VoiceFreeze, VoiceShown};

impl OscSettings for PneumaParams {
    fn target(&self) -> (String, u16) {
        (
            self.osc_host(),
            self.osc_port.value().clamp(1, 65535) as u16,
        )
    }

    fn format(&self) -> OscFormat {
        self.osc_format.value().into()
    }

    fn enabled(&self) -> bool {
        self.osc_enabled.value()
    }
}

/// Mono sources on stereo outputs: the right channel takes a copy of the left one before the
/// engine, so a mono voice comes out on both sides and the stereo image stays centred.
/// - Mono in, stereo out (a layout): always.
/// - Stereo in: while the right input has been exact digital silence since activation (a mono
///   track feeding a stereo plugin, whose second input the host leaves silent). The first
///   sample that is not 0 on the right makes the input stereo until the next activation.
#[derive(Debug, Default, Clone, Copy)]
struct MonoSource {
    /// The layout has one input and two outputs.
    mono_input: bool,
    /// The right input carried something since activation.
    right_heard: bool,
}

impl MonoSource {
    fn new(layout: &AudioIOLayout) -> Self {
        let count = |c: Option<NonZeroU32>| c.map_or(0, NonZeroU32::get);
        Self {
            mono_input: count(layout.main_input_channels) == 1
                && count(layout.main_output_channels) == 2,
            right_heard: false,
        }
    }

    /// Copies the left channel into the right one where the source is mono. Never allocates.
    fn apply(&mut self, audio: &mut [&mut [f32]]) {
        let [left, right] = audio else {
            return;
        };
        if !self.mono_input && !self.right_heard {
            self.right_heard = right.iter().any(|&s| s != 0.0);
        }
        if self.mono_input || !self.right_heard {
            right.copy_from_slice(left);
        }
    }
}

/// The Pneuma plugin instance.
pub struct Pneuma {
    params: Arc<PneumaParams>,
    /// The engine and its replacement when structural settings change ([`rebuild`]).
    slot: EngineSlot,
    /// The rest pose went out since the controls stopped following the voice (bypass, or no
    /// engine); the next frames from the engine clear it.
    at_rest: bool,
    mono: MonoSource,
    cc: CcEncoder,
    midi_was_enabled: bool,
    osc_feed: Option<OscFeed>,
    osc_worker: Option<OscWorker>,
    osc_stats: Option<Arc<OscStats>>,
    jumps: JumpDetector,
    pre_roll: PreRoll,
    /// The audio side of the editor's data path ([`editor::feed`]).
    view: EditorFeed,
    view_shared: Arc<EditorShared>,
    /// The voices learned from breath-like files, shared by the engine builder and the editor.
    breath_like_voices: Arc<VoiceCache>,
    /// The freeze switch and the saved breath voice on the audio thread ([`voice`]).
    voice: VoiceFreeze,
    /// The seam where a new engine takes over while playing.
    seam: declick::Seam,
}

impl Default for Pneuma {
    fn default() -> Self {
        let params = Arc::new(PneumaParams::default());
        let cc = CcEncoder::new(params.cc_map()).expect("the default CC map is valid");
        let (view, view_shared) = editor::feed::channel();
        let breath_like_voices = Arc::new(VoiceCache::default());
        Self {
            slot: EngineSlot::new(params.clone(), breath_like_voices.clone()),
            breath_like_voices,
            params,
            at_rest: false,
            mono: MonoSource::default(),
            cc,
            midi_was_enabled: true,
            osc_feed: None,
            osc_worker: None,
            osc_stats: None,
            jumps: JumpDetector::default(),
            pre_roll: PreRoll::default(),
            view,
            view_shared,
            voice: VoiceFreeze::default(),
            seam: declick::Seam::default(),
        }
    }
}

impl Pneuma {
    /// OSC counters (sent, failed, dropped), once activated.
    pub fn osc_stats(&self) -> Option<&Arc<OscStats>> {
        self.osc_stats.as_ref()
    }

    /// The GUI's end of the editor's data path.
    pub fn editor_shared(&self) -> &Arc<EditorShared> {
        &self.view_shared
    }

    fn reset_streams(&mut self) {
        self.slot.reset();
        self.cc.reset();
    }

    /// Audio thread, start of a block: the engine slot swaps in an engine built for new
    /// structural settings ([`EngineSlot::follow`]); the host hears of its latency, or is asked
    /// for a restart, and the editor shows it. Never allocates, frees or blocks.
    fn follow_structure(&mut self, context: &mut impl ProcessContext<Self>, block: usize) {
        let (view, at_rest, voice, seam) = (
            &mut self.view,
            &mut self.at_rest,
            &mut self.voice,
            &mut self.seam,
        );
        self.slot.follow(block, |event| match event {
            SlotEvent::Swapped {
                latency,
                running,
                sample_rate_hz,
            } => {
                context.set_latency_samples(latency);
                // The editor shows the latency the swapped-in engine costs.
                view.activated(running, latency, sample_rate_hz);
                *at_rest = false;
                voice.engine_changed();
                seam.swapped(latency);
            }
            SlotEvent::RestartWanted => context.request_restart(),
        });
    }

    /// Audio thread, start of a block: the freeze switch and the saved breath voice reach the
    /// engine ([`voice`]). Never allocates, locks or waits.
    fn follow_voice(&mut self) {
        let freeze = self.params.freeze_breath_voice.value();
        let (engine, built) = self.slot.engine_and_voice();
        self.voice
            .follow(engine, built, &self.params.breath_voice, freeze);
    }

    /// What the editor shows of the breath voice.
    fn voice_shown(&mut self) -> VoiceShown {
        match self.slot.engine_mut() {
            Some(engine) => self.voice.shown(engine),
            None => VoiceShown::NoEngine,
        }
    }

    /// Runs the engine (or the pass-through where there is none) over `audio`, sending its
    /// control frames to the enabled outputs.
    fn run_engine(
        &mut self,
        audio: &mut [&mut [f32]],
        midi_on: bool,
        osc_on: bool,
        send_cc: &mut dyn FnMut(u32, CcMessage),
    ) {
        let bypassed = self.params.bypass.value();
        match self.slot.engine_mut() {
            Some(engine) => {
                self.at_rest = bypassed;
                let outputs = if bypassed {
                    Outputs {
                        cc: None,
                        osc: None,
                        view: Some(&mut self.view),
                    }
                } else {
                    Outputs {
                        cc: midi_on.then_some(&mut self.cc),
                        osc: if osc_on { self.osc_feed.as_mut() } else { None },
                        view: Some(&mut self.view),
                    }
                };
                run_block(engine, audio, outputs, send_cc);
            }
            None => {
                for channel in audio.iter_mut() {
                    sanitize_in_place(channel);
                }
            }
        }
    }
}

/// Where a block's control frames go: the CC encoder (when MIDI is on), the OSC feed (when OSC
/// is on) and the editor (when open).
pub struct Outputs<'a> {
    /// The CC encoder, or `None` when MIDI output is off.
    pub cc: Option<&'a mut CcEncoder>,
    /// The OSC feed, or `None` when OSC output is off.
    pub osc: Option<&'a mut OscFeed>,
    /// The editor's feed (frames and inserted breaths), or `None`.
    pub view: Option<&'a mut EditorFeed>,
}

/// The audio-thread work of one block: runs the engine in place (then flushes subnormal output
/// samples to 0), the outputs being its sinks ([`FrameSink`]): every control frame to the CC
/// encoder, the OSC feed and the editor, inserted and heard breaths to the editor.
/// `send_cc(offset, message)` receives each CC message with its sample offset in the block.
/// Never allocates, locks or blocks.
pub fn run_block(
    engine: &mut Engine,
    audio: &mut [&mut [f32]],
    outputs: Outputs<'_>,
    send_cc: &mut dyn FnMut(u32, CcMessage),
) {
    // Positions from 0: a frame's position is its sample offset in this block.
    let cc = outputs
        .cc
        .map(|encoder| CcSink::new(encoder, |at, m| send_cc(at as u32, m)));
    engine.process_into(audio, 0, &mut (cc, outputs.osc, outputs.view));
    // The engine passes the voice bit for bit, subnormal samples included; hosts and validators
    // reject subnormal output, so they become 0 (no other sample changes).
    for channel in audio.iter_mut() {
        sanitize_in_place(channel);
    }
}

/// Sends the rest pose ([`ControlFrame::rest`]: silent, head straight, breath at rest)
/// to the outputs: every controller the CC encoder has not sent at that value, and one OSC frame.
pub fn send_rest_pose(outputs: &mut Outputs<'_>, send_cc: &mut dyn FnMut(u32, CcMessage)) {
    let cc = outputs
        .cc
        .as_deref_mut()
        .map(|encoder| CcSink::new(encoder, |_, m| send_cc(0, m)));
    (cc, outputs.osc.as_deref_mut()).frame(&ControlFrame::rest(0, 0.0), 0);
}

/// Reads a breath sample (WAV, FLAC, AIFF, … any channel count, mixed to mono). Empty path:
/// none.
pub fn load_breath_sample(path: &str) -> Result<Option<BreathSample>, String> {
    if path.trim().is_empty() {
        return Ok(None);
    }
    // The same reader as the CLI's (pneuma-io): every format and WAV variant it accepts.
    let (mono, rate_hz) =
        pneuma_io::read_mono(std::path::Path::new(path)).map_err(|e| e.to_string())?;
    BreathSample::from_mono(mono, f64::from(rate_hz))
        .map(Some)
        .map_err(|e| format!("{path}: {e}"))
}

/// Replaces every sample that is not a normal finite number (NaN, ±inf, subnormal) by `0.0` and
/// leaves every other sample bit-identical. Never allocates.
pub fn sanitize_in_place(samples: &mut [f32]) {
    for sample in samples.iter_mut() {
        // `is_normal()` is false for 0.0 as well, which maps to itself.
        if !sample.is_normal() {
            *sample = 0.0;
        }
    }
}

impl Plugin for Pneuma {
    const NAME: &'static str = "Pneuma";
    const VENDOR: &'static str = "Pneuma";
    const URL: &'static str = env!("CARGO_PKG_REPOSITORY");
    const EMAIL: &'static str = "";
    const VERSION: &'static str = env!("CARGO_PKG_VERSION");

    // Stereo first: the first layout is the default one. The order is kept (hosts and the
    // test host select layouts by index): stereo, mono, then mono in / stereo out, which puts a
    // mono voice on both sides (see `MonoSource`).
    const AUDIO_IO_LAYOUTS: &'static [AudioIOLayout] = &[
        AudioIOLayout {
            main_input_channels: NonZeroU32::new(2),
            main_output_channels: NonZeroU32::new(2),
            ..AudioIOLayout::const_default()
        },
        AudioIOLayout {
            main_input_channels: NonZeroU32::new(1),
            main_output_channels: NonZeroU32::new(1),
            ..AudioIOLayout::const_default()
        },
        AudioIOLayout {
            main_input_channels: NonZeroU32::new(1),
            main_output_channels: NonZeroU32::new(2),
            ..AudioIOLayout::const_default()
        },
    ];

    // No MIDI input: on VST3 it adds ~2 000 hidden parameters and slows host loading badly.
    const MIDI_INPUT: MidiConfig = MidiConfig::None;
    // CC output, for the control lanes (sent through `context.try_send_event(NoteEvent::MidiCC {..})`).
    const MIDI_OUTPUT: MidiConfig = MidiConfig::MidiCCs;

    const SAMPLE_ACCURATE_AUTOMATION: bool = false;

    type SysExMessage = ();
    type Editor = editor::PneumaEditor;
    type BackgroundTask = ();

    /// A state saved before a parameter or field existed loads it at its default
    /// ([`params::migrate`]), never at the value the instance held before.
    fn filter_state(state: &mut PluginState) {
        params::migrate::fill_defaults(state);
    }

    fn params(&self) -> Arc<dyn Params> {
        // Filed under units (VST3) / modules (CLAP) for the hosts' generic views.
        Arc::new(params::HostParams(self.params.clone()))
    }

    fn deactivate(&mut self) {
        // Off the audio thread: drop what the audio thread handed back.
        self.slot.deactivate();
    }

    fn editor(&mut self, _executor: AsyncExecutor<Self>) -> Option<Self::Editor> {
        editor::create(
            self.params.clone(),
            self.view_shared.clone(),
            self.params.editor_layout.clone(),
            self.breath_like_voices.clone(),
        )
    }

    fn activate(
        &mut self,
        audio_io_layout: &AudioIOLayout,
        buffer_config: &BufferConfig,
        context: &mut impl ActivateContext<Self>,
    ) -> bool {
        // Everything is read afresh here: earlier changes need no action.
        self.params.changes.clear();
        let channels = audio_io_layout
            .main_output_channels
            .map_or(1, NonZeroU32::get) as usize;
        // Never refuse: a host may use any rate (1 Hz, 768 kHz, 1 234.5678 Hz). Where the engine
        // cannot run, the audio passes untouched and the controls rest.
        let latency = self.slot.activate(
            buffer_config.sample_rate,
            buffer_config.max_buffer_size,
            channels,
            context.plugin_api() == PluginApi::Clap,
            buffer_config.process_mode,
        );
        context.set_latency_samples(latency);
        self.view
            .activated(self.slot.is_running(), latency, buffer_config.sample_rate);
        self.at_rest = false;
        self.voice.engine_changed();
        self.mono = MonoSource::new(audio_io_layout);
        self.seam = declick::Seam::activate(buffer_config.sample_rate);
        // One millisecond of tolerance for rounded host positions (at least one sample).
        self.pre_roll = PreRoll::default();
        self.jumps = JumpDetector::new(
            (f64::from(buffer_config.sample_rate) / 1000.0)
                .ceil()
                .max(1.0) as i64,
        );
        // A map the parameters describe may be invalid (a controller over 31 in 14-bit mode):
        // keep the previous one then.
        let _ = self.cc.set_map(self.params.cc_map());
        self.cc.reset();
        if self.osc_worker.is_none() {
            match osc_sender::start(self.params.clone()) {
                Ok((feed, worker, stats)) => {
                    self.osc_feed = Some(feed);
                    self.osc_worker = Some(worker);
                    self.osc_stats = Some(stats);
                }
                // OSC is optional: the plugin still works without its thread.
                Err(e) => nice_error!("Pneuma: cannot start the OSC thread: {e}"),
            }
        }
        true
    }

    fn reset(&mut self) {
        self.reset_streams();
    }

    fn process(
        &mut self,
        buffer: &mut Buffer,
        _aux: &mut AuxiliaryBuffers,
        context: &mut impl ProcessContext<Self>,
    ) -> ProcessStatus {
        let transport = context.transport();
        let pos = transport.pos_samples();
        let playing = transport.playing;
        // Before a transport start or jump resets the stream: a freeze takes the voice learned
        // up to here, not the empty one after the reset.
        self.follow_voice();
        let jumped = self.jumps.check(playing, pos, buffer.samples());
        if jumped {
            self.reset_streams();
            self.pre_roll.start(pos, self.slot.latency_samples());
        }
        self.follow_structure(context, buffer.samples());
        // A new engine takes the frozen voice before its first block.
        self.follow_voice();
        let changes = &self.params.changes;
        if ChangeFlags::take(&changes.cc_map) {
            // An invalid map (two signals on one controller, a 14-bit controller over 31) keeps
            // the previous one; the editor shows why (`editor::view`).
            if self.cc.set_map(self.params.cc_map()).is_err() {
                debug_assert!(self.cc.map().validate().is_ok(), "the kept map is valid");
            }
        }
        if ChangeFlags::take(&changes.engine) {
            // The live part applies now; a stream part waits for the build that the structure
            // flag asked for.
            self.slot.apply_live_settings();
        }
        let midi_on = self.params.midi_enabled.value();
        if midi_on && !self.midi_was_enabled {
            self.cc.reset();
        }
        self.midi_was_enabled = midi_on;
        let osc_on = self.params.osc_enabled.value();
        let bypassed = self.params.bypass.value();

        let mut cc_lost = false;
        let mut send_cc = |offset: u32, m: CcMessage| {
            // A full host event buffer loses the message; never block for it.
            if context
                .try_send_event(NoteEvent::MidiCC {
                    timing: offset,
                    channel: m.channel,
                    cc: m.controller,
                    value: f32::from(m.value) / 127.0,
                })
                .is_err()
            {
                cc_lost = true;
            }
        };
        self.mono.apply(buffer.as_slice());
        self.view.begin_block(buffer.as_slice());
        let rest = bypassed || !self.slot.is_running();
        if rest && !self.at_rest {
            // Once: every controller to the rest pose, one rest frame to OSC.
            self.at_rest = true;
            let mut outputs = Outputs {
                cc: midi_on.then_some(&mut self.cc),
                osc: if osc_on { self.osc_feed.as_mut() } else { None },
                view: None,
            };
            send_rest_pose(&mut outputs, &mut send_cc);
        }
        let audio = buffer.as_slice();
        let restart_at = if playing {
            self.pre_roll.restart_at(pos, audio)
        } else {
            self.pre_roll.stop();
            None
        };
        // A stream that starts afresh here (a jump, the end of a silent pre-roll) has no seam.
        if jumped || restart_at.is_some() {
            self.seam.restart();
        }
        self.seam.before(audio);
        match restart_at {
            // A silent pre-roll ends in this block: the engine starts afresh with the audio, as
            // `pneuma render` starts at the file's first sample.
            Some(at) => {
                let mut heads: [&mut [f32]; 2] = Default::default();
                let mut tails: [&mut [f32]; 2] = Default::default();
                let channels = audio.len().min(2);
                for (i, channel) in audio.iter_mut().take(2).enumerate() {
                    let (head, tail) = channel.split_at_mut(at);
                    heads[i] = head;
                    tails[i] = tail;
                }
                self.run_engine(&mut heads[..channels], midi_on, osc_on, &mut send_cc);
                self.reset_streams();
                let offset = at as u32;
                self.run_engine(&mut tails[..channels], midi_on, osc_on, &mut |o, m| {
                    send_cc(o + offset, m)
                });
            }
            None => self.run_engine(audio, midi_on, osc_on, &mut send_cc),
        }
        self.seam.after(audio);
        if cc_lost {
            // Forget what was sent so every controller is sent again at the next frame: a lost
            // message must not leave a receiver on a stale value.
            self.cc.reset();
            if rest {
                self.at_rest = false;
            }
        }
        let shown = self.voice_shown();
        shown.store(&self.view.status().breath_voice);
        self.view.end_block(self.osc_stats.as_deref(), cc_lost);
        ProcessStatus::Normal
    }
}

impl ClapPlugin for Pneuma {
    const CLAP_ID: &'static str = "org.pneuma.pneuma";
    const CLAP_DESCRIPTION: Option<&'static str> =
        Some("Speech gives a body: breaths, head pose and breathing from a voice");
    const CLAP_MANUAL_URL: Option<&'static str> = None;
    const CLAP_SUPPORT_URL: Option<&'static str> = None;
    const CLAP_FEATURES: &'static [ClapFeature] = &[
        ClapFeature::AudioEffect,
        ClapFeature::Stereo,
        ClapFeature::Mono,
        ClapFeature::Utility,
        ClapFeature::Analyzer,
    ];

    fn remote_controls(&self, context: &mut impl RemoteControlsContext) {
        // One page per group of core's table, derived from the parameters (`params::remote`).
        context.add_section("Pneuma", |section| {
            for (name, members) in params::remote::pages(self.params.as_ref()) {
                section.add_page(name, |page| {
                    members
                        .into_iter()
                        .for_each(|(_, ptr)| params::remote::add(page, ptr))
                });
            }
        });
    }
}

impl Vst3Plugin for Pneuma {
    const VST3_CLASS_ID: [u8; 16] = *b"PneumaBreathHead";
    const VST3_SUBCATEGORIES: &'static [Vst3SubCategory] =
        &[Vst3SubCategory::Fx, Vst3SubCategory::Analyzer];
}

nice_export_clap!(Pneuma);
nice_export_vst3!(Pneuma);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn breath_level_param_has_promised_id_range_and_default() {
        let params = PneumaParams::default();
        let map = params.param_map();
        let ids: Vec<&str> = map.iter().map(|(id, _, _)| id.as_str()).collect();
        // The id saved in host projects (docs/guide/plugin.md): a literal, not the code's own constant.
        assert!(ids.contains(&"breath_level_db"));

        let p = &params.breath_level_db;
        assert_eq!(p.default_plain_value(), -22.0);
        assert_eq!(p.value(), -22.0);
        assert_eq!(p.preview_plain(0.0), -40.0);
        assert_eq!(p.preview_plain(1.0), -6.0);
        assert_eq!(p.name(), "Breath level");
    }

    #[test]
    fn breath_samples_load_from_wav_and_bad_files_are_refused() {
        assert!(load_breath_sample("").unwrap().is_none());
        assert!(load_breath_sample("/no/such/breath.wav").is_err());
        let dir = std::env::temp_dir().join(format!("pneuma-plugin-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("breath.wav");
        let spec = hound::WavSpec {
            channels: 2,
            sample_rate: 44_100,
            bits_per_sample: 16,
            sample_format: hound::SampleFormat::Int,
        };
        let mut w = hound::WavWriter::create(&path, spec).unwrap();
        let mut state = 1u32;
        for _ in 0..(44_100 / 2) {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let v = (state >> 16) as i16 / 8;
            w.write_sample(v).unwrap();
            w.write_sample(v).unwrap();
        }
        w.finalize().unwrap();
        let sample = load_breath_sample(path.to_str().unwrap()).unwrap();
        assert!(sample.is_some(), "a half-second noise breath is usable");
        // Silence is refused by the breathing model, with the path in the message.
        let silent = dir.join("silent.wav");
        let mut w = hound::WavWriter::create(&silent, spec).unwrap();
        for _ in 0..44_100 {
            w.write_sample(0i16).unwrap();
        }
        w.finalize().unwrap();
        let err = load_breath_sample(silent.to_str().unwrap()).unwrap_err();
        assert!(err.contains("silent.wav"), "{err}");
        // The same file as saved from a pipe (ffmpeg/sox write 0xFFFFFFFF as the data size):
        // the CLI reads it, so the plugin must too (issue 17.5: one reader for both).
        let mut bytes = std::fs::read(&path).unwrap();
        let data = bytes.windows(4).position(|w| w == b"data").unwrap();
        bytes[data + 4..data + 8].copy_from_slice(&u32::MAX.to_le_bytes());
        let piped = dir.join("piped.wav");
        std::fs::write(&piped, &bytes).unwrap();
        let sample = load_breath_sample(piped.to_str().unwrap());
        assert!(
            sample.as_ref().is_ok_and(|s| s.is_some()),
            "a streamed-size WAV loads: {sample:?}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    fn layout(inputs: u32, outputs: u32) -> AudioIOLayout {
        AudioIOLayout {
            main_input_channels: NonZeroU32::new(inputs),
            main_output_channels: NonZeroU32::new(outputs),
            ..AudioIOLayout::const_default()
        }
    }

    #[test]
    fn a_mono_source_comes_out_on_both_sides() {
        let voice = [0.25f32, -0.5, 0.125, 0.0];
        // Stereo in with a silent right input: the left is copied until the right is heard.
        let mut mono = MonoSource::new(&layout(2, 2));
        let (mut l, mut r) = (voice, [0.0f32; 4]);
        mono.apply(&mut [&mut l[..], &mut r[..]]);
        assert_eq!((l, r), (voice, voice), "silent right input takes the left");
        let other = [0.0f32, 0.0, 0.0, 0.75];
        let (mut l, mut r) = (voice, other);
        mono.apply(&mut [&mut l[..], &mut r[..]]);
        assert_eq!((l, r), (voice, other), "a heard right input stays as it is");
        let (mut l, mut r) = (voice, [0.0f32; 4]);
        mono.apply(&mut [&mut l[..], &mut r[..]]);
        assert_eq!(r, [0.0; 4], "stereo until the next activation");
        // Mono in, stereo out: always copied.
        let mut mono = MonoSource::new(&layout(1, 2));
        for right in [[0.0f32; 4], other] {
            let (mut l, mut r) = (voice, right);
            mono.apply(&mut [&mut l[..], &mut r[..]]);
            assert_eq!(r, voice);
        }
        // Mono in and out: one channel, nothing to do.
        let mut l = voice;
        MonoSource::new(&layout(1, 1)).apply(&mut [&mut l[..]]);
        assert_eq!(l, voice);
        // Every layout the plugin offers has a main input and output and no side ports.
        for l in Pneuma::AUDIO_IO_LAYOUTS {
            assert!(l.main_input_channels.is_some() && l.main_output_channels.is_some());
            assert!(l.aux_input_ports.is_empty() && l.aux_output_ports.is_empty());
        }
    }

    #[test]
    fn sanitize_keeps_normal_samples_and_silences_the_rest() {
        let normal = [0.5_f32, -1.0, 1e-30, -0.25, f32::MIN_POSITIVE, 1e6];
        let mut block = normal;
        sanitize_in_place(&mut block);
        assert_eq!(
            block.map(f32::to_bits),
            normal.map(f32::to_bits),
            "normal samples pass bit-exact"
        );

        let mut bad = [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE / 2.0,
            -1e-45,
            0.0,
        ];
        sanitize_in_place(&mut bad);
        assert!(bad.iter().all(|&s| s == 0.0), "{bad:?}");
    }
}
