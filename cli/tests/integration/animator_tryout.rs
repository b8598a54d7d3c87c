//! What a tryout by an animator and VTuber met, end to end: `--bvh-fps` without `--bvh` wrote
//! no BVH and removed an earlier one (now it turns `--bvh` on, as `--osc-*` options turn on
//! OSC, in `render` and `speak`); the MIDI file was 7-bit with a fixed head range (now
//! `--midi-14bit` and `--midi-head-range-deg`, read back by an independent reader); an unknown
//! espeak-ng voice was told twice, espeak-ng's line and our question (now once, what to do).

use std::path::Path;

use crate::support::{self, assert_ok, pneuma, two_phrases, write_wav};

/// `pneuma render IN -o OUT --no-progress --no-plot EXTRA…`: its standard error, after checking
/// it succeeded.
fn render_ok(input: &Path, out: &Path, extra: &[&str]) -> String {
    let o = support::render(
        input,
        out,
        &[&["--no-progress", "--no-plot"], extra].concat(),
    );
    assert_ok(&o);
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A 16 kHz WAV of [`two_phrases`] at `dir/ep.wav`.
fn episode(dir: &Path) -> std::path::PathBuf {
    let input = dir.join("ep.wav");
    write_wav(&input, (16_000, 1, 16, false), &two_phrases(), 1.0);
    input
}

#[test]
fn bvh_fps_alone_writes_the_bvh_at_that_rate_and_keeps_an_earlier_one() {
    let dir = tempfile::tempdir().expect("temp");
    let input = episode(dir.path());
    let out = dir.path().join("out");
    render_ok(&input, &out, &["--bvh"]);
    let err = render_ok(&input, &out, &["--bvh-fps", "24"]);
    assert!(!err.contains("removed"), "{err}");
    let (frames, frame_time_s) = support::bvh_timing(&out.join("ep.bvh"));
    assert!((frame_time_s - 1.0 / 24.0).abs() < 1e-6, "{frame_time_s}");
    // One frame per 1/24 s over the audio's length.
    let length_s = two_phrases().len() as f64 / 16_000.0;
    assert!(
        (frames as f64 - length_s * 24.0).abs() <= 1.0,
        "{frames} frames over {length_s} s"
    );
}

#[test]
fn speak_takes_bvh_fps_and_it_turns_the_bvh_on() {
    if !support::tool_or_skip("espeak-ng", "--version", "speak_takes_bvh_fps") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let out = dir.path().to_str().expect("utf-8");
    assert_ok(&pneuma(&[
        "speak",
        "A breath group.",
        "-o",
        out,
        "--bvh-fps",
        "30",
        "--no-plot",
        "-q",
    ]));
    let (frames, frame_time_s) = support::bvh_timing(&dir.path().join("speech.bvh"));
    assert!((frame_time_s - 1.0 / 30.0).abs() < 1e-6, "{frame_time_s}");
    assert!(frames > 30, "{frames} frames");
}

/// The column `name` of a controls CSV, with each row's `time_s`.
fn controls_column(path: &Path, name: &str) -> Vec<(f64, f64)> {
    let csv = std::fs::read_to_string(path).expect("controls CSV");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).expect(n);
    let (t, v) = (col("time_s"), col(name));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[t].parse().expect("time"), f[v].parse().expect(name))
        })
        .collect()
}

#[test]
fn midi_14bit_writes_msb_lsb_pairs_over_the_head_range_asked() {
    let Some(python) = support::python_tools("midi_14bit_writes_msb_lsb_pairs") else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp");
    // Speech, so the head moves (the generated vowels are held at rest).
    let input = pneuma_testkit::voice::example_voice_path();
    let out = dir.path().join("out");
    let range_deg = 5.0;
    // Without --midi: each --midi-* option turns it on.
    render_ok(
        &input,
        &out,
        &[
            "--midi-14bit",
            "--midi-head-range-deg",
            &range_deg.to_string(),
        ],
    );
    let (_, ccs) = support::read_midi(&python, &out.join("voice.mid"));
    // MIDI 1.0's pairs: every message on a controller n < 32 (the MSB) is followed at the same
    // time by one on n + 32 (the LSB); nothing else is sent.
    assert!(ccs.len() > 20, "{} messages", ccs.len());
    assert_eq!(ccs.len() % 2, 0);
    let mut pitch = Vec::new();
    for pair in ccs.chunks(2) {
        let ((t, _, msb_cc, msb), (t2, _, lsb_cc, lsb)) = (pair[0], pair[1]);
        assert!(msb_cc < 32 && lsb_cc == msb_cc + 32 && t == t2, "{pair:?}");
        if msb_cc == 16 {
            pitch.push((t, u32::from(msb) * 128 + u32::from(lsb)));
        }
    }
    // Head pitch (CC 16/48): 8192 is 0°, 0 and 16384 the ends of ±range.
    let csv = controls_column(&out.join("voice.controls.csv"), "head_pitch_deg");
    let mut largest_deg: f64 = 0.0;
    for (t, value) in pitch {
        let (_, deg) = *csv
            .iter()
            .find(|(ct, _)| (ct - t).abs() < 0.5 / 120.0)
            .unwrap_or_else(|| panic!("no controls row at {t} s"));
        let want = (deg.clamp(-range_deg, range_deg) / range_deg + 1.0) * 8192.0;
        // The CSV has 3 decimals: 0.0005° is 0.8 of a step at ±5°.
        assert!(
            (f64::from(value) - want.min(16383.0)).abs() <= 2.0,
            "{deg}° at {t} s sent as {value}, want {want}"
        );
        largest_deg = largest_deg.max(deg.abs());
    }
    // The head moved, so the range mattered (±30° would give a third of the swing).
    assert!(largest_deg > 0.5, "the head barely moved: {largest_deg}°");
}

#[test]
fn a_midi_head_range_outside_the_table_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().expect("temp");
    let input = episode(dir.path());
    let out = dir.path().join("out");
    let o = support::render(&input, &out, &["--midi-head-range-deg", "0"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--midi-head-range-deg 0° is out of range: use "),
        "{err}"
    );
    assert!(!out.exists(), "{err}");
}

#[test]
fn frame_rate_help_says_it_moves_breaths_and_points_to_bvh_fps() {
    for command in ["render", "speak"] {
        let o = pneuma(&[command, "--help"]);
        assert_ok(&o);
        let help = String::from_utf8_lossy(&o.stdout);
        let start = help.find("--frame-rate").expect("--frame-rate");
        let paragraph = &help[start..help[start..].find("\n\n").map_or(help.len(), |e| start + e)];
        for words in ["analysis", "breaths", "--bvh-fps"] {
            assert!(paragraph.contains(words), "{command}: {words}: {paragraph}");
        }
    }
}

#[test]
fn an_unknown_espeak_voice_is_told_once_with_what_to_do() {
    if !support::tool_or_skip("espeak-ng", "--version", "an_unknown_espeak_voice") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let out = dir.path().join("spoken");
    let o = pneuma(&[
        "speak",
        "--voice",
        "nonexistent",
        "hello",
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("no voice `nonexistent`") && err.contains("`espeak-ng --voices`"),
        "{err}"
    );
    // espeak-ng's own line is not repeated beside ours.
    assert!(!err.contains("does not exist"), "{err}");
    assert!(!out.exists());
}
