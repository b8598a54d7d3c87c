//! `pneuma analyze IN -o OUT.csv`: streams an audio file (any format `pneuma-io` reads) through
//! the analysis front end and writes one CSV row per frame (contract in DESIGN.md).
//! Multichannel input is mixed to mono, or one channel is analysed (`--channel`); channels that
//! cancel in the mix (antiphase) are named in a warning, as `render` does.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use pneuma_core::encode::features_csv;
use pneuma_core::{AnalysisConfig, AnalysisError, Analyzer, FeatureFrame};
use thiserror::Error;

use crate::channel::Channel;
use crate::options::{render_for, F0_MAX, F0_MIN, FRAME_RATE, SETTING_FLAGS};
use crate::output::Output;
use crate::render::findings::{antiphase_message, ChannelEnergy};
use crate::wav::WavInfo;
use pneuma_io::{mix_to_mono, AudioSource, ReadError};

/// Frames read from the file per block.
const BLOCK_FRAMES: usize = 8192;
/// CSV text gathered before it is written to an output file.
const FLUSH_BYTES: usize = 1 << 16;

/// Errors of `pneuma analyze`.
#[derive(Debug, Error)]
pub enum AnalyzeError {
    /// The input file.
    #[error(transparent)]
    Audio(#[from] ReadError),
    /// The settings.
    #[error("invalid analysis settings: {0}")]
    Settings(#[from] AnalysisError),
    /// `--channel` names a channel the input does not have.
    #[error("{}", channel.missing(usize::from(*channels), "the input"))]
    NoSuchChannel {
        /// The channel asked for.
        channel: Channel,
        /// The input's channels.
        channels: u16,
    },
    /// The output file.
    #[error("cannot write {path}: {source}{}", crate::output::write_hint(source))]
    Output {
        /// Where we tried to write.
        path: PathBuf,
        /// Why it failed.
        source: std::io::Error,
    },
}

/// What an analysis run did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalyzeSummary {
    /// The input format.
    pub info: WavInfo,
    /// Whether the input is stored losslessly (lossy input has no bit depth to report).
    pub lossless: bool,
    /// Frames written.
    pub frames: u64,
    /// Voiced frames among them.
    pub voiced_frames: u64,
    /// The channels cancel when mixed to mono (nothing was heard).
    pub antiphase: bool,
}

/// Analyses an opened audio input into frames (its mono mix, or channel `pick`), calling
/// `on_frame` for each; returns its format and whether its channels cancel in the mix. (It
/// takes the opened source because a pipe can be opened only once, and `run` checks the header
/// before it creates the output.)
pub fn analyze_source(
    mut src: AudioSource,
    config: AnalysisConfig,
    pick: Option<Channel>,
    mut on_frame: impl FnMut(&FeatureFrame),
) -> Result<(WavInfo, bool), AnalyzeError> {
    let info = src.info();
    let channels = info.channels as usize;
    if let Some(channel) = pick.filter(|c| c.index() >= channels) {
        return Err(AnalyzeError::NoSuchChannel {
            channel,
            channels: info.channels,
        });
    }
    let pick = pick.map(Channel::index);
    let mut analyzer = Analyzer::new(config)?;
    analyzer.prepare(info.sample_rate_hz as f64, BLOCK_FRAMES)?;
    let mut block = Vec::with_capacity(BLOCK_FRAMES * channels);
    let mut mono = Vec::with_capacity(BLOCK_FRAMES);
    let mut planar = vec![Vec::with_capacity(BLOCK_FRAMES); channels];
    let mut energy = ChannelEnergy::new(info.sample_rate_hz as f64);
    while src.read_interleaved(BLOCK_FRAMES, &mut block)? > 0 {
        for (c, chan) in planar.iter_mut().enumerate() {
            chan.clear();
            chan.extend(block.iter().skip(c).step_by(channels.max(1)));
        }
        energy.add(&planar, planar.first().map_or(0, Vec::len));
        match pick {
            Some(k) => analyzer.process(&planar[k], &mut on_frame)?,
            None => {
                mix_to_mono(&block, channels, &mut mono);
                analyzer.process(&mono, &mut on_frame)?;
            }
        }
    }
    analyzer.finish(&mut on_frame)?;
    Ok((info, pick.is_none() && energy.antiphase()))
}

/// Runs `pneuma analyze`: `output` is a path or `-` for standard output. A file is only
/// replaced when the whole analysis succeeded.
pub fn run(
    input: &Path,
    output: &Path,
    config: AnalysisConfig,
    pick: Option<Channel>,
) -> Result<AnalyzeSummary, AnalyzeError> {
    let out_err = |source| AnalyzeError::Output {
        path: output.to_owned(),
        source,
    };
    if output.as_os_str() != "-" && crate::options::same_file(input, output) {
        return Err(AnalyzeError::Output {
            path: output.to_owned(),
            source: std::io::Error::other("it is the input file; choose another output path"),
        });
    }
    // A file is streamed to a temporary name and renamed into place only when the whole
    // analysis succeeded, so a broken input never touches an existing output and memory stays
    // bounded on long files. Standard output cannot take back what it printed, so it gets the
    // rows only at the end.
    let src = AudioSource::open(input)?;
    let lossless = src.lossless();
    let stream = output.as_os_str() != "-";
    let mut out = Output::create(output).map_err(out_err)?;
    let mut text = String::with_capacity(FLUSH_BYTES + 256);
    text.push_str(features_csv::HEADER);
    text.push('\n');
    let (mut frames, mut voiced_frames) = (0u64, 0u64);
    let mut write_error = None;
    let (info, antiphase) = analyze_source(src, config, pick, |f| {
        features_csv::write_row(&mut text, f);
        frames += 1;
        voiced_frames += u64::from(f.voiced);
        if stream && text.len() >= FLUSH_BYTES && write_error.is_none() {
            write_error = out.writer().write_all(text.as_bytes()).err();
            text.clear();
        }
    })?;
    if let Some(e) = write_error {
        return Err(out_err(e));
    }
    out.writer().write_all(text.as_bytes()).map_err(out_err)?;
    out.commit().map_err(out_err)?;
    Ok(AnalyzeSummary {
        info,
        lossless,
        frames,
        voiced_frames,
        antiphase,
    })
}

/// Command-line arguments of `pneuma analyze`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Input audio: WAV, FLAC, MP3, M4A/AAC, Ogg Vorbis, AIFF or CAF (any channels, 8–192 kHz);
    /// `-` reads standard input.
    pub input: PathBuf,
    /// Output CSV path, or `-` for standard output.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Frames per second (the table's `frame_rate_hz`).
    #[arg(long, help = FRAME_RATE.help_saying("Rows (analysis frames) per second of the CSV"), default_value_t = FRAME_RATE.default_value())]
    pub frame_rate: f64,
    /// Lowest f0 searched, Hz (the table's `f0_min_hz`).
    #[arg(long, help = F0_MIN.help(), default_value_t = F0_MIN.default_value(), value_parser = crate::options::number)]
    pub f0_min: f64,
    /// Highest f0 searched, Hz (the table's `f0_max_hz`), at least 1.5 times --f0-min.
    #[arg(long, help = F0_MAX.help(), default_value_t = F0_MAX.default_value(), value_parser = crate::options::number)]
    pub f0_max: f64,
    /// Refuse to replace an existing output file. By default it is replaced, only when the
    /// analysis succeeded.
    #[arg(short = 'n', long)]
    pub no_overwrite: bool,
    /// Analyse one channel of the input instead of the mono mix: `left` (the first), `right`
    /// (the second) or its number from 1. For a file whose channels cancel when mixed
    /// (antiphase), or one track of a multitrack recording.
    #[arg(long, value_parser = Channel::parse, value_name = "CHANNEL")]
    pub channel: Option<Channel>,
}

