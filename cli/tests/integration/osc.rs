//! `pneuma render --osc` from the outside: a host that is not an address is refused before
//! anything is rendered, with what to give; a port nothing listens on is said in the summary
//! (the frames themselves are checked against the plugin's in
//! `tests/tests/integration/cli_osc.rs`).

use std::process::{Command, Stdio};

#[test]
fn an_osc_host_that_is_not_an_address_stops_the_render_before_it_starts() {
    let out = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .arg("render")
        .arg(pneuma_testkit::voice::example_voice_path())
        .args(["-o", "-", "--osc-host", "my-avatar-pc"])
        .stdout(Stdio::null())
        .output()
        .expect("pneuma runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--osc-host `my-avatar-pc` is not an IP address")
            && err
                .contains("give a numeric address such as 127.0.0.1 or 192.168.1.20, or localhost"),
        "{err}"
    );
}

/// Renders the example voice into `dir`, sending OSC as fast as possible with `osc_args`;
/// asserts it succeeded and returns its standard error.
fn render_sending(dir: &std::path::Path, osc_args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .arg("render")
        .arg(pneuma_testkit::voice::example_voice_path())
        .arg("-o")
        .arg(dir)
        .args(["--no-progress", "--no-plot", "--osc-speed", "max"])
        .args(osc_args)
        .output()
        .expect("pneuma runs");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(0), "{err}");
    err
}

#[test]
fn a_port_nothing_listens_on_is_said_with_what_to_do() {
    // A free port: bound, then closed again before the render.
    let port = std::net::UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .expect("a free port")
        .port();
    let dir = tempfile::tempdir().expect("temp");
    let err = render_sending(dir.path(), &["--osc-port", &port.to_string()]);
    assert!(
        err.contains(&format!("to 127.0.0.1:{port}"))
            && err.contains("refused, the others lost with them: nothing listens on that port"),
        "{err}"
    );
}

#[test]
fn a_target_the_socket_cannot_connect_to_still_renders_and_counts_what_failed() {
    // The broadcast address: a UDP socket without SO_BROADCAST can neither connect nor send
    // there. The render writes its files and says what failed.
    let dir = tempfile::tempdir().expect("temp");
    let err = render_sending(dir.path(), &["--osc-host", "255.255.255.255"]);
    assert!(dir.path().join("voice.wav").exists(), "{err}");
    assert!(
        err.contains("to 255.255.255.255:") && err.contains("not sent"),
        "{err}"
    );
}
