//! OSC output from `render` and `speak` (`--osc`, `--osc-host`, `--osc-port`, `--osc-format`,
//! `--osc-speed`): the control frames sent over UDP as the plugin sends them, through the
//! shared sender of `pneuma-osc` ([`pneuma_osc::paced`]), in real time by default or at a
//! multiple of it. The option names are `pneuma-app`'s; the port's and format's range, names
//! and defaults are core's settings table's (`osc_port`, `osc_format`). Off unless one of the
//! options is given.

use pneuma_core::encode::osc::OscFormat;
use pneuma_core::settings::output::{OSC_FORMAT, OSC_PORT};
use pneuma_core::settings::{Setting, Unit};
use pneuma_osc::paced::{PacedSender, PacedStats, Speed};
use pneuma_osc::{format_of_index, OscError, DEFAULT_OSC_HOST, DEFAULT_OSC_PORT};

/// The OSC options (flattened into a subcommand's arguments).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct OscArgs {
    /// Send the control frames as OSC bundles over UDP while rendering, as the plugin sends
    /// them (also turned on by any --osc-* option).
    #[arg(long)]
    pub osc: bool,
    /// OSC target address, numeric or localhost [default: 127.0.0.1].
    #[arg(long, value_name = "ADDR")]
    pub osc_host: Option<String>,
    /// OSC target port.
    #[arg(long, value_name = "PORT", help = setting_help(&OSC_PORT), value_parser = port)]
    pub osc_port: Option<u16>,
    /// OSC address space.
    #[arg(long, value_name = "FMT", help = setting_help(&OSC_FORMAT), value_parser = format)]
    pub osc_format: Option<OscFormat>,
    /// How fast the frames are sent: a multiple of real time (1: as the audio plays, 4: four
    /// times as fast) or max [default: 1]; the render takes the audio's length divided by it.
    #[arg(long, value_name = "SPEED", value_parser = Speed::parse)]
    pub osc_speed: Option<Speed>,
}

/// The table's help, range and default of `setting`.
fn setting_help(setting: &Setting) -> String {
    crate::options::table_help(setting, Unit::None)
}

/// `--osc-port` in the table's range.
fn port(text: &str) -> Result<u16, String> {
    OSC_PORT
        .parse(text)
        .map(|p| p as u16)
        .map_err(|e| e.render(&|s| ("--osc-port".to_owned(), s.unit)))
}

/// `--osc-format`: one of the table's names.
fn format(text: &str) -> Result<OscFormat, String> {
    OSC_FORMAT
        .parse(text)
        .map(|i| format_of_index(i as usize))
        .map_err(|e| e.render(&|s| ("--osc-format".to_owned(), s.unit)))
}

/// Where and how the frames go, checked before anything is rendered.
#[derive(Debug, Clone, PartialEq)]
pub struct OscPlan {
    /// Target address as given.
    pub host: String,
    /// Target port.
    pub port: u16,
    /// Address space.
    pub format: OscFormat,
    /// Pace.
    pub speed: Speed,
}

impl OscArgs {
    /// Whether OSC is asked for.
    pub fn wanted(&self) -> bool {
        self.osc
            || self.osc_host.is_some()
            || self.osc_port.is_some()
            || self.osc_format.is_some()
            || self.osc_speed.is_some()
    }

    /// The plan, `None` when OSC is off; `Err` (naming `--osc-host` and what to give) when the
    /// host is not an address.
    pub fn plan(&self) -> Result<Option<OscPlan>, String> {
        if !self.wanted() {
            return Ok(None);
        }
        let plan = OscPlan {
            host: self
                .osc_host
                .clone()
                .unwrap_or_else(|| DEFAULT_OSC_HOST.to_owned()),
            port: self.osc_port.unwrap_or(DEFAULT_OSC_PORT),
            format: self
                .osc_format
                .unwrap_or_else(|| format_of_index(OSC_FORMAT.default as usize)),
            speed: self.osc_speed.unwrap_or(Speed::Times(1.0)),
        };
        // The same check the sender makes, before a long render rather than after.
        if pneuma_osc::target::resolve(&plan.host, plan.port).is_none() {
            return Err(format!(
                "--osc-host {}",
                pneuma_osc::paced::OpenError::NotAnAddress(plan.host.clone())
            ));
        }
        Ok(Some(plan))
    }
}

