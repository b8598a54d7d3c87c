//! `pneuma speak` end to end (when espeak-ng is installed, as `.ci/run` makes sure), its errors,
//! and the plot on a long input.

use std::path::Path;
use std::process::Command;

use crate::support;
use support::tool_or_skip;

use pneuma_cli::plot::{write_plot, HEIGHT_PX, WIDTH_PX};
use pneuma_core::{BreathEvent, BreathKind, BreathingState, ControlFrame, Phase};

fn pneuma() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pneuma"))
}

/// Whether espeak-ng is installed. Without it a test skips visibly, except under `CI=true`
/// (`.ci/run` installs it), where it fails.
fn espeak_or_skip(test: &str) -> bool {
    tool_or_skip("espeak-ng", "--version", test)
}

fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (header, rows)
}

fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n");
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20))
}

const TEXT: &str = "Breathing is vital for animals. What about virtual characters? Does the \
    perceivable presence or absence of this behavior play a role in how they are perceived_ \
    is breathing movement effective at conveying state and trait related information? \
    These are the questions that motivate our research.";

#[test]
fn speak_end_to_end_with_espeak() {
    if !espeak_or_skip("speak_end_to_end_with_espeak") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let run = |seed: &str, preset: &str, out: &Path| {
        let o = pneuma()
            .args(["speak", TEXT, "-o"])
            .arg(out)
            .args(["--seed", seed, "--preset", preset])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run("7", "neutral", &out);
    for f in [
        "speech.wav",
        "speech.controls.csv",
        "speech.breaths.csv",
        "speech.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    // No scratch files left behind.
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 4);

    let (h, rows) = csv(&out.join("speech.controls.csv"));
    assert_eq!(h.join(","), pneuma_core::encode::controls_csv::HEADER);
    let (bh, breaths) = csv(&out.join("speech.breaths.csv"));
    assert_eq!(bh.join(","), "start_s,end_s,kind,peak_db");
    assert!(breaths.len() >= 3, "{} breaths", breaths.len());

    let reader = hound::WavReader::open(out.join("speech.wav")).unwrap();
    let rate = reader.spec().sample_rate as f64;
    let duration_s = reader.duration() as f64 / rate;
    let last_t: f64 = rows.last().unwrap()[0].parse().unwrap();
    assert!(
        (duration_s - last_t).abs() < 2.0 / 120.0,
        "{duration_s} vs {last_t}"
    );

    // Every breath lies in a pause (never on top of speech), in an inspiration phase, and is
    // followed by speech; the lung rises during it and falls during the speech after it.
    let col = |name: &str| h.iter().position(|c| c == name).unwrap();
    let (t_c, speak_c, phase_c, lung_c) =
        (col("time_s"), col("speaking"), col("phase"), col("lung"));
    let at = |t: f64| &rows[((t * 120.0).round() as usize).min(rows.len() - 1)];
    for b in &breaths {
        let (s, e): (f64, f64) = (b[0].parse().unwrap(), b[1].parse().unwrap());
        assert!(e > s);
        let mid = at(0.5 * (s + e));
        assert_eq!(mid[speak_c], "0");
        assert_eq!(mid[phase_c], "inspiration");
        let lung_start: f32 = at(s + 0.02)[lung_c].parse().unwrap();
        let lung_end: f32 = at(e - 0.02)[lung_c].parse().unwrap();
        assert!(lung_end > lung_start + 0.1);
        let after = at(e + 0.3);
        assert_eq!(after[speak_c], "1");
        assert_eq!(after[phase_c], "expiration");
        let peak: f32 = b[3].parse().unwrap();
        assert!((-60.0..-10.0).contains(&peak), "breath peak {peak} dBFS");
    }
    assert!(rows.iter().all(|r| r[t_c].parse::<f64>().is_ok()));
    assert_eq!(png_size(&out.join("speech.png")), (WIDTH_PX, HEIGHT_PX));

    // Same seed, same audio bit for bit; another preset changes the breathing.
    let again = dir.path().join("again");
    run("7", "neutral", &again);
    assert_eq!(
        std::fs::read(out.join("speech.wav")).unwrap(),
        std::fs::read(again.join("speech.wav")).unwrap()
    );
    let anxious = dir.path().join("anxious");
    run("7", "anxious", &anxious);
    let (_, anxious_breaths) = csv(&anxious.join("speech.breaths.csv"));
    assert!(anxious_breaths.len() > breaths.len());
}

#[test]
fn missing_tts_names_the_package() {
    let dir = tempfile::tempdir().unwrap();
    for (tts, package) in [("espeak", "espeak-ng"), ("festival", "festival")] {
        let o = pneuma()
            .args(["speak", "Hello there.", "--tts", tts, "-o"])
            .arg(dir.path())
            .env("PATH", dir.path())
            .output()
            .unwrap();
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(&format!("apt-get install {package}")),
            "{tts}: {err}"
        );
    }
}

