//! What a render keeps of what the user already had: a WAV's cue points (a DAW's chapter and ad
//! markers) and `LIST`/`INFO` tags, its `fmt ` form (channel mask, plain float), the breath
//! markers of a batch's file that cannot hold cue points, and a warning for an audio file of
//! another render beside the outputs.

use std::path::Path;

use crate::podcast::{flac_comments, riff_chunks, u32_at};
use crate::support::{assert_ok, render, render_saying};
use pneuma_testkit::voice::example_voice_path;

/// A RIFF chunk with its pad byte.
fn chunk(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
    let mut out = id.to_vec();
    out.extend_from_slice(&(body.len() as u32).to_le_bytes());
    out.extend_from_slice(body);
    if body.len() % 2 == 1 {
        out.push(0);
    }
    out
}

/// A WAV file of `chunks` (each id and body), with its RIFF size.
fn wav_of(chunks: &[([u8; 4], Vec<u8>)]) -> Vec<u8> {
    let mut body = b"WAVE".to_vec();
    for (id, b) in chunks {
        body.extend(chunk(id, b));
    }
    let mut out = b"RIFF".to_vec();
    out.extend_from_slice(&(body.len() as u32).to_le_bytes());
    out.extend(body);
    out
}

/// A `LIST` body of `kind` with NUL-terminated texts under their ids.
fn list(kind: &[u8; 4], items: &[(&[u8; 4], Vec<u8>)]) -> Vec<u8> {
    let mut out = kind.to_vec();
    for (id, b) in items {
        out.extend(chunk(id, b));
    }
    out
}

/// `id` then `text` and a NUL (an `adtl` label).
fn labl(id: u32, text: &str) -> Vec<u8> {
    let mut b = id.to_le_bytes().to_vec();
    b.extend_from_slice(text.as_bytes());
    b.push(0);
    b
}

/// The example voice with INFO tags before its data and two cue points (a chapter marker and
/// an ad region with its length) after it, as ffmpeg and a DAW write them.
fn tagged_voice_with_cues(path: &Path) {
    let voice = std::fs::read(example_voice_path()).expect("voice");
    let chunks = riff_chunks(&voice);
    let fmt = chunks
        .iter()
        .find(|c| &c.0 == b"fmt ")
        .expect("fmt")
        .1
        .clone();
    let data = chunks
        .iter()
        .find(|c| &c.0 == b"data")
        .expect("data")
        .1
        .clone();
    let info = list(
        b"INFO",
        &[(b"INAM", b"Ep 1\0".to_vec()), (b"IART", b"Host\0".to_vec())],
    );
    let mut cue = 2u32.to_le_bytes().to_vec();
    for (id, frame) in [(1u32, 16_000u32), (2, 160_000)] {
        for v in [id, frame] {
            cue.extend_from_slice(&v.to_le_bytes());
        }
        cue.extend_from_slice(b"data");
        cue.extend_from_slice(&[0u8; 8]);
        cue.extend_from_slice(&frame.to_le_bytes());
    }
    let mut ltxt = 2u32.to_le_bytes().to_vec();
    ltxt.extend_from_slice(&32_000u32.to_le_bytes());
    ltxt.extend_from_slice(b"rgn ");
    ltxt.extend_from_slice(&[0u8; 8]);
    let adtl = list(
        b"adtl",
        &[
            (b"labl", labl(1, "Chapter 1")),
            (b"labl", labl(2, "Ad break")),
            (b"ltxt", ltxt),
        ],
    );
    let bytes = wav_of(&[
        (*b"fmt ", fmt),
        (*b"LIST", info),
        (*b"data", data),
        (*b"cue ", cue),
        (*b"LIST", adtl),
    ]);
    std::fs::write(path, bytes).expect("write");
}