impl OscPlan {
    /// Opens the sender; the error names `--osc-host` and says what to do.
    pub fn open(&self) -> Result<PacedSender, String> {
        PacedSender::open(&self.host, self.port, self.format, self.speed)
            .map_err(|e| format!("--osc-host {}: {e}", self.host))
    }

    /// Ends the stream in the rest pose ([`PacedSender::rest`]) and says what was sent
    /// ([`OscPlan::describe`]).
    pub fn finish(&self, mut sender: PacedSender) -> String {
        sender.rest();
        self.describe(&sender.stats())
    }

    /// The summary line of what was sent: `OSC: 1200 bundles (vmc) to 127.0.0.1:39539 in
    /// real time, ending in the rest pose` (when it went out), and the reason when frames were
    /// not sent; as fast as possible, what to do when a receiver drops bundles.
    pub fn describe(&self, stats: &PacedStats) -> String {
        let format = OSC_FORMAT.names()[match self.format {
            OscFormat::Pneuma => 0,
            OscFormat::Vmc => 1,
        }];
        let host = self.host.trim();
        // An IPv6 address in brackets, so its port reads apart from it.
        let host = if host.contains(':') {
            format!("[{host}]")
        } else {
            host.to_owned()
        };
        let mut line = format!(
            "OSC: {} ({format}) to {host}:{} {}",
            crate::options::count((stats.sent + stats.failed) as usize, "bundle"),
            self.port,
            match self.speed {
                // A receiver that reads slower than the sender drops what overflows its
                // socket buffer (a Python receiver here took 2242 of 3867; at 8x, all).
                Speed::Max => "as fast as possible (if the receiver drops bundles, give a \
                               speed such as --osc-speed 8)"
                    .to_owned(),
                s => format!("in {s}"),
            }
        );
        if stats.rested {
            line.push_str(", ending in the rest pose");
        }
        match (stats.failed, stats.last_error) {
            // A connected socket hears a refusal on the send after a lost bundle: those it
            // counted as sent were lost as well.
            (n @ 1.., Some(e @ OscError::Refused)) => {
                line.push_str(&format!(
                    "; {n} refused, the others lost with them: {}",
                    e.text()
                ));
            }
            (n @ 1.., Some(e)) => line.push_str(&format!("; {n} not sent: {}", e.text())),
            _ => {}
        }
        line
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        osc: OscArgs,
    }

    fn parse(args: &str) -> Result<OscArgs, String> {
        Cli::try_parse_from(std::iter::once("pneuma").chain(args.split_whitespace()))
            .map(|c| c.osc)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn osc_is_off_unless_asked_and_defaults_come_from_the_table() {
        assert_eq!(parse("").unwrap().plan(), Ok(None));
        let plan = parse("--osc").unwrap().plan().unwrap().unwrap();
        assert_eq!(
            plan,
            OscPlan {
                host: "127.0.0.1".into(),
                port: 39539,
                format: OscFormat::Pneuma,
                speed: Speed::Times(1.0),
            }
        );
        let plan = parse("--osc-format VMC --osc-port 9000 --osc-speed max")
            .unwrap()
            .plan()
            .unwrap()
            .unwrap();
        assert_eq!(
            (plan.format, plan.port, plan.speed),
            (OscFormat::Vmc, 9000, Speed::Max)
        );
    }

    #[test]
    fn bad_values_say_what_to_give() {
        for (args, wanted) in [
            (
                "--osc-port 0",
                "--osc-port 0 is out of range: use 1 to 65535",
            ),
            (
                "--osc-format osc",
                "--osc-format: `osc` is not one of pneuma or vmc",
            ),
            ("--osc-speed 0", "or max"),
        ] {
            let e = parse(args).expect_err(args);
            assert!(e.contains(wanted), "{args}: {e}");
        }
        let e = parse("--osc-host my-avatar-pc")
            .unwrap()
            .plan()
            .unwrap_err();
        assert!(
            e.starts_with("--osc-host `my-avatar-pc` is not an IP address")
                && e.contains("192.168.1.20, or localhost"),
            "{e}"
        );
    }
}
