//! `pneuma render IN -o DIR`: streams an audio file (any format `pneuma-io` reads, or standard
//! input) through the [`Engine`] in blocks and writes `DIR/<stem>.wav|flac|aiff` (the input
//! with breaths, same rate, channels and bit depth; see [`output_container`]),
//! `DIR/<stem>.controls.csv`, `DIR/<stem>.breaths.csv`, `DIR/<stem>.png`, with `--bvh`
//! `DIR/<stem>.bvh` and with `--markers` the editors' marker files (contracts in DESIGN.md); or,
//! with `-o -`, only the audio as WAV to standard output. Several inputs go to
//! [`crate::batch`].
//!
//! The engine runs as in the plugin (with `--lookahead-ms` exactly as the plugin; by default with
//! the engine's whole-file lookahead of seconds), driven by core's one offline loop
//! ([`offline::stream`]): it removes the lookahead delay by dropping the first `latency` output
//! samples and feeds silence at the end (the engine's tail) until every frame of the file is
//! out. The outputs that follow frames are sinks ([`FrameSink`]): the controls CSV and the BVH
//! as [`TextSink`]s, the plot's frames and the breaths kept in memory. Memory stays bounded:
//! audio is read, processed and written block by block, the controls stream to their file, and
//! the plot keeps a min/max envelope of at most a few hundred thousand points. Every output file
//! is written under a temporary name and renamed into
//! place only when the whole render succeeded.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use pneuma_core::breathing::{BreathSample, Preset, SampleSlot};
use pneuma_core::encode::breaths_csv;
use pneuma_core::encode::sink::{FrameSink, TextSink};
use pneuma_core::engine::offline::{self, TailFrames};
use pneuma_core::engine::{Engine, EngineConfig, EngineError, PlacementMode};
use pneuma_core::{BreathEvent, ControlFrame};
use thiserror::Error;

use crate::audio_out::{AudioSink, Container};
use crate::markers::MarkerKind;
use crate::output::{commit_all, Output, Staged};
use crate::wav::WavInfo;
use pneuma_io::{AudioSource, InputFormat, ReadError};

/// Sample frames per block.
const BLOCK_FRAMES: usize = 4096;
/// Most points of the plot's waveform envelope.
const PLOT_POINTS: usize = 400_000;
/// Most control frames kept for the plot.
const PLOT_FRAMES: usize = 200_000;

/// Errors of `pneuma render`.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The input file.
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// The settings.
    #[error("invalid settings: {0}")]
    Settings(#[from] EngineError),
    /// A breath sample or the head model.
    #[error("{0}")]
    Input(String),
    /// An output file.
    #[error("cannot write {path}: {source}{}", crate::output::write_hint(source))]
    Output {
        /// Where we tried to write.
        path: PathBuf,
        /// Why it failed.
        source: std::io::Error,
    },
    /// The plot.
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// Ctrl-C.
    #[error("interrupted (Ctrl-C): nothing was written, existing files are unchanged")]
    Interrupted,
}

/// Set by the Ctrl-C handler; a render checks it after every block and stops, leaving no
/// partial file (its staged files are removed when dropped).
pub static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

fn interrupted() -> bool {
    INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed)
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

