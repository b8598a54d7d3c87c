//! Every setting of Pneuma in one table (issue 34, point 1): id, label, unit, range, default,
//! scope (live or stream), help, and why the range is what it is ([`Setting`]), in groups
//! ([`GROUPS`]). Core's validation and string setters walk it through [`Field`] bindings; the
//! doors derive from it the CLI's options and their messages, the plugin's parameters, their
//! groups, `pneuma-app`'s OSC options, and `docs/settings.md` ([`doc`]; a test holds the file
//! to the table).
//!
//! - [`setting`]: the types ([`Setting`], [`Unit`], [`Kind`], [`Scope`], [`SettingError`],
//!   [`Field`]) and the checks and text conversions;
//! - [`table`]: the groups in documentation order, [`all`], [`find`];
//! - [`doc`]: the table as Markdown (`docs/settings.md`);
//! - one file per group: [`breathing`], [`placement`], [`head`], [`analysis`] (with the
//!   speaker normalisation), [`phrase`], [`output`] (MIDI CC and OSC).

pub mod analysis;
pub mod breathing;
pub mod doc;
pub mod head;
pub mod output;
pub mod phrase;
pub mod placement;
pub mod setting;
pub mod table;

pub use setting::{
    check_fields, copy_scope, find_field, sanitize_fields, set_field, set_field_text, show_number,
    Field, Kind, Relation, Scope, Setting, SettingError, Unit,
};
pub use table::{all, find, group_of, Group, GROUPS};
