//! What new users met (issue 33), end to end: dotted output folder names, every file of a batch
//! folder accounted for, and the messages (a folder given to `analyze`, text named `.wav`,
//! lossy input without a bit depth, "1 breath", a closed pipe, no empty folder left behind).

use std::io::Read as _;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::support;
use pneuma_testkit::voice::example_voice_path as example_voice;
use support::{assert_ok, breaths_csv, pneuma, render, render_saying, two_phrases, write_wav};

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
    // A batch into it is the same one mistake: told once, before any input is rendered.
    let second = dir.path().join("ep2.wav");
    write_wav(&second, (16_000, 1, 16, false), &two_phrases(), 1.0);
    let o = pneuma(&[
        "render",
        input.to_str().expect("utf-8"),
        second.to_str().expect("utf-8"),
        "-o",
        dir.path().join("ep_out.flac").to_str().expect("utf-8"),
    ]);
    let err = stderr(&o);
    assert!(!o.status.success(), "{err}");
    assert_eq!(err.matches("looks like a file name").count(), 1, "{err}");
    assert!(!err.contains("FAILED"), "no table of failed inputs: {err}");
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
        opus_row.contains("Opus")
            && opus_row.contains("ffmpeg -i '")
            && opus_row.contains("episodes/ep04.opus' '")
            && opus_row.contains("episodes/ep04.flac'"),
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
        // Generated vowels are not speech to the speech decision.
        "--any-sound",
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
fn the_summary_counts_the_real_breaths_heard_and_left_in() {
    // A speaker who breathes in every pause (seven 0.3 s inhalations): the render inserts
    // none over them and says how many it heard, in the summary and the batch table; with the
    // breaths gated out there is nothing to count.
    use pneuma_testkit::signals;
    let dir = tempfile::tempdir().expect("temp");
    let breathing = dir.path().join("breathing.wav");
    let gated = dir.path().join("gated.wav");
    write_wav(
        &breathing,
        (16_000, 1, 16, false),
        &signals::phrases_with_breaths(16_000.0, 16.0, 5),
        1.0,
    );
    write_wav(
        &gated,
        (16_000, 1, 16, false),
        &signals::phrases_with_pauses(16_000.0, 16.0, 60.0, 5),
        1.0,
    );
    let heard_line = "real breaths heard in the pauses and left as they are: ";
    for (input, heard) in [(&breathing, true), (&gated, false)] {
        let out = dir.path().join("out");
        // Generated vowels are not speech to the speech decision.
        let o = render_saying(input, &out, &["--any-sound"]);
        assert_ok(&o);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        let n = err
            .lines()
            .find_map(|l| l.trim().strip_prefix(heard_line))
            .map(|n| n.parse::<usize>().expect("a count"));
        if heard {
            assert!(matches!(n, Some(5..=7)), "{err}");
        } else {
            assert_eq!(n, None, "{err}");
        }
    }
    let out = dir.path().join("batch");
    let o = pneuma(&[
        "render",
        breathing.to_str().expect("utf-8"),
        gated.to_str().expect("utf-8"),
        "-o",
        out.to_str().expect("utf-8"),
        "--no-plot",
        "--no-progress",
        "--any-sound",
    ]);
    assert_ok(&o);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    let cells = |name: &str| -> Vec<String> {
        let line = err.lines().find(|l| l.contains(name)).expect(name);
        line.split_whitespace().map(str::to_string).collect()
    };
    let header = cells("heard");
    let column = header
        .iter()
        .position(|c| c == "heard")
        .expect("a heard column");
    assert_eq!(cells("gated.wav")[column], "0", "{err}");
    assert!(
        cells("breathing.wav")[column]
            .parse::<usize>()
            .expect("a count")
            >= 5,
        "{err}"
    );
}

