//! Turning `pneuma render`'s arguments into a validated plan: the input files (folders
//! expanded, a batch's names and job count checked) and, for one input, a [`Job`]: the opened
//! input, the engine settings and the engine prepared for that input (head model, breath
//! samples), and where each output goes ([`OutputPlan`]). Everything a render can refuse before
//! it writes is refused here, in the order a user meets it; nothing is written here.

use std::path::{Path, PathBuf};

use pneuma_core::breathing::{BreathSample, Preset, SampleSlot};
use pneuma_core::encode::midi_cc::CcMap;
use pneuma_core::engine::{Engine, EngineConfig, EngineError, PlacementMode};
use pneuma_io::{AudioSource, InputFormat, WavMeta};

use super::error::RenderError;
use super::findings::Finding;
use super::leftovers::Leftover;
use super::marks::Optional;
use crate::audio_out::Container;
use crate::channel::Channel;
use crate::markers::MarkerKind;
use crate::options::{
    render_for, SettingFlag, BREATH_LEVEL, FRAME_RATE, LOOKAHEAD, MIN_PAUSE, MODE, SETTING_FLAGS,
};
use crate::wav::WavInfo;

/// Sample frames per block.
pub const BLOCK_FRAMES: usize = 4096;

/// Most jobs accepted by `--jobs`.
const MAX_JOBS: usize = 256;

/// Parses `--jobs`, refusing a count outside 1..=[`MAX_JOBS`] whether or not a batch follows.
fn parse_jobs(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_JOBS).contains(&n) => Ok(n),
        _ => Err(format!("{text} is out of range: use 1 to {MAX_JOBS}")),
    }
}

