//! What a podcaster does with `pneuma render`: pipes (`-` in, `-o -` out), breath markers for
//! editors (Audacity labels, REAPER regions, WAV cue points — each parsed back here), batches
//! with a broken file, the output format and tags of lossy and lossless input, and Ctrl-C.

use std::path::Path;
use std::process::Command;

use crate::support;
use pneuma_testkit::voice::example_voice_path;
use support::{
    assert_ok, breaths_csv, ffmpeg_encode, have_ffmpeg, pneuma, pneuma_with_stdin, render, samples,
};

/// The RIFF chunks of a WAV file: (id, body).
pub(crate) fn riff_chunks(bytes: &[u8]) -> Vec<([u8; 4], Vec<u8>)> {
    assert_eq!(&bytes[..4], b"RIFF");
    assert_eq!(&bytes[8..12], b"WAVE");
    let riff_end = 8 + u32::from_le_bytes(bytes[4..8].try_into().expect("4")) as usize;
    assert_eq!(riff_end, bytes.len(), "RIFF size");
    let mut at = 12;
    let mut out = Vec::new();
    while at + 8 <= bytes.len() {
        let id: [u8; 4] = bytes[at..at + 4].try_into().expect("4");
        let size = u32::from_le_bytes(bytes[at + 4..at + 8].try_into().expect("4")) as usize;
        out.push((id, bytes[at + 8..at + 8 + size].to_vec()));
        at += 8 + size + size % 2;
    }
    out
}

pub(crate) fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().expect("4"))
}

#[test]
fn standard_input_and_output_carry_the_same_audio_as_files() {
    // Both sides as the plugin (`--lookahead-ms`): a file's whole-file render hears the whole
    // file before it places anything (the breath voice and its colour), which standard input,
    // read once, cannot.
    let dir = tempfile::tempdir().expect("temp");
    assert_ok(&render(
        &example_voice_path(),
        &dir.path().join("file"),
        &["--no-plot", "--lookahead-ms", "500"],
    ));
    let want = samples(&dir.path().join("file/voice.wav"));
    let bytes = std::fs::read(example_voice_path()).expect("voice");
    let o = pneuma_with_stdin(
        &["render", "-", "-o", "-", "--quiet", "--lookahead-ms", "500"],
        &bytes,
    );
    assert_ok(&o);
    // A streamed WAV: sizes unknown (0xFFFFFFFF), read to the end.
    assert_eq!(&o.stdout[..4], b"RIFF");
    assert_eq!(u32_at(&o.stdout, 4), u32::MAX);
    let piped = dir.path().join("piped.wav");
    std::fs::write(&piped, &o.stdout).expect("write");
    assert!(
        samples(&piped) == want,
        "stdin→stdout audio differs from the file render"
    );
    // Standard input into a folder: the outputs are named `stdin.*`.
    let o = pneuma_with_stdin(
        &[
            "render",
            "-",
            "-o",
            dir.path().join("named").to_str().expect("utf8"),
            "--quiet",
            "--no-plot",
            "--lookahead-ms",
            "500",
        ],
        &bytes,
    );
    assert_ok(&o);
    assert!(samples(&dir.path().join("named/stdin.wav")) == want);
    assert_eq!(
        breaths_csv(&dir.path().join("named/stdin.breaths.csv")),
        breaths_csv(&dir.path().join("file/voice.breaths.csv"))
    );
    // Markers have nowhere to go with -o -.
    let o = pneuma_with_stdin(&["render", "-", "-o", "-", "--markers", "audacity"], &bytes);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("drop --markers"));
}

