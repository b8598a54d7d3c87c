//! WAV input through Pneuma's own RIFF/WAVE reader: the files users have (odd-length metadata
//! chunks, `fact`, WAVE_FORMAT_EXTENSIBLE with fewer valid bits than the container, streamed
//! sizes, RF64) are read with exact sample values, and every file that cannot be read fails with
//! its specific reason. The headers are written byte by byte here, independent of any WAV writer.

use std::path::{Path, PathBuf};

use pneuma_cli::wav::{WavError, WavInfo, WavSource};
use pneuma_testkit::signals::{self, GlottalVowel, Vowel};

use crate::support;
use support::{assert_analyze_fails, pneuma};

const PCM: u16 = 0x0001;
const FLOAT: u16 = 0x0003;
const IMA_ADPCM: u16 = 0x0011;
const MP3: u16 = 0x0055;

// ---- byte-by-byte WAV construction ----

/// A chunk announcing `size` bytes followed by `body` as given (no pad byte).
fn raw_chunk(id: &[u8; 4], size: u32, body: &[u8]) -> Vec<u8> {
    let mut c = id.to_vec();
    c.extend_from_slice(&size.to_le_bytes());
    c.extend_from_slice(body);
    c
}

/// A well-formed chunk: the body's length and the pad byte after an odd body.
fn chunk(id: &[u8; 4], body: &[u8]) -> Vec<u8> {
    let mut c = raw_chunk(id, body.len() as u32, body);
    if body.len() % 2 == 1 {
        c.push(0);
    }
    c
}

/// A 16-byte `fmt ` body.
fn fmt_body(tag: u16, channels: u16, rate: u32, bits: u16, block_align: u16) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(&tag.to_le_bytes());
    b.extend_from_slice(&channels.to_le_bytes());
    b.extend_from_slice(&rate.to_le_bytes());
    b.extend_from_slice(&(rate * u32::from(block_align)).to_le_bytes());
    b.extend_from_slice(&block_align.to_le_bytes());
    b.extend_from_slice(&bits.to_le_bytes());
    b
}

/// A plain `fmt ` chunk with the block_align the format needs.
fn fmt(tag: u16, channels: u16, rate: u32, bits: u16) -> Vec<u8> {
    chunk(
        b"fmt ",
        &fmt_body(tag, channels, rate, bits, channels * bits.div_ceil(8)),
    )
}

/// `KSDATAFORMAT_SUBTYPE_*` for a format tag.
fn guid(tag: u16) -> [u8; 16] {
    let mut g = [
        0, 0, 0x00, 0x00, 0x00, 0x00, 0x10, 0x00, 0x80, 0x00, 0x00, 0xaa, 0x00, 0x38, 0x9b, 0x71,
    ];
    g[..2].copy_from_slice(&tag.to_le_bytes());
    g
}

/// A 40-byte WAVE_FORMAT_EXTENSIBLE `fmt ` chunk.
fn fmt_ext(channels: u16, rate: u32, container: u16, valid: u16, sub: [u8; 16]) -> Vec<u8> {
    let mut b = fmt_body(0xfffe, channels, rate, container, channels * container / 8);
    b.extend_from_slice(&22u16.to_le_bytes());
    b.extend_from_slice(&valid.to_le_bytes());
    b.extend_from_slice(&(if channels == 2 { 3u32 } else { 4 }).to_le_bytes());
    b.extend_from_slice(&sub);
    chunk(b"fmt ", &b)
}

/// `magic`, the RIFF size, `WAVE` and the chunks.
fn riff_with(magic: &[u8; 4], riff_size: u32, chunks: &[Vec<u8>]) -> Vec<u8> {
    let mut f = magic.to_vec();
    f.extend_from_slice(&riff_size.to_le_bytes());
    f.extend_from_slice(b"WAVE");
    for c in chunks {
        f.extend_from_slice(c);
    }
    f
}

/// A RIFF/WAVE file with the right RIFF size.
fn riff(chunks: &[Vec<u8>]) -> Vec<u8> {
    let body: usize = 4 + chunks.iter().map(Vec::len).sum::<usize>();
    riff_with(b"RIFF", body as u32, chunks)
}

