//! What a user tryout of `pneuma render` met, end to end: files of an earlier render left
//! beside a new one's (now removed, or named with `--no-overwrite`; only files Pneuma wrote,
//! never a user's file of such a name or a link, and named even under `--quiet`), silence or
//! dither told to be normalised (now said to hold no signal), and a batch's name clashes named
//! one pair a run (now every group at once, letter case aside; a file given twice is no clash).

use std::path::{Path, PathBuf};

use crate::support::{assert_ok, pneuma, two_phrases, write_wav};

/// Writes [`two_phrases`] to `path` as a 16-bit 16 kHz mono WAV.
fn write_phrases(path: &Path) {
    write_wav(path, (16_000, 1, 16, false), &two_phrases(), 1.0);
}

/// A folder `episodes` in `dir` holding `ep.wav` ([`write_phrases`]): the folder and the file.
fn episodes_folder(dir: &Path) -> (PathBuf, PathBuf) {
    let episodes = dir.join("episodes");
    std::fs::create_dir(&episodes).expect("dir");
    let input = episodes.join("ep.wav");
    write_phrases(&input);
    (episodes, input)
}

/// `pneuma render IN -o OUT --no-progress EXTRA…`: its standard error, after checking it
/// succeeded.
fn render_ok(input: &Path, out: &Path, extra: &[&str]) -> String {
    let mut args = vec![
        "render",
        input.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--no-progress",
    ];
    args.extend_from_slice(extra);
    let o = pneuma(&args);
    assert_ok(&o);
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The extras of the first render, whose files the second one does not write.
const EXTRAS: [&str; 4] = ["--markers", "audacity,reaper", "--bvh", "--midi"];
/// The files [`EXTRAS`] write for the stem `ep`, with what leaves each out.
const EXTRA_FILES: [(&str, &str); 4] = [
    ("ep.breaths.txt", "no --markers audacity"),
    ("ep.breaths.reaper.csv", "no --markers reaper"),
    ("ep.bvh", "no --bvh"),
    ("ep.mid", "no --midi"),
];

#[test]
fn a_render_removes_the_files_an_earlier_render_left_and_says_which() {
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("ep.wav");
    write_phrases(&input);
    let out = dir.path().join("out");
    render_ok(&input, &out, &EXTRAS);
    // Files no render of `ep` writes stay: the user's, another stem's, another audio format.
    let bystanders = ["ep.notes.txt", "ep.breaths.txt.bak", "other.bvh", "ep.flac"];
    for b in bystanders {
        std::fs::write(out.join(b), "the user's").expect("write");
    }
    let err = render_ok(&input, &out, &[]);
    for (name, why) in EXTRA_FILES {
        assert!(!out.join(name).exists(), "{name} was left: {err}");
        let said = format!("{} ({why})", out.join(name).display());
        assert!(err.contains(&said), "{said} not in: {err}");
    }
    assert!(err.contains("  removed "), "{err}");
    for b in bystanders {
        assert!(out.join(b).is_file(), "{b} was removed");
    }
    assert!(out.join("ep.png").is_file() && out.join("ep.breaths.csv").is_file());

    // --no-overwrite keeps them and names them in a warning (the render's own files are new).
    render_ok(&input, &out, &EXTRAS);
    for own in ["ep.wav", "ep.controls.csv", "ep.breaths.csv", "ep.png"] {
        std::fs::remove_file(out.join(own)).expect("rm");
    }
    let err = render_ok(&input, &out, &["--no-overwrite"]);
    for (name, why) in EXTRA_FILES {
        assert!(out.join(name).is_file(), "{name} was removed despite -n");
        assert!(
            err.contains(&format!("{} ({why})", out.join(name).display())),
            "{err}"
        );
    }
    assert!(
        err.contains("warning: ") && err.contains("--no-overwrite keeps them"),
        "{err}"
    );
    assert!(!err.contains("  removed "), "{err}");

    // The plot is one of them when --no-plot leaves it out.
    let err = render_ok(&input, &out, &["--no-plot"]);
    assert!(!out.join("ep.png").exists(), "{err}");
    assert!(err.contains("ep.png (--no-plot)"), "{err}");
    assert!(out.join("ep.wav").is_file() && out.join("ep.flac").is_file());
}

#[test]
fn a_batch_removes_each_inputs_leftovers_and_says_so_under_the_table() {
    let dir = tempfile::tempdir().expect("temp");
    let episodes = dir.path().join("episodes");
    std::fs::create_dir(&episodes).expect("dir");
    for name in ["a.wav", "b.wav"] {
        write_phrases(&episodes.join(name));
    }
    let out = dir.path().join("out");
    render_ok(&episodes, &out, &["--no-plot", "--bvh", "--midi"]);
    assert!(out.join("a.bvh").is_file() && out.join("b.mid").is_file());
    let err = render_ok(&episodes, &out, &["--no-plot", "--midi"]);
    for stem in ["a", "b"] {
        let bvh = out.join(format!("{stem}.bvh"));
        assert!(!bvh.exists(), "{stem}.bvh was left: {err}");
        assert!(
            err.contains(&format!("removed {} (no --bvh)", bvh.display())),
            "{err}"
        );
        assert!(out.join(format!("{stem}.mid")).is_file(), "{err}");
    }
}

/// A 16-bit WAV of `seconds` of `mono` samples drawn from `steps` (in 16-bit steps).
fn steps_wav(path: &Path, seconds: f32, steps: &[i32]) {
    let n = (16_000.0 * seconds) as usize;
    // A fixed pseudo-random walk through `steps` (dither-like, no tone).
    let mut state = 0x2545_f491_u32;
    let x: Vec<f32> = (0..n)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            steps[state as usize % steps.len()] as f32 / 32767.0
        })
        .collect();
    write_wav(path, (16_000, 1, 16, false), &x, 1.0);
}

