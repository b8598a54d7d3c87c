//! Running one planned render ([`Job`]) through the engine and its sinks: blocks from the
//! input through core's one offline loop ([`offline::stream`]), which removes the lookahead
//! delay by dropping the first `latency` output samples and feeds silence at the end (the
//! engine's tail) until every frame of the file is out. The outputs that follow frames are
//! sinks ([`FrameSink`]): the controls CSV as a [`TextSink`], the BVH ([`BvhFile`], written
//! whole at the end, its frame count the frames the decoded audio gave), the plot's frames and
//! the breaths kept in memory ([`Kept`]). Memory stays bounded: audio is read, processed and
//! written block by block, the controls stream to their file, and the plot keeps a min/max
//! envelope of at most a few hundred thousand points ([`Envelope`]). Every output file is
//! written under a temporary name and renamed into place only when the whole render succeeded
//! ([`commit_all`]); then the files an earlier render left for the same stem, which this one
//! does not write, are removed ([`super::leftovers`]).

use std::ops::Range;
use std::path::{Path, PathBuf};

use pneuma_core::analysis::FrameClock;
use pneuma_core::encode::breaths_csv;
use pneuma_core::encode::midi_cc::CcMap;
use pneuma_core::encode::midi_file::MidiFileSink;
use pneuma_core::encode::sink::{FrameSink, TextSink};
use pneuma_core::engine::offline::{self, TailFrames};
use pneuma_core::engine::{PlacementMode, VoiceStatus};
use pneuma_core::{BreathEvent, BreathKind, ControlFrame};
use pneuma_io::{AudioSource, InputFormat, WavMeta};

use super::bvh_file::BvhFile;
use super::error::{interrupted, out_err, RenderError};
use super::findings::{findings, AirRun, ChannelEnergy, Finding};
use super::leftovers::Cleared;
use super::plan::{Args, FolderFiles, Job, OutputPlan, BLOCK_FRAMES};
use crate::audio_out::{AudioSink, Container, Cue};
use crate::output::{commit_all, Output, Staged};
use crate::wav::WavInfo;

/// Most points of the plot's waveform envelope.
const PLOT_POINTS: usize = 400_000;
/// Most control frames kept for the plot.
const PLOT_FRAMES: usize = 200_000;

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
    /// Real breaths heard in the input's pauses, left as they are (in lookahead mode none is
    /// inserted over one; live mode may have started one before the breath was heard); none
    /// when no speech was found.
    pub heard_breaths: usize,
    /// Control frames written.
    pub frames: u64,
    /// Length of the output audio, seconds.
    pub length_s: f64,
    /// Output samples clipped to the integer range.
    pub clipped: u64,
    /// What the user should know about the input (no speech, antiphase channels, …).
    pub findings: Vec<Finding>,
    /// What was sent as OSC (`--osc`), for the summary.
    pub osc: Option<String>,
    /// The files an earlier render left that this one does not write: removed, or kept.
    pub leftovers: Cleared,
    /// Where the inserted breaths took their voice from, at the end of the render.
    pub voice: VoiceStatus,
    /// The learned voice's level at the end of the render (`None`: the built-in voice).
    pub voice_level: Option<LearnedLevel>,
    /// The low-pass corner the inserted breaths passed through to stay inside the recording's
    /// bandwidth, Hz, at the end of the render (`None`: no limit).
    pub band_limit_hz: Option<f64>,
    /// Warnings on what the outputs could not carry or where they went instead (the input's
    /// cue points in a FLAC, the breath markers of a batch's file that is not WAV).
    pub notes: Vec<String>,
}

/// A learned voice's level, as the summary gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LearnedLevel {
    /// Under its speaker's speech, dB.
    pub re_speech_db: f64,
    /// The `--breath-level-db` that plays it there with the render's breathing preset
    /// ([`pneuma_core::engine::EngineConfig::learned_level_setting_db`]).
    pub setting_db: Option<f32>,
}

/// The summary's line on the breath voice, learned at `level` (`None`: not learned), given the
/// breaths inserted (those played from the user's breath samples use no voice).
pub fn describe_voice(
    voice: VoiceStatus,
    level: Option<LearnedLevel>,
    inserted: &[BreathEvent],
) -> String {
    let from_samples = inserted
        .iter()
        .filter(|b| b.kind == BreathKind::Sample)
        .count();
    if from_samples > 0 && from_samples == inserted.len() {
        return "breath sound: your breath samples".into();
    }
    let samples_note = if from_samples > 0 {
        format!(
            " ({from_samples} of {} from your breath samples)",
            crate::options::count(inserted.len(), "breath")
        )
    } else {
        String::new()
    };
    describe_voice_status(voice, level) + &samples_note
}