/// Command-line arguments of `pneuma render`.
#[derive(Debug, Clone, clap::Args)]
pub struct Args {
    /// Input audio: WAV, FLAC, MP3, M4A/AAC, Ogg Vorbis, AIFF or CAF (any channels, 8–192
    /// kHz); `-` reads standard input. Several files or folders render them all (a batch, in
    /// parallel; folders give the audio files directly inside them).
    #[arg(required = true, value_name = "IN")]
    pub inputs: Vec<PathBuf>,
    /// Output folder (created if missing); the files inside are named after the input. `-`
    /// writes only the audio, as WAV, to standard output (one input).
    #[arg(short, long, value_name = "DIR")]
    pub output: PathBuf,
    /// Audio format of the output: by default the input's own for WAV, FLAC and AIFF, and FLAC
    /// for everything else (never a second lossy generation).
    #[arg(long, value_enum)]
    pub format: Option<Container>,
    /// Breath markers for editors, comma-separated: audacity (label track
    /// `<stem>.breaths.txt`), reaper (region list `<stem>.breaths.reaper.csv`), cue (cue points
    /// inside the output WAV).
    #[arg(long, value_enum, value_delimiter = ',', value_name = "KIND")]
    pub markers: Vec<MarkerKind>,
    /// Files rendered at once in a batch (1 to 256; default: the number of cores).
    #[arg(short = 'j', long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Breathing preset.
    #[arg(long, default_value = "neutral", value_parser = clap::builder::PossibleValuesParser::new(Preset::NAMES))]
    pub preset: String,
    /// Breath level relative to the speech level, dB (-60 to -6).
    #[arg(long, default_value_t = -22.0, allow_hyphen_values = true, value_parser = crate::options::number)]
    pub breath_level_db: f32,
    /// Pauses shorter than this get no breath, ms (100 to 5000).
    #[arg(long, default_value_t = 250.0, value_parser = crate::options::number)]
    pub min_pause_ms: f32,
    /// Placement: `lookahead` (breath ends just before the next phrase) or `live` (no delay).
    #[arg(long, default_value = "lookahead")]
    pub mode: String,
    /// Lookahead of the lookahead mode, ms (300 to 2000): renders as the plugin with that
    /// lookahead. Without it the render looks seconds ahead (the engine's whole-file lookahead).
    #[arg(long, value_parser = crate::options::number)]
    pub lookahead_ms: Option<f32>,
    /// Do not insert breaths (controls only; the audio is copied unchanged).
    #[arg(long)]
    pub no_breaths: bool,
    /// Folder with user breath samples `mouth.wav` and/or `nose.wav` (or .flac, .aiff, … any
    /// input format; the same as giving
    /// them with --breath-mouth and --breath-nose).
    #[arg(long, value_name = "DIR")]
    pub breath_samples: Option<PathBuf>,
    /// A WAV recording of a mouth inhalation to use instead of the procedural one.
    #[arg(long, value_name = "WAV")]
    pub breath_mouth: Option<PathBuf>,
    /// A WAV recording of a nose inhalation to use instead of the procedural one.
    #[arg(long, value_name = "WAV")]
    pub breath_nose: Option<PathBuf>,
    /// Head-pose model file (JSON); the embedded default model when absent.
    #[arg(long)]
    pub head_model: Option<PathBuf>,
    /// Seed of every random source.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Control frames per second (10 to 1000).
    #[arg(long, default_value_t = 120.0)]
    pub frame_rate: f64,
    /// Also write `<stem>.bvh` (head and neck motion).
    #[arg(long)]
    pub bvh: bool,
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
    /// Print errors only: no progress bar, no summary.
    #[arg(long, short)]
    pub quiet: bool,
}

impl Args {
    /// The engine settings these arguments ask for.
    pub fn engine_config(&self) -> Result<EngineConfig, RenderError> {
        let preset = Preset::from_name(&self.preset)
            .map_err(|e| RenderError::Input(format!("--preset: {e}")))?;
        // The options in the user's terms first; the engine checks its own settings again.
        use crate::options::check_range;
        let lookahead_ms = self.lookahead_ms.unwrap_or(500.0);
        check_range("--breath-level-db", self.breath_level_db, -60.0, -6.0, "dB")
            .and_then(|()| check_range("--min-pause-ms", self.min_pause_ms, 100.0, 5000.0, "ms"))
            .and_then(|()| check_range("--lookahead-ms", lookahead_ms, 300.0, 2000.0, "ms"))
            .and_then(|()| check_range("--frame-rate", self.frame_rate as f32, 10.0, 1000.0, "Hz"))
            .map_err(RenderError::Input)?;
        let mut c = EngineConfig::default();
        c.analysis.frame_rate_hz = self.frame_rate;
        c.placement.mode = PlacementMode::from_name(&self.mode)?;
        c.placement.breath_level_db = self.breath_level_db;
        c.placement.min_pause_s = self.min_pause_ms / 1000.0;
        c.placement.lookahead_s = lookahead_ms / 1000.0;
        c.placement.whole_file = self.lookahead_ms.is_none();
        c.placement.insert_breaths = !self.no_breaths;
        c.breathing = preset.params();
        c.seed = self.seed;
        c.validate()?;
        Ok(c)
    }
}

