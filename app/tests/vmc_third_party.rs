//! VMC checked by third-party code: the plugin's OSC sender (`pneuma_osc::worker`, the one the
//! app and the plugin use) sends VMC bundles for frames with a known head pose to `vmc_receiver.py`, which parses
//! them with python-osc and vmcp and checks bone names, the Unity frame, the quaternion order,
//! blendshape names, one `/VMC/Ext/Blend/Apply` per bundle and one bundle per frame.
//!
//! The receiver and its Python are the testkit's ([`pneuma_testkit::vmc`]): without that Python
//! the test says how to make it and passes only when `PNEUMA_REQUIRE_VMC` is unset (local runs);
//! `.ci/run` sets it.

use std::net::UdpSocket;
use std::sync::Arc;
use std::time::Duration;

use pneuma_core::encode::osc::OscFormat;
use pneuma_core::{ControlFrame, HeadAngles};
use pneuma_osc::worker::{self as osc_sender, OscSettings};
use pneuma_testkit::vmc;

struct Target(u16);

impl OscSettings for Target {
    fn target(&self) -> (String, u16) {
        ("127.0.0.1".into(), self.0)
    }
    fn format(&self) -> OscFormat {
        OscFormat::Vmc
    }
}

fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .and_then(|s| s.local_addr())
        .map(|a| a.port())
        .expect("a free UDP port")
}

#[test]
fn vmc_bundles_pass_a_third_party_receiver() {
    let Some(python) = vmc::receiver_python("vmc_bundles_pass_a_third_party_receiver") else {
        return;
    };
    let (pitch, yaw, roll) = (10.0f32, 20.0f32, 5.0f32);
    let frames = 120;
    let port = free_udp_port();
    let head = ["--expect-head".to_owned(), format!("{pitch},{yaw},{roll}")];
    let receiver = vmc::Receiver::start(&python, port, frames, 30, &head, &std::env::temp_dir());
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
    let (accepted, report) = receiver.finish();
    println!("vmc receiver: {report}");
    assert!(
        accepted,
        "the third-party receiver refused the VMC output: {report}"
    );
}