/// Command-line arguments of `pneuma render`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Input audio: WAV, FLAC, MP3, M4A/AAC, Ogg Vorbis, AIFF or CAF (1 to 8 channels, or any
    /// count with `--channel`; 8–192 kHz); `-` reads standard input. Several files or folders render them all (a batch, in
    /// parallel; folders give the audio files directly inside them).
    #[arg(required = true, value_name = "IN")]
    pub inputs: Vec<PathBuf>,
    /// Output folder (created if missing); the files inside are named after the input. `-`
    /// writes only the audio, as WAV, to standard output (one input).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Audio format of the output: by default the input's own for WAV, FLAC and AIFF, and FLAC
    /// for everything else (never a second lossy generation); MP3 only when asked.
    #[arg(long, value_enum)]
    pub format: Option<Container>,
    /// MP3 encoding (`--bitrate`, `--vbr`).
    #[command(flatten)]
    pub mp3: crate::mp3_out::Mp3Args,
    /// Breath markers for editors, comma-separated: audacity (label track
    /// `<stem>.breaths.txt`), reaper (region list `<stem>.breaths.reaper.csv`), cue (cue points
    /// inside the output WAV; in a batch, a file whose output is not WAV gets the Audacity
    /// label track instead, with a warning).
    #[arg(long, value_enum, value_delimiter = ',', value_name = "KIND")]
    pub markers: Vec<MarkerKind>,
    /// Set by the render itself for a batch's files: what one file's render refuses (cue
    /// points in an output that is not WAV) becomes a warning.
    #[arg(skip)]
    pub in_batch: bool,
    /// Files rendered at once in a batch (1 to 256; default: the number of cores).
    #[arg(short = 'j', long, value_name = "N", value_parser = parse_jobs)]
    pub jobs: Option<usize>,
    /// Breathing preset.
    #[arg(long, default_value = "neutral", value_parser = clap::builder::PossibleValuesParser::new(Preset::NAMES))]
    pub preset: String,
    /// Breath level relative to the speech level, dB (help, range, default: the table's
    /// `breath_level_db`).
    #[arg(long, conflicts_with = "no_breaths", help = BREATH_LEVEL.help(), default_value_t = BREATH_LEVEL.default_value(), allow_hyphen_values = true, value_parser = crate::options::number)]
    pub breath_level_db: f64,
    /// Shortest pause that gets a full breath, ms (the table's `min_pause_s`).
    #[arg(long, help = MIN_PAUSE.help(), default_value_t = MIN_PAUSE.default_value(), value_parser = crate::options::number)]
    pub min_pause_ms: f64,
    /// Placement: `lookahead` or `live` (the table's `mode`).
    #[arg(long, help = MODE.help(), default_value = MODE.setting.names()[MODE.setting.default as usize], value_parser = clap::builder::PossibleValuesParser::new(MODE.setting.names()))]
    pub mode: String,
    /// Lookahead of the lookahead mode, ms (the table's `lookahead_s`): renders as the plugin
    /// with that lookahead. Without it the render looks seconds ahead (the engine's whole-file
    /// lookahead).
    #[arg(long, help = LOOKAHEAD.help_with_default(&format!("none: the render looks seconds ahead, the engine's whole-file lookahead; the plugin's is {}", LOOKAHEAD.setting.default_text(LOOKAHEAD.unit))), value_parser = crate::options::number)]
    pub lookahead_ms: Option<f64>,
    /// Do not insert breaths (controls only; the audio samples are written unchanged, with the
    /// tags and cue points any render carries, not the input's other chunks such as bext).
    #[arg(long)]
    pub no_breaths: bool,
    /// Breaths in the pauses of any sound, not only of speech (the speech decision off): for
    /// singing or generated test signals. Music, noise and silence then get breaths too.
    #[arg(long)]
    pub any_sound: bool,
    /// Render one channel of the input as a mono file: `left` (the first), `right` (the
    /// second) or its number from 1 (one track of a multitrack recording; any channel count).
    /// For a file whose channels cancel when mixed to mono (antiphase), or one speaker's track.
    #[arg(long, value_parser = Channel::parse, value_name = "CHANNEL")]
    pub channel: Option<Channel>,
    /// Folder with user breath samples `mouth.wav` and/or `nose.wav` (or .flac, .aiff, … any
    /// input format; the same as giving them with --breath-mouth and --breath-nose, which it
    /// cannot be combined with).
    #[arg(
        long,
        conflicts_with_all = ["no_breaths", "breath_mouth", "breath_nose"],
        value_name = "DIR"
    )]
    pub breath_samples: Option<PathBuf>,
    /// A recording of a mouth inhalation ([`crate::options::BREATH_MOUTH_HELP`]).
    #[arg(long, conflicts_with = "no_breaths", value_name = "FILE", help = crate::options::BREATH_MOUTH_HELP)]
    pub breath_mouth: Option<PathBuf>,
    /// A recording of a nose inhalation ([`crate::options::BREATH_NOSE_HELP`]).
    #[arg(long, conflicts_with = "no_breaths", value_name = "FILE", help = crate::options::BREATH_NOSE_HELP)]
    pub breath_nose: Option<PathBuf>,
    /// Learn the breath voice from this recording of the same speaker (e.g. the raw take
    /// before its breaths were edited out) instead of from the input.
    #[arg(long, conflicts_with = "no_breaths", value_name = "FILE")]
    pub breath_like: Option<PathBuf>,
    /// Use the built-in breath voice: learn nothing from the recording.
    #[arg(long, conflicts_with_all = ["breath_like", "no_breaths"])]
    pub built_in_breath: bool,
    /// Head-pose model file (JSON); the embedded default model when absent.
    #[arg(long)]
    pub head_model: Option<PathBuf>,
    /// Seed of every random source.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Analysis and control frames per second (the table's `frame_rate_hz`; help text:
    /// [`crate::options::frame_rate_help`]).
    #[arg(long, help = crate::options::frame_rate_help(), default_value_t = FRAME_RATE.default_value())]
    pub frame_rate: f64,
    /// BVH output (`--bvh`, `--bvh-fps`).
    #[command(flatten)]
    pub bvh: crate::bvh_out::BvhArgs,
    /// MIDI file output (`--midi`, `--midi-14bit`, `--midi-head-range-deg`).
    #[command(flatten)]
    pub midi: crate::midi_out::MidiArgs,
    /// OSC output (`--osc`, `--osc-host`, `--osc-port`, `--osc-format`, `--osc-speed`).
    #[command(flatten)]
    pub osc: crate::osc_out::OscArgs,
    /// Skip the plot.
    #[arg(long)]
    pub no_plot: bool,
    /// Refuse to replace existing outputs. By default existing outputs are replaced, all
    /// together and only when the whole run succeeded.
    #[arg(short = 'n', long)]
    pub no_overwrite: bool,
    /// No progress bar (the summary stays).
    #[arg(long)]
    pub no_progress: bool,
    /// Print errors only, and the files removed as an earlier render's leftovers (a removal is
    /// never silent): no progress bar, no summary, no warnings.
    #[arg(long, short)]
    pub quiet: bool,
}

