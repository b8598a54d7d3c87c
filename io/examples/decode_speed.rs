//! Decode speed of each input file, in multiples of real time:
//! `cargo run --release -p pneuma-io --example decode_speed -- [--symphonia-wav] FILE...`.
//!
//! Each file is read to the end through [`AudioSource`] (the path `pneuma` takes) in blocks of
//! 4096 sample frames. With `--symphonia-wav`, WAV files are read through symphonia's WAV reader
//! instead, to compare it with the own reader (the choice the crate documentation explains).
//! Peak memory is measured around the command (`/usr/bin/time -v`), one file per run.

use std::path::Path;
use std::time::Instant;

use pneuma_io::{AudioSource, DecodedSource, InputFormat};

fn main() {
    let mut symphonia_wav = false;
    let mut files = Vec::new();
    for a in std::env::args().skip(1) {
        if a == "--symphonia-wav" {
            symphonia_wav = true;
        } else {
            files.push(a);
        }
    }
    if files.is_empty() {
        eprintln!("usage: decode_speed [--symphonia-wav] FILE...");
        std::process::exit(2);
    }
    for f in files {
        let path = Path::new(&f);
        let start = Instant::now();
        let (frames, rate, label) = if symphonia_wav && path_is_wav(path) {
            let file = std::fs::File::open(path).expect("open");
            let mut src = DecodedSource::open(path, Box::new(file), InputFormat::Wav)
                .unwrap_or_else(|e| fail(&e.to_string()));
            let rate = src.info().sample_rate_hz;
            let mut block = Vec::new();
            while src
                .read_interleaved(4096, &mut block)
                .unwrap_or_else(|e| fail(&e.to_string()))
                > 0
            {}
            (src.frames_read(), rate, "WAV via symphonia")
        } else {
            let mut src = AudioSource::open(path).unwrap_or_else(|e| fail(&e.to_string()));
            let rate = src.info().sample_rate_hz;
            let label = src.format().name();
            let mut block = Vec::new();
            while src
                .read_interleaved(4096, &mut block)
                .unwrap_or_else(|e| fail(&e.to_string()))
                > 0
            {}
            (src.frames_read(), rate, label)
        };
        let secs = start.elapsed().as_secs_f64();
        let audio_s = frames as f64 / f64::from(rate);
        println!(
            "{f}: {label}, {audio_s:.1} s of audio decoded in {secs:.2} s = {:.0}x real time",
            audio_s / secs.max(1e-9)
        );
    }
}

fn path_is_wav(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("wav"))
}

fn fail(msg: &str) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(1)
}
