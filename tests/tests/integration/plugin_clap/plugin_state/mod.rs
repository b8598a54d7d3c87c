//! Sessions saved before the settings table (issue 34, point 1) keep their meaning.
//!
//! `tests/fixtures/plugin-state-before-settings-table.clap` is a state the plugin saved at
//! commit 459c225 (before the settings table) through this CLAP host, with every parameter
//! and every persisted field away from its default ([`SET`], [`FIELDS`]);
//! `plugin-state-before-settings-table.values` holds the CLAP value (normalized, or the step
//! index of a stepped parameter: what hosts store as automation) each parameter had then. The
//! test loads the state into today's plugin and checks every value against both.

use std::path::PathBuf;

use pneuma_tests::host::Plugin;

use pneuma_plugin::params::ADDED_SINCE_SETTINGS_TABLE;

use super::{load, PARAM_IDS};

/// Every parameter set away from its default: id, the text the host typed, and the plain value
/// nice-plug stores in the state (JSON, tagged with the parameter's type).
const SET: &[(&str, &str, &str)] = &[
    ("bypass", "On", r#"{"bool":true}"#),
    ("preset", "Tired", r#"{"string":"tired"}"#),
    ("thorax_vs_abdomen", "0.3", r#"{"f32":0.3}"#),
    ("capacity_lung", "45", r#"{"f32":45.0}"#),
    ("mouth_vs_nose", "0.8", r#"{"f32":0.8}"#),
    ("breath_sound", "0.6", r#"{"f32":0.6}"#),
    ("opening", "0.25", r#"{"f32":0.25}"#),
    ("speaking_loudness", "0.7", r#"{"f32":0.7}"#),
    ("inspiration_length_s", "1.6", r#"{"f32":1.6}"#),
    ("neck_amplitude_deg", "7.5", r#"{"f32":7.5}"#),
    ("breath_level_db", "-30", r#"{"f32":-30.0}"#),
    ("insert_breaths", "Off", r#"{"bool":false}"#),
    ("freeze_breath_voice", "On", r#"{"bool":true}"#),
    ("speech_only", "Off", r#"{"bool":false}"#),
    ("min_pause_s", "0.6", r#"{"f32":0.6}"#),
    ("mode", "Live", r#"{"string":"live"}"#),
    ("lookahead_s", "0.9", r#"{"f32":0.9}"#),
    ("head_amount", "2.5", r#"{"f32":2.5}"#),
    ("head_max_pitch_deg", "20", r#"{"f32":20.0}"#),
    ("head_max_yaw_deg", "35", r#"{"f32":35.0}"#),
    ("head_max_roll_deg", "6", r#"{"f32":6.0}"#),
    ("frame_rate_hz", "90", r#"{"i32":90}"#),
    ("midi_enabled", "Off", r#"{"bool":false}"#),
    ("midi_channel", "5", r#"{"i32":5}"#),
    ("cc_14bit", "On", r#"{"bool":true}"#),
    ("cc_head_range_deg", "45", r#"{"f32":45.0}"#),
    ("cc_lung", "3", r#"{"i32":3}"#),
    ("cc_head_pitch", "4", r#"{"i32":4}"#),
    ("cc_head_yaw", "5", r#"{"i32":5}"#),
    ("cc_head_roll", "6", r#"{"i32":6}"#),
    ("cc_thorax", "7", r#"{"i32":7}"#),
    ("cc_abdomen", "8", r#"{"i32":8}"#),
    ("cc_nostril_flare", "9", r#"{"i32":9}"#),
    ("cc_mouth_open", "10", r#"{"i32":10}"#),
    ("cc_neck_pitch", "11", r#"{"i32":11}"#),
    ("cc_speaking", "12", r#"{"i32":12}"#),
    ("cc_loudness", "off", r#"{"i32":0}"#),
    ("osc_enabled", "On", r#"{"bool":true}"#),
    ("osc_port", "9100", r#"{"i32":9100}"#),
    ("osc_format", "VMC", r#"{"string":"vmc"}"#),
];

/// Every persisted field away from its default: key and the JSON nice-plug stores for it.
const FIELDS: &[(&str, &str)] = &[
    ("osc_host", "\"192.168.1.20\""),
    ("breath_sample_mouth", "\"/samples/mouth.wav\""),
    ("breath_sample_nose", "\"/samples/nose.wav\""),
    (
        "editor_layout",
        "{\"width\":1234,\"height\":777,\"zoom\":1.5}",
    ),
];

fn fixture(name: &str) -> PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name)
}

const STATE: &str = "plugin-state-before-settings-table.clap";
const VALUES: &str = "plugin-state-before-settings-table.values";

/// `got` is the tagged plain value `want` (numbers within float rounding: the host hands over
/// normalized values, so 0.6 may be stored as 0.59999996).
fn same_plain(got: &serde_json::Value, want: &str) -> bool {
    let want: serde_json::Value = serde_json::from_str(want).expect("a tagged JSON value");
    match (got.as_object(), want.as_object()) {
        (Some(g), Some(w)) if g.len() == 1 && w.len() == 1 => {
            let (tag, w) = w.iter().next().unwrap();
            match (g.get(tag), w.as_f64()) {
                (Some(g), Some(w)) if tag == "f32" => g
                    .as_f64()
                    .is_some_and(|g| (g - w).abs() <= 1e-6 * w.abs().max(1.0)),
                (Some(g), _) => g == w,
                (None, _) => false,
            }
        }
        _ => false,
    }
}

/// The state's JSON.
fn json(state: &[u8]) -> serde_json::Value {
    serde_json::from_str(Plugin::state_json(state)).expect("the state is JSON")
}

#[test]
#[ignore = "writes the fixture from the bundle as it is; run only on the commit it documents"]
fn write_state_fixture() {
    let mut plugin = load();
    for (id, text, _) in SET {
        plugin.set_param(id, text).unwrap();
    }
    // Persisted fields have no host interface: edit them into a saved state and let the plugin
    // load it, then save what the plugin holds.
    let mut state = json(&plugin.save_state());
    for (key, value) in FIELDS {
        state["fields"][*key] = serde_json::Value::String((*value).to_owned());
    }
    let text = state.to_string();
    let mut edited = (text.len() as u64).to_le_bytes().to_vec();
    edited.extend_from_slice(text.as_bytes());
    plugin.load_state(&edited).unwrap();
    let saved = plugin.save_state();
    std::fs::write(fixture(STATE), &saved).unwrap();
    let mut values = String::from(
        "# CLAP value of every parameter after loading plugin-state-before-settings-table.clap\n\
         # into the plugin of commit 459c225, written by the commit that added this file with\n\
         # `cargo test -p pneuma-tests --test integration plugin_clap::plugin_state::write_state_fixture -- --ignored`\n",
    );
    for id in PARAM_IDS {
        let v = plugin.param_value(id).expect("every parameter has a value");
        values.push_str(&format!("{id} {v}\n"));
    }
    std::fs::write(fixture(VALUES), values).unwrap();
}

#[test]
fn a_state_saved_before_the_settings_table_keeps_every_value() {
    let saved = std::fs::read(fixture(STATE)).expect("the state fixture is committed");
    let before = json(&saved);
    // The fixture holds what was set: every parameter of its time, every field (the fixture
    // itself can fail); parameters added since are not in it.
    let added = |id: &str| ADDED_SINCE_SETTINGS_TABLE.contains(&id);
    for (id, _, plain) in SET {
        let got = &before["params"][*id];
        if added(id) {
            assert!(
                got.is_null(),
                "{id} is in the fixture but listed as added since"
            );
            continue;
        }
        assert!(
            same_plain(got, plain),
            "{id} in the fixture: {got}, set {plain}"
        );
    }
    for (key, value) in FIELDS {
        assert_eq!(before["fields"][*key], *value, "{key} in the fixture");
    }
    assert_eq!(SET.len(), PARAM_IDS.len(), "every parameter is set");

    let mut plugin = load();
    plugin.load_state(&saved).unwrap();
    // What hosts store for automation: the CLAP value of each parameter.
    let values = std::fs::read_to_string(fixture(VALUES)).expect("the values are committed");
    let mut checked = 0;
    for line in values.lines().filter(|l| !l.starts_with('#')) {
        let (id, want) = line.split_once(' ').expect("`id value` lines");
        let want: f64 = want.parse().unwrap();
        let got = plugin
            .param_value(id)
            .unwrap_or_else(|| panic!("{id} is gone"));
        assert!(
            (got - want).abs() <= 1e-6 * want.abs().max(1.0),
            "{id}: CLAP value {got}, before {want}"
        );
        checked += 1;
    }
    assert_eq!(checked, PARAM_IDS.len() - ADDED_SINCE_SETTINGS_TABLE.len());
    // Saved again, the state holds the same plain values and fields; a parameter added since
    // holds its default, as a fresh instance does.
    let after = json(&plugin.save_state());
    let fresh = json(&load().save_state());
    for (id, _, plain) in SET {
        let got = &after["params"][*id];
        if added(id) {
            assert_eq!(
                *got, fresh["params"][*id],
                "{id}: its default after an old state"
            );
            continue;
        }
        assert!(
            same_plain(got, plain),
            "{id} after loading: {got}, set {plain}"
        );
        assert_eq!(
            *got, before["params"][*id],
            "{id}: the plain value as saved"
        );
    }
    for (key, value) in FIELDS {
        assert_eq!(after["fields"][*key], *value, "{key} after loading");
    }
}
