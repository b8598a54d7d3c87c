//! Test-only: the audio-thread path ([`crate::run_block`]: engine, CC encoder, OSC feed) never
//! allocates after `prepare`. It runs under nice-plug's allocation guard (`assert_no_alloc`, the
//! global allocator `assert_process_allocs` installs in debug builds), which aborts the test
//! binary on any allocation inside the guarded closure.

use std::sync::Arc;

use pneuma_core::encode::midi_cc::{CcEncoder, CcMap};
use pneuma_core::encode::osc::OscFormat;

use pneuma_core::engine::Engine;
use pneuma_core::head::HeadModel;

use crate::osc_sender::{self, OscSettings};
use crate::params::PneumaParams;
use crate::{run_block, Outputs};

struct Target;

impl OscSettings for Target {
    fn target(&self) -> (String, u16) {
        ("127.0.0.1".into(), 9)
    }
    fn format(&self) -> OscFormat {
        OscFormat::Vmc
    }
}

#[test]
fn the_audio_path_never_allocates_after_prepare() {
    let params = PneumaParams::default();
    let mut engine =
        Engine::new(params.engine_config(), HeadModel::default_model().clone()).unwrap();
    engine.prepare(48_000.0, 512, 2).unwrap();
    let mut cc = CcEncoder::new(CcMap::default()).unwrap();
    let (mut feed, _worker, _stats) = osc_sender::start(Arc::new(Target)).unwrap();
    // A voiced-ish signal with pauses, NaN and a changing block size.
    let mut left = vec![0.0f32; 512];
    let mut right = vec![0.0f32; 512];
    let mut sent = 0usize;
    let mut phase = 0.0f32;
    nice_assert_no_alloc::assert_no_alloc(|| {
        for block in 0..600 {
            let n = 1 + (block * 37) % 512;
            for i in 0..n {
                phase += 2.0 * std::f32::consts::PI * 150.0 / 48_000.0;
                let on = (block / 60) % 2 == 0;
                left[i] = if on { 0.3 * phase.sin() } else { 0.0 };
                right[i] = if i == 3 { f32::NAN } else { left[i] };
            }
            // What `process()` does per block before the engine runs.
            let config = params.engine_config();
            engine.set_config(&config).unwrap();
            std::hint::black_box(params.cc_map());
            let mut audio: [&mut [f32]; 2] = [&mut left[..n], &mut right[..n]];
            let outputs = Outputs {
                cc: Some(&mut cc),
                osc: Some(&mut feed),
            };
            run_block(&mut engine, &mut audio, outputs, &mut |_, _| sent += 1);
        }
    });
    assert!(sent > 20, "the path did work: {sent} CC messages");
}
