//! The level of the voice a breath belongs to: the speaker who speaks next. A breath is as loud
//! as its own speaker's voice allows, and in an interview whose guest speaks 12 dB under the host
//! the guest's breaths lie 12 dB under the host's. A breath heard is measured against its
//! speaker's level ([`crate::breathing::learned::HeardBreath::speaker_level_db`]) and a breath
//! inserted plays that far under the level of the speaker after it (the breath track moves the
//! voice by that level less the voice's speech level), as far as it is known when the breath is
//! placed: a lookahead too short to hear the phrase after the breath for the speech decision's
//! window (the plugin's default 500 ms) and live mode take the speaker before it, so there the
//! breath before a turn has the last speaker's level (`Placement::breath_speaker_db`).
//!
//! A phrase's level here is the median level of its voiced frames (the statistic of the
//! recording's speech level, so that for one speaker the two agree). A speaker's level is the
//! median of the recent phrases' levels within [`SAME_SPEAKER_DB`] of the phrase after the
//! breath: a speaker's phrases wander a few dB, two voices recorded further apart than that are
//! two speakers. One speaker: every phrase is near every other, and the speaker's level is the
//! median of the recent phrases whichever phrase comes next. No speaker model, no state beyond
//! the phrase being spoken and the last [`RECENT_PHRASES`] levels. Allocation-free.

use crate::analysis::{FeatureFrame, LEVEL_FLOOR_DB};
use crate::breathing::learned;

/// Two phrase levels this far apart or more are taken for two speakers, dB.
const SAME_SPEAKER_DB: f32 = learned::SAME_SPEAKER_DB as f32;
/// Phrases whose levels are kept (about two minutes of speech).
pub(crate) const RECENT_PHRASES: usize = 32;
/// Voiced frames a phrase needs before its level counts.
pub(crate) const MIN_VOICED_FRAMES: u32 = 3;
/// Width of the bins of a phrase's level histogram, dB.
const BIN_DB: f32 = 0.5;
/// Bins from the level floor to 0 dBFS.
const BINS: usize = (-LEVEL_FLOOR_DB / BIN_DB) as usize;

/// A phrase's levels: the mean power of its voiced frames (the placement's phrase level) and
/// the median of their levels (the speaker level's statistic), dBFS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PhraseLevel {
    /// The mean power of the voiced frames, dBFS (what a breath's gain follows).
    pub(crate) mean_db: f32,
    /// The median level of the voiced frames, dBFS (what a speaker's level is made of).
    pub(crate) median_db: f32,
}

/// The voiced frames' levels of a stretch: their power sum and a histogram.
#[derive(Debug, Clone, Copy)]
pub(crate) struct VoicedLevels {
    power: f64,
    voiced: u32,
    histogram: [u16; BINS],
}

impl Default for VoicedLevels {
    fn default() -> Self {
        Self {
            power: 0.0,
            voiced: 0,
            histogram: [0; BINS],
        }
    }
}

impl VoicedLevels {
    /// Whether frame `f` is a voiced frame with a finite level (the frames that count).
    pub(crate) fn counts(f: &FeatureFrame) -> bool {
        f.voiced && f.rms_db.is_finite() && f.level_db.is_finite()
    }

    /// Adds frame `f` when it counts; true when it did.
    pub(crate) fn add(&mut self, f: &FeatureFrame) -> bool {
        let counts = Self::counts(f);
        if counts {
            self.power += 10f64.powf(f64::from(f.rms_db) / 10.0);
            self.voiced += 1;
            let bin = ((f.rms_db - LEVEL_FLOOR_DB) / BIN_DB).clamp(0.0, BINS as f32 - 1.0);
            let c = &mut self.histogram[bin as usize];
            *c = c.saturating_add(1);
        }
        counts
    }

    /// The levels, once `frames` voiced frames (at least one) have counted.
    pub(crate) fn level(&self, frames: u32) -> Option<PhraseLevel> {
        if self.voiced < frames.max(1) {
            return None;
        }
        let total: u32 = self.histogram.iter().map(|&c| u32::from(c)).sum();
        let mut seen = 0;
        let mut median_db = 0.0;
        for (bin, &c) in self.histogram.iter().enumerate() {
            seen += u32::from(c);
            if 2 * seen >= total {
                median_db = LEVEL_FLOOR_DB + (bin as f32 + 0.5) * BIN_DB;
                break;
            }
        }
        Some(PhraseLevel {
            mean_db: (10.0 * (self.power / f64::from(self.voiced)).log10()) as f32,
            median_db,
        })
    }
}

/// The phrase being spoken and the levels of the recent ones; see the module docs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhraseLevels {
    spoken: VoicedLevels,
    /// Recent phrases' median levels, dBFS: a ring of the last `count.min(RECENT_PHRASES)`.
    levels: [f32; RECENT_PHRASES],
    count: usize,
}

impl Default for PhraseLevels {
    fn default() -> Self {
        Self {
            spoken: VoicedLevels::default(),
            levels: [0.0; RECENT_PHRASES],
            count: 0,
        }
    }
}

