//! The app's own command-line options, split from the ones nice-plug's standalone wrapper takes.
//! `--osc-port` and `--osc-format` are settings of core's table (`osc_port`, `osc_format`):
//! their range, names and the port's default come from it.

use nice_plug::prelude::Enum;
use pneuma_core::settings::output::{OSC_FORMAT, OSC_PORT};
use pneuma_core::settings::{Setting, Unit};
use pneuma_osc::{DEFAULT_OSC_HOST, DEFAULT_OSC_PORT};
use pneuma_plugin::editor::standalone::AppDefaults;
use pneuma_plugin::params::OscFormatChoice;

/// The app's help (printed before nice-plug's own).
pub fn help() -> String {
    format!(
        "\
pneuma-app: Pneuma live: microphone in, voice with breaths out, head pose and breathing to an
avatar app (OSC/VMC) and as MIDI CC.

Pneuma options:
      --no-gui              No window (headless rigs); runs until Ctrl+C
      --osc-host <ADDR>     OSC/VMC target address, numeric or localhost [default: 127.0.0.1]
      --osc-port <PORT>     OSC/VMC target port, {ports} [default: {port}]
      --osc-format <FMT>    {formats} [default: vmc]
      --no-osc              Send no OSC
      --lookahead           Lookahead mode (better breath timing, adds latency); default: live

Audio and MIDI options (nice-plug's standalone wrapper) follow.
",
        ports = OSC_PORT.range_text(Unit::None),
        port = OSC_PORT.default_text(Unit::None),
        formats = OSC_FORMAT.range_text(Unit::None),
    )
}

/// The value of `setting` that `text` gives, the error naming `flag`.
fn table_value(flag: &str, setting: &'static Setting, text: &str) -> Result<f64, String> {
    setting
        .parse(text)
        .map_err(|e| e.render(&|s| (flag.to_owned(), s.unit)))
}

/// What the app's own options say.
#[derive(Debug, Clone, PartialEq)]
pub struct AppOptions {
    /// No window.
    pub no_gui: bool,
    /// `--help` was asked.
    pub help: bool,
    /// The parameters' defaults for this process.
    pub defaults: AppDefaults,
    /// OSC off.
    pub no_osc: bool,
    /// The backend the user named (`-b`/`--backend`), if any.
    pub backend: Option<String>,
    /// The user named an input device.
    pub has_input_device: bool,
    /// The user named a sample rate or period size.
    pub has_rate: bool,
    /// Arguments for nice-plug's wrapper, in order.
    pub rest: Vec<String>,
}

fn value<'a>(args: &'a [String], i: &mut usize, name: &str) -> Result<&'a str, String> {
    *i += 1;
    args.get(*i)
        .map(String::as_str)
        .ok_or_else(|| format!("{name} needs a value"))
}