/// The breath voice's own part of [`describe_voice`]: where it comes from and, once learned,
/// the level it learned and the `--breath-level-db` that plays it there (each dB over or under
/// that setting moves the breaths as much).
fn describe_voice_status(voice: VoiceStatus, level: Option<LearnedLevel>) -> String {
    let breaths = |n| crate::options::count(n, "breath");
    let level = level.map_or(String::new(), |l| {
        let at = l.setting_db.map_or(String::new(), |db| {
            format!(", where --breath-level-db {db:.0} plays them")
        });
        format!(
            "; this speaker's breaths lie {:.0} dB under the speech{at}",
            -l.re_speech_db
        )
    });
    match voice {
        VoiceStatus::Fixed { breaths: n } => {
            format!("breath voice: learned from {}{level}", breaths(n))
        }
        VoiceStatus::Learning { breaths: 0 } | VoiceStatus::BuiltIn => {
            "breath voice: built-in (no breath of the speaker's was learned)".into()
        }
        VoiceStatus::Learning { breaths: n } => {
            format!(
                "breath voice: learned as the render went, from {}{level}",
                breaths(n)
            )
        }
    }
}

/// The summary's line on the breaths' band limit, when there was one.
pub fn describe_band_limit(band_limit_hz: Option<f64>) -> Option<String> {
    band_limit_hz.map(|hz| {
        format!(
            "breaths low-passed at {:.1} kHz, where the recording's sound ends (a call or a \
             line converted up)",
            hz / 1000.0
        )
    })
}

/// What a lossy input became, for the summary: `" (MP3 input written as FLAC: …)"`.
pub fn lossy_note(s: &RenderSummary) -> String {
    let (format, lossless) = s.input_format;
    // MP3 output is asked for: no note.
    if lossless
        || s.container == Container::Mp3
        || s.container == Container::Wav && format == InputFormat::Wav
    {
        return String::new();
    }
    format!(
        "; {} input written as {} (no second lossy generation; --format wav for WAV)",
        format.name(),
        s.container.extension().to_uppercase()
    )
}

/// Renders `input` (`-`: standard input) as `args` ask ([`Job::plan`], then [`render`]);
/// `progress` is called with the fraction done (0..1) now and then.
pub fn run(
    args: &Args,
    input: &Path,
    progress: impl FnMut(f64),
) -> Result<RenderSummary, RenderError> {
    render(Job::plan(args, input)?, progress)
}

