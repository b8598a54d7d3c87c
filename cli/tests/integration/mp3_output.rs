//! `pneuma render --format mp3` end to end: the MP3 decoded back (by symphonia through
//! `pneuma-io`, and by ffmpeg) has exactly the WAV render's samples once the encoder delay and
//! padding in LAME's Info frame are trimmed, aligned to the sample, with the breaths' energy
//! where the WAV render has it; the bitrate defaults (192 kbps, or the most the rate holds;
//! the input's own for MP3 input), tags and chapters carried over, and bad bitrates refused.
//!
//! The ffmpeg tests skip visibly without ffmpeg and fail under CI=true (`.ci/run` installs it).

use std::path::Path;
use std::process::Command;

use crate::support;
use pneuma_testkit::voice::{example_voice_at, example_voice_path};
use support::{assert_ok, breaths_csv, ffmpeg_encode, have_ffmpeg, read_audio, render, write_wav};

/// Mono samples of `path` decoded by ffmpeg (32-bit float, the file's own rate).
fn ffmpeg_decode(path: &Path) -> Vec<f32> {
    let o = Command::new("ffmpeg")
        .args(["-hide_banner", "-loglevel", "error", "-i"])
        .arg(path)
        .args(["-ac", "1", "-f", "f32le", "-"])
        .output()
        .expect("ffmpeg runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o.stdout
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

/// RMS level of `x[from..to]` in dB (full scale 1).
fn rms_db(x: &[f32], from: usize, to: usize) -> f64 {
    let s = &x[from.min(x.len())..to.min(x.len())];
    let power = s.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / s.len().max(1) as f64;
    10.0 * (power + 1e-12).log10()
}

/// The lag (samples, within ±`max`) at which `b` best matches `a` over `a[from..from + len]`.
fn best_lag(a: &[f32], b: &[f32], from: usize, len: usize, max: i64) -> i64 {
    (-max..=max)
        .max_by(|&p, &q| {
            let score = |lag: i64| -> f64 {
                (from..from + len)
                    .map(|i| {
                        let j = i as i64 + lag;
                        let y = if j < 0 {
                            0.0
                        } else {
                            *b.get(j as usize).unwrap_or(&0.0)
                        };
                        f64::from(a[i]) * f64::from(y)
                    })
                    .sum()
            };
            score(p).total_cmp(&score(q))
        })
        .expect("a lag")
}

/// Checks a decoded MP3 against the WAV render: the same length, no offset, and in every
/// breath of `breaths` (s) the same energy within 1.5 dB; `what` names the decoder.
fn assert_like_the_wav(what: &str, mp3: &[f32], wav: &[f32], rate: f64, breaths: &[(f64, f64)]) {
    assert_eq!(
        mp3.len(),
        wav.len(),
        "{what}: decoded MP3 has {} samples, the WAV render {}",
        mp3.len(),
        wav.len()
    );
    assert!(!breaths.is_empty(), "the WAV render has breaths");
    let at = |s: f64| (s * rate).round() as usize;
    // Aligned to the sample around the second breath (speech on both sides).
    let (start, _) = breaths[1.min(breaths.len() - 1)];
    let from = at(start).saturating_sub(4000);
    let lag = best_lag(wav, mp3, from, 8000, 1200);
    assert_eq!(lag, 0, "{what}: the MP3 is shifted by {lag} samples");
    for &(s, e) in breaths {
        let (a, b) = (rms_db(wav, at(s), at(e)), rms_db(mp3, at(s), at(e)));
        assert!(
            (a - b).abs() < 1.5,
            "{what}: breath {s:.3}–{e:.3} s at {b:.1} dB in the MP3, {a:.1} dB in the WAV"
        );
    }
}

/// Renders the example voice as WAV and as MP3 (with `extra`) into `dir`; returns the WAV
/// render's samples and breaths.
fn wav_and_mp3(dir: &Path, extra: &[&str]) -> (Vec<f32>, Vec<(f64, f64)>) {
    let voice = example_voice_path();
    assert_ok(&render(&voice, &dir.join("wav"), &["--no-plot"]));
    assert_ok(&render(
        &voice,
        &dir.join("mp3"),
        &[&["--no-plot", "--format", "mp3"], extra].concat(),
    ));
    let (wav, _, _) = read_audio(&dir.join("wav/voice.wav"));
    (wav, breaths_csv(&dir.join("wav/voice.breaths.csv")))
}

#[test]
fn mp3_decoded_by_symphonia_has_the_wav_renders_samples_and_breaths() {
    let dir = tempfile::tempdir().expect("temp");
    for (name, extra) in [("cbr", &[][..]), ("vbr", &["--vbr"][..])] {
        let sub = dir.path().join(name);
        let (wav, breaths) = wav_and_mp3(&sub, extra);
        let (mp3, rate, channels) = read_audio(&sub.join("mp3/voice.mp3"));
        assert_eq!((rate, channels), (16_000, 1));
        assert_like_the_wav(name, &mp3, &wav, 16_000.0, &breaths);
    }
}

#[test]
fn a_vbr_mp3_averages_about_the_bitrate_asked() {
    let dir = tempfile::tempdir().expect("temp");
    // The example voice as a 44.1 kHz stereo WAV, as a podcast's master is.
    let voice = dir.path().join("voice.wav");
    let samples = example_voice_at(44_100);
    write_wav(&voice, (44_100, 2, 16, false), &samples, 1.0);
    let seconds = samples.len() as f64 / 44_100.0;
    for kbps in [64, 128] {
        let out = dir.path().join(kbps.to_string());
        let asked = kbps.to_string();
        let args = ["--no-plot", "--format", "mp3", "--vbr", "--bitrate", &asked];
        assert_ok(&render(&voice, &out, &args));
        let mp3 = std::fs::read(out.join("voice.mp3")).expect("mp3");
        let average = mp3.len() as f64 * 8.0 / seconds / 1000.0;
        // LAME's average-bitrate mode spends less on the pauses and on a side channel that is
        // silent: the average comes out under the one asked (64 → 57, 128 → 85 kbps), never
        // over. LAME's quality levels (`-V`) gave 45 and 60 kbps here.
        let ratio = average / f64::from(kbps);
        assert!(
            (0.6..=1.05).contains(&ratio),
            "--vbr --bitrate {kbps}: {average:.1} kbps on average"
        );
        // Marked variable: LAME heads a VBR stream with a `Xing` frame, a CBR one with `Info`.
        let head = &mp3[..mp3.len().min(8192)];
        assert!(head.windows(4).any(|w| w == b"Xing"), "no Xing frame");
    }
}

#[test]
fn mp3_decoded_by_ffmpeg_has_the_wav_renders_samples_and_breaths() {
    if !have_ffmpeg("mp3_decoded_by_ffmpeg_has_the_wav_renders_samples_and_breaths") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let (wav, breaths) = wav_and_mp3(dir.path(), &[]);
    let mp3 = ffmpeg_decode(&dir.path().join("mp3/voice.mp3"));
    assert_like_the_wav("ffmpeg", &mp3, &wav, 16_000.0, &breaths);
}

/// ffprobe's `key=value` lines for `entries` of `path`.
fn ffprobe(path: &Path, entries: &[&str]) -> String {
    let o = Command::new("ffprobe")
        .args(["-v", "error"])
        .args(entries)
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(path)
        .output()
        .expect("ffprobe runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn the_bitrate_is_the_mp3_inputs_own_and_its_tags_and_chapters_carry_over() {
    if !have_ffmpeg("the_bitrate_is_the_mp3_inputs_own_and_its_tags_and_chapters_carry_over") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    // A 44.1 kHz stereo MP3 at 96 kbps CBR with a title, an artist and two chapters.
    let meta = dir.path().join("meta.txt");
    std::fs::write(
        &meta,
        ";FFMETADATA1\ntitle=Episode 4\nartist=The Host\n\
         [CHAPTER]\nTIMEBASE=1/1000\nSTART=0\nEND=10000\ntitle=Intro\n\
         [CHAPTER]\nTIMEBASE=1/1000\nSTART=10000\nEND=25000\ntitle=Talk\n",
    )
    .expect("meta");
    let input = dir.path().join("ep4.mp3");
    ffmpeg_encode(
        &example_voice_path(),
        &input,
        &[
            "-f",
            "ffmetadata",
            "-i",
            meta.to_str().expect("utf-8"),
            "-map",
            "0:a",
            "-map_metadata",
            "1",
            "-map_chapters",
            "1",
            "-ar",
            "44100",
            "-ac",
            "2",
            "-c:a",
            "libmp3lame",
            "-b:a",
            "96k",
            "-id3v2_version",
            "3",
        ],
    );
    let out = dir.path().join("out");
    assert_ok(&render(&input, &out, &["--no-plot", "--format", "mp3"]));
    let mp3 = out.join("ep4.mp3");
    let stream = ffprobe(
        &mp3,
        &["-show_entries", "stream=bit_rate,sample_rate,channels"],
    );
    assert!(stream.contains("bit_rate=96000"), "{stream}");
    assert!(stream.contains("sample_rate=44100"), "{stream}");
    let tags = ffprobe(&mp3, &["-show_entries", "format_tags=title,artist"]);
    assert!(tags.contains("TAG:title=Episode 4"), "{tags}");
    assert!(tags.contains("TAG:artist=The Host"), "{tags}");
    let chapters = ffprobe(&mp3, &["-show_chapters"]);
    assert!(chapters.contains("TAG:title=Intro"), "{chapters}");
    assert!(chapters.contains("TAG:title=Talk"), "{chapters}");
    assert!(chapters.contains("start_time=10.000000"), "{chapters}");
    // --bitrate wins over the input's.
    let out = dir.path().join("out128");
    assert_ok(&render(
        &input,
        &out,
        &["--no-plot", "--format", "mp3", "--bitrate", "128"],
    ));
    let stream = ffprobe(&out.join("ep4.mp3"), &["-show_entries", "stream=bit_rate"]);
    assert!(stream.contains("bit_rate=128000"), "{stream}");
}

#[test]
fn without_mp3_input_the_bitrate_is_192_or_the_most_the_rate_holds() {
    let dir = tempfile::tempdir().expect("temp");
    // The example voice is 16 kHz: an MP3 at 16 kHz (MPEG-2) holds at most 160 kbps.
    let (wav, _) = wav_and_mp3(dir.path(), &[]);
    let bytes = std::fs::metadata(dir.path().join("mp3/voice.mp3"))
        .expect("mp3")
        .len() as f64;
    let kbps = bytes * 8.0 / (wav.len() as f64 / 16_000.0) / 1000.0;
    assert!((kbps - 160.0).abs() < 3.0, "{kbps:.1} kbps");
    // At 44.1 kHz: 192 kbps.
    let (voice, _, _) = read_audio(&example_voice_path());
    let cd = dir.path().join("cd.wav");
    let resampled: Vec<f32> = (0..voice.len() * 441 / 160)
        .map(|i| voice[i * 160 / 441])
        .collect();
    support::write_wav(&cd, (44_100, 2, 16, false), &resampled, 0.5);
    assert_ok(&render(
        &cd,
        &dir.path().join("cd"),
        &["--no-plot", "--format", "mp3"],
    ));
    let bytes = std::fs::metadata(dir.path().join("cd/cd.mp3"))
        .expect("mp3")
        .len() as f64;
    let kbps = bytes * 8.0 / (resampled.len() as f64 / 44_100.0) / 1000.0;
    assert!((kbps - 192.0).abs() < 3.0, "{kbps:.1} kbps");
}

#[test]
fn bad_bitrates_and_mp3_options_without_mp3_fail_clearly_and_write_nothing() {
    let dir = tempfile::tempdir().expect("temp");
    let voice = example_voice_path();
    for (extra, want) in [
        (
            &["--format", "mp3", "--bitrate", "100"][..],
            "100 kbps is not an MP3 bitrate: give one of 8, 16, 24, 32",
        ),
        (
            &["--format", "mp3", "--bitrate", "loud"][..],
            "'loud' is not a number of kbps",
        ),
        (
            &["--format", "mp3", "--bitrate", "320"][..],
            "--bitrate 320: an MP3 at 16000 Hz holds 8 to 160 kbps",
        ),
        (
            &["--bitrate", "128"][..],
            "--bitrate and --vbr set the MP3 encoding: add --format mp3",
        ),
        (&["--vbr"][..], "add --format mp3"),
    ] {
        let out = dir.path().join("out");
        let o = render(&voice, &out, extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?} should fail");
        assert!(err.contains(want), "{extra:?}: `{want}` not in {err}");
        assert!(!out.exists(), "{extra:?} created {}", out.display());
    }
}
