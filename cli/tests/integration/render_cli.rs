//! `pneuma render` end to end: every output file of the contract, the input's format kept
//! (mono, stereo, 16-bit, 24-bit, float), the audio bit-identical outside the inserted breaths,
//! breaths only in long pauses, and broken input rejected without touching existing output.

use std::path::{Path, PathBuf};

use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

use crate::support;
use support::render;

/// Writes `mono` to all channels (the second at 0.7×) in the given format.
fn write_wav(path: &Path, rate: u32, channels: u16, bits: u16, float: bool, mono: &[f32]) {
    support::write_wav(path, (rate, channels, bits, float), mono, 0.7);
}

/// Phrases (voiced glottal vowels) separated by the given pauses after a 0.5 s lead-in; returns
/// the mono signal and the phrase spans in seconds.
fn phrases(rate: u32, lengths: &[f64], pauses: &[f64]) -> (Vec<f32>, Vec<(f64, f64)>) {
    let r = rate as f64;
    let mut x = vec![0.0f32; (0.5 * r) as usize];
    let mut spans = Vec::new();
    for (i, &len) in lengths.iter().enumerate() {
        let on = x.len() as f64 / r;
        let v = signals::glottal_vowel(
            &GlottalVowel {
                sample_rate_hz: r,
                length_s: len,
                vowel: [Vowel::A, Vowel::I, Vowel::U][i % 3],
                jitter: 0.01,
                shimmer: 0.04,
                peak: 0.5,
                seed: i as u64,
            },
            |t| 150.0 - 30.0 * t / len,
        );
        x.extend(v);
        spans.push((on, x.len() as f64 / r));
        let p = pauses.get(i).copied().unwrap_or(0.4);
        x.extend(std::iter::repeat_n(0.0, (p * r) as usize));
    }
    (x, spans)
}

/// Raw samples as i64 (float bits for float files), interleaved.
fn raw(path: &Path) -> (hound::WavSpec, Vec<i64>) {
    let mut r = hound::WavReader::open(path).expect("open wav");
    let spec = r.spec();
    let v = if spec.sample_format == hound::SampleFormat::Float {
        r.samples::<f32>()
            .map(|s| s.expect("sample").to_bits() as i64)
            .collect()
    } else {
        r.samples::<i32>()
            .map(|s| s.expect("sample") as i64)
            .collect()
    };
    (spec, v)
}

fn read_breaths(path: &Path) -> Vec<(f64, f64, String, f64)> {
    let text = std::fs::read_to_string(path).expect("breaths csv");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("start_s,end_s,kind,peak_db"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), 4, "{l}");
            (
                f[0].parse().expect("start"),
                f[1].parse().expect("end"),
                f[2].to_string(),
                f[3].parse().expect("peak"),
            )
        })
        .collect()
}