#[test]
fn a_flac_through_a_pipe_renders_like_the_file() {
    if !have_ffmpeg("a_flac_through_a_pipe_renders_like_the_file") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let flac = dir.path().join("voice.flac");
    ffmpeg_encode(&example_voice_path(), &flac, &[]);
    // Both as the plugin (see above).
    assert_ok(&render(
        &example_voice_path(),
        &dir.path().join("file"),
        &["--no-plot", "--lookahead-ms", "500"],
    ));
    let o = pneuma_with_stdin(
        &["render", "-", "-o", "-", "--quiet", "--lookahead-ms", "500"],
        &std::fs::read(&flac).expect("flac"),
    );
    assert_ok(&o);
    let piped = dir.path().join("piped.wav");
    std::fs::write(&piped, &o.stdout).expect("write");
    assert!(samples(&piped) == samples(&dir.path().join("file/voice.wav")));
}

/// `M:SS.mmm` in seconds.
fn minutes(s: &str) -> f64 {
    let (m, rest) = s.split_once(':').expect("M:SS.mmm");
    m.parse::<f64>().expect("minutes") * 60.0 + rest.parse::<f64>().expect("seconds")
}

#[test]
fn markers_are_parsed_back_as_the_breaths() {
    let dir = tempfile::tempdir().expect("temp");
    let out = dir.path().join("out");
    assert_ok(&render(
        &example_voice_path(),
        &out,
        &["--no-plot", "--markers", "audacity,reaper,cue"],
    ));
    let want = breaths_csv(&out.join("voice.breaths.csv"));
    assert!(want.len() >= 3, "the example voice gets breaths: {want:?}");

    // Audacity: start<TAB>end<TAB>label.
    let text = std::fs::read_to_string(out.join("voice.breaths.txt")).expect("labels");
    let labels: Vec<(f64, f64, String)> = text
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            assert_eq!(f.len(), 3, "{l}");
            (
                f[0].parse().expect("start"),
                f[1].parse().expect("end"),
                f[2].to_string(),
            )
        })
        .collect();
    assert_eq!(labels.len(), want.len());
    for (i, ((s, e, label), (ws, we))) in labels.iter().zip(&want).enumerate() {
        assert!(
            (s - ws).abs() < 1e-5 && (e - we).abs() < 1e-5,
            "{s} {e} vs {ws} {we}"
        );
        assert!(label.starts_with(&format!("breath {} (", i + 1)), "{label}");
    }

    // REAPER: #,Name,Start,End,Length with regions R1…
    let csv = std::fs::read_to_string(out.join("voice.breaths.reaper.csv")).expect("reaper");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("#,Name,Start,End,Length"));
    let regions: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(regions.len(), want.len());
    for (i, (r, (ws, we))) in regions.iter().zip(&want).enumerate() {
        assert_eq!(r[0], format!("R{}", i + 1));
        assert!((minutes(&r[2]) - ws).abs() < 6e-4, "{} vs {ws}", r[2]);
        assert!((minutes(&r[3]) - we).abs() < 6e-4, "{} vs {we}", r[3]);
        assert!((minutes(&r[4]) - (we - ws)).abs() < 1.1e-3, "{}", r[4]);
    }

    // Cue points inside the WAV, with labels and lengths in LIST/adtl.
    let bytes = std::fs::read(out.join("voice.wav")).expect("wav");
    let chunks = riff_chunks(&bytes);
    let ids: Vec<&[u8; 4]> = chunks.iter().map(|c| &c.0).collect();
    assert_eq!(ids, [b"fmt ", b"data", b"cue ", b"LIST"], "chunk order");
    let cue = &chunks[2].1;
    assert_eq!(u32_at(cue, 0) as usize, want.len());
    let adtl = &chunks[3].1;
    assert_eq!(&adtl[..4], b"adtl");
    let mut labl = std::collections::HashMap::new();
    let mut ltxt = std::collections::HashMap::new();
    let mut at = 4;
    while at + 8 <= adtl.len() {
        let size = u32_at(adtl, at + 4) as usize;
        let body = &adtl[at + 8..at + 8 + size];
        match &adtl[at..at + 4] {
            b"labl" => {
                let text = String::from_utf8(body[4..body.len() - 1].to_vec()).expect("utf8");
                labl.insert(u32_at(body, 0), text);
            }
            b"ltxt" => {
                ltxt.insert(u32_at(body, 0), u32_at(body, 4));
            }
            other => panic!("unexpected adtl chunk {other:?}"),
        }
        at += 8 + size + size % 2;
    }
    for (i, (ws, we)) in want.iter().enumerate() {
        let p = &cue[4 + 24 * i..4 + 24 * (i + 1)];
        let id = u32_at(p, 0);
        assert_eq!(&p[8..12], b"data");
        let frame = u32_at(p, 20) as f64;
        assert!(
            (frame / 16_000.0 - ws).abs() <= 1.0 / 16_000.0,
            "cue {id} at {frame}"
        );
        assert!(
            labl[&id].starts_with(&format!("breath {} (", i + 1)),
            "{}",
            labl[&id]
        );
        let len = ltxt[&id] as f64 / 16_000.0;
        assert!(
            (len - (we - ws)).abs() <= 2.0 / 16_000.0,
            "cue {id} length {len}"
        );
    }
    // The audio itself is the same as without markers.
    assert_ok(&render(
        &example_voice_path(),
        &dir.path().join("plain"),
        &["--no-plot"],
    ));
    assert!(samples(&out.join("voice.wav")) == samples(&dir.path().join("plain/voice.wav")));
    // Cue points need a WAV output.
    let o = render(
        &example_voice_path(),
        &dir.path().join("x"),
        &["--markers", "cue", "--format", "flac"],
    );
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("--markers cue writes cue points inside a WAV")
    );
}

