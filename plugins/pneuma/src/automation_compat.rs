//! Automation saved by earlier versions keeps its meaning: hosts store automation (and VST3
//! their parameter values) as normalized 0..1 values, so a parameter's range, skew or step
//! decides which plain value a saved curve means. `tests/fixtures/normalized-before-settings-table.txt`
//! (beside this crate's `Cargo.toml`) holds, for every parameter, the plain value at seven
//! normalized values and the normalized value at the minimum, default and maximum, as the
//! plugin computed them before the settings table (issue 34, point 1). The test checks that
//! today's parameters compute the same numbers.

// The parameters are walked through nice-plug's `ParamPtr`, whose methods are `unsafe` (the
// pointer must not outlive its `PneumaParams`, which the tests keep alive).
#![allow(unsafe_code)]

use nice_plug::prelude::*;

use crate::params::{PneumaParams, ADDED_SINCE_SETTINGS_TABLE as ADDED_SINCE};

/// The fixture's path.
fn fixture_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests")
        .join("fixtures")
        .join("normalized-before-settings-table.txt")
}

/// Normalized values at which the plain value is recorded.
const NORMALIZED: [f32; 7] = [0.0, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0];

#[test]
#[ignore = "writes the fixture from the code as it is; run only on the commit it documents"]
fn write_fixture() {
    use std::fmt::Write as _;
    let params = PneumaParams::default();
    let mut out = String::from(
        "# Normalized <-> plain values of every Pneuma parameter before the settings table\n\
         # (issue 34, point 1): the plugin of commit 459c225, written by the commit that added this\n\
         # file with `cargo test -p pneuma-plugin --lib automation_compat::write_fixture -- --ignored`.\n\
         # Lines: `<id> normalized <n> plain <p>` (preview_plain(n) = p) and\n\
         # `<id> plain <p> normalized <n>` (preview_normalized(p) = n) at min, default, max.\n",
    );
    for (id, ptr, _) in params.param_map() {
        // SAFETY: `params` outlives `ptr`.
        unsafe {
            for n in NORMALIZED {
                writeln!(out, "{id} normalized {n} plain {}", ptr.preview_plain(n)).unwrap();
            }
            let plains = [
                ptr.preview_plain(0.0),
                ptr.default_plain_value(),
                ptr.preview_plain(1.0),
            ];
            for p in plains {
                writeln!(
                    out,
                    "{id} plain {p} normalized {}",
                    ptr.preview_normalized(p)
                )
                .unwrap();
            }
        }
    }
    std::fs::write(fixture_path(), out).unwrap();
}

#[test]
fn saved_automation_means_the_same_plain_values_as_before() {
    let text = std::fs::read_to_string(fixture_path()).expect("the fixture is committed");
    let params = PneumaParams::default();
    let map = params.param_map();
    let mut seen = std::collections::BTreeSet::new();
    let mut lines = 0;
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
    {
        let words: Vec<&str> = line.split(' ').collect();
        let [id, from, a, _, b] = words[..] else {
            panic!("bad fixture line {line:?}");
        };
        let (a, b): (f32, f32) = (a.parse().unwrap(), b.parse().unwrap());
        let ptr = map
            .iter()
            .find(|(i, _, _)| i == id)
            .map(|(_, p, _)| *p)
            .unwrap_or_else(|| panic!("parameter {id} is gone: saved sessions lose it"));
        // SAFETY: `params` outlives `ptr`.
        let (got, want) = unsafe {
            match from {
                "normalized" => (ptr.preview_plain(a), b),
                "plain" => (ptr.preview_normalized(a), b),
                other => panic!("bad fixture line kind {other:?}"),
            }
        };
        assert!(
            (got - want).abs() <= 1e-6 * want.abs().max(1.0),
            "{id}: {from} {a} now gives {got}, before {want}"
        );
        seen.insert(id.to_owned());
        lines += 1;
    }
    let ids: std::collections::BTreeSet<String> = map
        .iter()
        .map(|(id, _, _)| id.clone())
        .filter(|id| !ADDED_SINCE.contains(&id.as_str()))
        .collect();
    assert_eq!(
        seen, ids,
        "every parameter but the ones added since is in the fixture"
    );
    assert_eq!(lines, ids.len() * 10);
    for id in ADDED_SINCE {
        assert!(
            map.iter().any(|(i, _, _)| i == id),
            "{id} is listed as added but is no parameter"
        );
    }
}