/// Runs a planned render: creates the outputs, streams the input through the engine into
/// them, and commits every file together (or, to standard output, finishes the audio).
pub fn render(job: Job, progress: impl FnMut(f64)) -> Result<RenderSummary, RenderError> {
    let Job {
        mut source,
        info,
        input_channels,
        input_format,
        carried,
        mut engine,
        breath_like_note,
        outputs,
    } = job;
    let WavMeta {
        tags,
        cues: input_cues,
        form,
    } = carried;
    if let Some(files) = &outputs.files {
        std::fs::create_dir_all(&files.folder).map_err(out_err(&files.folder))?;
    }
    // Standard output carries the samples alone: the input's tags are said to be left.
    let tags_left = (outputs.files.is_none() && !tags.fields().is_empty())
        .then(|| "the input's tags are not carried: standard output holds none".to_string());
    let audio = match &outputs.files {
        None => AudioSink::stdout(info),
        Some(_) => match outputs.mp3 {
            Some(mp3) => AudioSink::create_mp3(&outputs.audio, info, tags, mp3),
            None => AudioSink::create_keeping(&outputs.audio, info, outputs.container, tags, form),
        },
    }
    .map_err(out_err(&outputs.audio))?;
    let frame_rate_hz = engine.config().analysis.frame_rate_hz;
    let frames_total =
        FrameClock::new(frame_rate_hz, info.sample_rate_hz as f64).frames_in(info.frames);
    let mut sinks = (
        controls_sink(outputs.files.as_ref())?,
        bvh_sink(
            outputs.files.as_ref(),
            outputs.bvh_fps.unwrap_or(frame_rate_hz),
        )?,
        Kept::new(frames_total),
        midi_sink(outputs.files.as_ref(), outputs.cc_map)?,
        outputs
            .osc
            .as_ref()
            .map(crate::osc_out::OscPlan::open)
            .transpose()
            .map_err(RenderError::Input)?,
    );
    let channels = info.channels as usize;
    let mut interleaved = Vec::with_capacity(BLOCK_FRAMES * input_channels.0);
    let mut energy = ChannelEnergy::new(info.sample_rate_hz as f64);
    let mut pass = AudioPass::new(audio, &outputs.audio, info, progress);
    offline::stream(
        &mut engine,
        channels,
        &[BLOCK_FRAMES],
        TailFrames::InputOnly,
        |planar: &mut [Vec<f32>], max: usize| {
            let n = read_block(&mut source, &mut interleaved, input_channels, planar, max)?;
            energy.add(planar, n);
            Ok(n)
        },
        &mut sinks,
        |(controls, bvh, _, midi, _), planar, range| {
            check_text_sinks(controls, bvh, outputs.files.as_ref())?;
            check_midi(midi, outputs.files.as_ref())?;
            pass.write(planar, range)
        },
    )?;
    // The learning pass and the render read the input apart: a file changed in between would
    // be rendered with another file's analysis (nothing is committed; to standard output the
    // audio has gone, the exit status says it failed).
    if engine.replay_verified() == Some(false) {
        return Err(RenderError::Input(
            "the input changed while it was rendered (its samples are not the ones analysed \
             first): render it again once nothing writes to it"
                .into(),
        ));
    }
    // The output's length: the findings' and the breaths' (one cut by the end of the file
    // ends with it).
    let length_s = pass.written as f64 / info.sample_rate_hz as f64;
    let mut found = findings(&energy, &engine.speech_summary(), length_s);
    found.extend(breath_like_note);
    let voice = engine.voice_status();
    let voice_level = engine.learned_voice().map(|v| LearnedLevel {
        re_speech_db: v.level_re_speech_db,
        setting_db: engine.config().learned_level_setting_db(),
    });
    let band_limit_hz = engine.breath_band_limit_hz();
    let (controls, bvh, kept, midi, osc) = sinks;
    // Live mode breathes after each pause without seeing the phrase to come, and its lung
    // runs past the reserve in ordinary speech (10 of the 17 Keele and styletalk clips would
    // be told): the finding is lookahead mode's.
    let placement = &engine.config().placement;
    if placement.insert_breaths && placement.mode == PlacementMode::Lookahead {
        found.extend(
            kept.air
                .finding(1.0 / frame_rate_hz, f64::from(placement.catch_breath_min_s)),
        );
    }
    let osc = outputs
        .osc
        .as_ref()
        .zip(osc)
        .map(|(plan, sender)| plan.finish(sender));
    let AudioPass {
        mut audio,
        envelope,
        ..
    } = pass;
    let breaths = breaths_within(kept.breaths, length_s);
    let clipped = audio.clipped();
    let mut notes = outputs.notes.clone();
    notes.extend(tags_left);
    let breath_cues = if outputs.cues {
        crate::markers::cues(&breaths, info.sample_rate_hz)
    } else {
        Vec::new()
    };
    let holder = outputs.files.as_ref().map(|_| outputs.container);
    match carried_cues(&input_cues, breath_cues, holder) {
        Ok(cues) => audio.set_cues(cues),
        Err(note) => notes.push(note),
    }
    let files = match (&outputs.files, controls) {
        (Some(folder), Some(controls)) => commit_files(
            &outputs,
            folder,
            Finished {
                audio,
                controls,
                bvh,
                midi,
                breaths: &breaths,
                envelope,
                plot_frames: &kept.plot,
                length_s,
            },
        )?,
        // Standard output: the audio is all there is.
        _ => {
            audio.finish().map_err(out_err(&outputs.audio))?;
            vec![outputs.audio.clone()]
        }
    };
    // Only once this render's files are in place: a failed render changes nothing.
    let leftovers = super::leftovers::clear(&outputs.leftovers, outputs.keep_leftovers);
    Ok(RenderSummary {
        info,
        input_format,
        container: outputs.container,
        files,
        breaths,
        // Breath-like sounds in the pauses of what is not speech (a song, an animal) are no
        // speaker's breaths: a render that found no speech reports none.
        heard_breaths: if found.iter().any(super::findings::Finding::found_no_speech) {
            0
        } else {
            kept.heard
        },
        frames: kept.frames,
        length_s,
        clipped,
        findings: found,
        osc,
        leftovers,
        voice,
        voice_level,
        band_limit_hz,
        notes,
    })
}

