//! A tester's robustness findings, each a test that failed before its fix: valid files refused
//! as damaged, partial files left by a termination, outputs that replaced audio.

use std::path::Path;

use crate::support;
use pneuma_testkit::voice::example_voice_path;
use support::{assert_ok, ffmpeg_encode, have_ffmpeg, pneuma, read_audio, render};

/// Seconds of audio in an audio file pneuma reads.
fn duration_s(path: &Path) -> f64 {
    let (samples, rate_hz, channels) = read_audio(path);
    samples.len() as f64 / f64::from(channels) / f64::from(rate_hz)
}

#[test]
fn a_vbr_mp3_without_a_xing_frame_renders_and_analyzes_whole() {
    if !have_ffmpeg("a_vbr_mp3_without_a_xing_frame_renders_and_analyzes_whole") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    // What an encoder writing to a pipe makes: VBR frames and no Xing frame before them.
    let mp3 = dir.path().join("vbr_piped.mp3");
    let lame = ["-c:a", "libmp3lame", "-q:a", "2", "-write_xing", "0"];
    ffmpeg_encode(&example_voice_path(), &mp3, &lame);
    let out = dir.path().join("out");
    let o = render(&mp3, &out, &["--no-plot"]);
    assert_ok(&o);
    let (voice_s, rendered_s) = (
        duration_s(&example_voice_path()),
        duration_s(&out.join("vbr_piped.flac")),
    );
    // The encoder's delay and padding stay (no LAME frame says how long they are).
    assert!(
        (rendered_s - voice_s).abs() < 0.2,
        "{rendered_s} s rendered of {voice_s} s"
    );
    let csv = dir.path().join("vbr.csv");
    let args = [
        "analyze",
        mp3.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ];
    assert_ok(&pneuma(&args));
}

#[test]
fn a_chained_ogg_file_renders_every_stream() {
    if !have_ffmpeg("a_chained_ogg_file_renders_every_stream") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let ogg = dir.path().join("a.ogg");
    ffmpeg_encode(&example_voice_path(), &ogg, &["-c:a", "libvorbis"]);
    let once = std::fs::read(&ogg).expect("ogg");
    let chained = dir.path().join("chained.ogg");
    std::fs::write(&chained, [once.clone(), once].concat()).expect("write");
    let out = dir.path().join("out");
    assert_ok(&render(&chained, &out, &["--no-plot"]));
    let (one_s, both_s) = (duration_s(&ogg), duration_s(&out.join("chained.flac")));
    assert!(
        (both_s - 2.0 * one_s).abs() < 0.05,
        "{both_s} s of 2 × {one_s} s"
    );
}

/// A 10-minute 16 kHz WAV at `path`: long enough for a debug render to be stopped midway.
fn write_long_wav(path: &Path) {
    let tone: Vec<f32> = (0..16_000 * 600)
        .map(|i| 0.1 * (i as f32 * 0.05).sin())
        .collect();
    support::write_wav(path, (16_000, 1, 16, false), &tone, 1.0);
}

/// Whether `dir` exists and holds a file (a render's hidden partial file, once it writes).
fn has_files(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_some())
}

#[test]
fn sigterm_and_sighup_stop_a_render_leaving_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("long.wav");
    write_long_wav(&input);
    for signal in ["TERM", "HUP"] {
        let out = dir.path().join(format!("new_{signal}"));
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pneuma"))
            .args([
                "render",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "-q",
            ])
            .spawn()
            .expect("pneuma starts");
        let started = std::time::Instant::now();
        while !has_files(&out) && started.elapsed().as_secs() < 60 {
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        assert!(
            has_files(&out),
            "SIG{signal}: the render never started writing"
        );
        let kill = std::process::Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(kill.success());
        let status = child.wait().expect("pneuma ends");
        assert_eq!(status.code(), Some(130), "SIG{signal}: {status}");
        assert!(
            !out.exists(),
            "SIG{signal}: the folder the render made stays"
        );
    }
}

#[test]
fn analyze_refuses_to_write_its_csv_over_an_audio_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let take1 = dir.path().join("take1.wav");
    std::fs::copy(example_voice_path(), &take1).expect("copy");
    for name in ["take2.wav", "take2.FLAC", "take2.mp3", "take2.opus"] {
        let take2 = dir.path().join(name);
        std::fs::write(&take2, b"a recording").expect("write");
        let o = pneuma(&[
            "analyze",
            take1.to_str().unwrap(),
            "-o",
            take2.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "-o {name}: {err}");
        assert!(err.contains("give a .csv name"), "{err}");
        assert!(err.contains("take2.csv"), "{err}");
        assert_eq!(std::fs::read(&take2).expect("kept"), b"a recording");
    }
}

#[test]
fn an_input_named_like_a_side_output_is_never_replaced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let voice = std::fs::read(example_voice_path()).expect("voice");
    for (name, extra) in [
        ("take.png", &[][..]),
        ("t.bvh", &["--bvh"]),
        ("t.mid", &["--midi"]),
    ] {
        let input = dir.path().join(name);
        std::fs::write(&input, &voice).expect("write");
        let o = render(&input, dir.path(), extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{name}: {err}");
        assert!(err.contains("it is the input file"), "{name}: {err}");
        assert!(
            std::fs::read(&input).expect("input") == voice,
            "{name} was replaced"
        );
    }
}

#[test]
fn a_missing_channel_is_named_as_it_was_typed() {
    let dir = tempfile::tempdir().expect("temp dir");
    for typed in ["2", "right"] {
        let o = render(&example_voice_path(), dir.path(), &["--channel", typed]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{err}");
        assert!(
            err.contains(&format!("--channel {typed} needs 2 channels")),
            "{err}"
        );
    }
}

#[test]
fn samples_that_are_not_numbers_are_said_and_never_called_zero() {
    let dir = tempfile::tempdir().expect("temp dir");
    let all_nan = dir.path().join("allnan.wav");
    support::write_wav(&all_nan, (16_000, 1, 32, true), &[f32::NAN; 16_000], 1.0);
    let o = support::render_saying(&all_nan, &dir.path().join("out"), &[]);
    assert_ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("16000 samples are not numbers"), "{err}");
    assert!(err.contains("written as 0"), "{err}");
    assert!(!err.contains("every sample is zero"), "{err}");
}
