//! `process` and `finish` never allocate, at any rate and block size: a counting global
//! allocator watches the thread while the analyzer runs, and while the engine runs into the
//! sinks a plugin drives (MIDI CC and OSC encoders).

use pneuma_core::encode::midi_cc::{CcEncoder, CcMap};
use pneuma_core::encode::osc::{OscFormat, TimeTag};
use pneuma_core::encode::sink::{CcSink, FrameSink, OscSink};
use pneuma_core::{AnalysisConfig, Analyzer, BreathEvent, ControlFrame};
use pneuma_testkit::signals;

/// Counts frames and breaths.
#[derive(Default)]
struct Count {
    frames: usize,
    breaths: usize,
}

impl FrameSink for Count {
    fn frame(&mut self, _: &ControlFrame, _: u64) {
        self.frames += 1;
    }
    fn breath(&mut self, _: &BreathEvent) {
        self.breaths += 1;
    }
}

use crate::support::watched;

#[test]
fn the_counter_sees_allocations() {
    let (_, n) = watched(|| vec![1u8; 100]);
    assert!(n >= 1);
}

#[test]
fn process_never_allocates() {
    for rate in [
        8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 96_000.0, 192_000.0,
    ] {
        let mut x = signals::harmonic_tone(rate, 1.0, 0.5, &[1.0, 0.5, 0.3], |t| 100.0 + 200.0 * t);
        x[1000] = f32::NAN;
        let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
        a.prepare(rate, 4096).expect("rate");
        let mut frames = 0usize;
        let ((), n) = watched(|| {
            for (i, size) in [1usize, 37, 512, 4096].iter().cycle().enumerate() {
                let start = (i * 1000) % (x.len() - 4096);
                a.process(&x[start..start + size], |_| frames += 1)
                    .expect("prepared");
                if i > 200 {
                    break;
                }
            }
            a.finish(|_| frames += 1).expect("prepared");
            a.reset();
        });
        assert!(frames > 10);
        assert_eq!(n, 0, "{n} allocations at {rate} Hz");
    }
}

/// Speech-like phrases with pauses at `rate` (so that the speech decision lets breaths in):
/// 0.8 s of glottal vowels in 0.2 s syllables, 0.6 s silence (with a breath-like burst in two
/// pauses of three), repeated.
fn phrases(rate: f64, seconds: f64) -> Vec<f32> {
    use pneuma_testkit::signals::{GlottalVowel, Vowel};
    let mut x = Vec::new();
    let mut k = 0u64;
    while (x.len() as f64) < seconds * rate {
        let t = x.len() as f64 / rate;
        if k % 5 < 4 {
            let v = signals::glottal_vowel(
                &GlottalVowel {
                    sample_rate_hz: rate,
                    length_s: 0.2,
                    vowel: [Vowel::A, Vowel::I, Vowel::U][(k % 3) as usize],
                    jitter: 0.01,
                    shimmer: 0.05,
                    peak: 0.4,
                    seed: k,
                },
                |s| 130.0 + 30.0 * (2.0 * (t + s)).sin(),
            );
            let n = v.len();
            x.extend(v.iter().enumerate().map(|(i, y)| {
                y * (0.3 + 0.7 * (std::f64::consts::PI * i as f64 / n as f64).sin()) as f32
            }));
        } else {
            // A breath-like burst early in the first pause, late in the second, none in the
            // third, and so on: live mode hears it before its breath starts (kept silent) or
            // while it plays (faded out); the third pause gets its breath.
            let mut pause = vec![0.0f32; (0.6 * rate) as usize];
            if let Some(from_s) = [Some(0.05), Some(0.3), None][(k / 5 % 3) as usize] {
                let (a, b) = ((from_s * rate) as usize, ((from_s + 0.25) * rate) as usize);
                for (p, n) in pause[a..b]
                    .iter_mut()
                    .zip(signals::white_noise(b - a, 0.01, k))
                {
                    *p = n;
                }
            }
            x.extend(pause);
        }
        k += 1;
    }
    x.truncate((seconds * rate) as usize);
    x[777] = f32::NAN;
    x[1234] = f32::INFINITY;
    x
}

#[test]
fn the_engine_never_allocates_while_processing() {
    use pneuma_core::engine::{Engine, EngineConfig, PlacementMode};
    use pneuma_core::head::HeadModel;
    for (rate, channels, mode) in [
        (44_100.0, 1usize, PlacementMode::Lookahead),
        (48_000.0, 2, PlacementMode::Lookahead),
        (16_000.0, 1, PlacementMode::Live),
        (96_000.0, 2, PlacementMode::Live),
    ] {
        let x = phrases(rate, 4.5);
        let mut config = EngineConfig::default();
        config.placement.mode = mode;
        let mut engine = Engine::new(config, HeadModel::default_model().clone()).expect("config");
        engine.prepare(rate, 1024, channels).expect("prepare");
        let mut bufs = vec![x.clone(); channels];
        let mut counted = Count::default();
        let mut encoder = CcEncoder::new(CcMap::default()).expect("default map");
        let (mut cc_messages, mut osc_bytes) = (0usize, 0usize);
        let ((), n) = watched(|| {
            // The outputs a plugin drives: MIDI CC and OSC encoders as sinks.
            let cc = CcSink::new(&mut encoder, |_, _| cc_messages += 1);
            let osc = OscSink::new(
                OscFormat::Vmc,
                |f: &ControlFrame| TimeTag::from_unix_seconds(f.time_s),
                |_: &ControlFrame, bytes: &[u8]| osc_bytes += bytes.len(),
            );
            let mut sinks = (&mut counted, cc, osc);
            let mut pos = 0;
            for size in [1usize, 37, 512, 1024, 3000].iter().cycle() {
                if pos >= x.len() {
                    break;
                }
                let size = (*size).min(x.len() - pos);
                let (a, b) = bufs.split_at_mut(1);
                let mut chans: [&mut [f32]; 2] = match b.first_mut() {
                    Some(r) => [&mut a[0][pos..pos + size], &mut r[pos..pos + size]],
                    None => [&mut a[0][pos..pos + size], &mut []],
                };
                engine.process_into(&mut chans[..channels], pos as u64, &mut sinks);
                pos += size;
            }
            engine.finish();
            engine.take_breaths(|b| sinks.breath(b));
            engine.reset();
        });
        let Count { frames, breaths } = counted;
        assert!(frames > 100, "{frames} frames");
        assert!(breaths >= 1, "no breath inserted at {rate} Hz");
        assert!(cc_messages > frames, "{cc_messages} CC messages");
        assert!(osc_bytes > 100 * frames, "{osc_bytes} OSC bytes");
        assert_eq!(
            n, 0,
            "{n} allocations at {rate} Hz, {channels} ch, {mode:?}"
        );
    }
}