#[test]
fn speech_with_no_pause_to_breathe_in_is_told_out_of_air() {
    // 25 s of one vowel with a syllable rhythm and no pause (as a take whose breaths were cut
    // out with their pauses): the render says the speech ran out of air and why. The same
    // voice in 1.5 s phrases with 0.5 s pauses, and live mode (which runs its lung low in
    // ordinary speech), are not told.
    use pneuma_testkit::signals::{self, GlottalVowel, Vowel};
    let dir = tempfile::tempdir().expect("temp");
    let rate = 16_000.0;
    let vowel = signals::glottal_vowel(
        &GlottalVowel {
            sample_rate_hz: rate,
            length_s: 25.0,
            vowel: Vowel::A,
            jitter: 0.01,
            shimmer: 0.05,
            peak: 0.5,
            seed: 3,
        },
        |t| 120.0 + 20.0 * (1.9 * t).sin(),
    );
    let lead = (0.5 * rate) as usize;
    let mut breathless = vec![0.0f32; lead];
    breathless.extend(vowel.iter().enumerate().map(|(i, x)| {
        let syllable = (std::f64::consts::PI * 4.0 * i as f64 / rate).sin().abs();
        x * (0.3 + 0.7 * syllable) as f32
    }));
    let paused = signals::phrases_with_pauses(rate, 25.0, 60.0, 3);
    let told = "with its air used up";
    for (name, x, extra, want) in [
        ("breathless.wav", &breathless, None, true),
        ("paused.wav", &paused, None, false),
        ("breathless_live.wav", &breathless, Some("live"), false),
    ] {
        let input = dir.path().join(name);
        write_wav(&input, (16_000, 1, 16, false), x, 1.0);
        let mut args = vec!["--any-sound"];
        if let Some(mode) = extra {
            args.extend(["--mode", mode]);
        }
        let o = render_saying(&input, &dir.path().join("out"), &args);
        assert_ok(&o);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert_eq!(err.contains(told), want, "{name}: {err}");
        if want {
            assert!(err.contains("ripple delete"), "{err}");
        }
    }
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

#[test]
fn render_midi_is_a_standard_midi_file_of_the_controls() {
    let Some(python) = support::python_tools("render_midi_is_a_standard_midi_file_of_the_controls")
    else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("two.wav");
    write_wav(&input, (16_000, 1, 16, false), &two_phrases(), 1.0);
    let out = dir.path().join("out");
    assert_ok(&render(&input, &out, &["--no-plot", "--midi"]));
    let (head, ccs) = support::read_midi(&python, &out.join("two.mid"));
    assert_eq!(
        head, "0 960 500000 1",
        "format 0, 960 ticks, 120 BPM, one track"
    );
    // The lung (CC 2) as the controls CSV has it at the same time, 0..1 to 0..127.
    let csv = std::fs::read_to_string(out.join("two.controls.csv")).expect("csv");
    let rows: Vec<(f64, f64)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse().expect("time"), f[6].parse().expect("lung"))
        })
        .collect();
    let lung: Vec<_> = ccs.iter().filter(|c| c.2 == 2).collect();
    assert!(lung.len() > 10, "the lung moves: {}", lung.len());
    for &&(t, channel, _, value) in &lung {
        assert_eq!(channel, 0);
        let (_, l) = rows
            .iter()
            .find(|(rt, _)| (rt - t).abs() < 0.5 / 120.0)
            .unwrap_or_else(|| panic!("no controls row at {t} s"));
        let want = l * 127.0;
        assert!(
            (f64::from(value) - want).abs() <= 1.0,
            "lung {l} at {t} s sent as {value}"
        );
    }
    // Every mapped controller is there, the last message within the audio.
    let controllers: std::collections::BTreeSet<u8> = ccs.iter().map(|c| c.2).collect();
    assert_eq!(
        controllers.into_iter().collect::<Vec<_>>(),
        vec![2, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25]
    );
    let length_s = two_phrases().len() as f64 / 16_000.0;
    assert!(ccs.last().expect("messages").0 <= length_s);
}

#[test]
fn speak_writes_the_midi_file_too() {
    if !support::tool_or_skip("espeak-ng", "--version", "speak_writes_the_midi_file_too") {
        return;
    }
    let Some(python) = support::python_tools("speak_writes_the_midi_file_too") else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp");
    let o = pneuma(&[
        "speak",
        "One breath group. And another one after it.",
        "-o",
        dir.path().to_str().expect("utf-8"),
        "--midi",
        "--no-plot",
        "-q",
    ]);
    assert_ok(&o);
    let (head, ccs) = support::read_midi(&python, &dir.path().join("speech.mid"));
    assert_eq!(head, "0 960 500000 1");
    assert!(
        ccs.iter().any(|c| c.2 == 24 && c.3 == 127),
        "speaking gate opens"
    );
    assert!(
        ccs.iter().filter(|c| c.2 == 2).count() > 5,
        "the lung moves"
    );
}

