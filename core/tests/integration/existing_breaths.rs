//! Breaths already in the input: a breath-like noise burst in a pause between two phrases is
//! reported by `Engine::take_existing_breaths` with its time, and no breath is inserted over it;
//! the same phrases with a quiet pause report none. A burst an editor's cut left short (digital
//! silence where the rest of it was) gets the rest put back beside it.

use pneuma_core::engine::{offline, Engine, EngineConfig, PlacementMode};
use pneuma_core::head::HeadModel;
use pneuma_testkit::signals;

const RATE_HZ: f64 = 16_000.0;
/// The breath-like burst inside the pause, seconds.
const BURST_S: (f64, f64) = (2.0, 2.35);

/// A 1.6 s vowel, a 0.9 s pause (with the burst when `with_burst`), a 1.6 s vowel, 0.8 s of
/// silence.
fn phrases(with_burst: bool) -> Vec<f32> {
    phrases_with_burst(with_burst.then_some(BURST_S))
}

/// [`phrases`] with the burst at `burst_s` (seconds, inside the pause at 1.6–2.5 s).
fn phrases_with_burst(burst_s: Option<(f64, f64)>) -> Vec<f32> {
    let vowel = || signals::harmonic_tone(RATE_HZ, 1.6, 0.3, &[1.0, 0.6, 0.4, 0.3, 0.2], |_| 140.0);
    let mut x = vowel();
    let pause_start = x.len();
    x.extend(vec![0.0; (0.9 * RATE_HZ) as usize]);
    if let Some((a_s, b_s)) = burst_s {
        // About 26 dB under the vowels' level: breath noise, unvoiced, not a phrase.
        let a = (a_s * RATE_HZ) as usize;
        let b = (b_s * RATE_HZ) as usize;
        let noise = signals::white_noise(b - a, 0.01, 7);
        for (i, n) in noise.into_iter().enumerate() {
            let ramp = ((i.min(b - a - 1 - i) as f32) / 160.0).min(1.0);
            x[a + i] += n * ramp;
        }
    }
    assert!(burst_s.is_none_or(|(a_s, _)| pause_start < (a_s * RATE_HZ) as usize));
    x.extend(vowel());
    x.extend(vec![0.0; (0.8 * RATE_HZ) as usize]);
    x
}

/// Breath spans (start, end), seconds.
type Spans = Vec<(f64, f64)>;

/// Runs the engine over `audio` in 256-sample blocks; returns the existing breaths and the
/// inserted ones.
fn run(audio: &[f32]) -> (Spans, Spans) {
    run_in(audio, PlacementMode::Lookahead)
}

/// [`run`] in placement mode `mode`.
fn run_in(audio: &[f32], mode: PlacementMode) -> (Spans, Spans) {
    let r = render_in(audio, mode, &[256]);
    let inserted = r.breaths.iter().map(|b| (b.start_s, b.end_s)).collect();
    (r.existing_breaths, inserted)
}

/// The engine's render of `audio` in placement mode `mode`, in blocks of `blocks` samples.
fn render_in(audio: &[f32], mode: PlacementMode, blocks: &[usize]) -> offline::Rendered {
    // The phrases are steady tones, which the speech decision calls no speech; this test is
    // about the sound in the pause, so every pause counts.
    let mut config = EngineConfig::default();
    config.placement.speech_only = false;
    config.placement.mode = mode;
    let mut engine =
        Engine::new(config, HeadModel::default_model().clone()).expect("default engine");
    engine.prepare(RATE_HZ, 256, 1).expect("prepare");
    offline::render(&mut engine, &[audio.to_vec()], blocks)
}

#[test]
fn a_breath_in_a_pause_is_reported_with_its_time_and_nothing_is_inserted_over_it() {
    let (existing, inserted) = run(&phrases(true));
    assert_eq!(existing.len(), 1, "one breath already there: {existing:?}");
    let (start_s, end_s) = existing[0];
    assert!(
        (start_s - BURST_S.0).abs() < 0.05 && (end_s - BURST_S.1).abs() < 0.05,
        "reported at {start_s:.3}..{end_s:.3} s, the burst is at {BURST_S:?}"
    );
    assert!(
        inserted.iter().all(|&(a, b)| b <= 1.6 || a >= 2.5),
        "a breath inserted in the pause that holds one: {inserted:?}"
    );
}