#[test]
fn render_keeps_the_format_and_changes_only_the_breaths() {
    let dir = tempfile::tempdir().expect("tempdir");
    let pauses = [0.2, 0.8, 1.2];
    let (x, spans) = phrases(22_050, &[1.0, 1.0, 1.2, 0.8], &pauses);
    for (channels, bits, float) in [
        (1u16, 16u16, false),
        (2, 24, false),
        (1, 32, true),
        (2, 16, false),
    ] {
        let name = format!("in_{channels}ch_{bits}{}", if float { "f" } else { "" });
        let input = dir.path().join(format!("{name}.wav"));
        write_wav(&input, 22_050, channels, bits, float, &x);
        let out = dir.path().join(format!("out_{name}"));
        // Sustained generated vowels are not speech to the speech decision: --any-sound.
        let o = render(&input, &out, &["--any-sound"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for ext in ["wav", "controls.csv", "breaths.csv", "png"] {
            assert!(
                out.join(format!("{name}.{ext}")).is_file(),
                "missing {name}.{ext}"
            );
        }
        let (spec_in, a) = raw(&input);
        let (spec_out, b) = raw(&out.join(format!("{name}.wav")));
        assert_eq!(
            spec_in, spec_out,
            "the output format differs from the input's"
        );
        assert_eq!(a.len(), b.len(), "the output length differs");
        let breaths = read_breaths(&out.join(format!("{name}.breaths.csv")));
        // Lead-in (0.5 s), 0.8 s and 1.2 s pauses get a breath; the 0.2 s pause does not.
        assert_eq!(breaths.len(), 3, "{breaths:?}");
        for (s, e, kind, peak) in &breaths {
            assert!(
                ["mouth", "nose", "mixed", "sample"].contains(&kind.as_str()),
                "{kind}"
            );
            assert!(*peak < -6.0, "breath peak {peak} dBFS");
            for &(on, off) in &spans {
                assert!(
                    *e <= on || *s >= off,
                    "breath {s}–{e} overlaps speech {on}–{off}"
                );
            }
        }
        let ch = channels as usize;
        let mut changed = 0;
        for (i, (p, q)) in a.iter().zip(&b).enumerate() {
            if p != q {
                changed += 1;
                let t = (i / ch) as f64 / 22_050.0;
                assert!(
                    breaths
                        .iter()
                        .any(|(s, e, _, _)| t >= s - 1e-3 && t <= e + 1e-3),
                    "{name}: sample at {t:.4} s changed outside every breath"
                );
            }
        }
        assert!(
            changed > 1000,
            "{name}: the breaths changed only {changed} samples"
        );
    }
}

#[test]
fn controls_follow_the_contract_and_bvh_is_written_on_request() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (x, _) = phrases(16_000, &[1.0, 1.0], &[0.7]);
    let input = dir.path().join("v.wav");
    write_wav(&input, 16_000, 1, 16, false, &x);
    let out = dir.path().join("out");
    // Sustained generated vowels are not speech to the speech decision, and the body neither
    // speaks nor breathes for what is not speech: --any-sound.
    let o = render(
        &input,
        &out,
        &[
            "--bvh",
            "--frame-rate",
            "60",
            "--preset",
            "calm",
            "--any-sound",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("v.controls.csv")).expect("controls");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,f0_hz,voiced,rms_db,speaking,phase,lung,thorax,abdomen,neck_pitch_deg,nostril_flare,mouth_open,head_pitch_deg,head_yaw_deg,head_roll_deg")
    );
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    let duration = x.len() as f64 / 16_000.0;
    assert_eq!(
        rows.len(),
        (duration * 60.0).ceil() as usize,
        "one row per 60 Hz frame"
    );
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 15);
        let t: f64 = r[0].parse().expect("time");
        assert!((t - k as f64 / 60.0).abs() < 1e-3, "row {k} at {t}");
        assert!(["rest", "inspiration", "expiration"].contains(&r[5].as_str()));
        for col in [6, 7, 8, 10, 11] {
            let v: f64 = r[col].parse().expect("number");
            assert!((0.0..=1.0).contains(&v), "column {col} = {v}");
        }
    }
    assert!(rows.iter().any(|r| r[5] == "inspiration"));
    assert!(rows.iter().any(|r| r[4] == "1"));
    let bvh = std::fs::read_to_string(out.join("v.bvh")).expect("bvh written");
    assert!(
        bvh.starts_with("HIERARCHY"),
        "{}",
        &bvh[..bvh.len().min(80)]
    );
    assert!(bvh.contains("MOTION"));
}

