//! The BVH of a render (`--bvh`), whose header holds its frame count: the count follows the
//! control frames of the audio actually decoded, never the length the input's header
//! announced (a FLAC whose STREAMINFO said half its length gave a BVH of half the audio; an
//! input that announces none, a pipe, gave no BVH at all).
//!
//! The motion lines stream into a temporary file beside the BVH as the render goes; at the
//! end the BVH is written whole, the header with the count of lines written and then the
//! lines, and goes with the render's other files ([`crate::output::commit_all`]). Another
//! rate (`--bvh-fps`) is core's [`Resample`], the pose at each instant interpolated between the
//! frames either side (no instant past the last frame's time, as [`Resample::count`] counts).

use std::path::Path;

use pneuma_core::encode::bvh;
use pneuma_core::encode::sink::{FrameSink, Resample, TextSink};
use pneuma_core::ControlFrame;

use crate::output::{Output, Staged};

/// Frames passed on to `inner`, counted.
struct Counted<S> {
    inner: S,
    frames: u64,
}

impl<S: FrameSink> FrameSink for Counted<S> {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        self.inner.frame(frame, at);
        self.frames += 1;
    }
}

/// The motion lines at the BVH's rate, counted, into the temporary file.
type Lines = Resample<Counted<TextSink<Output>>>;

/// A BVH being written: a [`FrameSink`] of the render's control frames.
pub struct BvhFile {
    lines: Lines,
    bvh_fps: f64,
}

impl BvhFile {
    /// Starts the BVH that goes to `path`, of control frames written at `bvh_fps`: its lines
    /// go to a temporary file (removed when this is dropped).
    pub fn create(path: &Path, bvh_fps: f64) -> std::io::Result<Self> {
        let text = TextSink::new(Output::create(path)?, "", bvh::push_control)?;
        let counted = Counted {
            inner: text,
            frames: 0,
        };
        Ok(Self {
            lines: Resample::new(counted, bvh_fps, u64::MAX),
            bvh_fps,
        })
    }

    /// The first write error of the lines, if any.
    pub fn check(&self) -> std::io::Result<()> {
        self.lines.inner().inner.check()
    }

    /// Writes the BVH for `path` whole, its header counting the lines, under a temporary name
    /// ([`Staged`]) for the render to commit with its other files.
    pub fn finish(self, path: &Path) -> std::io::Result<Staged> {
        let Counted {
            inner: text,
            frames: lines,
        } = self.lines.into_inner();
        let body = staged(text.into_inner()?.finish()?)?;
        let mut out = Output::create(path)?;
        let header = bvh::header(usize::try_from(lines).unwrap_or(usize::MAX), self.bvh_fps);
        out.writer().write_all(header.as_bytes())?;
        std::io::copy(&mut std::fs::File::open(body.temp())?, out.writer())?;
        // `body` is dropped uncommitted: its temporary file goes.
        staged(out.finish()?)
    }
}

/// A finished file output's staged file (the BVH is never standard output).
fn staged(file: Option<Staged>) -> std::io::Result<Staged> {
    file.ok_or_else(|| std::io::Error::other("not a file"))
}

impl FrameSink for BvhFile {
    fn frame(&mut self, frame: &ControlFrame, at: u64) {
        self.lines.frame(frame, at);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `Frames:` count and the motion lines of the BVH `text`.
    fn frames_and_lines(text: &str) -> (usize, usize) {
        let count = text
            .lines()
            .find_map(|l| l.strip_prefix("Frames: "))
            .and_then(|n| n.parse().ok())
            .expect("a frame count");
        let motion = text.split_once("Frame Time: ").expect("motion").1;
        (count, motion.lines().count() - 1)
    }

    #[test]
    fn the_header_counts_the_lines_of_the_frames_received() {
        let dir = tempfile::tempdir().expect("temp dir");
        for (frames, fps) in [
            (121u64, 120.0),
            (121, 24.0),
            (121, 1000.0),
            (1, 30.0),
            (0, 30.0),
        ] {
            let path = dir.path().join(format!("x{frames}_{fps}.bvh"));
            let mut bvh = BvhFile::create(&path, fps).expect("create");
            for i in 0..frames {
                let f = ControlFrame {
                    index: i,
                    time_s: i as f64 / 120.0,
                    ..Default::default()
                };
                bvh.frame(&f, i * 400);
            }
            let staged = bvh.finish(&path).expect("finish");
            crate::output::commit_all(vec![staged]).expect("commit");
            let text = std::fs::read_to_string(&path).expect("read");
            let want = Lines::count(frames, 120.0, fps) as usize;
            assert_eq!(
                frames_and_lines(&text),
                (want, want),
                "{frames} frames at {fps}"
            );
            assert!(text.starts_with(&bvh::header(want, fps)));
        }
        // Only the BVHs are left: the temporary files of their lines are gone.
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
    }
}