/// Parses `args` (the program name first).
pub fn parse(args: &[String]) -> Result<AppOptions, String> {
    let mut o = AppOptions {
        no_gui: false,
        help: false,
        defaults: AppDefaults {
            live: true,
            osc_host: DEFAULT_OSC_HOST.to_owned(),
            osc_port: DEFAULT_OSC_PORT,
            osc_format: OscFormatChoice::Vmc,
        },
        no_osc: false,
        backend: None,
        has_input_device: false,
        has_rate: false,
        rest: Vec::new(),
    };
    let mut i = 1;
    while i < args.len() {
        let a = args[i].as_str();
        let (flag, inline) = match a.split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f, Some(v.to_owned())),
            _ => (a, None),
        };
        let take = |i: &mut usize| -> Result<String, String> {
            match &inline {
                Some(v) => Ok(v.clone()),
                None => value(args, i, flag).map(str::to_owned),
            }
        };
        match flag {
            "--no-gui" => o.no_gui = true,
            "--no-osc" => o.no_osc = true,
            "--lookahead" => o.defaults.live = false,
            "--osc-host" => {
                let host = take(&mut i)?;
                if host.trim().is_empty() {
                    return Err(
                        "--osc-host is empty: give a numeric address such as 127.0.0.1 \
                                or 192.168.1.20, or localhost"
                            .into(),
                    );
                }
                // The check the plugin's sender makes, at start rather than silently later
                // (the same words as the CLI's).
                if pneuma_osc::target::resolve(&host, DEFAULT_OSC_PORT).is_none() {
                    return Err(format!(
                        "--osc-host {}",
                        pneuma_osc::paced::OpenError::NotAnAddress(host)
                    ));
                }
                o.defaults.osc_host = host;
            }
            "--osc-port" => {
                let port = table_value(flag, &OSC_PORT, &take(&mut i)?)?;
                // In the table's range 1..=65535.
                o.defaults.osc_port = port as u16;
            }
            "--osc-format" => {
                let index = table_value(flag, &OSC_FORMAT, &take(&mut i)?)?;
                o.defaults.osc_format = OscFormatChoice::from_index(index as usize);
            }
            "-h" | "--help" => {
                o.help = true;
                o.rest.push(a.to_owned());
            }
            "-b" | "--backend" => {
                let v = take(&mut i)?;
                o.backend = Some(v.clone());
                o.rest.extend(["--backend".to_owned(), v]);
            }
            _ => {
                match flag {
                    "--input-device" => o.has_input_device = true,
                    "-r" | "--sample-rate" | "-p" | "--period-size" => o.has_rate = true,
                    _ => {}
                }
                o.rest.push(a.to_owned());
            }
        }
        i += 1;
    }
    Ok(o)
}

/// The backend to use and, for JACK, the server's rate and period.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Backend {
    /// The backend to name to nice-plug, or `None` where the user named one.
    pub name: Option<&'static str>,
    /// A running JACK server, as the probe found it.
    pub jack: Option<JackServer>,
}

/// Where no backend was named: JACK when a server answers, otherwise ALSA. A named backend is
/// passed on; `jack` named with no server running is an error that says what to do.
pub fn choose_backend(o: &AppOptions) -> Result<Backend, String> {
    let named = o.backend.as_deref();
    let jack = match named {
        None | Some("jack") | Some("auto") => jack_server(),
        _ => None,
    };
    if named == Some("jack") && jack.is_none() {
        return Err(
            "--backend jack: no JACK server answers. Start one (`jackd -d alsa`, \
                    `jackd -d dummy` for tests, or PipeWire's JACK), or use --backend alsa"
                .into(),
        );
    }
    // (The probe ran only for no backend, `jack` or `auto`.)
    if jack.is_some_and(|j| j.taken) {
        return Err(format!(
            "the JACK server already has a client named `{JACK_CLIENT}` (another pneuma-app, or \
             one that did not quit: `jack_lsp` lists its ports): quit it first"
        ));
    }
    let name = match named {
        Some(_) => None,
        None if jack.is_some() => Some("jack"),
        None => Some("alsa"),
    };
    Ok(Backend { name, jack })
}

/// The JACK client name nice-plug's wrapper opens (the plugin's name in lower case).
const JACK_CLIENT: &str = "pneuma";

/// A running JACK server as the probe finds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct JackServer {
    /// Sample rate, Hz.
    pub rate: u32,
    /// Period, samples.
    pub period: u32,
    /// A client named [`JACK_CLIENT`] runs already: the wrapper's would be refused.
    pub taken: bool,
}

/// A running JACK server (a client opens without starting a server). None where no server
/// runs or the JACK library is missing.
fn jack_server() -> Option<JackServer> {
    match jack::Client::new("pneuma_probe", jack::ClientOptions::NO_START_SERVER) {
        Ok((client, status)) if status.is_empty() => Some(JackServer {
            rate: client.sample_rate(),
            period: client.buffer_size(),
            taken: !client
                .ports(
                    Some(&format!("^{JACK_CLIENT}:")),
                    None,
                    jack::PortFlags::empty(),
                )
                .is_empty(),
        }),
        _ => None,
    }
}

