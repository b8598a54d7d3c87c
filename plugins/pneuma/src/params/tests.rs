//! Tests of the parameters: the table's ranges and ids, the callbacks, the state.

use super::*;

#[test]
fn ids_are_the_promised_ones_in_order() {
    let params = PneumaParams::default();
    let ids: Vec<String> = params
        .param_map()
        .into_iter()
        .map(|(id, _, _)| id)
        .collect();
    assert_eq!(ids, PARAM_IDS);
}

#[test]
fn hosts_see_every_parameter_in_a_unit_of_one_contiguous_run() {
    let host = HostParams(Arc::new(PneumaParams::default()));
    let map = host.param_map();
    let ids: Vec<&str> = map.iter().map(|(id, _, _)| id.as_str()).collect();
    assert_eq!(ids, PARAM_IDS, "same ids in the same order");
    let units: Vec<&str> = map.iter().map(|(_, _, u)| u.as_str()).collect();
    assert_eq!(units[0], "", "bypass at the top");
    assert!(units[1..].iter().all(|u| !u.is_empty()), "{units:?}");
    let mut runs: Vec<&str> = units[1..].to_vec();
    runs.dedup();
    assert_eq!(
        runs,
        [
            "Breathing",
            "Breaths & timing",
            "Head",
            "Analysis",
            "MIDI CC",
            "OSC"
        ],
        "each unit one run, in this order"
    );
    assert_eq!(unit_of("cc_loudness"), "MIDI CC");
    assert_eq!(unit_of("mode"), "Breaths & timing");
    assert_eq!(unit_of("preset"), "Breathing");
    assert_eq!(unit_of("freeze_breath_voice"), "Breaths & timing");
}

#[test]
fn every_parameter_is_a_setting_of_the_table_or_the_plugins_own() {
    let params = PneumaParams::default();
    for (id, _, _) in params.param_map() {
        let in_table = settings::find(&id).is_some();
        let own = plugin_only(&id).is_some();
        assert!(
            in_table != own,
            "{id}: in the table {in_table}, plugin-only {own}"
        );
    }
    // The plugin-only list names nothing the table holds.
    for (id, group, why) in PLUGIN_ONLY {
        assert!(settings::find(id).is_none() && !why.is_empty(), "{id}");
        assert!(group.is_empty() || settings::GROUPS.iter().any(|g| g.id == *group));
    }
    assert!(plugin_only("cc_speaking").is_some() && plugin_only("cc_nothing").is_none());
}

#[test]
fn parameters_of_the_table_take_its_range_default_and_names() {
    let params = PneumaParams::default();
    let mut checked = 0;
    for (id, ptr, _) in params.param_map() {
        let Some(s) = settings::find(&id) else {
            continue;
        };
        // SAFETY: `params` outlives every pointer of its map.
        let (lo, hi, default, name) = unsafe {
            (
                ptr.preview_plain(0.0),
                ptr.preview_plain(1.0),
                ptr.default_plain_value(),
                ptr.name(),
            )
        };
        assert_eq!((f64::from(lo), f64::from(hi)), (s.min(), s.max()), "{id}");
        assert_eq!(default, s.default, "{id}");
        assert_eq!(name, s.label, "{id}");
        checked += 1;
    }
    // All but bypass, preset, the freeze switch, the two output switches and the CC controllers.
    assert_eq!(checked, PARAM_IDS.len() - 5 - SIGNAL_COUNT);
    // The choices' ids are the table's names, in its order.
    assert_eq!(ModeChoice::ids().expect("ids"), placement::MODE.names());
    assert_eq!(
        OscFormatChoice::ids().expect("ids"),
        output::OSC_FORMAT.names()
    );
}

#[test]
fn default_cc_map_is_the_design_map() {
    let params = PneumaParams::default();
    assert_eq!(params.cc_map(), CcMap::default());
    params.cc_map().validate().unwrap();
}

