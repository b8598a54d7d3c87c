//! The shipped example voice is what its README and transcript promise: a small mono WAV whose
//! silent stretches are the planned pauses, several shorter than 250 ms and some over a second.

use pneuma_testkit::voice::{example_voice, example_voice_path};

/// (start_s, length_s) of every run of exact digital silence of at least `min_s`.
fn silent_runs(samples: &[f32], rate: f64, min_s: f64) -> Vec<(f64, f64)> {
    let mut runs = Vec::new();
    let mut start = None;
    for (i, &s) in samples.iter().chain(std::iter::once(&1.0)).enumerate() {
        match (s == 0.0, start) {
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
    let voice_path = example_voice_path();
    let dir = voice_path.parent().expect("assets/examples");
    let size: u64 = std::fs::read_dir(dir)
        .expect("assets/examples exists")
        .map(|e| e.expect("entry").metadata().expect("metadata").len())
        .sum();
    assert!(
        size < 1_000_000,
        "assets/examples holds {size} bytes; keep it under 1 MB"
    );

    // Mono 16-bit (pneuma_testkit::voice checks the format).
    let (samples, rate) = example_voice();
    let rate = f64::from(rate);
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
    let peak = samples.iter().fold(0.0f32, |m, s| m.max(s.abs())) * 32_768.0;
    assert!(peak > 16_000.0 && peak < 32_767.0, "peak {peak}");
}
