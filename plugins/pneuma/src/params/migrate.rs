//! Loading a state saved by an earlier version of the plugin ([`fill_defaults`], the plugin's
//! `filter_state`): nice-plug sets only the parameters and persisted fields a state names, so a
//! preset or project saved before a parameter existed, loaded into a running instance, would
//! keep that parameter's current value from whatever was loaded before (a breath voice frozen
//! in one project carried into another). Every parameter and field the state does not name
//! gets its default, as in a fresh instance.

use nice_plug::plugin::ParamValue;
use nice_plug::prelude::*;

use super::PneumaParams;

/// A parameter's default as a state stores it (as nice-plug serializes a value: plain floats
/// and integers, booleans, an enum by its stable id when it has one).
#[allow(unsafe_code)]
fn default_value(ptr: ParamPtr) -> ParamValue {
    // SAFETY: `ptr` comes from `param_map` of a `PneumaParams` the caller keeps alive for the
    // call; nice-plug's wrappers dereference the same pointers the same way.
    unsafe {
        match ptr {
            ParamPtr::FloatParam(p) => ParamValue::F32((*p).default_plain_value()),
            ParamPtr::IntParam(p) => ParamValue::I32((*p).default_plain_value()),
            ParamPtr::BoolParam(p) => ParamValue::Bool((*p).default_plain_value()),
            ParamPtr::EnumParam(p) => match (*p).unmodulated_plain_id() {
                // A fresh parameter's value is its default.
                Some(id) => ParamValue::String(id.to_owned()),
                None => ParamValue::I32((*p).default_plain_value()),
            },
        }
    }
}

/// Gives every parameter and persisted field `state` does not name its default.
pub fn fill_defaults(state: &mut PluginState) {
    let defaults = PneumaParams::default();
    for (id, ptr, _) in defaults.param_map() {
        state.params.entry(id).or_insert_with(|| default_value(ptr));
    }
    for (name, json) in defaults.serialize_fields() {
        state.fields.entry(name).or_insert(json);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_old_state_gets_the_defaults_of_what_it_does_not_name_and_keeps_the_rest() {
        let defaults = PneumaParams::default();
        let n_params = defaults.param_map().len();
        let n_fields = defaults.serialize_fields().len();
        // A state of an earlier version: one parameter with a value of its own, no freeze
        // switch, no breath voice or breath-like field.
        let mut state = PluginState {
            version: "0.1.0".into(),
            params: [("breath_level_db".to_owned(), ParamValue::F32(-30.0))].into(),
            fields: [("osc_host".to_owned(), "\"10.0.0.2\"".to_owned())].into(),
        };
        fill_defaults(&mut state);
        assert_eq!(state.params.len(), n_params);
        assert_eq!(state.fields.len(), n_fields);
        assert!(matches!(state.params["breath_level_db"], ParamValue::F32(v) if v == -30.0));
        assert_eq!(state.fields["osc_host"], "\"10.0.0.2\"");
        assert!(
            matches!(state.params["freeze_breath_voice"], ParamValue::Bool(false)),
            "the freeze switch is off in a state that never had it"
        );
        // Every filled value is the fresh instance's (a float and an enum for example).
        assert!(matches!(state.params["lookahead_s"], ParamValue::F32(v) if v == 0.5));
        assert!(matches!(
            state.params["mode"],
            ParamValue::String(_) | ParamValue::I32(_)
        ));
        // The fields a fresh instance saves: no frozen voice, no breath-like file.
        let fresh = defaults.serialize_fields();
        for name in ["breath_voice", "breath_like"] {
            assert_eq!(state.fields[name], fresh[name], "{name}");
        }
        // Every parameter a state names is set as it was saved.
        let mut full = state.clone();
        full.params
            .insert("freeze_breath_voice".into(), ParamValue::Bool(true));
        fill_defaults(&mut full);
        assert!(matches!(
            full.params["freeze_breath_voice"],
            ParamValue::Bool(true)
        ));
    }
}
