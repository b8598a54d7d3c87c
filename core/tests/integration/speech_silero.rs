//! The Rust Silero VAD (`pneuma_core::speech::silero`) against onnxruntime running the
//! package's own ONNX model on the same generated signal: speech-like phrases, silence, white
//! noise and a steady vowel.
//!
//! The reference probabilities below were produced by
//!
//! ```sh
//! PNEUMA_SILERO_SIGNAL=/tmp/silero_signal.f32 cargo test -p pneuma-core --test integration \
//!     speech_silero:: -- --ignored write_the_signal
//! target/venv-speech/bin/python eval/python/speech_baselines.py silero \
//!     /tmp/silero_signal.f32 /tmp/silero_reference.txt
//! ```
//!
//! (the virtual environment as `.ci/run` makes it: onnxruntime 1.32.0, silero-vad 6.2.3).

use pneuma_core::speech::silero::{Silero, CHUNK, SILERO_RATE_HZ};
use pneuma_testkit::signals::{self as test_signals, GlottalVowel, Vowel};

/// The signal at 16 kHz, a whole number of chunks.
fn signal() -> Vec<f32> {
    let sr = SILERO_RATE_HZ;
    let secs = |s: f64| (s * sr) as usize;
    let mut x = test_signals::white_noise(secs(0.3), 3e-4, 1);
    // A 2 s phrase (seed 1) and 0.5 s of silence.
    x.extend(crate::generated_phrases::sequence(0.0, &[2.0], &[0.5]).0);
    x.extend(test_signals::white_noise(secs(0.6), 0.05, 2));
    x.extend(test_signals::glottal_vowel(
        &GlottalVowel {
            sample_rate_hz: sr,
            length_s: 1.0,
            vowel: Vowel::A,
            jitter: 0.01,
            shimmer: 0.05,
            peak: 0.4,
            seed: 3,
        },
        |_| 150.0,
    ));
    x.resize(x.len().div_ceil(CHUNK) * CHUNK, 0.0);
    x
}

/// onnxruntime's probability of every chunk of [`signal`] (the command in the module docs).
#[rustfmt::skip]
const REFERENCE: [f64; 138] = [
    0.0105130076, 0.0115929544, 0.00736695528, 0.00745341182, 0.00683495402, 0.00641658902,
    0.00591152906, 0.00504353642, 0.00456342101, 0.854466081, 0.951969326, 0.914922476,
    0.650860012, 0.37789911, 0.219165355, 0.946026325, 0.988823712, 0.989555359,
    0.990745783, 0.991510332, 0.991920471, 0.993658781, 0.995211065, 0.989809513,
    0.978169918, 0.970300555, 0.969861746, 0.990048289, 0.983128369, 0.991087198,
    0.989933074, 0.995074213, 0.991496205, 0.992279053, 0.998025656, 0.998039722,
    0.997488737, 0.994798541, 0.99196583, 0.995569229, 0.993314266, 0.995196223,
    0.994669557, 0.985578179, 0.990307808, 0.987665653, 0.994271755, 0.998813152,
    0.997978926, 0.998147607, 0.997062922, 0.997542262, 0.994773805, 0.99595511,
    0.994743109, 0.996926248, 0.994447708, 0.994488478, 0.994742751, 0.995832324,
    0.992867351, 0.994183779, 0.991925955, 0.992052674, 0.987914324, 0.993816197,
    0.998519957, 0.998444498, 0.997962415, 0.997628868, 0.999061465, 0.998753965,
    0.248664171, 0.24886772, 0.0947931707, 0.033105731, 0.00883060694, 0.00414162874,
    0.00318211317, 0.00300380588, 0.00302985311, 0.00322645903, 0.00347429514, 0.00367391109,
    0.00381690264, 0.00392210484, 0.00399845839, 0.0323815644, 0.0437862277, 0.0200744569,
    0.017267555, 0.0198214948, 0.0263024569, 0.0394102037, 0.0252771676, 0.018441081,
    0.0157026649, 0.0258879066, 0.0237034559, 0.0185123086, 0.0217627585, 0.0261819363,
    0.0188133419, 0.0195629895, 0.0143575668, 0.0124490559, 0.991165876, 0.999269009,
    0.997188687, 0.997624815, 0.996575534, 0.996466815, 0.995202541, 0.992671371,
    0.991366863, 0.987330616, 0.987511992, 0.976760507, 0.962190568, 0.938099265,
    0.912081838, 0.946963608, 0.902583718, 0.84551692, 0.799246073, 0.748767972,
    0.646257401, 0.695711613, 0.553899288, 0.593138278, 0.469827712, 0.433127463,
    0.641912043, 0.492117703, 0.440272778, 0.473304272, 0.630191863, 0.394846559,
];

