//! Where a new engine takes over while the plugin processes (a stream setting changed): no click
//! at either end of the new engine's lookahead silence (the plugin's `declick`). The host here
//! runs no transport; the seam does not depend on it.

use pneuma_tests::host::Plugin;

use super::load;

/// A change that needs a new engine while a tone plays (here the frame rate) leaves no click:
/// the old engine's last output falls to the new one's silence, and what the new engine hears
/// comes out of its delay rising from 0 (the plugin's `declick`, 5 ms ramps).
#[test]
fn a_new_engine_taking_over_while_processing_leaves_no_click() {
    let rate = 48_000.0f32;
    let mut plugin = load();
    plugin.activate(f64::from(rate), 256, 1).unwrap();
    // A tone that never comes near 0: its own largest step is 0.2 · 2π · 220 / 48 000 ≈ 0.006.
    let tone = |i: usize| 0.3 + 0.2 * (2.0 * std::f32::consts::PI * 220.0 * i as f32 / rate).sin();
    let mut out = Vec::new();
    let mut i = 0;
    let mut block = |plugin: &mut Plugin, out: &mut Vec<f32>| {
        let mut b = vec![(i..i + 256).map(tone).collect::<Vec<f32>>()];
        plugin.process(&mut b);
        out.extend_from_slice(&b[0]);
        i += 256;
    };
    // 1 s of the tone, then the change; the new engine is built in the background while the
    // tone plays on (2 ms of wall time per block, 1.5 s or more in all).
    for _ in 0..188 {
        block(&mut plugin, &mut out);
    }
    plugin.set_param("frame_rate_hz", "60").unwrap();
    for _ in 0..750 {
        block(&mut plugin, &mut out);
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    // The swap: the new engine's lookahead (0.5 s) of silence somewhere after the change.
    let after_change = &out[188 * 256..];
    let quiet_at = after_change
        .windows(12_000)
        .position(|w| w.iter().all(|x| x.abs() < 1e-3))
        .expect("no new engine took over");
    // And the tone comes back out of the new engine's delay (the rising ramp).
    assert!(
        after_change[quiet_at + 12_000..].iter().any(|&x| x > 0.09),
        "the tone never came back after the swap: it came too late to test the rising ramp"
    );
    // From the first output of the tone on (the stream starts with the lookahead's silence and
    // the tone from 0.3), no step larger than the tone's own and the ramps'.
    let from = 24_000 + 1;
    let step = out[from..]
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .fold(0.0f32, f32::max);
    assert!(step < 0.02, "a step of {step} in the output: a click");
}