#[test]
fn a_quiet_pause_reports_no_breath_already_there() {
    let (existing, inserted) = run(&phrases(false));
    assert!(existing.is_empty(), "{existing:?}");
    assert!(
        inserted.iter().any(|&(a, b)| a >= 1.6 && b <= 2.5),
        "the quiet pause gets an inserted breath: {inserted:?}"
    );
}

/// [`phrases`] over a music bed: a chord (A major, four harmonics a note) about 30 dB under the
/// vowels all along, which swells by 7 dB over the burst's span in the pause when `swell`
/// (over the breath margin, under the level a phrase starts at).
fn phrases_over_a_bed(breath: bool, swell: bool) -> Vec<f32> {
    let mut x = phrases(breath);
    let len_s = x.len() as f64 / RATE_HZ;
    for f0 in [440.0, 554.37, 659.25] {
        let note = signals::harmonic_tone(RATE_HZ, len_s, 0.004, &[1.0, 0.5, 0.3, 0.2], |_| f0);
        for (i, (v, n)) in x.iter_mut().zip(note).enumerate() {
            let t = i as f64 / RATE_HZ;
            // 20 ms ramps into and out of the swell.
            let up = ((t - BURST_S.0) / 0.02)
                .min((BURST_S.1 - t) / 0.02)
                .clamp(0.0, 1.0);
            let gain = if swell { 1.0 + (2.24 - 1.0) * up } else { 1.0 };
            *v += n * gain as f32;
        }
    }
    x
}

#[test]
fn a_music_bed_swelling_in_a_pause_is_no_breath_and_a_breath_over_it_is_one() {
    // The chord's swell is as loud over the bed as a breath would be, and unvoiced, but tonal:
    // the pause gets its inserted breath.
    let (existing, inserted) = run(&phrases_over_a_bed(false, true));
    assert!(
        existing.is_empty(),
        "the swell taken for a breath: {existing:?}"
    );
    assert!(
        inserted.iter().any(|&(a, b)| a >= 1.6 && b <= 2.5),
        "the pause under the bed gets an inserted breath: {inserted:?}"
    );
    // A breath's noise over the same bed (no swell) is heard, and nothing is inserted over it.
    let (existing, inserted) = run(&phrases_over_a_bed(true, false));
    assert_eq!(existing.len(), 1, "the breath over the bed: {existing:?}");
    assert!(
        !inserted
            .iter()
            .any(|&(a, b)| a < BURST_S.1 && b > BURST_S.0),
        "a breath inserted over the real one: {inserted:?}"
    );
}

#[test]
fn live_mode_never_doubles_a_breath_already_there() {
    // Live mode starts its breath once the pause has lasted the minimum pause (0.25 s after
    // the offset at 1.6 s, at 1.85 s): a speaker who breathes in at once (at 1.65 s) is heard
    // before that, and one who breathes in later (at 2.0 s) while the inserted breath plays.
    let fade_s = f64::from(EngineConfig::default().placement.live_fade_s);
    let heard_after_s = f64::from(pneuma_core::settings::phrase::BREATH_MIN_S.default);
    let cases = [
        ((1.65, 2.0), None),
        ((2.0, 2.35), Some(2.0 + heard_after_s)),
    ];
    for (burst_s, faded_by_s) in cases {
        let (existing, inserted) = run_in(&phrases_with_burst(Some(burst_s)), PlacementMode::Live);
        assert_eq!(existing.len(), 1, "burst at {burst_s:?}: {existing:?}");
        let in_pause: Vec<_> = inserted
            .iter()
            .filter(|&&(a, b)| b > 1.6 && a < 2.5)
            .collect();
        match faded_by_s {
            None => assert!(
                in_pause.is_empty(),
                "burst at {burst_s:?}: a breath inserted over it: {in_pause:?}"
            ),
            // The breath that began before the burst fades out once the burst is heard.
            Some(by_s) => assert!(
                in_pause.iter().all(|&&(_, b)| b <= by_s + fade_s + 0.03),
                "burst at {burst_s:?}: the inserted breath plays on over it: {in_pause:?}"
            ),
        }
    }
    // The breath kept silent still breathes in: the cycle inspires in the pause.
    let r = render_in(
        &phrases_with_burst(Some((1.65, 2.0))),
        PlacementMode::Live,
        &[256],
    );
    assert!(
        r.frames.iter().map(|f| &f.0).any(|f| f.time_s > 1.6
            && f.time_s < 2.5
            && f.breathing.phase == pneuma_core::Phase::Inspiration),
        "no inspiration in the pause whose breath is the speaker's"
    );
    // Any block partition hears the burst at the same sample and fades the same breath.
    let audio = phrases_with_burst(Some((2.0, 2.35)));
    let whole = render_in(&audio, PlacementMode::Live, &[256]);
    for blocks in [&[1usize][..], &[37], &[1000, 3, 512]] {
        let other = render_in(&audio, PlacementMode::Live, blocks);
        let bits = |r: &offline::Rendered| -> Vec<u32> {
            r.audio[0].iter().map(|x| x.to_bits()).collect()
        };
        assert!(
            bits(&other) == bits(&whole) && other.breaths == whole.breaths,
            "blocks {blocks:?}: a different render"
        );
    }
    // Without a burst the pause gets its live breath.
    let (_, inserted) = run_in(&phrases_with_burst(None), PlacementMode::Live);
    assert!(
        inserted.iter().any(|&(a, b)| a >= 1.6 && b <= 2.5),
        "the quiet pause gets a live breath: {inserted:?}"
    );
}

