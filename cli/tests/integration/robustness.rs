//! A tester's robustness findings, each a test that failed before its fix: valid files refused
//! as damaged, partial files left by a termination, outputs that replaced audio.

use std::path::Path;

use crate::support;
use pneuma_testkit::voice::example_voice_path;
use support::{assert_ok, ffmpeg_encode, have_ffmpeg, pneuma, read_audio, render};

/// Seconds of audio in an audio file pneuma reads.
fn duration_s(path: &Path) -> f64 {
    let (samples, rate_hz, channels) = read_audio(path);
    samples.len() as f64 / f64::from(channels) / f64::from(rate_hz)
}

#[test]
fn a_vbr_mp3_without_a_xing_frame_renders_and_analyzes_whole() {
    if !have_ffmpeg("a_vbr_mp3_without_a_xing_frame_renders_and_analyzes_whole") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    // What an encoder writing to a pipe makes: VBR frames and no Xing frame before them.
    let mp3 = dir.path().join("vbr_piped.mp3");
    let lame = ["-c:a", "libmp3lame", "-q:a", "2", "-write_xing", "0"];
    ffmpeg_encode(&example_voice_path(), &mp3, &lame);
    let out = dir.path().join("out");
    let o = render(&mp3, &out, &["--no-plot"]);
    assert_ok(&o);
    let (voice_s, rendered_s) = (
        duration_s(&example_voice_path()),
        duration_s(&out.join("vbr_piped.flac")),
    );
    // The encoder's delay and padding stay (no LAME frame says how long they are).
    assert!(
        (rendered_s - voice_s).abs() < 0.2,
        "{rendered_s} s rendered of {voice_s} s"
    );
    let csv = dir.path().join("vbr.csv");
    let args = [
        "analyze",
        mp3.to_str().unwrap(),
        "-o",
        csv.to_str().unwrap(),
    ];
    assert_ok(&pneuma(&args));
}

#[test]
fn a_chained_ogg_file_renders_every_stream_in_every_output() {
    if !have_ffmpeg("a_chained_ogg_file_renders_every_stream_in_every_output") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let ogg = dir.path().join("a.ogg");
    ffmpeg_encode(&example_voice_path(), &ogg, &["-c:a", "libvorbis"]);
    let once = std::fs::read(&ogg).expect("ogg");
    let chained = dir.path().join("chained.ogg");
    std::fs::write(&chained, [once.clone(), once].concat()).expect("write");
    let out = dir.path().join("out");
    assert_ok(&render(&chained, &out, &["--no-plot", "--bvh", "--midi"]));
    let (one_s, both_s) = (duration_s(&ogg), duration_s(&out.join("chained.flac")));
    assert!(
        (both_s - 2.0 * one_s).abs() < 0.05,
        "{both_s} s of 2 × {one_s} s"
    );
    // The side outputs run as long (the BVH's header counts the frames of the audio decoded).
    let (frames, frame_s) = support::bvh_timing(&out.join("chained.bvh"));
    let bvh_s = frames as f64 * frame_s;
    assert!((bvh_s - both_s).abs() < 0.05, "BVH {bvh_s} s of {both_s} s");
    let csv = std::fs::read_to_string(out.join("chained.controls.csv")).expect("controls");
    let last = csv.lines().last().and_then(|l| l.split(',').next());
    let csv_s: f64 = last.and_then(|t| t.parse().ok()).expect("a time");
    assert!(
        (csv_s - both_s).abs() < 0.05,
        "controls {csv_s} s of {both_s} s"
    );
    if let Some(python) =
        support::python_tools("a_chained_ogg_file_renders_every_stream_in_every_output")
    {
        let (_, ccs) = support::read_midi(&python, &out.join("chained.mid"));
        let midi_s = ccs.last().map_or(0.0, |c| c.0);
        assert!(midi_s > both_s - 1.0, "MIDI to {midi_s} s of {both_s} s");
    }
}

