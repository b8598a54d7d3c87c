//! The table: every setting of Pneuma in its group, in documentation order (`docs/settings.md`
//! is generated from it, [`super::doc`]).

use super::setting::Setting;
use super::{analysis, breathing, head, output, phrase, placement};

/// A group of settings: one part of the engine's settings or one output.
#[derive(Debug)]
pub struct Group {
    /// Short stable name (`breathing`, `placement`, ...).
    pub id: &'static str,
    /// Name for people; the plugin files its parameters of the group under it.
    pub name: &'static str,
    /// What the group is about.
    pub help: &'static str,
    /// Its settings, in documentation order.
    pub settings: &'static [&'static Setting],
}

/// Every group, in documentation order.
pub static GROUPS: [Group; 8] = [
    Group {
        id: "breathing",
        name: "Breathing",
        help: "The breathing model (Bernardet et al.): cycle, breath sounds, breath groups",
        settings: &breathing::SETTINGS,
    },
    Group {
        id: "placement",
        name: "Breaths & timing",
        help: "Where and how loud breaths go, and the delay that lets them fit",
        settings: &placement::SETTINGS,
    },
    Group {
        id: "head",
        name: "Head",
        help: "Head-pose synthesis (van Welbergen et al.)",
        settings: &head::SETTINGS,
    },
    Group {
        id: "analysis",
        name: "Analysis",
        help: "The analysis front end: frame clock, f0, voicing, level",
        settings: &analysis::SETTINGS,
    },
    Group {
        id: "speaker",
        name: "Speaker normalisation",
        help: "Running per-speaker f0 and level statistics (the frames' f0_st and level_db): the \
               breath detector's level rule and older head models read them",
        settings: &analysis::SPEAKER_SETTINGS,
    },
    Group {
        id: "phrase",
        name: "Phrases",
        help: "Phrase tracking: speech, pauses, breaths already in the input",
        settings: &phrase::SETTINGS,
    },
    Group {
        id: "midi",
        name: "MIDI CC",
        help: "The MIDI CC map (each signal's controller: docs/DESIGN.md, MIDI CC)",
        settings: &output::MIDI_SETTINGS,
    },
    Group {
        id: "osc",
        name: "OSC",
        help: "The OSC output's port and address space",
        settings: &output::OSC_SETTINGS,
    },
];

/// Every setting, group by group.
pub fn all() -> impl Iterator<Item = &'static Setting> {
    GROUPS.iter().flat_map(|g| g.settings.iter().copied())
}

/// The setting with this id.
pub fn find(id: &str) -> Option<&'static Setting> {
    all().find(|s| s.id == id)
}

/// The group holding `setting`.
pub fn group_of(setting: &Setting) -> Option<&'static Group> {
    GROUPS
        .iter()
        .find(|g| g.settings.iter().any(|s| std::ptr::eq(*s, setting)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::setting::Kind;

    #[test]
    fn ids_are_unique_and_named_with_their_units() {
        let ids: Vec<&str> = all().map(|s| s.id).collect();
        let mut unique = ids.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), ids.len(), "an id is used twice: {ids:?}");
        for s in all() {
            let suffix = match s.unit {
                crate::settings::Unit::Seconds => Some("_s"),
                crate::settings::Unit::Hertz => Some("_hz"),
                crate::settings::Unit::Decibels | crate::settings::Unit::DecibelsFs => Some("_db"),
                crate::settings::Unit::Degrees => Some("_deg"),
                crate::settings::Unit::DegreesPerSecond => Some("_deg_s"),
                _ => None,
            };
            if let Some(suffix) = suffix {
                assert!(s.id.ends_with(suffix), "{} is in {:?}", s.id, s.unit);
            }
        }
    }

    #[test]
    fn every_default_lies_in_its_range_and_every_range_is_explained() {
        for s in all() {
            s.check(f64::from(s.default))
                .unwrap_or_else(|e| panic!("default of {}: {e}", s.id));
            assert!(s.min() < s.max(), "{}: empty range", s.id);
            assert!(!s.help.is_empty() && !s.why.is_empty(), "{}", s.id);
            assert!(!s.label.is_empty(), "{}", s.id);
            if let Kind::Number { step, .. } = s.kind {
                assert!(
                    step > 0.0 && f64::from(step) <= s.max() - s.min(),
                    "{}",
                    s.id
                );
            }
        }
        assert!(find("breath_level_db").is_some() && find("nothing").is_none());
        assert_eq!(
            group_of(find("mode").unwrap()).map(|g| g.id),
            Some("placement")
        );
    }
}
