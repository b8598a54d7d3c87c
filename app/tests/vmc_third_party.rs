//! VMC checked by third-party code: the plugin's OSC sender (`pneuma_osc::worker`, the one the
//! app and the plugin use) sends VMC bundles for frames with a known head pose to `vmc_receiver.py`, which parses
//! them with python-osc and vmcp and checks bone names, the Unity frame, the quaternion order,
//! blendshape names, one `/VMC/Ext/Blend/Apply` per bundle and one bundle per frame.
//!
//! The receiver runs in a Python environment with `python-osc` and `vmcp`: `.ci/run` makes one
//! under `target/vmc-venv`. Without it the test says how to make it and passes only when
//! `PNEUMA_REQUIRE_VMC` is unset (local runs); `.ci/run` sets it.

use std::net::UdpSocket;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

use pneuma_core::encode::osc::OscFormat;
use pneuma_core::{ControlFrame, HeadAngles};
use pneuma_osc::worker::{self as osc_sender, OscSettings};

struct Target(u16);

impl OscSettings for Target {
    fn target(&self) -> (String, u16) {
        ("127.0.0.1".into(), self.0)
    }
    fn format(&self) -> OscFormat {
        OscFormat::Vmc
    }
}

fn python() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("PNEUMA_VMC_PYTHON") {
        return Some(PathBuf::from(p));
    }
    let venv = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/vmc-venv/bin/python");
    venv.exists().then_some(venv)
}

fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .map(|a| a.port())
        .expect("a free UDP port")
}

#[test]
fn vmc_bundles_pass_a_third_party_receiver() {
    let Some(python) = python() else {
        let msg = "no Python with python-osc and vmcp: run `python3 -m venv target/vmc-venv && \
                   target/vmc-venv/bin/pip install python-osc==1.10.2 vmcp==1.0.6`";
        assert!(std::env::var_os("PNEUMA_REQUIRE_VMC").is_none(), "{msg}");
        eprintln!("skipped: {msg}");
        return;
    };
    let (pitch, yaw, roll) = (10.0f32, 20.0f32, 5.0f32);
    let frames = 120;
    let port = free_udp_port();
    let ready = std::env::temp_dir().join(format!("pneuma-vmc-ready-{}", std::process::id()));
    let _ = std::fs::remove_file(&ready);
    let script = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/vmc_receiver.py");
    let receiver = Command::new(&python)
        .arg(&script)
        .args(["--port", &port.to_string()])
        .args(["--bundles", &frames.to_string()])
        .args(["--timeout-s", "30"])
        .args(["--expect-head", &format!("{pitch},{yaw},{roll}")])
        .arg("--ready-file")
        .arg(&ready)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the receiver");
    let t0 = Instant::now();
    while !ready.exists() {
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "receiver did not start"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let (mut feed, _worker, _stats) = osc_sender::start(Arc::new(Target(port))).unwrap();
    // Real time, 120 frames a second, the pose held (the last frame is what the receiver
    // checks); a few extra frames in case the first ones race the socket.
    for index in 0..(frames as u64 + 30) {
        let mut frame = ControlFrame {
            index,
            time_s: index as f64 / 120.0,
            head: HeadAngles {
                pitch_deg: pitch,
                yaw_deg: yaw,
                roll_deg: roll,
            },
            ..ControlFrame::default()
        };
        frame.breathing.lung = 0.5;
        frame.breathing.mouth_open = 0.25;
        feed.push(&frame);
        std::thread::sleep(Duration::from_micros(8333));
    }
    let out = receiver.wait_with_output().unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    println!("vmc receiver: {report}");
    assert!(
        out.status.success(),
        "the third-party receiver refused the VMC output: {report}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let _ = std::fs::remove_file(&ready);
}