#[test]
fn mu_law_and_a_law_wav_render_as_their_16_bit_twins() {
    if !support::have_ffmpeg("mu_law_and_a_law_wav_render_as_their_16_bit_twins") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("call.wav");
    write_wav(&input, (8_000, 1, 16, false), &two_phrases(), 1.0);
    for codec in ["pcm_mulaw", "pcm_alaw"] {
        // The phone file, and ffmpeg's own decoding of it to 16-bit PCM.
        let law = dir.path().join(format!("{codec}.wav"));
        support::ffmpeg_encode(&input, &law, &["-ar", "8000", "-c:a", codec]);
        let twin = dir.path().join(format!("{codec}_twin.wav"));
        support::ffmpeg_encode(&law, &twin, &["-c:a", "pcm_s16le"]);
        let (got, rate, channels) = support::read_audio(&law);
        assert_eq!((rate, channels), (8_000, 1));
        assert_eq!(
            got,
            support::samples(&twin),
            "{codec}: decoded as ffmpeg does"
        );
        let out = dir.path().join(codec);
        let o = pneuma(&[
            "render",
            law.to_str().expect("utf-8"),
            "-o",
            out.to_str().expect("utf-8"),
            "--no-plot",
            "--any-sound",
        ]);
        assert_ok(&o);
        assert!(
            stderr(&o).contains("(WAV, 8000 Hz, 1 ch, 16-bit)"),
            "{}",
            stderr(&o)
        );
        // ... and says the companding was not kept (the tryout of 8 December 2026 found the
        // format line alone silent about it).
        let law_name = if codec == "pcm_mulaw" {
            "µ-law"
        } else {
            "A-law"
        };
        assert!(
            stderr(&o).contains(&format!(
                "G.711 {law_name}: the output holds them as 16-bit"
            )),
            "{}",
            stderr(&o)
        );
        let twin_said = support::render_saying(&twin, &out, &["--any-sound"]);
        assert_ok(&twin_said);
        assert!(
            !stderr(&twin_said).contains("G.711"),
            "{}",
            stderr(&twin_said)
        );
        let rendered = support::samples(&out.join(format!("{codec}.wav")));
        assert_eq!(
            rendered,
            support::samples(&out.join(format!("{codec}_twin.wav"))),
            "{codec}: the render equals the 16-bit twin's"
        );
        assert!(!breaths_csv(&out.join(format!("{codec}.breaths.csv"))).is_empty());
    }
}

#[test]
fn the_bvh_is_person_sized_in_metres_at_the_asked_frame_rate() {
    let Some(python) =
        support::python_tools("the_bvh_is_person_sized_in_metres_at_the_asked_frame_rate")
    else {
        return;
    };
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("two.wav");
    let audio = two_phrases();
    write_wav(&input, (16_000, 1, 16, false), &audio, 1.0);
    let length_s = audio.len() as f64 / 16_000.0;
    for (fps, extra) in [(24.0, &["--bvh-fps", "24"][..]), (120.0, &[][..])] {
        let out = dir.path().join(format!("fps{fps}"));
        assert_ok(&render(
            &input,
            &out,
            &[&["--no-plot", "--bvh"], extra].concat(),
        ));
        let text = support::python_tool(&python, "read_bvh.py", &[&out.join("two.bvh")]);
        let first: Vec<f64> = text
            .lines()
            .next()
            .expect("line")
            .split(' ')
            .map(|x| x.parse().expect("number"))
            .collect();
        let (frames, frame_time_s, height, rows) = (first[0], first[1], first[2], first[3]);
        assert_eq!(frames, rows, "{fps}: the header's count is the rows'");
        assert!(
            (frame_time_s - 1.0 / fps).abs() < 1e-7,
            "{fps}: {frame_time_s}"
        );
        assert!((height - 1.8).abs() < 1e-9, "1.8 m tall: {height}");
        // Frames × frame time is the audio's duration (within a frame).
        let duration_s = frames * frame_time_s;
        assert!(
            (duration_s - length_s).abs() <= 1.0 / fps + 1.0 / 120.0,
            "{fps} fps: {duration_s} s of motion for {length_s} s of audio"
        );
        assert_eq!(text.lines().nth(1), Some("Hips Chest Neck Head"));
    }
    let o = render(
        &input,
        &dir.path().join("bad"),
        &["--bvh", "--bvh-fps", "0"],
    );
    assert!(
        stderr(&o).contains("--bvh-fps 0 fps is out of range: use 1 to 1000 fps"),
        "{}",
        stderr(&o)
    );
    // --jobs is refused out of its range for one input as for a batch.
    for jobs in ["0", "300"] {
        let o = render(&input, &dir.path().join("jobs"), &["--jobs", jobs]);
        assert!(!o.status.success(), "--jobs {jobs}");
        assert!(
            stderr(&o).contains(&format!("{jobs} is out of range: use 1 to 256")),
            "{}",
            stderr(&o)
        );
    }
}