/// The cue points of the output: the input's own (a DAW's chapter and ad markers, at the same
/// sample frames: the render keeps the input's length and time) and the breath markers, in
/// time order; `Err` with the summary's warning when the output (`container`, `None` for
/// standard output, which carries the samples alone) cannot hold the input's.
fn carried_cues(
    input: &[Cue],
    breaths: Vec<Cue>,
    container: Option<Container>,
) -> Result<Vec<Cue>, String> {
    if container != Some(Container::Wav) && !input.is_empty() {
        let what = match input.len() {
            1 => "cue point is".to_string(),
            n => format!("{n} cue points are"),
        };
        return Err(match container {
            Some(c) => format!(
                "the input's {what} not carried: {} holds none (--format wav keeps them)",
                c.extension().to_uppercase()
            ),
            None => format!(
                "the input's {what} not carried: standard output holds none (render to a file \
                 to keep them)"
            ),
        });
    }
    let mut cues: Vec<Cue> = input.iter().cloned().chain(breaths).collect();
    cues.sort_by_key(|c| c.start_frame);
    Ok(cues)
}

/// The controls CSV, streaming into its file (none for standard output).
fn controls_sink(files: Option<&FolderFiles>) -> Result<Option<TextSink<Output>>, RenderError> {
    let Some(files) = files else {
        return Ok(None);
    };
    let path = &files.controls;
    let o = Output::create(path).map_err(out_err(path))?;
    Ok(Some(TextSink::controls_csv(o).map_err(out_err(path))?))
}

/// The BVH at `bvh_fps` with `--bvh`, its frame count the frames of the audio decoded.
fn bvh_sink(files: Option<&FolderFiles>, bvh_fps: f64) -> Result<Option<BvhFile>, RenderError> {
    let Some(path) = files.and_then(|f| f.bvh.as_ref()) else {
        return Ok(None);
    };
    let bvh = BvhFile::create(path, bvh_fps).map_err(out_err(path))?;
    Ok(Some(bvh))
}

/// The MIDI file with `--midi`: the plugin's CC map with the resolution and head range asked
/// for (`map`), streaming into its file.
fn midi_sink(
    files: Option<&FolderFiles>,
    map: CcMap,
) -> Result<Option<MidiFileSink<Output>>, RenderError> {
    let Some(path) = files.and_then(|f| f.midi.as_ref()) else {
        return Ok(None);
    };
    let o = Output::create(path).map_err(out_err(path))?;
    MidiFileSink::new(o, map)
        .map(Some)
        .map_err(|e| midi_err(path, e))
}

/// A MIDI file's error as the render's.
fn midi_err(path: &Path, e: pneuma_core::encode::midi_file::MidiFileError) -> RenderError {
    use pneuma_core::encode::midi_file::MidiFileError;
    match e {
        MidiFileError::Io(source) => out_err(path)(source),
        other => out_err(path)(std::io::Error::other(other.to_string())),
    }
}

/// A failed write of the MIDI file stops the render.
fn check_midi(
    midi: &Option<MidiFileSink<Output>>,
    files: Option<&FolderFiles>,
) -> Result<(), RenderError> {
    if let (Some(m), Some(path)) = (midi, files.and_then(|f| f.midi.as_ref())) {
        m.check().map_err(out_err(path))?;
    }
    Ok(())
}

/// Reads the next block of `source` into the engine's planar buffers; the frames read.
fn read_block(
    source: &mut AudioSource,
    interleaved: &mut Vec<f32>,
    (input_channels, pick): (usize, Option<usize>),
    planar: &mut [Vec<f32>],
    max: usize,
) -> Result<usize, RenderError> {
    let n = source.read_interleaved(max, interleaved)?;
    for (i, frame) in interleaved.chunks_exact(input_channels).enumerate() {
        match pick {
            Some(k) => planar[0][i] = frame[k],
            None => {
                for (c, &x) in frame.iter().enumerate() {
                    planar[c][i] = x;
                }
            }
        }
    }
    Ok(n)
}