#[test]
fn a_batch_finishes_the_good_files_and_reports_the_broken_one() {
    let dir = tempfile::tempdir().expect("temp");
    let inputs = dir.path().join("episodes");
    std::fs::create_dir(&inputs).expect("dir");
    for name in ["ep1.wav", "ep2.wav", "ep3.wav"] {
        std::fs::copy(example_voice_path(), inputs.join(name)).expect("copy");
    }
    std::fs::write(inputs.join("broken.mp3"), "not audio at all\n".repeat(10)).expect("write");
    std::fs::write(inputs.join("notes.txt"), "skipped: not audio").expect("write");
    let out = dir.path().join("out");
    let o = pneuma(&[
        "render",
        inputs.to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
        "--no-plot",
        "--jobs",
        "2",
    ]);
    assert!(!o.status.success(), "a failed file makes the batch fail");
    let err = String::from_utf8_lossy(&o.stderr);
    let table: Vec<&str> = err.lines().collect();
    assert!(
        table[0].starts_with("input") && table[0].contains("result"),
        "{err}"
    );
    let row = |name: &str| {
        table
            .iter()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("{name} not in: {err}"))
            .to_string()
    };
    assert!(row("broken.mp3").contains("FAILED") && row("broken.mp3").contains("it holds text"));
    assert!(row("notes.txt").contains("skipped") && row("notes.txt").contains("not audio"));
    for ep in ["ep1", "ep2", "ep3"] {
        assert!(row(&format!("{ep}.wav")).contains(" ok "), "{}", row(ep));
        assert!(out.join(format!("{ep}.wav")).exists());
        assert!(out.join(format!("{ep}.breaths.csv")).exists());
    }
    assert!(err.contains("3 rendered, 1 failed, 1 skipped"), "{err}");
    let left: Vec<String> = std::fs::read_dir(&out)
        .expect("out")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("broken") || n.contains("partial"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    // The same three alone succeed; two files with one stem are refused before anything runs.
    std::fs::remove_file(inputs.join("broken.mp3")).expect("rm");
    let o = pneuma(&[
        "render",
        inputs.to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
        "--no-plot",
        "-q",
    ]);
    assert_ok(&o);
    std::fs::copy(example_voice_path(), inputs.join("ep1.aiff")).expect("copy");
    let o = pneuma(&[
        "render",
        inputs.to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("would write the same output files"));
}

/// The Vorbis comments of a FLAC file.
pub(crate) fn flac_comments(path: &Path) -> Vec<String> {
    let b = std::fs::read(path).expect("flac");
    assert_eq!(&b[..4], b"fLaC");
    let mut at = 4;
    loop {
        let last = b[at] & 0x80 != 0;
        let kind = b[at] & 0x7f;
        let len = u32::from_be_bytes([0, b[at + 1], b[at + 2], b[at + 3]]) as usize;
        let body = &b[at + 4..at + 4 + len];
        if kind == 4 {
            let vendor = u32_at(body, 0) as usize;
            let mut p = 4 + vendor;
            let n = u32_at(body, p);
            p += 4;
            let mut out = Vec::new();
            for _ in 0..n {
                let l = u32_at(body, p) as usize;
                out.push(String::from_utf8(body[p + 4..p + 4 + l].to_vec()).expect("utf8"));
                p += 4 + l;
            }
            return out;
        }
        assert!(!last, "no Vorbis comment block");
        at += 4 + len;
    }
}

#[test]
fn lossy_input_becomes_flac_with_its_tags_and_lossless_keeps_its_format() {
    if !have_ffmpeg("lossy_input_becomes_flac_with_its_tags_and_lossless_keeps_its_format") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let mp3 = dir.path().join("episode.mp3");
    ffmpeg_encode(
        &example_voice_path(),
        &mp3,
        &[
            "-metadata",
            "title=Episode 12: Breathing",
            "-metadata",
            "artist=The Host",
            // ffmpeg writes a comment as an ID3 TXXX frame described "comment", not COMM.
            "-metadata",
            "comment=Recorded live",
            "-c:a",
            "libmp3lame",
        ],
    );
    let out = dir.path().join("out");
    let o = pneuma(&[
        "render",
        mp3.to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
        "--no-plot",
    ]);
    assert_ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("MP3 input written as FLAC (no second lossy generation"),
        "{err}"
    );
    let comments = flac_comments(&out.join("episode.flac"));
    assert!(
        comments.contains(&"TITLE=Episode 12: Breathing".to_string()),
        "{comments:?}"
    );
    assert!(
        comments.contains(&"ARTIST=The Host".to_string()),
        "{comments:?}"
    );
    assert!(
        comments.contains(&"COMMENT=Recorded live".to_string()),
        "ffmpeg's comment carried: {comments:?}"
    );
    // A FLAC tagged by ffmpeg holds its comment as DESCRIPTION: carried as the comment.
    let flac_in = dir.path().join("tagged.flac");
    ffmpeg_encode(
        &example_voice_path(),
        &flac_in,
        &["-metadata", "comment=Second take"],
    );
    let flac_out = dir.path().join("flac_out");
    assert_ok(&pneuma(&[
        "render",
        flac_in.to_str().expect("utf8"),
        "-o",
        flac_out.to_str().expect("utf8"),
        "--no-plot",
        "-q",
    ]));
    let comments = flac_comments(&flac_out.join("tagged.flac"));
    assert!(
        comments.contains(&"COMMENT=Second take".to_string()),
        "{comments:?}"
    );
    assert!(!out.join("episode.mp3").exists() && !out.join("episode.wav").exists());
    // --format wav: the tags as LIST/INFO.
    let o = pneuma(&[
        "render",
        mp3.to_str().expect("utf8"),
        "-o",
        out.to_str().expect("utf8"),
        "--no-plot",
        "--format",
        "wav",
        "-q",
    ]);
    assert_ok(&o);
    let chunks = riff_chunks(&std::fs::read(out.join("episode.wav")).expect("wav"));
    let info = &chunks.iter().find(|c| &c.0 == b"LIST").expect("LIST").1;
    let text = String::from_utf8_lossy(info);
    assert!(
        text.starts_with("INFO") && text.contains("INAM") && text.contains("Episode 12: Breathing"),
        "{text}"
    );
    assert!(text.contains("IART") && text.contains("The Host"), "{text}");
    // 24-bit stereo AIFF in, 24-bit stereo AIFF out, the same samples as the WAV route.
    let wav24 = dir.path().join("st.wav");
    ffmpeg_encode(
        &example_voice_path(),
        &wav24,
        &["-ac", "2", "-c:a", "pcm_s24le"],
    );
    let aiff = dir.path().join("st.aiff");
    ffmpeg_encode(&wav24, &aiff, &["-c:a", "pcm_s24be"]);
    assert_ok(&render(&wav24, &dir.path().join("w"), &["--no-plot"]));
    assert_ok(&render(&aiff, &dir.path().join("a"), &["--no-plot"]));
    let a = dir.path().join("a/st.aiff");
    let mut src = pneuma_io::AudioSource::open(&a).expect("aiff out");
    assert_eq!(src.format(), pneuma_io::InputFormat::Aiff);
    assert_eq!((src.info().bits, src.info().channels), (24, 2));
    let mut block = Vec::new();
    assert!(src.read_interleaved(16, &mut block).expect("read") > 0);
    assert!(
        samples(&a) == samples(&dir.path().join("w/st.wav")),
        "AIFF route differs"
    );
}

