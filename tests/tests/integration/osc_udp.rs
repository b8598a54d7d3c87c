//! OSC end to end: the built plugin (through the CLAP test host) sends to UDP sockets on
//! 127.0.0.1; the test decodes the packets and checks addresses, types and values in both formats,
//! and that the target and format change while audio runs.

use std::net::UdpSocket;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use pneuma_testkit::osc::{decode, Message, OscType};
use pneuma_testkit::voice::example_voice_at;
use pneuma_tests::bundle::plugin_path;
use pneuma_tests::host::Plugin;

fn socket() -> UdpSocket {
    let s = UdpSocket::bind("127.0.0.1:0").expect("bind a UDP port on loopback");
    s.set_read_timeout(Some(Duration::from_millis(300)))
        .unwrap();
    s
}

/// Every bundle that arrives until the socket stays quiet for the read timeout.
fn drain(sock: &UdpSocket) -> Vec<Vec<Message>> {
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    while let Ok(n) = sock.recv(&mut buf) {
        assert!(&buf[..8] == b"#bundle\0", "every frame comes as a bundle");
        out.push(decode(&buf[..n]).expect("valid OSC"));
    }
    out
}

/// Plays `signal` through `plugin` (see [`play`]) while a thread receives on `sock` (the
/// socket's buffer would overflow otherwise): it waits up to 10 s for the first packet, then
/// keeps receiving until the audio has ended and the socket has been quiet for 300 ms, so a
/// stall of the player or the sender cannot end it early.
fn play_and_listen(
    plugin: &mut Plugin,
    signal: &[f32],
    sock: UdpSocket,
) -> (UdpSocket, Vec<Vec<Message>>) {
    let played = Arc::new(AtomicBool::new(false));
    let listener = std::thread::spawn({
        let played = Arc::clone(&played);
        move || {
            let mut buf = [0u8; 4096];
            sock.set_read_timeout(Some(Duration::from_secs(10)))
                .unwrap();
            let mut out = Vec::new();
            if let Ok(n) = sock.recv(&mut buf) {
                out.push(decode(&buf[..n]).expect("valid OSC"));
            }
            sock.set_read_timeout(Some(Duration::from_millis(300)))
                .unwrap();
            loop {
                let done = played.load(Ordering::SeqCst);
                out.extend(drain(&sock));
                if done {
                    break;
                }
            }
            (sock, out)
        }
    });
    play(plugin, signal);
    played.store(true, Ordering::SeqCst);
    listener.join().unwrap()
}

/// Processes `signal` in 480-sample blocks (10 ms at 48 kHz), roughly paced at 10× real time
/// so the sender keeps up without dropping.
fn play(plugin: &mut Plugin, signal: &[f32]) {
    let start = Instant::now();
    for (i, chunk) in signal.chunks(480).enumerate() {
        plugin.process(&mut [chunk.to_vec()]);
        let due = Duration::from_micros(1000 * i as u64);
        if let Some(wait) = due.checked_sub(start.elapsed()) {
            std::thread::sleep(wait);
        }
    }
}

fn float(v: &OscType) -> f32 {
    match v {
        OscType::Float(f) => *f,
        other => panic!("expected a float, got {other:?}"),
    }
}