/// The cue points of a WAV file: (frame, length, label), in the file's order.
fn cue_points(path: &Path) -> Vec<(u32, u32, String)> {
    let chunks = riff_chunks(&std::fs::read(path).expect("wav"));
    let Some(cue) = chunks.iter().find(|c| &c.0 == b"cue ") else {
        return Vec::new();
    };
    let adtl = (chunks.iter())
        .find(|c| &c.0 == b"LIST" && &c.1[..4] == b"adtl")
        .expect("adtl");
    let mut labels = std::collections::HashMap::new();
    let mut lengths = std::collections::HashMap::new();
    let mut at = 4;
    while at + 8 <= adtl.1.len() {
        let size = u32_at(&adtl.1, at + 4) as usize;
        let body = &adtl.1[at + 8..at + 8 + size];
        let id = u32_at(body, 0);
        match &adtl.1[at..at + 4] {
            b"labl" => {
                let text = String::from_utf8_lossy(&body[4..body.len() - 1]).into_owned();
                labels.insert(id, text);
            }
            _ => {
                lengths.insert(id, u32_at(body, 4));
            }
        }
        at += 8 + size + size % 2;
    }
    (0..u32_at(&cue.1, 0) as usize)
        .map(|i| {
            let p = &cue.1[4 + 24 * i..];
            let id = u32_at(p, 0);
            (
                u32_at(p, 20),
                lengths.get(&id).copied().unwrap_or(0),
                labels.get(&id).cloned().unwrap_or_default(),
            )
        })
        .collect()
}

/// The `LIST`/`INFO` texts of a WAV file: (id, text).
fn info_tags(path: &Path) -> Vec<(String, String)> {
    let chunks = riff_chunks(&std::fs::read(path).expect("wav"));
    let Some(info) = (chunks.iter()).find(|c| &c.0 == b"LIST" && &c.1[..4] == b"INFO") else {
        return Vec::new();
    };
    let mut out = Vec::new();
    let mut at = 4;
    while at + 8 <= info.1.len() {
        let size = u32_at(&info.1, at + 4) as usize;
        let text = &info.1[at + 8..at + 8 + size];
        let end = text.iter().position(|&b| b == 0).unwrap_or(text.len());
        out.push((
            String::from_utf8_lossy(&info.1[at..at + 4]).into_owned(),
            String::from_utf8_lossy(&text[..end]).into_owned(),
        ));
        at += 8 + size + size % 2;
    }
    out
}

#[test]
fn a_wavs_cue_points_and_info_tags_carry_over_and_merge_with_the_breath_cues() {
    let dir = tempfile::tempdir().expect("temp");
    let input = dir.path().join("marked.wav");
    tagged_voice_with_cues(&input);
    let out = dir.path().join("out");

    // WAV: the DAW's markers at their frames with their labels and lengths, the tags.
    assert_ok(&render(&input, &out, &["--no-plot"]));
    let wav = out.join("marked.wav");
    let theirs = [
        (16_000, 0, "Chapter 1".to_string()),
        (160_000, 32_000, "Ad break".to_string()),
    ];
    assert_eq!(cue_points(&wav), theirs);
    let tags = info_tags(&wav);
    assert!(tags.contains(&("INAM".into(), "Ep 1".into())), "{tags:?}");
    assert!(tags.contains(&("IART".into(), "Host".into())), "{tags:?}");

    // With --markers cue: theirs and the breaths', in time order.
    assert_ok(&render(&input, &out, &["--no-plot", "--markers", "cue"]));
    let all = cue_points(&wav);
    let breaths = all.iter().filter(|c| c.2.starts_with("breath ")).count();
    assert!(breaths >= 3, "{all:?}");
    assert_eq!(all.len(), breaths + 2, "{all:?}");
    assert!(theirs.iter().all(|c| all.contains(c)), "{all:?}");
    assert!(all.windows(2).all(|w| w[0].0 <= w[1].0), "{all:?}");

    // FLAC: the tags as Vorbis comments; the cue points cannot go in, and the summary says so.
    let o = render_saying(&input, &out, &["--format", "flac"]);
    assert_ok(&o);
    let comments = flac_comments(&out.join("marked.flac"));
    assert!(comments.contains(&"TITLE=Ep 1".to_string()), "{comments:?}");
    assert!(
        comments.contains(&"ARTIST=Host".to_string()),
        "{comments:?}"
    );
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(
        said.contains("warning: the input's 2 cue points are not carried: FLAC holds none"),
        "{said}"
    );

    // Standard output carries the samples alone, and the summary says what was left.
    let o = render_saying(&input, Path::new("-"), &[]);
    assert_ok(&o);
    assert_eq!(&o.stdout[..4], b"RIFF");
    let said = String::from_utf8_lossy(&o.stderr);
    for left in [
        "the input's 2 cue points are not carried: standard output holds none",
        "the input's tags are not carried: standard output holds none",
    ] {
        assert!(said.contains(left), "{said}");
    }
}