/// Five minutes of the example voice at 48 kHz in `path`: long enough to be interrupted
/// mid-render.
fn write_five_minutes(path: &Path) {
    write_long(path, 48_000, 1, false, 300.0);
}

/// `seconds` of the example voice at `rate` Hz in `channels` channels, float or 16-bit.
fn write_long(path: &Path, rate: u32, channels: u16, float: bool, seconds: f64) {
    let one = pneuma_testkit::voice::example_voice_at(rate);
    let mut mono = Vec::new();
    while mono.len() < (seconds * f64::from(rate)) as usize {
        mono.extend_from_slice(&one);
    }
    let bits = if float { 32 } else { 16 };
    support::write_wav(path, (rate, channels, bits, float), &mono, 0.9);
}

#[test]
fn an_interrupted_batch_says_which_files_it_stopped_and_which_it_never_started() {
    let dir = tempfile::tempdir().expect("temp");
    let first = dir.path().join("a.wav");
    write_five_minutes(&first);
    for name in ["b.wav", "c.wav"] {
        std::fs::copy(&first, dir.path().join(name)).expect("copy");
    }
    let out = dir.path().join("out");
    let child = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .args(["render", "-j", "1", "--no-progress", "-o"])
        .arg(&out)
        .args(["a.wav", "b.wav", "c.wav"].map(|n| dir.path().join(n)))
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start");
    let start = std::time::Instant::now();
    while std::fs::read_dir(&out).map_or(0, |d| d.count()) < 1 {
        assert!(
            start.elapsed().as_secs() < 60,
            "the batch never started writing"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let o = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(!err.contains("FAILED"), "no file failed: {err}");
    let row = |name: &str| {
        err.lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("no row for {name}: {err}"))
            .to_string()
    };
    assert!(row("a.wav").contains("interrupted"), "{err}");
    for name in ["b.wav", "c.wav"] {
        assert!(row(name).contains("not started"), "{err}");
    }
    assert!(
        err.contains("0 rendered, 0 failed, 3 interrupted or not started"),
        "{err}"
    );
    // Nothing half-written (the folder the batch made is gone, or empty).
    let left: Vec<_> = std::fs::read_dir(&out).map_or(Vec::new(), |d| d.collect());
    assert!(left.is_empty(), "{left:?}");
}

/// Renders five minutes at 48 kHz into a folder holding an old render, sends `signals` (back to
/// back) once the render is writing, and returns the exit code, standard error, the folder's
/// file names afterwards (after checking that the old file is unchanged) and the time between
/// the first signal and the last.
fn interrupt_a_render(signals: &[&str]) -> Interrupted {
    let dir = tempfile::tempdir().expect("temp");
    let long = dir.path().join("long.wav");
    // Big blocks (96 kHz stereo float), so that stopping takes a few milliseconds.
    write_long(&long, 96_000, 2, true, 120.0);
    let out = dir.path().join("out");
    std::fs::create_dir(&out).expect("dir");
    std::fs::write(out.join("long.wav"), "old render").expect("write");
    let child = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .args([
            "render",
            long.to_str().expect("utf8"),
            "-o",
            out.to_str().expect("utf8"),
            "-q",
            "--bvh",
            "--midi",
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start");
    // Wait until the render is writing (its temporary files exist) and well under way, then
    // signal.
    let start = std::time::Instant::now();
    while std::fs::read_dir(&out).expect("out").count() < 2 {
        assert!(
            start.elapsed().as_secs() < 60,
            "the render never started writing"
        );
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    std::thread::sleep(std::time::Duration::from_millis(300));
    // Back to back, as `timeout` sends them (to the process, then its group): one `kill` each,
    // a few milliseconds apart, so the first is delivered before the second is sent (two
    // pending signals would merge) and the second comes while the render is still stopping
    // (about 10 ms). The time between them is returned: a loaded machine may stretch it.
    let mut sent = Vec::new();
    for signal in signals {
        sent.push(std::time::Instant::now());
        let kill = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .expect("kill");
        assert!(kill.success());
    }
    let apart = sent
        .last()
        .zip(sent.first())
        .map_or(std::time::Duration::ZERO, |(l, f)| l.duration_since(*f));
    let o = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    let mut names: Vec<String> = std::fs::read_dir(&out)
        .expect("out")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    if names == ["long.wav"] {
        assert_eq!(
            std::fs::read_to_string(out.join("long.wav")).expect("old"),
            "old render"
        );
    }
    Interrupted {
        code: o.status.code(),
        err,
        names,
        apart,
    }
}

/// What [`interrupt_a_render`] saw.
struct Interrupted {
    code: Option<i32>,
    err: String,
    names: Vec<String>,
    /// Between the first signal and the last.
    apart: std::time::Duration,
}

#[test]
fn ctrl_c_leaves_no_partial_file_and_the_old_outputs() {
    let r = interrupt_a_render(&["INT"]);
    assert_eq!(r.code, Some(130), "{}", r.err);
    assert!(r.err.contains("interrupted"), "{}", r.err);
    assert_eq!(r.names, ["long.wav"], "only the old file stays");
}

#[test]
fn a_signal_delivered_twice_at_once_is_one_interruption() {
    // `timeout` signals the process and then its process group: two signals at once. Before,
    // the second one exited on the spot, without a word and leaving the temporary files.
    for signal in ["INT", "TERM"] {
        // Two signals sent further apart than the handler's half second are two
        // interruptions (a loaded machine can stretch two `kill`s that far): try again.
        let r = (0..3)
            .map(|_| interrupt_a_render(&[signal, signal]))
            .find(|r| r.apart < std::time::Duration::from_millis(400))
            .expect("two signals within 0.4 s in one of three tries");
        assert_eq!(r.code, Some(130), "{signal}: {}", r.err);
        assert!(r.err.contains("nothing was written"), "{signal}: {}", r.err);
        assert_eq!(r.names, ["long.wav"], "{signal}: only the old file stays");
    }
}

#[test]
fn a_run_stopped_at_once_removes_its_temporary_files_and_only_those() {
    // What a second Ctrl-C does (`output::exit_removing_temporaries`), run in a process of its
    // own (this test binary again, this test alone), since it removes every temporary file of
    // the process and exits. Before, the exit left them all behind.
    const CHILD: &str = "PNEUMA_TEST_TEMPORARIES_DIR";
    if let Some(dir) = std::env::var_os(CHILD) {
        use pneuma_cli::output::{created_folders, exit_removing_temporaries, Output};
        let dir = Path::new(&dir);
        let mut done = Output::create(&dir.join("done.csv")).expect("create");
        done.writer().write_all(b"kept").expect("write");
        done.commit().expect("commit");
        // A folder the run made, holding only an output being written.
        let made = dir.join("made");
        std::fs::create_dir(&made).expect("dir");
        created_folders(std::slice::from_ref(&made));
        let mut open = Output::create(&made.join("open.wav")).expect("create");
        open.writer().write_all(b"half").expect("write");
        open.writer().flush().expect("flush");
        let staged = Output::create(&dir.join("staged.bvh"))
            .expect("create")
            .finish()
            .expect("finish");
        std::mem::forget((open, staged));
        exit_removing_temporaries(7, |removed| eprintln!("removed: {removed}"));
    }
    let dir = tempfile::tempdir().expect("temp");
    let o = Command::new(std::env::current_exe().expect("test binary"))
        .args([
            "--exact",
            "podcast::a_run_stopped_at_once_removes_its_temporary_files_and_only_those",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .env(CHILD, dir.path())
        .output()
        .expect("run");
    let said =
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(7), "the child exited at once: {said}");
    assert!(said.contains("removed: true"), "{said}");
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        ["done.csv"],
        "the made folder and every temporary file are gone"
    );
    assert_eq!(
        std::fs::read(dir.path().join("done.csv")).expect("kept"),
        b"kept"
    );
}

#[test]
fn a_breath_sample_folder_may_hold_flac() {
    if !have_ffmpeg("a_breath_sample_folder_may_hold_flac") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let (wavs, flacs) = (dir.path().join("wavs"), dir.path().join("flacs"));
    std::fs::create_dir(&wavs).expect("dir");
    std::fs::create_dir(&flacs).expect("dir");
    // Half a second of shaped noise as a breath.
    let mut state = 7u32;
    let noise: Vec<f32> = (0..22_050)
        .map(|i| {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let env = (std::f32::consts::PI * i as f32 / 22_050.0).sin();
            ((state >> 8) as f32 / (1u32 << 24) as f32 - 0.5) * 0.2 * env
        })
        .collect();
    support::write_wav(&wavs.join("mouth.wav"), (44_100, 1, 16, false), &noise, 1.0);
    ffmpeg_encode(&wavs.join("mouth.wav"), &flacs.join("mouth.flac"), &[]);
    for (samples_dir, out) in [(&wavs, "a"), (&flacs, "b")] {
        assert_ok(&render(
            &example_voice_path(),
            &dir.path().join(out),
            &[
                "--no-plot",
                "--breath-samples",
                samples_dir.to_str().expect("utf8"),
            ],
        ));
    }
    let kinds = std::fs::read_to_string(dir.path().join("b/voice.breaths.csv")).expect("csv");
    assert!(kinds.contains(",sample,"), "{kinds}");
    assert!(
        samples(&dir.path().join("a/voice.wav")) == samples(&dir.path().join("b/voice.wav")),
        "mouth.flac renders as mouth.wav"
    );
}

#[test]
fn a_render_that_found_no_speech_counts_no_real_breaths() {
    // Generated vowels with a breath-like noise in each pause: the speech decision takes the
    // vowels for no speech, so the noises between them are no speaker's breaths (the summary
    // said "4 real breaths heard", then "no speech found"). Heard as any sound, they are.
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("vowels.wav");
    let x = pneuma_testkit::signals::phrases_with_breaths(16_000.0, 12.0, 3);
    support::write_wav(&input, (16_000, 1, 16, false), &x, 1.0);
    let said = |out: &str, extra: &[&str]| {
        let o = support::render_saying(&input, &dir.path().join(out), extra);
        assert_ok(&o);
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    let any = said("any", &["--any-sound"]);
    assert!(any.contains("real breaths heard in the pauses"), "{any}");
    let judged = said("judged", &[]);
    assert!(judged.contains("warning: no speech found"), "{judged}");
    assert!(!judged.contains("real breaths heard"), "{judged}");
}

#[test]
fn a_render_says_what_it_found_and_renders_one_channel_on_request() {
    let dir = tempfile::tempdir().expect("temp");
    let (voice, rate, channels) = support::read_audio(&example_voice_path());
    assert_eq!(channels, 1);
    // The voice on the left, inverted on the right: they cancel when mixed to mono.
    let anti = dir.path().join("anti.wav");
    support::write_wav(&anti, (rate, 2, 16, false), &voice, -1.0);
    let silence = dir.path().join("silence.wav");
    support::write_wav(&silence, (16_000, 1, 16, false), &vec![0.0; 48_000], 1.0);
    let noise = dir.path().join("noise.wav");
    let hiss = pneuma_testkit::signals::white_noise(48_000, 0.05, 7);
    support::write_wav(&noise, (16_000, 1, 16, false), &hiss, 1.0);
    let run = |input: &Path, out: &str, extra: &[&str]| {
        let out = dir.path().join(out);
        let o = support::render_saying(input, &out, extra);
        assert_ok(&o);
        (String::from_utf8_lossy(&o.stderr).into_owned(), out)
    };
    let (said, out) = run(&anti, "anti", &[]);
    assert!(
        said.contains("warning: left and right are in antiphase: render one channel"),
        "{said}"
    );
    assert!(breaths_csv(&out.join("anti.breaths.csv")).is_empty());
    let (said, out) = run(&anti, "left", &["--channel", "left"]);
    assert!(!said.contains("warning:"), "{said}");
    let (_, _, rendered_channels) = support::read_audio(&out.join("anti.wav"));
    assert_eq!(rendered_channels, 1);
    assert!(!breaths_csv(&out.join("anti.breaths.csv")).is_empty());
    let (said, _) = run(&noise, "noise", &[]);
    assert!(said.contains("warning: no speech found"), "{said}");
    // Digital silence holds nothing to find speech in.
    let (said, _) = run(&silence, "silence", &[]);
    assert!(
        said.contains("warning: the input holds no signal"),
        "{said}"
    );
    let (said, _) = run(&example_voice_path(), "voice", &[]);
    assert!(!said.contains("warning:"), "{said}");
    // The batch table has a column for it.
    let (said, _) = run(&anti, "batch", &[noise.to_str().expect("utf-8")]);
    let header = said.lines().find(|l| l.starts_with("input")).unwrap_or("");
    assert!(header.contains("warnings"), "{said}");
    assert!(
        said.contains("antiphase") && said.contains("no speech"),
        "{said}"
    );
    // A mono file has no right channel.
    let o = pneuma(&[
        "render",
        silence.to_str().expect("utf-8"),
        "-o",
        dir.path().join("right").to_str().expect("utf-8"),
        "--channel",
        "right",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--channel"));
}

#[test]
fn one_track_of_a_recording_with_more_channels_than_the_engine_takes_renders_alone() {
    let dir = tempfile::tempdir().expect("temp");
    let (voice, rate, _) = support::read_audio(&example_voice_path());
    // Ten tracks (a field recorder's polyWAV): the voice on every one, the first at full level.
    let tracks = dir.path().join("tracks.wav");
    support::write_wav(&tracks, (rate, 10, 16, false), &voice, 0.5);
    let out = dir.path().join("all");
    let o = support::render_saying(&tracks, &out, &[]);
    assert!(!o.status.success());
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(said.contains("--channel N, N from 1 to 10"), "{said}");
    let o = support::render_saying(&tracks, &dir.path().join("seven"), &["--channel", "7"]);
    assert_ok(&o);
    let (rendered, _, channels) = support::read_audio(&dir.path().join("seven/tracks.wav"));
    assert_eq!(channels, 1);
    assert_eq!(rendered.len(), voice.len());
    assert!(!breaths_csv(&dir.path().join("seven/tracks.breaths.csv")).is_empty());
    // Outside the breaths the output is track 7 (the voice at half level), not the first.
    let peak = |x: &[f32]| x.iter().fold(0.0f32, |m, v| m.max(v.abs()));
    assert!((peak(&rendered) / peak(&voice) - 0.5).abs() < 0.02);
    let o = support::render_saying(&tracks, &dir.path().join("eleven"), &["--channel", "11"]);
    assert!(!o.status.success());
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(said.contains("pick one of 1 to 10"), "{said}");
    let o = support::render_saying(&tracks, &dir.path().join("zero"), &["--channel", "0"]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a channel"));
}
