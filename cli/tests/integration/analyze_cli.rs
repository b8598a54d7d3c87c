//! `pneuma analyze` end to end: WAV formats in, the CSV contract out, broken files rejected
//! with clear errors and without touching existing output.

use std::path::{Path, PathBuf};

use pneuma_testkit::signals;

use crate::support;
use support::{assert_analyze_fails, files_besides, pneuma, pneuma_with_stdin};

/// Writes `mono` to all channels (the second at 0.5×) in the given format.
fn write_wav(path: &Path, rate: u32, channels: u16, bits: u16, float: bool, mono: &[f32]) {
    support::write_wav(path, (rate, channels, bits, float), mono, 0.5);
}

/// 0.3 s silence, 0.6 s of a 200 Hz voice-like tone, 0.3 s silence.
fn test_signal(rate: u32) -> Vec<f32> {
    let r = rate as f64;
    let mut x = vec![0.0; (0.3 * r) as usize];
    x.extend(signals::harmonic_tone(
        r,
        0.6,
        0.5,
        &[1.0, 0.6, 0.4, 0.2],
        |_| 200.0,
    ));
    x.extend(vec![0.0; (0.3 * r) as usize]);
    x
}

struct Row {
    time_s: f64,
    f0_hz: f64,
    voiced: bool,
    voicing: f64,
    rms_db: f64,
}

fn parse_csv(text: &str) -> Vec<Row> {
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("time_s,f0_hz,voiced,voicing,rms_db"));
    lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            assert_eq!(v.len(), 5, "{l}");
            Row {
                time_s: v[0].parse().expect("time"),
                f0_hz: v[1].parse().expect("f0"),
                voiced: match v[2] {
                    "0" => false,
                    "1" => true,
                    other => panic!("voiced must be 0/1, got {other}"),
                },
                voicing: v[3].parse().expect("voicing"),
                rms_db: v[4].parse().expect("rms"),
            }
        })
        .collect()
}

fn check_rows(rows: &[Row], length_s: f64) {
    assert_eq!(rows.len(), (length_s * 120.0).ceil() as usize);
    for (k, r) in rows.iter().enumerate() {
        assert!((r.time_s - k as f64 / 120.0).abs() < 1e-6);
        assert!((0.0..=1.0).contains(&r.voicing));
        assert_eq!(r.voiced, r.f0_hz > 0.0);
        let in_tone = r.time_s > 0.36 && r.time_s < 0.84;
        let in_silence = r.time_s < 0.25 || r.time_s > 0.95;
        if in_tone {
            assert!(
                r.voiced && (r.f0_hz - 200.0).abs() < 3.0,
                "t {} f0 {}",
                r.time_s,
                r.f0_hz
            );
        }
        if in_silence {
            assert!(
                !r.voiced && r.rms_db <= -90.0,
                "t {} rms {}",
                r.time_s,
                r.rms_db
            );
        }
    }
}

fn temp() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