/// What a render did.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSummary {
    /// The input format (rate, channels, bits also of the output).
    pub info: WavInfo,
    /// The input's container and whether it is lossless.
    pub input_format: (InputFormat, bool),
    /// The output's container.
    pub container: Container,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Breaths inserted.
    pub breaths: Vec<BreathEvent>,
    /// Control frames written.
    pub frames: u64,
    /// Length of the output audio, seconds.
    pub length_s: f64,
    /// Output samples clipped to the integer range.
    pub clipped: u64,
}

/// A min/max envelope of the mono output for the plot, bounded in size.
struct Envelope {
    bucket: usize,
    filled: usize,
    lo: f32,
    hi: f32,
    points: Vec<f32>,
}

impl Envelope {
    /// For `total_frames` samples; 0 (a length not known before the end) starts with
    /// buckets of two samples and widens them as the input goes on.
    fn new(total_frames: u64) -> Self {
        let bucket = if total_frames == 0 {
            2
        } else {
            usize::try_from(total_frames.saturating_mul(2).div_ceil(PLOT_POINTS as u64))
                .unwrap_or(usize::MAX)
                .max(1)
        };
        Self {
            bucket,
            filled: 0,
            lo: f32::INFINITY,
            hi: f32::NEG_INFINITY,
            points: Vec::new(),
        }
    }
    fn push(&mut self, x: f32) {
        if self.bucket == 1 {
            self.points.push(x);
            return;
        }
        self.lo = self.lo.min(x);
        self.hi = self.hi.max(x);
        self.filled += 1;
        if self.filled == self.bucket {
            self.points.push(self.lo);
            self.points.push(self.hi);
            self.filled = 0;
            self.lo = f32::INFINITY;
            self.hi = f32::NEG_INFINITY;
            if self.points.len() >= 2 * PLOT_POINTS {
                // Longer than announced (a length not known before): merge neighbouring
                // buckets, so the envelope stays bounded.
                let merged: Vec<f32> = self
                    .points
                    .chunks(4)
                    .flat_map(|c| match *c {
                        [lo1, hi1, lo2, hi2] => [lo1.min(lo2), hi1.max(hi2)],
                        [lo, hi, ..] => [lo, hi],
                        _ => unreachable!("points come in pairs"),
                    })
                    .collect();
                self.points = merged;
                self.bucket *= 2;
            }
        }
    }
    /// The points, evenly spread over the samples pushed so far (a last partial bucket
    /// included).
    fn finish(mut self) -> Vec<f32> {
        if self.filled > 0 {
            self.points.push(self.lo);
            self.points.push(self.hi);
        }
        self.points
    }
}

/// What a render keeps of the engine's output besides the files: the number of control frames,
/// every `every`-th frame for the plot (at most [`PLOT_FRAMES`]) and the inserted breaths.
struct Kept {
    every: usize,
    frames: u64,
    plot: Vec<ControlFrame>,
    breaths: Vec<BreathEvent>,
}

impl Kept {
    fn new(frames_total: u64) -> Self {
        Self {
            every: (frames_total as usize).div_ceil(PLOT_FRAMES).max(1),
            frames: 0,
            plot: Vec::new(),
            breaths: Vec::new(),
        }
    }
}

impl FrameSink for Kept {
    fn frame(&mut self, frame: &ControlFrame, _at: u64) {
        if (frame.index as usize).is_multiple_of(self.every) {
            self.plot.push(*frame);
            if self.plot.len() > 2 * PLOT_FRAMES {
                // Longer than announced (a length not known before): keep every other one.
                self.every *= 2;
                let every = self.every;
                self.plot
                    .retain(|f| (f.index as usize).is_multiple_of(every));
            }
        }
        self.frames += 1;
    }
    fn breath(&mut self, breath: &BreathEvent) {
        self.breaths.push(*breath);
    }
}