impl Args {
    /// The engine settings these arguments ask for.
    pub fn engine_config(&self) -> Result<EngineConfig, RenderError> {
        let preset = Preset::from_name(&self.preset)
            .map_err(|e| RenderError::Input(format!("--preset: {e}")))?;
        // The options in the user's terms (the option typed, in its unit) against the table's
        // ranges first; the engine checks its own settings again.
        self.bvh.fps().map_err(RenderError::Input)?;
        let mut c = EngineConfig::default();
        let mut set = |flag: &SettingFlag, value: f64| -> Result<(), RenderError> {
            flag.apply(&mut c, value).map_err(RenderError::Input)
        };
        set(&BREATH_LEVEL, self.breath_level_db)?;
        set(&MIN_PAUSE, self.min_pause_ms)?;
        if let Some(ms) = self.lookahead_ms {
            set(&LOOKAHEAD, ms)?;
        }
        set(&FRAME_RATE, self.frame_rate)?;
        let mode = MODE
            .setting
            .parse(&self.mode)
            .map_err(|e| RenderError::Input(render_for(&SETTING_FLAGS, &e)))?;
        set(&MODE, mode)?;
        if self.lookahead_ms.is_some() && c.placement.mode == PlacementMode::Live {
            return Err(RenderError::Input(
                "--lookahead-ms sets lookahead mode's delay, and live mode has none: drop \
                 --lookahead-ms to render live, or --mode live to render with the plugin's \
                 lookahead"
                    .into(),
            ));
        }
        c.placement.whole_file = self.lookahead_ms.is_none();
        c.placement.insert_breaths = !self.no_breaths;
        c.placement.speech_only = !self.any_sound;
        c.breathing = preset.params();
        c.seed = self.seed;
        c.validate()?;
        Ok(c)
    }

    /// `-o -`: only the audio, to standard output.
    pub(crate) fn to_stdout(&self) -> bool {
        self.output.as_os_str() == "-"
    }
}

/// The groups of inputs whose outputs would have the same names (the same output stem, letter
/// case aside), each with every input of that stem, in the order given; the groups in the order
/// of their first input. Case is set aside on every system: macOS and Windows file systems
/// take `Talk.png` and `talk.png` for one file, and a folder rendered on Linux may be read there.
fn clashing_stems(inputs: &[PathBuf]) -> Vec<Vec<&Path>> {
    let mut groups: Vec<(String, Vec<&Path>)> = Vec::new();
    for p in inputs {
        let stem = output_stem(p).to_lowercase();
        match groups.iter_mut().find(|(s, _)| *s == stem) {
            Some((_, group)) => group.push(p),
            None => groups.push((stem, vec![p])),
        }
    }
    groups
        .into_iter()
        .map(|(_, g)| g)
        .filter(|g| g.len() > 1)
        .collect()
}

/// The error for clashing inputs: every group on its own line, so one renaming pass fixes all.
fn clash_message(groups: &[Vec<&Path>], output: &Path) -> String {
    let lines: Vec<String> = groups
        .iter()
        .map(|g| {
            let names: Vec<String> = g.iter().map(|p| p.display().to_string()).collect();
            format!("\n  {}", names.join(", "))
        })
        .collect();
    format!(
        "inputs with the same name (letter case aside) would write the same output files in {} \
         ({}):{}\nrename all but one of each group, or render them into different folders",
        output.display(),
        crate::options::count(groups.len(), "group"),
        lines.concat()
    )
}

