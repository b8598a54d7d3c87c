//! CPU per plugin instance: the plugin library `cargo bench` builds (optimised, as the release
//! bundle; or `PNEUMA_CLAP`, see `pneuma_tests::bundle`) through the CLAP test host at 48 kHz in
//! 64-sample blocks, mono and stereo, one second of the example voice per iteration.
//! Real-time multiple = 1 s / (time per iteration). Also the time from loading the plugin (the
//! bundle's library already mapped by an earlier load) to its first processed block: load,
//! activate at 48 kHz, one 64-sample block. Run: `cargo bench -p pneuma-tests`.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use pneuma_testkit::voice::example_voice_at;
use pneuma_tests::bundle::plugin_path;
use pneuma_tests::host::Plugin;

fn plugin_cpu(c: &mut Criterion) {
    let voice = example_voice_at(48_000);
    let second = &voice[48_000 * 2..48_000 * 3];
    let mut group = c.benchmark_group("plugin_48k_64");
    group.throughput(Throughput::Elements(48_000));
    for (channels, osc) in [(1, false), (2, false), (1, true)] {
        let mut plugin = Plugin::load(&plugin_path(), "org.pneuma.pneuma").expect("bundle loads");
        if osc {
            plugin.set_param("osc_enabled", "On").unwrap();
            // Nobody listens on the discard port: the sends still happen.
            plugin.set_param("osc_port", "9").unwrap();
        }
        plugin.activate(48_000.0, 64, channels).unwrap();
        let source: Vec<Vec<Vec<f32>>> = second
            .chunks(64)
            .map(|b| vec![b.to_vec(); channels])
            .collect();
        let mut blocks = source.clone();
        let name = format!("{channels}ch{}", if osc { "_osc" } else { "" });
        group.bench_function(name, |b| {
            b.iter(|| {
                for (block, src) in blocks.iter_mut().zip(&source) {
                    for (c, s) in block.iter_mut().zip(src) {
                        c.copy_from_slice(s);
                    }
                    std::hint::black_box(plugin.process(block));
                }
            })
        });
    }
    group.finish();
}

fn load_to_first_block(c: &mut Criterion) {
    let path = plugin_path();
    let mut group = c.benchmark_group("plugin_load");
    group.sample_size(20);
    group.bench_function("load_activate_first_block_48k_64", |b| {
        b.iter(|| {
            let mut plugin = Plugin::load(&path, "org.pneuma.pneuma").expect("bundle loads");
            plugin.activate(48_000.0, 64, 2).unwrap();
            let mut block = vec![vec![0.0f32; 64]; 2];
            std::hint::black_box(plugin.process(&mut block));
        })
    });
    group.finish();
}

criterion_group!(benches, plugin_cpu, load_to_first_block);
criterion_main!(benches);
