//! Every input format end to end: the example voice encoded by ffmpeg (FLAC, AIFF, CAF, ALAC and
//! AAC in M4A, MP3, Ogg Vorbis, IMA and Microsoft ADPCM WAV) renders like the WAV itself — bit
//! for bit for lossless input, the same breaths for lossy input — and damaged or mislabelled
//! files fail with clear errors.
//!
//! ffmpeg is installed by `.ci/run`; without it these tests skip visibly, and under CI=true they
//! fail.

use std::path::{Path, PathBuf};

use crate::support;
use pneuma_testkit::voice::example_voice_path;
use support::{breaths_csv, ffmpeg_encode, have_ffmpeg, pneuma, read_audio, render};

/// Breath start times of a `breaths.csv`.
fn breath_starts(path: &Path) -> Vec<f64> {
    breaths_csv(path)
        .into_iter()
        .map(|(start_s, _)| start_s)
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
    if !have_ffmpeg("every_lossless_format_renders_bit_for_bit_as_the_wav") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let reference = render_ok(&example_voice_path(), &dir.path().join("wav"), &[]);
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
        ffmpeg_encode(&example_voice_path(), &input, codec);
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
    /// The lag of `b` against `a` (samples, ±2048) that best lines up 0.5 s of speech at 1 s.
    fn lag(a: &[f32], b: &[f32]) -> i64 {
        let (from, n) = (16_000usize, 8_000usize);
        (-2048i64..=2048)
            .max_by(|&x, &y| {
                let dot = |l: i64| -> f64 {
                    (0..n)
                        .map(|i| {
                            let j = (from + i) as i64 + l;
                            f64::from(a[from + i]) * f64::from(b[j as usize])
                        })
                        .sum()
                };
                dot(x).total_cmp(&dot(y))
            })
            .unwrap_or(0)
    }
    if !have_ffmpeg("lossy_formats_render_with_the_same_breaths") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    render_ok(&example_voice_path(), &dir.path().join("wav"), &[]);
    let want_breaths = breath_starts(&dir.path().join("wav/voice.breaths.csv"));
    let (voice_audio, _, _) = read_audio(&example_voice_path());
    for (name, ext, codec) in [
        ("mp3", "mp3", &["-c:a", "libmp3lame", "-b:a", "64k"][..]),
        ("ogg", "ogg", &["-c:a", "libvorbis", "-q:a", "4"][..]),
        ("m4a", "m4a", &["-c:a", "aac", "-b:a", "64k"][..]),
        ("ima", "wav", &["-c:a", "adpcm_ima_wav"][..]),
        ("msadpcm", "wav", &["-c:a", "adpcm_ms"][..]),
    ] {
        let sub = dir.path().join(name);
        std::fs::create_dir_all(&sub).expect("dir");
        let input = sub.join(format!("voice.{ext}"));
        ffmpeg_encode(&example_voice_path(), &input, codec);
        let out = render_ok(&input, &sub.join("out"), &[]);
        let (got, rate, _) = read_audio(&out);
        assert_eq!(rate, 16_000, "{name}");
        // MP3 (LAME header) and Vorbis are trimmed to the original length, AAC in MP4 by its
        // edit list (its length in milliseconds: within a few samples). ADPCM WAV fills its
        // last block (ffmpeg: 2041 samples a block here) and counts the padding in its `fact`
        // chunk: the file is that much longer.
        let diff = (got.len() as i64 - voice_audio.len() as i64).abs();
        let slack = match name {
            "ima" | "msadpcm" => 2048,
            "m4a" => 16,
            _ => 0,
        };
        // Nothing starts late: the encoder's priming is gone (AAC's 1024 samples without the
        // edit list), so controls and breaths stay on the video's time.
        assert_eq!(lag(&voice_audio, &got), 0, "{name}");
        assert!(
            diff <= slack,
            "{name}: {} vs {} samples",
            got.len(),
            voice_audio.len()
        );
        let breaths = breath_starts(&sub.join("out/voice.breaths.csv"));
        assert_eq!(breaths.len(), want_breaths.len(), "{name}: {breaths:?}");
        for (a, b) in breaths.iter().zip(&want_breaths) {
            assert!(
                (a - b).abs() < 0.15,
                "{name}: breath at {a} s, WAV at {b} s"
            );
        }
    }
}

#[test]
fn damaged_and_mislabelled_files_fail_clearly() {
    if !have_ffmpeg("damaged_and_mislabelled_files_fail_clearly") {
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
    ffmpeg_encode(
        &example_voice_path(),
        &mp3,
        &["-c:a", "libmp3lame", "-b:a", "64k"],
    );
    let bytes = std::fs::read(&mp3).expect("mp3");
    let cut = dir.path().join("cut.mp3");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).expect("write");
    fails(
        &cut,
        &["cut.mp3 is damaged after", "announces", "ffmpeg -i IN"],
    );
    // A FLAC with a flipped byte in its audio: a frame fails its CRC.
    let flac = dir.path().join("voice.flac");
    ffmpeg_encode(&example_voice_path(), &flac, &["-c:a", "flac"]);
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
            "notes.mp3 is not audio: it holds text",
            "give an audio file",
        ],
    );
    // Opus: no decoder, and the command that converts it.
    let opus = dir.path().join("voice.opus");
    ffmpeg_encode(&example_voice_path(), &opus, &["-c:a", "libopus"]);
    fails(
        &opus,
        &["Opus", "is not supported", "ffmpeg -i IN OUT.flac"],
    );
}

#[test]
fn analyze_reads_flac_like_the_wav() {
    if !have_ffmpeg("analyze_reads_flac_like_the_wav") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let flac = dir.path().join("voice.flac");
    ffmpeg_encode(&example_voice_path(), &flac, &["-c:a", "flac"]);
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
    let a = run(&example_voice_path(), &dir.path().join("wav.csv"));
    let b = run(&flac, &dir.path().join("flac.csv"));
    assert!(a.lines().count() > 100);
    assert!(a == b, "the FLAC's analysis CSV differs from the WAV's");
}
