//! The files `pneuma speak` writes in its folder, all named after the stem `speech`: always
//! the audio (`--format`: 16-bit WAV by default, or FLAC or AIFF at the TTS's rate, or MP3 at
//! the nearest rate it holds), the controls and the breaths; the plot unless `--no-plot`, the
//! BVH and the MIDI file when asked. Everything is staged and moved into place together, or
//! nothing is ([`crate::output::commit_all`]). The plot, BVH and MIDI file an earlier run left
//! and this one does not write are then removed as a render's are
//! ([`crate::render::leftovers`]); audio of another format with the same stem is left alone
//! and named, as `render` does ([`other_audio`]: it may be the user's own).

use std::io::Write;
use std::path::{Path, PathBuf};

use pneuma_core::encode::midi_cc::CcMap;
use pneuma_core::encode::midi_file::MidiFileSink;
use pneuma_core::encode::sink::{FrameSink as _, Resample, TextSink};
use pneuma_core::encode::{breaths_csv, controls_csv};
use pneuma_core::{BreathEvent, ControlFrame};
use pneuma_io::Tags;

use super::{Args, SpeakError};
use crate::audio_out::{AudioSink, Container};
use crate::mp3_out::Mp3Settings;
use crate::output::{commit_all, Output, Staged};
use crate::plot::draw_png;
use crate::render::leftovers::{self, Cleared, Leftover};
use crate::render::marks::Optional;
use crate::wav::WavInfo;

/// The stem every file is named after.
const STEM: &str = "speech";
const CONTROLS_FILE: &str = "speech.controls.csv";
const BREATHS_FILE: &str = "speech.breaths.csv";
const PLOT_FILE: &str = "speech.png";
const BVH_FILE: &str = "speech.bvh";
const MIDI_FILE: &str = "speech.mid";
/// Bits per sample of the integer formats (the TTS's own depth).
const BITS: u16 = 16;

/// The audio file's name as `container`: `speech.wav`, `speech.flac`, ….
pub fn audio_name(container: Container) -> String {
    format!("{STEM}.{}", container.extension())
}

/// Every file a run with the audio as `container` may write, in `folder`.
pub fn all_paths(folder: &Path, container: Container) -> Vec<PathBuf> {
    let audio = audio_name(container);
    [
        audio.as_str(),
        CONTROLS_FILE,
        BREATHS_FILE,
        PLOT_FILE,
        BVH_FILE,
        MIDI_FILE,
    ]
    .iter()
    .map(|n| folder.join(n))
    .collect()
}

/// The audio files of the other formats beside this run's (an earlier take's `speech.wav`
/// beside this one's `speech.flac`, or the user's file), for a warning: they stay, but the
/// files beside them now describe this take.
pub fn other_audio(folder: &Path, container: Container) -> Vec<PathBuf> {
    let audio = folder.join(audio_name(container));
    crate::audio_out::other_formats_beside(&audio).collect()
}

/// The warning on `other`, beside `container`'s audio.
pub fn other_audio_line(other: &Path, container: Container) -> String {
    format!(
        "{} stays beside this take's {}: it is not this take's audio (an earlier take in \
         another --format, or your own file), and {BREATHS_FILE} and the other files now \
         describe {}; remove it, or speak into another folder",
        other.display(),
        audio_name(container),
        audio_name(container),
    )
}

/// The spoken take to write.
pub struct Take<'a> {
    /// The mono audio, within ±1.
    pub audio: &'a [f32],
    /// Its rate, Hz (the TTS's).
    pub rate_hz: u32,
    /// The control frames.
    pub frames: &'a [ControlFrame],
    /// The inserted breaths.
    pub breaths: &'a [BreathEvent],
}

/// How the optional outputs are written, resolved from the options before anything is spoken.
pub struct Formats {
    /// The audio's container.
    pub container: Container,
    /// The MP3 encoding, with `--format mp3`.
    pub mp3: Option<Mp3Settings>,
    /// The BVH's frame rate when not the control frame rate.
    pub bvh_fps: Option<f64>,
    /// The MIDI file's controller map.
    pub cc_map: CcMap,
}