/// A failed write of the controls or the BVH stops the render.
fn check_text_sinks(
    controls: &Option<TextSink<Output>>,
    bvh: &Option<BvhFile>,
    files: Option<&FolderFiles>,
) -> Result<(), RenderError> {
    let Some(files) = files else {
        return Ok(());
    };
    if let Some(text) = controls {
        text.check().map_err(out_err(&files.controls))?;
    }
    if let (Some(bvh), Some(path)) = (bvh, &files.bvh) {
        bvh.check().map_err(out_err(path))?;
    }
    Ok(())
}

/// The audio side of a render: the output audio, the plot's envelope, the progress.
struct AudioPass<'a, P> {
    audio: AudioSink,
    path: &'a Path,
    channels: usize,
    total_in: u64,
    out_interleaved: Vec<f32>,
    envelope: Envelope,
    /// Sample frames written to the output.
    written: u64,
    last_progress: f64,
    progress: P,
}

impl<'a, P: FnMut(f64)> AudioPass<'a, P> {
    fn new(audio: AudioSink, path: &'a Path, info: WavInfo, progress: P) -> Self {
        let channels = info.channels as usize;
        Self {
            audio,
            path,
            channels,
            total_in: info.frames,
            out_interleaved: Vec::with_capacity(BLOCK_FRAMES * channels),
            envelope: Envelope::new(info.frames),
            written: 0,
            last_progress: 0.0,
            progress,
        }
    }

    /// Writes the output samples `range` of `planar`, feeds the envelope, reports progress;
    /// stops on Ctrl-C.
    fn write(&mut self, planar: &[Vec<f32>], range: Range<usize>) -> Result<(), RenderError> {
        self.out_interleaved.clear();
        for i in range.clone() {
            let mut mono = 0.0;
            for p in planar {
                self.out_interleaved.push(p[i]);
                mono += p[i];
            }
            self.envelope.push(mono / self.channels as f32);
        }
        self.written += range.len() as u64;
        self.audio
            .write_interleaved(&self.out_interleaved)
            .map_err(out_err(self.path))?;
        if interrupted() {
            return Err(RenderError::Interrupted);
        }
        let done = self.written as f64 / self.total_in.max(1) as f64;
        if done - self.last_progress >= 0.01 {
            self.last_progress = done;
            (self.progress)(done.min(1.0));
        }
        Ok(())
    }
}

/// The breaths that start before `length_s`, each ending by then at the latest.
fn breaths_within(mut breaths: Vec<BreathEvent>, length_s: f64) -> Vec<BreathEvent> {
    breaths.retain(|b| b.start_s < length_s);
    for b in &mut breaths {
        b.end_s = b.end_s.min(length_s);
    }
    breaths
}

/// What a render to a folder has once the input is through.
struct Finished<'a> {
    audio: AudioSink,
    controls: TextSink<Output>,
    bvh: Option<BvhFile>,
    midi: Option<MidiFileSink<Output>>,
    breaths: &'a [BreathEvent],
    envelope: Envelope,
    plot_frames: &'a [ControlFrame],
    length_s: f64,
}

/// Finishes every file of a render to a folder under a temporary name, then moves them all
/// into place together, or none; the files in the order the summary lists them.
fn commit_files(
    outputs: &OutputPlan,
    files: &FolderFiles,
    done: Finished<'_>,
) -> Result<Vec<PathBuf>, RenderError> {
    let mut breaths_out = Output::create(&files.breaths).map_err(out_err(&files.breaths))?;
    breaths_csv::write_all(&mut breaths_out.writer(), done.breaths)
        .map_err(out_err(&files.breaths))?;
    let mut written = vec![
        outputs.audio.clone(),
        files.controls.clone(),
        files.breaths.clone(),
    ];
    let mut staged = vec![
        done.audio
            .finish()
            .map_err(out_err(&outputs.audio))?
            .ok_or_else(|| out_err(&outputs.audio)(std::io::Error::other("not a file")))?,
        staged_file(
            done.controls
                .into_inner()
                .map_err(out_err(&files.controls))?,
            &files.controls,
        )?,
        staged_file(breaths_out, &files.breaths)?,
    ];
    for (kind, path) in &files.markers {
        let mut o = Output::create(path).map_err(out_err(path))?;
        o.writer()
            .write_all(kind.file_text(done.breaths).as_bytes())
            .map_err(out_err(path))?;
        staged.push(staged_file(o, path)?);
        written.push(path.clone());
    }
    if let (Some(bvh), Some(path)) = (done.bvh, &files.bvh) {
        staged.push(bvh.finish(path).map_err(out_err(path))?);
        written.push(path.clone());
    }
    if let (Some(m), Some(path)) = (done.midi, &files.midi) {
        let o = m.finish().map_err(|e| midi_err(path, e))?;
        staged.push(staged_file(o, path)?);
        written.push(path.clone());
    }
    if let Some(path) = &files.plot {
        let plot = Staged::new(path).map_err(out_err(path))?;
        crate::plot::draw_png(
            plot.temp(),
            path,
            &done.envelope.finish(),
            done.length_s,
            done.plot_frames,
            done.breaths,
        )?;
        staged.push(plot);
        written.push(path.clone());
    }
    if interrupted() {
        return Err(RenderError::Interrupted);
    }
    commit_all(staged).map_err(|(path, source)| RenderError::Output { path, source })?;
    Ok(written)
}

