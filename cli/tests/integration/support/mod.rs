//! Shared by the CLI end-to-end tests: running the `pneuma` binary, encoding inputs with
//! ffmpeg, writing test WAV files and reading outputs back.

pub mod episode;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use pneuma_testkit::signals::{self as test_signals, GlottalVowel, Vowel};

/// True when `program` runs (`program version_arg` succeeds). Without it a test skips visibly,
/// except under `CI=true` (`.ci/run` installs it), where it fails. The Debian package has the
/// program's name (`espeak-ng`, `ffmpeg`).
pub fn tool_or_skip(program: &str, version_arg: &str, test: &str) -> bool {
    if Command::new(program)
        .arg(version_arg)
        .output()
        .is_ok_and(|o| o.status.success())
    {
        return true;
    }
    assert!(
        !pneuma_testkit::python::ci(),
        "{test}: {program} is not installed but CI=true: install it (apt-get install {program})"
    );
    eprintln!("SKIPPED {test}: {program} is not installed (apt-get install {program})");
    false
}

/// Runs the built `pneuma` binary with `args`.
pub fn pneuma(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .args(args)
        .output()
        .expect("the pneuma binary runs")
}

/// Runs the built `pneuma` binary with `args`, writing `stdin` to its standard input.
pub fn pneuma_with_stdin(args: &[&str], stdin: &[u8]) -> Output {
    use std::io::Write as _;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_pneuma"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the pneuma binary starts");
    let mut pipe = child.stdin.take().expect("stdin");
    let bytes = stdin.to_vec();
    // A writer thread, so a reader that stops early cannot dead-lock the test.
    let writer = std::thread::spawn(move || {
        let _ = pipe.write_all(&bytes);
    });
    let out = child.wait_with_output().expect("the pneuma binary runs");
    writer.join().expect("writer");
    out
}

/// Runs `pneuma render INPUT -o OUT --quiet` with `extra` arguments.
pub fn render(input: &Path, out: &Path, extra: &[&str]) -> Output {
    render_with(input, out, &["--quiet"], extra)
}

/// Runs `pneuma render INPUT -o OUT --no-plot --no-progress` with `extra` arguments: the
/// summary and its warnings on standard error.
pub fn render_saying(input: &Path, out: &Path, extra: &[&str]) -> Output {
    render_with(input, out, &["--no-plot", "--no-progress"], extra)
}

/// Runs `pneuma render INPUT -o OUT` with the `options` and then the `extra` arguments.
fn render_with(input: &Path, out: &Path, options: &[&str], extra: &[&str]) -> Output {
    let (input, out) = (input.to_str().expect("utf-8"), out.to_str().expect("utf-8"));
    let args: Vec<&str> = (["render", input, "-o", out].into_iter())
        .chain(options.iter().chain(extra).copied())
        .collect();
    pneuma(&args)
}

/// Writes `mono` to every channel of a WAV file in the given format, channels after the first
/// scaled by `other_channel_gain` (so a mix differs from a copy).
pub fn write_wav(
    path: &Path,
    format: (u32, u16, u16, bool),
    mono: &[f32],
    other_channel_gain: f32,
) {
    let (rate, channels, bits, float) = format;
    let spec = hound::WavSpec {
        channels,
        sample_rate: rate,
        bits_per_sample: bits,
        sample_format: if float {
            hound::SampleFormat::Float
        } else {
            hound::SampleFormat::Int
        },
    };
    let mut w = hound::WavWriter::create(path, spec).expect("create wav");
    for &v in mono {
        for ch in 0..channels {
            let v = if ch == 0 { v } else { v * other_channel_gain };
            if float {
                w.write_sample(v).expect("write");
            } else {
                let max = ((1i64 << (bits - 1)) - 1) as f32;
                w.write_sample((v * max).round() as i32).expect("write");
            }
        }
    }
    w.finalize().expect("finalize");
}

/// The files in `dir` other than `keep`.
pub fn files_besides(dir: &Path, keep: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry").path())
        .filter(|p| p != keep)
        .collect()
}

