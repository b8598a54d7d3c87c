//! Every input format end to end: the example voice encoded by ffmpeg (FLAC, AIFF, CAF, ALAC and
//! AAC in M4A, MP3, Ogg Vorbis) renders like the WAV itself — bit for bit for lossless input,
//! the same breaths for lossy input — and damaged or mislabelled files fail with clear errors.
//!
//! ffmpeg is installed by `.ci/run`; without it these tests skip visibly, and under CI=true they
//! fail.

use std::path::{Path, PathBuf};
use std::process::Command;

mod support;
use support::{pneuma, render, tool_or_skip};

/// True when ffmpeg runs; otherwise skips visibly (fails under CI=true).
fn ffmpeg_or_skip(test: &str) -> bool {
    tool_or_skip("ffmpeg", "-version", test)
}

fn voice() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/examples/voice.wav")
}

/// Encodes `input` to `out` with ffmpeg and the codec arguments `codec`.
fn encode(input: &Path, out: &Path, codec: &[&str]) {
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

/// Reads an audio file (any format) as interleaved f32 with its rate and channels.
fn read_audio(path: &Path) -> (Vec<f32>, u32, u16) {
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

/// Breath start times of a `breaths.csv`.
fn breath_starts(path: &Path) -> Vec<f64> {
    std::fs::read_to_string(path)
        .expect("breaths csv")
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().expect("start").parse().expect("number"))
        .collect()
}

/// Renders `input` into `out` and returns the rendered audio file's path.
fn render_ok(input: &Path, out: &Path, extra: &[&str]) -> PathBuf {
    let o = render(input, out, &[&["--no-plot"], extra].concat());
    assert!(
        o.status.success(),
        "render {}: {}",
        input.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    let stem = input.file_stem().expect("stem").to_string_lossy();
    let found: Vec<PathBuf> = std::fs::read_dir(out)
        .expect("out dir")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_stem().is_some_and(|s| s.to_string_lossy() == stem)
                && !p.to_string_lossy().ends_with(".csv")
        })
        .collect();
    assert_eq!(
        found.len(),
        1,
        "one audio output in {}: {found:?}",
        out.display()
    );
    found[0].clone()
}

#[test]
fn every_lossless_format_renders_bit_for_bit_as_the_wav() {
    if !ffmpeg_or_skip("every_lossless_format_renders_bit_for_bit_as_the_wav") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let reference = render_ok(&voice(), &dir.path().join("wav"), &[]);
    let (want, rate, channels) = read_audio(&reference);
    let want_breaths = breath_starts(&dir.path().join("wav/voice.breaths.csv"));
    assert!(!want_breaths.is_empty(), "the example voice gets breaths");
    for (ext, codec) in [
        ("flac", &["-c:a", "flac"][..]),
        ("aiff", &["-c:a", "pcm_s16be"][..]),
        ("caf", &["-c:a", "pcm_s16le"][..]),
        ("m4a", &["-c:a", "alac"][..]),
    ] {
        let sub = dir.path().join(ext);
        std::fs::create_dir_all(&sub).expect("dir");
        let input = sub.join(format!("voice.{ext}"));
        encode(&voice(), &input, codec);
        let out = render_ok(&input, &sub.join("out"), &[]);
        let (got, got_rate, got_channels) = read_audio(&out);
        assert_eq!((got_rate, got_channels), (rate, channels), "{ext}");
        assert_eq!(got.len(), want.len(), "{ext}: length");
        let differing = got
            .iter()
            .zip(&want)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(differing, 0, "{ext}: samples differ from the WAV render");
        assert_eq!(
            breath_starts(&sub.join("out/voice.breaths.csv")),
            want_breaths,
            "{ext}: breaths"
        );
    }
}

