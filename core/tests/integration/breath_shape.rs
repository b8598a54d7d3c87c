//! The spectral shape of breath noise: the frame band levels ([`FeatureFrame::bands`]) are
//! bit-identical for any block partition and at every host rate; a pause holding breath-shaped
//! noise is heard as a breath already there (and gets no second one), while a pause holding
//! /s/-like noise, a decaying reverberant tail or stationary room noise at the same level is
//! not (and gets an inserted breath).

use pneuma_core::analysis::rms;
use pneuma_core::analysis::{AnalysisConfig, Analyzer, FeatureFrame};
use pneuma_core::engine::{offline, Engine, EngineConfig};
use pneuma_core::head::HeadModel;
use pneuma_testkit::signals;

/// The pause between the two phrases, seconds.
const PAUSE_S: (f64, f64) = (2.6, 3.5);
/// Where the sound inside the pause lies, seconds.
const SOUND_S: (f64, f64) = (3.0, 3.3);

/// 1 s of silence, a 1.6 s vowel, a 0.9 s pause, a 1.6 s vowel and 0.8 s of silence at
/// `rate_hz`; `pause` adds its sound to the whole signal given the vowel's RMS.
fn phrases(rate_hz: f64, pause: impl Fn(&mut [f32], f64)) -> Vec<f32> {
    let vowel = || signals::harmonic_tone(rate_hz, 1.6, 0.3, &[1.0, 0.6, 0.4, 0.3, 0.2], |_| 140.0);
    let speech_rms = rms(&vowel());
    let samples = |s: f64| vec![0.0; (s * rate_hz).round() as usize];
    let mut x = samples(PAUSE_S.0 - 1.6);
    x.extend(vowel());
    x.extend(samples(PAUSE_S.1 - PAUSE_S.0));
    x.extend(vowel());
    x.extend(samples(0.8));
    pause(&mut x, speech_rms);
    x
}

/// Adds `len_s` of band-limited noise at `(low, high)` Hz, `re_speech_db` under the speech RMS,
/// from `start_s` on, with 30 ms fades.
fn add_noise(
    x: &mut [f32],
    rate_hz: f64,
    start_s: f64,
    len_s: f64,
    band_hz: (f64, f64),
    level: f64,
) {
    let a = (start_s * rate_hz) as usize;
    let n = (len_s * rate_hz) as usize;
    let fade = 0.03 * rate_hz;
    let noise = signals::band_noise(n, rate_hz, band_hz, level, 21);
    for (i, v) in noise.into_iter().enumerate() {
        let env = ((i.min(n - 1 - i) as f64) / fade).min(1.0) as f32;
        x[a + i] += env * v;
    }
}

/// Adds stationary room noise (50–4000 Hz) of RMS `level` over the whole of `x`.
fn add_room_noise(x: &mut [f32], rate_hz: f64, level: f64) {
    let len_s = x.len() as f64 / rate_hz;
    add_noise(x, rate_hz, 0.0, len_s, (50.0, 4000.0), level);
}

/// The RMS `db` under the speech RMS.
fn under_speech(speech_rms: f64, db: f64) -> f64 {
    speech_rms * 10f64.powf(-db / 20.0)
}

/// Breath spans (start, end), seconds.
type Spans = Vec<(f64, f64)>;

/// Renders `audio` with the default engine in `block` sample blocks; returns the breaths heard
/// in the input and the inserted ones.
fn render(audio: &[f32], rate_hz: f64, block: usize) -> (Spans, Spans) {
    // The phrases are steady tones, which the speech decision calls no speech; this test is
    // about the sound in the pause, so every pause counts.
    let mut config = EngineConfig::default();
    config.placement.speech_only = false;
    let mut engine =
        Engine::new(config, HeadModel::default_model().clone()).expect("default engine");
    engine.prepare(rate_hz, block, 1).expect("prepare");
    let r = offline::render(&mut engine, &[audio.to_vec()], &[block]);
    let inserted = r.breaths.iter().map(|b| (b.start_s, b.end_s)).collect();
    (r.existing_breaths, inserted)
}

fn in_pause(spans: &Spans) -> Spans {
    spans
        .iter()
        .copied()
        .filter(|&(a, b)| a < PAUSE_S.1 && b > PAUSE_S.0)
        .collect()
}

/// The phrases with 0.3 s of `band_hz` noise 25 dB under speech in the pause (at [`SOUND_S`]).
fn with_sound_in_pause(rate_hz: f64, band_hz: (f64, f64)) -> Vec<f32> {
    phrases(rate_hz, |x, s| {
        let len_s = SOUND_S.1 - SOUND_S.0;
        add_noise(x, rate_hz, SOUND_S.0, len_s, band_hz, under_speech(s, 25.0));
    })
}