/// Finishes a file output of the render (never standard output) into its staged file.
fn staged_file(out: Output, path: &Path) -> Result<Staged, RenderError> {
    out.finish()
        .map_err(out_err(path))?
        .ok_or_else(|| out_err(path)(std::io::Error::other("not a file")))
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
/// every `every`-th frame for the plot (at most [`PLOT_FRAMES`]), the inserted breaths, the
/// number of real breaths heard and the longest run of speech on an emptied lung.
struct Kept {
    every: usize,
    frames: u64,
    plot: Vec<ControlFrame>,
    breaths: Vec<BreathEvent>,
    heard: usize,
    air: AirRun,
}

impl Kept {
    fn new(frames_total: u64) -> Self {
        Self {
            every: (frames_total as usize).div_ceil(PLOT_FRAMES).max(1),
            frames: 0,
            plot: Vec::new(),
            breaths: Vec::new(),
            heard: 0,
            air: AirRun::default(),
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
        self.air
            .frame(frame.time_s, frame.speaking, frame.breathing.lung);
    }
    fn breath(&mut self, breath: &BreathEvent) {
        self.breaths.push(*breath);
    }
    fn existing_breath(&mut self, _start_s: f64, _end_s: f64) {
        self.heard += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_voice_line_names_the_users_samples_when_they_sounded() {
        let breath = |kind| BreathEvent {
            start_s: 1.0,
            end_s: 1.4,
            kind,
            peak_db: -30.0,
        };
        let samples = [breath(BreathKind::Sample), breath(BreathKind::Sample)];
        assert_eq!(
            describe_voice(VoiceStatus::BuiltIn, None, &samples),
            "breath sound: your breath samples"
        );
        let some = [breath(BreathKind::Sample), breath(BreathKind::Mixed)];
        let level = |setting_db| {
            Some(LearnedLevel {
                re_speech_db: -31.4,
                setting_db,
            })
        };
        let line = describe_voice(VoiceStatus::Fixed { breaths: 3 }, level(Some(-22.0)), &some);
        assert!(
            line.starts_with("breath voice: learned from 3 breaths"),
            "{line}"
        );
        assert!(
            line.ends_with("(1 of 2 breaths from your breath samples)"),
            "{line}"
        );
        assert!(
            line.contains("breaths lie 31 dB under the speech, where --breath-level-db -22"),
            "{line}"
        );
        // Another preset's setting (calm's), and none (a silent breathing sound).
        let calm = describe_voice(VoiceStatus::Fixed { breaths: 3 }, level(Some(-19.1)), &some);
        assert!(
            calm.contains("where --breath-level-db -19 plays them"),
            "{calm}"
        );
        let silent = describe_voice(VoiceStatus::Fixed { breaths: 3 }, level(None), &some);
        assert!(silent.contains("31 dB under the speech ("), "{silent}");
        let none = describe_voice(VoiceStatus::BuiltIn, None, &[breath(BreathKind::Mixed)]);
        assert!(none.starts_with("breath voice: built-in"), "{none}");
        assert!(!none.contains("dB under"), "{none}");
    }

    #[test]
    fn the_band_limit_line_gives_the_corner_in_khz_and_only_with_a_limit() {
        assert_eq!(describe_band_limit(None), None);
        let line = describe_band_limit(Some(7_612.5)).expect("a limit gets a line");
        assert!(line.starts_with("breaths low-passed at 7.6 kHz"), "{line}");
    }

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
