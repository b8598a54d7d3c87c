//! `pneuma train` and `pneuma eval head` end to end on a generated data set (glottal vowels
//! whose f0 drives the head pitch of the paired head CSV), plus clear errors for a missing data
//! folder, a broken head CSV and a broken model file.

use std::fmt::Write as _;
use std::path::Path;

use pneuma_core::head::HeadModel;
use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

use crate::support;
use support::pneuma;

fn f0_of(t: f64, phase: f64) -> f64 {
    if t % 2.0 < 1.6 {
        150.0 * 2f64.powf(0.25 * (1.7 * t + phase).sin())
    } else {
        0.0
    }
}

/// One clip: 8 s of phrases (1.6 s voiced, 0.4 s pause) and a 30 fps head CSV whose pitch
/// follows the semitone f0 contour.
fn write_clip(dir: &Path, name: &str, phase: f64, seed: u64) {
    let cfg = GlottalVowel {
        sample_rate_hz: 16_000.0,
        length_s: 8.0,
        vowel: Vowel::A,
        jitter: 0.005,
        shimmer: 0.03,
        peak: 0.5,
        seed,
    };
    let mut x = signals::glottal_vowel(&cfg, |t| f0_of(t, phase));
    signals::add_white_noise(&mut x, 40.0, seed + 1);
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: 16_000,
        bits_per_sample: 16,
        sample_format: hound::SampleFormat::Int,
    };
    let mut w = hound::WavWriter::create(dir.join(format!("{name}.wav")), spec).unwrap();
    for v in x {
        w.write_sample((v * 32767.0).round() as i16).unwrap();
    }
    w.finalize().unwrap();
    let mut csv = String::from("time_s,pitch_deg,yaw_deg,roll_deg\n");
    for i in 0..240 {
        let t = i as f64 / 30.0;
        let st = 3.0 * (1.7 * t + phase).sin();
        let _ = writeln!(
            csv,
            "{t:.4},{:.4},{:.4},{:.4}",
            2.0 + 1.2 * st,
            3.0 * (0.6 * t + phase).sin(),
            1.5 * (1.1 * t).cos()
        );
    }
    std::fs::write(dir.join(format!("{name}.head.csv")), csv).unwrap();
}

#[test]
fn train_then_eval_on_generated_clips() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    write_clip(&data, "one", 0.0, 1);
    write_clip(&data, "two", 1.5, 2);
    write_clip(&data, "three", 3.0, 3);
    let model = dir.path().join("model.json");
    let out = pneuma(&[
        "train",
        "--data",
        data.to_str().unwrap(),
        "-o",
        model.to_str().unwrap(),
        "--components",
        "3",
        "--restarts",
        "1",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("held-out log-likelihood"), "{stdout}");
    assert!(stdout.contains("kept: "), "{stdout}");
    let m = HeadModel::from_json(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(m.provenance.clips, ["one", "three", "two"]);
    assert_eq!(m.provenance.held_out_log_likelihood.len(), 5);
    assert!(
        m.provenance.voiced_frames > 1000,
        "{}",
        m.provenance.voiced_frames
    );

    let out = pneuma(&[
        "eval",
        "head",
        "--model",
        model.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mean = stdout
        .lines()
        .find(|l| l.starts_with("mean,"))
        .expect("a mean row");
    let cols: Vec<f64> = mean
        .split(',')
        .skip(1)
        .map(|v| v.parse().unwrap())
        .collect();
    // In this data head pitch is a function of f0, so the real motion's CCA with f0 is high.
    // The generated motion's CCA is not asserted: on three 8 s clips of smooth sinusoids it
    // comes out near 0.45 whether or not the training motion followed f0 (checked by training
    // on a head pitch unrelated to f0), so it says nothing here; the model's tie to f0 is
    // checked on real motion by `eval head --cross-validate --check` in `.ci/run`. What is
    // asserted of the generated motion is that it moves on every axis and is rarely frozen.
    let cca_real = cols[2];
    assert!(cca_real > 0.8, "{mean}");
    for (axis, col) in [("roll", 7), ("pitch", 9), ("yaw", 11)] {
        assert!(
            cols[col] > 0.2,
            "generated {axis} SD {} deg: {mean}",
            cols[col]
        );
    }
    assert!(
        cols[15] < 0.3,
        "generated frozen share {}: {mean}",
        cols[15]
    );
    assert!(stdout.contains("targets:"));
}

#[test]
fn clear_errors_for_bad_data_and_models() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("nope");
    let out = pneuma(&["train", "--data", missing.to_str().unwrap(), "-o", "x.json"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("cannot read the data folder"));

    let data = dir.path().join("data");
    std::fs::create_dir(&data).unwrap();
    // A folder as the model file is refused before any training.
    let out = pneuma(&[
        "train",
        "--data",
        data.to_str().unwrap(),
        "-o",
        dir.path().to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("is a folder; give the model file"),
        "{err}"
    );
    let out = pneuma(&["eval", "head", "--data", data.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("no <clip>.wav + <clip>.head.csv pairs"));

    // A lone WAV and a lone motion file: the message names which partner is missing.
    std::fs::write(data.join("solo.wav"), b"RIFF").unwrap();
    std::fs::write(
        data.join("other.head.csv"),
        "time_s,pitch_deg,yaw_deg,roll_deg\n",
    )
    .unwrap();
    let out = pneuma(&["train", "--data", data.to_str().unwrap(), "-o", "x.json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("no .head.csv for solo.wav")
            && err.contains("no audio file (.wav, .flac, …) for other.head.csv"),
        "{err}"
    );
    std::fs::remove_file(data.join("solo.wav")).unwrap();
    std::fs::remove_file(data.join("other.head.csv")).unwrap();

    write_clip(&data, "one", 0.0, 1);
    std::fs::write(
        data.join("one.head.csv"),
        "time_s,pitch_deg,yaw_deg\n0,1,2\n",
    )
    .unwrap();
    let out = pneuma(&["eval", "head", "--data", data.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("roll_deg"), "{err}");
    // One clip leaves nothing to hold out: refused, saying so.
    write_clip(&data, "one", 0.0, 1);
    let out = pneuma(&["train", "--data", data.to_str().unwrap(), "-o", "x.json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("holds one clip"),
        "{err}"
    );

    let bad_model = dir.path().join("bad.json");
    std::fs::write(
        &bad_model,
        r#"{"format": "pneuma-head-model", "version": 7}"#,
    )
    .unwrap();
    let out = pneuma(&[
        "eval",
        "head",
        "--model",
        bad_model.to_str().unwrap(),
        "--data",
        data.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("version 7"), "{err}");
}
