//! Which breaths the engine heard in an episode are real: the hand labels of the Keele and
//! styletalk clips (`assets/labels/*.csv`, [`crate::labels`]) moved to where each clip lies in
//! the episode. Every pause of those clips was looked at when they were labelled, so a heard
//! breath over no label there is not a breath; the PTDB clips hold no labels, so a breath heard
//! in them cannot be judged.
//! The clear `breath` labels also tell where an inserted breath lies over a real one
//! ([`RealBreaths::breath_frames`]).

use std::collections::BTreeMap;
use std::path::Path;

use super::recipe::{Episode, Segment};
use super::sources::{FRAMES_PER_S, KEELE, STYLETALK};
use crate::data::read_labels;
use crate::labels::LabelKind;
use crate::stats::overlaps;

/// The labelled spans (`breath` and `unsure` alike) of every labelled clip, seconds, with
/// whether the span is a clear breath.
#[derive(Debug, Clone, Default)]
pub struct RealBreaths {
    by_clip: BTreeMap<String, Vec<(f64, f64, bool)>>,
}

impl RealBreaths {
    /// Reads the Keele and styletalk labels from `dir` (`keele_breaths.csv`,
    /// `styletalk_breaths.csv`); every Keele and styletalk clip is labelled, with or without
    /// spans.
    pub fn load(dir: &Path) -> Result<Self, String> {
        let mut by_clip: BTreeMap<String, Vec<(f64, f64, bool)>> = KEELE
            .iter()
            .chain(&STYLETALK)
            .map(|c| (c.to_string(), Vec::new()))
            .collect();
        for file in ["keele_breaths.csv", "styletalk_breaths.csv"] {
            for l in read_labels(&dir.join(file)).map_err(|e| e.to_string())? {
                by_clip.entry(l.clip.clone()).or_default().push((
                    l.start_s,
                    l.end_s,
                    l.kind == LabelKind::Breath,
                ));
            }
        }
        Ok(Self { by_clip })
    }

    /// Whether the breath the engine heard at `span_s` (episode seconds) in `segment` lies on
    /// a labelled real one (`None`: an unlabelled clip).
    pub fn on_label(&self, segment: &Segment, span_s: (f64, f64)) -> Option<bool> {
        let spans = self.by_clip.get(&segment.clip)?;
        let offset_s = segment.frames.0 as f64 / FRAMES_PER_S;
        let in_clip = (span_s.0 - offset_s, span_s.1 - offset_s);
        Some(spans.iter().any(|&(a, b, _)| overlaps((a, b), in_clip)))
    }

    /// Per label frame of `episode`: on a clear `breath` label of its clip (each span moved
    /// to where its clip lies, cut to the clip's segment).
    pub fn breath_frames(&self, episode: &Episode) -> Vec<bool> {
        let n = episode.frames();
        let mut out = vec![false; n];
        for seg in &episode.segments {
            let Some(spans) = self.by_clip.get(&seg.clip) else {
                continue;
            };
            let (first, end) = (seg.frames.0, seg.frames.1.min(n));
            for &(a, b, _) in spans.iter().filter(|&&(_, _, clear)| clear) {
                let fa = first + (a * FRAMES_PER_S).floor().max(0.0) as usize;
                let fb = (first + (b * FRAMES_PER_S).ceil() as usize).min(end);
                out[fa.min(fb)..fb].iter_mut().for_each(|f| *f = true);
            }
        }
        out
    }
}

/// The speech segment of `episode` that holds the middle of `span_s` (episode seconds).
pub fn segment_at(episode: &Episode, span_s: (f64, f64)) -> Option<&Segment> {
    let mid_frame = 0.5 * (span_s.0 + span_s.1) * FRAMES_PER_S;
    episode
        .segments
        .iter()
        .find(|g| (g.frames.0 as f64) <= mid_frame && mid_frame < g.frames.1 as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::podcast::recipe::{Condition, Labels};

    #[test]
    fn a_heard_breath_is_judged_against_its_clips_labels_moved_to_the_segment() {
        let real = RealBreaths {
            by_clip: [
                ("f1nw0000".to_string(), vec![(2.0, 2.4, true)]),
                ("Obama_clip1".to_string(), vec![]),
            ]
            .into(),
        };
        // The clip starts 10 s into the episode.
        let at = |clip: &str| Segment {
            clip: clip.to_string(),
            speaker: 0,
            condition: Condition::Clean,
            frames: (
                (10.0 * FRAMES_PER_S) as usize,
                (40.0 * FRAMES_PER_S) as usize,
            ),
        };
        assert_eq!(real.on_label(&at("f1nw0000"), (12.1, 12.5)), Some(true));
        assert_eq!(real.on_label(&at("f1nw0000"), (2.1, 2.5)), Some(false));
        assert_eq!(real.on_label(&at("Obama_clip1"), (12.1, 12.5)), Some(false));
        assert_eq!(real.on_label(&at("mic_F01_sa1"), (12.1, 12.5)), None);
    }

    #[test]
    fn breath_frames_lie_where_the_clip_lies_and_only_clear_breaths_count() {
        let real = RealBreaths {
            by_clip: [(
                "andrew_clip_1".to_string(),
                vec![(1.0, 1.2, true), (2.0, 2.1, false), (9.0, 9.5, true)],
            )]
            .into(),
        };
        // The clip lies from 10 s to 15 s: its span at 9 s is cut off with it.
        let episode = Episode {
            index: 0,
            main_piece: 0,
            stings: [0, 0],
            audio: Vec::new(),
            clean: Vec::new(),
            labels: Labels {
                truth: vec![false; 2000],
                ..Labels::default()
            },
            segments: vec![Segment {
                clip: "andrew_clip_1".to_string(),
                speaker: 0,
                condition: Condition::Clean,
                frames: (1000, 1500),
            }],
        };
        let f = real.breath_frames(&episode);
        let on: Vec<usize> = (0..f.len()).filter(|&k| f[k]).collect();
        assert_eq!(on, (1100..1120).collect::<Vec<_>>());
    }

    #[test]
    fn every_keele_and_styletalk_clip_is_labelled_and_the_shipped_labels_load() {
        let real = RealBreaths::load(&crate::data::workspace_root().join("assets/labels"))
            .expect("the shipped labels");
        for clip in KEELE.iter().chain(&STYLETALK) {
            assert!(real.by_clip.contains_key(*clip), "{clip}");
        }
        assert!(real.by_clip["f1nw0000"].len() >= 6);
    }
}
