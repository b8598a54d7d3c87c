//! `pneuma analyze IN.wav -o OUT.csv`: streams a WAV file through the analysis front end and
//! writes one CSV row per frame (contract in DESIGN.md). Multichannel input is mixed to mono.

use std::path::{Path, PathBuf};

use pneuma_core::encode::features_csv;
use pneuma_core::{AnalysisConfig, AnalysisError, Analyzer, FeatureFrame};
use thiserror::Error;

use crate::output::Output;
use crate::wav::{mix_to_mono, WavError, WavInfo, WavSource};

/// Frames read from the file per block.
const BLOCK_FRAMES: usize = 8192;

/// Errors of `pneuma analyze`.
#[derive(Debug, Error)]
pub enum AnalyzeError {
    /// The input file.
    #[error(transparent)]
    Wav(#[from] WavError),
    /// The settings.
    #[error("invalid analysis settings: {0}")]
    Settings(#[from] AnalysisError),
    /// The output file.
    #[error("cannot write {path}: {source} (check that the folder exists and is writable)")]
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
    /// Frames written.
    pub frames: u64,
    /// Voiced frames among them.
    pub voiced_frames: u64,
}

/// Analyses `input` into frames, calling `on_frame` for each; returns the input's format.
pub fn analyze_file(
    input: &Path,
    config: AnalysisConfig,
    mut on_frame: impl FnMut(&FeatureFrame),
) -> Result<WavInfo, AnalyzeError> {
    let mut src = WavSource::open(input)?;
    let info = src.info();
    let mut analyzer = Analyzer::new(config)?;
    analyzer.prepare(info.sample_rate_hz as f64, BLOCK_FRAMES)?;
    let mut block = Vec::with_capacity(BLOCK_FRAMES * info.channels as usize);
    let mut mono = Vec::with_capacity(BLOCK_FRAMES);
    while src.read_interleaved(BLOCK_FRAMES, &mut block)? > 0 {
        mix_to_mono(&block, info.channels as usize, &mut mono);
        analyzer.process(&mono, &mut on_frame)?;
    }
    analyzer.finish(&mut on_frame)?;
    Ok(info)
}

/// Runs `pneuma analyze`: `output` is a path or `-` for standard output. A file is only
/// replaced when the whole analysis succeeded.
pub fn run(
    input: &Path,
    output: &Path,
    config: AnalysisConfig,
) -> Result<AnalyzeSummary, AnalyzeError> {
    let out_err = |source| AnalyzeError::Output {
        path: output.to_owned(),
        source,
    };
    if output.as_os_str() != "-" && same_file(input, output) {
        return Err(AnalyzeError::Output {
            path: output.to_owned(),
            source: std::io::Error::other("it is the input file; choose another output path"),
        });
    }
    // Read and analyse first, so a broken input never touches the output.
    let mut text = String::with_capacity(1 << 16);
    text.push_str(features_csv::HEADER);
    text.push('\n');
    let (mut frames, mut voiced_frames) = (0u64, 0u64);
    let info = analyze_file(input, config, |f| {
        features_csv::write_row(&mut text, f);
        frames += 1;
        voiced_frames += u64::from(f.voiced);
    })?;
    let mut out = Output::create(output).map_err(out_err)?;
    out.writer().write_all(text.as_bytes()).map_err(out_err)?;
    out.commit().map_err(out_err)?;
    Ok(AnalyzeSummary {
        info,
        frames,
        voiced_frames,
    })
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