/// Times of the frames of `r` inside `(from_s, to_s)` whose cycle inspires, seconds.
fn inspiring_s(r: &offline::Rendered, (from_s, to_s): (f64, f64)) -> Vec<f64> {
    r.frames
        .iter()
        .map(|f| &f.0)
        .filter(|f| f.time_s > from_s && f.time_s < to_s)
        .filter(|f| f.breathing.phase == pneuma_core::Phase::Inspiration)
        .map(|f| f.time_s)
        .collect()
}

/// [`phrases`] in a room whose 40 Hz hum carries its level (the input gate, which reads the
/// whole band, hears nothing of a soft breath over it), with a soft 0.35 s breath (band noise
/// 0.5–4 kHz) from `from_s`.
fn hum_room_with_breath(from_s: f64) -> Vec<f32> {
    let rate = RATE_HZ;
    let mut x = phrases(false);
    let room = signals::white_noise(x.len(), 3e-4, 11);
    for (i, (v, n)) in x.iter_mut().zip(room).enumerate() {
        let t = i as f64 / rate;
        *v += n + 0.02 * (std::f64::consts::TAU * 40.0 * t).sin() as f32;
    }
    let (a, b) = ((from_s * rate) as usize, ((from_s + 0.35) * rate) as usize);
    let breath = signals::band_noise(b - a, rate, (500.0, 4000.0), 2e-3, 13);
    for (i, n) in breath.into_iter().enumerate() {
        let ramp = ((i.min(b - a - 1 - i) as f32) / 160.0).min(1.0);
        x[a + i] += n * ramp;
    }
    x
}

#[test]
fn live_mode_breathes_in_with_a_breath_before_the_first_phrase() {
    // A stream that starts with 1 s of silence holding the speaker's breath at 0.4–0.75 s, then
    // the phrases: live mode's cycle inspires with that breath as with one between phrases
    // (before, only a pause after a phrase could), and the first phrase breathes out from the
    // lung it filled, with no step when the phrase is confirmed.
    let burst = (0.4, 0.75);
    let lead = (1.0 * RATE_HZ) as usize;
    let mut audio = vec![0.0; lead];
    let (a, b) = ((burst.0 * RATE_HZ) as usize, (burst.1 * RATE_HZ) as usize);
    for (i, n) in signals::white_noise(b - a, 0.01, 7).into_iter().enumerate() {
        let ramp = ((i.min(b - a - 1 - i) as f32) / 160.0).min(1.0);
        audio[a + i] = n * ramp;
    }
    audio.extend(phrases(false));
    let heard_s = burst.0 + f64::from(pneuma_core::settings::phrase::BREATH_MIN_S.default) + 0.02;
    let r = render_in(&audio, PlacementMode::Live, &[256]);
    let in_breath = r
        .frames
        .iter()
        .filter(|f| f.0.time_s > heard_s && f.0.time_s < burst.1 - 0.05)
        .count();
    let inspiring = inspiring_s(&r, (heard_s, burst.1 - 0.05));
    assert!(
        in_breath > 0 && inspiring.len() == in_breath,
        "{} of {in_breath} frames inside the breath before the first phrase inspire",
        inspiring.len()
    );
    let lung = |f: &(pneuma_core::ControlFrame, u64)| f.0.breathing.lung;
    let speaking = r.frames.iter().position(|f| f.0.speaking).expect("speech");
    let (before, first) = (lung(&r.frames[speaking - 1]), lung(&r.frames[speaking]));
    assert!(
        before > 0.3 && (first - before).abs() < 0.02,
        "lung {before:.3} before the first phrase, {first:.3} at its first frame"
    );
    // Any block partition gives the same control frames.
    for blocks in [&[1usize][..], &[37], &[1000, 3, 512]] {
        let other = render_in(&audio, PlacementMode::Live, blocks);
        assert!(other.frames == r.frames, "blocks {blocks:?}: other frames");
    }
}

