//! Checks of the Ardour end-to-end run (`tests/ardour/run.sh`, its own step in `.ci/run`):
//! ignored in `cargo test`, run by the script with `PNEUMA_ARDOUR_OUT` set to its output folder.
//!
//! - `write_the_voice_for_ardour`: the example voice at 48 kHz (32-bit float WAV), the file
//!   the session plays and `pneuma render` renders.
//! - `the_ardour_session_matches_the_reference`: Ardour's export equals the CLI render (breaths
//!   included, latency compensated); the CC Ardour recorded on a MIDI track (CC 2 and 16–18
//!   above all) are the CC the plugin sends in the reference CLAP host, at the same timeline
//!   positions once the reported latency is taken off; the facts the Lua scripts wrote:
//!   lookahead latency reported, Live mode reporting 0 without a reload, a session saved right
//!   after a change reopening with it.

use std::collections::BTreeMap;
use std::path::PathBuf;

use pneuma_testkit::voice::{example_voice_at, read_wav as read};
use pneuma_tests::bundle::plugin_path;
use pneuma_tests::host::Plugin;

const RATE: u32 = 48_000;

fn out_dir() -> PathBuf {
    std::env::var_os("PNEUMA_ARDOUR_OUT")
        .map(PathBuf::from)
        .expect("PNEUMA_ARDOUR_OUT is not set: run tests/ardour/run.sh, which sets it")
}

#[test]
#[ignore = "part of tests/ardour/run.sh"]
fn write_the_voice_for_ardour() {
    let voice = example_voice_at(RATE);
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: RATE,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let path = out_dir().join("voice48k.wav");
    let mut w = hound::WavWriter::create(&path, spec).expect("the voice file can be written");
    for s in voice {
        w.write_sample(s).unwrap();
    }
    w.finalize().unwrap();
}

/// `key=value` lines of `facts.txt`.
fn facts() -> BTreeMap<String, f64> {
    let text = std::fs::read_to_string(out_dir().join("facts.txt")).expect("facts.txt");
    text.lines()
        .filter_map(|l| l.split_once('='))
        .map(|(k, v)| {
            let v = v.trim().parse().unwrap_or_else(|_| panic!("{k}={v}"));
            (k.to_owned(), v)
        })
        .collect()
}

/// A CC message at a timeline sample.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cc {
    sample: f64,
    controller: u8,
    value: u8,
}

/// The CC messages of a standard MIDI file (format 0 or 1, one tempo), times in samples.
fn read_smf(path: &std::path::Path) -> Vec<Cc> {
    let d = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&d[..4], b"MThd", "not a MIDI file");
    let be16 = |i: usize| u16::from_be_bytes([d[i], d[i + 1]]);
    let be32 = |i: usize| u32::from_be_bytes([d[i], d[i + 1], d[i + 2], d[i + 3]]);
    let tracks = be16(10);
    let division = f64::from(be16(12));
    assert!(division > 0.0 && be16(12) < 0x8000, "SMPTE time division");
    let mut tempo_us = 500_000.0;
    let mut out = Vec::new();
    let mut pos = 8 + be32(4) as usize;
    for _ in 0..tracks {
        assert_eq!(&d[pos..pos + 4], b"MTrk");
        let end = pos + 8 + be32(pos + 4) as usize;
        let mut p = pos + 8;
        let (mut tick, mut status) = (0u64, 0u8);
        let varlen = |p: &mut usize| {
            let mut v = 0u64;
            loop {
                let b = d[*p];
                *p += 1;
                v = (v << 7) | u64::from(b & 0x7F);
                if b < 0x80 {
                    return v;
                }
            }
        };
        while p < end {
            tick += varlen(&mut p);
            if d[p] == 0xFF || d[p] == 0xF0 || d[p] == 0xF7 {
                let kind = d[p];
                let meta = if kind == 0xFF { d[p + 1] } else { 0 };
                p += if kind == 0xFF { 2 } else { 1 };
                let len = varlen(&mut p) as usize;
                if kind == 0xFF && meta == 0x51 {
                    tempo_us = f64::from(u32::from_be_bytes([0, d[p], d[p + 1], d[p + 2]]));
                }
                p += len;
                continue;
            }
            if d[p] >= 0x80 {
                status = d[p];
                p += 1;
            }
            let data_len = if matches!(status & 0xF0, 0xC0 | 0xD0) {
                1
            } else {
                2
            };
            if status & 0xF0 == 0xB0 {
                out.push(Cc {
                    sample: tick as f64 * tempo_us / division * f64::from(RATE) / 1e6,
                    controller: d[p],
                    value: d[p + 1],
                });
            }
            p += data_len;
        }
        pos = end;
    }
    out
}