/// Writes every file of `take` in `args.out_dir`, all together or none, then clears what an
/// earlier run left; returns what became of those leftovers.
pub fn write(args: &Args, take: &Take, formats: &Formats) -> Result<Cleared, SpeakError> {
    let out = |name: &str| args.out_dir.join(name);
    let mut staged = vec![
        write_audio(&out(&audio_name(formats.container)), take, formats)?,
        write_file(&out(CONTROLS_FILE), |mut w| {
            controls_csv::write_all(&mut w, take.frames)
        })?,
        write_file(&out(BREATHS_FILE), |mut w| {
            breaths_csv::write_all(&mut w, take.breaths)
        })?,
    ];
    if args.bvh.wanted() {
        let (frame_rate, fps) = (args.frame_rate, formats.bvh_fps.unwrap_or(args.frame_rate));
        staged.push(write_file(&out(BVH_FILE), |w| {
            // At the BVH's rate: the pose at each instant, as `render` writes it.
            let n = Resample::<TextSink<&mut dyn Write>>::count(
                take.frames.len() as u64,
                frame_rate,
                fps,
            );
            let mut bvh = Resample::new(TextSink::bvh(w, n as usize, fps)?, fps, n);
            for f in take.frames {
                bvh.frame(f, 0);
            }
            bvh.into_inner().into_inner().map(drop)
        })?);
    }
    if args.midi.wanted() {
        staged.push(write_file(&out(MIDI_FILE), |w| {
            let cursor = std::io::Cursor::new(Vec::new());
            let mut midi =
                MidiFileSink::new(cursor, formats.cc_map).map_err(std::io::Error::other)?;
            for f in take.frames {
                midi.frame(f, 0);
            }
            let bytes = midi.finish().map_err(std::io::Error::other)?;
            w.write_all(&bytes.into_inner())
        })?);
    }
    if !args.no_plot {
        let plot_path = out(PLOT_FILE);
        let plot = Staged::new(&plot_path).map_err(|source| SpeakError::Output {
            path: plot_path.clone(),
            source,
        })?;
        let length_s = take.audio.len() as f64 / f64::from(take.rate_hz);
        draw_png(
            plot.temp(),
            &plot_path,
            take.audio,
            length_s,
            take.frames,
            take.breaths,
        )?;
        staged.push(plot);
    }
    commit_all(staged).map_err(|(path, source)| SpeakError::Output { path, source })?;
    // The optional files this run did not write, as an earlier one may have left them: they
    // would describe another take (a BVH of 3.9 s beside 1.8 s of speech).
    let unwritten: Vec<Leftover> = [
        (PLOT_FILE, Optional::Plot, args.no_plot),
        (BVH_FILE, Optional::Bvh, !args.bvh.wanted()),
        (MIDI_FILE, Optional::Midi, !args.midi.wanted()),
    ]
    .into_iter()
    .filter(|&(_, _, left_out)| left_out)
    .map(|(name, file, _)| Leftover {
        path: out(name),
        file,
    })
    .collect();
    Ok(leftovers::clear(&unwritten, args.no_overwrite))
}

/// The audio, staged, as `formats` ask.
fn write_audio(path: &Path, take: &Take, formats: &Formats) -> Result<Staged, SpeakError> {
    let err = |source| SpeakError::Output {
        path: path.to_owned(),
        source,
    };
    let info = WavInfo {
        sample_rate_hz: take.rate_hz,
        channels: 1,
        bits: BITS,
        float: false,
        frames: take.audio.len() as u64,
    };
    let tags = Tags::default();
    let mut sink = match formats.mp3 {
        Some(mp3) => AudioSink::create_mp3(path, info, tags, mp3),
        None => AudioSink::create_as(path, info, formats.container, tags),
    }
    .map_err(err)?;
    sink.write_interleaved(take.audio).map_err(err)?;
    sink.finish().map_err(err)?.ok_or_else(|| err(not_a_file()))
}

fn not_a_file() -> std::io::Error {
    std::io::Error::other("speak writes files, not standard output")
}

fn write_file(
    path: &Path,
    body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<Staged, SpeakError> {
    let err = |source| SpeakError::Output {
        path: path.to_owned(),
        source,
    };
    let mut out = Output::create(path).map_err(err)?;
    body(out.writer()).map_err(err)?;
    out.finish().map_err(err)?.ok_or_else(|| err(not_a_file()))
}
