//! What new users met (issue 33), end to end: dotted output folder names, every file of a batch
//! folder accounted for, and the messages (a folder given to `analyze`, text named `.wav`,
//! lossy input without a bit depth, "1 breath", a closed pipe, no empty folder left behind).

use std::io::Read as _;
use std::path::Path;
use std::process::{Command, Stdio};

mod support;
use support::{assert_ok, breaths_csv, example_voice, pneuma, render, write_wav};

use pneuma_core::test_signals::{self, GlottalVowel, Vowel};

/// Two glottal-vowel phrases with one pause between them, 16 kHz mono.
fn two_phrases() -> Vec<f32> {
    let r = 16_000.0;
    let phrase = |seed| {
        test_signals::glottal_vowel(
            &GlottalVowel {
                sample_rate_hz: r,
                length_s: 1.5,
                vowel: Vowel::A,
                jitter: 0.01,
                shimmer: 0.04,
                peak: 0.5,
                seed,
            },
            |t| 150.0 - 20.0 * t,
        )
    };
    let mut x = phrase(1);
    x.extend(std::iter::repeat_n(0.0, 12_800));
    x.extend(phrase(2));
    x.extend(std::iter::repeat_n(0.0, 3_200));
    x
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn dated_and_versioned_folder_names_are_folders() {
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("ep.wav");
    write_wav(&input, (16_000, 1, 16, false), &two_phrases(), 1.0);
    for name in ["2024.06.01", "Season.1", "renders.v2", "new.v3/"] {
        let out = format!("{}/{name}", dir.path().display());
        let o = render(&input, Path::new(&out), &["--no-plot"]);
        assert_ok(&o);
        let folder = dir.path().join(name.trim_end_matches('/'));
        assert!(folder.join("ep.wav").is_file(), "{name}: no ep.wav inside");
        assert!(folder.join("ep.breaths.csv").is_file(), "{name}");
    }
    // A name that is a file's is still refused, and says how to force a folder.
    let o = render(&input, &dir.path().join("ep_out.flac"), &[]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("looks like a file name"),
        "{}",
        stderr(&o)
    );
    assert!(stderr(&o).contains("ending in /"), "{}", stderr(&o));
    assert!(!dir.path().join("ep_out.flac").exists());
}

#[test]
fn every_file_of_a_batch_folder_is_in_the_table() {
    let dir = tempfile::tempdir().expect("temp");
    let episodes = dir.path().join("episodes");
    std::fs::create_dir(&episodes).expect("dir");
    write_wav(
        &episodes.join("ep01.wav"),
        (16_000, 1, 16, false),
        &two_phrases(),
        1.0,
    );
    // Ogg Opus (its first page), WMA (the ASF header GUID) and show notes.
    let mut opus = b"OggS\0\x02".to_vec();
    opus.resize(28, 0);
    opus.extend_from_slice(b"OpusHead\x01\x01");
    std::fs::write(episodes.join("ep04.opus"), &opus).expect("write");
    let mut asf = vec![0x30, 0x26, 0xb2, 0x75, 0x8e, 0x66, 0xcf, 0x11];
    asf.resize(64, 0);
    std::fs::write(episodes.join("ep05.wma"), &asf).expect("write");
    std::fs::write(episodes.join("notes.txt"), "show notes\n").expect("write");
    // Text named as audio is tried, and fails with why.
    std::fs::write(episodes.join("ep06.mp3"), "not an mp3 at all\n").expect("write");
    let out = dir.path().join("out");
    let o = pneuma(&[
        "render",
        episodes.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--no-plot",
        "--no-progress",
    ]);
    let err = stderr(&o);
    assert!(!o.status.success(), "one failed: {err}");
    let row = |name: &str| {
        err.lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("{name} is not in the table: {err}"))
            .to_owned()
    };
    assert!(row("ep01.wav").contains(" ok "), "{err}");
    let opus_row = row("ep04.opus");
    assert!(opus_row.contains("skipped"), "{opus_row}");
    assert!(
        opus_row.contains("Opus") && opus_row.contains("ffmpeg -i 'ep04.opus' 'ep04.flac'"),
        "{opus_row}"
    );
    assert!(row("ep05.wma").contains("skipped"), "{err}");
    assert!(row("ep05.wma").contains("WMA"), "{err}");
    assert!(row("notes.txt").contains("skipped  "), "{err}");
    assert!(row("notes.txt").contains("not audio"), "{err}");
    assert!(row("ep06.mp3").contains("FAILED"), "{err}");
    assert!(row("ep06.mp3").contains("it holds text"), "{err}");
    assert!(
        err.contains("1 rendered, 1 failed, 3 skipped"),
        "counts: {err}"
    );
    assert!(out.join("ep01.wav").is_file());
}