#[test]
fn bad_input_gets_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (&["speak", "  ...  "], "no text"),
        (
            &["speak", "Hi.", "--preset", "sleepy"],
            "[possible values: neutral, calm, anxious, tired, excited]",
        ),
        (
            &["speak", "Hi.", "--rate", "5"],
            "--rate 5 is out of range: use 0.5 to 2",
        ),
        (
            &["speak", "Hi.", "--loudness", "0"],
            "--loudness 0 is out of range: use 0.05 to 1",
        ),
        (
            &["speak", "--text-file", "/nonexistent/x.txt"],
            "--text-file: cannot read /nonexistent/x.txt",
        ),
    ];
    for (args, want) in cases {
        let o = pneuma()
            .args(args)
            .arg("-o")
            .arg(dir.path())
            .output()
            .unwrap();
        assert!(!o.status.success());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
    }
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

#[test]
fn plot_of_a_long_file_has_a_fixed_size() {
    let rate = 8_000.0;
    let seconds = 1200.0;
    let audio: Vec<f32> = (0..(rate * seconds) as usize)
        .map(|i| (i as f32 * 0.05).sin() * 0.3)
        .collect();
    let controls: Vec<ControlFrame> = (0..(seconds * 120.0) as usize)
        .map(|i| ControlFrame {
            index: i as u64,
            time_s: i as f64 / 120.0,
            breathing: BreathingState {
                phase: if i % 600 < 60 {
                    Phase::Inspiration
                } else {
                    Phase::Expiration
                },
                lung: (i % 600) as f32 / 600.0,
                ..Default::default()
            },
            ..Default::default()
        })
        .collect();
    let breaths: Vec<BreathEvent> = (0..240)
        .map(|k| BreathEvent {
            start_s: k as f64 * 5.0,
            end_s: k as f64 * 5.0 + 0.5,
            kind: BreathKind::Mouth,
            peak_db: -30.0,
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("long.png");
    write_plot(&path, &audio, seconds, &controls, &breaths).unwrap();
    assert_eq!(png_size(&path), (WIDTH_PX, HEIGHT_PX));
    assert!(std::fs::metadata(&path).unwrap().len() < 2_000_000);
    assert!(write_plot(&path, &[], seconds, &[], &[]).is_err());
    assert!(write_plot(&path, &audio[..100], f64::NAN, &controls, &breaths).is_err());
}

#[test]
fn speak_moves_the_head_and_writes_bvh_at_the_asked_rate() {
    if !espeak_or_skip("speak_moves_the_head_and_writes_bvh_at_the_asked_rate") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = pneuma()
        .args(["speak", TEXT, "--output"])
        .arg(&out)
        .args(["--bvh", "--no-plot", "--frame-rate", "60", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(o.stderr.is_empty(), "-q printed something");
    assert!(!out.join("speech.png").exists(), "--no-plot drew a plot");
    let (h, rows) = csv(&out.join("speech.controls.csv"));
    // 60 frames per second.
    let t1: f64 = rows[1][0].parse().unwrap();
    assert!((t1 - 1.0 / 60.0).abs() < 1e-6, "second frame at {t1} s");
    // The head moves: each angle column varies over the speech.
    for name in ["head_pitch_deg", "head_yaw_deg", "head_roll_deg"] {
        let c = h.iter().position(|x| x == name).expect(name);
        let v: Vec<f64> = rows.iter().map(|r| r[c].parse().unwrap()).collect();
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!(hi - lo > 0.5, "{name} spans only {lo}..{hi} degrees");
    }
    let bvh = std::fs::read_to_string(out.join("speech.bvh")).unwrap();
    let frames: usize = bvh
        .lines()
        .find_map(|l| l.strip_prefix("Frames:"))
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    assert_eq!(frames, rows.len());
    assert!(bvh.contains("Frame Time: 0.016"), "BVH not at 60 frames/s");
}

#[test]
fn a_bad_voice_points_to_the_voice_list() {
    if !espeak_or_skip("a_bad_voice_points_to_the_voice_list") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // A voice espeak-ng refuses, and three it would take silently and speak in another voice
    // (a typo of `en-us`, variants it does not have): the same error, before any audio.
    for voice in ["xx-nonesuch", "en-uss", "en-us+nonsense", "en-us+F3"] {
        let out = dir.path().join(voice);
        let o = pneuma()
            .args(["speak", "Hello there.", "--voice", voice, "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "--voice {voice} succeeded");
        assert!(
            err.contains(&format!("has no voice `{voice}`")) && err.contains("espeak-ng --voices"),
            "{err}"
        );
        assert!(
            !out.join("speech.wav").exists(),
            "--voice {voice} wrote audio"
        );
    }
    // The forms espeak-ng takes: a language in any case or with a region, with a variant, a
    // voice file, a voice name.
    for voice in [
        "EN-US",
        "en-AU",
        "en-us+f3",
        "gmw/en-US",
        "English (America)",
    ] {
        let o = pneuma()
            .args(["speak", "Hello.", "--no-plot", "--voice", voice, "-o"])
            .arg(dir.path().join("ok"))
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "--voice {voice}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

/// `speak` runs the engine over its timeline (issue 31): breaths vary in length with the pause
/// and the coming group as in a render, and the lung keeps the render's reserve at the end of
/// a group instead of emptying (the hand-built timeline before gave every breath the preset's
/// 0.60 s and a lung of 0.00 before each one).
#[test]
fn speak_breathes_like_a_render_varied_breaths_and_a_reserve() {
    if !espeak_or_skip("speak_breathes_like_a_render_varied_breaths_and_a_reserve") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{TEXT} {TEXT} Short one. {TEXT}");
    let o = pneuma()
        .args(["speak", &text, "-o"])
        .arg(dir.path())
        .arg("--no-plot")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, breaths) = csv(&dir.path().join("speech.breaths.csv"));
    let lengths: Vec<f64> = breaths
        .iter()
        .map(|b| b[1].parse::<f64>().unwrap() - b[0].parse::<f64>().unwrap())
        .collect();
    assert!(lengths.len() >= 8, "{} breaths", lengths.len());
    let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
    let sd =
        (lengths.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / lengths.len() as f64).sqrt();
    assert!(sd > 0.02, "breath lengths {lengths:?} hardly vary");
    assert!(
        lengths.iter().all(|l| (0.1..0.9).contains(l)),
        "{lengths:?}"
    );
    let (h, rows) = csv(&dir.path().join("speech.controls.csv"));
    let lung_c = h.iter().position(|c| c == "lung").unwrap();
    let mut before: Vec<f64> = breaths
        .iter()
        .skip(1)
        .map(|b| {
            let i = (b[0].parse::<f64>().unwrap() * 120.0).floor() as usize;
            rows[i.saturating_sub(1)][lung_c].parse().unwrap()
        })
        .collect();
    before.sort_by(f64::total_cmp);
    let median = before[before.len() / 2];
    assert!(
        median > 0.05,
        "lung before a breath: median {median} ({before:?})"
    );
}

/// Writes `script` as an executable `text2wave` in `bin` (a stand-in for festival's).
#[cfg(unix)]
fn fake_text2wave(bin: &Path, script: &str) {
    use std::os::unix::fs::PermissionsExt;
    let fake = bin.join("text2wave");
    std::fs::write(&fake, script).unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
}

/// A TTS that exits 0 without writing audio: festival's `text2wave` asked for a voice it does
/// not have says "unbound variable" and writes nothing. Told in our words (which voice, how
/// to list them), never as a file missing from the scratch folder.
#[cfg(unix)]
#[test]
fn a_tts_that_writes_nothing_is_told_as_such_and_a_bad_festival_voice_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    for (said, want) in [
        (
            "SIOD ERROR: unbound variable : voice_xx",
            "festival has no voice `xx`: `echo '(print (voice.list))' | festival --pipe`",
        ),
        (
            "",
            "`text2wave` failed on chunk \"Hello there.\": wrote no audio",
        ),
    ] {
        fake_text2wave(
            &bin,
            &format!("#!/bin/sh\nwhile read -r l; do :; done\necho '{said}' >&2\nexit 0\n"),
        );
        let o = pneuma()
            .args([
                "speak",
                "Hello there.",
                "--tts",
                "festival",
                "--voice",
                "xx",
                "-o",
            ])
            .arg(dir.path().join("out"))
            .env("PATH", &bin)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{err}");
        assert!(err.contains(want), "{err}");
        assert!(!err.contains(".pneuma-speak"), "a scratch path: {err}");
        assert!(
            !dir.path().join("out").exists(),
            "an output folder was left"
        );
    }
}

/// A second take in the same folder leaves no file of the first one that it did not write
/// itself: the BVH, MIDI file and plot of a longer take would describe other audio.
#[test]
fn a_second_take_removes_what_the_first_wrote_and_it_did_not() {
    if !espeak_or_skip("a_second_take_removes_what_the_first_wrote_and_it_did_not") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let speak = |extra: &[&str]| {
        let o = pneuma()
            .args(["speak", "A first take, longer than the second.", "-o"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    speak(&["--bvh", "--midi"]);
    for f in ["speech.bvh", "speech.mid", "speech.png"] {
        assert!(out.join(f).is_file(), "{f} written");
    }
    // A file of the user's beside them is theirs.
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let err = speak(&["--no-plot", "--quiet"]);
    for f in ["speech.bvh", "speech.mid", "speech.png"] {
        assert!(!out.join(f).exists(), "{f} left from the first take");
        assert!(err.contains(f), "the removal of {f} is told: {err}");
    }
    assert!(out.join("speech.wav").is_file() && out.join("notes.txt").is_file());
}

/// A podcaster takes the spoken text as FLAC, AIFF or MP3 for the edit, as `render` writes
/// them: the same take as the WAV (sample for sample when lossless, the same length as MP3),
/// and the MP3 options refused where they mean nothing (before anything is spoken) or where the
/// TTS's rate cannot hold them (after its first chunk).
#[test]
fn speak_writes_the_format_asked_and_refuses_mp3_options_without_mp3() {
    if !espeak_or_skip("speak_writes_the_format_asked_and_refuses_mp3_options_without_mp3") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let speak = |extra: &[&str]| {
        pneuma()
            .args([
                "speak",
                "A short take. Then a second sentence.",
                "--no-plot",
                "-o",
            ])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let ok = |extra: &[&str]| {
        let o = speak(extra);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stderr).into_owned()
    };
    ok(&[]);
    let (wav, rate_hz) = pneuma_io::read_mono(&out.join("speech.wav")).unwrap();
    for (format, kind) in [
        ("flac", pneuma_io::InputFormat::Flac),
        ("aiff", pneuma_io::InputFormat::Aiff),
        ("mp3", pneuma_io::InputFormat::Mp3),
    ] {
        let said = ok(&["--format", format]);
        let path = out.join(format!("speech.{format}"));
        assert!(
            said.contains("speech.wav stays beside this take's"),
            "the earlier take's WAV is named: {said}"
        );
        assert_eq!(
            pneuma_io::AudioSource::open(&path).unwrap().format(),
            kind,
            "{format}"
        );
        let (got, got_hz) = pneuma_io::read_mono(&path).unwrap();
        assert_eq!(got_hz, rate_hz, "{format} at the TTS's rate");
        assert_eq!(got.len(), wav.len(), "{format}: the take's length");
        if format == "mp3" {
            let dot = |a: &[f32], b: &[f32]| -> f64 {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| f64::from(*x) * f64::from(*y))
                    .sum()
            };
            let r = dot(&got, &wav) / (dot(&got, &got) * dot(&wav, &wav)).sqrt();
            assert!(r > 0.95, "the MP3 is the same take: r {r}");
        } else {
            assert_eq!(got, wav, "{format} holds the WAV's samples");
        }
    }
    // The WAV of the first run is not this run's and not removed (it may be the user's), but
    // it is named above.
    assert!(out.join("speech.wav").is_file());
    let mp3_before = std::fs::read(out.join("speech.mp3")).unwrap();
    for (extra, says) in [
        (&["--bitrate", "64"][..], "add --format mp3"),
        (&["--vbr", "--format", "flac"][..], "add --format mp3"),
        (&["--format", "mp3", "--bitrate", "320"][..], "kbps"),
    ] {
        let o = speak(extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            !o.status.success() && err.contains(says),
            "{extra:?}: {err}"
        );
    }
    let mp3_after = std::fs::read(out.join("speech.mp3")).unwrap();
    assert!(
        mp3_after == mp3_before,
        "a refused run leaves the earlier MP3 as it was"
    );
}

/// A voice-over artist sets the breaths' level as in `render`, or takes the same take dry.
#[test]
fn speak_takes_the_breath_level_and_a_dry_take() {
    if !espeak_or_skip("speak_takes_the_breath_level_and_a_dry_take") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let speak = |name: &str, extra: &[&str]| {
        let out = dir.path().join(name);
        let o = pneuma()
            .args(["speak", TEXT, "--no-plot", "-o"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let (_, breaths) = csv(&out.join("speech.breaths.csv"));
        let mut peaks: Vec<f64> = breaths.iter().map(|b| b[3].parse().unwrap()).collect();
        peaks.sort_by(f64::total_cmp);
        let (_, controls) = csv(&out.join("speech.controls.csv"));
        (peaks, controls)
    };
    let (default, controls) = speak("default", &[]);
    let (quiet, _) = speak("quiet", &["--breath-level-db", "-40"]);
    assert!(!default.is_empty() && default.len() == quiet.len());
    let median = |p: &[f64]| p[p.len() / 2];
    let lower = median(&default) - median(&quiet);
    assert!(
        (12.0..24.0).contains(&lower),
        "--breath-level-db -40 against the default: {lower:.1} dB lower"
    );
    let (dry, dry_controls) = speak("dry", &["--no-breaths"]);
    assert!(dry.is_empty(), "a dry take inserted {dry:?}");
    // The body breathes as with breaths: the same controls.
    assert_eq!(dry_controls, controls);
    let o = pneuma()
        .args(["speak", "Hi.", "--breath-level-db", "-90", "-o"])
        .arg(dir.path().join("bad"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && err.contains("--breath-level-db"),
        "{err}"
    );
}

/// festival reads bytes, not UTF-8: a text with "café" and typographic quotes reaches it in
/// ASCII ("cafe"), and what has no ASCII spelling is left out with a warning, even under
/// --quiet (a chunk of nothing else is not spoken); a text with nothing festival can say is
/// refused before anything is written.
#[cfg(unix)]
#[test]
fn festival_is_given_ascii_and_told_what_it_could_not_say() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    // A half-second vowel-like tone stands for each chunk festival would say.
    let tone: Vec<f32> = (0..8000)
        .map(|i| 0.3 * (2.0 * std::f32::consts::PI * 140.0 * i as f32 / 16000.0).sin())
        .collect();
    let wav = dir.path().join("tone.wav");
    support::write_wav(&wav, (16000, 1, 16, false), &tone, 1.0);
    let said = dir.path().join("said.txt");
    fake_text2wave(
        &bin,
        &format!(
            "#!/bin/sh\ncat >> '{}'\ncp '{}' \"$2\"\n",
            said.display(),
            wav.display()
        ),
    );
    let speak = |text: &str, out: &str| {
        pneuma()
            .args(["speak", text, "--tts", "festival", "--quiet", "-o"])
            .arg(dir.path().join(out))
            .env("PATH", format!("{}:/usr/bin:/bin", bin.display()))
            .output()
            .unwrap()
    };
    let o = speak(
        "The caf\u{e9} was na\u{ef}ve, \u{201c}Zo\u{eb}\u{201d} said. \u{65e5}\u{672c}. Dvo\u{159}\u{e1}k!",
        "out",
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let given = std::fs::read(&said).unwrap();
    let given = String::from_utf8(given).unwrap();
    assert!(given.is_ascii(), "festival was given {given:?}");
    // A chunk of nothing festival can say is not sent to it.
    assert!(
        given
            .lines()
            .all(|l| l.chars().any(|c| c.is_ascii_alphabetic())),
        "{given:?}"
    );
    for w in ["The cafe was naive", "\"Zoe\" said", "Dvorak"] {
        assert!(given.contains(w), "{w:?} not in {given:?}");
    }
    assert!(
        err.contains(
            "warning: festival reads ASCII only: 2 characters without an ASCII spelling were left \
             out (\u{65e5} \u{672c})"
        ),
        "{err}"
    );
    assert!(dir.path().join("out/speech.wav").is_file());

    let o = speak("\u{65e5}\u{672c}\u{8a9e}", "none");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.contains("festival reads ASCII only: 3 characters") && err.contains("--tts espeak"),
        "{err}"
    );
    assert!(
        !dir.path().join("none").exists(),
        "an output folder was made"
    );
}