/// The options in the user's terms (the option typed, in its unit), before the analysis
/// settings they become are checked under their own names.
fn check_options(args: &Args) -> Result<(), String> {
    FRAME_RATE.check(args.frame_rate)?;
    F0_MIN.check(args.f0_min)?;
    F0_MAX.check(args.f0_max)?;
    // The f0 range against itself, as the analysis checks it, named as typed.
    if let Err(AnalysisError::Setting(e)) = analysis_config(args).validate() {
        return Err(render_for(&SETTING_FLAGS, &e));
    }
    check_output_file(&args.input, &args.output)?;
    if args.no_overwrite && args.output.as_os_str() != "-" {
        crate::options::refuse_existing(std::slice::from_ref(&args.output))?;
    }
    Ok(())
}

/// `-o` names the CSV file: a folder (existing, or a name ending in `/`) is refused with a file
/// name inside it to give instead, and so is an audio file's name (`take2.wav`: a recording
/// would be replaced by CSV text), with the `.csv` name to give.
fn check_output_file(input: &Path, output: &Path) -> Result<(), String> {
    let stem = input
        .file_stem()
        .filter(|_| input.as_os_str() != "-")
        .map_or("analysis".into(), |s| s.to_string_lossy().into_owned());
    if crate::options::names_folder(output) {
        return Err(format!(
            "-o {} is a folder, but analyze writes one CSV file: give a file name, e.g. -o {}",
            output.display(),
            output.join(format!("{stem}.csv")).display()
        ));
    }
    if names_audio(output) {
        return Err(format!(
            "-o {} names an audio file, but analyze writes CSV text (it would replace the \
             audio): give a .csv name, e.g. -o {}",
            output.display(),
            output.with_extension("csv").display()
        ));
    }
    Ok(())
}

