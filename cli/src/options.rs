//! What the subcommands share about their options: numbers as users paste them (a Unicode
//! minus accepted), options bound to a setting of core's table ([`SettingFlag`]: their help,
//! default and range come from the table, and a refused value is named as typed), the
//! `--no-overwrite` check, the head-model loading and the progress bar.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use pneuma_core::engine::EngineConfig;
use pneuma_core::settings::{analysis, breathing, output, placement, Setting, SettingError, Unit};
use pneuma_io::capped::HEAD_MODEL_MAX_BYTES;

/// A command-line option that gives one setting of core's table
/// ([`pneuma_core::settings`]), typed in `unit` (`--min-pause-ms` gives `min_pause_s` in
/// milliseconds). Its help text, default and range are the table's.
#[derive(Debug, Clone, Copy)]
pub struct SettingFlag {
    /// The option as typed: `--min-pause-ms`.
    pub flag: &'static str,
    /// The setting it gives.
    pub setting: &'static Setting,
    /// The unit it is typed in.
    pub unit: Unit,
}

impl SettingFlag {
    /// Factor from the option's unit to the setting's.
    fn factor(&self) -> f64 {
        self.unit.factor_to(self.setting.unit).unwrap_or(1.0)
    }

    /// The help text: the table's help, its range and default in the option's unit.
    pub fn help(&self) -> String {
        table_help(self.setting, self.unit)
    }

    /// The help text with the default in words (`the preset's`).
    pub fn help_with_default(&self, default: &str) -> String {
        help_text(self.setting.help, self.setting, self.unit, default)
    }

    /// The help text with `what` in place of the table's help (a command that uses the setting
    /// for less, or more, than the table says), the table's range and default after it.
    pub fn help_saying(&self, what: &str) -> String {
        let default = self.setting.default_text(self.unit);
        help_text(what, self.setting, self.unit, &default)
    }

    /// The table's default in the option's unit (for clap's `default_value_t`).
    pub fn default_value(&self) -> f64 {
        f64::from(self.setting.default) / self.factor()
    }

    /// `value` (in the option's unit) in the setting's unit, checked against the table's
    /// range; the error names the option and the range in the option's unit.
    pub fn check(&self, value: f64) -> Result<f64, String> {
        let v = value * self.factor();
        self.setting
            .check(v)
            .map(|()| v)
            .map_err(|e| render_for(&[self], &e))
    }

    /// [`SettingFlag::check`]s `value` and sets it in `config`; the errors name the options.
    pub fn apply(&self, config: &mut EngineConfig, value: f64) -> Result<(), String> {
        let v = self.check(value)?;
        config
            .set_value(self.setting, v)
            .map_err(|e| render_for(&SETTING_FLAGS, &e))
    }
}

/// The help of an option that gives `setting` in `unit` as it is: the table's help, its range
/// and its default.
pub fn table_help(setting: &Setting, unit: Unit) -> String {
    help_text(setting.help, setting, unit, &setting.default_text(unit))
}

/// `what` with the range of `setting` in `unit` and `default` after it: every option's help
/// that comes from the table has this shape.
fn help_text(what: &str, setting: &Setting, unit: Unit, default: &str) -> String {
    format!("{what} ({}; default {default})", setting.range_text(unit))
}

/// `--breath-mouth` (render, speak).
pub const BREATH_MOUTH_HELP: &str = "A recording of a mouth inhalation (any input format) that \
    plays instead of the built-in or learned breath voice, for the mouth's share of each breath \
    (the preset's mouth share; the nose's share comes from --breath-nose, else the built-in nose \
    sound)";
/// `--breath-nose` (render, speak).
pub const BREATH_NOSE_HELP: &str = "A recording of a nose inhalation (any input format) that \
    plays instead of the built-in or learned breath voice, for the nose's share of each breath \
    (one minus the preset's mouth share; the mouth's share comes from --breath-mouth, else the \
    built-in mouth sound)";