/// The plugin's CC messages for the voice in the reference CLAP host (stereo layout fed the
/// mono voice on both sides, as Ardour's mono track gives it), at timeline samples: the
/// absolute output sample minus the reported latency.
fn reference_cc(voice: &[f32], blocks: usize) -> (Vec<Cc>, u32) {
    let mut plugin = Plugin::load(&plugin_path(), "org.pneuma.pneuma").expect("bundle loads");
    plugin.activate(f64::from(RATE), blocks, 2).unwrap();
    let latency = plugin.latency();
    // One second past the end, as Ardour recorded.
    let mut input = voice.to_vec();
    input.resize(voice.len() + latency as usize + RATE as usize, 0.0);
    let mut out = Vec::new();
    for chunk in input.chunks(blocks) {
        let mut audio = vec![chunk.to_vec(), chunk.to_vec()];
        for e in plugin.process(&mut audio) {
            out.push(Cc {
                sample: e.sample as f64 - f64::from(latency),
                controller: e.controller,
                value: e.value,
            });
        }
    }
    (out, latency)
}

#[test]
#[ignore = "part of tests/ardour/run.sh"]
fn the_ardour_session_matches_the_reference() {
    let dir = out_dir();
    let facts = facts();
    let fact = |k: &str| {
        *facts
            .get(k)
            .unwrap_or_else(|| panic!("no {k} in facts.txt"))
    };
    eprintln!("facts: {facts:?}");

    // Latencies and state.
    assert_eq!(
        fact("lookahead_latency_samples"),
        24_000.0,
        "lookahead latency"
    );
    assert_eq!(
        fact("reopened_latency_samples"),
        24_000.0,
        "reopened, lookahead"
    );
    assert_eq!(fact("live_latency_samples"), 0.0, "Mode = Live reports 0");
    assert_eq!(
        fact("live_route_latency_samples"),
        0.0,
        "the track's latency follows"
    );
    assert_eq!(fact("reopened_mode"), 1.0, "reopened in Live mode");
    assert_eq!(
        fact("reopened_breath_level_db"),
        -10.0,
        "saved as soon as the change reached the plugin"
    );
    assert_eq!(
        fact("reopened_live_latency_samples"),
        0.0,
        "reopened live: latency 0"
    );

    // Audio: the export (master bus, stereo) against the CLI render of the same file.
    let (export, export_rate) = read(&dir.join("export.wav"));
    let (render, render_rate) = read(&dir.join("render/voice48k.wav"));
    let (voice, _) = read(&dir.join("voice48k.wav"));
    assert_eq!((export_rate, render_rate), (RATE, RATE));
    let render = &render[0];
    let voice = &voice[0];
    assert_eq!(fact("voice_samples") as usize, voice.len());
    assert!(
        export[0].len() >= render.len(),
        "export of {} samples, render {}",
        export[0].len(),
        render.len()
    );
    let breath_samples = render.iter().zip(voice).filter(|(r, v)| r != v).count();
    assert!(
        breath_samples > RATE as usize,
        "the render holds breaths ({breath_samples} samples differ from the voice)"
    );
    let mut audio_errors = Vec::new();
    for (c, channel) in export.iter().enumerate() {
        let worst = channel
            .iter()
            .zip(render)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f32, f32::max);
        let first = channel
            .iter()
            .zip(render)
            .position(|(a, b)| (a - b).abs() > 1e-6);
        eprintln!(
            "export channel {c} vs render: max |diff| {worst:.3e}, first over 1e-6 at {first:?}"
        );
        if let Some(first) = first {
            audio_errors.push(format!(
                "Ardour's export (channel {c}) differs from `pneuma render` from sample {first}"
            ));
        }
    }

    // MIDI: what Ardour recorded against what the plugin sends, on the timeline.
    let recorded = read_smf(&dir.join("cc.mid"));
    let offset = fact("cc_region_position_samples");
    let recorded: Vec<Cc> = recorded
        .into_iter()
        .map(|c| Cc {
            sample: c.sample + offset,
            ..c
        })
        .collect();
    let (reference, latency) = reference_cc(voice, 1024);
    assert_eq!(f64::from(latency), fact("lookahead_latency_samples"));
    eprintln!(
        "CC messages: {} recorded by Ardour, {} from the reference host",
        recorded.len(),
        reference.len()
    );
    for controller in [2u8, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25] {
        let of = |v: &[Cc]| -> Vec<Cc> {
            v.iter()
                .filter(|c| c.controller == controller)
                .copied()
                .collect()
        };
        // Both up to half a second after the voice (Ardour recorded a second past it).
        let end = voice.len() as f64 + f64::from(RATE) / 2.0;
        let upto = |v: Vec<Cc>| -> Vec<Cc> { v.into_iter().filter(|c| c.sample < end).collect() };
        let (got, want) = (upto(of(&recorded)), upto(of(&reference)));
        assert!(
            !want.is_empty(),
            "CC {controller}: none from the reference host"
        );
        assert_eq!(
            got.iter().map(|c| c.value).collect::<Vec<_>>(),
            want.iter().map(|c| c.value).collect::<Vec<_>>(),
            "CC {controller}: recorded values differ from the plugin's ({} vs {})",
            got.len(),
            want.len()
        );
        let worst = got
            .iter()
            .zip(&want)
            .map(|(g, w)| (g.sample - w.sample).abs())
            .fold(0.0, f64::max);
        eprintln!(
            "CC {controller}: {} messages, timing off by at most {worst:.2} samples",
            got.len()
        );
        assert!(
            worst <= 2.0,
            "CC {controller} recorded up to {worst} samples away from the plugin's timeline"
        );
    }
    assert!(audio_errors.is_empty(), "{audio_errors:?}");
}