#[test]
fn lossy_formats_render_with_the_same_breaths() {
    if !ffmpeg_or_skip("lossy_formats_render_with_the_same_breaths") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    render_ok(&voice(), &dir.path().join("wav"), &[]);
    let want_breaths = breath_starts(&dir.path().join("wav/voice.breaths.csv"));
    let (voice_audio, _, _) = read_audio(&voice());
    for (ext, codec) in [
        ("mp3", &["-c:a", "libmp3lame", "-b:a", "64k"][..]),
        ("ogg", &["-c:a", "libvorbis", "-q:a", "4"][..]),
        ("m4a", &["-c:a", "aac", "-b:a", "64k"][..]),
    ] {
        let sub = dir.path().join(ext);
        std::fs::create_dir_all(&sub).expect("dir");
        let input = sub.join(format!("voice.{ext}"));
        encode(&voice(), &input, codec);
        let out = render_ok(&input, &sub.join("out"), &[]);
        let (got, rate, _) = read_audio(&out);
        assert_eq!(rate, 16_000, "{ext}");
        // MP3 (LAME header) and Vorbis are trimmed to the original length; AAC in MP4 keeps its
        // encoder delay and padding (1024 + under 1024 samples: symphonia reads no edit list).
        let diff = (got.len() as i64 - voice_audio.len() as i64).abs();
        let slack = if ext == "m4a" { 2048 } else { 0 };
        assert!(
            diff <= slack,
            "{ext}: {} vs {} samples",
            got.len(),
            voice_audio.len()
        );
        let breaths = breath_starts(&sub.join("out/voice.breaths.csv"));
        assert_eq!(breaths.len(), want_breaths.len(), "{ext}: {breaths:?}");
        for (a, b) in breaths.iter().zip(&want_breaths) {
            assert!((a - b).abs() < 0.15, "{ext}: breath at {a} s, WAV at {b} s");
        }
    }
}

#[test]
fn damaged_and_mislabelled_files_fail_clearly() {
    if !ffmpeg_or_skip("damaged_and_mislabelled_files_fail_clearly") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let fails = |input: &Path, must: &[&str]| {
        let out = dir.path().join("out");
        let o = render(input, &out, &["--no-plot"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{}: rendered", input.display());
        for m in must {
            assert!(err.contains(m), "{}: `{m}` not in: {err}", input.display());
        }
        assert!(
            !out.exists() || std::fs::read_dir(&out).expect("dir").next().is_none(),
            "{}: output left behind",
            input.display()
        );
    };
    // A truncated MP3: the LAME header announces more than is there.
    let mp3 = dir.path().join("voice.mp3");
    encode(&voice(), &mp3, &["-c:a", "libmp3lame", "-b:a", "64k"]);
    let bytes = std::fs::read(&mp3).expect("mp3");
    let cut = dir.path().join("cut.mp3");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
    fails(
        &cut,
        &["cut.mp3 is damaged after", "announces", "ffmpeg -i IN"],
    );
    // A FLAC with a flipped byte in its audio: a frame fails its CRC.
    let flac = dir.path().join("voice.flac");
    encode(&voice(), &flac, &["-c:a", "flac"]);
    let mut bytes = std::fs::read(&flac).expect("flac");
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x5a;
    let bad = dir.path().join("bad.flac");
    std::fs::write(&bad, &bytes).expect("write");
    fails(&bad, &["bad.flac is damaged after", "re-export it"]);
    // A text file named .mp3.
    let text = dir.path().join("notes.mp3");
    std::fs::write(&text, "these are my show notes, not audio\n".repeat(20)).expect("write");
    fails(
        &text,
        &[
            "notes.mp3 is not an audio file Pneuma can read",
            "ffmpeg -i IN OUT.flac",
        ],
    );
    // Opus: no decoder, and the command that converts it.
    let opus = dir.path().join("voice.opus");
    encode(&voice(), &opus, &["-c:a", "libopus"]);
    fails(
        &opus,
        &["Opus", "is not supported", "ffmpeg -i IN OUT.flac"],
    );
}

#[test]
fn analyze_reads_flac_like_the_wav() {
    if !ffmpeg_or_skip("analyze_reads_flac_like_the_wav") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let flac = dir.path().join("voice.flac");
    encode(&voice(), &flac, &["-c:a", "flac"]);
    let run = |input: &Path, out: &Path| {
        let o = pneuma(&[
            "analyze",
            input.to_str().expect("utf8"),
            "-o",
            out.to_str().expect("utf8"),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out).expect("csv")
    };
    let a = run(&voice(), &dir.path().join("wav.csv"));
    let b = run(&flac, &dir.path().join("flac.csv"));
    assert!(a.lines().count() > 100);
    assert!(a == b, "the FLAC's analysis CSV differs from the WAV's");
}