/// Checks a batch's arguments before anything runs; the number of render threads.
pub fn check_batch(args: &Args, inputs: &[PathBuf]) -> Result<usize, String> {
    if args.to_stdout() {
        return Err(
            "-o - (standard output) takes one input; give an output folder for a batch".into(),
        );
    }
    if inputs.iter().any(|p| p.as_os_str() == "-") {
        return Err("- (standard input) cannot be part of a batch; render it on its own".into());
    }
    if args.osc.wanted() {
        return Err(
            "OSC sends one render's frames as they play: render one file with --osc, \
                    or drop the --osc options for a batch"
                .into(),
        );
    }
    let clashes = clashing_stems(inputs);
    if !clashes.is_empty() {
        return Err(clash_message(&clashes, &args.output));
    }
    // The parser refused counts outside 1..=MAX_JOBS.
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    Ok(jobs.min(inputs.len()).max(1))
}

/// The output container for an input: `asked`, else the input's own when it is lossless and
/// writable (WAV, FLAC, AIFF), else FLAC (other lossless containers, and lossy input, which is
/// never encoded lossy a second time).
pub fn output_container(asked: Option<Container>, format: InputFormat) -> Container {
    asked.unwrap_or(match format {
        InputFormat::Wav => Container::Wav,
        InputFormat::Aiff => Container::Aiff,
        _ => Container::Flac,
    })
}

/// One input's render, checked and ready to run: nothing is written yet.
pub struct Job {
    /// The opened input.
    pub source: AudioSource,
    /// The format rendered (rate, channels, bits also of the output): the input's, with one
    /// channel when `--channel` picks one.
    pub info: WavInfo,
    /// The input's channels, and the one rendered (`--channel`), if one.
    pub input_channels: (usize, Option<usize>),
    /// The input's container and whether it is lossless.
    pub input_format: (InputFormat, bool),
    /// What the output carries over from the input: its tags (any format), a WAV's cue
    /// points and its `fmt ` form (kept only for a WAV of the input's channels).
    pub carried: WavMeta,
    /// The engine, prepared for the rendered rate and channels, with the breath samples.
    pub engine: Engine,
    /// What the user should know about the `--breath-like` file.
    pub breath_like_note: Option<Finding>,
    /// Where the outputs go.
    pub outputs: OutputPlan,
}

/// The files a render writes into its output folder besides the audio.
#[derive(Debug, Clone, PartialEq)]
pub struct FolderFiles {
    /// The output folder (created by the render).
    pub folder: PathBuf,
    /// `<stem>.controls.csv`.
    pub controls: PathBuf,
    /// `<stem>.breaths.csv`.
    pub breaths: PathBuf,
    /// `<stem>.png`, unless `--no-plot`.
    pub plot: Option<PathBuf>,
    /// `<stem>.bvh` with `--bvh`.
    pub bvh: Option<PathBuf>,
    /// `<stem>.mid` with `--midi`.
    pub midi: Option<PathBuf>,
    /// The marker files with `--markers` (cue points are inside the audio).
    pub markers: Vec<(MarkerKind, PathBuf)>,
}

/// Which of the optional files beside the audio a render writes.
#[derive(Debug, Clone, Copy)]
struct Wanted<'a> {
    plot: bool,
    bvh: bool,
    midi: bool,
    markers: &'a [MarkerKind],
}

impl Wanted<'static> {
    /// Every optional file: the names an earlier render of the same stem may have left.
    fn all() -> Self {
        Self {
            plot: true,
            bvh: true,
            midi: true,
            markers: <MarkerKind as clap::ValueEnum>::value_variants(),
        }
    }
}