fn i16_bytes(v: &[i16]) -> Vec<u8> {
    v.iter().flat_map(|s| s.to_le_bytes()).collect()
}

fn i32_bytes(v: &[i32]) -> Vec<u8> {
    v.iter().flat_map(|s| s.to_le_bytes()).collect()
}

/// 24-bit little-endian containers.
fn i24_bytes(v: &[i32]) -> Vec<u8> {
    v.iter()
        .flat_map(|s| s.to_le_bytes()[..3].to_vec())
        .collect()
}

fn f32_bytes(v: &[f32]) -> Vec<u8> {
    v.iter().flat_map(|s| s.to_le_bytes()).collect()
}

fn put(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write test file");
    p
}

fn temp() -> tempfile::TempDir {
    tempfile::tempdir().expect("temp dir")
}

// ---- reading through the library ----

/// Reads the whole file in small blocks (to cross block boundaries).
fn read_all(path: &Path) -> (WavInfo, Vec<f32>) {
    let mut src = WavSource::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let info = src.info();
    let mut all = Vec::new();
    let mut block = Vec::new();
    loop {
        let n = src
            .read_interleaved(3, &mut block)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        if n == 0 {
            break;
        }
        assert_eq!(block.len(), n * info.channels as usize);
        all.extend_from_slice(&block);
    }
    assert_eq!(
        src.frames_read() as usize,
        all.len() / info.channels as usize
    );
    (info, all)
}

/// Bit-exact comparison of sample lists.
fn assert_same(got: &[f32], want: &[f32], what: &str) {
    let g: Vec<u32> = got.iter().map(|v| v.to_bits()).collect();
    let w: Vec<u32> = want.iter().map(|v| v.to_bits()).collect();
    assert_eq!(g, w, "{what}: got {got:?}, want {want:?}");
}

/// 16-bit samples as the reader must return them.
fn scaled16(v: &[i16]) -> Vec<f32> {
    v.iter().map(|&s| s as f32 / 32768.0).collect()
}

// ---- running `pneuma analyze` ----

/// 0.3 s silence, 0.6 s of a 200 Hz tone, 0.3 s silence at 16 kHz, as 16-bit samples.
fn tone16() -> Vec<i16> {
    let mut x = vec![0.0f32; 4800];
    x.extend(signals::harmonic_tone(
        16_000.0,
        0.6,
        0.5,
        &[1.0, 0.6, 0.4, 0.2],
        |_| 200.0,
    ));
    x.extend(vec![0.0; 4800]);
    x.iter().map(|v| (v * 32767.0).round() as i16).collect()
}

/// `pneuma analyze FILE -o -`: the CSV.
fn analyze(path: &Path) -> String {
    let out = pneuma(&["analyze", path.to_str().expect("utf-8"), "-o", "-"]);
    assert!(
        out.status.success(),
        "{}: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8")
}

/// The CSV of [`tone16`] (1.2 s): one row per 1/120 s, the tone voiced at 200 Hz.
fn check_tone_csv(csv: &str, what: &str) {
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().expect("number")).collect())
        .collect();
    assert_eq!(rows.len(), 144, "{what}: rows");
    let tone: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] > 0.36 && r[0] < 0.84).collect();
    assert!(!tone.is_empty());
    for r in tone {
        assert!(r[2] == 1.0 && (r[1] - 200.0).abs() < 3.0, "{what}: {r:?}");
    }
}

// ---- chunks ----