fn out_err(path: &Path) -> impl Fn(std::io::Error) -> RenderError + '_ {
    move |source| RenderError::Output {
        path: path.to_owned(),
        source,
    }
}

/// Reads the breath sample at `path`; `label` names it in errors.
fn load_sample(path: &Path, label: &str) -> Result<BreathSample, RenderError> {
    let (samples, rate) = pneuma_io::read_mono(path)?;
    BreathSample::from_mono(samples, rate as f64)
        .map_err(|e| RenderError::Input(format!("{label} {}: {e}", path.display())))
}

/// Renders `input` (`-`: standard input) as `args` ask; `progress` is called with the fraction
/// done (0..1) now and then.
pub fn run(
    args: &Args,
    input: &Path,
    mut progress: impl FnMut(f64),
) -> Result<RenderSummary, RenderError> {
    let config = args.engine_config()?;
    let to_stdout = args.output.as_os_str() == "-";
    if to_stdout && !args.markers.is_empty() {
        return Err(RenderError::Input(
            "-o - writes only the audio to standard output: drop --markers, or give an output \
             folder"
                .into(),
        ));
    }
    if to_stdout && args.format.is_some_and(|f| f != Container::Wav) {
        return Err(RenderError::Input(
            "-o - writes WAV (a stream of unknown length): drop --format, or give an output \
             folder"
                .into(),
        ));
    }
    let mut src = AudioSource::open(input)?;
    let container = if to_stdout {
        Container::Wav
    } else {
        output_container(args.format, src.format())
    };
    if args.markers.contains(&MarkerKind::Cue) && container != Container::Wav {
        return Err(RenderError::Input(format!(
            "--markers cue writes cue points inside a WAV file, but the output is {}: add \
             --format wav, or use --markers audacity or reaper",
            container.extension().to_uppercase()
        )));
    }
    let input_format = (src.format(), src.lossless());
    let tags = src.tags();
    let info = src.info();
    let channels = info.channels as usize;
    if channels > pneuma_core::engine::MAX_CHANNELS {
        return Err(EngineError::Channels(channels).into());
    }
    if args.bvh && !to_stdout && info.frames == 0 {
        return Err(RenderError::Input(
            "--bvh needs the input's length before the render (the BVH header holds the frame \
             count), and this input does not announce it (a pipe, or a stream of unknown \
             length): save it to a file first, or drop --bvh"
                .into(),
        ));
    }
    let model =
        crate::options::load_head_model(args.head_model.as_deref()).map_err(RenderError::Input)?;
    let mut engine = Engine::new(config.clone(), model)?;
    engine.prepare(info.sample_rate_hz as f64, BLOCK_FRAMES, channels)?;
    let mut sample_names = Vec::new();
    for (slot, path, name) in [
        (SampleSlot::Mouth, &args.breath_mouth, "--breath-mouth"),
        (SampleSlot::Nose, &args.breath_nose, "--breath-nose"),
    ] {
        if let Some(path) = path {
            engine.set_breath_sample(slot, Some(load_sample(path, name)?));
            sample_names.push(name);
        }
    }
    if let Some(dir) = &args.breath_samples {
        if !dir.is_dir() {
            return Err(RenderError::Input(format!(
                "--breath-samples {}: not a folder (it should hold mouth.wav and/or nose.wav, or .flac, .aiff, …)",
                dir.display()
            )));
        }
        let before = sample_names.len();
        for (slot, name) in [(SampleSlot::Mouth, "mouth"), (SampleSlot::Nose, "nose")] {
            if let Some(path) = pneuma_io::find_audio(dir, name) {
                engine.set_breath_sample(slot, Some(load_sample(&path, "breath sample")?));
                sample_names.push(name);
            }
        }
        if sample_names.len() == before {
            return Err(RenderError::Input(format!(
                "--breath-samples {}: no mouth or nose audio file (mouth.wav, nose.flac, …) in it",
                dir.display()
            )));
        }
    }

    if !to_stdout {
        crate::options::check_output_folder("-o", &args.output).map_err(RenderError::Input)?;
        std::fs::create_dir_all(&args.output).map_err(out_err(&args.output))?;
    }
    let stem = output_stem(input);
    let wav_path = if to_stdout {
        PathBuf::from("-")
    } else {
        args.output
            .join(format!("{stem}.{}", container.extension()))
    };
    if same_file(input, &wav_path) {
        return Err(RenderError::Output {
            path: wav_path,
            source: std::io::Error::other("it is the input file; choose another output folder"),
        });
    }
    let controls_path = args.output.join(format!("{stem}.controls.csv"));
    let breaths_path = args.output.join(format!("{stem}.breaths.csv"));
    let plot_path = args.output.join(format!("{stem}.png"));
    let bvh_path = args.output.join(format!("{stem}.bvh"));
    let marker_paths: Vec<(MarkerKind, PathBuf)> = args
        .markers
        .iter()
        .filter_map(|&k| {
            k.suffix()
                .map(|s| (k, args.output.join(format!("{stem}.{s}"))))
        })
        .collect();
    if args.no_overwrite && !to_stdout {
        let mut all = vec![
            wav_path.clone(),
            controls_path.clone(),
            breaths_path.clone(),
        ];
        all.extend((!args.no_plot).then(|| plot_path.clone()));
        all.extend(args.bvh.then(|| bvh_path.clone()));
        all.extend(marker_paths.iter().map(|(_, p)| p.clone()));
        crate::options::refuse_existing(&all).map_err(RenderError::Input)?;
    }

    let mut audio_out = if to_stdout {
        AudioSink::stdout(info)
    } else {
        AudioSink::create_as(&wav_path, info, container, tags)
    }
    .map_err(out_err(&wav_path))?;

    let total_in = info.frames;
    let frame_rate = config.analysis.frame_rate_hz;
    let clock = pneuma_core::analysis::FrameClock::new(frame_rate, info.sample_rate_hz as f64);
    let frames_total = clock.frames_in(total_in);
    // The outputs that follow the frames. With -o - only the audio is written: no controls,
    // breaths, plot or BVH files.
    let controls = if to_stdout {
        None
    } else {
        let o = Output::create(&controls_path).map_err(out_err(&controls_path))?;
        Some(TextSink::controls_csv(o).map_err(out_err(&controls_path))?)
    };
    // The BVH streams too: its header needs the frame count, known from the input's header.
    let bvh_out = if args.bvh && !to_stdout {
        let o = Output::create(&bvh_path).map_err(out_err(&bvh_path))?;
        Some(TextSink::bvh(o, frames_total as usize, frame_rate).map_err(out_err(&bvh_path))?)
    } else {
        None
    };
    let mut sinks = (controls, bvh_out, Kept::new(frames_total));

    let mut envelope = Envelope::new(total_in);
    let mut interleaved = Vec::with_capacity(BLOCK_FRAMES * channels);
    let mut out_interleaved = Vec::with_capacity(BLOCK_FRAMES * channels);
    let mut written = 0u64; // sample frames written to the output
    let mut last_progress = 0.0;
    offline::stream(
        &mut engine,
        channels,
        &[BLOCK_FRAMES],
        TailFrames::InputOnly,
        |planar: &mut [Vec<f32>], max: usize| -> Result<usize, RenderError> {
            let n = src.read_interleaved(max, &mut interleaved)?;
            for (i, frame) in interleaved.chunks_exact(channels).enumerate() {
                for (c, &x) in frame.iter().enumerate() {
                    planar[c][i] = x;
                }
            }
            Ok(n)
        },
        &mut sinks,
        |(controls, bvh, _), planar, range| {
            // A failed write of the controls or the BVH stops the render.
            for (text, path) in [(controls, &controls_path), (bvh, &bvh_path)] {
                if let Some(text) = text {
                    text.check().map_err(out_err(path))?;
                }
            }
            out_interleaved.clear();
            for i in range.clone() {
                let mut mono = 0.0;
                for p in planar {
                    out_interleaved.push(p[i]);
                    mono += p[i];
                }
                envelope.push(mono / channels as f32);
            }
            written += range.len() as u64;
            audio_out
                .write_interleaved(&out_interleaved)
                .map_err(out_err(&wav_path))?;
            if interrupted() {
                return Err(RenderError::Interrupted);
            }
            let done = written as f64 / total_in.max(1) as f64;
            if done - last_progress >= 0.01 {
                last_progress = done;
                progress(done.min(1.0));
            }
            Ok(())
        },
    )?;
    let (controls, bvh_out, kept) = sinks;
    let Kept {
        frames: frames_written,
        plot: plot_frames,
        mut breaths,
        ..
    } = kept;
    // A breath cut by the end of the file ends with it.
    let duration_s = written as f64 / info.sample_rate_hz as f64;
    breaths.retain(|b| b.start_s < duration_s);
    for b in &mut breaths {
        b.end_s = b.end_s.min(duration_s);
    }
    let clipped = audio_out.clipped();
    if args.markers.contains(&MarkerKind::Cue) {
        audio_out.set_cues(crate::markers::cues(&breaths, info.sample_rate_hz));
    }
    let Some(controls) = controls else {
        // Standard output: the audio is all there is.
        audio_out.finish().map_err(out_err(&wav_path))?;
        return Ok(RenderSummary {
            info,
            input_format,
            container,
            files: vec![wav_path],
            breaths,
            frames: frames_written,
            length_s: duration_s,
            clipped,
        });
    };

    let mut breaths_out = Output::create(&breaths_path).map_err(out_err(&breaths_path))?;
    breaths_csv::write_all(&mut breaths_out.writer(), &breaths).map_err(out_err(&breaths_path))?;

    // Every file is finished under a temporary name first ...
    let mut files = vec![
        wav_path.clone(),
        controls_path.clone(),
        breaths_path.clone(),
    ];
    let mut staged = vec![
        audio_out
            .finish()
            .map_err(out_err(&wav_path))?
            .ok_or_else(|| out_err(&wav_path)(std::io::Error::other("not a file")))?,
        staged_file(
            controls.into_inner().map_err(out_err(&controls_path))?,
            &controls_path,
        )?,
        staged_file(breaths_out, &breaths_path)?,
    ];
    for (kind, path) in &marker_paths {
        let mut o = Output::create(path).map_err(out_err(path))?;
        o.writer()
            .write_all(kind.file_text(&breaths).as_bytes())
            .map_err(out_err(path))?;
        staged.push(staged_file(o, path)?);
        files.push(path.clone());
    }
    if let Some(o) = bvh_out {
        let o = o.into_inner().map_err(out_err(&bvh_path))?;
        staged.push(staged_file(o, &bvh_path)?);
        files.push(bvh_path.clone());
    }
    if !args.no_plot {
        let plot = Staged::new(&plot_path).map_err(out_err(&plot_path))?;
        crate::plot::draw_png(
            plot.temp(),
            &plot_path,
            &envelope.finish(),
            duration_s,
            &plot_frames,
            &breaths,
        )?;
        staged.push(plot);
        files.push(plot_path.clone());
    }
    // ... then all are moved into place together, or none.
    if interrupted() {
        return Err(RenderError::Interrupted);
    }
    commit_all(staged).map_err(|(path, source)| RenderError::Output { path, source })?;
    Ok(RenderSummary {
        info,
        input_format,
        container,
        files,
        breaths,
        frames: frames_written,
        length_s: duration_s,
        clipped,
    })
}