impl FolderFiles {
    /// The files Pneuma names `<stem>.<suffix>` in `folder`, those `wanted`: the one naming
    /// rule of a render's files besides the audio.
    fn named(folder: &Path, stem: &str, wanted: Wanted<'_>) -> Self {
        let named = |suffix: &str| folder.join(format!("{stem}.{suffix}"));
        Self {
            folder: folder.to_owned(),
            controls: named("controls.csv"),
            breaths: named("breaths.csv"),
            plot: wanted.plot.then(|| named("png")),
            bvh: wanted.bvh.then(|| named("bvh")),
            midi: wanted.midi.then(|| named("mid")),
            markers: wanted
                .markers
                .iter()
                .filter_map(|&k| k.suffix().map(|s| (k, named(s))))
                .collect(),
        }
    }

    /// The optional files, each with which one it is.
    fn optional(&self) -> impl Iterator<Item = (&PathBuf, Optional)> {
        (self.plot.iter().map(|p| (p, Optional::Plot)))
            .chain(self.bvh.iter().map(|p| (p, Optional::Bvh)))
            .chain(self.midi.iter().map(|p| (p, Optional::Midi)))
            .chain(self.markers.iter().map(|(k, p)| (p, Optional::Markers(*k))))
    }

    /// The files Pneuma names for this stem that these do not include: what an earlier
    /// render may have left ([`super::leftovers`]).
    fn leftovers(&self, stem: &str) -> Vec<Leftover> {
        let mine: Vec<&PathBuf> = self.paths().collect();
        Self::named(&self.folder, stem, Wanted::all())
            .optional()
            .filter(|(p, _)| !mine.contains(p))
            .map(|(path, file)| Leftover {
                path: path.clone(),
                file,
            })
            .collect()
    }

    /// Every file of the folder but the audio, in the order they are listed.
    fn paths(&self) -> impl Iterator<Item = &PathBuf> {
        [&self.controls, &self.breaths]
            .into_iter()
            .chain(&self.plot)
            .chain(&self.bvh)
            .chain(&self.midi)
            .chain(self.markers.iter().map(|(_, p)| p))
    }
}

/// Where one input's outputs go.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputPlan {
    /// The audio's container.
    pub container: Container,
    /// The audio file, `-` for standard output.
    pub audio: PathBuf,
    /// Cue points inside the audio (`--markers cue`).
    pub cues: bool,
    /// The BVH's frame rate when `--bvh-fps` is given (else the control frames').
    pub bvh_fps: Option<f64>,
    /// The MIDI file's CC map (`--midi-14bit`, `--midi-head-range-deg`).
    pub cc_map: CcMap,
    /// The other files, `None` with `-o -` (only the audio, to standard output).
    pub files: Option<FolderFiles>,
    /// The files named for the stem that this render does not write, removed once it is
    /// committed (kept with `--no-overwrite`).
    pub leftovers: Vec<Leftover>,
    /// Keep the leftovers and warn of them (`--no-overwrite`).
    pub keep_leftovers: bool,
    /// The MP3 encoding when the audio is MP3.
    pub mp3: Option<crate::mp3_out::Mp3Settings>,
    /// Where the frames go as OSC, if anywhere.
    pub osc: Option<crate::osc_out::OscPlan>,
    /// Warnings for the summary on where the outputs differ from what was asked (the breath
    /// markers of a batch's file that cannot hold cue points).
    pub notes: Vec<String>,
}