#[test]
fn no_breaths_copies_the_audio_exactly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (x, _) = phrases(48_000, &[0.8, 0.8], &[0.8]);
    let input = dir.path().join("v.wav");
    write_wav(&input, 48_000, 2, 24, false, &x);
    let out = dir.path().join("out");
    let o = render(&input, &out, &["--no-breaths", "--no-plot"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(raw(&input), raw(&out.join("v.wav")));
    assert_eq!(read_breaths(&out.join("v.breaths.csv")).len(), 0);
}

#[test]
fn broken_input_fails_cleanly_and_keeps_existing_output() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("out");
    std::fs::create_dir_all(&out).expect("mkdir");
    // An earlier good render's files must survive a failed render.
    let keep = out.join("v.wav");
    std::fs::write(&keep, b"earlier render").expect("write");
    let (x, _) = phrases(16_000, &[1.0], &[0.5]);
    let good = dir.path().join("good.wav");
    write_wav(&good, 16_000, 1, 16, false, &x);
    let bytes = std::fs::read(&good).expect("read");
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("empty", vec![], "holds no audio"),
        (
            "text",
            b"hello, this is not audio".to_vec(),
            "is not audio: it holds text",
        ),
        ("truncated", bytes[..bytes.len() / 2].to_vec(), "damaged"),
    ];
    for (name, content, message) in cases {
        let input = dir.path().join("v.wav");
        std::fs::write(&input, &content).expect("write");
        let o = render(&input, &out, &[]);
        assert!(!o.status.success(), "{name} was accepted");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(message), "{name}: {err}");
        assert_eq!(
            std::fs::read(&keep).expect("kept"),
            b"earlier render",
            "{name}"
        );
        let leftovers: Vec<PathBuf> = std::fs::read_dir(&out)
            .expect("dir")
            .map(|e| e.expect("entry").path())
            .filter(|p| p.to_string_lossy().contains(".partial"))
            .collect();
        assert!(leftovers.is_empty(), "{name}: {leftovers:?}");
    }
    // Bad settings are named.
    let o = render(&good, &out, &["--preset", "sleepy"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("preset"));
    // Out-of-range options are named as typed, in their unit, with the range: the settings
    // table's (core/src/settings), the plugin's since its first release, not the wider ones
    // the command line had (-60 dB, 5000 ms, 10 to 1000 Hz).
    for (option, value, want) in [
        (
            "--breath-level-db",
            "-50",
            "--breath-level-db -50 dB is out of range: use -40 to -6 dB",
        ),
        (
            "--lookahead-ms",
            "0",
            "--lookahead-ms 0 ms is out of range: use 300 to 2000 ms",
        ),
        (
            "--min-pause-ms",
            "2500",
            "--min-pause-ms 2500 ms is out of range: use 100 to 2000 ms",
        ),
        (
            "--frame-rate",
            "500",
            "--frame-rate 500 Hz is out of range: use 30 to 240 Hz",
        ),
        ("--mode", "later", "[possible values: lookahead, live]"),
    ] {
        let o = render(&good, &out, &[option, value]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{option} {value}");
        assert!(err.contains(want), "{option}: {err}");
        assert!(!err.contains("_s`") && !err.contains("writable"), "{err}");
    }
    // A lookahead is refused in live mode, which has none.
    let o = render(&good, &out, &["--mode", "live", "--lookahead-ms", "300"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("live mode has none"),
        "{err}"
    );
    // An existing file is not a folder to write into.
    let file = dir.path().join("notes");
    std::fs::write(&file, b"x").unwrap();
    let o = render(&good, &file, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("is an existing file"),
        "{err}"
    );
    // A Unicode minus pasted from the docs is a minus.
    let o = render(&good, &out, &["--breath-level-db", "\u{2212}30"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // `-o name.wav` is not silently made a folder.
    let o = render(&good, &dir.path().join("result.wav"), &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("output folder"),
        "{err}"
    );
    assert!(!dir.path().join("result.wav").exists());
    // -n keeps existing outputs and says which one exists.
    let o = render(&good, &out, &["-n"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--no-overwrite"),
        "{err}"
    );
}

#[test]
fn help_shows_every_range_in_ascii() {
    // Lines wrap at the terminal's width (100 columns without one): compare words only.
    let words = |out: &[u8]| {
        String::from_utf8_lossy(out)
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
    };
    let o = support::pneuma(&["render", "--help"]);
    let help = words(&o.stdout);
    assert!(!help.contains('\u{2212}'), "Unicode minus in help");
    for want in [
        "-40 to -6 dB; default -22 dB",
        "100 to 2000 ms; default 250 ms",
        "300 to 2000 ms",
        "30 to 240 Hz; default 120 Hz",
        "[default: lookahead]",
    ] {
        assert!(
            help.contains(want),
            "`{want}` not in render --help:\n{help}"
        );
    }
    let o = support::pneuma(&["speak", "--help"]);
    let help = words(&o.stdout);
    for want in ["0.5 to 2", "0.05 to 1", "--output"] {
        assert!(help.contains(want), "`{want}` not in speak --help:\n{help}");
    }
}