/// Finishes a file output of the render (never standard output) into its staged file.
fn staged_file(out: Output, path: &Path) -> Result<Staged, RenderError> {
    out.finish()
        .map_err(out_err(path))?
        .ok_or_else(|| out_err(path)(std::io::Error::other("not a file")))
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

fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// What a lossy input became, for the summary: `" (MP3 input written as FLAC: …)"`.
pub fn lossy_note(s: &RenderSummary) -> String {
    let (format, lossless) = s.input_format;
    if lossless || s.container == Container::Wav && format == InputFormat::Wav {
        return String::new();
    }
    format!(
        "; {} input written as {} (no second lossy generation; --format wav for WAV)",
        format.name(),
        s.container.extension().to_uppercase()
    )
}

/// Exit code of an interrupted run (128 + SIGINT), as shells expect.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Installs the Ctrl-C handler: the first Ctrl-C sets [`INTERRUPTED`] (the render stops after
/// its current block and removes its temporary files), a second one exits at once.
pub fn install_interrupt_handler() {
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, std::sync::atomic::Ordering::Relaxed) {
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
    });
}

/// Runs `pneuma render` from parsed arguments: one input with a progress bar when a terminal
/// is attached and the job takes more than a second, or a batch (several inputs or a folder).
pub fn main(args: Args) -> ExitCode {
    install_interrupt_handler();
    let inputs = match crate::batch::expand_inputs(&args.inputs) {
        Ok(v) => v,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    if args.inputs.len() > 1 || args.inputs[0].is_dir() {
        return crate::batch::main(&args, &inputs);
    }
    let input = &inputs[0];
    let mut bar = crate::options::Progress::new("rendering", !args.quiet && !args.no_progress);
    let result = run(&args, input, |f| bar.set(f));
    bar.finish();
    match result {
        Ok(s) => {
            if !args.quiet {
                eprintln!(
                    "rendered {} ({}, {} Hz, {} ch, {}-bit{}): {} breaths, {} control frames{}{}",
                    input.display(),
                    s.input_format.0.name(),
                    s.info.sample_rate_hz,
                    s.info.channels,
                    s.info.bits,
                    if s.info.float { " float" } else { "" },
                    s.breaths.len(),
                    s.frames,
                    if s.clipped > 0 {
                        format!(", {} samples clipped", s.clipped)
                    } else {
                        String::new()
                    },
                    lossy_note(&s)
                );
                for f in &s.files {
                    eprintln!("  {}", f.display());
                }
            }
            ExitCode::SUCCESS
        }
        Err(RenderError::Interrupted) => {
            eprintln!("error: {}", RenderError::Interrupted);
            ExitCode::from(EXIT_INTERRUPTED)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_envelope_of_unknown_length_stays_bounded_and_keeps_the_extremes() {
        let n = 5 * PLOT_POINTS;
        let mut e = Envelope::new(0);
        for i in 0..n {
            // A ramp with one spike in the middle.
            e.push(if i == n / 2 { 2.0 } else { i as f32 / n as f32 });
        }
        let points = e.finish();
        assert!(
            points.len() <= 2 * PLOT_POINTS + 2,
            "{} points",
            points.len()
        );
        assert!(points.len() >= PLOT_POINTS / 2, "{} points", points.len());
        let max = points.iter().copied().fold(f32::MIN, f32::max);
        let min = points.iter().copied().fold(f32::MAX, f32::min);
        assert_eq!((min, max), (0.0, 2.0));
        // Pairs stay in time order: the last pair holds the end of the ramp.
        assert!(points[points.len() - 1] > 0.99);
    }

    #[test]
    fn plot_frames_of_unknown_length_stay_bounded_and_evenly_spaced() {
        let mut kept = Kept::new(0);
        let n = 5 * PLOT_FRAMES as u64;
        for index in 0..n {
            let f = ControlFrame {
                index,
                ..Default::default()
            };
            kept.frame(&f, 0);
        }
        assert_eq!(kept.frames, n);
        assert!(kept.plot.len() <= 2 * PLOT_FRAMES, "{}", kept.plot.len());
        let steps: Vec<u64> = kept
            .plot
            .windows(2)
            .map(|w| w[1].index - w[0].index)
            .collect();
        assert!(steps.iter().all(|&s| s == kept.every as u64), "uneven");
        assert!(kept
            .plot
            .last()
            .is_some_and(|f| f.index + kept.every as u64 >= n));
    }
}