#[test]
fn odd_length_chunks_are_skipped_with_their_pad_byte() {
    let dir = temp();
    let v: Vec<i16> = vec![0, 1, -1, 32767, -32768, 12345, -12345];
    // LIST of 5 bytes (+ pad), bext of 3, iXML of 1, then data, then a chunk after the data.
    let file = riff(&[
        chunk(b"LIST", b"INFOx"),
        fmt(PCM, 1, 16_000, 16),
        chunk(b"bext", b"abc"),
        chunk(b"iXML", b"<"),
        chunk(b"data", &i16_bytes(&v)),
        chunk(b"LIST", &[0x7f; 9]),
    ]);
    let (info, got) = read_all(&put(dir.path(), "odd.wav", &file));
    assert_eq!(
        info,
        WavInfo {
            sample_rate_hz: 16_000,
            channels: 1,
            bits: 16,
            float: false,
            frames: 7
        }
    );
    assert_same(&got, &scaled16(&v), "odd chunks");

    // End to end: a real signal behind an odd LIST chunk analyses like any file.
    let file = riff(&[
        fmt(PCM, 1, 16_000, 16),
        chunk(b"LIST", b"INFOISFT\x05\0\0\0Lavf\0"),
        chunk(b"data", &i16_bytes(&tone16())),
        chunk(b"id3 ", b"trailing tag"),
    ]);
    check_tone_csv(
        &analyze(&put(dir.path(), "list.wav", &file)),
        "odd LIST chunk",
    );
}

#[test]
fn fact_chunks_of_any_length_are_skipped() {
    let dir = temp();
    let v: Vec<i16> = vec![100, -200, 300, -400];
    for (name, fact) in [
        ("fact4", chunk(b"fact", &4u32.to_le_bytes())),
        ("fact7", chunk(b"fact", &[1, 2, 3, 4, 5, 6, 7])),
        ("fact0", chunk(b"fact", &[])),
    ] {
        let file = riff(&[
            fmt(PCM, 2, 44_100, 16),
            fact,
            chunk(b"data", &i16_bytes(&v)),
        ]);
        let (info, got) = read_all(&put(dir.path(), &format!("{name}.wav"), &file));
        assert_eq!((info.channels, info.frames), (2, 2), "{name}");
        assert_same(&got, &scaled16(&v), name);
    }
}

// ---- sample formats ----

#[test]
fn plain_float_tag_3_is_read_bit_exactly() {
    let dir = temp();
    let v = [
        0.0f32,
        0.5,
        -0.25,
        1.0,
        -1.0,
        1.0e-7,
        0.123_456_79,
        -0.987_654_3,
    ];
    let file = riff(&[
        fmt(FLOAT, 2, 48_000, 32),
        chunk(b"fact", &4u32.to_le_bytes()),
        chunk(b"data", &f32_bytes(&v)),
    ]);
    let (info, got) = read_all(&put(dir.path(), "float.wav", &file));
    assert!(info.float);
    assert_eq!((info.bits, info.channels, info.frames), (32, 2, 4));
    assert_same(&got, &v, "float");
}

#[test]
fn extensible_float_is_read_bit_exactly() {
    let dir = temp();
    let v = [0.75f32, -0.5, 3.0e-5, -1.0];
    let file = riff(&[
        fmt_ext(1, 96_000, 32, 32, guid(FLOAT)),
        chunk(b"data", &f32_bytes(&v)),
    ]);
    let (info, got) = read_all(&put(dir.path(), "extfloat.wav", &file));
    assert!(info.float);
    assert_eq!((info.bits, info.frames), (32, 4));
    assert_same(&got, &v, "extensible float");
}

/// 24-bit values: extremes, ±1, and values using every byte.
const S24: [i32; 8] = [
    -8_388_608, 8_388_607, 1, -1, 0x12_3456, -0x12_3457, 0, 0x7f_0001,
];

#[test]
fn extensible_24_in_32_is_read_from_the_top_of_the_container() {
    let dir = temp();
    let containers: Vec<i32> = S24.iter().map(|s| s << 8).collect();
    let file = riff(&[
        fmt_ext(2, 48_000, 32, 24, guid(PCM)),
        chunk(b"data", &i32_bytes(&containers)),
    ]);
    let (info, got) = read_all(&put(dir.path(), "24in32.wav", &file));
    assert_eq!((info.bits, info.float, info.frames), (32, false, 4));
    let want: Vec<f32> = S24.iter().map(|&s| s as f32 / 8_388_608.0).collect();
    assert_same(&got, &want, "24 in 32");
}