#[test]
fn live_mode_starts_no_breath_over_breath_noise_not_yet_confirmed() {
    // A room with a hum ([`hum_room_with_breath`]) and a soft breath that begins 0.05 s before
    // live mode's breath is due (1.85 s): it is not confirmed a breath by then, but it is under
    // way, and the inserted breath stays silent (without that, it plays until the breath is
    // confirmed). The same breath starting after the inserted one gives it a fade as soon as it
    // is under way.
    let fade_s = f64::from(EngineConfig::default().placement.live_fade_s);
    let under_way_s = f64::from(pneuma_core::phrase::BREATH_UNDER_WAY_S);
    let in_pause = |r: &offline::Rendered| -> Vec<(f64, f64)> {
        r.breaths
            .iter()
            .map(|b| (b.start_s, b.end_s))
            .filter(|&(a, b)| b > 1.6 && a < 2.5)
            .collect()
    };
    let early = render_in(&hum_room_with_breath(1.80), PlacementMode::Live, &[256]);
    assert!(
        in_pause(&early).is_empty(),
        "a breath inserted over the one under way: {:?}",
        in_pause(&early)
    );
    let late = render_in(&hum_room_with_breath(2.0), PlacementMode::Live, &[256]);
    let spans = in_pause(&late);
    assert!(
        !spans.is_empty()
            && spans
                .iter()
                .all(|&(_, b)| b <= 2.0 + under_way_s + fade_s + 0.04),
        "the inserted breath does not give way to the one under way: {spans:?}"
    );
    // Any block partition hears the breath under way at the same frame.
    for blocks in [&[1usize][..], &[37], &[1000, 3, 512]] {
        let other = render_in(&hum_room_with_breath(2.0), PlacementMode::Live, blocks);
        assert_eq!(other.breaths, late.breaths, "blocks {blocks:?}");
    }
}