impl Job {
    /// Opens `input` and checks everything `args` ask of it: the settings, the options that
    /// need a file output or a WAV, the channels, the head model, the breath samples and the
    /// output names (`--no-overwrite`, never over the input).
    pub fn plan(args: &Args, input: &Path) -> Result<Self, RenderError> {
        let config = args.engine_config()?;
        check_stdout_options(args)?;
        let source = AudioSource::open(input)?;
        let container = if args.to_stdout() {
            Container::Wav
        } else {
            output_container(args.format, source.format())
        };
        let mut info = source.info();
        let mp3 = mp3_settings(args, input, container, &source, args.channel.is_some())?;
        let input_channels = info.channels as usize;
        let pick = args.channel.map(Channel::index);
        if let Some(channel) = args.channel {
            if channel.index() >= input_channels {
                let name = input.display().to_string();
                return Err(RenderError::Input(channel.missing(input_channels, &name)));
            }
            info.channels = 1;
        }
        check_input_shape(&info)?;
        let (engine, breath_like_note) = prepared_engine(args, input, config, &info)?;
        let mut outputs = OutputPlan::new(args, input, container)?;
        outputs.mp3 = mp3;
        // G.711 (telephone) samples are read as 16-bit linear PCM and written so: say so, as
        // the format line says only "16-bit".
        if let (Some(law), Container::Wav) = (source.companding(), container) {
            outputs.notes.push(format!(
                "the input's samples are G.711 {law}: the output holds them as 16-bit linear PCM \
                 (the same values, twice the size); Pneuma writes no {law}"
            ));
        }
        Ok(Self {
            input_channels: (input_channels, pick),
            input_format: (source.format(), source.lossless()),
            carried: WavMeta {
                tags: source.tags(),
                cues: source.cue_points().to_vec(),
                form: source.fmt_form().filter(|_| pick.is_none()),
            },
            info,
            source,
            engine,
            breath_like_note,
            outputs,
        })
    }
}

/// `-o -` writes only WAV audio: no markers, no other format.
fn check_stdout_options(args: &Args) -> Result<(), RenderError> {
    if args.to_stdout() && !args.markers.is_empty() {
        return Err(RenderError::Input(
            "-o - writes only the audio to standard output: drop --markers, or give an output \
             folder"
                .into(),
        ));
    }
    if args.to_stdout() && (args.midi.wanted() || args.bvh.wanted()) {
        return Err(RenderError::Input(
            "-o - writes only the audio to standard output: drop the --midi and --bvh options \
             (--bvh-fps too), or give an output folder"
                .into(),
        ));
    }
    if args.to_stdout() && args.format.is_some_and(|f| f != Container::Wav) {
        return Err(RenderError::Input(
            "-o - writes WAV (a stream of unknown length): drop --format, or give an output \
             folder"
                .into(),
        ));
    }
    Ok(())
}

/// The MP3 encoding with `--format mp3` (`None` for other formats); `--bitrate` and `--vbr`
/// without it, more than two channels (unless one is picked), and a bitrate the MP3's rate
/// does not hold are refused.
fn mp3_settings(
    args: &Args,
    input: &Path,
    container: Container,
    source: &AudioSource,
    one_channel: bool,
) -> Result<Option<crate::mp3_out::Mp3Settings>, RenderError> {
    let info = source.info();
    if container == Container::Mp3 && info.channels > 2 && !one_channel {
        return Err(RenderError::Input(format!(
            "MP3 holds one or two channels and {} has {}: add --channel left, or write \
             --format flac",
            input.display(),
            info.channels
        )));
    }
    args.mp3
        .settings(
            container == Container::Mp3,
            input,
            source.format(),
            info.sample_rate_hz,
        )
        .map_err(RenderError::Input)
}

/// The marker files to write and whether the audio gets cue points, with the summary's
/// warnings. Cue points live inside a WAV file: asked for another output, one file's render is
/// refused, and a batch's file gets its breath markers in the Audacity label track instead
/// (beside the REAPER list, if asked), with a warning, so a batch of WAVs and MP3s finishes.
fn marker_plan(
    args: &Args,
    container: Container,
    stem: &str,
) -> Result<(Vec<MarkerKind>, bool, Vec<String>), RenderError> {
    let mut markers = args.markers.clone();
    let cue = markers.contains(&MarkerKind::Cue);
    if !cue || container == Container::Wav {
        return Ok((markers, cue, Vec::new()));
    }
    let format = container.extension().to_uppercase();
    if !args.in_batch {
        return Err(RenderError::Input(format!(
            "--markers cue writes cue points inside a WAV file, but the output is {format}: add \
             --format wav, or use --markers audacity or reaper"
        )));
    }
    markers.retain(|k| *k != MarkerKind::Cue);
    if !markers.contains(&MarkerKind::Audacity) {
        markers.push(MarkerKind::Audacity);
    }
    let files: Vec<String> = (markers.iter())
        .filter_map(|k| k.suffix().map(|s| format!("{stem}.{s}")))
        .collect();
    let note = format!(
        "{format} holds no cue points: the breath markers are in {} (--format wav for cue \
         points)",
        files.join(" and ")
    );
    Ok((markers, false, vec![note]))
}

