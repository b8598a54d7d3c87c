//! `pneuma speak "TEXT" -o DIR`: text to speech with breaths, after Bernardet et al.
//!
//! The text is cut into breath groups by the paper's chunker; each chunk is synthesised by a TTS
//! program (espeak-ng by default, festival's `text2wave` as the alternative), its real duration is
//! measured from the audio (leading and trailing silence below −50 dBFS trimmed, as the paper
//! measures the length of the TTS output), and the timeline is laid out as
//! `[rest 0.25 s] [pause] [chunk] [pause] [chunk] … [rest 0.6 s]`, each pause the 0.1 s gap plus
//! room for the inspiration its chunk needs ([`pause_before_s`]). The timeline then runs through
//! the same [`Engine`] as `pneuma render` (whole file known, breaths in every pause): the engine
//! places each breath and chooses its length from the pause and the coming group, plays it at
//! the preset's level under the speech, runs the breath cycle (with its reserve) and the head,
//! and analyses the speech for the controls. So `speak` breathes as a render of a recording
//! does, and varies as it does. Its breaths take the built-in voice coloured by the TTS's
//! speech, as a render of a recording without breaths does: a TTS breathes nothing to learn.
//!
//! Writes `DIR/speech.wav` (16-bit mono at the TTS rate; `--format` FLAC, AIFF or MP3
//! instead), `DIR/speech.controls.csv`, `DIR/speech.breaths.csv` and `DIR/speech.png`, on
//! request `speech.bvh` and `speech.mid`, all together or none ([`files`]).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use pneuma_core::analysis::FrameClock;
use pneuma_core::breathing::{
    chunk_text, BreathSample, BreathingError, BreathingParams, Chunk, LowLevelParams, Preset,
    SampleSlot,
};
use pneuma_core::encode::sink::FrameSink as _;
use pneuma_core::engine::voice_learning::VoiceLearner;
use pneuma_core::engine::{offline, BreathVoiceMode, Engine, EngineConfig, EngineError};
use pneuma_core::{BreathEvent, ControlFrame};
use thiserror::Error;

use crate::audio_out::Container;
use crate::options::{BREATH_LEVEL, FRAME_RATE, LOUDNESS, RATE};
use crate::plot::PlotError;
use crate::render::leftovers::Cleared;
use pneuma_io::capped::TEXT_MAX_BYTES;
use pneuma_io::{read_mono, read_text_capped, CappedReadError, InputFormat, ReadError};

mod files;
mod voices;

/// Silence before the first breath, seconds.
pub const LEAD_IN_S: f64 = 0.25;
/// Pause between the end of a chunk and the next inspiration, seconds.
pub const PAUSE_S: f64 = 0.1;
/// Rest after the last chunk, seconds.
pub const TAIL_S: f64 = 0.6;
/// Samples per block through the engine.
const BLOCK: usize = 4096;
/// Level under which the ends of a TTS chunk count as silence, dBFS.
pub const TRIM_DB: f32 = -50.0;

/// Which TTS program speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Tts {
    /// `espeak-ng` (Debian package `espeak-ng`).
    Espeak,
    /// festival's `text2wave` (Debian package `festival`).
    Festival,
}

impl Tts {
    /// The program run and the Debian package that provides it.
    fn program(self) -> (&'static str, &'static str) {
        match self {
            Self::Espeak => ("espeak-ng", "espeak-ng"),
            Self::Festival => ("text2wave", "festival"),
        }
    }

    /// Its name in messages: its package's.
    fn name(self) -> &'static str {
        self.program().1
    }

    /// How to list its voices, and an example of one.
    fn voices_hint(self) -> &'static str {
        match self {
            Self::Espeak => {
                "`espeak-ng --voices` lists the voices it has (give a language, e.g. --voice \
                 en-us, a voice file, e.g. gmw/en-US, or a name with spaces for its \
                 underscores, e.g. \"English (America)\"; a variant after +, e.g. en-us+f3)"
            }
            Self::Festival => {
                "`echo '(print (voice.list))' | festival --pipe` lists the voices it has (give \
                 one of them, e.g. --voice kal_diphone)"
            }
        }
    }

    /// Whether its error output `said` tells that voice `voice` does not exist: espeak-ng fails
    /// with "The specified espeak-ng voice does not exist"; festival's `text2wave` exits 0 and
    /// writes nothing, having said "unbound variable : voice_NAME".
    fn says_no_voice(self, said: &str, voice: &str) -> bool {
        match self {
            Self::Espeak => said.contains("voice does not exist"),
            Self::Festival => {
                said.contains("unbound variable")
                    && said.contains(&format!("voice_{}", voice.trim_start_matches("voice_")))
            }
        }
    }
}