#[test]
fn live_mode_breathes_in_with_the_speakers_own_breath() {
    // The speaker breathes in at 2.0–2.35 s, after live mode's breath began (1.85 s): the
    // input gate hears the breath at once (which stops the inspiration), and once it counts as
    // a breath (after the shortest heard breath) the cycle inspires with it for as long as it
    // lasts.
    let heard_s = 2.0 + f64::from(pneuma_core::settings::phrase::BREATH_MIN_S.default) + 0.02;
    let r = render_in(
        &phrases_with_burst(Some((2.0, 2.35))),
        PlacementMode::Live,
        &[256],
    );
    let in_breath: Vec<_> = r
        .frames
        .iter()
        .map(|f| &f.0)
        .filter(|f| f.time_s > heard_s && f.time_s < 2.3)
        .collect();
    let inspiring = in_breath
        .iter()
        .filter(|f| f.breathing.phase == pneuma_core::Phase::Inspiration)
        .count();
    assert!(
        !in_breath.is_empty() && inspiring == in_breath.len(),
        "{inspiring} of {} frames inside the speaker's breath inspire",
        in_breath.len()
    );
    let lung_at = |t: f64| {
        r.frames
            .iter()
            .map(|f| &f.0)
            .find(|f| f.time_s >= t)
            .map(|f| f.breathing.lung)
    };
    assert!(
        lung_at(2.3) > lung_at(heard_s),
        "the lung does not rise inside the breath: {:?} -> {:?}",
        lung_at(heard_s),
        lung_at(2.3)
    );
    // Any block partition gives the same control frames.
    let audio = phrases_with_burst(Some((2.0, 2.35)));
    for blocks in [&[1usize][..], &[37], &[1000, 3, 512]] {
        let other = render_in(&audio, PlacementMode::Live, blocks);
        assert!(other.frames == r.frames, "blocks {blocks:?}: other frames");
    }
    // A breath heard before live mode's breath is due (it begins at 1.65 s and counts by
    // about 1.8 s; the live breath was due at 1.85 s) gives the pause one inspiration of the
    // preset's length from when it was heard, not one started over when the live breath falls
    // due. (The room's hum keeps the input gate from cancelling the live breath on its own.)
    let length_s = f64::from(EngineConfig::default().breathing.map().length_inspiration_s);
    let early = render_in(&hum_room_with_breath(1.65), PlacementMode::Live, &[256]);
    let inspiring = inspiring_s(&early, (1.6, 3.0));
    let (first, last) = (inspiring[0], inspiring[inspiring.len() - 1]);
    assert!(
        first < 1.85 && last - first <= length_s + 0.02,
        "inspiration {first:.3}–{last:.3} s; one of {length_s} s begun when the breath was heard"
    );
}

#[test]
fn the_breathing_cycle_breathes_in_with_the_breath_already_there() {
    for whole_file in [false, true] {
        let mut c = EngineConfig::default();
        c.placement.whole_file = whole_file;
        // Steady tones are no speech, and a breath between two phrases that are not speech
        // does not drive the cycle: the decision is off, as in `run`.
        c.placement.speech_only = false;
        let mut engine = Engine::new(c, HeadModel::default_model().clone()).expect("engine");
        engine.prepare(RATE_HZ, 256, 1).expect("prepare");
        let r = pneuma_core::engine::offline::render(&mut engine, &[phrases(true)], &[256]);
        assert!(
            r.breaths.iter().all(|b| b.end_s <= 1.6 || b.start_s >= 2.5),
            "whole file {whole_file}: a second breath in the pause: {:?}",
            r.breaths
        );
        // The inspiration in the pause (1.6–2.5 s) lies on the burst and covers most of it.
        let inspiring = inspiring_s(&r, (1.6, 2.5));
        let (first, last) = (inspiring.first(), inspiring.last());
        let covered_s = inspiring.len() as f64 / 120.0;
        assert!(
            first.is_some_and(|&t| (t - BURST_S.0).abs() < 0.05)
                && last.is_some_and(|&t| (t - BURST_S.1).abs() < 0.05)
                && covered_s >= 0.8 * (BURST_S.1 - BURST_S.0),
            "whole file {whole_file}: inspiration at {first:?}..{last:?} ({covered_s:.3} s), \
             the breath at {BURST_S:?}"
        );
    }
}

#[test]
fn a_longer_breath_already_there_fills_the_lung_deeper_before_the_same_group() {
    // The same phrases, the same coming group (one 1.6 s vowel): the speaker's inhalation is
    // 0.3 s or 0.7 s long. The lung's peak over the pause follows the breath's length.
    let peak = |burst_s: (f64, f64)| {
        let r = render_in(
            &phrases_with_burst(Some(burst_s)),
            PlacementMode::Lookahead,
            &[256],
        );
        assert_eq!(
            r.existing_breaths.len(),
            1,
            "{burst_s:?}: {:?}",
            r.existing_breaths
        );
        r.frames
            .iter()
            .map(|f| &f.0)
            .filter(|f| f.time_s > 1.6 && f.time_s < 2.6)
            .map(|f| f.breathing.lung)
            .fold(0.0f32, f32::max)
    };
    let (short, long) = (peak((1.9, 2.2)), peak((1.7, 2.4)));
    assert!(
        long >= short + 0.2 && long > 0.9,
        "lung peak after a 0.3 s breath {short:.3}, after a 0.7 s one {long:.3}"
    );
}