/// The `fmt ` body of a WAV file.
fn fmt_of(path: &Path) -> Vec<u8> {
    let chunks = riff_chunks(&std::fs::read(path).expect("wav"));
    chunks.into_iter().find(|c| &c.0 == b"fmt ").expect("fmt").1
}

/// A 16 kHz stereo `WAVE_FORMAT_EXTENSIBLE` fmt chunk of `bits` per sample, front left and
/// right (mask 0x3), subformat `format` (1 PCM, 3 IEEE float).
fn stereo_extensible_fmt(bits: u16, format: u8) -> Vec<u8> {
    let block = 2 * bits / 8;
    let mut ext = Vec::new();
    for v in [0xfffeu16, 2] {
        ext.extend_from_slice(&v.to_le_bytes());
    }
    for v in [16_000u32, 16_000 * u32::from(block)] {
        ext.extend_from_slice(&v.to_le_bytes());
    }
    for v in [block, bits, 22, bits] {
        ext.extend_from_slice(&v.to_le_bytes());
    }
    ext.extend_from_slice(&3u32.to_le_bytes());
    ext.extend_from_slice(&[
        format, 0, 0, 0, 0, 0, 0x10, 0, 0x80, 0, 0, 0xaa, 0, 0x38, 0x9b, 0x71,
    ]);
    ext
}

/// `pcm` as float in `channels` identical channels, written with the fmt chunk `fmt` to
/// `<name>.wav` in `dir` and rendered into `dir/out`: the output, its fmt chunk and the frames
/// its `fact` chunk counts.
fn rendered_float(
    dir: &std::path::Path,
    name: &str,
    fmt: Vec<u8>,
    channels: usize,
    pcm: &[i16],
) -> (std::path::PathBuf, Vec<u8>, usize) {
    let float: Vec<u8> = (pcm.iter())
        .flat_map(|&v| (f32::from(v) / 32_768.0).to_le_bytes().repeat(channels))
        .collect();
    let input = dir.join(format!("{name}.wav"));
    std::fs::write(&input, wav_of(&[(*b"fmt ", fmt), (*b"data", float)])).expect("write");
    let out = dir.join("out");
    assert_ok(&render(&input, &out, &["--no-plot"]));
    let wav = out.join(format!("{name}.wav"));
    let chunks = riff_chunks(&std::fs::read(&wav).expect("wav"));
    let fact = chunks.iter().find(|c| &c.0 == b"fact").expect("fact");
    let frames = u32_at(&fact.1, 0) as usize;
    (wav.clone(), fmt_of(&wav), frames)
}

