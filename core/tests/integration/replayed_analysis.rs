//! A whole-file render that learns the voice first analyses the file once: the learning pass
//! records its analysis and the render's engine replays it (`Engine::replay_analysis`). The
//! render is then the same, bit for bit, as one that analyses the file again, for any number
//! of channels (the learning pass mixes them as the engine does), any block partition and
//! broken samples; it never allocates; an input longer than the record is counted, never
//! silently analysed as something else.

use pneuma_core::engine::voice_learning::{Learned, VoiceLearner};
use pneuma_core::engine::{offline, BreathVoiceMode, Engine, EngineConfig};
use pneuma_core::head::HeadModel;
use pneuma_testkit::signals;

use crate::support::watched;

const RATE_HZ: f64 = 16_000.0;

fn config() -> EngineConfig {
    let mut c = EngineConfig::default();
    c.placement.whole_file = true;
    // The generated speaker's sustained vowels are not speech to the speech decision.
    c.placement.speech_only = false;
    c
}

/// `channels` channels of a speaker with breaths in the pauses of the first half (the
/// second half's were cut out), each channel another mix (a level, a little noise of its
/// own), with a few broken samples.
fn recording(channels: usize, seconds: f64) -> Vec<Vec<f32>> {
    let with = signals::phrases_with_breaths(RATE_HZ, seconds, 5);
    let without = signals::phrases_with_pauses(RATE_HZ, seconds, 60.0, 5);
    let cut = with.len() / 2;
    let x: Vec<f32> = with[..cut].iter().chain(&without[cut..]).copied().collect();
    (0..channels)
        .map(|c| {
            let noise =
                signals::band_noise(x.len(), RATE_HZ, (200.0, 6000.0), 0.003, 40 + c as u64);
            let gain = 1.0 - 0.3 * c as f32;
            let mut ch: Vec<f32> = x.iter().zip(&noise).map(|(v, n)| gain * v + n).collect();
            ch[1000 + 7 * c] = f32::NAN;
            ch[2000] = f32::INFINITY;
            ch
        })
        .collect()
}

fn interleaved(x: &[Vec<f32>]) -> Vec<f32> {
    (0..x[0].len())
        .flat_map(|i| x.iter().map(move |c| c[i]))
        .collect()
}

/// The learning pass over `x`, fed in blocks of `block` frames.
fn learn(x: &[Vec<f32>], block: usize) -> Learned {
    let mut l = VoiceLearner::recording(&config(), RATE_HZ).expect("config");
    let channels = x.len();
    for chunk in interleaved(x).chunks(block * channels) {
        l.feed_interleaved(chunk, channels).expect("prepared");
    }
    l.finish().expect("prepared")
}

fn engine(mode: BreathVoiceMode, channels: usize) -> Engine {
    let mut e = Engine::new(config(), HeadModel::default_model().clone()).expect("config");
    e.set_voice_mode(mode);
    e.prepare(RATE_HZ, 1024, channels).expect("prepare");
    e
}

#[test]
fn a_replayed_learning_pass_renders_as_analysing_again_for_any_channels_and_partition() {
    for channels in [1, 2, 3] {
        let x = recording(channels, 10.0);
        let learned = learn(&x, 777);
        let voice = learned.voice.expect("the speaker's breaths are heard");
        let record = learned
            .record
            .expect("a recording learner keeps its analysis");
        let mode = BreathVoiceMode::Fixed(voice);
        assert_eq!(
            record.samples(),
            x[0].len() as u64 + engine(mode, channels).tail_samples(),
            "the input and the engine's tail"
        );
        let analysed = offline::render(&mut engine(mode, channels), &x, &[1024]);
        assert!(
            analysed.breaths.len() >= 2,
            "{} breaths",
            analysed.breaths.len()
        );
        for blocks in [vec![1024], vec![37, 512, 3]] {
            let mut e = engine(mode, channels);
            e.replay_analysis(record.clone()).expect("same rates");
            let replayed = offline::render(&mut e, &x, &blocks);
            assert!(
                replayed.audio == analysed.audio,
                "{channels} channels, blocks {blocks:?}: the audio differs"
            );
            assert_eq!(replayed.breaths, analysed.breaths, "{channels} channels");
            assert_eq!(replayed.frames.len(), analysed.frames.len());
            assert!(
                replayed
                    .frames
                    .iter()
                    .zip(&analysed.frames)
                    .all(|(a, b)| a == b),
                "{channels} channels, blocks {blocks:?}: the control frames differ"
            );
            assert!(e.dropped().is_none(), "{:?}", e.dropped());
            assert_eq!(e.replay_verified(), Some(true));
        }
    }
}

