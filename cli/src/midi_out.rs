//! MIDI file options of `render` and `speak` (`--midi`, `--midi-14bit`,
//! `--midi-head-range-deg`): the plugin's CC map ([`CcMap::default`]) with the two choices the
//! plugin offers beside its controllers, its resolution and head range, taken from core's
//! settings table (`cc_14bit`, `cc_head_range_deg`: help, range and default). Off unless one of
//! the options is given: any `--midi-*` option turns `--midi` on, as any `--osc-*` option
//! turns on OSC ([`crate::osc_out::OscArgs::wanted`]). The file is core's
//! ([`pneuma_core::encode::midi_file`]).

use pneuma_core::encode::midi_cc::{CcMap, CcSignal};
use pneuma_core::settings::output::{CC_14BIT, CC_HEAD_RANGE_DEG};
use pneuma_core::settings::{set_field, Setting, Unit};

use crate::options::{render_for, MIDI_HEAD_RANGE};

/// `--midi`'s help: the default map as core numbers it.
fn midi_help() -> String {
    let map: Vec<String> = CcSignal::ALL
        .iter()
        .zip(CcSignal::DEFAULT_CONTROLLERS)
        .map(|(s, cc)| format!("{cc} {}", s.name()))
        .collect();
    format!(
        "Also write a Standard MIDI File of the CC lanes the plugin sends, `<stem>.mid` \
         (`speech.mid` from speak), at 120 BPM so a DAW places each change at its second; the \
         plugin's default map, channel 1, CC {}; also turned on by any --midi-* option",
        map.join(", ")
    )
}

/// `--midi-head-range-deg` in the table's range, in degrees.
fn head_range(text: &str) -> Result<f32, String> {
    CC_HEAD_RANGE_DEG
        .parse_in(text, MIDI_HEAD_RANGE.unit)
        .map(|v| v as f32)
        .map_err(|e| render_for(&[&MIDI_HEAD_RANGE], &e))
}

/// The MIDI options (flattened into a subcommand's arguments).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct MidiArgs {
    /// Also write the MIDI file (help text: `midi_help`).
    #[arg(long, help = midi_help())]
    pub midi: bool,
    /// 14-bit CC pairs (the table's `cc_14bit`; a switch: its help and default).
    #[arg(long, help = format!(
        "{} (default {}). Turns --midi on",
        CC_14BIT.help,
        CC_14BIT.default_text(Unit::None)
    ))]
    pub midi_14bit: bool,
    /// Head angle at the ends of the CC range, degrees (the table's `cc_head_range_deg`).
    #[arg(
        long,
        value_name = "DEG",
        help = format!("{}. Turns --midi on", MIDI_HEAD_RANGE.help()),
        value_parser = head_range
    )]
    pub midi_head_range_deg: Option<f32>,
}

impl MidiArgs {
    /// Whether a MIDI file is asked for: `--midi`, or any `--midi-*` option.
    pub fn wanted(&self) -> bool {
        self.midi || self.midi_14bit || self.midi_head_range_deg.is_some()
    }

    /// The CC map: the plugin's default with the resolution and head range asked for (the
    /// table's defaults where none is given). `Err` says what to change.
    pub fn map(&self) -> Result<CcMap, String> {
        let mut map = CcMap::default();
        let mut set = |setting: &Setting, value: f64| {
            set_field(&mut map, CcMap::fields(), setting.id, value)
                .unwrap_or_else(|| unreachable!("CcMap holds {}", setting.id))
                .map_err(|e| e.to_string())
        };
        if self.midi_14bit {
            set(&CC_14BIT, 1.0)?;
        }
        if let Some(deg) = self.midi_head_range_deg {
            set(&CC_HEAD_RANGE_DEG, f64::from(deg))?;
        }
        map.validate().map_err(|e| e.to_string())?;
        Ok(map)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;
    use pneuma_core::encode::midi_cc::CcResolution;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        midi: MidiArgs,
    }

    fn parse(args: &str) -> Result<MidiArgs, String> {
        Cli::try_parse_from(std::iter::once("pneuma").chain(args.split_whitespace()))
            .map(|c| c.midi)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn any_midi_option_turns_midi_on_and_sets_the_map() {
        let off = parse("").unwrap();
        assert!(!off.wanted());
        assert_eq!(
            off.map(),
            Ok(CcMap::default()),
            "the plugin's map by default"
        );
        let fine = parse("--midi-14bit").unwrap();
        assert!(fine.wanted(), "--midi-14bit without --midi");
        assert_eq!(fine.map().unwrap().resolution, CcResolution::Bits14);
        let range = parse("--midi-head-range-deg 12.5").unwrap();
        assert!(range.wanted(), "--midi-head-range-deg without --midi");
        let map = range.map().unwrap();
        assert_eq!(map.head_range_deg, 12.5);
        assert_eq!(map.resolution, CcMap::default().resolution);
    }

    #[test]
    fn a_head_range_outside_the_table_names_the_option_and_the_range() {
        let (below, above) = (CC_HEAD_RANGE_DEG.min() - 1.0, CC_HEAD_RANGE_DEG.max() + 1.0);
        for bad in [below.to_string(), above.to_string(), "wide".into()] {
            let e = parse(&format!("--midi-head-range-deg {bad}")).expect_err(&bad);
            assert!(e.contains("--midi-head-range-deg"), "{bad}: {e}");
            assert!(
                e.contains(&CC_HEAD_RANGE_DEG.range_text(Unit::Degrees)),
                "{bad}: {e}"
            );
        }
    }
}