#[test]
fn a_breath_cut_short_by_digital_silence_gets_its_rest_put_back_beside_it() {
    // The burst's first 0.15 s, then the cut: digital silence to the next phrase (the pause is
    // zeros around the burst in `phrases`); then the same file exported at 16 bits with TPDF
    // dither, as an editor's export leaves it (the cut holds dither, about -96 dBFS, not
    // zeros).
    let mut cut = phrases(true);
    let cut_at = ((BURST_S.0 + 0.15) * RATE_HZ) as usize;
    cut[cut_at..(BURST_S.1 * RATE_HZ) as usize].fill(0.0);
    for (name, audio) in [("zeros", cut.clone()), ("dithered", dithered_16_bit(&cut))] {
        assert_rest_put_back_beside_remnant(name, &audio);
    }
}

#[test]
fn a_breath_an_editor_attenuated_gets_put_back_beside_what_is_left_of_it() {
    // A room (white noise at -60 dBFS) under the phrases; the burst 14 dB over it, its first
    // 0.15 s left and the rest lowered by 40 dB, as a de-breath tool does (the room with it):
    // that stretch lies far under the room, where no recorded room falls, not at a cut's
    // dither. What is left is heard as the pause's breath, and the rest goes back beside it.
    // Before, the remnant passed for the whole breath and nothing went back.
    let mut x = phrases(false);
    let room = signals::white_noise(x.len(), 1e-3, 21);
    let (a, b) = (
        (BURST_S.0 * RATE_HZ) as usize,
        (BURST_S.1 * RATE_HZ) as usize,
    );
    let burst = signals::white_noise(b - a, 5e-3, 7);
    for (v, n) in x.iter_mut().zip(room) {
        *v += n;
    }
    for (i, n) in burst.into_iter().enumerate() {
        let ramp = ((i.min(b - a - 1 - i) as f32) / 160.0).min(1.0);
        x[a + i] += n * ramp;
    }
    let cut_at = ((BURST_S.0 + 0.15) * RATE_HZ) as usize;
    for v in &mut x[cut_at..b] {
        *v *= 0.01;
    }
    assert_rest_put_back_beside_remnant("attenuated", &x);
}

/// `audio` (the phrases, with a breath in the pause that an edit left short) gets one breath
/// heard, the remnant, and one put back in the pause from the remnant's end.
fn assert_rest_put_back_beside_remnant(name: &str, audio: &[f32]) {
    let (existing, inserted) = run(audio);
    assert_eq!(
        existing.len(),
        1,
        "{name}: the remnant is heard: {existing:?}"
    );
    let remnant_end_s = existing[0].1;
    let beside: Vec<_> = inserted
        .iter()
        .filter(|&&(a, b)| a >= 1.6 && b <= 2.5)
        .collect();
    assert_eq!(
        beside.len(),
        1,
        "{name}: one breath put back in the pause: {inserted:?}"
    );
    let (start_s, end_s) = *beside[0];
    assert!(
        (start_s - remnant_end_s).abs() < 0.06 && end_s - start_s >= 0.12,
        "{name}: put back at {start_s:.3}..{end_s:.3} s, the remnant ends at \
         {remnant_end_s:.3} s"
    );
}

/// `x` quantised to 16 bits with TPDF dither of one least step (seeded).
fn dithered_16_bit(x: &[f32]) -> Vec<f32> {
    let mut rng = pneuma_core::rng::SeededRng::new(16);
    x.iter()
        .map(|&v| {
            let tpdf = rng.uniform() - rng.uniform();
            ((f64::from(v) * 32_768.0 + tpdf).round() / 32_768.0) as f32
        })
        .collect()
}