#[test]
fn extensible_20_in_24_is_read_from_the_top_of_the_container() {
    let dir = temp();
    let s20 = [-524_288, 524_287, 1, -1, 0x1_2345, -0x1_2346];
    let containers: Vec<i32> = s20.iter().map(|s| s << 4).collect();
    let file = riff(&[
        fmt_ext(1, 44_100, 24, 20, guid(PCM)),
        chunk(b"data", &i24_bytes(&containers)),
    ]);
    let (info, got) = read_all(&put(dir.path(), "20in24.wav", &file));
    assert_eq!((info.bits, info.float, info.frames), (24, false, 6));
    let want: Vec<f32> = s20.iter().map(|&s| s as f32 / 524_288.0).collect();
    assert_same(&got, &want, "20 in 24");
}

#[test]
fn eight_bit_is_unsigned_around_128() {
    let dir = temp();
    let bytes = [0u8, 128, 255, 1, 127, 129];
    let file = riff(&[fmt(PCM, 1, 8_000, 8), chunk(b"data", &bytes)]);
    let (info, got) = read_all(&put(dir.path(), "u8.wav", &file));
    assert_eq!((info.bits, info.frames), (8, 6));
    assert_same(
        &got,
        &[
            -1.0,
            0.0,
            127.0 / 128.0,
            -127.0 / 128.0,
            -1.0 / 128.0,
            1.0 / 128.0,
        ],
        "8-bit",
    );
}

#[test]
fn twenty_four_bit_plain_pcm_is_sign_extended() {
    let dir = temp();
    let file = riff(&[fmt(PCM, 1, 22_050, 24), chunk(b"data", &i24_bytes(&S24))]);
    let (info, got) = read_all(&put(dir.path(), "s24.wav", &file));
    assert_eq!((info.bits, info.frames), (24, 8));
    let want: Vec<f32> = S24.iter().map(|&s| s as f32 / 8_388_608.0).collect();
    assert_same(&got, &want, "24-bit");
}

// ---- lengths: streamed, RF64, empty, truncated ----

#[test]
fn streamed_sizes_are_read_to_the_end_of_the_file() {
    let dir = temp();
    let x = tone16();
    let data = i16_bytes(&x);
    let whole = put(
        dir.path(),
        "whole.wav",
        &riff(&[fmt(PCM, 1, 16_000, 16), chunk(b"data", &data)]),
    );
    let reference = analyze(&whole);
    check_tone_csv(&reference, "whole file");
    // ffmpeg to a pipe: RIFF and data sizes 0xFFFFFFFF; others write 0 and RIFF 0 or
    // 0xFFFFFFFF; sox writes 0x7FFFF000. A trailing partial frame is dropped.
    let cases: [(&str, u32, u32); 4] = [
        ("ffffffff", u32::MAX, u32::MAX),
        ("zero_riff_ffffffff", u32::MAX, 0),
        ("zero_riff_zero", 0, 0),
        ("sox_unspecified", 0x7fff_f024, 0x7fff_f000),
    ];
    for (name, riff_size, data_size) in cases {
        let mut body = data.clone();
        body.push(0x55); // half a frame
        let file = riff_with(
            b"RIFF",
            riff_size,
            &[
                fmt(PCM, 1, 16_000, 16),
                chunk(b"LIST", b"INFO"),
                raw_chunk(b"data", data_size, &body),
            ],
        );
        let path = put(dir.path(), &format!("{name}.wav"), &file);
        let (info, got) = read_all(&path);
        assert_eq!(
            info.frames,
            x.len() as u64,
            "{name}: frames from the length"
        );
        assert_same(&got, &scaled16(&x), name);
        assert_eq!(analyze(&path), reference, "{name}: analysis differs");
    }
}

