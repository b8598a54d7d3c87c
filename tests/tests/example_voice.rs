//! The shipped example voice is what its README and transcript promise: a small mono WAV whose
//! silent stretches are the planned pauses, several shorter than 250 ms and some over a second.

use std::path::PathBuf;

fn assets() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../assets/examples")
}

/// (start_s, length_s) of every run of exact digital silence of at least `min_s`.
fn silent_runs(samples: &[i16], rate: f64, min_s: f64) -> Vec<(f64, f64)> {
    let mut runs = Vec::new();
    let mut start = None;
    for (i, &s) in samples.iter().chain(std::iter::once(&1)).enumerate() {
        match (s == 0, start) {
            (true, None) => start = Some(i),
            (false, Some(b)) => {
                let len = (i - b) as f64 / rate;
                if len >= min_s {
                    runs.push((b as f64 / rate, len));
                }
                start = None;
            }
            _ => {}
        }
    }
    runs
}

#[test]
fn example_voice_matches_its_transcript() {
    let dir = assets();
    let size: u64 = std::fs::read_dir(&dir)
        .expect("assets/examples exists")
        .map(|e| e.expect("entry").metadata().expect("metadata").len())
        .sum();
    assert!(
        size < 1_000_000,
        "assets/examples holds {size} bytes; keep it under 1 MB"
    );

    let mut reader = hound::WavReader::open(dir.join("voice.wav")).expect("voice.wav opens");
    let spec = reader.spec();
    assert_eq!((spec.channels, spec.bits_per_sample), (1, 16));
    let rate = spec.sample_rate as f64;
    let samples: Vec<i16> = reader
        .samples::<i16>()
        .map(|s| s.expect("sample"))
        .collect();
    let length_s = samples.len() as f64 / rate;
    assert!((20.0..=30.0).contains(&length_s), "{length_s} s");

    // Planned pauses from the transcript (`phrase<TAB>pause_ms`), in order.
    let transcript = std::fs::read_to_string(dir.join("transcript.txt")).expect("transcript");
    let planned: Vec<f64> = transcript
        .lines()
        .filter(|l| !l.starts_with('#') && l.contains('\t'))
        .map(|l| {
            l.rsplit('\t')
                .next()
                .expect("pause")
                .trim()
                .parse::<f64>()
                .expect("ms")
                / 1000.0
        })
        .collect();
    assert!(planned.len() >= 8, "{planned:?}");
    assert!(planned.iter().filter(|&&p| p < 0.25).count() >= 2);
    assert!(planned.iter().filter(|&&p| p > 1.0).count() >= 2);

    // Every planned pause between phrases is a run of digital silence of that length.
    let runs = silent_runs(&samples, rate, 0.14);
    for (i, want) in planned[..planned.len() - 1].iter().enumerate() {
        assert!(
            runs.iter().any(|(_, len)| (len - want).abs() < 0.002),
            "pause {i} of {want} s not found among {runs:?}"
        );
    }
    // Speech is present and not clipped.
    let peak = samples
        .iter()
        .map(|s| s.unsigned_abs())
        .max()
        .expect("samples");
    assert!(peak > 16_000 && peak < 32_767, "peak {peak}");
}