/// Command-line arguments of `pneuma speak`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The text to speak ("." and "_" mark pauses).
    pub text: Option<String>,
    /// Read the text from this file instead.
    #[arg(long, value_name = "FILE", conflicts_with = "text")]
    pub text_file: Option<PathBuf>,
    /// Output folder (created if missing); receives speech.wav (or the --format's), speech.controls.csv,
    /// speech.breaths.csv and speech.png.
    #[arg(short = 'o', long = "output", alias = "out", value_name = "DIR")]
    pub out_dir: PathBuf,
    /// Audio format of speech.*: 16-bit WAV, FLAC or AIFF at the TTS's rate, or MP3.
    #[arg(long, value_enum, default_value_t = Container::Wav)]
    pub format: Container,
    /// MP3 encoding (`--bitrate`, `--vbr`), as in `render`.
    #[command(flatten)]
    pub mp3: crate::mp3_out::Mp3Args,
    /// Breathing preset.
    #[arg(long, default_value = "neutral", value_parser = clap::builder::PossibleValuesParser::new(Preset::NAMES))]
    pub preset: String,
    /// TTS voice (espeak-ng: e.g. `en-us`, `en-gb`; festival: e.g. `kal_diphone`).
    #[arg(long)]
    pub voice: Option<String>,
    /// Speaking-rate multiplier (the table's `prosody_rate`; default: the preset's).
    #[arg(long, help = RATE.help_with_default("the preset's"), value_parser = crate::options::number)]
    pub rate: Option<f64>,
    /// Speaking loudness (the table's `speaking_loudness`; default: the preset's); louder
    /// speech gets shorter breath groups (Equation 1) and a louder TTS.
    #[arg(long, help = LOUDNESS.help_with_default("the preset's"), value_parser = crate::options::number)]
    pub loudness: Option<f64>,
    /// Seed of the breath sounds (the same default as `render`).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Refuse to replace existing outputs. By default existing outputs are replaced, all
    /// together and only when the whole run succeeded.
    #[arg(short = 'n', long)]
    pub no_overwrite: bool,
    /// Print errors only, no summary.
    #[arg(long, short)]
    pub quiet: bool,
    /// TTS program.
    #[arg(long, value_enum, default_value_t = Tts::Espeak)]
    pub tts: Tts,
    /// A recording of a mouth inhalation ([`crate::options::BREATH_MOUTH_HELP`]).
    #[arg(long, value_name = "FILE", help = crate::options::BREATH_MOUTH_HELP)]
    pub breath_mouth: Option<PathBuf>,
    /// A recording of a nose inhalation ([`crate::options::BREATH_NOSE_HELP`]).
    #[arg(long, value_name = "FILE", help = crate::options::BREATH_NOSE_HELP)]
    pub breath_nose: Option<PathBuf>,
    /// Head-pose model file (JSON); the embedded default model when absent.
    #[arg(long, value_name = "JSON")]
    pub head_model: Option<PathBuf>,
    /// Analysis and control frames per second (the table's `frame_rate_hz`; help text:
    /// [`crate::options::frame_rate_help`]).
    #[arg(long, help = crate::options::frame_rate_help(), default_value_t = FRAME_RATE.default_value())]
    pub frame_rate: f64,
    /// BVH output as in `render` (`--bvh`, `--bvh-fps`).
    #[command(flatten)]
    pub bvh: crate::bvh_out::BvhArgs,
    /// MIDI file output as in `render` (`--midi`, `--midi-14bit`, `--midi-head-range-deg`).
    #[command(flatten)]
    pub midi: crate::midi_out::MidiArgs,
    /// OSC output as in `render` (the frames are sent once the files are written).
    #[command(flatten)]
    pub osc: crate::osc_out::OscArgs,
    /// Skip the plot.
    #[arg(long)]
    pub no_plot: bool,
    /// Breath level relative to the speech level, dB, as in `render` (help, range, default:
    /// the table's `breath_level_db`).
    #[arg(long, conflicts_with = "no_breaths", help = BREATH_LEVEL.help(), default_value_t = BREATH_LEVEL.default_value(), allow_hyphen_values = true, value_parser = crate::options::number)]
    pub breath_level_db: f64,
    /// Insert no breath sound: a dry take of the same timeline (its pauses stay silent), with
    /// the breathing and the head in the controls as with breaths.
    #[arg(long)]
    pub no_breaths: bool,
    /// Folder with breath samples `mouth.wav` and/or `nose.wav` (the same as giving them with
    /// --breath-mouth and --breath-nose, as in `render`).
    #[arg(long, value_name = "DIR", conflicts_with_all = ["breath_mouth", "breath_nose"])]
    pub breath_samples: Option<PathBuf>,
}