#[test]
fn a_chained_ogg_with_an_opus_stream_is_refused_as_opus_not_as_damaged() {
    if !have_ffmpeg("a_chained_ogg_with_an_opus_stream_is_refused_as_opus_not_as_damaged") {
        return;
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let (vorbis, opus) = (dir.path().join("a.ogg"), dir.path().join("b.opus"));
    ffmpeg_encode(&example_voice_path(), &vorbis, &["-c:a", "libvorbis"]);
    ffmpeg_encode(&example_voice_path(), &opus, &["-c:a", "libopus"]);
    let bytes = [
        std::fs::read(&vorbis).expect("ogg"),
        std::fs::read(&opus).expect("opus"),
    ]
    .concat();
    let chained = dir.path().join("chained.ogg");
    std::fs::write(&chained, &bytes).expect("write");
    // Before, the Vorbis stream was decoded and the file called damaged at the Opus one.
    let out = dir.path().join("out");
    let piped = dir.path().join("piped");
    let from_pipe = [
        "render",
        "-",
        "-o",
        piped.to_str().unwrap(),
        "-q",
        "--no-plot",
    ];
    for (o, which) in [
        (render(&chained, &out, &["--no-plot"]), "its stream 2"),
        (
            support::pneuma_with_stdin(&from_pipe, &bytes),
            "a later stream",
        ),
    ] {
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{err}");
        for m in ["Ogg Opus", which, "is not supported", "ffmpeg -i PART.opus"] {
            assert!(err.contains(m), "`{m}` not in: {err}");
        }
        assert!(!err.contains("damaged"), "{err}");
    }
    assert!(!out.join("chained.flac").exists(), "no audio written");
}

/// A RIFF chunk: id, size, body and its pad byte.
fn chunk(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
    let mut c = [&id[..], &(body.len() as u32).to_le_bytes(), body].concat();
    if body.len() % 2 == 1 {
        c.push(0);
    }
    c
}

/// A 16 kHz 16-bit mono WAV file of `chunks` after its `fmt ` chunk.
fn wav_bytes(chunks: &[Vec<u8>]) -> Vec<u8> {
    let fmt: Vec<u8> = [1u16, 1]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .chain(16_000u32.to_le_bytes())
        .chain(32_000u32.to_le_bytes())
        .chain([2u16, 16].iter().flat_map(|v| v.to_le_bytes()))
        .collect();
    let body = [b"WAVE".to_vec(), chunk(b"fmt ", &fmt), chunks.concat()].concat();
    [&b"RIFF"[..], &(body.len() as u32).to_le_bytes(), &body].concat()
}

#[test]
fn a_piped_wav_with_audio_past_its_data_chunk_is_refused_rather_than_cut() {
    // 4 s of speech-like audio, 64 000 16-bit samples; `half` bytes hold the first 2 s.
    let pcm: Vec<u8> = support::two_phrases()
        .iter()
        .flat_map(|&v| ((v * 32767.0).round() as i16).to_le_bytes())
        .collect();
    let half = pcm.len() / 2;
    let list = chunk(b"LIST", &[&b"INFO"[..], &chunk(b"INAM", b"ep\0")].concat());
    let two = "standard input holds 2 data chunks; Pneuma reads one";
    let (first, second) = (chunk(b"data", &pcm[..half]), chunk(b"data", &pcm[half..]));
    // A header announcing 1 s before all 4 s (a recorder stopped before it updated it), in
    // the first phrase: what follows is not silence, which would pass for zero padding.
    let short_head = [&b"data"[..], &(half as u32 / 2).to_le_bytes(), &pcm].concat();
    let refused: [(Vec<u8>, &[&str]); 3] = [
        (wav_bytes(&[first.clone(), second.clone()]), &[two]),
        // Another chunk between the two.
        (wav_bytes(&[first, list.clone(), second]), &[two]),
        (
            wav_bytes(&[short_head]),
            &[
                "standard input: its data chunk announces 1.0 s, yet more audio follows it",
                "put `sox --ignore-length -t wav - -t wav -` in the pipe",
            ],
        ),
    ];
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("out");
    let out_s = out.to_str().unwrap();
    for (bytes, wants) in &refused {
        for args in [
            &["render", "-", "-o", out_s, "-q", "--no-plot"][..],
            // The audio has gone to standard output: the exit status says it failed.
            &["render", "-", "-o", "-", "-q"],
            &["analyze", "-", "-o", out_s],
        ] {
            let o = support::pneuma_with_stdin(args, bytes);
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(!o.status.success(), "{args:?}: {err}");
            for want in *wants {
                assert!(err.contains(want), "{args:?}: {err}");
            }
            assert!(!has_files(&out) && !out.is_file(), "{args:?} wrote {out_s}");
        }
    }
    // Whole, with a chunk or zero padding after the data: rendered whole from the pipe.
    for after in [list, vec![0; 64]] {
        let bytes = wav_bytes(&[chunk(b"data", &pcm), after]);
        let args = ["render", "-", "-o", out_s, "-q", "--no-plot"];
        assert_ok(&support::pneuma_with_stdin(&args, &bytes));
        let rendered_s = duration_s(&out.join("stdin.wav"));
        assert!((rendered_s - 4.0).abs() < 1e-3, "{rendered_s} s of 4 s");
    }
}

/// The `Frames:` count, frame time and motion lines of the BVH at `path`.
fn bvh_frames(path: &Path) -> (u64, f64, usize) {
    let (count, frame_s) = support::bvh_timing(path);
    let text = std::fs::read_to_string(path).expect("the BVH");
    let motion = text.split_once("Frame Time:").expect("a MOTION section").1;
    (count, frame_s, motion.lines().skip(1).count())
}

#[test]
fn a_bvh_runs_as_long_as_the_audio_decoded_whatever_the_header_announced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("half.flac");
    std::fs::write(&input, half_announced_flac(dir.path())).expect("write");
    // The same audio from a pipe, as a WAV of unknown length (as ffmpeg writes one there).
    let pcm: Vec<u8> = support::read_audio(&example_voice_path())
        .0
        .iter()
        .flat_map(|&v| ((v * 32767.0).round() as i16).to_le_bytes())
        .collect();
    let streamed = [
        &b"RIFF"[..],
        &[0xff; 4],
        b"WAVE",
        &chunk_fmt_of_voice(),
        b"data",
        &[0xff; 4],
    ];
    let streamed = [streamed.concat(), pcm].concat();
    for fps in ["120", "24", "1000"] {
        let out = dir.path().join(format!("out{fps}"));
        assert_ok(&render(&input, &out, &["--no-plot", "--bvh-fps", fps]));
        assert_bvh_as_long(&out.join("half.flac"), &out.join("half.bvh"));
        // Before, refused: "--bvh needs the input's length before the render".
        let piped = dir.path().join(format!("piped{fps}"));
        let piped_s = piped.to_str().unwrap();
        let args = [
            "render",
            "-",
            "-o",
            piped_s,
            "-q",
            "--no-plot",
            "--bvh-fps",
            fps,
        ];
        assert_ok(&support::pneuma_with_stdin(&args, &streamed));
        assert_bvh_as_long(&piped.join("stdin.wav"), &piped.join("stdin.bvh"));
    }
}

