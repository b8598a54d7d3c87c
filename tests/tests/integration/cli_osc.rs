//! `pneuma render --osc` sends what the plugin sends: the same bundles (addresses, types and
//! values, frame by frame) for the same input, in both formats, received and decoded by the
//! testkit's rosc decoder (written apart from core's encoder); the plugin runs through the CLAP
//! host, the render in process. The VMC output also passes the third-party receiver the app's
//! tests use (python-osc + vmcp, `app/tests/vmc_receiver.py`), whose time-tag check also holds
//! the pacing: at `--osc-speed 4` the tags step by a quarter frame period.

use std::collections::BTreeMap;
use std::ffi::OsString;
use std::net::UdpSocket;
use std::path::{Path, PathBuf};

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use pneuma_core::encode::osc::TimeTag;
use pneuma_testkit::osc::{decode, Message, OscType};
use pneuma_testkit::vmc;
use pneuma_tests::bundle::plugin_path;
use pneuma_tests::host::Plugin;

/// Seconds of the example voice rendered (short: the plugin side plays it at 10x real time).
const CLIP_S: usize = 6;

fn socket() -> UdpSocket {
    UdpSocket::bind("127.0.0.1:0").expect("bind a UDP port on loopback")
}

/// Receives every bundle on `sock` while `work` runs and until the socket has been quiet for
/// 300 ms afterwards; `work`'s result and the bundles.
fn listen_while<T>(sock: UdpSocket, work: impl FnOnce() -> T) -> (T, Vec<Vec<Message>>) {
    let done = Arc::new(AtomicBool::new(false));
    let listener = std::thread::spawn({
        let done = Arc::clone(&done);
        move || {
            sock.set_read_timeout(Some(Duration::from_millis(300)))
                .unwrap();
            let mut buf = [0u8; 4096];
            let mut out = Vec::new();
            loop {
                let finished = done.load(Ordering::SeqCst);
                match sock.recv(&mut buf) {
                    Ok(n) => out.push(decode(&buf[..n]).expect("valid OSC")),
                    Err(_) if finished => break,
                    Err(_) => {}
                }
            }
            out
        }
    });
    let result = work();
    done.store(true, Ordering::SeqCst);
    (result, listener.join().unwrap())
}

/// The first `CLIP_S` seconds of the example voice, as a WAV file in `dir`; the samples and rate.
fn clip(dir: &Path) -> (PathBuf, Vec<f32>, u32) {
    let (voice, rate) = pneuma_testkit::voice::example_voice();
    let samples = voice[..rate as usize * CLIP_S].to_vec();
    let path = dir.join("clip.wav");
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: rate,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(&path, spec).unwrap();
    for &s in &samples {
        w.write_sample(s).unwrap();
    }
    w.finalize().unwrap();
    (path, samples, rate)
}

/// `pneuma render IN -o DIR/out --osc-port PORT --osc-format FORMAT --osc-speed SPEED` in process
/// (the command's own argument parsing and code path); the OSC line of its summary.
fn render(input: &Path, dir: &Path, port: u16, format: &str, speed: &str) -> Option<String> {
    use clap::{Args as _, FromArgMatches as _};
    let argv: Vec<OsString> = [
        "render",
        input.to_str().unwrap(),
        "-o",
        dir.join("out").to_str().unwrap(),
        "--quiet",
        "--no-plot",
        "--lookahead-ms",
        "500",
        "--osc-port",
        &port.to_string(),
        "--osc-format",
        format,
        "--osc-speed",
        speed,
    ]
    .iter()
    .map(OsString::from)
    .collect();
    let matches = pneuma_cli::render::Args::augment_args(clap::Command::new("render"))
        .try_get_matches_from(argv)
        .expect("valid render options");
    let args = pneuma_cli::render::Args::from_arg_matches(&matches).expect("render options");
    pneuma_cli::render::run(&args, input, |_| {})
        .expect("pneuma render")
        .osc
}

/// The plugin with OSC on to `port` in `format` (its parameter's name), playing `voice` (and its
/// latency in silence) in 512-sample blocks at about 10x real time so its sender keeps up.
fn plugin_sends(voice: &[f32], rate: u32, port: u16, format: &str) {
    let mut plugin = Plugin::load(&plugin_path(), "org.pneuma.pneuma").expect("loads");
    plugin.set_param("osc_enabled", "On").unwrap();
    plugin.set_param("osc_port", &port.to_string()).unwrap();
    plugin.set_param("osc_format", format).unwrap();
    plugin.activate(f64::from(rate), 512, 1).expect("activates");
    let latency = plugin.latency() as usize;
    let mut input = voice.to_vec();
    input.resize(voice.len() + latency, 0.0);
    let block_s = 512.0 / f64::from(rate) / 10.0;
    let start = Instant::now();
    for (i, block) in input.chunks(512).enumerate() {
        plugin.process(&mut [block.to_vec()]);
        let due = Duration::from_secs_f64(block_s * (i + 1) as f64);
        if let Some(wait) = due.checked_sub(start.elapsed()) {
            std::thread::sleep(wait);
        }
    }
    // The worker's last frames leave within a few polls.
    std::thread::sleep(Duration::from_millis(100));
}

/// The CLI's bundles before its ease to the rest pose (`rest_ease_steps` frames at 120 Hz, the
/// last of them the rest pose: levels at the floor).
fn without_the_ease(mut cli: Vec<Vec<Message>>) -> Vec<Vec<Message>> {
    let ease = pneuma_osc::paced::rest_ease_steps(1.0 / 120.0) as usize;
    assert!(cli.len() > ease, "{} bundles", cli.len());
    let last = cli.last().expect("bundles");
    let rms = |b: &[Message]| {
        b.iter()
            .find(|m| m.address == "/pneuma/rms")
            .map(|m| m.args.clone())
    };
    if let Some(args) = rms(last) {
        assert_eq!(
            args,
            vec![OscType::Float(-120.0)],
            "the stream ends at rest"
        );
    }
    cli.truncate(cli.len() - ease);
    cli
}

