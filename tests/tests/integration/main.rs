//! End-to-end tests, one module per subject, in one test binary (one build and one link
//! instead of four): [`plugin_clap`] and [`osc_udp`] load the plugin library through a CLAP host
//! (`pneuma_tests::bundle` says which library), [`example_voice`] checks the shipped voice, and
//! [`ardour`] holds the checks `tests/ardour/run.sh` runs (ignored in `cargo test`).

mod ardour;
mod cli_midi;
mod cli_osc;
mod example_voice;
mod osc_udp;
mod plugin_clap;