#[test]
fn breath_shaped_noise_in_a_pause_is_heard_and_gets_no_second_breath() {
    for rate_hz in [16_000.0, 44_100.0] {
        let x = with_sound_in_pause(rate_hz, (500.0, 5000.0));
        let (heard, inserted) = render(&x, rate_hz, 512);
        assert_eq!(heard.len(), 1, "{rate_hz} Hz: heard {heard:?}");
        let (a, b) = heard[0];
        assert!(
            (a - SOUND_S.0).abs() < 0.06 && (b - SOUND_S.1).abs() < 0.06,
            "{rate_hz} Hz: heard at {a:.3}..{b:.3} s, the breath is at {SOUND_S:?}"
        );
        assert!(
            in_pause(&inserted).is_empty(),
            "{rate_hz} Hz: a second breath inserted: {inserted:?}"
        );
    }
}

/// Asserts that the pause between the phrases of `x` holds no heard breath and gets an
/// inserted one. (The leading silence is not judged: noise from the first sample on stands
/// over a noise floor that has not learnt it yet.)
fn assert_no_breath_heard(x: &[f32], what: &str) {
    let (heard, inserted) = render(x, 16_000.0, 512);
    assert!(
        in_pause(&heard).is_empty(),
        "{what} heard as a breath: {heard:?}"
    );
    assert_eq!(
        in_pause(&inserted).len(),
        1,
        "{what}: the pause gets one inserted breath: {inserted:?}"
    );
}

#[test]
fn sibilant_noise_at_a_breaths_level_is_no_breath() {
    let x = with_sound_in_pause(16_000.0, (2500.0, 7500.0));
    assert_no_breath_heard(&x, "/s/-like noise 2.5–7.5 kHz");
}

#[test]
fn a_decaying_reverberant_tail_is_no_breath() {
    // A hall: vowel-coloured noise (100–700 Hz) from the phrase's end, starting 18 dB under
    // speech and falling 60 dB per second, into room noise 45 dB under speech.
    let rate_hz = 16_000.0;
    let x = phrases(rate_hz, |x, s| {
        add_room_noise(x, rate_hz, under_speech(s, 45.0));
        let a = (PAUSE_S.0 * rate_hz) as usize;
        let n = (0.8 * rate_hz) as usize;
        let tail = signals::band_noise(n, rate_hz, (100.0, 700.0), under_speech(s, 18.0), 5);
        for (i, v) in tail.into_iter().enumerate() {
            let t = i as f64 / rate_hz;
            x[a + i] += v * 10f64.powf(-60.0 * t / 20.0) as f32;
        }
    });
    assert_no_breath_heard(&x, "a decaying tail");
}

#[test]
fn stationary_room_noise_is_no_breath() {
    // Room noise (50–4000 Hz) 40 dB under speech over the whole signal.
    let rate_hz = 16_000.0;
    let x = phrases(rate_hz, |x, s| {
        add_room_noise(x, rate_hz, under_speech(s, 40.0))
    });
    assert_no_breath_heard(&x, "stationary room noise");
}

#[test]
fn heard_breaths_are_the_same_for_any_block_partition() {
    let rate_hz = 16_000.0;
    let x = with_sound_in_pause(rate_hz, (500.0, 5000.0));
    let want = render(&x, rate_hz, 512);
    assert_eq!(want.0.len(), 1, "{want:?}");
    for block in [1usize, 37, 4096] {
        assert_eq!(render(&x, rate_hz, block), want, "blocks of {block}");
    }
}

/// The frames of `x` analysed in blocks whose sizes cycle through `sizes`.
fn frames_in_blocks(x: &[f32], rate_hz: f64, sizes: &[usize]) -> Vec<FeatureFrame> {
    let mut a = Analyzer::new(AnalysisConfig::default()).expect("default config");
    a.prepare(rate_hz, 4096).expect("supported rate");
    let mut frames = Vec::new();
    let mut rest = x;
    for &n in sizes.iter().cycle() {
        if rest.is_empty() {
            break;
        }
        let (block, after) = rest.split_at(n.min(rest.len()));
        a.process(block, |f| frames.push(*f)).expect("prepared");
        rest = after;
    }
    a.finish(|f| frames.push(*f)).expect("prepared");
    frames
}

#[test]
fn band_levels_are_bit_identical_for_any_block_partition() {
    for rate_hz in [8_000.0, 20_000.0, 44_100.0, 192_000.0] {
        let mut x = signals::harmonic_tone(rate_hz, 0.4, 0.3, &[1.0, 0.5, 0.3], |_| 150.0);
        x.extend(signals::white_noise((0.3 * rate_hz) as usize, 0.02, 9));
        let bits = |v: &[FeatureFrame]| -> Vec<[u32; 3]> {
            v.iter()
                .map(|f| {
                    [
                        f.bands.low_db.to_bits(),
                        f.bands.mid_db.to_bits(),
                        f.bands.high_db.to_bits(),
                    ]
                })
                .collect()
        };
        let want = bits(&frames_in_blocks(&x, rate_hz, &[4096]));
        assert!(want.len() > 50, "{rate_hz}: {} frames", want.len());
        for size in [1usize, 37, 512] {
            assert_eq!(
                bits(&frames_in_blocks(&x, rate_hz, &[size])),
                want,
                "{rate_hz} Hz in blocks of {size}"
            );
        }
        let uneven = bits(&frames_in_blocks(&x, rate_hz, &[1, 300, 7, 2048, 64]));
        assert_eq!(uneven, want, "{rate_hz} Hz in uneven blocks");
    }
}