#[test]
fn rf64_and_bw64_take_the_data_size_from_ds64() {
    let dir = temp();
    let v: Vec<i16> = (0..10).map(|k| k * 1000 - 5000).collect();
    let data = i16_bytes(&v);
    let ds64 = |riff: u64, data: u64, frames: u64| {
        let mut b = Vec::new();
        b.extend_from_slice(&riff.to_le_bytes());
        b.extend_from_slice(&data.to_le_bytes());
        b.extend_from_slice(&frames.to_le_bytes());
        b.extend_from_slice(&0u32.to_le_bytes()); // no table entries
        b
    };
    let body = ds64(1000, data.len() as u64, 5);
    for (name, magic, ds) in [
        ("rf64", b"RF64", chunk(b"ds64", &body)),
        ("bw64", b"BW64", chunk(b"ds64", &body)),
        // Old libsndfile: a 28-byte ds64 announced as 32 bytes.
        ("rf64_sndfile", b"RF64", raw_chunk(b"ds64", 32, &body)),
    ] {
        let file = riff_with(
            magic,
            u32::MAX,
            &[
                ds,
                fmt(PCM, 2, 48_000, 16),
                raw_chunk(b"data", u32::MAX, &data),
                // Must not be read as audio: the ds64 data size ends before it.
                chunk(b"LIST", &[0x7f; 12]),
            ],
        );
        let (info, got) = read_all(&put(dir.path(), &format!("{name}.wav"), &file));
        assert_eq!((info.channels, info.frames), (2, 5), "{name}");
        assert_same(&got, &scaled16(&v), name);
    }
    // RF64 streamed (ds64 sizes left at 0): read to the end of the file.
    let file = riff_with(
        b"RF64",
        u32::MAX,
        &[
            chunk(b"ds64", &ds64(0, 0, 0)),
            fmt(PCM, 1, 48_000, 16),
            raw_chunk(b"data", u32::MAX, &data),
        ],
    );
    let (info, got) = read_all(&put(dir.path(), "rf64_stream.wav", &file));
    assert_eq!(info.frames, 10);
    assert_same(&got, &scaled16(&v), "RF64 streamed");
}

#[test]
fn found_by_fuzzing() {
    let dir = temp();
    // An RF64 whose ds64 announces 2^64 − 2 bytes of 8-bit data with 3 000 bytes there:
    // `render` multiplied the announced frame count and panicked; it is a truncated file.
    let mut ds = Vec::new();
    for v in [0u64, u64::MAX - 1, 0] {
        ds.extend_from_slice(&v.to_le_bytes());
    }
    ds.extend_from_slice(&0u32.to_le_bytes());
    let huge = put(
        dir.path(),
        "huge.wav",
        &riff_with(
            b"RF64",
            u32::MAX,
            &[
                chunk(b"ds64", &ds),
                fmt(PCM, 1, 16_000, 8),
                raw_chunk(b"data", u32::MAX, &[0x80; 3000]),
            ],
        ),
    );
    assert_analyze_fails(
        &huge,
        &["damaged after 3000 sample frames", "holds only 3000"],
    );
    let out = dir.path().join("render");
    let o = support::render(&huge, &out, &[]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && !err.contains("panicked"), "{err}");
    assert!(err.contains("damaged after 3000 sample frames"), "{err}");
    // An odd-length chunk written without its pad byte puts the chunks out of step.
    let mut odd = fmt(PCM, 1, 16_000, 16);
    odd.extend_from_slice(&raw_chunk(b"odd ", 3, b"abc"));
    odd.extend_from_slice(&chunk(b"data", &i16_bytes(&[1, 256, 1, 256])));
    let mut file = b"RIFF".to_vec();
    file.extend_from_slice(&((odd.len() + 4) as u32).to_le_bytes());
    file.extend_from_slice(b"WAVE");
    file.extend_from_slice(&odd);
    assert_analyze_fails(
        &put(dir.path(), "nopad.wav", &file),
        &["out of step", "without its pad byte"],
    );
    // A folder is not a file to convert.
    assert_analyze_fails(dir.path(), &["it is a folder"]);
}

