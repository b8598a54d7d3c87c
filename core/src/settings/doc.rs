//! The settings table as Markdown: `docs/settings.md` is this text (this module's test holds
//! the file to it; `PNEUMA_BLESS=1` rewrites it), so the documentation's list of settings is
//! derived from the table like the doors' options and parameters.

use super::setting::{Kind, Scope};
use super::table::GROUPS;

/// The Markdown page listing every setting, group by group: id, range with unit, default,
/// when a change takes effect, what it does and why the range is what it is.
pub fn markdown() -> String {
    let mut out = String::from(
        "# Settings\n\n\
         <!-- Generated from core/src/settings/ (settings::doc): edit the table, then run\n\
         `PNEUMA_BLESS=1 cargo test -p pneuma-core --lib settings::doc`. -->\n\n\
         Every setting of Pneuma with its id (the plugin's parameter id where the plugin has\n\
         one, the name `EngineConfig::set` and the evaluations' `--set` take), its range and\n\
         default, and when a change takes effect: *live* at once, *stream* at the next\n\
         `prepare` (in the plugin: a new engine, built in the background). The command line's\n\
         options give some of them in other units (`--min-pause-ms`); their help says which.\n",
    );
    for group in &GROUPS {
        out.push_str(&format!(
            "\n## {} (`{}`)\n\n{}.\n\n",
            group.name, group.id, group.help
        ));
        out.push_str("| id | range | default | takes effect | what it does | why this range |\n");
        out.push_str("|---|---|---|---|---|---|\n");
        for s in group.settings {
            let range = match s.kind {
                Kind::Switch => "on or off".to_owned(),
                _ => s.range_text(s.unit),
            };
            let scope = match s.scope {
                Scope::Live => "live",
                Scope::Stream => "stream",
            };
            out.push_str(&format!(
                "| `{}` | {} | {} | {} | {} | {} |\n",
                s.id,
                cell(&range),
                cell(&s.default_text(s.unit)),
                scope,
                cell(s.help),
                cell(s.why)
            ));
        }
    }
    out
}

/// Text safe in a Markdown table cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `docs/settings.md` beside the core crate.
    fn path() -> std::path::PathBuf {
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/settings.md")
    }

    #[test]
    fn docs_settings_md_is_the_table() {
        let want = markdown();
        if std::env::var_os("PNEUMA_BLESS").is_some() {
            std::fs::write(path(), &want).expect("write docs/settings.md");
        }
        let have = std::fs::read_to_string(path()).unwrap_or_default();
        assert!(
            have == want,
            "docs/settings.md is not the settings table: run `PNEUMA_BLESS=1 cargo test -p \
             pneuma-core --lib settings::doc` and commit the file"
        );
        // Facts a reader relies on, written out here.
        for row in [
            "| `breath_level_db` | -40 to -6 dB | -22 dB | live |",
            "| `frame_rate_hz` | 30 to 240 Hz | 120 Hz | stream |",
            "| `lowpass_hz` | 0 (off) or 500 to 3500 Hz | 1800 Hz | stream |",
            "| `mode` | lookahead or live | lookahead | stream |",
            "| `insert_breaths` | on or off | on | live |",
        ] {
            assert!(want.contains(row), "{row}");
        }
    }
}