/// `pneuma analyze INPUT -o existing.csv` fails with every one of `must_mention` in its
/// message, leaves the existing output as it was and no temporary file beside it.
pub fn assert_analyze_fails(input: &Path, must_mention: &[&str]) {
    let dir = tempfile::tempdir().expect("temp dir");
    let csv = dir.path().join("existing.csv");
    std::fs::write(&csv, "precious\n").expect("write");
    let out = pneuma(&[
        "analyze",
        input.to_str().expect("utf-8"),
        "-o",
        csv.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "{} should fail; stderr {err}",
        input.display()
    );
    assert!(err.starts_with("error: "), "{err}");
    for m in must_mention {
        assert!(err.contains(m), "{}: `{m}` not in: {err}", input.display());
    }
    assert_eq!(std::fs::read_to_string(&csv).expect("kept"), "precious\n");
    let leftovers = files_besides(dir.path(), &csv);
    assert!(leftovers.is_empty(), "partial files left: {leftovers:?}");
}

/// Asserts that a run succeeded, showing its standard error when not.
pub fn assert_ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// True when ffmpeg runs; otherwise skips visibly (fails under CI=true).
pub fn have_ffmpeg(test: &str) -> bool {
    tool_or_skip("ffmpeg", "-version", test)
}

/// Encodes `input` to `out` with ffmpeg and the codec (or metadata, channel…) arguments `codec`.
pub fn ffmpeg_encode(input: &Path, out: &Path, codec: &[&str]) {
    let o = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-y", "-i"])
        .arg(input)
        .args(codec)
        .arg(out)
        .output()
        .expect("ffmpeg runs");
    assert!(
        o.status.success(),
        "ffmpeg {codec:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Reads an audio file (any format pneuma reads) as interleaved f32 with its rate and channels.
pub fn read_audio(path: &Path) -> (Vec<f32>, u32, u16) {
    let mut src =
        pneuma_io::AudioSource::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let info = src.info();
    let mut all = Vec::new();
    let mut block = Vec::new();
    while src.read_interleaved(4096, &mut block).expect("read") > 0 {
        all.extend_from_slice(&block);
    }
    (all, info.sample_rate_hz, info.channels)
}

/// Interleaved samples of any audio file pneuma reads.
pub fn samples(path: &Path) -> Vec<f32> {
    read_audio(path).0
}

/// `(start_s, end_s)` of every row of a `breaths.csv`.
pub fn breaths_csv(path: &Path) -> Vec<(f64, f64)> {
    std::fs::read_to_string(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<f64> = l
                .split(',')
                .take(2)
                .map(|x| x.parse().expect("a number"))
                .collect();
            (f[0], f[1])
        })
        .collect()
}

/// A BVH file's `Frames:` count and `Frame Time:` in seconds.
pub fn bvh_timing(path: &Path) -> (u64, f64) {
    let text = std::fs::read_to_string(path).expect("the BVH is written");
    let value = |key: &str| {
        let line = text.lines().find(|l| l.starts_with(key)).expect(key);
        line[key.len()..].trim().to_owned()
    };
    (
        value("Frames:").parse().expect("frames"),
        value("Frame Time:").parse().expect("frame time"),
    )
}

/// A Python with the independent readers the tests use (`mido` for MIDI files, `bvh` for BVH):
/// `PNEUMA_PYTHON_TOOLS`, else the venv `.ci/run` makes (`target/cli-venv`). `None` skips the
/// test visibly, except under CI=true, where it fails.
pub fn python_tools(test: &str) -> Option<PathBuf> {
    pneuma_testkit::python::FILE_READERS.python(test, pneuma_testkit::python::ci())
}

/// Runs `cli/tests/tools/<script>` with `python` and `args`; its standard output.
pub fn python_tool(python: &Path, script: &str, args: &[&Path]) -> String {
    let o = Command::new(python)
        .arg(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("tests/tools")
                .join(script),
        )
        .args(args)
        .output()
        .expect("python runs");
    assert!(
        o.status.success(),
        "{script}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The lines of `read_midi.py`: the header line and `(time_s, channel, controller, value)`.
pub fn read_midi(python: &Path, file: &Path) -> (String, Vec<(f64, u8, u8, u8)>) {
    let text = python_tool(python, "read_midi.py", &[file]);
    let mut lines = text.lines();
    let head = lines.next().expect("header line").to_owned();
    let ccs = lines
        .map(|l| {
            let f: Vec<f64> = l.split(' ').map(|x| x.parse().expect("number")).collect();
            (f[0], f[1] as u8, f[2] as u8, f[3] as u8)
        })
        .collect();
    (head, ccs)
}

/// Two glottal-vowel phrases with one pause between them, 16 kHz mono.
pub fn two_phrases() -> Vec<f32> {
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