/// Whether `path`'s extension is an audio format's, read or not ([`pneuma_io::AUDIO_EXTENSIONS`],
/// [`pneuma_io::UNREAD_AUDIO_EXTENSIONS`]), in any letter case.
fn names_audio(path: &Path) -> bool {
    let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
        return false;
    };
    let unread = pneuma_io::UNREAD_AUDIO_EXTENSIONS.iter().map(|(e, _)| e);
    (pneuma_io::AUDIO_EXTENSIONS.iter().chain(unread)).any(|e| e.eq_ignore_ascii_case(ext))
}

/// The analysis settings the options give.
fn analysis_config(args: &Args) -> AnalysisConfig {
    AnalysisConfig {
        frame_rate_hz: args.frame_rate,
        f0_min_hz: args.f0_min as f32,
        f0_max_hz: args.f0_max as f32,
        // Two periods of the lowest f0, at least the default 40 ms.
        window_s: AnalysisConfig::default()
            .window_s
            .max(2.0 / args.f0_min as f32),
        ..Default::default()
    }
}

/// Runs `pneuma analyze` from parsed arguments, printing a summary or the error.
pub fn main(args: Args) -> ExitCode {
    if let Err(e) = check_options(&args) {
        eprintln!("error: {e}");
        return ExitCode::FAILURE;
    }
    match run(
        &args.input,
        &args.output,
        analysis_config(&args),
        args.channel,
    ) {
        Ok(s) => {
            if args.output.as_os_str() != "-" {
                eprintln!(
                    "analysed {} ({}): {} frames, {} voiced -> {}",
                    args.input.display(),
                    crate::options::describe_format(&s.info, s.lossless),
                    s.frames,
                    s.voiced_frames,
                    args.output.display()
                );
            }
            if s.antiphase {
                eprintln!("warning: {}", antiphase_message("analyse"));
            }
            ExitCode::SUCCESS
        }
        // The reader of standard output went away (`| head`): end quietly, as Unix tools do.
        Err(AnalyzeError::Output { ref source, .. })
            if args.output.as_os_str() == "-" && crate::output::is_broken_pipe(source) =>
        {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