/// `--frame-rate` (render, analyze, speak).
pub static FRAME_RATE: SettingFlag = SettingFlag {
    flag: "--frame-rate",
    setting: &analysis::FRAME_RATE_HZ,
    unit: Unit::Hertz,
};
/// `--frame-rate`'s help in `render` and `speak`, where the rate is the analysis' clock too:
/// another rate may move breaths, which `--bvh-fps` never does.
pub fn frame_rate_help() -> String {
    format!(
        "{}: the rate of the controls CSV, MIDI, OSC and BVH, and the clock the analysis and the \
         breath placement run on, so another rate can move, add or drop breaths in the audio. \
         For a scene's frame rate (a BVH at 24 fps) keep it and give --bvh-fps, which \
         resamples only the BVH",
        FRAME_RATE.help_saying("Analysis and control frames per second")
    )
}

/// `--f0-min` (analyze).
pub static F0_MIN: SettingFlag = SettingFlag {
    flag: "--f0-min",
    setting: &analysis::F0_MIN_HZ,
    unit: Unit::Hertz,
};
/// `--f0-max` (analyze).
pub static F0_MAX: SettingFlag = SettingFlag {
    flag: "--f0-max",
    setting: &analysis::F0_MAX_HZ,
    unit: Unit::Hertz,
};
/// `--breath-level-db` (render, speak).
pub static BREATH_LEVEL: SettingFlag = SettingFlag {
    flag: "--breath-level-db",
    setting: &placement::BREATH_LEVEL_DB,
    unit: Unit::Decibels,
};
/// `--min-pause-ms` (render).
pub static MIN_PAUSE: SettingFlag = SettingFlag {
    flag: "--min-pause-ms",
    setting: &placement::MIN_PAUSE_S,
    unit: Unit::Milliseconds,
};
/// `--lookahead-ms` (render).
pub static LOOKAHEAD: SettingFlag = SettingFlag {
    flag: "--lookahead-ms",
    setting: &placement::LOOKAHEAD_S,
    unit: Unit::Milliseconds,
};
/// `--mode` (render).
pub static MODE: SettingFlag = SettingFlag {
    flag: "--mode",
    setting: &placement::MODE,
    unit: Unit::None,
};
/// `--rate` (speak).
pub static RATE: SettingFlag = SettingFlag {
    flag: "--rate",
    setting: &breathing::PROSODY_RATE,
    unit: Unit::None,
};
/// `--loudness` (speak).
pub static LOUDNESS: SettingFlag = SettingFlag {
    flag: "--loudness",
    setting: &breathing::SPEAKING_LOUDNESS,
    unit: Unit::None,
};

/// `--midi-head-range-deg` (render, speak).
pub static MIDI_HEAD_RANGE: SettingFlag = SettingFlag {
    flag: "--midi-head-range-deg",
    setting: &output::CC_HEAD_RANGE_DEG,
    unit: Unit::Degrees,
};

/// Every option that gives a setting of the table.
pub static SETTING_FLAGS: [&SettingFlag; 10] = [
    &FRAME_RATE,
    &F0_MIN,
    &F0_MAX,
    &BREATH_LEVEL,
    &MIN_PAUSE,
    &LOOKAHEAD,
    &MODE,
    &RATE,
    &LOUDNESS,
    &MIDI_HEAD_RANGE,
];

/// `error` with every setting that one of `flags` gives named as that option, in its unit
/// (the others by their ids).
pub fn render_for(flags: &[&SettingFlag], error: &SettingError) -> String {
    error.render(&|s| {
        flags
            .iter()
            .find(|f| std::ptr::eq(f.setting, s))
            .map_or_else(
                || (s.id.to_owned(), s.unit),
                |f| (f.flag.to_owned(), f.unit),
            )
    })
}

/// Parses a number as typed or pasted: the Unicode minus (U+2212, as printed by some
/// documents) is taken as `-`. For clap's `value_parser`; `f64`, so that a range check sees the
/// value as typed (`-5.9999999` would be `-6.0` as an `f32`).
pub fn number(s: &str) -> Result<f64, String> {
    let ascii = s.trim().replace('\u{2212}', "-");
    ascii
        .parse::<f64>()
        .map_err(|_| format!("`{s}` is not a number (write e.g. -22 or 0.5)"))
}

/// `Err` naming `option` when `value` lies outside `min..=max` (all in the option's `unit`).
pub fn check_range(option: &str, value: f64, min: f64, max: f64, unit: &str) -> Result<(), String> {
    if value.is_finite() && (min..=max).contains(&value) {
        Ok(())
    } else {
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        Err(format!(
            "{option} {value}{unit} is out of range: use {min} to {max}{unit}"
        ))
    }
}