impl PhraseLevels {
    /// One analysis frame of the phrase being spoken; true when it counts (voiced, finite).
    pub(crate) fn frame(&mut self, f: &FeatureFrame) -> bool {
        self.spoken.add(f)
    }

    /// A phrase starts: its frames count from here.
    pub(crate) fn start(&mut self) {
        self.spoken = VoicedLevels::default();
    }

    /// The level of the phrase being spoken, once it has `frames` voiced frames.
    pub(crate) fn spoken(&self, frames: u32) -> Option<PhraseLevel> {
        self.spoken.level(frames)
    }

    /// The phrase ended: its level joins the recent ones (when it has enough voiced frames)
    /// and is returned.
    pub(crate) fn end(&mut self) -> Option<PhraseLevel> {
        let level = self.spoken(MIN_VOICED_FRAMES)?;
        self.levels[self.count % RECENT_PHRASES] = level.median_db;
        self.count += 1;
        Some(level)
    }

    /// The median level of the last phrase that ended with a level, dBFS.
    pub(crate) fn last_db(&self) -> Option<f32> {
        let last = self.count.checked_sub(1)?;
        Some(self.levels[last % RECENT_PHRASES])
    }

    /// The level of the speaker of `phrase` (one that ended: [`PhraseLevels::end`]), dBFS; NaN
    /// for a phrase without a level.
    pub(crate) fn speaker_of(&self, phrase: Option<PhraseLevel>) -> f32 {
        phrase.map_or(f32::NAN, |l| self.speaker_level_db(l.median_db))
    }

    /// The level of the speaker whose phrase's median level is `next_db`, dBFS: the median of
    /// the recent phrases within [`SAME_SPEAKER_DB`] of it, itself included.
    pub(crate) fn speaker_level_db(&self, next_db: f32) -> f32 {
        let n = self.count.min(RECENT_PHRASES);
        let mut near = [0.0f64; RECENT_PHRASES + 1];
        near[0] = f64::from(next_db);
        let mut k = 1;
        for &db in &self.levels[..n] {
            if (db - next_db).abs() < SAME_SPEAKER_DB {
                near[k] = f64::from(db);
                k += 1;
            }
        }
        learned::median(&mut near[..k]) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn levels(dbs: &[f32]) -> PhraseLevels {
        let mut p = PhraseLevels::default();
        for &db in dbs {
            p.levels[p.count % RECENT_PHRASES] = db;
            p.count += 1;
        }
        p
    }

    #[test]
    fn one_speakers_level_is_the_recent_phrases_whatever_the_next_one() {
        // Phrases wandering 3 dB around -24 dBFS.
        let p = levels(&[-24.0, -22.0, -26.0, -23.0, -25.0, -21.5, -26.5, -24.0]);
        for next in [-27.0, -24.0, -21.0] {
            let db = p.speaker_level_db(next);
            assert!((db + 24.0).abs() <= 1.0, "{next}: {db}");
        }
        assert_eq!(PhraseLevels::default().speaker_level_db(-30.0), -30.0);
    }

    #[test]
    fn in_an_interview_each_speakers_level_is_their_own() {
        // Host at -20 dBFS, guest 12 dB under, in turns.
        let p = levels(&[
            -20.0, -21.0, -32.0, -33.0, -19.0, -31.0, -32.5, -20.5, -20.0, -32.0,
        ]);
        let guest = p.speaker_level_db(-31.0);
        let host = p.speaker_level_db(-21.0);
        assert!((guest + 32.0).abs() <= 0.5, "guest {guest}");
        assert!((host + 20.0).abs() <= 0.5, "host {host}");
        // The guest's first phrase after the host's alone: its own level.
        let p = levels(&[-20.0, -21.0, -19.0]);
        assert_eq!(p.speaker_level_db(-32.0), -32.0);
    }

    #[test]
    fn a_phrase_counts_once_it_has_enough_voiced_frames() {
        let mut p = PhraseLevels::default();
        let mut f = FeatureFrame {
            voiced: true,
            rms_db: -20.0,
            level_db: 0.0,
            ..FeatureFrame::default()
        };
        p.start();
        p.frame(&f);
        assert_eq!(p.end(), None, "one voiced frame");
        p.start();
        for db in [-20.0, -20.2, -26.0] {
            f.rms_db = db;
            assert!(p.frame(&f));
        }
        f.voiced = false;
        assert!(!p.frame(&f));
        let level = p.end().expect("three voiced frames");
        let mean: f64 = [-20.0f64, -20.2, -26.0]
            .iter()
            .map(|db| 10f64.powf(db / 10.0))
            .sum::<f64>()
            / 3.0;
        assert!((f64::from(level.mean_db) - 10.0 * mean.log10()).abs() < 1e-4);
        // The median frame, to the histogram's half-dB bin.
        assert!((level.median_db + 20.2).abs() <= BIN_DB, "{level:?}");
        assert_eq!(p.count, 1);
        assert_eq!(p.last_db(), Some(level.median_db));
        assert_eq!(
            p.speaker_of(Some(level)),
            level.median_db,
            "its own level, alone"
        );
        assert!(p.speaker_of(None).is_nan());
        assert_eq!(PhraseLevels::default().last_db(), None);
    }
}