#[test]
fn a_controller_that_14_bit_pairs_cannot_use_is_off_in_14_bit_mode_only() {
    let params = PneumaParams::default();
    let thorax = CcSignal::Thorax.index();
    let set = |id: &str, plain: f32| {
        let ptr = param(&params, id);
        // SAFETY: `params` outlives the pointer.
        unsafe {
            let normalized = ptr.preview_normalized(plain);
            ptr._internal_set_normalized_value(normalized);
        }
    };
    set("cc_thorax", 40.0);
    assert_eq!(params.cc_map().controllers[thorax], Some(40), "7-bit");
    set("cc_14bit", 1.0);
    assert_eq!(
        params.cc_map().controllers[thorax],
        None,
        "40 cannot be an MSB"
    );
    params.cc_map().validate().unwrap();
    set("cc_thorax", 31.0);
    assert_eq!(params.cc_map().controllers[thorax], Some(31));
}

#[test]
fn defaults_are_the_models_defaults_and_presets_replace_the_controls() {
    let params = PneumaParams::default();
    assert_eq!(params.breathing_params(), BreathingParams::default());
    assert_eq!(params.head_config(), HeadConfig::default());
    params.breathing_params().validate().unwrap();
    params.head_config().validate().unwrap();
    // Every slider's range lies inside what the models accept: all minima, all maxima.
    let p = &params;
    for x in [0.0, 1.0] {
        let breathing = BreathingParams {
            thorax_vs_abdomen: p.thorax_vs_abdomen.preview_plain(x),
            capacity_lung: p.capacity_lung.preview_plain(x),
            mouth_vs_nose: p.mouth_vs_nose.preview_plain(x),
            amplitude_breathing_sound: p.breath_sound.preview_plain(x),
            opening_inspiration_channels: p.opening.preview_plain(x),
            speaking_loudness: p.speaking_loudness.preview_plain(x),
            inspiration_length_s: p.inspiration_length_s.preview_plain(x),
            neck_motion_amplitude_deg: p.neck_amplitude_deg.preview_plain(x),
            ..BreathingParams::default()
        };
        breathing.validate().unwrap();
        let head = HeadConfig {
            amount: p.head_amount.preview_plain(x),
            max_pitch_deg: p.head_max_pitch_deg.preview_plain(x),
            max_yaw_deg: p.head_max_yaw_deg.preview_plain(x),
            max_roll_deg: p.head_max_roll_deg.preview_plain(x),
            ..HeadConfig::default()
        };
        head.validate().unwrap();
    }
    for preset in Preset::ALL {
        preset.params().validate().unwrap();
    }
}

#[test]
fn preset_choices_map_to_the_core_presets_by_index() {
    let ids = PresetChoice::ids().expect("ids");
    assert_eq!(ids.len(), Preset::ALL.len() + 1);
    let params = PneumaParams::default();
    for (i, preset) in Preset::ALL.into_iter().enumerate() {
        assert_eq!(ids[i + 1], preset.name());
        let choice = PresetChoice::from_index(i + 1);
        let normalized = params.preset.preview_normalized(choice);
        // SAFETY: `params` outlives the pointer.
        unsafe { param(&params, "preset")._internal_set_normalized_value(normalized) };
        assert_eq!(params.breathing_params(), preset.params(), "{choice:?}");
    }
}

#[test]
fn default_parameters_give_the_default_engine() {
    let params = PneumaParams::default();
    assert_eq!(params.engine_config(), EngineConfig::default());
    params.engine_config().validate().unwrap();
}

/// The parameter with this id (the pointer lives as long as `params`).
fn param(params: &PneumaParams, want: &str) -> ParamPtr {
    params
        .param_map()
        .into_iter()
        .find(|(id, _, _)| id == want)
        .map(|(_, ptr, _)| ptr)
        .unwrap_or_else(|| panic!("no parameter {want}"))
}

#[test]
fn every_parameter_text_parses_back_to_its_value() {
    let params = PneumaParams::default();
    for (id, ptr, _) in params.param_map() {
        // SAFETY: `params` outlives every pointer of its map.
        unsafe {
            // Both ends, the middle and the default of every parameter.
            for normalized in [0.0, 0.5, 1.0, ptr.default_normalized_value()] {
                let text = ptr.normalized_value_to_string(normalized, true);
                let back = ptr.string_to_normalized_value(&text);
                let text_back = back.map(|b| ptr.normalized_value_to_string(b, true));
                assert_eq!(
                    text_back.as_ref(),
                    Some(&text),
                    "{id}: {text:?} does not parse back"
                );
            }
        }
    }
    let cc = &params.cc_lung;
    // What users read and type (README), not the code's own constant.
    assert_eq!(cc.normalized_value_to_string(0.0, true), "off");
    assert_eq!(cc.string_to_normalized_value(" OFF "), Some(0.0));
    assert_eq!(parse_cc_text("17"), Some(17));
    assert_eq!(parse_cc_text("seventeen"), None);
}