/// `a` and `b` name the same existing file (links and `.` resolved); false when either does not
/// exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// With `--no-overwrite`: `Err` naming the first of `outputs` that exists already.
pub fn refuse_existing(outputs: &[PathBuf]) -> Result<(), String> {
    match outputs.iter().find(|p| p.exists()) {
        Some(p) => Err(format!(
            "{} exists and --no-overwrite is given: remove it, choose another output, or drop -n",
            p.display()
        )),
        None => Ok(()),
    }
}

/// Whether `path` surely names a folder: it exists as one, or its name ends in `/`.
pub fn names_folder(path: &Path) -> bool {
    ends_in_separator(path) || path.is_dir()
}

/// Whether `path`'s name ends in `/` (a folder, whatever exists there).
fn ends_in_separator(path: &Path) -> bool {
    let text = path.to_string_lossy();
    text.ends_with('/') || text.ends_with(std::path::MAIN_SEPARATOR)
}

/// The extensions of the files the commands write besides audio: names ending so are files,
/// never folders (as are audio names, read or not, see [`pneuma_io::AUDIO_EXTENSIONS`]). Any
/// other name (`2024.06.01`, `Season.1`, `renders.v2`) is a folder.
const FILE_EXTENSIONS: [&str; 7] = ["csv", "png", "bvh", "mid", "midi", "txt", "json"];

/// `Err` when `-o` names a file (an audio extension, or one of the files a render writes, and
/// not an existing folder) where a folder is wanted, instead of silently making a folder of that
/// name. A name ending in `/` is always a folder; so is any other dotted name (dates, versions).
pub fn check_output_folder(option: &str, dir: &Path) -> Result<(), String> {
    // One look at what is there: a batch's other renders may make the folder meanwhile, and
    // "not a folder yet" then "exists" read as two looks would call it a file.
    if ends_in_separator(dir) {
        return Ok(());
    }
    if let Ok(meta) = std::fs::metadata(dir) {
        if meta.is_dir() {
            return Ok(());
        }
        return Err(format!(
            "{option} {} is an existing file, but {option} names the output folder (the files \
             inside are named after the input); give a folder, e.g. {option} out",
            dir.display()
        ));
    }
    let file_like = dir.extension().and_then(|e| e.to_str()).is_some_and(|e| {
        pneuma_io::AUDIO_EXTENSIONS
            .iter()
            .chain(&FILE_EXTENSIONS)
            .chain(pneuma_io::UNREAD_AUDIO_EXTENSIONS.iter().map(|(x, _)| x))
            .any(|x| x.eq_ignore_ascii_case(e))
    });
    if file_like {
        return Err(format!(
            "{option} {} looks like a file name, but {option} names the output folder (the \
             files inside are named after the input); give a folder, e.g. {option} out (a name \
             ending in / is always taken as a folder)",
            dir.display()
        ));
    }
    Ok(())
}

/// `1 breath`, `2 breaths`: a count with its noun, for summaries.
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// An input's format for summaries: `48000 Hz, 2 ch, 24-bit`; lossy input (MP3, AAC, …) has
/// no bit depth, so none is named.
pub fn describe_format(info: &pneuma_io::AudioInfo, lossless: bool) -> String {
    let depth = match (lossless, info.float) {
        (false, _) => String::new(),
        (true, true) => format!(", {}-bit float", info.bits),
        (true, false) => format!(", {}-bit", info.bits),
    };
    format!("{} Hz, {} ch{depth}", info.sample_rate_hz, info.channels)
}

/// What a head-pose model file is, for the size cap's message.
const HEAD_MODEL_FILE: &str = "a head-pose model (JSON, as `pneuma train` writes)";

/// The head-pose model from `path` (JSON), or the embedded default model when `None`.
pub fn load_head_model(path: Option<&Path>) -> Result<pneuma_core::head::HeadModel, String> {
    match path {
        Some(p) => {
            let text = pneuma_io::read_text_capped(p, HEAD_MODEL_MAX_BYTES, HEAD_MODEL_FILE)
                .map_err(|e| format!("--head-model: {e}"))?;
            pneuma_core::head::HeadModel::from_json(&text)
                .map_err(|e| format!("--head-model {}: {e}", p.display()))
        }
        None => Ok(pneuma_core::head::HeadModel::default_model().clone()),
    }
}

