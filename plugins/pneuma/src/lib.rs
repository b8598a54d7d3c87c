//! Pneuma as a CLAP and VST3 plugin, built on nice-plug.
//!
//! This is the plugin shell: it declares the plugin (name, ids, audio layouts, MIDI, parameters)
//! and passes audio through unchanged. The engine from `pneuma-core` (analysis, breath insertion,
//! head pose, MIDI CC and OSC output) is wired in later; until then:
//!
//! - audio: stereo (default) or mono, output equals input sample for sample, except that
//!   non-finite samples (NaN, ±inf) and subnormals are replaced by silence (`0.0`), so neither ever
//!   reaches the output (DESIGN.md, "Real-time rules");
//! - MIDI input: none. Declaring it on VST3 adds about 2 000 hidden parameters and hosts take tens
//!   of seconds to load the plugin, and no feature needs it;
//! - MIDI output: declared as [`MidiConfig::MidiCCs`] so the control signals can later leave as CC
//!   lanes (DESIGN.md, "Contracts", MIDI CC); nothing is sent yet;
//! - latency: zero samples;
//! - no editor.
//!
//! Real-time: `process()` never allocates, locks, blocks, logs or does I/O. The crate enables
//! nice-plug's `assert_process_allocs` (debug builds abort on an allocation in `process()`) and
//! `unsafe_flush_denormals` (flush-to-zero while processing).

// No `#![allow(unsafe_code)]` needed: the unsafe entry points come from nice-plug's export macros
// (`nice_export_clap!`, `nice_export_vst3!`), and the lint is not reported inside external macros.

use std::num::NonZeroU32;
use std::sync::Arc;

use nice_plug::prelude::*;

/// Stable identifier of the breath level parameter, saved in host projects and presets.
pub const BREATH_LEVEL_PARAM_ID: &str = "breath_level_db";
/// Lowest breath level, in dB relative to the speech level.
pub const BREATH_LEVEL_MIN_DB: f32 = -40.0;
/// Highest breath level, in dB relative to the speech level.
pub const BREATH_LEVEL_MAX_DB: f32 = -6.0;
/// Default breath level, in dB relative to the speech level.
pub const BREATH_LEVEL_DEFAULT_DB: f32 = -22.0;

/// The Pneuma plugin instance: owns its parameters; the engine joins later.
pub struct Pneuma {
    /// Parameters shared with the host wrapper (and later the editor).
    params: Arc<PneumaParams>,
}

/// The plugin's parameters. Parameter ids are part of saved host state: never change them.
#[derive(Params)]
pub struct PneumaParams {
    /// Loudness of the inserted breaths, in dB relative to the speech level around them, range
    /// -40..-6 dB, default -22 dB.
    ///
    /// Not used yet: the plugin is a pass-through shell until the breath voice is wired in.
    #[id = "breath_level_db"]
    pub breath_level_db: FloatParam,
}

impl Default for PneumaParams {
    fn default() -> Self {
        Self {
            breath_level_db: FloatParam::new(
                "Breath level",
                BREATH_LEVEL_DEFAULT_DB,
                FloatRange::Linear {
                    min: BREATH_LEVEL_MIN_DB,
                    max: BREATH_LEVEL_MAX_DB,
                },
            )
            .with_unit(" dB")
            .with_step_size(0.1),
        }
    }
}

impl Default for Pneuma {
    fn default() -> Self {
        Self {
            params: Arc::new(PneumaParams::default()),
        }
    }
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

    // Stereo first: the first layout is the default one.
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
    ];

    // No MIDI input: on VST3 it adds ~2 000 hidden parameters and slows host loading badly.
    const MIDI_INPUT: MidiConfig = MidiConfig::None;
    // CC output, for the control lanes (sent through `context.try_send_event(NoteEvent::MidiCC {..})`).
    const MIDI_OUTPUT: MidiConfig = MidiConfig::MidiCCs;

    const SAMPLE_ACCURATE_AUTOMATION: bool = false;

    type Editor = ();
    type SysExMessage = ();
    type BackgroundTask = ();

    fn params(&self) -> Arc<dyn Params> {
        self.params.clone()
    }

    fn activate(
        &mut self,
        _audio_io_layout: &AudioIOLayout,
        _buffer_config: &BufferConfig,
        context: &mut impl ActivateContext<Self>,
    ) -> bool {
        context.set_latency_samples(0);
        true
    }

    fn process(
        &mut self,
        buffer: &mut Buffer,
        _aux: &mut AuxiliaryBuffers,
        _context: &mut impl ProcessContext<Self>,
    ) -> ProcessStatus {
        // The wrapper has already copied input to output; only non-finite/subnormal samples change.
        for channel in buffer.as_slice().iter_mut() {
            sanitize_in_place(channel);
        }
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
        assert_eq!(
            ids,
            vec![BREATH_LEVEL_PARAM_ID],
            "exactly one parameter, by its stable id"
        );

        let p = &params.breath_level_db;
        assert_eq!(p.default_plain_value(), -22.0);
        assert_eq!(p.value(), -22.0);
        assert_eq!(p.preview_plain(0.0), -40.0);
        assert_eq!(p.preview_plain(1.0), -6.0);
        assert_eq!(p.name(), "Breath level");
    }

    #[test]
    fn audio_layouts_are_stereo_first_then_mono() {
        let channels: Vec<(Option<u32>, Option<u32>)> = Pneuma::AUDIO_IO_LAYOUTS
            .iter()
            .map(|l| {
                (
                    l.main_input_channels.map(NonZeroU32::get),
                    l.main_output_channels.map(NonZeroU32::get),
                )
            })
            .collect();
        assert_eq!(channels, vec![(Some(2), Some(2)), (Some(1), Some(1))]);
        assert!(Pneuma::AUDIO_IO_LAYOUTS
            .iter()
            .all(|l| l.aux_input_ports.is_empty() && l.aux_output_ports.is_empty()));
    }

    #[test]
    fn midi_is_output_cc_only_and_ids_are_stable() {
        assert!(matches!(Pneuma::MIDI_INPUT, MidiConfig::None));
        assert!(matches!(Pneuma::MIDI_OUTPUT, MidiConfig::MidiCCs));
        assert_eq!(Pneuma::CLAP_ID, "org.pneuma.pneuma");
        assert_eq!(&Pneuma::VST3_CLASS_ID, b"PneumaBreathHead");
        assert_eq!(Pneuma::NAME, "Pneuma");
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
