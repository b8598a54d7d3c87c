//! Inserted breaths stay inside the recording's bandwidth: speech made at 16 kHz and converted
//! to 48 kHz holds nothing above 8 kHz, and its breaths hold nothing there either; the same
//! speech over a room's full-band floor gets full breaths.

use pneuma_core::engine::offline::{self, Rendered};
use pneuma_core::engine::{Engine, EngineConfig};
use pneuma_core::head::HeadModel;
use pneuma_testkit::resample::resample;
use pneuma_testkit::signals;
use realfft::RealFftPlanner;

use crate::generated_phrases::sequence;
use crate::support::streamed_watched;

const RATE_HZ: u32 = 48_000;

/// A stream engine (the plugin's lookahead), prepared.
fn engine() -> Engine {
    let mut e = Engine::new(EngineConfig::default(), HeadModel::default_model().clone()).unwrap();
    e.prepare(f64::from(RATE_HZ), 4096, 1).unwrap();
    e
}

fn render(x: &[f32]) -> Rendered {
    render_in(x, &[1024])
}

fn render_in(x: &[f32], blocks: &[usize]) -> Rendered {
    offline::render(&mut engine(), &[x.to_vec()], blocks)
}

/// Speech made at 16 kHz, converted to 48 kHz, and where each phrase starts and ends. The
/// generated vowels carry nothing near 8 kHz, so the phrases get the aspiration noise real
/// voices have there (2–7.9 kHz, 25 dB under the speech).
fn converted() -> (Vec<f32>, Vec<(f64, f64)>) {
    let (mut x16, spans) = sequence(0.6, &[1.5, 1.5, 1.5, 1.5], &[0.8, 0.8, 0.8]);
    let speech_rms = pneuma_core::analysis::rms(&x16[(0.6 * 16_000.0) as usize..]);
    let aspiration = signals::band_noise(x16.len(), 16_000.0, (2_000.0, 7_900.0), 1.0, 21);
    let gain = (speech_rms * 10f64.powf(-1.25)) as f32;
    for (x, a) in x16.iter_mut().zip(&aspiration) {
        if *x != 0.0 {
            *x += gain * a;
        }
    }
    (resample(&x16, 16_000, RATE_HZ), spans)
}

/// Power of `x` above `split_hz` against its power from 1 kHz to `split_hz`, dB.
fn above_db(x: &[f32], split_hz: f64) -> f64 {
    let n = x.len().next_power_of_two();
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut input: Vec<f64> = x.iter().map(|&v| f64::from(v)).collect();
    input.resize(n, 0.0);
    let mut spectrum = fft.make_output_vec();
    fft.process(&mut input, &mut spectrum).unwrap();
    let bin_hz = f64::from(RATE_HZ) / n as f64;
    let (mut band, mut above) = (0.0, 0.0);
    for (k, c) in spectrum.iter().enumerate() {
        let hz = k as f64 * bin_hz;
        if hz >= split_hz {
            above += c.norm_sqr();
        } else if hz >= 1_000.0 {
            band += c.norm_sqr();
        }
    }
    10.0 * (above / band).log10()
}

/// The breaths after the first phrase (the voice's bandwidth is known by then): what each added
/// above 9 kHz, dB against its own 1–9 kHz.
fn breaths_above_db(x: &[f32], r: &Rendered, first_offset_s: f64) -> Vec<f64> {
    r.breaths
        .iter()
        .filter(|b| b.start_s > first_offset_s)
        .map(|b| {
            let (a, z) = (
                (b.start_s * f64::from(RATE_HZ)) as usize,
                (b.end_s * f64::from(RATE_HZ)) as usize,
            );
            let added: Vec<f32> = r.audio[0][a..z]
                .iter()
                .zip(&x[a..z])
                .map(|(o, i)| o - i)
                .collect();
            above_db(&added, 9_000.0)
        })
        .collect()
}

/// `x` (speech after 0.6 s) over a room's full-band floor, 30 dB under the speech.
fn over_room(x: &[f32]) -> Vec<f32> {
    let lead = (0.6 * f64::from(RATE_HZ)) as usize;
    let speech_rms = pneuma_core::analysis::rms(&x[lead..]);
    let floor = signals::white_noise(x.len(), speech_rms * 10f64.powf(-1.5), 5);
    x.iter().zip(&floor).map(|(a, b)| a + b).collect()
}

#[test]
fn breaths_in_speech_converted_up_from_16_khz_stay_under_its_band_edge() {
    let (converted, spans) = converted();
    let full = over_room(&converted);
    let limited = breaths_above_db(&converted, &render(&converted), spans[0].1);
    let open = breaths_above_db(&full, &render(&full), spans[0].1);
    assert!(
        limited.len() >= 3 && open.len() >= 3,
        "{limited:?} {open:?}"
    );
    assert!(
        limited.iter().all(|&db| db < -45.0),
        "breaths in a recording that ends at 8 kHz reach above 9 kHz: {limited:.1?} dB"
    );
    // The breath's own 8 kHz top leaves about -31 dB there.
    assert!(
        open.iter().all(|&db| db > -38.0),
        "breaths over a full-band floor lost their top: {open:.1?} dB"
    );
}

#[test]
fn band_limited_breaths_are_the_same_for_any_partition_and_never_allocate() {
    let (x, spans) = converted();
    let reference = render_in(&x, &[4096]);
    let above = breaths_above_db(&x, &reference, spans[0].1);
    assert!(
        above.len() >= 3 && above.iter().all(|&db| db < -45.0),
        "{above:.1?}"
    );
    for blocks in [vec![1], vec![37, 512, 3], vec![700]] {
        let r = render_in(&x, &blocks);
        assert!(r.audio == reference.audio, "blocks {blocks:?}");
        assert_eq!(r.breaths, reference.breaths, "blocks {blocks:?}");
    }
    let (breaths, n) = streamed_watched(&mut engine(), &x, |_| {});
    assert!(breaths >= 3, "{breaths} breaths");
    assert_eq!(n, 0, "{n} allocations");
}

#[test]
fn the_engine_tells_the_band_limit_it_puts_on_breaths_and_none_over_a_full_band_room() {
    let (converted, _) = converted();
    let mut e = engine();
    assert_eq!(e.breath_band_limit_hz(), None, "nothing heard yet");
    offline::render(&mut e, std::slice::from_ref(&converted), &[1024]);
    let hz = e
        .breath_band_limit_hz()
        .expect("speech from 16 kHz has a limit");
    assert!((7_000.0..8_000.0).contains(&hz), "{hz} Hz");
    let mut e = engine();
    offline::render(&mut e, &[over_room(&converted)], &[1024]);
    assert_eq!(e.breath_band_limit_hz(), None);
}
