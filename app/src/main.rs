//! `pneuma-app`: Pneuma without a DAW. The microphone goes in, the voice with breaths comes
//! out, the head pose and breathing go to an avatar app over OSC/VMC and out as MIDI CC, and the
//! editor is the window. It is the plugin itself, run by nice-plug's standalone wrapper.
//!
//! Its own options (everything else goes to nice-plug's wrapper; `--help` lists both):
//! - `--no-gui`: no window, for headless streaming rigs; runs until Ctrl+C or SIGTERM.
//! - `--osc-host ADDR` (default 127.0.0.1), `--osc-port N` (default 39539, the VMC port),
//!   `--osc-format vmc|pneuma` (default vmc), `--no-osc`.
//! - `--lookahead`: lookahead mode (better breath timing, costs the lookahead in latency); the
//!   default is live mode, no latency.
//!
//! Audio: with no `--backend`, JACK when a JACK server runs (inputs connected with
//! `--connect-jack-inputs system:capture_1`, a virtual JACK MIDI output port `pneuma:midi_output`
//! for the CC), otherwise ALSA with the default input device. A backend that cannot start is an
//! error that says what to do; the app never runs silently on a dummy device unless asked
//! (`--backend dummy`). On JACK, a stopped server ends the app with a word and status 1
//! ([`watch`]). Ctrl+C and SIGTERM end it, window or not ([`quit`]).

mod options;
mod quit;
mod rest;
mod watch;

use std::process::ExitCode;

use nice_plug::prelude::nice_export_standalone_with_args;
use pneuma_plugin::editor::{set_headless, standalone};
use pneuma_plugin::Pneuma;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let opts = match options::parse(&args) {
        Ok(o) => o,
        Err(e) => {
            eprintln!("pneuma-app: {e}");
            return ExitCode::from(2);
        }
    };
    if opts.help {
        println!("{}", options::help());
    }
    set_headless(opts.no_gui);
    let _ = standalone::set_app_defaults(opts.defaults.clone());
    let backend = if opts.help {
        options::Backend {
            name: None,
            jack: None,
        }
    } else {
        match options::choose_backend(&opts) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("pneuma-app: {e}");
                return ExitCode::from(1);
            }
        }
    };
    let rest: rest::RestTarget = (!opts.no_osc).then(|| {
        let d = &opts.defaults;
        (d.osc_host.clone(), d.osc_port, d.osc_format.into())
    });
    // Ctrl+C and SIGTERM end the app, window or not (nice-plug's wrapper alone may not).
    if !opts.help {
        quit::watch(rest.clone());
    }
    // On JACK, a stopped server ends the app with a word (nice-plug's backend would hang).
    let _watch = options::uses_jack(&opts, backend)
        .then(|| watch::start(rest))
        .flatten();
    let wrapper_args = options::wrapper_args(&args[0], &opts, backend);
    if nice_export_standalone_with_args::<Pneuma, _>(wrapper_args) {
        ExitCode::SUCCESS
    } else {
        eprintln!(
            "pneuma-app: the audio backend stopped or could not start (see the message above). \
             JACK: start a server (`jackd -d alsa`, or PipeWire's JACK) and check the port names \
             with `jack_lsp`. ALSA: `--backend alsa --input-device ''` lists the devices."
        );
        ExitCode::from(1)
    }
}