#[test]
fn a_wav_keeps_its_channel_mask_and_its_plain_float_header() {
    let dir = tempfile::tempdir().expect("temp");
    let voice = std::fs::read(example_voice_path()).expect("voice");
    let data = riff_chunks(&voice)
        .into_iter()
        .find(|c| &c.0 == b"data")
        .expect("data")
        .1;
    let pcm: Vec<i16> = (data.chunks_exact(2))
        .map(|b| i16::from_le_bytes([b[0], b[1]]))
        .collect();

    // Stereo 16-bit WAVE_FORMAT_EXTENSIBLE with the front left and right mask (0x3).
    let ext = stereo_extensible_fmt(16, 1);
    let stereo: Vec<u8> = pcm
        .iter()
        .flat_map(|v| [v.to_le_bytes(), v.to_le_bytes()].concat())
        .collect();
    let input = dir.path().join("stereo.wav");
    std::fs::write(&input, wav_of(&[(*b"fmt ", ext), (*b"data", stereo)])).expect("write");
    let out = dir.path().join("out");
    assert_ok(&render(&input, &out, &["--no-plot"]));
    let fmt = fmt_of(&out.join("stereo.wav"));
    assert_eq!(u16::from_le_bytes([fmt[0], fmt[1]]), 0xfffe);
    assert_eq!(u32_at(&fmt, 20), 3, "channel mask");

    // Mono float, plain WAVEFORMAT (format tag 3, 16 bytes): plain tag 3 again, with its
    // cbSize and a `fact` chunk, which readers such as sox take without a warning.
    let mut plain = Vec::new();
    for v in [3u16, 1] {
        plain.extend_from_slice(&v.to_le_bytes());
    }
    for v in [16_000u32, 64_000] {
        plain.extend_from_slice(&v.to_le_bytes());
    }
    for v in [4u16, 32] {
        plain.extend_from_slice(&v.to_le_bytes());
    }
    let (wav, fmt, fact_frames) = rendered_float(dir.path(), "float", plain, 1, &pcm);
    assert_eq!(fmt.len(), 18, "WAVEFORMATEX with its cbSize");
    assert_eq!(u16::from_le_bytes([fmt[0], fmt[1]]), 3, "plain float tag");
    assert_eq!(fact_frames, pcm.len(), "fact: sample frames");
    if crate::support::tool_or_skip("sox", "--version", "plain float WAV through sox") {
        let o = std::process::Command::new("sox")
            .args([wav.to_str().expect("utf-8"), "-n", "stat"])
            .output()
            .expect("sox");
        let said = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success() && !said.contains("WARN"), "{said}");
    }

    // Stereo float in WAVE_FORMAT_EXTENSIBLE: kept so, with a `fact` chunk too (non-PCM data).
    let ext = stereo_extensible_fmt(32, 3);
    let (_, fmt, fact_frames) = rendered_float(dir.path(), "float_ext", ext, 2, &pcm);
    let tag = u16::from_le_bytes([fmt[0], fmt[1]]);
    assert_eq!(tag, 0xfffe, "extensible kept");
    assert_eq!(fact_frames, pcm.len(), "fact: sample frames");
}

#[test]
fn a_batch_with_cue_markers_gives_a_flac_file_label_tracks_and_finishes() {
    let dir = tempfile::tempdir().expect("temp");
    let eps = dir.path().join("eps");
    std::fs::create_dir(&eps).expect("dir");
    std::fs::copy(example_voice_path(), eps.join("ep1.wav")).expect("copy");
    // A FLAC episode: the voice as it is (written by pneuma itself: no encoder needed).
    let flac_dir = dir.path().join("flac");
    assert_ok(&render(
        &example_voice_path(),
        &flac_dir,
        &["--no-plot", "--no-breaths", "--format", "flac"],
    ));
    std::fs::copy(flac_dir.join("voice.flac"), eps.join("ep2.flac")).expect("copy");
    let out = dir.path().join("out");
    let o = render_saying(&eps, &out, &["--markers", "cue"]);
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{said}");
    assert!(said.contains("2 rendered, 0 failed"), "{said}");
    assert!(
        said.contains(
            "ep2.flac: FLAC holds no cue points: the breath markers are in ep2.breaths.txt"
        ),
        "{said}"
    );
    let labels = std::fs::read_to_string(out.join("ep2.breaths.txt")).expect("labels");
    assert!(labels.lines().count() >= 3, "{labels}");
    assert!(
        !out.join("ep1.breaths.txt").exists(),
        "the WAV has its cue points"
    );
    assert!(cue_points(&out.join("ep1.wav")).len() >= 3);
}

#[test]
fn an_audio_file_of_another_render_beside_the_outputs_is_named() {
    let dir = tempfile::tempdir().expect("temp");
    let out = dir.path().join("out");
    assert_ok(&render(&example_voice_path(), &out, &["--no-plot"]));
    let flac_dir = dir.path().join("flac");
    assert_ok(&render(
        &example_voice_path(),
        &flac_dir,
        &["--no-plot", "--format", "flac"],
    ));
    let o = render_saying(&flac_dir.join("voice.flac"), &out, &[]);
    assert_ok(&o);
    let said = String::from_utf8_lossy(&o.stderr);
    let old = out.join("voice.wav");
    assert!(old.exists(), "another format's audio stays");
    assert!(
        said.contains(&format!(
            "warning: {} stays beside this render's",
            old.display()
        )),
        "{said}"
    );
}