#[test]
fn options_of_the_breath_sound_are_refused_with_no_breaths() {
    let dir = tempfile::tempdir().expect("temp");
    let voice = example_voice();
    let out = dir.path().join("out");
    for option in [
        &["--breath-level-db", "-10"][..],
        &["--breath-like", voice.to_str().expect("utf-8")],
        &["--built-in-breath"],
    ] {
        let o = render(&voice, &out, &[&["--no-breaths"][..], option].concat());
        assert!(!o.status.success(), "{option:?} was accepted");
        let err = stderr(&o);
        assert!(
            err.contains(option[0]) && err.contains("--no-breaths"),
            "{err}"
        );
    }
    // A folder of samples and a single sample file: which one would win is not the user's
    // guess to make (as `speak`).
    let folder = dir.path().to_str().expect("utf-8");
    let o = render(
        &voice,
        &out,
        &["--breath-samples", folder, "--breath-mouth", folder],
    );
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(
        err.contains("--breath-samples") && err.contains("--breath-mouth"),
        "{err}"
    );
    assert!(!out.exists(), "a refused render made its folder");
}

/// A breath sample that is missing or no audio is named by the option that gave it, in
/// `render` and in `speak`.
#[test]
fn a_bad_breath_sample_names_its_option() {
    let dir = tempfile::tempdir().expect("temp");
    let voice = example_voice();
    let out = dir.path().join("out");
    let notes = dir.path().join("notes.wav");
    std::fs::write(&notes, "not a breath at all").expect("write");
    let missing = dir.path().join("missing.wav");
    for (option, file) in [("--breath-mouth", &missing), ("--breath-nose", &notes)] {
        let file = file.to_str().expect("utf-8");
        let o = render(&voice, &out, &[option, file]);
        let err = stderr(&o);
        assert!(!o.status.success() && err.contains(option), "render: {err}");
        let o = pneuma(&[
            "speak",
            "Hi",
            "-o",
            out.to_str().expect("utf-8"),
            option,
            file,
        ]);
        let err = stderr(&o);
        assert!(!o.status.success() && err.contains(option), "speak: {err}");
    }
}

#[test]
fn a_failed_speak_leaves_no_folder_behind() {
    let dir = tempfile::tempdir().expect("temp");
    let out = dir.path().join("a/b/c");
    // No such voice (or no espeak-ng at all): the run fails either way.
    let o = pneuma(&[
        "speak",
        "Hi",
        "-o",
        out.to_str().expect("utf-8"),
        "--voice",
        "zzqx",
    ]);
    assert!(!o.status.success(), "{}", stderr(&o));
    assert!(
        !dir.path().join("a").exists(),
        "the folders it made are left"
    );
}

#[test]
fn a_breath_like_file_of_music_is_said_and_not_learned_from() {
    // A new user gave a music file as --breath-like: it was learned from ("learned from 1
    // breath") without a word. Eight plucked chords (harmonic tones decaying over 0.35 s, with
    // quiet gaps between them) hold no speech: the render says so and learns the voice from the
    // input, as without the option.
    let dir = tempfile::tempdir().expect("temp");
    let voice = example_voice();
    let rate = 16_000.0;
    let music = pneuma_testkit::signals::plucked_chords(rate, 14.0);
    let like = dir.path().join("chords.wav");
    write_wav(&like, (16_000, 1, 16, false), &music, 1.0);
    let voice_line = |o: &std::process::Output| {
        stderr(o)
            .lines()
            .find(|l| l.contains("breath voice"))
            .map(str::to_owned)
            .unwrap_or_default()
    };
    let plain = render_saying(&voice, &dir.path().join("plain"), &[]);
    let liked = render_saying(
        &voice,
        &dir.path().join("liked"),
        &["--breath-like", like.to_str().expect("utf-8")],
    );
    assert_ok(&plain);
    assert_ok(&liked);
    assert!(
        stderr(&liked).contains("warning: the --breath-like file holds no speech"),
        "{}",
        stderr(&liked)
    );
    assert!(
        !voice_line(&liked).is_empty() && voice_line(&liked) == voice_line(&plain),
        "learned as without the file: {:?} against {:?}",
        voice_line(&liked),
        voice_line(&plain)
    );
    assert!(
        !stderr(&plain).contains("--breath-like"),
        "{}",
        stderr(&plain)
    );
}