#[test]
fn analyze_names_a_folder_given_for_its_file() {
    let dir = tempfile::tempdir().expect("temp");
    let voice = example_voice();
    for out in [
        format!("{}/", dir.path().display()),
        format!("{}/new/", dir.path().display()),
    ] {
        let o = pneuma(&["analyze", voice.to_str().expect("utf-8"), "-o", &out]);
        assert!(!o.status.success());
        let err = stderr(&o);
        assert!(
            err.contains("is a folder, but analyze writes one CSV file"),
            "{err}"
        );
        assert!(err.contains("voice.csv"), "{err}");
    }
}

#[test]
fn summaries_count_breaths_in_words_and_lossy_input_has_no_bit_depth() {
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("two.wav");
    write_wav(&input, (16_000, 1, 16, false), &two_phrases(), 1.0);
    let out = dir.path().join("out");
    let o = pneuma(&[
        "render",
        input.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--no-plot",
    ]);
    assert_ok(&o);
    let n = breaths_csv(&out.join("two.breaths.csv")).len();
    assert_eq!(n, 1, "the test input should get exactly one breath");
    let err = stderr(&o);
    assert!(err.contains("16-bit): 1 breath, "), "{err}");

    if !support::have_ffmpeg("summaries_…_lossy_input_has_no_bit_depth") {
        return;
    }
    let mp3 = dir.path().join("two.mp3");
    support::ffmpeg_encode(&input, &mp3, &["-c:a", "libmp3lame", "-b:a", "64k"]);
    let o = pneuma(&[
        "render",
        mp3.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--no-plot",
    ]);
    assert_ok(&o);
    let err = stderr(&o);
    assert!(err.contains("(MP3, 16000 Hz, 1 ch)"), "{err}");
    assert!(!err.contains("-bit"), "{err}");
}

#[test]
fn a_closed_pipe_ends_render_quietly_as_analyze() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .args([
            "render",
            example_voice().to_str().expect("utf-8"),
            "-o",
            "-",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starts");
    let mut head = [0u8; 64];
    child
        .stdout
        .take()
        .expect("stdout")
        .read_exact(&mut head)
        .expect("the WAV header");
    // stdout is dropped here: the reader went away, as `| head -c 64` does.
    let o = child.wait_with_output().expect("ends");
    assert_eq!(&head[..4], b"RIFF");
    assert!(o.status.success(), "exit {:?}: {}", o.status, stderr(&o));
    assert_eq!(stderr(&o), "", "no message for a closed pipe");
}

#[test]
fn a_failed_render_leaves_no_folder_it_created() {
    let dir = tempfile::tempdir().expect("temp");
    let text = dir.path().join("take.wav");
    std::fs::write(&text, "these are notes\n").expect("write");
    let out = dir.path().join("new/renders");
    let o = render(&text, &out, &[]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("it holds text"), "{}", stderr(&o));
    assert!(!dir.path().join("new").exists(), "the created folders stay");
    // A folder that existed stays, empty or not.
    std::fs::create_dir(dir.path().join("kept")).expect("dir");
    let o = render(&text, &dir.path().join("kept"), &[]);
    assert!(!o.status.success());
    assert!(dir.path().join("kept").is_dir());
}
