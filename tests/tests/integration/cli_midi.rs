//! `pneuma render --midi` writes the CC lanes the plugin sends: the same controllers, channel and
//! values at the same times (within one frame). The plugin library runs through the CLAP host and
//! the render in process; the MIDI
//! file is read back by an independent reader (Python's `mido`, in the venv `.ci/run` makes:
//! `target/cli-venv`, or the Python named by `PNEUMA_PYTHON_TOOLS`).

use std::collections::BTreeMap;
use std::ffi::OsStr;
use std::path::PathBuf;
use std::process::Command;

use pneuma_testkit::voice::workspace_root;
use pneuma_tests::bundle::plugin_path;
use pneuma_tests::host::Plugin;

/// A Python with mido (and bvh, in the same environment), or `None` (the test then skips
/// visibly; under CI=true it fails).
fn python_tools(test: &str) -> Option<PathBuf> {
    pneuma_testkit::python::FILE_READERS.python(test, pneuma_testkit::python::ci())
}

/// `(time_s, value)` per controller.
type Lanes = BTreeMap<u8, Vec<(f64, u8)>>;

#[test]
fn the_midi_file_holds_the_plugins_cc_lanes() {
    let Some(python) = python_tools("the_midi_file_holds_the_plugins_cc_lanes") else {
        return;
    };
    let voice_path = pneuma_testkit::voice::example_voice_path();
    let (voice, rate) = pneuma_testkit::voice::example_voice();
    let dir = std::env::temp_dir().join(format!("pneuma-cli-midi-{}", std::process::id()));
    // `pneuma render --midi` in process: the command's own arguments and code path.
    use clap::{Args as _, FromArgMatches as _};
    let argv: Vec<&OsStr> = vec![
        "render".as_ref(),
        voice_path.as_os_str(),
        "-o".as_ref(),
        dir.as_os_str(),
        "--quiet".as_ref(),
        "--no-plot".as_ref(),
        "--midi".as_ref(),
        "--lookahead-ms".as_ref(),
        "500".as_ref(),
    ];
    let matches = pneuma_cli::render::Args::augment_args(clap::Command::new("render"))
        .try_get_matches_from(argv)
        .expect("valid render options");
    let args = pneuma_cli::render::Args::from_arg_matches(&matches).expect("render options");
    pneuma_cli::render::run(&args, &voice_path, |_| {}).expect("pneuma render");
    let read = Command::new(&python)
        .arg(workspace_root().join("cli/tests/tools/read_midi.py"))
        .arg(dir.join("voice.mid"))
        .output()
        .expect("python runs");
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8_lossy(&read.stdout).into_owned();
    assert!(
        read.status.success(),
        "{}",
        String::from_utf8_lossy(&read.stderr)
    );
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("0 960 500000 1"), "format 0, 120 BPM");
    let mut file = Lanes::new();
    for l in lines {
        let f: Vec<f64> = l.split(' ').map(|x| x.parse().expect("number")).collect();
        assert_eq!(f[1], 0.0, "channel 1");
        file.entry(f[2] as u8).or_default().push((f[0], f[3] as u8));
    }

    let mut plugin = Plugin::load(&plugin_path(), "org.pneuma.pneuma").expect("loads");
    plugin.activate(f64::from(rate), 512, 1).expect("activates");
    let latency = plugin.latency() as u64;
    let mut input = voice.clone();
    input.resize(voice.len() + latency as usize, 0.0);
    let mut live = Lanes::new();
    for block in input.chunks(512) {
        for e in plugin.process(&mut [block.to_vec()]) {
            let t = (e.sample - latency) as f64 / f64::from(rate);
            // The render ends with the input; the plugin goes on through the padding.
            if t < voice.len() as f64 / f64::from(rate) - 1.0 / 120.0 {
                live.entry(e.controller).or_default().push((t, e.value));
            }
        }
    }
    assert_eq!(
        file.keys().collect::<Vec<_>>(),
        live.keys().collect::<Vec<_>>(),
        "the same controllers"
    );
    let frame_s = 1.0 / 120.0;
    for (cc, want) in &live {
        let got = &file[cc];
        assert!(
            got.len() >= want.len(),
            "CC {cc}: {} vs {}",
            got.len(),
            want.len()
        );
        for (i, ((tw, vw), (tg, vg))) in want.iter().zip(got).enumerate() {
            assert_eq!(vw, vg, "CC {cc} message {i} at {tw:.3} s");
            assert!(
                (tw - tg).abs() <= frame_s,
                "CC {cc} message {i}: {tg} s vs {tw} s"
            );
        }
    }
    assert!(live[&2].len() > 20, "the lung moves: {}", live[&2].len());
}