#[test]
fn a_file_without_sample_frames_holds_no_audio() {
    let dir = temp();
    let empty = put(
        dir.path(),
        "zero.wav",
        &riff(&[fmt(PCM, 1, 16_000, 16), chunk(b"data", &[])]),
    );
    assert_analyze_fails(&empty, &["holds no audio", "data chunk is empty"]);
    assert!(matches!(
        WavSource::open(&empty),
        Err(WavError::Empty { .. })
    ));
    // Less than one frame.
    let short = put(
        dir.path(),
        "short.wav",
        &riff(&[fmt(PCM, 2, 16_000, 16), chunk(b"data", &[1, 2])]),
    );
    assert_analyze_fails(
        &short,
        &["holds no audio", "less than one 4-byte sample frame"],
    );
    // A header announcing 0 bytes with audio after it (a crashed writer): say how to recover.
    let lost = put(
        dir.path(),
        "lost.wav",
        &riff(&[
            fmt(PCM, 1, 16_000, 16),
            raw_chunk(b"data", 0, &i16_bytes(&[1, 2, 3, 4])),
        ]),
    );
    assert_analyze_fails(
        &lost,
        &["holds no audio", "8 bytes follow", "sox --ignore-length"],
    );
    // Only the header written, announcing audio that never came: nothing to keep with sox.
    let header_only = put(
        dir.path(),
        "header_only.wav",
        &riff(&[fmt(PCM, 1, 16_000, 16), raw_chunk(b"data", 40_000, &[])]),
    );
    assert_analyze_fails(
        &header_only,
        &[
            "holds no audio",
            "but not one follows it (only the header was written); record",
        ],
    );
    // Streamed, but nothing came.
    let streamed = put(
        dir.path(),
        "streamed_empty.wav",
        &riff_with(
            b"RIFF",
            u32::MAX,
            &[fmt(PCM, 1, 16_000, 16), raw_chunk(b"data", u32::MAX, &[7])],
        ),
    );
    assert_analyze_fails(&streamed, &["holds no audio"]);
}

#[test]
fn data_announced_beyond_the_end_is_truncated() {
    let dir = temp();
    let x = tone16();
    let file = riff_with(
        b"RIFF",
        20_000,
        &[
            fmt(PCM, 1, 16_000, 16),
            raw_chunk(b"data", 40_000, &i16_bytes(&x[..5000])),
        ],
    );
    let path = put(dir.path(), "cut.wav", &file);
    // Found when the file is opened, before anything is read or analysed.
    match WavSource::open(&path) {
        Err(WavError::Truncated { frames_read, .. }) => assert_eq!(frames_read, 5000),
        other => panic!("expected Truncated at open, got {other:?}"),
    }
    assert_analyze_fails(
        &path,
        &[
            "damaged after 5000 sample frames",
            "announces 20000 sample frames but the file holds only 5000",
            "sox --ignore-length IN OUT.wav",
        ],
    );
}

// ---- what is not read ----