#[test]
fn silence_and_dither_are_said_to_hold_no_signal_not_to_need_normalising() {
    let dir = tempfile::tempdir().expect("temp");
    let inputs = dir.path().join("in");
    std::fs::create_dir(&inputs).expect("dir");
    // Dither of an export of silence (-1, 0, +1 steps: peak -90 dBFS), and all zeros.
    steps_wav(&inputs.join("dither.wav"), 3.0, &[-1, 0, 0, 1]);
    steps_wav(&inputs.join("zeros.wav"), 3.0, &[0]);
    let out = dir.path().join("out");
    let err = render_ok(&inputs.join("dither.wav"), &out, &["--no-plot"]);
    assert!(
        err.contains("warning: the input holds no signal (silence or dither only, peak -90 dBFS)"),
        "{err}"
    );
    assert!(
        !err.contains("normalise it") && !err.contains("gain -n"),
        "{err}"
    );
    let err = render_ok(&inputs.join("zeros.wav"), &out, &["--no-plot"]);
    assert!(
        err.contains("warning: the input holds no signal (digital silence"),
        "{err}"
    );
    assert!(!err.contains("no speech found"), "{err}");
    // The batch table says it in its warnings column.
    let err = render_ok(&inputs, &out, &["--no-plot"]);
    for name in ["dither.wav", "zeros.wav"] {
        let row = err.lines().find(|l| l.contains(name)).expect("a row");
        assert!(row.contains(" ok ") && row.contains("no signal"), "{row}");
    }
}