#[test]
fn pneuma_then_vmc_bundles_arrive_with_the_documented_addresses_types_and_values() {
    let voice = example_voice_at(48_000);
    let first = socket();
    let second = socket();
    let mut plugin = Plugin::load(&plugin_path(), "org.pneuma.pneuma").unwrap();
    plugin.set_param("osc_enabled", "On").unwrap();
    plugin
        .set_param("osc_port", &first.local_addr().unwrap().port().to_string())
        .unwrap();
    plugin.set_param("osc_format", "pneuma").unwrap();
    plugin.activate(48_000.0, 480, 1).unwrap();
    let (first, bundles) = play_and_listen(&mut plugin, &voice[..48_000 * 8], first);
    assert!(
        bundles.len() > 300,
        "{} of ~960 frames arrived in 8 s of audio",
        bundles.len()
    );

    let want: [(&str, &str); 14] = [
        ("/pneuma/frame", "if"),
        ("/pneuma/f0", "f"),
        ("/pneuma/voiced", "i"),
        ("/pneuma/rms", "f"),
        ("/pneuma/level", "f"),
        ("/pneuma/speaking", "i"),
        ("/pneuma/breath/phase", "s"),
        ("/pneuma/breath/lung", "f"),
        ("/pneuma/breath/thorax", "f"),
        ("/pneuma/breath/abdomen", "f"),
        ("/pneuma/breath/nostril_flare", "f"),
        ("/pneuma/breath/mouth_open", "f"),
        ("/pneuma/breath/neck_pitch", "f"),
        ("/pneuma/head", "fff"),
    ];
    let mut voiced = 0;
    let mut last_time = -1.0f32;
    let mut last_tag = 0u64;
    for b in &bundles {
        assert_eq!(b.len(), want.len());
        for (m, (address, types)) in b.iter().zip(want) {
            assert_eq!(m.address, address);
            let got: String = m
                .args
                .iter()
                .map(|a| match a {
                    OscType::Int(_) => 'i',
                    OscType::Float(_) => 'f',
                    OscType::String(_) => 's',
                    other => panic!("{address}: {other:?} is not i, f or s"),
                })
                .collect();
            assert_eq!(got, types, "types of {address}");
        }
        let time_s = float(&b[0].args[1]);
        assert!(time_s > last_time, "frame times increase");
        last_time = time_s;
        let tag = b[0].time_tag.unwrap();
        assert!(tag > last_tag, "time tags increase");
        last_tag = tag;
        let f0 = float(&b[1].args[0]);
        let is_voiced = b[2].args[0] == OscType::Int(1);
        if is_voiced {
            voiced += 1;
            assert!((50.0..=600.0).contains(&f0), "voiced f0 {f0} Hz");
        } else {
            assert_eq!(f0, 0.0, "unvoiced frames send f0 0");
        }
        let rms = float(&b[3].args[0]);
        assert!((-120.0..=0.0).contains(&rms), "rms {rms} dBFS");
        let phase = &b[6].args[0];
        assert!(
            ["rest", "inspiration", "expiration"]
                .iter()
                .any(|p| *phase == OscType::String((*p).into())),
            "{phase:?}"
        );
        for m in &b[7..12] {
            let v = float(&m.args[0]);
            assert!((0.0..=1.0).contains(&v), "{} = {v}", m.address);
        }
    }
    assert!(voiced > bundles.len() / 4, "{voiced} voiced frames");

    // Switch target and format while running.
    plugin
        .set_param("osc_port", &second.local_addr().unwrap().port().to_string())
        .unwrap();
    plugin.set_param("osc_format", "VMC").unwrap();
    let (_, vmc) = play_and_listen(&mut plugin, &voice[48_000 * 8..48_000 * 12], second);
    assert!(vmc.len() > 150, "{} VMC bundles", vmc.len());
    let stray = drain(&first);
    assert!(
        stray.len() < 5,
        "{} bundles still went to the old target",
        stray.len()
    );
    for b in &vmc {
        let addresses: Vec<&str> = b.iter().map(|m| m.address.as_str()).collect();
        assert_eq!(
            addresses,
            [
                "/VMC/Ext/OK",
                "/VMC/Ext/T",
                "/VMC/Ext/Bone/Pos",
                "/VMC/Ext/Bone/Pos",
                "/VMC/Ext/Bone/Pos",
                "/VMC/Ext/Blend/Val",
                "/VMC/Ext/Blend/Val",
                "/VMC/Ext/Blend/Val",
                "/VMC/Ext/Blend/Apply"
            ]
        );
        assert_eq!(b[0].args, [OscType::Int(1)], "the model is loaded");
        for (m, bone) in b[2..5].iter().zip(["Chest", "Neck", "Head"]) {
            assert_eq!(m.args[0], OscType::String(bone.into()));
            assert_eq!(m.args.len(), 8);
            let q: Vec<f32> = m.args[4..].iter().map(float).collect();
            let norm: f32 = q.iter().map(|v| v * v).sum();
            assert!((norm - 1.0).abs() < 1e-4, "{bone} quaternion norm {norm}");
        }
        for (m, name) in b[5..8].iter().zip(["A", "Breath", "NostrilFlare"]) {
            assert_eq!(m.args[0], OscType::String(name.into()));
            let v = float(&m.args[1]);
            assert!((0.0..=1.0).contains(&v), "{name} = {v}");
        }
        assert!(b[8].args.is_empty());
    }
    // The time messages step by whole frame periods (one, but for a datagram lost on the way).
    let times: Vec<f32> = vmc.iter().map(|b| float(&b[1].args[0])).collect();
    // The plugin's frame rate is the setting's default.
    let rate_hz = pneuma_core::settings::analysis::FRAME_RATE_HZ.default;
    let steps: Vec<f32> = times.windows(2).map(|w| (w[1] - w[0]) * rate_hz).collect();
    for s in &steps {
        assert!(
            *s > 0.5 && (s - s.round()).abs() < 1e-2,
            "/VMC/Ext/T step {s} periods"
        );
    }
    let single = steps.iter().filter(|s| s.round() == 1.0).count();
    assert!(
        single * 10 >= steps.len() * 9,
        "{single} of {} steps one period",
        steps.len()
    );
}

#[test]
fn an_unresolvable_target_does_not_disturb_the_audio() {
    let voice = example_voice_at(48_000);
    let voice = &voice[..48_000 * 3];
    let mut with_osc = Plugin::load(&plugin_path(), "org.pneuma.pneuma").unwrap();
    // Port 9 (discard) on a host name that never resolves is set through the state.
    with_osc.set_param("osc_enabled", "On").unwrap();
    with_osc.set_param("osc_port", "9").unwrap();
    let state = with_osc.save_state();
    with_osc
        .load_state(&Plugin::edit_state(
            &state,
            "127.0.0.1",
            "no-such-host.invalid",
        ))
        .unwrap();
    let mut without = Plugin::load(&plugin_path(), "org.pneuma.pneuma").unwrap();
    with_osc.activate(48_000.0, 64, 1).unwrap();
    without.activate(48_000.0, 64, 1).unwrap();
    for chunk in voice.chunks(64) {
        let mut a = [chunk.to_vec()];
        let mut b = [chunk.to_vec()];
        let ea = with_osc.process(&mut a);
        let eb = without.process(&mut b);
        assert_eq!(a, b);
        assert_eq!(ea, eb);
    }
}