#[test]
fn bad_headers_fail_with_their_reason() {
    let dir = temp();
    let data = chunk(b"data", &i16_bytes(&[1, 2, 3, 4]));
    let list = chunk(b"LIST", b"INFO");
    let mut ext_short = fmt_body(0xfffe, 1, 16_000, 16, 2);
    ext_short.extend_from_slice(&[0, 0]);
    let mut bad_guid = guid(PCM);
    bad_guid[15] = 0x72;
    let cases: Vec<(&str, Vec<u8>, Vec<&str>)> = vec![
        (
            "zero_channels",
            riff(&[
                chunk(b"fmt ", &fmt_body(PCM, 0, 16_000, 16, 0)),
                data.clone(),
            ]),
            vec!["0 channels"],
        ),
        (
            "bad_block_align",
            riff(&[
                chunk(b"fmt ", &fmt_body(PCM, 2, 16_000, 16, 6)),
                data.clone(),
            ]),
            vec!["block_align of 6", "2 channels of 16-bit samples take 4"],
        ),
        (
            "zero_rate",
            riff(&[chunk(b"fmt ", &fmt_body(PCM, 1, 0, 16, 2)), data.clone()]),
            vec!["sample rate of 0 Hz"],
        ),
        (
            "slow_rate",
            riff(&[fmt(PCM, 1, 4_000, 16), data.clone()]),
            vec!["4000 Hz", "sox IN -r 48000"],
        ),
        (
            "zero_bits",
            riff(&[
                chunk(b"fmt ", &fmt_body(PCM, 1, 16_000, 0, 2)),
                data.clone(),
            ]),
            vec!["0 bits per sample"],
        ),
        (
            "float64",
            riff(&[fmt(FLOAT, 1, 16_000, 64), chunk(b"data", &[0; 32])]),
            vec!["64-bit float is not supported", "sox IN -b 24 OUT.wav"],
        ),
        (
            "ima_adpcm",
            // Read through symphonia since ADPCM is supported; this header lacks the
            // samples-per-block field, so it cannot be.
            riff(&[fmt(IMA_ADPCM, 1, 8_000, 4), chunk(b"data", &[0x00; 16])]),
            vec![
                "IMA ADPCM",
                "header cannot be read",
                "not a readable WAV file",
                "sox IN -b 16 OUT.wav",
            ],
        ),
        (
            "mp3",
            riff(&[fmt(MP3, 1, 44_100, 0), chunk(b"data", &[0xff; 16])]),
            vec!["MP3", "not supported"],
        ),
        (
            "ima_adpcm_extensible",
            riff(&[fmt_ext(1, 8_000, 8, 8, guid(IMA_ADPCM)), data.clone()]),
            vec!["IMA ADPCM", "WAVE_FORMAT_EXTENSIBLE", "not supported"],
        ),
        (
            "unknown_guid",
            riff(&[fmt_ext(1, 16_000, 16, 16, bad_guid), data.clone()]),
            vec!["subformat GUID 01000000000010008000", "not supported"],
        ),
        (
            "short_extensible",
            riff(&[chunk(b"fmt ", &ext_short), data.clone()]),
            vec!["shorter than the 40"],
        ),
        (
            "valid_over_container",
            riff(&[fmt_ext(1, 16_000, 16, 20, guid(PCM)), data.clone()]),
            vec!["20 valid bits in a 16-bit container"],
        ),
        (
            "big_endian",
            riff_with(b"RIFX", 40, &[fmt(PCM, 1, 16_000, 16), data.clone()]),
            vec!["big-endian WAV (RIFX)", "sox"],
        ),
        (
            "missing_fmt",
            riff(std::slice::from_ref(&list)),
            vec!["no fmt chunk"],
        ),
        (
            "data_only",
            riff(&[list.clone(), data.clone()]),
            vec!["data chunk comes before the fmt chunk"],
        ),
        (
            "data_before_fmt",
            riff(&[data.clone(), fmt(PCM, 1, 16_000, 16)]),
            vec!["data chunk comes before the fmt chunk"],
        ),
        (
            "missing_data",
            riff(&[fmt(PCM, 1, 16_000, 16), list.clone()]),
            vec!["no data chunk"],
        ),
        (
            "huge_list",
            riff(&[
                fmt(PCM, 1, 16_000, 16),
                raw_chunk(b"LIST", 0xffff_fff0, b"INFO"),
                data.clone(),
            ]),
            vec![
                "'LIST' chunk announces 4294967280 bytes",
                "before any data chunk",
            ],
        ),
        (
            "huge_fmt",
            riff(&[raw_chunk(
                b"fmt ",
                0x7fff_ffff,
                &fmt_body(PCM, 1, 16_000, 16, 2),
            )]),
            vec!["'fmt ' chunk announces 2147483647 bytes"],
        ),
        (
            "tiny_fmt",
            riff(&[chunk(b"fmt ", &[1, 0, 1, 0]), data.clone()]),
            vec!["fmt chunk is 4 bytes"],
        ),
        (
            "flac",
            // Named .wav but FLAC inside: read as FLAC (pneuma-io goes by content), and this
            // one is cut inside its header.
            b"fLaC\0\0\0\x22 and more bytes".to_vec(),
            vec!["ends inside its FLAC header"],
        ),
        (
            "text",
            b"just some text".to_vec(),
            vec!["is not audio: it holds text (\"just some text…\")"],
        ),
        ("tiny", b"RIFF\x04\0".to_vec(), vec!["6 bytes long"]),
        // Too short for the text rule and for any header: no advice to convert it.
        (
            "hi",
            b"hi\n".to_vec(),
            vec!["3 bytes long, too short to hold any audio"],
        ),
        (
            "not_wave",
            riff_with(b"RIFF", 4, &[])
                .iter()
                .take(8)
                .chain(b"AVI ")
                .copied()
                .collect(),
            vec!["form 'AVI '"],
        ),
    ];
    for (name, bytes, must) in cases {
        assert_analyze_fails(&put(dir.path(), &format!("{name}.wav"), &bytes), &must);
    }
}