/// Largest difference allowed: the two sum in different orders (measured: about 1e-6).
const TOLERANCE: f64 = 2e-5;

#[test]
fn the_rust_network_gives_onnxruntimes_probabilities() {
    let x = signal();
    assert_eq!(
        x.len() / CHUNK,
        REFERENCE.len(),
        "the signal changed: rerun the reference"
    );
    let mut net = Silero::new();
    let mut worst = (0.0f64, 0);
    for (k, (chunk, want)) in x.chunks_exact(CHUNK).zip(REFERENCE).enumerate() {
        let p = net.step(chunk.try_into().expect("a chunk"));
        let d = (f64::from(p) - want).abs();
        if d > worst.0 {
            worst = (d, k);
        }
    }
    assert!(
        worst.0 <= TOLERANCE,
        "chunk {} differs from onnxruntime by {}",
        worst.1,
        worst.0
    );
    // The signal spans the whole range: speech near 1, silence and noise near 0.
    assert!(REFERENCE.iter().any(|&p| p > 0.99) && REFERENCE.iter().any(|&p| p < 0.01));
    // After a reset the same chunks give the same probabilities again.
    net.reset();
    let again: Vec<f32> = x
        .chunks_exact(CHUNK)
        .map(|c| net.step(c.try_into().expect("a chunk")))
        .collect();
    let mut fresh = Silero::new();
    let first: Vec<f32> = x
        .chunks_exact(CHUNK)
        .map(|c| fresh.step(c.try_into().expect("a chunk")))
        .collect();
    assert_eq!(again, first);
}

#[test]
#[ignore = "writes the signal for the reference command in the module docs"]
fn write_the_signal() {
    let path = std::env::var("PNEUMA_SILERO_SIGNAL").expect("PNEUMA_SILERO_SIGNAL=<path>");
    let bytes: Vec<u8> = signal().iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(path, bytes).expect("write the signal");
}

/// A block of garbage in a float file (finite but absurd, ±1e20: a corrupt or unnormalised
/// take) must not leave the network's state NaN, which would call nothing speech for the
/// rest of the stream: the speech after it is heard as speech again.
#[test]
fn speech_after_a_block_of_absurd_samples_is_speech_again() {
    let x = signal();
    let chunks: Vec<&[f32; CHUNK]> = x
        .chunks_exact(CHUNK)
        .map(|c| c.try_into().expect("a chunk"))
        .collect();
    for garbage in [1e20f32, -1e20, 3.0e38] {
        let mut net = Silero::new();
        let mut alternating = [garbage; CHUNK];
        alternating.iter_mut().step_by(2).for_each(|v| *v = -*v);
        for bad in [[garbage; CHUNK], alternating] {
            let p = net.step(&bad);
            assert!(p.is_finite(), "{garbage}: {p}");
        }
        let after: Vec<f32> = chunks.iter().map(|c| net.step(c)).collect();
        assert!(after.iter().all(|p| p.is_finite()), "{garbage}: {after:?}");
        // The phrase (chunks 15–70 of the reference lie over 0.9) is speech again.
        let speech = after[20..70].iter().filter(|&&p| p > 0.5).count();
        assert!(speech >= 45, "{garbage}: {speech} of 50 chunks of speech");
    }
}