#[test]
fn a_batch_names_every_clashing_group_at_once() {
    let dir = tempfile::tempdir().expect("temp");
    let inputs = dir.path().join("in");
    std::fs::create_dir(&inputs).expect("dir");
    let wav = inputs.join("talk.wav");
    write_phrases(&wav);
    let clashing = ["talk.mp3", "talk.flac", "truncated.mp3", "truncated.wav"];
    for name in clashing {
        std::fs::copy(&wav, inputs.join(name)).expect("copy");
    }
    write_phrases(&inputs.join("alone.wav"));
    let out = dir.path().join("out");
    let o = pneuma(&[
        "render",
        inputs.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(err.contains("would write the same output files"), "{err}");
    assert!(err.contains("(2 groups)"), "{err}");
    let line = |stem: &str| -> Vec<String> {
        let l = err
            .lines()
            .find(|l| l.contains(&format!("{stem}.wav")))
            .unwrap_or_else(|| panic!("no {stem} group: {err}"));
        l.trim().split(", ").map(str::to_owned).collect()
    };
    let names = |stem: &str, exts: &[&str]| -> Vec<String> {
        exts.iter()
            .map(|e| inputs.join(format!("{stem}.{e}")).display().to_string())
            .collect()
    };
    assert_eq!(line("talk"), names("talk", &["flac", "mp3", "wav"]));
    assert_eq!(line("truncated"), names("truncated", &["mp3", "wav"]));
    assert!(!err.contains("alone"), "{err}");
    assert!(!out.exists(), "nothing is rendered");
}

/// A file of each name a render may leave, as a user made it: artwork, a motion capture, a
/// song, label tracks of their own.
const USERS_FILES: [(&str, &[u8]); 5] = [
    ("ep.png", b"\x89PNG\r\n\x1a\n the podcast's artwork"),
    ("ep.bvh", b"HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n"),
    ("ep.mid", b"MThd\0\0\0\x06\0\x01\0\x02\x01\xe0 the song"),
    ("ep.breaths.txt", b"1.000000\t2.000000\tchorus\n"),
    (
        "ep.breaths.reaper.csv",
        b"#,Name,Start,End,Length\nR1,Intro,0:00.000,0:12.500,0:12.500\n",
    ),
];

#[test]
fn a_users_files_of_those_names_beside_the_input_stay_and_are_not_named() {
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("ep.wav");
    write_phrases(&input);
    for (name, bytes) in USERS_FILES {
        std::fs::write(dir.path().join(name), bytes).expect("write");
    }
    // Into the input's own folder, the audio as FLAC beside it; no plot, BVH, MIDI or markers.
    let err = render_ok(&input, dir.path(), &["--format", "flac", "--no-plot"]);
    assert!(dir.path().join("ep.flac").is_file(), "{err}");
    for (name, bytes) in USERS_FILES {
        let now = std::fs::read(dir.path().join(name)).unwrap_or_default();
        assert_eq!(now, bytes, "{name} was touched: {err}");
        assert!(!err.contains(name), "{name} named: {err}");
    }
    assert!(
        !err.contains("removed") && !err.contains("earlier render"),
        "{err}"
    );
}

#[cfg(unix)]
#[test]
fn a_link_of_a_leftovers_name_stays() {
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("ep.wav");
    write_phrases(&input);
    let out = dir.path().join("out");
    render_ok(&input, &out, &["--bvh"]);
    // Pneuma's own BVH, kept by the user under another name and linked to as `ep.bvh`.
    let kept = out.join("take.bvh");
    std::fs::rename(out.join("ep.bvh"), &kept).expect("rename");
    std::os::unix::fs::symlink(&kept, out.join("ep.bvh")).expect("link");
    let err = render_ok(&input, &out, &[]);
    assert!(
        std::fs::symlink_metadata(out.join("ep.bvh")).is_ok(),
        "{err}"
    );
    assert!(kept.is_file(), "{err}");
    assert!(!err.contains("ep.bvh") && !err.contains("removed"), "{err}");
}

#[test]
fn quiet_still_names_what_it_removed() {
    let dir = tempfile::tempdir().expect("temp");
    let (episodes, input) = episodes_folder(dir.path());
    let out = dir.path().join("out");
    let removed = format!("removed {} (no --bvh)", out.join("ep.bvh").display());
    // One input, then a batch (a folder).
    for given in [&input, &episodes] {
        render_ok(given, &out, &["--bvh", "--quiet"]);
        assert!(out.join("ep.bvh").is_file());
        let err = render_ok(given, &out, &["--quiet"]);
        assert!(!out.join("ep.bvh").exists(), "{err}");
        assert!(err.contains(&removed), "{}: {err:?}", given.display());
        assert!(!err.contains("rendered"), "quiet: {err}");
    }
}

#[test]
fn names_that_differ_only_in_letter_case_clash() {
    let dir = tempfile::tempdir().expect("temp");
    let talk = dir.path().join("Talk.wav");
    write_phrases(&talk);
    let lower = dir.path().join("talk.flac");
    std::fs::copy(&talk, &lower).expect("copy");
    let out = dir.path().join("out");
    let o = pneuma(&[
        "render",
        talk.to_str().expect("utf-8"),
        lower.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(err.contains("would write the same output files"), "{err}");
    let group = format!("{}, {}", talk.display(), lower.display());
    assert!(err.contains(&group), "{err}");
    assert!(!out.exists(), "nothing is rendered");
}

#[test]
fn an_input_given_twice_is_rendered_once() {
    let dir = tempfile::tempdir().expect("temp");
    let (episodes, input) = episodes_folder(dir.path());
    let out = dir.path().join("out");
    let path = input.to_str().expect("utf-8");
    let folder = episodes.to_str().expect("utf-8");
    let out_s = out.to_str().expect("utf-8");
    // Twice as a file: one render and its summary; as a folder and a file in it: a batch of one.
    for (given, once) in [
        ([path, path], format!("rendered {path} (")),
        ([folder, path], "1 rendered, 0 failed, 0 skipped".to_owned()),
    ] {
        let o = pneuma(&["render", given[0], given[1], "-o", out_s, "--no-progress"]);
        assert_ok(&o);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !err.contains("rename") && !err.contains("same name"),
            "{err}"
        );
        assert_eq!(err.matches(&once).count(), 1, "{once}: {err}");
        assert!(out.join("ep.wav").is_file(), "{err}");
    }
}