/// A bundle's messages without their time tag.
fn strip(bundle: &[Message]) -> Vec<(String, Vec<OscType>)> {
    bundle
        .iter()
        .map(|m| (m.address.clone(), m.args.clone()))
        .collect()
}

fn tag_s(bundle: &[Message]) -> f64 {
    TimeTag(bundle[0].time_tag.expect("a bundle's time tag")).to_unix_seconds()
}

#[test]
fn the_cli_sends_the_plugins_bundles_in_both_formats() {
    let dir = std::env::temp_dir().join(format!("pneuma-cli-osc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (input, voice, rate) = clip(&dir);
    let frames_in_clip = CLIP_S * 120;

    // pneuma: bundles matched by their frame index (`/pneuma/frame`).
    let rx = socket();
    let port = rx.local_addr().unwrap().port();
    let (line, cli) = listen_while(rx, || render(&input, &dir, port, "pneuma", "10"));
    let line = line.expect("the summary names what was sent");
    assert!(
        line.contains(&format!("{} bundles (pneuma)", cli.len())),
        "{line}"
    );
    // The CLI's stream ends easing to the rest pose; the plugin's frames are the ones before.
    let cli = without_the_ease(cli);
    assert!(
        cli.len().abs_diff(frames_in_clip) <= 2,
        "every frame of the {CLIP_S} s clip arrives once: {}",
        cli.len()
    );
    let rx = socket();
    let port = rx.local_addr().unwrap().port();
    let ((), live) = listen_while(rx, || plugin_sends(&voice, rate, port, "pneuma"));
    let by_index = |bundles: &[Vec<Message>]| -> BTreeMap<i32, Vec<Message>> {
        bundles
            .iter()
            .map(|b| {
                assert_eq!(b[0].address, "/pneuma/frame");
                let OscType::Int(i) = b[0].args[0] else {
                    panic!("frame index {:?}", b[0].args[0])
                };
                (i, b.clone())
            })
            .collect()
    };
    let (cli_frames, live_frames) = (by_index(&cli), by_index(&live));
    assert_eq!(cli_frames.len(), cli.len(), "one bundle per frame");
    let mut compared = 0;
    for (i, want) in &live_frames {
        let Some(got) = cli_frames.get(i) else {
            continue;
        };
        assert_eq!(strip(got), strip(want), "frame {i}");
        compared += 1;
    }
    assert!(
        compared * 10 >= cli.len() * 9,
        "{compared} of {} frames compared with the plugin's",
        cli.len()
    );

    // VMC: no frame index in the bundles; each side's frames are numbered by their time tags
    // from its first bundle (the CLI's at 10x: a tenth of a period apart), then aligned on the
    // plugin's first frames (which its worker may have dropped under load).
    let rx = socket();
    let port = rx.local_addr().unwrap().port();
    let (_, cli) = listen_while(rx, || render(&input, &dir, port, "vmc", "10"));
    let cli = without_the_ease(cli);
    let rx = socket();
    let port = rx.local_addr().unwrap().port();
    let ((), live) = listen_while(rx, || plugin_sends(&voice, rate, port, "VMC"));
    let numbered = |bundles: &[Vec<Message>], period_s: f64| -> BTreeMap<i64, Vec<Message>> {
        let t0 = tag_s(&bundles[0]);
        bundles
            .iter()
            .map(|b| (((tag_s(b) - t0) / period_s).round() as i64, b.clone()))
            .collect()
    };
    let cli = numbered(&cli, 1.0 / 1200.0);
    let live = numbered(&live, 1.0 / 120.0);
    assert!(
        cli.len().abs_diff(frames_in_clip) <= 2,
        "{} VMC bundles",
        cli.len()
    );
    let matching = |offset: i64| {
        live.iter()
            .filter(|(k, b)| {
                cli.get(&(*k + offset))
                    .is_some_and(|c| strip(c) == strip(b))
            })
            .count()
    };
    let (offset, matched) = (0..4)
        .map(|o| (o, matching(o)))
        .max_by_key(|x| x.1)
        .unwrap();
    assert!(
        matched * 10 >= cli.len() * 9,
        "{matched} of {} VMC bundles equal the plugin's (offset {offset})",
        cli.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_clis_vmc_passes_a_third_party_receiver_at_four_times_real_time() {
    let test = "the_clis_vmc_passes_a_third_party_receiver_at_four_times_real_time";
    let Some(python) = vmc::receiver_python(test) else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("pneuma-cli-vmc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (input, _, _) = clip(&dir);
    let port = socket().local_addr().unwrap().port();
    // 240 bundles: 2 s of audio; at 4x the receiver's time tags must step by 1/480 s, and the
    // frames' own times (`/VMC/Ext/T`) by the stream's 1/120 s.
    let rate = ["--frame-rate-hz", "480", "--stream-rate-hz", "120"].map(str::to_owned);
    let receiver = vmc::Receiver::start(&python, port, 240, 60, &rate, &dir);
    render(&input, &dir, port, "vmc", "4");
    let (accepted, report) = receiver.finish();
    let _ = std::fs::remove_dir_all(&dir);
    println!("vmc receiver: {report}");
    assert!(
        accepted,
        "the third-party receiver refused the CLI's VMC: {report}"
    );
}
