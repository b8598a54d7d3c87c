//! Outputs that are not plain files, and runs whose outputs must land together: a symbolic
//! link is followed (its target replaced, the link kept), a FIFO and `/dev/null` are written
//! through (never replaced), a full device is an error (tested on device nodes made in a
//! temporary folder, never on the system's own), `-o -` into a closed pipe ends quietly,
//! and a render with one blocked output name replaces nothing and leaves no temporary file.

use std::io::Read;
use std::os::unix::fs::FileTypeExt;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::support;
use support::pneuma;

/// A voiced-looking test tone: 200 Hz with a slow level wobble, `length_s` long at 16 kHz.
fn tone(length_s: f64) -> Vec<f32> {
    let rate = 16_000.0;
    (0..(length_s * rate) as usize)
        .map(|i| {
            let t = i as f64 / rate;
            (0.3 * (0.6 + 0.4 * (1.3 * t).sin()) * (2.0 * std::f64::consts::PI * 200.0 * t).sin())
                as f32
        })
        .collect()
}

fn input(dir: &Path, length_s: f64) -> String {
    let wav = dir.join("in.wav");
    support::write_wav(&wav, (16_000, 1, 16, false), &tone(length_s), 1.0);
    wav.to_str().expect("utf-8").to_owned()
}

fn analyze_to(input: &str, output: &Path) -> std::process::Output {
    pneuma(&["analyze", input, "-o", output.to_str().expect("utf-8")])
}

#[test]
fn a_symlink_is_followed_and_kept() {
    let dir = tempfile::tempdir().expect("temp dir");
    let wav = input(dir.path(), 1.0);
    let real = dir.path().join("real.csv");
    std::fs::write(&real, "old\n").expect("write");
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink(&real, &link).expect("symlink");
    let out = analyze_to(&wav, &link);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta = std::fs::symlink_metadata(&link).expect("link");
    assert!(meta.file_type().is_symlink(), "the link was replaced");
    let text = std::fs::read_to_string(&real).expect("target");
    assert!(
        text.starts_with("time_s,"),
        "the target was not written: {text}"
    );
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names.len(), 3, "leftover files: {names:?}");
}

#[test]
fn a_fifo_with_a_reader_gets_the_data() {
    let dir = tempfile::tempdir().expect("temp dir");
    let wav = input(dir.path(), 1.0);
    let fifo = dir.path().join("pipe.csv");
    let made = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(made.success());
    let reader_path = fifo.clone();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        std::fs::File::open(&reader_path)
            .expect("open fifo")
            .read_to_string(&mut text)
            .expect("read fifo");
        text
    });
    let out = analyze_to(&wav, &fifo);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // Checked before joining: a replaced FIFO would leave the reader waiting for ever.
    let meta = std::fs::symlink_metadata(&fifo).expect("fifo");
    assert!(meta.file_type().is_fifo(), "the FIFO was replaced");
    let text = reader.join().expect("reader");
    assert!(
        text.starts_with("time_s,") && text.lines().count() > 100,
        "{text}"
    );
}

/// A character device node like `/dev/null` (1,3) or `/dev/full` (1,7) in `dir`, so that a
/// broken build replaces a copy, never the system's own device. `None` when nodes cannot be
/// made here (not root): the test then says so and skips.
fn device(dir: &Path, name: &str, minor: u32) -> Option<std::path::PathBuf> {
    let path = dir.join(name);
    let made = Command::new("mknod")
        .args(["-m", "666"])
        .arg(&path)
        .args(["c", "1", &minor.to_string()])
        .status()
        .is_ok_and(|s| s.success());
    made.then_some(path)
}

#[test]
fn a_null_device_is_written_through_and_a_full_one_is_an_error() {
    let dir = tempfile::tempdir().expect("temp dir");
    let wav = input(dir.path(), 1.0);
    let (Some(null), Some(full)) = (device(dir.path(), "null", 3), device(dir.path(), "full", 7))
    else {
        assert!(
            std::env::var("CI").is_err(),
            "cannot make device nodes under CI=true (run as root)"
        );
        eprintln!("SKIPPED: cannot make device nodes here (not root)");
        return;
    };
    let out = analyze_to(&wav, &null);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = analyze_to(&wav, &full);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "writing to a full device succeeded");
    assert!(err.contains("full"), "{err}");
    assert!(!err.contains("writable"), "{err}");
    for dev in [&null, &full] {
        let meta = std::fs::symlink_metadata(dev).expect("device");
        assert!(
            meta.file_type().is_char_device(),
            "{} was replaced",
            dev.display()
        );
    }
}

#[test]
fn stdout_into_a_closed_pipe_ends_quietly() {
    let dir = tempfile::tempdir().expect("temp dir");
    // 30 s: about 150 kB of CSV, more than a pipe holds.
    let wav = input(dir.path(), 30.0);
    let mut child = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .args(["analyze", &wav, "-o", "-"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("pneuma starts");
    let mut first = [0u8; 16];
    let mut stdout = child.stdout.take().expect("stdout");
    stdout.read_exact(&mut first).expect("first bytes");
    drop(stdout); // as `| head -c 16` does
    let out = child.wait_with_output().expect("pneuma ends");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "status {:?}: {err}", out.status);
    assert!(err.is_empty(), "error spew: {err}");
}

#[test]
fn a_render_with_one_blocked_name_replaces_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let wav = input(dir.path(), 3.0);
    let out_dir = dir.path().join("out");
    std::fs::create_dir(&out_dir).expect("out dir");
    // Old outputs that must survive, and a folder where the breaths CSV should go.
    for name in ["in.wav", "in.controls.csv", "in.png"] {
        std::fs::write(out_dir.join(name), "old").expect("old file");
    }
    std::fs::create_dir(out_dir.join("in.breaths.csv")).expect("blocker");
    std::fs::write(out_dir.join("in.breaths.csv").join("x"), "x").expect("blocker content");
    let out = support::render(Path::new(&wav), &out_dir, &[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "render over a blocked name succeeded"
    );
    assert!(err.contains("in.breaths.csv"), "{err}");
    for name in ["in.wav", "in.controls.csv", "in.png"] {
        let text = std::fs::read(out_dir.join(name)).expect("old file kept");
        assert_eq!(text, b"old", "{name} was replaced");
    }
    let mut names: Vec<String> = std::fs::read_dir(&out_dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["in.breaths.csv", "in.controls.csv", "in.png", "in.wav"],
        "temporary files left"
    );
    // Unblocked, the same render replaces all of them.
    std::fs::remove_dir_all(out_dir.join("in.breaths.csv")).expect("unblock");
    let out = support::render(Path::new(&wav), &out_dir, &[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for name in ["in.wav", "in.controls.csv", "in.png", "in.breaths.csv"] {
        let bytes = std::fs::read(out_dir.join(name)).expect("written");
        assert!(bytes.len() > 20 && bytes != b"old", "{name} not written");
    }
}