#[test]
fn each_change_raises_its_flag_and_only_that() {
    let params = PneumaParams::default();
    let flags = params.changes.clone();
    let taken = || [&flags.engine, &flags.cc_map, &flags.structure].map(ChangeFlags::take);
    assert_eq!(taken(), [false; 3], "nothing changed yet");
    let change = |id: &str, normalized: f32| {
        // SAFETY: `params` outlives the pointer.
        unsafe { param(&params, id)._internal_set_normalized_value(normalized) };
        taken()
    };
    // [engine, CC map, structure]
    assert_eq!(change("breath_level_db", 0.9), [true, false, false]);
    assert_eq!(change("preset", 0.6), [true, false, false]);
    assert_eq!(change("bypass", 1.0), [true, false, false]);
    assert_eq!(change("cc_head_yaw", 0.0), [false, true, false]);
    assert_eq!(change("midi_channel", 1.0), [false, true, false]);
    assert_eq!(change("cc_head_range_deg", 0.2), [false, true, false]);
    assert_eq!(change("mode", 1.0), [true, false, true]);
    assert_eq!(change("lookahead_s", 1.0), [true, false, true]);
    assert_eq!(change("frame_rate_hz", 0.0), [true, false, true]);
    // The speech decision is a stream setting: a new engine, and the engine is told.
    assert!(params.engine_config().placement.speech_only);
    assert_eq!(change("speech_only", 0.0), [true, false, true]);
    assert!(!params.engine_config().placement.speech_only);
    assert_eq!(change("osc_port", 0.3), [false, false, false]);
    assert_eq!(change("midi_enabled", 0.0), [false, false, false]);
    // The same value again is no change.
    assert_eq!(change("mode", 1.0), [false, false, false]);
    // Bypass keeps the audio path but stops the breaths.
    assert!(!params.engine_config().placement.insert_breaths);
    // Every parameter raises a flag except the ones the audio thread reads each block.
    let read_each_block = [
        "midi_enabled",
        "osc_enabled",
        "osc_port",
        "osc_format",
        "freeze_breath_voice",
    ];
    for (id, ptr, _) in params.param_map() {
        // SAFETY: as above.
        unsafe {
            let now = ptr.unmodulated_normalized_value();
            ptr._internal_set_normalized_value(if now > 0.5 { 0.0 } else { 1.0 });
        }
        let raised = taken().contains(&true);
        assert_eq!(raised, !read_each_block.contains(&id.as_str()), "{id}");
    }
}

#[test]
fn persisted_settings_round_trip() {
    let params = PneumaParams::default();
    *params.osc_host.write().unwrap() = "192.168.1.20".into();
    params.breath_sample_nose.set_path("/tmp/nose.wav".into());
    params.breath_like.set_path("/tmp/raw take.wav".into());
    let frozen = Some(breath_voice::FrozenVoice::BuiltIn);
    let seen = params.breath_voice.restores();
    params.breath_voice.try_store(frozen, seen);
    let saved = params.serialize_fields();
    let fresh = PneumaParams::default();
    let before = fresh.breath_sample_nose.generation();
    fresh.deserialize_fields(&saved);
    assert_eq!(fresh.osc_host(), "192.168.1.20");
    assert_eq!(fresh.breath_sample_nose.get(), "/tmp/nose.wav");
    assert_eq!(fresh.breath_like.get(), "/tmp/raw take.wav");
    assert_eq!(fresh.breath_voice.get(), frozen);
    assert!(
        fresh.breath_voice.restores() > 0,
        "a restored voice is seen as a restore"
    );
    let after = fresh.breath_sample_nose.generation();
    assert!(after > before, "a restored path is seen as a change");
    // Restoring the same path again is no change (no needless restart).
    fresh.deserialize_fields(&saved);
    assert_eq!(fresh.breath_sample_nose.generation(), after);
    assert_eq!(fresh.breath_sample_mouth.get(), "");
}