/// The example voice as a FLAC (rendered into `dir`) whose STREAMINFO announces half its
/// samples (36 bits at bytes 21.5..26); its STREAMINFO block ends at byte 42.
fn half_announced_flac(dir: &Path) -> Vec<u8> {
    let flac_dir = dir.join("flac");
    let args = ["--format", "flac", "--no-plot"];
    assert_ok(&render(&example_voice_path(), &flac_dir, &args));
    let mut flac = std::fs::read(flac_dir.join("voice.flac")).expect("flac");
    assert_eq!(&flac[..4], b"fLaC");
    let field = u64::from_be_bytes(flac[18..26].try_into().unwrap());
    let total = field & ((1 << 36) - 1);
    let half = (field & !((1 << 36) - 1)) | (total / 2);
    flac[18..26].copy_from_slice(&half.to_be_bytes());
    flac
}

/// A FLAC CUESHEET metadata block (not the last) of tracks starting at `starts` (sample
/// frames), without index points: symphonia reads each track as a chapter.
fn cuesheet_block(starts: &[u64]) -> Vec<u8> {
    // Catalog number, lead-in, CD-DA flag and reserved bytes, all zero.
    let mut body = vec![0u8; 128 + 8 + 1 + 258];
    body.push(starts.len() as u8);
    for (i, &at) in starts.iter().enumerate() {
        body.extend_from_slice(&at.to_be_bytes());
        body.push(i as u8 + 1);
        body.extend_from_slice(&[0u8; 12 + 14]); // ISRC, flags and reserved
        body.push(0); // index points
    }
    [&[5u8][..], &(body.len() as u32).to_be_bytes()[1..], &body].concat()
}