#[test]
fn a_replayed_render_never_allocates() {
    let x = recording(2, 8.0);
    let learned = learn(&x, 4096);
    let mut e = engine(BreathVoiceMode::Fixed(learned.voice.expect("heard")), 2);
    e.replay_analysis(learned.record.expect("recorded"))
        .expect("same rates");
    let (mut left, mut right) = (x[0].clone(), x[1].clone());
    let mut silence = [vec![0.0f32; 1000], vec![0.0f32; 1000]];
    let mut breaths = 0;
    let ((), n) = watched(|| {
        for (l, r) in left.chunks_mut(1000).zip(right.chunks_mut(1000)) {
            e.process(&mut [l, r], &mut |_, _| {});
            e.take_breaths(|_| breaths += 1);
        }
        for _ in 0..(e.tail_samples() / 1000 + 1) {
            let [l, r] = &mut silence;
            e.process(&mut [&mut l[..], &mut r[..]], &mut |_, _| {});
            e.take_breaths(|_| breaths += 1);
        }
    });
    assert!(breaths >= 1, "no breath inserted");
    assert_eq!(n, 0, "{n} allocations while replaying");
}

#[test]
fn an_input_longer_than_the_replayed_analysis_is_counted_not_analysed() {
    let x = recording(1, 8.0);
    let short = [x[0][..x[0].len() / 2].to_vec()];
    let learned = learn(&short, 4096);
    let record = learned.record.expect("recorded");
    let mut e = engine(BreathVoiceMode::BuiltIn, 1);
    e.replay_analysis(record.clone()).expect("same rates");
    offline::render(&mut e, &x, &[1024]);
    let past = e.dropped().unanalysed_samples;
    assert_eq!(e.replay_verified(), Some(false), "not the samples recorded");
    // The record covers the first half and its tail of silence; the rest was not analysed.
    let expected = x[0].len() as u64 + e.tail_samples() - record.samples();
    assert_eq!(past, expected);
    let mut same = engine(BreathVoiceMode::BuiltIn, 1);
    same.replay_analysis(record).expect("same rates");
    offline::render(&mut same, &short, &[1024]);
    assert_eq!(same.dropped().unanalysed_samples, 0);
    assert_eq!(same.replay_verified(), Some(true));
}

#[test]
fn a_record_of_another_rate_or_other_samples_is_refused() {
    let x = recording(1, 6.0);
    let record = learn(&x, 4096).record.expect("recorded");
    let mut other_rate = Engine::new(config(), HeadModel::default_model().clone()).expect("config");
    other_rate.prepare(2.0 * RATE_HZ, 1024, 1).expect("prepare");
    let err = other_rate
        .replay_analysis(record.clone())
        .expect_err("another rate");
    assert!(err.to_string().contains("record it again"), "{err}");
    // The same length, one sample changed (a file rewritten between the passes).
    let mut changed = x.clone();
    changed[0][12_345] += 0.01;
    let mut e = engine(BreathVoiceMode::BuiltIn, 1);
    e.replay_analysis(record).expect("same rates");
    offline::render(&mut e, &changed, &[1024]);
    assert_eq!(e.dropped().unanalysed_samples, 0);
    assert_eq!(e.replay_verified(), Some(false));
}
