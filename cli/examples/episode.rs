//! Writes a generated speech-like episode for measuring long renders (used by `.ci/run`):
//! `cargo run --release -p pneuma-cli --example episode -- OUT.wav LENGTH_S [RATE_HZ] [CHANNELS]`.

#[path = "../tests/integration/support/episode.rs"]
mod episode;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: episode OUT.wav LENGTH_S [RATE_HZ=48000] [CHANNELS=2]";
    let (Some(out), Some(length_s)) = (args.first(), args.get(1).and_then(|s| s.parse().ok()))
    else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let rate_hz = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(48_000);
    let channels = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(2);
    episode::write_episode(std::path::Path::new(out), length_s, rate_hz, channels);
}
