//! `cargo xtask train-breath-voice [--data DIR] [--check]`: fits the built-in breath voice
//! (`assets/models/breath_voice.json`, embedded in `pneuma-core`) on every clear labelled
//! breath of the styletalk and Keele clips (`pneuma_eval::restore::reference`): figures only,
//! no audio. Deterministic: `--check` regenerates the file and fails on any difference.
//! `pneuma eval restore` judges the same fit held out (each speaker scored with the voice
//! fitted on the others).

use pneuma_eval::restore::{load_all, reference, LabelledSets};

const OUTPUT: &str = "assets/models/breath_voice.json";

/// Runs the chore; returns the process exit code.
pub fn main(args: &[String]) -> i32 {
    let root = crate::workspace_root();
    let (data, check) = match crate::data_and_check(args, root.join("../shared/data")) {
        Ok(parsed) => parsed,
        Err(code) => return code,
    };
    let sets = LabelledSets {
        data: data.join("styletalk"),
        labels: root.join("assets/labels/styletalk_breaths.csv"),
        keele: data.join("keele"),
        keele_labels: root.join("assets/labels/keele_breaths.csv"),
    };
    let run = || -> Result<i32, String> {
        let clips = load_all(&sets, None)?;
        let voice = reference::fit(&clips).ok_or("no labelled breath to fit on")?;
        let text = serde_json::to_string_pretty(&voice).map_err(|e| e.to_string())? + "\n";
        let path = root.join(OUTPUT);
        println!(
            "built-in breath voice: {} speakers, {} breaths; level {:+.1} dB re speech (spread {:.1} dB), length {:.2} s",
            voice.speakers,
            voice.voice.breaths,
            voice.voice.level_re_speech_db,
            voice.voice.level_sd_db,
            voice.voice.length_s
        );
        if check {
            let old = std::fs::read_to_string(&path).map_err(|e| format!("{OUTPUT}: {e}"))?;
            if old != text {
                eprintln!("{OUTPUT} differs from what the data gives: run `cargo xtask train-breath-voice` and commit it");
                return Ok(1);
            }
            println!("{OUTPUT} is what the data gives, bit for bit");
        } else {
            std::fs::write(&path, text).map_err(|e| format!("{OUTPUT}: {e}"))?;
            println!("wrote {OUTPUT}");
        }
        Ok(0)
    };
    match run() {
        Ok(code) => code,
        Err(e) => {
            eprintln!("train-breath-voice: {e}");
            1
        }
    }
}