/// The end times (ms) of the `CHAP` frames of the ID3v2.3 tag that starts `mp3`.
fn id3_chapter_ends_ms(mp3: &[u8]) -> Vec<u32> {
    assert_eq!(&mp3[..4], b"ID3\x03", "an ID3v2.3 tag first");
    let size = mp3[6..10]
        .iter()
        .fold(0usize, |n, &b| n << 7 | usize::from(b));
    let tag = &mp3[10..10 + size];
    let mut ends = Vec::new();
    let mut at = 0;
    while at + 10 <= tag.len() && tag[at] != 0 {
        let len = u32::from_be_bytes(tag[at + 4..at + 8].try_into().unwrap()) as usize;
        let body = &tag[at + 10..at + 10 + len];
        if &tag[at..at + 4] == b"CHAP" {
            // The element id (ended by a zero byte), then the start and end times.
            let id = body.iter().position(|&b| b == 0).expect("element id") + 1;
            ends.push(u32::from_be_bytes(body[id + 4..id + 8].try_into().unwrap()));
        }
        at += 10 + len;
    }
    ends
}

#[test]
fn an_mp3s_last_chapter_ends_with_the_audio_written_whatever_the_header_announced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let flac = half_announced_flac(dir.path());
    let (samples, rate_hz, channels) = read_audio(&example_voice_path());
    // Chapters at 0 and 1 s, in a CUESHEET block after the STREAMINFO.
    let cues = cuesheet_block(&[0, u64::from(rate_hz)]);
    let input = dir.path().join("chapters.flac");
    std::fs::write(&input, [&flac[..42], &cues, &flac[42..]].concat()).expect("write");
    let out = dir.path().join("out");
    assert_ok(&render(&input, &out, &["--no-plot", "--format", "mp3"]));
    let mp3 = std::fs::read(out.join("chapters.mp3")).expect("mp3");
    let frames = samples.len() as f64 / f64::from(channels);
    let voice_ms = (frames * 1000.0 / f64::from(rate_hz)).round() as u32;
    // Before, the last chapter ended at the announced half.
    assert_eq!(id3_chapter_ends_ms(&mp3), [1000, voice_ms]);
    let written_s = duration_s(&out.join("chapters.mp3"));
    assert!(
        (written_s * 1000.0 - f64::from(voice_ms)).abs() <= 1.0,
        "{written_s} s"
    );
}

/// The BVH at `bvh` has as many motion lines as its header counts, and lasts as long as the
/// `audio` to within a frame of each.
fn assert_bvh_as_long(audio: &Path, bvh: &Path) {
    let audio_s = duration_s(audio);
    let (count, frame_s, lines) = bvh_frames(bvh);
    let name = bvh.display();
    assert_eq!(count as usize, lines, "{name}: header and motion differ");
    let bvh_s = count as f64 * frame_s;
    assert!(
        (bvh_s - audio_s).abs() <= frame_s + 1.0 / 120.0,
        "{name}: BVH {bvh_s} s of {audio_s} s"
    );
}

/// The `fmt ` chunk of the example voice (16-bit mono at its rate).
fn chunk_fmt_of_voice() -> Vec<u8> {
    let (_, rate_hz, channels) = support::read_audio(&example_voice_path());
    assert_eq!(channels, 1, "the example voice is mono");
    let fmt = [
        &1u16.to_le_bytes()[..],
        &1u16.to_le_bytes(),
        &rate_hz.to_le_bytes(),
    ];
    let rest = [
        &(2 * rate_hz).to_le_bytes()[..],
        &2u16.to_le_bytes(),
        &16u16.to_le_bytes(),
    ];
    chunk(b"fmt ", &[fmt.concat(), rest.concat()].concat())
}

/// A 10-minute 16 kHz WAV at `path`: long enough for a debug render to be stopped midway.
fn write_long_wav(path: &Path) {
    let tone: Vec<f32> = (0..16_000 * 600)
        .map(|i| 0.1 * (i as f32 * 0.05).sin())
        .collect();
    support::write_wav(path, (16_000, 1, 16, false), &tone, 1.0);
}