#[test]
fn a_breath_after_a_bed_stopped_under_speech_is_heard_and_not_doubled() {
    // A bed (white noise at -34 dBFS) under the first phrase and its 1.2 s pause sets the
    // room; it stops 0.3 s into the second phrase, under the voice, and a quiet room (-80
    // dBFS) goes on. Phrases are words (0.25 s vowels, 0.08 s apart); the pauses after the
    // second are short (0.7 s), and all but the first hold a real breath 20 dB over the new
    // room (21 dB under the old one). Every pause and word gap lies far under the old room,
    // each shorter than an editor's cut, but together longer: the room fell. The breaths are
    // heard, and nothing is inserted over them. (The first pause after the fall, with a
    // breath in it, would look as an attenuated breath does; it is left out.) Before, each
    // pause was measured alone and the old room held for two pauses: their breaths were not
    // heard and got a second one on top.
    let n = |s: f64| (s * RATE_HZ) as usize;
    let phrase = |x: &mut Vec<f32>, words: usize| {
        for w in 0..words {
            if w > 0 {
                x.extend(vec![0.0; n(0.08)]);
            }
            x.extend(signals::harmonic_tone(
                RATE_HZ,
                0.25,
                0.3,
                &[1.0, 0.6, 0.4, 0.3],
                |_| 140.0,
            ));
        }
    };
    let mut x = Vec::new();
    phrase(&mut x, 5);
    x.extend(vec![0.0; n(1.2)]);
    let bed_end = x.len() + n(0.3);
    phrase(&mut x, 5);
    let mut bursts_s = Vec::new();
    for k in 0..4 {
        let pause_start_s = x.len() as f64 / RATE_HZ;
        x.extend(vec![0.0; n(0.7)]);
        if k > 0 {
            bursts_s.push((pause_start_s + 0.15, pause_start_s + 0.55));
        }
        phrase(&mut x, 3);
    }
    x.extend(vec![0.0; n(0.8)]);
    let bed = signals::white_noise(bed_end, 0.02, 31);
    let room = signals::white_noise(x.len(), 1e-4, 32);
    for (i, v) in x.iter_mut().enumerate() {
        *v += room[i] + bed.get(i).copied().unwrap_or(0.0);
    }
    for &(a_s, b_s) in &bursts_s {
        let (a, b) = (n(a_s), n(b_s));
        for (i, v) in signals::white_noise(b - a, 1e-3, 33)
            .into_iter()
            .enumerate()
        {
            let ramp = ((i.min(b - a - 1 - i) as f32) / 160.0).min(1.0);
            x[a + i] += v * ramp;
        }
    }
    let (existing, inserted) = run(&x);
    for &(a_s, b_s) in &bursts_s {
        assert!(
            existing
                .iter()
                .any(|&(s, e)| (s - a_s).abs() < 0.06 && (e - b_s).abs() < 0.06),
            "the breath at {a_s:.2}..{b_s:.2} s is heard: {existing:?}"
        );
        assert!(
            inserted.iter().all(|&(s, e)| e <= a_s || s >= b_s),
            "nothing inserted over the breath at {a_s:.2}..{b_s:.2} s: {inserted:?}"
        );
    }
}

#[test]
fn a_phrase_whose_first_consonant_is_heard_apart_gets_its_breath_before_it() {
    // A vowel to 1.6 s, digital silence, an unvoiced burst at 2.40–2.45 s as loud as the
    // vowels (a word-initial /s/), 20 ms of zeros and 0.1 s of soft noise 37 dB under the
    // vowels (its stop's closure and release, as espeak-ng writes "st" at twice its rate: too
    // soft to be active, so the burst dies as a run of its own), the vowel from 2.57 s.
    // Before, the burst was the pause's last activity, 20 ms before the onset, and the pause
    // got no breath; now its breath ends before the burst, and none lies over it.
    let vowel = || signals::harmonic_tone(RATE_HZ, 1.6, 0.3, &[1.0, 0.6, 0.4, 0.3, 0.2], |_| 140.0);
    let at = |s: f64| (s * RATE_HZ) as usize;
    let mut x = vowel();
    x.resize(at(2.40), 0.0);
    x.extend(signals::white_noise(at(0.05), 0.1, 11));
    x.resize(at(2.47), 0.0);
    x.extend(signals::white_noise(at(0.10), 0.003, 12));
    x.extend(vowel());
    x.extend(vec![0.0; at(0.8)]);
    let (_, inserted) = run(&x);
    let in_pause: Vec<_> = inserted
        .iter()
        .filter(|&&(a, b)| b > 1.6 && a < 2.57)
        .collect();
    assert_eq!(in_pause.len(), 1, "one breath in the pause: {inserted:?}");
    let (a, b) = *in_pause[0];
    assert!(
        a >= 1.6 && b <= 2.40 && b - a >= 0.2,
        "the breath ends before the burst at 2.40 s: {a:.3}..{b:.3}"
    );
}
