//! `pneuma render` of a long generated episode with the plot: every output complete (the WAV
//! as long as the input, one controls row and one BVH frame per control frame up to the end,
//! the breaths CSV whole, the PNG a full image). The length defaults to 7 min at 16 kHz mono,
//! past the 6 min 40 s where the plot used to fail; an hour at 48 kHz stereo is checked by hand
//! with `PNEUMA_LONG_RENDER_S=3600 PNEUMA_LONG_RENDER_RATE=48000 PNEUMA_LONG_RENDER_CHANNELS=2`
//! (`.ci/run` renders and times the hour once through the release binary).

use std::path::Path;

use crate::support;
use crate::support::episode;

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Width and height from a PNG's IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert!(bytes.len() > 33, "PNG too short");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

#[test]
fn a_long_render_with_the_plot_writes_every_output_complete() {
    let length_s: f64 = env_or("PNEUMA_LONG_RENDER_S", 420.0);
    let rate_hz: u32 = env_or("PNEUMA_LONG_RENDER_RATE", 16_000);
    let channels: u16 = env_or("PNEUMA_LONG_RENDER_CHANNELS", 1);
    let dir = tempfile::tempdir().expect("temp dir");
    let input = dir.path().join("episode.wav");
    episode::write_episode(&input, length_s, rate_hz, channels);
    let out_dir = dir.path().join("out");
    // The generated episode's vowels are not speech to the speech decision: --any-sound.
    let out = support::render(&input, &out_dir, &["--bvh", "--any-sound"]);
    assert!(
        out.status.success(),
        "{length_s} s: {}",
        String::from_utf8_lossy(&out.stderr)
    );

    // The audio: as many sample frames as the input, same format.
    let wav = hound::WavReader::open(out_dir.join("episode.wav")).expect("output wav");
    let spec = wav.spec();
    assert_eq!((spec.sample_rate, spec.channels), (rate_hz, channels));
    let frames_in = (length_s * rate_hz as f64) as u32;
    assert_eq!(wav.duration(), frames_in, "output audio length");

    // The controls: rows at 120 frames/s with consecutive indices up to the end.
    let text = std::fs::read_to_string(out_dir.join("episode.controls.csv")).expect("controls");
    let mut rows = text.lines();
    let header = rows.next().expect("header");
    let time_col = header
        .split(',')
        .position(|c| c == "time_s")
        .expect("time_s column");
    let times: Vec<f64> = rows
        .map(|r| {
            r.split(',')
                .nth(time_col)
                .expect("time")
                .parse()
                .expect("number")
        })
        .collect();
    let expected = (length_s * 120.0).round() as usize;
    assert!(
        times.len().abs_diff(expected) <= 1,
        "{} control rows, expected {expected}",
        times.len()
    );
    for (i, t) in times.iter().enumerate() {
        assert!((t - i as f64 / 120.0).abs() < 1e-6, "row {i} at {t} s");
    }

    // The BVH: as many frames as control rows.
    let bvh = std::fs::read_to_string(out_dir.join("episode.bvh")).expect("bvh");
    let declared: usize = bvh
        .lines()
        .find_map(|l| l.strip_prefix("Frames:"))
        .expect("Frames: line")
        .trim()
        .parse()
        .expect("frame count");
    let motion = bvh.split("Frame Time:").nth(1).expect("motion");
    assert_eq!(declared, times.len());
    assert_eq!(
        motion.lines().skip(1).filter(|l| !l.is_empty()).count(),
        declared
    );

    // The breaths: whole rows inside the file, some on a talk this long.
    let breaths = std::fs::read_to_string(out_dir.join("episode.breaths.csv")).expect("breaths");
    let rows: Vec<&str> = breaths.lines().skip(1).collect();
    assert!(
        rows.len() as f64 > length_s / 20.0,
        "{} breaths",
        rows.len()
    );
    for r in rows {
        let f: Vec<&str> = r.split(',').collect();
        assert_eq!(f.len(), 4, "{r}");
        let end: f64 = f[1].parse().expect("end");
        assert!(end <= length_s + 1e-6, "{r}");
    }

    // The plot: a whole PNG of the fixed size.
    let png = std::fs::read(out_dir.join("episode.png")).expect("png");
    assert_eq!(png_size(&png), (1600, 800));
    assert_eq!(&png[png.len() - 8..png.len() - 4], b"IEND", "PNG cut short");

    let names = support::files_besides(&out_dir, Path::new(""));
    assert_eq!(names.len(), 5, "{names:?}");
}