/// Whether `dir` exists and holds a file (a render's hidden partial file, once it writes).
fn has_files(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_some())
}

#[test]
fn sigterm_and_sighup_stop_a_render_leaving_nothing() {
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("long.wav");
    write_long_wav(&input);
    for signal in ["TERM", "HUP"] {
        let out = dir.path().join(format!("new_{signal}"));
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pneuma"))
            .args([
                "render",
                input.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "-q",
            ])
            .spawn()
            .expect("pneuma starts");
        let started = std::time::Instant::now();
        while !has_files(&out) && started.elapsed().as_secs() < 60 {
            std::thread::sleep(std::time::Duration::from_millis(50));
        }
        assert!(
            has_files(&out),
            "SIG{signal}: the render never started writing"
        );
        let kill = std::process::Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .expect("kill runs");
        assert!(kill.success());
        let status = child.wait().expect("pneuma ends");
        assert_eq!(status.code(), Some(130), "SIG{signal}: {status}");
        assert!(
            !out.exists(),
            "SIG{signal}: the folder the render made stays"
        );
    }
}

#[test]
fn analyze_refuses_to_write_its_csv_over_an_audio_file() {
    let dir = tempfile::tempdir().expect("temp dir");
    let take1 = dir.path().join("take1.wav");
    std::fs::copy(example_voice_path(), &take1).expect("copy");
    for name in ["take2.wav", "take2.FLAC", "take2.mp3", "take2.opus"] {
        let take2 = dir.path().join(name);
        std::fs::write(&take2, b"a recording").expect("write");
        let o = pneuma(&[
            "analyze",
            take1.to_str().unwrap(),
            "-o",
            take2.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "-o {name}: {err}");
        assert!(err.contains("give a .csv name"), "{err}");
        assert!(err.contains("take2.csv"), "{err}");
        assert_eq!(std::fs::read(&take2).expect("kept"), b"a recording");
    }
}

#[test]
fn an_input_named_like_a_side_output_is_never_replaced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let voice = std::fs::read(example_voice_path()).expect("voice");
    for (name, extra) in [
        ("take.png", &[][..]),
        ("t.bvh", &["--bvh"]),
        ("t.mid", &["--midi"]),
    ] {
        let input = dir.path().join(name);
        std::fs::write(&input, &voice).expect("write");
        let o = render(&input, dir.path(), extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{name}: {err}");
        assert!(err.contains("it is the input file"), "{name}: {err}");
        assert!(
            std::fs::read(&input).expect("input") == voice,
            "{name} was replaced"
        );
    }
}

#[test]
fn a_missing_channel_is_named_as_it_was_typed() {
    let dir = tempfile::tempdir().expect("temp dir");
    for typed in ["2", "right"] {
        let o = render(&example_voice_path(), dir.path(), &["--channel", typed]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{err}");
        assert!(
            err.contains(&format!("--channel {typed} needs 2 channels")),
            "{err}"
        );
    }
}

#[test]
fn samples_that_are_not_numbers_are_said_and_never_called_zero() {
    let dir = tempfile::tempdir().expect("temp dir");
    let all_nan = dir.path().join("allnan.wav");
    support::write_wav(&all_nan, (16_000, 1, 32, true), &[f32::NAN; 16_000], 1.0);
    let o = support::render_saying(&all_nan, &dir.path().join("out"), &[]);
    assert_ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("16000 samples are not numbers"), "{err}");
    assert!(err.contains("written as 0"), "{err}");
    assert!(!err.contains("every sample is zero"), "{err}");
}

/// A file of `len_bytes` zero bytes at `path`, sparse where the file system allows.
fn zero_file(path: &Path, len_bytes: u64) {
    std::fs::File::create(path)
        .and_then(|f| f.set_len(len_bytes))
        .expect("zero file");
}

#[test]
fn a_model_or_text_file_past_its_size_limit_is_refused_by_name() {
    const MIB: u64 = 1024 * 1024;
    let dir = tempfile::tempdir().expect("temp dir");
    let (model, text) = (dir.path().join("big.json"), dir.path().join("big.txt"));
    zero_file(&model, 16 * MIB + 1);
    zero_file(&text, 16 * MIB + 1);
    let data = dir.path().join("data");
    std::fs::create_dir(&data).expect("data folder");
    std::fs::copy(example_voice_path(), data.join("clip.wav")).expect("copy");
    zero_file(&data.join("clip.head.csv"), 256 * MIB + 1);
    let voice = example_voice_path();
    let out = dir.path().join("out");
    let (voice, out_s) = (voice.to_str().unwrap(), out.to_str().unwrap());
    let cases: [(&[&str], String); 3] = [
        (
            &[
                "render",
                voice,
                "-o",
                out_s,
                "--head-model",
                model.to_str().unwrap(),
            ],
            format!(
                "--head-model: {} is larger than 16 MiB, the limit for a head-pose model (JSON, \
                 as `pneuma train` writes)",
                model.display()
            ),
        ),
        (
            &["speak", "--text-file", text.to_str().unwrap(), "-o", out_s],
            format!(
                "--text-file: {} is larger than 16 MiB, the limit for a text to speak",
                text.display()
            ),
        ),
        (
            &["train", "--data", data.to_str().unwrap(), "-o", out_s],
            "clip.head.csv is larger than 256 MiB, the limit for a head-motion CSV".into(),
        ),
    ];
    for (args, want) in cases {
        let o = pneuma(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}: {err}");
        assert!(err.contains(&want), "{args:?}: {err}");
    }
    assert!(!out.exists(), "a refused run wrote {}", out.display());
}

#[test]
fn an_evaluation_labels_file_past_its_size_limit_is_refused_by_name() {
    const MIB: u64 = 1024 * 1024;
    let dir = tempfile::tempdir().expect("temp dir");
    let labels = dir.path().join("labels.csv");
    zero_file(&labels, 64 * MIB + 1);
    let data = dir.path().join("data");
    std::fs::create_dir(&data).expect("data folder");
    let (labels_s, data_s) = (labels.to_str().unwrap(), data.to_str().unwrap());
    let want = format!(
        "{labels_s} is larger than 64 MiB, the limit for a breath labels file \
         (clip,start_s,end_s,kind): is it the right file?"
    );
    for what in ["breath-sounds", "restore"] {
        let args = ["eval", what, "--labels", labels_s, "--data", data_s];
        let o = pneuma(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}: {err}");
        assert!(err.contains(&want), "{args:?}: {err}");
    }
}

#[cfg(unix)]
#[test]
fn an_endless_head_model_is_refused_without_filling_memory() {
    let dir = tempfile::tempdir().expect("temp dir");
    let voice = example_voice_path();
    let out = dir.path().join("out");
    // 4 GB of address space: ample for a render, and without the cap the read of /dev/zero
    // fails here instead of taking the machine's memory.
    let o = std::process::Command::new("sh")
        .args(["-c", "ulimit -v 4000000 && exec \"$0\" \"$@\""])
        .arg(env!("CARGO_BIN_EXE_pneuma"))
        .args([
            "render",
            voice.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .args(["--head-model", "/dev/zero"])
        .output()
        .expect("sh runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--head-model: /dev/zero is larger than 16 MiB"),
        "{err}"
    );
}

#[test]
fn a_value_just_past_a_range_end_is_refused_as_typed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let voice = example_voice_path();
    let out = dir.path().join("out");
    let (voice, out_s) = (voice.to_str().unwrap(), out.to_str().unwrap());
    // Each is the range's end once narrowed to an f32, as the options were parsed before.
    let cases: [(&[&str], &str); 3] = [
        (
            &["render", voice, "-o", out_s, "--breath-level-db=-5.9999999"],
            "--breath-level-db -5.9999999 dB is out of range: use -40 to -6 dB",
        ),
        (
            &[
                "render",
                voice,
                "-o",
                out_s,
                "--breath-level-db=-40.0000001",
            ],
            "--breath-level-db -40.0000001 dB is out of range: use -40 to -6 dB",
        ),
        (
            &["speak", "Hi.", "-o", out_s, "--rate", "2.0000001"],
            "--rate 2.0000001 is out of range: use 0.5 to 2",
        ),
    ];
    for (args, want) in cases {
        let o = pneuma(args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    assert!(!out.exists(), "a refused run wrote {}", out.display());
}
