//! The spectral shape of breath noise: the frame band levels ([`FeatureFrame::bands`]) are
//! bit-identical for any block partition and at every host rate.

use pneuma_core::analysis::{AnalysisConfig, Analyzer, FeatureFrame};
use pneuma_core::test_signals;

/// Analyses `x` in blocks whose sizes `blocks` gives per call.
fn analyse_blocks(
    x: &[f32],
    rate_hz: f64,
    blocks: &mut dyn FnMut(usize) -> usize,
) -> Vec<FeatureFrame> {
    let mut a = Analyzer::new(AnalysisConfig::default()).expect("default config");
    a.prepare(rate_hz, 4096).expect("supported rate");
    let mut frames = Vec::new();
    let (mut pos, mut call) = (0, 0);
    while pos < x.len() {
        let n = blocks(call).clamp(1, x.len() - pos);
        a.process(&x[pos..pos + n], |f| frames.push(*f))
            .expect("prepared");
        pos += n;
        call += 1;
    }
    a.finish(|f| frames.push(*f)).expect("prepared");
    frames
}

#[test]
fn band_levels_are_bit_identical_for_any_block_partition() {
    for rate_hz in [8_000.0, 20_000.0, 44_100.0, 192_000.0] {
        let mut x = test_signals::harmonic_tone(rate_hz, 0.4, 0.3, &[1.0, 0.5, 0.3], |_| 150.0);
        x.extend(test_signals::white_noise((0.3 * rate_hz) as usize, 0.02, 9));
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
        let want = bits(&analyse_blocks(&x, rate_hz, &mut |_| 4096));
        assert!(want.len() > 50, "{rate_hz}: {} frames", want.len());
        for size in [1usize, 37, 512] {
            assert_eq!(
                bits(&analyse_blocks(&x, rate_hz, &mut |_| size)),
                want,
                "{rate_hz} Hz in blocks of {size}"
            );
        }
        let mut k = 0usize;
        let uneven = bits(&analyse_blocks(&x, rate_hz, &mut |_| {
            k += 1;
            [1, 300, 7, 2048, 64][k % 5]
        }));
        assert_eq!(uneven, want, "{rate_hz} Hz in uneven blocks");
    }
}
