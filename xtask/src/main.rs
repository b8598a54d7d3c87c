//! Project chores: `cargo xtask bundle <package> --release` (nice-plug's bundler), the
//! evaluations of the evaluation crate (`cargo xtask eval-pitch --data ../shared/data/ptdb`,
//! `eval-pauses`), the trainings of the shipped models (`train-voicing`, `train-default`) and
//! the structure checks (`check-structure`).

mod silero_weights;
mod structure;
mod train_breath_voice;
mod train_default;
mod train_speech;
mod train_voicing;

/// The workspace's root folder.
pub fn workspace_root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives in the workspace")
        .to_path_buf()
}

/// The `--data DIR` and `--check` arguments of a training chore (`data` unless `--data` is
/// given); `Err` holds the exit code after the usage error is printed.
pub fn data_and_check(
    args: &[String],
    mut data: std::path::PathBuf,
) -> Result<(std::path::PathBuf, bool), i32> {
    let mut check = false;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--data" => match it.next() {
                Some(d) => data = std::path::PathBuf::from(d),
                None => {
                    eprintln!("error: --data needs a folder");
                    return Err(2);
                }
            },
            "--check" => check = true,
            other => {
                eprintln!("error: unknown argument `{other}` (use --data DIR, --check)");
                return Err(2);
            }
        }
    }
    Ok((data, check))
}

fn main() -> nice_plug_xtask::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("eval-pauses") => std::process::exit(pneuma_eval::pauses::main(&args[1..])),
        Some("eval-pitch") => std::process::exit(pneuma_eval::pitch::main(
            &args[1..],
            &train_voicing::held_out_models,
        )),
        Some("train-voicing") => std::process::exit(train_voicing::main(&args[1..])),
        Some("silero-weights") => std::process::exit(silero_weights::main(&args[1..])),
        Some("train-speech") => std::process::exit(train_speech::main(&args[1..])),
        Some("train-default") => std::process::exit(train_default::main(&args[1..])),
        Some("train-breath-voice") => std::process::exit(train_breath_voice::main(&args[1..])),
        Some("check-structure") => std::process::exit(structure::main(&args[1..])),
        _ => nice_plug_xtask::main(),
    }
}