/// A progress bar on standard error that appears only when standard error is a terminal and
/// the job has run for more than [`Progress::DELAY`]; hidden otherwise.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    shown: bool,
}

impl Progress {
    /// Jobs shorter than this never show a bar.
    pub const DELAY: Duration = Duration::from_secs(1);

    /// A bar labelled `label`; none at all when `enabled` is false or stderr is no terminal.
    pub fn new(label: &str, enabled: bool) -> Self {
        let bar = (enabled && std::io::stderr().is_terminal()).then(|| {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(1000),
                indicatif::ProgressDrawTarget::hidden(),
            );
            bar.set_style(
                indicatif::ProgressStyle::with_template(&format!(
                    "{label} [{{bar:40}}] {{percent}}% ({{eta}} left)"
                ))
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            bar
        });
        Self {
            bar,
            start: Instant::now(),
            shown: false,
        }
    }

    /// Sets the fraction done (0..1).
    pub fn set(&mut self, fraction: f64) {
        let Some(bar) = &self.bar else { return };
        if !self.shown && self.start.elapsed() > Self::DELAY {
            bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            self.shown = true;
        }
        bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// The folders of `output` (and its parents) that do not exist yet, deepest first: a run that
/// fails or is interrupted removes those it created and left empty.
pub fn missing_folders(output: &Path) -> Vec<PathBuf> {
    if output.as_os_str() == "-" {
        return Vec::new();
    }
    output
        .ancestors()
        .filter(|p| !p.as_os_str().is_empty())
        .take_while(|p| !p.exists())
        .map(Path::to_path_buf)
        .collect()
}

/// Removes the `folders` (deepest first) that are empty; stops at the first that is not.
pub fn remove_empty(folders: &[PathBuf]) {
    for f in folders {
        if std::fs::remove_dir(f).is_err() {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::settings::Kind;

    /// The user guide's option tables give every option of the settings table the table's
    /// range and default, in the option's unit (the guide is written by hand; this holds it to
    /// the table).
    #[test]
    fn the_cli_guide_gives_each_setting_option_the_tables_range_and_default() {
        let guide = include_str!("../../docs/guide/cli.md").replace('\u{2212}', "-");
        for f in SETTING_FLAGS {
            let rows: Vec<&str> = guide
                .lines()
                .filter(|l| l.starts_with(&format!("| `{}`", f.flag)))
                .collect();
            assert!(!rows.is_empty(), "{}: no row in docs/guide/cli.md", f.flag);
            for row in rows {
                // | option | default | range / values | what it does |
                let cells: Vec<&str> = row.split('|').map(str::trim).collect();
                let (default, range) = (cells[2].replace('`', ""), cells[3].replace('`', ""));
                match f.setting.kind {
                    Kind::Choice(names) => {
                        assert_eq!(range, names.join(", "), "{row}");
                        assert_eq!(default, f.setting.default_text(f.unit), "{row}");
                    }
                    _ => {
                        let want = f.setting.range_text(f.unit);
                        assert!(range.starts_with(&want), "{row}: the table says {want}");
                        // A default in words ("the preset's", "none (...)") is the door's own.
                        if default.starts_with(|c: char| c.is_ascii_digit() || c == '-') {
                            let d = f.setting.default_text(f.unit);
                            assert!(d.starts_with(&default), "{row}: the table says {d}");
                        }
                    }
                }
            }
        }
    }

    /// `--min-pause-ms` decides which pauses get a full breath and end a group: a shorter
    /// pause still gets a catch breath when the air runs out (raising it gives more of them),
    /// and the help and the guide say so rather than "no breath".
    #[test]
    fn min_pause_help_and_guide_name_the_catch_breaths_in_shorter_pauses() {
        let help = MIN_PAUSE.help();
        assert!(
            help.contains("full breath") && help.contains("catch breath"),
            "{help}"
        );
        let guide = include_str!("../../docs/guide/cli.md");
        let row = guide
            .lines()
            .find(|l| l.starts_with("| `--min-pause-ms`"))
            .expect("row");
        assert!(
            row.contains("full breath") && row.contains("catch breath"),
            "{row}"
        );
    }

    #[test]
    fn numbers_accept_the_unicode_minus() {
        assert_eq!(number("\u{2212}22"), Ok(-22.0));
        assert_eq!(number("-22"), Ok(-22.0));
        assert_eq!(number("0.5"), Ok(0.5));
        assert!(number("x").is_err());
    }

    #[test]
    fn a_setting_option_is_checked_against_the_table_in_its_own_unit() {
        use pneuma_core::settings::placement::{CATCH_BREATH_MIN_S, MIN_PAUSE_S};
        let flag = SettingFlag {
            flag: "--min-pause-ms",
            setting: &MIN_PAUSE_S,
            unit: Unit::Milliseconds,
        };
        assert_eq!(flag.check(250.0), Ok(0.25));
        assert_eq!(flag.default_value(), 250.0);
        // The message names the option and the table's range (0.1 to 2 s), both in ms.
        assert_eq!(
            flag.check(5000.0).unwrap_err(),
            "--min-pause-ms 5000 ms is out of range: use 100 to 2000 ms"
        );
        assert!(flag.check(f64::NAN).is_err());
        assert!(
            flag.help().ends_with("(100 to 2000 ms; default 250 ms)"),
            "{}",
            flag.help()
        );
        // A setting no option gives keeps its id.
        let e = CATCH_BREATH_MIN_S.check(9.0).unwrap_err();
        assert!(render_for(&[&flag], &e).starts_with("catch_breath_min_s 9 s"));
    }

    #[test]
    fn ranges_name_the_option_and_unit() {
        assert!(check_range("--lookahead-ms", 300.0, 300.0, 2000.0, "ms").is_ok());
        let e = check_range("--lookahead-ms", 0.0, 300.0, 2000.0, "ms").unwrap_err();
        assert_eq!(e, "--lookahead-ms 0 ms is out of range: use 300 to 2000 ms");
        assert!(check_range("--rate", f64::NAN, 0.5, 2.0, "").is_err());
    }

    #[test]
    fn summaries_count_and_name_formats_as_they_are() {
        assert_eq!(count(1, "breath"), "1 breath");
        assert_eq!(count(0, "breath"), "0 breaths");
        assert_eq!(count(2, "breath"), "2 breaths");
        let info = pneuma_io::AudioInfo {
            sample_rate_hz: 44_100,
            channels: 2,
            bits: 24,
            float: false,
            frames: 0,
        };
        assert_eq!(describe_format(&info, true), "44100 Hz, 2 ch, 24-bit");
        assert_eq!(describe_format(&info, false), "44100 Hz, 2 ch");
        let float = pneuma_io::AudioInfo {
            bits: 32,
            float: true,
            ..info
        };
        assert_eq!(
            describe_format(&float, true),
            "44100 Hz, 2 ch, 32-bit float"
        );
    }

    #[test]
    fn a_file_name_is_not_taken_as_a_folder() {
        let dir = tempfile::tempdir().expect("temp dir");
        assert!(check_output_folder("-o", &dir.path().join("name.wav")).is_err());
        assert!(check_output_folder("-o", &dir.path().join("out")).is_ok());
        // An existing file of any name is not a folder to write into.
        let existing = dir.path().join("notes");
        std::fs::write(&existing, b"x").unwrap();
        let err = check_output_folder("-o", &existing).unwrap_err();
        assert!(err.contains("is an existing file"), "{err}");
        assert!(check_output_folder("-o", &dir.path().join("controls.CSV")).is_err());
        let dotted = dir.path().join("take.wav");
        std::fs::create_dir(&dotted).expect("dir");
        assert!(check_output_folder("-o", &dotted).is_ok());
        // Dated and versioned names are folders, existing or not; a trailing / always is.
        for name in [
            "2024.06.01",
            "Season.1",
            "renders.v2",
            "new.v3/",
            "new.wav/",
        ] {
            let p = PathBuf::from(format!("{}/{name}", dir.path().display()));
            assert!(check_output_folder("-o", &p).is_ok(), "{name}");
        }
    }
}