/// The engine takes the input's channels.
fn check_input_shape(info: &WavInfo) -> Result<(), RenderError> {
    let channels = info.channels as usize;
    if channels > pneuma_core::engine::MAX_CHANNELS {
        return Err(RenderError::Input(format!(
            "{} (a multitrack recording: render one track with --channel N, N from 1 to \
             {channels})",
            EngineError::Channels(channels)
        )));
    }
    Ok(())
}

/// The engine for `config` with the head model and breath samples `args` name and the breath
/// voice learned for `input` ([`super::voice`]), prepared for the input's rate and channels,
/// replaying the learning pass's analysis when there was one; and what the user should know
/// about the `--breath-like` file.
fn prepared_engine(
    args: &Args,
    input: &Path,
    config: EngineConfig,
    info: &WavInfo,
) -> Result<(Engine, Option<Finding>), RenderError> {
    let model =
        crate::options::load_head_model(args.head_model.as_deref()).map_err(RenderError::Input)?;
    let voice = super::voice::mode(
        args.built_in_breath,
        args.breath_like.as_deref(),
        input,
        args.channel.map(Channel::index),
        &config,
    )?;
    let mut engine = Engine::new(config, model)?;
    engine.set_voice_mode(voice.mode);
    engine.prepare(
        info.sample_rate_hz as f64,
        BLOCK_FRAMES,
        info.channels as usize,
    )?;
    if let Some(record) = voice.record {
        engine.replay_analysis(record)?;
    }
    for (slot, sample) in breath_samples(args)? {
        engine.set_breath_sample(slot, Some(sample));
    }
    Ok((engine, voice.note))
}

/// The breath samples `args` name: `--breath-mouth` and `--breath-nose`, or the `mouth` and
/// `nose` files of `--breath-samples` (clap refuses the two ways together).
fn breath_samples(args: &Args) -> Result<Vec<(SampleSlot, BreathSample)>, RenderError> {
    let mut samples = Vec::new();
    for (slot, path, name) in [
        (SampleSlot::Mouth, &args.breath_mouth, "--breath-mouth"),
        (SampleSlot::Nose, &args.breath_nose, "--breath-nose"),
    ] {
        if let Some(path) = path {
            samples.push((slot, load_sample(path, name)?));
        }
    }
    if let Some(dir) = &args.breath_samples {
        if !dir.is_dir() {
            return Err(RenderError::Input(format!(
                "--breath-samples {}: not a folder (it should hold mouth.wav and/or nose.wav, or .flac, .aiff, …)",
                dir.display()
            )));
        }
        let before = samples.len();
        for (slot, name) in [(SampleSlot::Mouth, "mouth"), (SampleSlot::Nose, "nose")] {
            if let Some(path) = pneuma_io::find_audio(dir, name) {
                samples.push((slot, load_sample(&path, "--breath-samples")?));
            }
        }
        if samples.len() == before {
            return Err(RenderError::Input(format!(
                "--breath-samples {}: no mouth or nose audio file (mouth.wav, nose.flac, …) in it",
                dir.display()
            )));
        }
    }
    Ok(samples)
}

/// Reads the breath sample at `path`; `label` names it in errors.
fn load_sample(path: &Path, label: &str) -> Result<BreathSample, RenderError> {
    let (samples, rate) =
        pneuma_io::read_mono(path).map_err(|e| RenderError::Input(format!("{label}: {e}")))?;
    BreathSample::from_mono(samples, rate as f64)
        .map_err(|e| RenderError::Input(format!("{label} {}: {e}", path.display())))
}