/// Errors of `pneuma speak`.
#[derive(Debug, Error)]
pub enum SpeakError {
    /// An option is out of range or inconsistent.
    #[error("{0}")]
    Option(String),
    /// No text given.
    #[error("no text to speak: give TEXT or --text-file FILE with some words in it")]
    NoText,
    /// The text file cannot be read, is too large or is no text.
    #[error("--text-file: {0}")]
    TextFile(#[source] CappedReadError),
    /// Bad breathing settings.
    #[error(transparent)]
    Breathing(#[from] BreathingError),
    /// The TTS program is not installed.
    #[error("`{program}` was not found: install the Debian package `{package}` (apt-get install {package}) or choose another --tts")]
    MissingTts {
        /// The program.
        program: &'static str,
        /// The package that provides it.
        package: &'static str,
    },
    /// The TTS program failed.
    #[error("`{program}` failed on chunk {chunk:?}: {reason}")]
    TtsFailed {
        /// The program.
        program: &'static str,
        /// The chunk's text.
        chunk: String,
        /// What went wrong.
        reason: String,
    },
    /// The TTS program does not know the voice asked for (said once, in our words: its own
    /// message is left out).
    #[error(
        "{} has no voice `{voice}`: {}, or leave --voice out for its default",
        .tts.name(),
        .tts.voices_hint()
    )]
    UnknownVoice {
        /// The TTS program.
        tts: Tts,
        /// The voice asked for.
        voice: String,
    },
    /// The TTS's output could not be read.
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// The TTS changed its sample rate between chunks.
    #[error("the TTS produced {0} Hz and then {1} Hz; use one voice")]
    RateChanged(u32, u32),
    /// An output file could not be written.
    #[error("cannot write {path}: {source}{}", crate::output::write_hint(source))]
    Output {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The engine refused its settings or the TTS's rate.
    #[error(transparent)]
    Engine(#[from] EngineError),
}

/// What `speak` produced.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeakSummary {
    /// The chunks, in order.
    pub chunks: Vec<Chunk>,
    /// Measured duration of each chunk's speech, seconds.
    pub chunk_durations_s: Vec<f64>,
    /// Total length of speech.wav, seconds.
    pub duration_s: f64,
    /// The inserted breaths.
    pub breaths: Vec<BreathEvent>,
    /// What was sent as OSC (`--osc`), for the summary.
    pub osc: Option<String>,
    /// The optional files an earlier run left that this one did not write (removed, or kept
    /// with `--no-overwrite`).
    pub leftovers: Cleared,
    /// The characters the TTS could not be given (festival reads ASCII only): left out.
    pub left_out: Vec<char>,
    /// Audio files of other formats named `speech.*` beside this take's: left, and named.
    pub other_audio: Vec<PathBuf>,
}

/// Runs `pneuma speak`.
pub fn main(args: Args) -> ExitCode {
    let created = crate::options::missing_folders(&args.out_dir);
    crate::output::created_folders(&created);
    let result = run(&args);
    if result.is_err() {
        crate::options::remove_empty(&created);
    }
    match result {
        Ok(s) => {
            if !args.quiet {
                // The engine breathes in every pause of the speech, the TTS's own pauses
                // inside a chunk too: the breaths, not the chunks, count the groups spoken.
                eprintln!(
                    "spoke {:.2} s with {} (the text cut into {} by the chunker) into {}",
                    s.duration_s,
                    plural(s.breaths.len(), "breath", "breaths"),
                    plural(s.chunks.len(), "chunk", "chunks"),
                    args.out_dir.display()
                );
                if let Some(osc) = &s.osc {
                    eprintln!("  {osc}");
                }
                for w in s.leftovers.warnings() {
                    eprintln!("warning: {w}");
                }
                for other in &s.other_audio {
                    eprintln!("warning: {}", files::other_audio_line(other, args.format));
                }
            }
            // Words lost and removals are never silent, not even under --quiet.
            if !s.left_out.is_empty() {
                eprintln!("warning: {}", left_out_line(args.tts, &s.left_out));
            }
            if let Some(removed) = s.leftovers.removed_line() {
                eprintln!("{removed}");
            }
            if crate::render::interrupted() {
                eprintln!("interrupted (Ctrl-C, SIGTERM or SIGHUP) while sending OSC: the files are written");
                return ExitCode::from(crate::render::EXIT_INTERRUPTED);
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// What a TTS could not be given, and what to do.
fn left_out_line(tts: Tts, left_out: &[char]) -> String {
    // A character that does not print is named by its code point.
    let shown: Vec<String> = left_out
        .iter()
        .take(8)
        .map(|&c| {
            if c.is_control() || c.is_whitespace() {
                format!("U+{:04X}", u32::from(c))
            } else {
                c.to_string()
            }
        })
        .collect();
    let shown = shown.join(" ");
    format!(
        "{} reads ASCII only: {} without an ASCII spelling {} left out ({shown}{}); \
         espeak-ng (--tts espeak, the default) is given the text as written",
        tts.name(),
        plural(left_out.len(), "character", "characters"),
        if left_out.len() == 1 { "was" } else { "were" },
        if left_out.len() > 8 { " …" } else { "" }
    )
}

/// `1 breath`, `2 breaths`.
fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// The breathing parameters from the preset and the overrides, validated.
pub fn params_from_args(args: &Args) -> Result<BreathingParams, SpeakError> {
    if let Some(r) = args.rate {
        RATE.check(r).map_err(SpeakError::Option)?;
    }
    if let Some(l) = args.loudness {
        LOUDNESS.check(l).map_err(SpeakError::Option)?;
    }
    FRAME_RATE
        .check(args.frame_rate)
        .map_err(SpeakError::Option)?;
    let mut p = Preset::from_name(&args.preset)?.params();
    if let Some(r) = args.rate {
        p.prosody_rate = r as f32;
    }
    if let Some(l) = args.loudness {
        p.speaking_loudness = l as f32;
    }
    p.validate()?;
    Ok(p)
}

fn text_from_args(args: &Args) -> Result<String, SpeakError> {
    let text = match (&args.text, &args.text_file) {
        (_, Some(path)) => read_text_capped(path, TEXT_MAX_BYTES, "a text to speak")
            .map_err(SpeakError::TextFile)?,
        (Some(t), None) => t.clone(),
        (None, None) => String::new(),
    };
    if text
        .split_whitespace()
        .all(|w| !w.chars().any(char::is_alphanumeric))
    {
        return Err(SpeakError::NoText);
    }
    Ok(text)
}

/// Synthesises `text` with the chosen TTS into mono samples and their rate.
fn synthesize(
    tts: Tts,
    text: &str,
    voice: Option<&str>,
    rate: f32,
    loudness: f32,
    dir: &Path,
) -> Result<(Vec<f32>, u32), SpeakError> {
    let wav = dir.join("chunk.wav");
    let (program, package) = tts.program();
    // A file left by the chunk before must not pass for this one's (festival exits 0 without
    // writing when it fails).
    let _ = std::fs::remove_file(&wav);
    let mut cmd = Command::new(program);
    match tts {
        Tts::Espeak => {
            let wpm = (175.0 * rate).round().clamp(80.0, 450.0) as u32;
            let amplitude = (100.0 * loudness / 0.5).round().clamp(10.0, 200.0) as u32;
            cmd.arg("--stdin")
                .arg("-s")
                .arg(wpm.to_string())
                .arg("-a")
                .arg(amplitude.to_string())
                .arg("-w")
                .arg(&wav);
            if let Some(v) = voice {
                cmd.arg("-v").arg(v);
            }
        }
        Tts::Festival => {
            cmd.arg("-o").arg(&wav);
            cmd.arg("-scale").arg(format!("{:.3}", loudness / 0.5));
            if let Some(v) = voice {
                let v = v.trim_start_matches("voice_");
                cmd.arg("-eval").arg(format!("(voice_{v})"));
            }
            cmd.arg("-eval").arg(format!(
                "(Parameter.set 'Duration_Stretch {:.3})",
                1.0 / rate
            ));
        }
    }
    let failed = |reason: String| SpeakError::TtsFailed {
        program,
        chunk: text.to_owned(),
        reason,
    };
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => SpeakError::MissingTts { program, package },
            _ => failed(e.to_string()),
        })?;
    if let Some(mut stdin) = child.stdin.take() {
        // A TTS that stopped reading (it failed at once) says why on its error output, below.
        stdin
            .write_all(text.as_bytes())
            .and_then(|()| stdin.write_all(b"\n"))
            .or_else(|e| match e.kind() {
                std::io::ErrorKind::BrokenPipe => Ok(()),
                _ => Err(e),
            })
            .map_err(|e| failed(e.to_string()))?;
    }
    let out = child
        .wait_with_output()
        .map_err(|e| failed(e.to_string()))?;
    let said = String::from_utf8_lossy(&out.stderr);
    let wrote = wav.is_file();
    if !out.status.success() || !wrote {
        // The failure that names the voice: ours says it once, with what to do.
        if let Some(v) = voice.filter(|v| tts.says_no_voice(&said, v)) {
            return Err(SpeakError::UnknownVoice {
                tts,
                voice: v.to_owned(),
            });
        }
        let what = if out.status.success() {
            "wrote no audio".to_owned()
        } else {
            out.status.to_string()
        };
        return Err(failed(match said.trim() {
            "" => what,
            said => format!("{what}: {said}"),
        }));
    }
    Ok(read_mono(&wav)?)
}

/// Trims leading and trailing samples below [`TRIM_DB`] (keeping 10 ms of margin).
pub fn trim_silence(audio: &[f32], rate_hz: u32) -> &[f32] {
    let threshold = 10f32.powf(TRIM_DB / 20.0);
    let margin = (0.01 * rate_hz as f64) as usize;
    let first = audio.iter().position(|v| v.abs() > threshold);
    let last = audio.iter().rposition(|v| v.abs() > threshold);
    match (first, last) {
        (Some(a), Some(b)) => &audio[a.saturating_sub(margin)..(b + 1 + margin).min(audio.len())],
        _ => &audio[..0],
    }
}

/// Reads the breath sample at `path`; `label` (the option that named it) names it in errors.
fn load_sample(path: &Path, label: &str) -> Result<BreathSample, SpeakError> {
    let (samples, rate) =
        read_mono(path).map_err(|e| SpeakError::Option(format!("{label}: {e}")))?;
    BreathSample::from_mono(samples, rate as f64).map_err(|e| {
        SpeakError::Breathing(BreathingError::BadSample(format!(
            "{label} {}: {e}",
            path.display()
        )))
    })
}

/// Runs `speak` and returns what it produced.
pub fn run(args: &Args) -> Result<SpeakSummary, SpeakError> {
    let text = text_from_args(args)?;
    let params = params_from_args(args)?;
    let low = params.map();
    let in_folder = |name: &str| {
        args.breath_samples
            .as_ref()
            .and_then(|d| pneuma_io::find_audio(d, name))
    };
    if let Some(d) = &args.breath_samples {
        if in_folder("mouth").is_none() && in_folder("nose").is_none() {
            return Err(SpeakError::Option(format!(
                "--breath-samples {}: no mouth or nose audio file (mouth.wav, nose.flac, …) in it",
                d.display()
            )));
        }
    }
    let mouth_path = args.breath_mouth.clone().or_else(|| in_folder("mouth"));
    let nose_path = args.breath_nose.clone().or_else(|| in_folder("nose"));
    let model =
        crate::options::load_head_model(args.head_model.as_deref()).map_err(SpeakError::Option)?;
    // The option that named each sample, for its errors.
    let label = |one: &'static str| {
        if args.breath_samples.is_some() {
            "--breath-samples"
        } else {
            one
        }
    };
    let mouth_sample = mouth_path
        .as_deref()
        .map(|p| load_sample(p, label("--breath-mouth")))
        .transpose()?;
    let nose_sample = nose_path
        .as_deref()
        .map(|p| load_sample(p, label("--breath-nose")))
        .transpose()?;
    let mut chunks = chunk_text(&text, &low);
    // festival says the bytes of a UTF-8 "é" as a pause or a letter: it is given each chunk in
    // ASCII (the chunker reads the text as written, its dashes among its breaks).
    let mut left_out = Vec::new();
    if args.tts == Tts::Festival && !chunks.is_empty() {
        (chunks, left_out) = crate::ascii_text::fold_chunks(chunks);
        if chunks.is_empty() {
            return Err(SpeakError::Option(left_out_line(args.tts, &left_out)));
        }
    }
    if chunks.is_empty() {
        return Err(SpeakError::NoText);
    }
    crate::options::check_output_folder("-o", &args.out_dir).map_err(SpeakError::Option)?;
    if let (Tts::Espeak, Some(v)) = (args.tts, args.voice.as_deref()) {
        if voices::espeak_knows(v) == Some(false) {
            return Err(SpeakError::UnknownVoice {
                tts: args.tts,
                voice: v.to_owned(),
            });
        }
    }
    let osc = args.osc.plan().map_err(SpeakError::Option)?;
    let bvh_fps = args.bvh.fps().map_err(SpeakError::Option)?;
    let cc_map = args.midi.map().map_err(SpeakError::Option)?;
    args.mp3
        .check_asked(args.format == Container::Mp3)
        .map_err(SpeakError::Option)?;
    if args.no_overwrite {
        let paths = files::all_paths(&args.out_dir, args.format);
        crate::options::refuse_existing(&paths).map_err(SpeakError::Option)?;
    }
    std::fs::create_dir_all(&args.out_dir).map_err(|source| SpeakError::Output {
        path: args.out_dir.clone(),
        source,
    })?;
    let scratch = Scratch::new(&args.out_dir)?;

    // Synthesise and measure every chunk.
    let mut rate_hz = 0u32;
    let mut mp3 = None;
    let mut speech: Vec<Vec<f32>> = Vec::with_capacity(chunks.len());
    for c in &chunks {
        let (audio, r) = synthesize(
            args.tts,
            &c.text,
            args.voice.as_deref(),
            low.prosody_rate,
            low.speaking_loudness,
            &scratch.0,
        )?;
        if rate_hz != 0 && r != rate_hz {
            return Err(SpeakError::RateChanged(rate_hz, r));
        }
        if rate_hz == 0 {
            // The MP3's bitrate range depends on the TTS's rate: checked on the first chunk,
            // before the rest is spoken.
            mp3 = args
                .mp3
                .settings(
                    args.format == Container::Mp3,
                    Path::new("-"),
                    InputFormat::Wav,
                    r,
                )
                .map_err(SpeakError::Option)?;
        }
        rate_hz = r;
        speech.push(trim_silence(&audio, r).to_vec());
    }
    let fs = rate_hz as f64;
    let formats = files::Formats {
        container: args.format,
        mp3,
        bvh_fps,
        cc_map,
    };

    // Lay out the timeline: each chunk after a pause long enough for the breath its group
    // needs; the engine then breathes into those pauses as it does in a recording.
    let secs = |n: usize| n as f64 / fs;
    let samples = |s: f64| (s * fs).round() as usize;
    let mut audio: Vec<f32> = vec![0.0; samples(LEAD_IN_S)];
    let mut durations = Vec::with_capacity(chunks.len());
    for s in &speech {
        let utterance_s = secs(s.len());
        durations.push(utterance_s);
        audio.resize(
            audio.len() + samples(pause_before_s(&low, utterance_s)),
            0.0,
        );
        audio.extend_from_slice(s);
    }
    audio.resize(audio.len() + samples(TAIL_S), 0.0);

    // The engine over the timeline, as `pneuma render` over a recording (whole-file lookahead):
    // the whole timeline heard first, its analysis replayed. A TTS breathes nothing, so nothing
    // is learned from what the tracker takes for a breath in it (a fricative's tail): the
    // built-in voice, coloured by the TTS's speech over the whole timeline, as a render of a
    // recording without breaths.
    let config = engine_config(args, params)?;
    let mut heard = VoiceLearner::recording(&config, fs)?;
    heard.feed(&audio)?;
    let heard = heard.finish()?;
    let mut engine = Engine::new(config, model)?;
    engine.set_voice_mode(BreathVoiceMode::BuiltIn);
    engine.prepare(fs, BLOCK, 1)?;
    if let Some(record) = heard.record {
        engine.replay_analysis(record)?;
    }
    engine.set_breath_sample(SampleSlot::Mouth, mouth_sample);
    engine.set_breath_sample(SampleSlot::Nose, nose_sample);
    let rendered = offline::render(&mut engine, std::slice::from_ref(&audio), &[BLOCK]);
    let file_frames = FrameClock::new(args.frame_rate, fs).frames_in(audio.len() as u64);
    let frames: Vec<ControlFrame> = rendered
        .frames
        .into_iter()
        .map(|(f, _)| f)
        .filter(|f| f.index < file_frames)
        .collect();
    let breaths = rendered.breaths;
    let mut audio = rendered.audio.into_iter().next().unwrap_or_default();
    for v in audio.iter_mut() {
        *v = v.clamp(-1.0, 1.0);
    }

    let take = files::Take {
        audio: &audio,
        rate_hz,
        frames: &frames,
        breaths: &breaths,
    };
    let leftovers = files::write(args, &take, &formats)?;
    let osc = match osc {
        Some(plan) => {
            let mut sender = plan.open().map_err(SpeakError::Option)?;
            // The files are written: Ctrl-C now stops the sending, and the stream still ends
            // in the rest pose (a second Ctrl-C exits at once).
            crate::render::install_interrupt_handler();
            for f in &frames {
                if crate::render::interrupted() {
                    break;
                }
                sender.frame(f, 0);
            }
            Some(plan.finish(sender))
        }
        None => None,
    };
    Ok(SpeakSummary {
        chunks,
        chunk_durations_s: durations,
        duration_s: secs(audio.len()),
        breaths,
        osc,
        leftovers,
        left_out,
        other_audio: files::other_audio(&args.out_dir, args.format),
    })
}

/// The silence laid out before a chunk of `utterance_s` seconds: the gap after the previous
/// chunk plus room for an inspiration that grows with the share of a full breath group the
/// chunk takes (half the preset's inspiration for a short chunk, all of it for a full group),
/// so the engine's breath in it varies with the group as a speaker's does.
pub fn pause_before_s(low: &LowLevelParams, utterance_s: f64) -> f64 {
    let share = (utterance_s / f64::from(low.length_utterance_s).max(1e-3)).clamp(0.0, 1.0);
    PAUSE_S + f64::from(low.length_inspiration_s) * (0.5 + 0.5 * share)
}

/// The engine settings of `speak`: the preset's breathing, the control frame rate and seed
/// asked for, breaths in every pause (the timeline holds only the TTS's speech, so no speech
/// decision is needed) with the whole file known in advance, as `pneuma render` of a file.
fn engine_config(args: &Args, params: BreathingParams) -> Result<EngineConfig, SpeakError> {
    let mut c = EngineConfig::default();
    // The options in the user's terms against the table's ranges, as `render` checks them.
    for (flag, value) in [
        (&FRAME_RATE, args.frame_rate),
        (&BREATH_LEVEL, args.breath_level_db),
    ] {
        flag.apply(&mut c, value).map_err(SpeakError::Option)?;
    }
    c.breathing = params;
    c.seed = args.seed;
    c.placement.whole_file = true;
    c.placement.insert_breaths = !args.no_breaths;
    c.placement.speech_only = false;
    c.validate()?;
    Ok(c)
}

/// A scratch folder for the TTS output, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(parent: &Path) -> Result<Self, SpeakError> {
        let dir = parent.join(format!(".pneuma-speak-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|source| SpeakError::Output {
            path: dir.clone(),
            source,
        })?;
        Ok(Self(dir))
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