/// Whether the app runs on a JACK server: the chosen backend, or the user's `jack` or `auto`
/// with a server running.
pub fn uses_jack(o: &AppOptions, backend: Backend) -> bool {
    backend.jack.is_some()
        && (backend.name == Some("jack")
            || matches!(o.backend.as_deref(), Some("jack") | Some("auto")))
}

/// The arguments for nice-plug's wrapper: the program name, the chosen backend, for JACK the
/// server's rate and period (nice-plug 0.4.2 hands the plugin its `--sample-rate`, 48 kHz by
/// default, whatever rate JACK runs at), for ALSA the default input device unless one was
/// named, then the user's other arguments.
pub fn wrapper_args(program: &str, o: &AppOptions, backend: Backend) -> Vec<String> {
    let mut out = vec![program.to_owned()];
    if let Some(b) = backend.name {
        out.extend(["--backend".to_owned(), b.to_owned()]);
    }
    if let (true, false, Some(j)) = (uses_jack(o, backend), o.has_rate, backend.jack) {
        out.extend([
            "--sample-rate".to_owned(),
            j.rate.to_string(),
            "--period-size".to_owned(),
            j.period.to_string(),
        ]);
    }
    let alsa = backend.name == Some("alsa") || o.backend.as_deref() == Some("alsa");
    if alsa && !o.has_input_device {
        out.extend(["--input-device".to_owned(), "default".to_owned()]);
    }
    out.extend(o.rest.iter().cloned());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(s: &str) -> Vec<String> {
        std::iter::once("pneuma-app")
            .chain(s.split_whitespace())
            .map(str::to_owned)
            .collect()
    }

    #[test]
    fn app_options_are_taken_and_the_rest_goes_to_the_wrapper() {
        let o = parse(&args(
            "--no-gui --osc-port=39540 --osc-host 192.168.1.20 --osc-format pneuma -b jack \
             --connect-jack-inputs system:capture_1",
        ))
        .unwrap();
        assert!(o.no_gui && o.defaults.live);
        assert_eq!(o.defaults.osc_port, 39540);
        assert_eq!(o.defaults.osc_host, "192.168.1.20");
        assert_eq!(o.defaults.osc_format, OscFormatChoice::Pneuma);
        let jack = Backend {
            name: None,
            jack: Some(JackServer {
                rate: 16_000,
                period: 256,
                taken: false,
            }),
        };
        assert_eq!(
            wrapper_args("pneuma-app", &o, jack),
            args(
                "--sample-rate 16000 --period-size 256 --backend jack \
                 --connect-jack-inputs system:capture_1"
            ),
            "JACK's own rate reaches the plugin"
        );
        let o = parse(&args("--lookahead")).unwrap();
        assert!(!o.defaults.live && !o.no_gui);
        assert_eq!(
            o.defaults.osc_format,
            OscFormatChoice::Vmc,
            "VMC by default"
        );
        assert_eq!(
            wrapper_args(
                "pneuma-app",
                &o,
                Backend {
                    name: Some("alsa"),
                    jack: None
                }
            ),
            args("--backend alsa --input-device default"),
            "ALSA takes the default microphone"
        );
    }

    #[test]
    fn bad_options_say_what_to_give() {
        for (a, wanted) in [
            (
                "--osc-port 0",
                "--osc-port 0 is out of range: use 1 to 65535",
            ),
            (
                "--osc-port x",
                "--osc-port: `x` is not a number: use 1 to 65535",
            ),
            (
                "--osc-format osc",
                "--osc-format: `osc` is not one of pneuma or vmc",
            ),
            ("--osc-host", "needs a value"),
            (
                "--osc-host avatar-pc.local",
                "--osc-host `avatar-pc.local` is not an IP address",
            ),
        ] {
            let e = parse(&args(a)).unwrap_err();
            assert!(e.contains(wanted), "{a}: {e}");
        }
        let help = help();
        assert!(help.contains("1 to 65535 [default: 39539]"), "{help}");
        assert!(help.contains("pneuma or vmc [default: vmc]"), "{help}");
    }
}