impl OutputPlan {
    /// The outputs of `input` as `args` ask, in `container`: refused when `-o` looks like a
    /// file, when any output (the audio, the plot, the BVH, …) would replace the input, or
    /// (`--no-overwrite`) when one exists.
    fn new(args: &Args, input: &Path, container: Container) -> Result<Self, RenderError> {
        let stem = output_stem(input);
        let (markers, cues, notes) = marker_plan(args, container, &stem)?;
        let osc = args.osc.plan().map_err(RenderError::Input)?;
        let cc_map = args.midi.map().map_err(RenderError::Input)?;
        if args.to_stdout() {
            return Ok(Self {
                container,
                audio: PathBuf::from("-"),
                cues,
                bvh_fps: None,
                cc_map,
                files: None,
                leftovers: Vec::new(),
                keep_leftovers: false,
                mp3: None,
                osc,
                notes,
            });
        }
        crate::options::check_output_folder("-o", &args.output).map_err(RenderError::Input)?;
        let audio = args
            .output
            .join(format!("{stem}.{}", container.extension()));
        let wanted = Wanted {
            plot: !args.no_plot,
            bvh: args.bvh.wanted(),
            midi: args.midi.wanted(),
            markers: &markers,
        };
        let files = FolderFiles::named(&args.output, &stem, wanted);
        // A WAV saved as take.png is replaced by the plot as surely as by the audio.
        if let Some(path) = std::iter::once(&audio)
            .chain(files.paths())
            .find(|p| crate::options::same_file(input, p))
        {
            return Err(RenderError::Output {
                path: path.clone(),
                source: std::io::Error::other("it is the input file; choose another output folder"),
            });
        }
        let mut notes = notes;
        notes.extend(other_audio(input, &audio).map(|other| {
            format!(
                "{} stays beside this render's {}: it is not this render's audio (another \
                 input's render, another --format, or your own file), and {stem}.breaths.csv \
                 and the other files now describe {}; remove it, or render into another folder",
                other.display(),
                audio.display(),
                audio.file_name().unwrap_or_default().to_string_lossy()
            )
        }));
        // Never the input, whatever its name.
        let leftovers = (files.leftovers(&stem).into_iter())
            .filter(|l| !crate::options::same_file(input, &l.path))
            .collect();
        if args.no_overwrite {
            let all: Vec<PathBuf> = std::iter::once(&audio)
                .chain(files.paths())
                .cloned()
                .collect();
            crate::options::refuse_existing(&all).map_err(RenderError::Input)?;
        }
        Ok(Self {
            container,
            audio,
            cues,
            bvh_fps: args.bvh.fps().map_err(RenderError::Input)?,
            cc_map,
            files: Some(files),
            leftovers,
            keep_leftovers: args.no_overwrite,
            mp3: None,
            osc,
            notes,
        })
    }
}

/// The audio files of the other formats a render writes with the stem of `audio` beside it
/// (not the input itself): an earlier render's of another input or format, or the user's file,
/// left by design and named in a warning, since the files beside it now belong to `audio`.
fn other_audio<'a>(input: &'a Path, audio: &'a Path) -> impl Iterator<Item = PathBuf> + 'a {
    crate::audio_out::other_formats_beside(audio)
        .filter(move |p| !crate::options::same_file(input, p))
}

/// The name the outputs of `input` are named after: its file stem, `stdin` for `-`.
fn output_stem(input: &Path) -> String {
    if input.as_os_str() == "-" {
        return "stdin".into();
    }
    input
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "render".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stems_that_differ_only_in_case_clash() {
        let inputs: Vec<PathBuf> = ["a/Talk.wav", "b/talk.mp3", "TALK.flac", "other.wav"]
            .map(PathBuf::from)
            .into();
        let groups = clashing_stems(&inputs);
        assert_eq!(groups.len(), 1, "{groups:?}");
        assert_eq!(
            groups[0],
            inputs[..3].iter().map(PathBuf::as_path).collect::<Vec<_>>()
        );
    }
}