// ---- render keeps an extensible 24-in-32 input exactly ----

/// Container values of a 24-in-32 stereo file: phrases at 22.05 kHz (the second channel 0.7×).
fn phrases_24in32() -> Vec<i32> {
    let r = 22_050.0;
    let mut x = vec![0.0f32; (0.5 * r) as usize];
    for (i, len) in [1.0, 1.0].into_iter().enumerate() {
        x.extend(signals::glottal_vowel(
            &GlottalVowel {
                sample_rate_hz: r,
                length_s: len,
                vowel: [Vowel::A, Vowel::I][i],
                jitter: 0.01,
                shimmer: 0.04,
                peak: 0.5,
                seed: i as u64,
            },
            |t| 150.0 - 30.0 * t / len,
        ));
        x.extend(std::iter::repeat_n(0.0, (0.9 * r) as usize));
    }
    x.iter()
        .flat_map(|&v| {
            let s = (v * 8_388_607.0).round() as i32;
            [s << 8, ((s as f32 * 0.7).round() as i32) << 8]
        })
        .collect()
}

/// Integer samples of a rendered WAV (read with hound, not with the reader under test).
fn rendered(path: &Path) -> (hound::WavSpec, Vec<i32>) {
    let mut r = hound::WavReader::open(path).expect("rendered wav");
    let spec = r.spec();
    let v = r.samples::<i32>().map(|s| s.expect("sample")).collect();
    (spec, v)
}

#[test]
fn render_keeps_24_in_32_samples_exactly_outside_breaths() {
    let dir = temp();
    let containers = phrases_24in32();
    let input = put(
        dir.path(),
        "v.wav",
        &riff(&[
            fmt_ext(2, 22_050, 32, 24, guid(PCM)),
            chunk(b"data", &i32_bytes(&containers)),
        ]),
    );
    let render = |out: &Path, extra: &[&str]| {
        let o = support::render(&input, out, &[&["--no-plot"], extra].concat());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };

    let plain = dir.path().join("plain");
    render(&plain, &["--no-breaths"]);
    let (spec, out) = rendered(&plain.join("v.wav"));
    assert_eq!(
        (spec.bits_per_sample, spec.channels, spec.sample_format),
        (32, 2, hound::SampleFormat::Int)
    );
    assert_eq!(
        out, containers,
        "--no-breaths must copy the samples exactly"
    );

    // Two sustained generated vowels are not speech to the speech decision (their voiced
    // frames say so by their offsets): --any-sound, as the other renders of generated vowels.
    let breathed = dir.path().join("breathed");
    render(&breathed, &["--any-sound"]);
    let (_, out) = rendered(&breathed.join("v.wav"));
    assert_eq!(out.len(), containers.len());
    let text = std::fs::read_to_string(breathed.join("v.breaths.csv")).expect("breaths");
    let breaths: Vec<(f64, f64)> = text
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse().expect("start"), f[1].parse().expect("end"))
        })
        .collect();
    assert!(!breaths.is_empty(), "the pauses get breaths");
    let mut changed = 0;
    for (i, (a, b)) in containers.iter().zip(&out).enumerate() {
        if a != b {
            changed += 1;
            let t = (i / 2) as f64 / 22_050.0;
            assert!(
                breaths.iter().any(|&(s, e)| t >= s - 1e-3 && t <= e + 1e-3),
                "sample at {t:.4} s changed outside every breath"
            );
        }
    }
    assert!(changed > 1000, "the breaths changed only {changed} samples");
}