#[test]
fn reads_every_supported_format() {
    let dir = temp();
    let cases: [(u32, u16, u16, bool); 6] = [
        (48_000, 1, 16, false),
        (44_100, 2, 24, false),
        (16_000, 1, 8, false),
        (96_000, 2, 32, false),
        (22_050, 1, 32, true),
        (8_000, 3, 16, false),
    ];
    for (rate, channels, bits, float) in cases {
        let wav = dir
            .path()
            .join(format!("in_{rate}_{channels}_{bits}_{float}.wav"));
        write_wav(&wav, rate, channels, bits, float, &test_signal(rate));
        let csv = dir.path().join("out.csv");
        let out = pneuma(&[
            "analyze",
            wav.to_str().expect("utf8"),
            "-o",
            csv.to_str().expect("utf8"),
        ]);
        assert!(
            out.status.success(),
            "{rate} {channels} {bits} {float}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let rows = parse_csv(&std::fs::read_to_string(&csv).expect("csv written"));
        check_rows(&rows, 1.2);
    }
}

#[test]
fn dash_writes_to_stdout() {
    let dir = temp();
    let wav = dir.path().join("in.wav");
    write_wav(&wav, 48_000, 1, 16, false, &test_signal(48_000));
    let out = pneuma(&["analyze", wav.to_str().expect("utf8"), "-o", "-"]);
    assert!(out.status.success());
    check_rows(
        &parse_csv(&String::from_utf8(out.stdout).expect("utf8")),
        1.2,
    );
}

#[test]
fn broken_files_fail_clearly_and_keep_existing_output() {
    let dir = temp();
    let empty = dir.path().join("empty.wav");
    std::fs::write(&empty, b"").expect("write");
    assert_analyze_fails(&empty, &["holds no audio"]);

    let text = dir.path().join("text.wav");
    std::fs::write(&text, b"this is not audio at all, just some text in a file").expect("write");
    assert_analyze_fails(
        &text,
        &["is not audio: it holds text", "give an audio file"],
    );

    // A real WAV cut in the middle of its data.
    let good = dir.path().join("good.wav");
    write_wav(&good, 48_000, 2, 24, false, &test_signal(48_000));
    let bytes = std::fs::read(&good).expect("read");
    let cut = dir.path().join("cut.wav");
    std::fs::write(&cut, &bytes[..bytes.len() / 2 + 1]).expect("write");
    assert_analyze_fails(&cut, &["damaged"]);

    // A rate outside 8–192 kHz.
    let slow = dir.path().join("slow.wav");
    write_wav(&slow, 4_000, 1, 16, false, &vec![0.0; 4000]);
    assert_analyze_fails(&slow, &["4000 Hz"]);

    // 64-bit float is not read.
    let mut f64_wav = bytes[..44].to_vec();
    // Patch the fmt chunk of a copy of the good file: format 3 (float), 64 bits.
    f64_wav[20] = 3;
    f64_wav[34] = 64;
    f64_wav.extend_from_slice(&[0u8; 64]);
    let f64_path = dir.path().join("f64.wav");
    std::fs::write(&f64_path, &f64_wav).expect("write");
    let out = pneuma(&["analyze", f64_path.to_str().expect("utf8"), "-o", "-"]);
    assert!(!out.status.success());

    assert_analyze_fails(&dir.path().join("missing.wav"), &["cannot open"]);
}

#[test]
fn a_long_file_streams_its_csv_also_from_a_pipe_and_a_late_failure_keeps_existing_output() {
    // 40 s at 8 kHz: its CSV (4 800 rows) is written to the output in several pieces.
    let dir = temp();
    let rate = 8_000;
    let mut x = Vec::new();
    while x.len() < 40 * rate as usize {
        x.extend(test_signal(rate));
    }
    let long = dir.path().join("long.wav");
    write_wav(&long, rate, 1, 16, false, &x);
    let csv = dir.path().join("long.csv");
    let out = pneuma(&[
        "analyze",
        long.to_str().expect("utf8"),
        "-o",
        csv.to_str().expect("utf8"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).expect("csv");
    let rows = parse_csv(&text);
    assert_eq!(
        rows.len(),
        (x.len() as f64 / rate as f64 * 120.0).ceil() as usize
    );
    // The rows of the first 30 s fill more than one 64 KiB piece.
    assert!(text.len() * 3 / 4 > 65_536, "CSV of {} bytes", text.len());
    // Through a pipe (`/dev/stdin`, length unknown) the same CSV comes out.
    let bytes = std::fs::read(&long).expect("read");
    let existing = dir.path().join("piped.csv");
    let o = pneuma_with_stdin(
        &[
            "analyze",
            "/dev/stdin",
            "-o",
            existing.to_str().expect("utf8"),
        ],
        &bytes,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read_to_string(&existing).expect("csv"), text);
    // The same file cut at 30 s, piped: the cut is only found when the data runs out, after
    // most rows were streamed to the temporary file. The earlier output stays, and no
    // temporary file is left.
    std::fs::write(&existing, "precious\n").expect("write");
    let cut = &bytes[..44 + 2 * 30 * rate as usize + 1];
    let o = pneuma_with_stdin(
        &[
            "analyze",
            "/dev/stdin",
            "-o",
            existing.to_str().expect("utf8"),
        ],
        cut,
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(err.contains("damaged after 240000 sample frames"), "{err}");
    assert_eq!(
        std::fs::read_to_string(&existing).expect("kept"),
        "precious\n"
    );
    let leftovers: Vec<PathBuf> = files_besides(dir.path(), &existing)
        .into_iter()
        .filter(|p| p.to_string_lossy().ends_with(".partial"))
        .collect();
    assert!(leftovers.is_empty(), "partial files left: {leftovers:?}");
    // From a regular file the cut is found before anything is analysed.
    let cut_path = dir.path().join("cut.wav");
    std::fs::write(&cut_path, cut).expect("write");
    assert_analyze_fails(&cut_path, &["damaged after 240000 sample frames"]);
}

#[test]
fn unwritable_output_is_a_clear_error() {
    let dir = temp();
    let wav = dir.path().join("in.wav");
    write_wav(&wav, 16_000, 1, 16, false, &test_signal(16_000));
    let out = pneuma(&[
        "analyze",
        wav.to_str().expect("utf8"),
        "-o",
        "/nonexistent-dir/out.csv",
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot write /nonexistent-dir/out.csv"));
}

#[test]
fn the_example_voice_has_phrases_and_pauses() {
    let voice = pneuma_testkit::voice::example_voice_path();
    let out = pneuma(&["analyze", voice.to_str().expect("utf8"), "-o", "-"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let rows = parse_csv(&String::from_utf8(out.stdout).expect("utf8"));
    let voiced = rows.iter().filter(|r| r.voiced).count() as f64 / rows.len() as f64;
    assert!((0.3..0.8).contains(&voiced), "voiced share {voiced}");
    // The long pauses of the transcript (5.715–6.915 s and 16.791–18.391 s) are silent.
    for r in rows
        .iter()
        .filter(|r| (5.8..6.85).contains(&r.time_s) || (16.9..18.3).contains(&r.time_s))
    {
        assert!(!r.voiced && r.rms_db < -90.0, "t {} {}", r.time_s, r.rms_db);
    }
    // A female TTS voice: median f0 in the female range.
    let mut f0: Vec<f64> = rows.iter().filter(|r| r.voiced).map(|r| r.f0_hz).collect();
    f0.sort_by(f64::total_cmp);
    let median = f0[f0.len() / 2];
    assert!((140.0..280.0).contains(&median), "median f0 {median}");
}

/// `dir/in.wav`: the test signal at 16 kHz, mono 16-bit.
fn voice_wav_16k(dir: &Path) -> PathBuf {
    let wav = dir.join("in.wav");
    write_wav(&wav, 16_000, 1, 16, false, &test_signal(16_000));
    wav
}

#[test]
fn f0_and_frame_rate_errors_name_the_option_typed_in_its_unit() {
    let dir = temp();
    let wav = voice_wav_16k(dir.path());
    let wav = wav.to_str().expect("utf8");
    let cases: [(&[&str], &str); 4] = [
        (
            &["--f0-min", "10"],
            "--f0-min 10 Hz is out of range: use 30 to 600 Hz",
        ),
        (&["--f0-max", "2000"], "--f0-max 2000 Hz is out of range"),
        (
            &["--f0-min", "200", "--f0-max", "250"],
            "at least 1.5 times --f0-min",
        ),
        (&["--frame-rate", "5"], "--frame-rate 5 Hz is out of range"),
    ];
    for (extra, want) in cases {
        let mut args = vec!["analyze", wav, "-o", "-"];
        args.extend_from_slice(extra);
        let out = pneuma(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{extra:?} was accepted");
        assert!(stderr.contains(want), "{extra:?}: {stderr}");
        assert!(
            !stderr.contains("f0_min_hz") && !stderr.contains("frame_rate_hz"),
            "{stderr}"
        );
    }
    let help = String::from_utf8_lossy(&pneuma(&["analyze", "--help"]).stdout).into_owned();
    assert!(
        help.contains("30 to 600") && help.contains("45 to 1000"),
        "{help}"
    );
}

#[test]
fn no_overwrite_keeps_an_existing_csv_and_says_so() {
    let dir = temp();
    let wav = voice_wav_16k(dir.path());
    let csv = dir.path().join("out.csv");
    std::fs::write(&csv, "keep me\n").expect("write");
    let (wav, csv_arg) = (wav.to_str().expect("utf8"), csv.to_str().expect("utf8"));
    let out = pneuma(&["analyze", wav, "-o", csv_arg, "-n"]);
    assert!(
        !out.status.success(),
        "an existing output was replaced under -n"
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("--no-overwrite"));
    assert_eq!(std::fs::read_to_string(&csv).expect("read"), "keep me\n");
    assert!(pneuma(&["analyze", wav, "-o", csv_arg]).status.success());
    assert!(std::fs::read_to_string(&csv)
        .expect("read")
        .starts_with("time_s,"));
}

#[test]
fn channels_in_antiphase_are_named_and_one_channel_can_be_analysed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let input = dir.path().join("antiphase.wav");
    // The second channel is the first inverted: the mono mix is silence.
    support::write_wav(&input, (16_000, 2, 16, false), &test_signal(16_000), -1.0);
    let out = dir.path().join("mix.csv");
    let o = pneuma(&[
        "analyze",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("warning: left and right are in antiphase")
            && stderr.contains("--channel left"),
        "{stderr}"
    );
    let mix = parse_csv(&std::fs::read_to_string(&out).expect("csv"));
    assert!(mix.iter().all(|r| !r.voiced), "the mix cancels");
    for channel in ["left", "right"] {
        let out = dir.path().join(format!("{channel}.csv"));
        let o = pneuma(&[
            "analyze",
            input.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--channel",
            channel,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(!String::from_utf8_lossy(&o.stderr).contains("warning"));
        let rows = parse_csv(&std::fs::read_to_string(&out).expect("csv"));
        let voiced: Vec<&Row> = rows.iter().filter(|r| r.voiced).collect();
        assert!(
            voiced.len() > 40,
            "{channel}: {} voiced frames",
            voiced.len()
        );
        assert!(voiced.iter().all(|r| (r.f0_hz - 200.0).abs() < 10.0));
    }
    // A mono file has no right channel.
    let mono = dir.path().join("mono.wav");
    write_wav(&mono, 16_000, 1, 16, false, &test_signal(16_000));
    let o = pneuma(&[
        "analyze",
        mono.to_str().unwrap(),
        "-o",
        dir.path().join("m.csv").to_str().unwrap(),
        "--channel",
        "right",
    ]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("drop --channel"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
