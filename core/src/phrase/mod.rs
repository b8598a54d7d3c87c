//! Phrase tracking on the feature frames: speech / pause, phrase onsets and offsets, pause
//! lengths, and whether a pause already holds a breath.
//!
//! ## The decision, per frame
//! - Levels are the voice-band level of the frame ([`FeatureFrame::band_db`], above 120 Hz), so
//!   low rumble does not look like speech.
//! - An adaptive noise floor follows the frame level by minimum statistics (the minimum of the
//!   last few half-second blocks), so it tracks stationary noise and rises within seconds when
//!   the noise gets louder.
//! - A frame is **active** when it is voiced, or when its level is both `activity_margin_db` over
//!   the noise floor and no more than `unvoiced_drop_db` under the running speech level (so
//!   fricatives count as speech, breaths and room noise do not).
//! - A phrase **starts** once a run of active frames holds `onset_voiced_s` of voiced frames. Its
//!   onset is then moved back over the contiguous frames just before it that stand
//!   `edge_margin_db` over the floor (an initial /s/ or /f/), at most `edge_extend_s`.
//! - A phrase **ends** after `hangover_s` without an active frame; its offset is the end of the
//!   last active frame, moved forward the same way over a decaying tail.
//! - Inside a pause, a **breath** is a run of at least `breath_min_s` of unvoiced frames that stand
//!   `breath_margin_db` over the floor but are not active (a noise burst well under the speech
//!   level) and that has a breath's spectral shape: with the room's band levels (an average of
//!   [`FeatureFrame::bands`] over frames at the floor) taken out of each frame's band powers, the
//!   run's mean high-over-mid level is at most `breath_max_high_over_mid_db` (not a sibilant)
//!   and its low-over-mid at most `breath_max_low_over_mid_db` (not a vowel's tail or rumble).
//!   A run that starts at the phrase's offset must also rise 3 dB over its lowest
//!   point (a reverberant tail only falls).
//!
//! Events are reported when they are certain, with the times they refer to (which lie in the
//! past): a consumer with lookahead (the engine's delay line) places breaths exactly, a live
//! consumer acts on them at once. Everything is causal and allocation-free after `new`.

mod config;

pub use config::{PhraseConfig, PhraseError};

use crate::analysis::noise_floor::NoiseFloor;
use crate::analysis::{BandLevels, FeatureFrame};

/// A pause before a phrase, reported with the onset that ends it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pause {
    /// Start of the pause (offset of the previous phrase; 0 for the silence that leads into the
    /// first phrase of the stream), seconds.
    pub start_s: f64,
    /// End of the pause (onset of the new phrase), seconds.
    pub end_s: f64,
    /// True for the silence before the first phrase of the stream (not a pause between
    /// phrases).
    pub leading: bool,
    /// True when a breath-like noise burst was heard inside the pause.
    pub has_breath: bool,
    /// The last breath-like burst heard inside the pause (start, end), seconds; `Some` exactly
    /// when `has_breath`.
    pub breath_s: Option<(f64, f64)>,
    /// End of the last activity inside the pause that did not become a phrase (a noise burst, a
    /// word too short to confirm), seconds; `None` when the pause was quiet. Nothing should be
    /// placed over it.
    pub last_activity_end_s: Option<f64>,
}

impl Pause {
    /// Length of the pause in seconds.
    pub fn length_s(&self) -> f64 {
        self.end_s - self.start_s
    }
}

/// What the tracker learned at one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PhraseEvent {
    /// Something active began in a pause (reported at once, before it is known to be speech):
    /// a live consumer fades out what it plays into the pause.
    Activity {
        /// Time of the first active frame, seconds.
        time_s: f64,
    },
    /// A phrase started at `onset_s`, ending `pause`.
    Start {
        /// Onset time, seconds (in the past of the frame that reports it).
        onset_s: f64,
        /// The pause that ended here.
        pause: Pause,
    },
    /// The phrase that started at `onset_s` ended at `offset_s` (confirmed after the hangover).
    End {
        /// Onset of the phrase, seconds.
        onset_s: f64,
        /// Offset of the phrase, seconds.
        offset_s: f64,
    },
}

/// Per-frame facts kept in the history ring.
#[derive(Debug, Clone, Copy, Default)]
struct FrameFacts {
    active: bool,
    over_floor: bool,
    voiced: bool,
    /// The voice-band level the decisions use, dBFS.
    level_db: f32,
    /// Over the floor by `breath_margin_db` (and not silence): loud enough for a breath run.
    breath_level: bool,
    /// The frame's high band over its mid band, dB ([`crate::analysis::BandLevels`]).
    high_over_mid_db: f32,
    /// The frame's low band over its mid band, dB.
    low_over_mid_db: f32,
}

/// How far a breath run's level must rise over its lowest point to be more than a reverberant
/// tail when it starts at the phrase's offset, dB.
const BREATH_RISE_DB: f32 = 3.0;

/// A frame within this of the noise floor teaches the room's band levels, dB.
const FLOOR_BAND_WITHIN_DB: f32 = 3.0;
/// ... and at least this far under the running speech level, dB (at the start of a stream the
/// floor still sits at the voice).
const FLOOR_BAND_UNDER_SPEECH_DB: f32 = 20.0;
/// Time constant of the room's band levels, seconds.
const FLOOR_BAND_TAU_S: f64 = 1.0;

/// The room's band powers (an exponential average over frames at the noise floor) and the shape
/// of a frame's band powers above them.
#[derive(Debug, Clone, Copy, Default)]
struct FloorBands {
    /// Mean power of the low, mid and high band at the floor (linear, full scale = 1).
    power: [f64; 3],
    /// Frames learnt so far (the first ones set the mean directly).
    learnt: u32,
}

impl FloorBands {
    fn powers(b: &BandLevels) -> [f64; 3] {
        [b.low_db, b.mid_db, b.high_db].map(|db| {
            if db.is_finite() {
                10f64.powf(f64::from(db.clamp(-120.0, 40.0)) / 10.0)
            } else {
                0.0
            }
        })
    }

    fn learn(&mut self, b: &BandLevels, weight: f64) {
        let p = Self::powers(b);
        self.learnt = self.learnt.saturating_add(1);
        let w = weight.max(1.0 / f64::from(self.learnt));
        for (m, v) in self.power.iter_mut().zip(p) {
            *m += w * (v - *m);
        }
    }

    /// (high over mid, low over mid) of the frame's band powers with the room's taken out
    /// (never below a tenth of the frame's own power), dB, within ±40 dB so one odd frame
    /// cannot swing a run's mean.
    fn excess_shape_db(&self, b: &BandLevels) -> (f32, f32) {
        let p = Self::powers(b);
        let e: [f64; 3] = std::array::from_fn(|k| (p[k] - self.power[k]).max(0.1 * p[k]));
        let ratio = |a: f64, m: f64| {
            if a > 0.0 && m > 0.0 {
                (10.0 * (a / m).log10()).clamp(-40.0, 40.0) as f32
            } else {
                0.0
            }
        };
        (ratio(e[2], e[1]), ratio(e[0], e[1]))
    }
}

/// Number of half-second blocks the noise floor looks back over.
const FLOOR_BLOCKS: usize = 6;
/// Length of one block of the noise floor's minimum ring, seconds.
const FLOOR_BLOCK_S: f32 = 0.5;

/// The phrase tracker. Feed it every feature frame in order with [`PhraseTracker::update`].
#[derive(Debug, Clone)]
pub struct PhraseTracker {
    config: PhraseConfig,
    frame_rate_hz: f64,
    // Frame counts derived from the config.
    onset_voiced_frames: u32,
    hangover_frames: u64,
    edge_frames: u64,
    offset_frames: u64,
    breath_min_frames: u32,
    run_gap_frames: u64,
    /// Noise floor (minimum statistics) and its latest value, dBFS.
    floor: NoiseFloor,
    floor_db: f32,
    // History ring of the last `history.len()` frames.
    history: Vec<FrameFacts>,
    frames_seen: u64,
    // Phrase state.
    in_phrase: bool,
    onset_index: u64,
    last_active_index: u64,
    last_offset_index: Option<u64>,
    candidate_start: Option<u64>,
    candidate_last_active: u64,
    candidate_voiced: u32,
    /// Last active frame of a run in this pause that did not become a phrase.
    pause_last_active: Option<u64>,
    // Breath detection inside the current pause.
    breath_run: u32,
    breath_run_start: u64,
    /// The run continues the phrase's decay (it starts at the offset): a reverberant tail
    /// unless its level rises again.
    breath_run_from_tail: bool,
    /// Lowest level of the run so far, dBFS.
    breath_run_min_db: f32,
    /// The run's level rose [`BREATH_RISE_DB`] over its lowest point.
    breath_run_rose: bool,
    /// Sums over the run of its frames' high-over-mid and low-over-mid band levels, dB.
    breath_run_high_sum: f32,
    breath_run_low_sum: f32,
    /// The room's band levels.
    floor_bands: FloorBands,
    /// Weight of one frame in the room's band levels (from [`FLOOR_BAND_TAU_S`]).
    floor_band_weight: f64,
    /// Frames (start, end) of the last breath run long enough to count, in this pause.
    breath_span: Option<(u64, u64)>,
    breath_seen: bool,
}

impl PhraseTracker {
    /// Creates a tracker for frames at `frame_rate_hz`.
    pub fn new(config: PhraseConfig, frame_rate_hz: f64) -> Result<Self, PhraseError> {
        config.validate()?;
        if !(frame_rate_hz.is_finite() && (10.0..=1000.0).contains(&frame_rate_hz)) {
            return Err(PhraseError::FrameRate(frame_rate_hz));
        }
        let frames = |s: f32| ((s as f64) * frame_rate_hz).round().max(1.0) as u64;
        let edge_frames = frames(config.edge_extend_s);
        let frames = |s: f32| ((s as f64) * frame_rate_hz).round() as u64;
        let hangover_frames = frames(config.hangover_s);
        let history_len = (edge_frames.max(hangover_frames) + frames(1.0)) as usize;
        let frames = |s: f32| ((s as f64) * frame_rate_hz).round().max(1.0) as u64;
        let mut t = Self {
            onset_voiced_frames: frames(config.onset_voiced_s) as u32,
            hangover_frames,
            edge_frames,
            offset_frames: frames(config.offset_extend_s),
            breath_min_frames: frames(config.breath_min_s) as u32,
            run_gap_frames: frames(config.run_gap_s),
            floor: NoiseFloor::with_blocks(frames(FLOOR_BLOCK_S) as usize, FLOOR_BLOCKS),
            config,
            frame_rate_hz,
            floor_db: f32::NEG_INFINITY,
            history: vec![FrameFacts::default(); history_len],
            frames_seen: 0,
            in_phrase: false,
            onset_index: 0,
            last_active_index: 0,
            last_offset_index: None,
            candidate_start: None,
            candidate_last_active: 0,
            candidate_voiced: 0,
            pause_last_active: None,
            breath_run: 0,
            breath_run_start: 0,
            breath_run_from_tail: false,
            breath_run_min_db: 0.0,
            breath_run_rose: false,
            breath_run_high_sum: 0.0,
            breath_run_low_sum: 0.0,
            breath_span: None,
            breath_seen: false,
            floor_bands: FloorBands::default(),
            floor_band_weight: 1.0 / (FLOOR_BAND_TAU_S * frame_rate_hz).max(1.0),
        };
        t.reset();
        Ok(t)
    }

    /// Clears all state (start of a new stream).
    pub fn reset(&mut self) {
        self.floor.reset();
        self.floor_db = f32::NEG_INFINITY;
        self.floor_bands = FloorBands::default();
        self.history
            .iter_mut()
            .for_each(|f| *f = FrameFacts::default());
        self.frames_seen = 0;
        self.in_phrase = false;
        self.onset_index = 0;
        self.last_active_index = 0;
        self.last_offset_index = None;
        self.candidate_start = None;
        self.candidate_last_active = 0;
        self.candidate_voiced = 0;
        self.pause_last_active = None;
        self.breath_run = 0;
        self.breath_seen = false;
        self.breath_span = None;
    }

    /// The settings.
    pub fn config(&self) -> &PhraseConfig {
        &self.config
    }

    /// The current noise-floor estimate in dBFS (−∞ before the first frame).
    pub fn noise_floor_db(&self) -> f32 {
        self.floor_db
    }

    /// True while inside a phrase (between a confirmed onset and a confirmed offset).
    pub fn in_phrase(&self) -> bool {
        self.in_phrase
    }

    /// How far in the past (seconds) an event may refer at most when it is reported: the
    /// hangover for offsets, the onset confirmation plus the edge extension for onsets.
    pub fn max_report_delay_s(&self) -> f64 {
        let onset = self.edge_frames + self.run_gap_frames * 4 + self.onset_voiced_frames as u64;
        onset.max(self.hangover_frames) as f64 / self.frame_rate_hz
    }

    fn time_s(&self, index: u64) -> f64 {
        index as f64 / self.frame_rate_hz
    }

    fn facts(&self, index: u64) -> FrameFacts {
        self.history[(index % self.history.len() as u64) as usize]
    }

    /// Feeds one frame (in order). Calls `on_event` for what became certain at this frame: at
    /// most an end, an activity and a start.
    pub fn update(&mut self, frame: &FeatureFrame, mut on_event: impl FnMut(PhraseEvent)) {
        let c = self.config;
        // Decisions use the voice-band level (rumble stays out); the speech level comes from
        // the full-band level and its speaker-relative value.
        let rms_db = if frame.band_db.is_finite() {
            frame.band_db
        } else {
            -120.0
        };
        self.floor_db = self.floor.update(Some(rms_db));
        let speech_level_db = if frame.level_db.is_finite() && frame.rms_db.is_finite() {
            frame.rms_db - frame.level_db
        } else {
            rms_db
        };
        let over_floor = rms_db >= self.floor_db + c.edge_margin_db && rms_db > c.silence_db;
        let loud = rms_db >= self.floor_db + c.activity_margin_db
            && rms_db >= speech_level_db - c.unvoiced_drop_db
            && rms_db > c.silence_db;
        let voiced = frame.voiced && rms_db > c.silence_db;
        let active = voiced || loud;
        let breath_level = rms_db >= self.floor_db + c.breath_margin_db && rms_db > c.silence_db;
        // The room's own band levels, learnt on frames at the floor, are taken out of the
        // frame's band powers: what is left is the shape of the sound over the room.
        if !voiced
            && rms_db <= self.floor_db + FLOOR_BAND_WITHIN_DB
            && rms_db <= speech_level_db - FLOOR_BAND_UNDER_SPEECH_DB
        {
            self.floor_bands.learn(&frame.bands, self.floor_band_weight);
        }
        let (high_over_mid_db, low_over_mid_db) = self.floor_bands.excess_shape_db(&frame.bands);
        let i = self.frames_seen;
        let len = self.history.len() as u64;
        self.history[(i % len) as usize] = FrameFacts {
            active,
            over_floor,
            voiced,
            level_db: rms_db,
            breath_level,
            high_over_mid_db,
            low_over_mid_db,
        };
        self.frames_seen += 1;

        if self.in_phrase {
            if active {
                self.last_active_index = i;
            } else if i - self.last_active_index >= self.hangover_frames {
                // The phrase ended: extend the offset forward over a decaying tail.
                let mut offset = self.last_active_index + 1;
                while offset < i
                    && offset - self.last_active_index <= self.offset_frames
                    && self.facts(offset).over_floor
                {
                    offset += 1;
                }
                self.in_phrase = false;
                self.last_offset_index = Some(offset);
                self.candidate_start = None;
                self.candidate_voiced = 0;
                self.pause_last_active = None;
                // Breath detection restarts from the offset (frames since are in the ring).
                self.breath_run = 0;
                self.breath_seen = false;
                self.breath_span = None;
                for k in offset..=i {
                    self.track_breath(k);
                }
                on_event(PhraseEvent::End {
                    onset_s: self.time_s(self.onset_index),
                    offset_s: self.time_s(offset),
                });
            }
            return;
        }

        // In a pause: look for a candidate phrase.
        if active {
            if self.candidate_start.is_none() {
                self.candidate_start = Some(i);
                self.candidate_voiced = 0;
                on_event(PhraseEvent::Activity {
                    time_s: self.time_s(i),
                });
            }
            self.candidate_last_active = i;
            if voiced {
                self.candidate_voiced += 1;
            }
        } else if let Some(_start) = self.candidate_start {
            if i - self.candidate_last_active > self.run_gap_frames {
                // The run died out without enough voicing: noise or a word too short to
                // confirm. Nothing may be placed over it.
                self.pause_last_active = Some(self.candidate_last_active);
                self.candidate_start = None;
                self.candidate_voiced = 0;
            }
        }
        if self.candidate_start.is_none() {
            self.track_breath(i);
        }
        if let Some(start) = self.candidate_start {
            if self.candidate_voiced >= self.onset_voiced_frames {
                // A phrase starts: move the onset back over a quiet consonant.
                let limit = self
                    .last_offset_index
                    .unwrap_or(0)
                    .max(self.pause_last_active.map_or(0, |k| k + 1))
                    .max(start.saturating_sub(self.edge_frames))
                    .max(i.saturating_sub(len - 1));
                let mut onset = start;
                while onset > limit && self.facts(onset - 1).over_floor {
                    onset -= 1;
                }
                // A breath run still going counts only with the part before the onset.
                let running = self.breath_run > 0
                    && self.breath_run_counts()
                    && onset.saturating_sub(self.breath_run_start) >= self.breath_min_frames as u64;
                let has_breath = self.breath_seen || running;
                let span = if running {
                    Some((self.breath_run_start, onset))
                } else {
                    self.breath_span
                };
                let breath_s = span
                    .filter(|_| has_breath)
                    .map(|(a, b)| (self.time_s(a), self.time_s(b)));
                debug_assert_eq!(breath_s.is_some(), has_breath, "a breath has its span");
                let pause = Pause {
                    start_s: self.time_s(self.last_offset_index.unwrap_or(0)),
                    end_s: self.time_s(onset),
                    leading: self.last_offset_index.is_none(),
                    has_breath,
                    breath_s,
                    last_activity_end_s: self.pause_last_active.map(|k| self.time_s(k + 1)),
                };
                self.in_phrase = true;
                self.onset_index = onset;
                self.last_active_index = i;
                self.candidate_start = None;
                self.pause_last_active = None;
                on_event(PhraseEvent::Start {
                    onset_s: self.time_s(onset),
                    pause,
                });
            }
        }
    }

    /// A run of breath-like frames counts as a breath when it has a breath's spectral shape
    /// (mean band balance within the configured limits) and does not only continue the
    /// phrase's decay: a reverberant tail falls from the offset on, an inhalation after it
    /// rises again.
    fn breath_run_counts(&self) -> bool {
        let n = self.breath_run.max(1) as f32;
        let c = &self.config;
        let high = self.breath_run_high_sum / n;
        let shaped = high <= c.breath_max_high_over_mid_db
            && self.breath_run_low_sum / n <= c.breath_max_low_over_mid_db;
        shaped && (!self.breath_run_from_tail || self.breath_run_rose)
    }

    fn track_breath(&mut self, index: u64) {
        let f = self.facts(index);
        if f.breath_level && !f.voiced && !f.active {
            if self.breath_run == 0 {
                self.breath_run_start = index;
                self.breath_run_from_tail = self.last_offset_index == Some(index);
                self.breath_run_min_db = f.level_db;
                self.breath_run_rose = false;
                self.breath_run_high_sum = 0.0;
                self.breath_run_low_sum = 0.0;
            }
            self.breath_run += 1;
            self.breath_run_high_sum += f.high_over_mid_db;
            self.breath_run_low_sum += f.low_over_mid_db;
            self.breath_run_min_db = self.breath_run_min_db.min(f.level_db);
            if f.level_db >= self.breath_run_min_db + BREATH_RISE_DB {
                self.breath_run_rose = true;
            }
        } else {
            if self.breath_run >= self.breath_min_frames && self.breath_run_counts() {
                self.breath_seen = true;
                self.breath_span = Some((self.breath_run_start, index));
            }
            self.breath_run = 0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(index: u64, rms_db: f32, voiced: bool) -> FeatureFrame {
        FeatureFrame {
            index,
            time_s: index as f64 / 100.0,
            f0_hz: if voiced { 150.0 } else { 0.0 },
            voiced,
            voicing: if voiced { 0.9 } else { 0.2 },
            rms_db,
            f0_st: 0.0,
            level_db: rms_db - -20.0,
            band_db: rms_db,
            bands: breathy(rms_db),
        }
    }

    /// Band levels of broadband breath noise at `rms_db`: most energy in the mid band.
    fn breathy(rms_db: f32) -> BandLevels {
        BandLevels {
            low_db: rms_db - 12.0,
            mid_db: rms_db - 1.5,
            high_db: rms_db - 6.0,
        }
    }

    /// Runs a scripted level/voicing sequence at 100 frames/s and collects the start and end
    /// events.
    fn run(script: &[(usize, f32, bool)]) -> Vec<PhraseEvent> {
        run_all(script)
            .into_iter()
            .filter(|e| !matches!(e, PhraseEvent::Activity { .. }))
            .collect()
    }

    /// All events, activity included.
    fn run_all(script: &[(usize, f32, bool)]) -> Vec<PhraseEvent> {
        let mut t = PhraseTracker::new(PhraseConfig::default(), 100.0).unwrap();
        let mut events = Vec::new();
        let mut i = 0u64;
        for &(n, db, v) in script {
            for _ in 0..n {
                t.update(&frame(i, db, v), |e| events.push(e));
                i += 1;
            }
        }
        events
    }

    #[test]
    fn two_phrases_give_start_end_start_with_the_pause() {
        let ev = run(&[
            (100, -70.0, false),
            (150, -20.0, true),
            (60, -70.0, false),
            (150, -20.0, true),
            (100, -70.0, false),
        ]);
        assert_eq!(ev.len(), 4, "{ev:?}");
        match ev[0] {
            PhraseEvent::Start { onset_s, pause } => {
                assert!((onset_s - 1.0).abs() < 0.011, "{onset_s}");
                assert!(pause.leading && pause.start_s == 0.0);
            }
            _ => panic!("{ev:?}"),
        }
        match ev[2] {
            PhraseEvent::Start { onset_s, pause } => {
                let p = pause;
                assert!(!p.leading && p.last_activity_end_s.is_none());
                assert!((onset_s - 3.1).abs() < 0.011, "{onset_s}");
                assert!((p.start_s - 2.5).abs() < 0.011, "{p:?}");
                assert!((p.length_s() - 0.6).abs() < 0.021, "{p:?}");
                assert!(!p.has_breath);
                assert_eq!(p.breath_s, None);
            }
            _ => panic!("{ev:?}"),
        }
    }

    #[test]
    fn a_short_dip_inside_a_phrase_is_not_a_pause() {
        let ev = run(&[
            (100, -70.0, false),
            (100, -20.0, true),
            (8, -70.0, false),
            (100, -20.0, true),
            (100, -70.0, false),
        ]);
        assert_eq!(ev.len(), 2, "{ev:?}");
    }

    #[test]
    fn unvoiced_noise_bursts_do_not_start_phrases_but_count_as_breath() {
        let ev = run(&[
            (100, -70.0, false),
            (100, -20.0, true),
            (40, -70.0, false),
            (35, -48.0, false), // breath-like: 22 dB under speech, 22 dB over the floor
            (30, -70.0, false),
            (100, -20.0, true),
            (50, -70.0, false),
        ]);
        let starts: Vec<_> = ev
            .iter()
            .filter_map(|e| match e {
                PhraseEvent::Start { pause, .. } => Some(*pause),
                _ => None,
            })
            .collect();
        assert_eq!(starts.len(), 2, "{ev:?}");
        assert!(starts[1].has_breath, "{ev:?}");
        // Its span: the burst's frames 240..275.
        let (start_s, end_s) = starts[1].breath_s.expect("the breath's span");
        assert!(
            (start_s - 2.40).abs() < 0.021 && (end_s - 2.75).abs() < 0.021,
            "breath at {start_s}..{end_s} s, want 2.40..2.75"
        );
        assert_eq!(
            starts[0].breath_s, None,
            "no breath before the first phrase"
        );
    }

    /// The pauses' `breath_s` of a script's phrase starts.
    fn breaths_of(script: &[(usize, f32, bool)]) -> Vec<Option<(f64, f64)>> {
        run(script)
            .iter()
            .filter_map(|e| match e {
                PhraseEvent::Start { pause, .. } => Some(pause.breath_s),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn a_reverberant_tail_is_not_a_breath_but_a_rise_after_it_is() {
        // A phrase whose sound decays over 0.6 s (3 dB per 50 ms, unvoiced) into the pause.
        let tail: Vec<(usize, f32, bool)> =
            (0..8).map(|k| (5, -42.0 - 3.0 * k as f32, false)).collect();
        let mut only_tail = vec![(100, -70.0, false), (100, -20.0, true)];
        only_tail.extend(&tail);
        only_tail.extend([(40, -70.0, false), (100, -20.0, true), (50, -70.0, false)]);
        assert_eq!(
            breaths_of(&only_tail),
            [None, None],
            "a tail heard as a breath"
        );
        // The same tail, then noise rising again 8 dB before the next phrase: an inhalation.
        let mut tail_then_breath = vec![(100, -70.0, false), (100, -20.0, true)];
        tail_then_breath.extend(&tail);
        tail_then_breath.extend([
            (25, -55.0, false),
            (5, -70.0, false),
            (100, -20.0, true),
            (50, -70.0, false),
        ]);
        let b = breaths_of(&tail_then_breath);
        assert!(b[1].is_some(), "the rise after the tail is a breath: {b:?}");
    }

    /// The pauses' `breath_s` of a script whose unvoiced frames between `from` and `to`
    /// (frame numbers) carry `bands` instead of breath-like band levels.
    fn breaths_with_bands(
        script: &[(usize, f32, bool)],
        (from, to): (u64, u64),
        bands: impl Fn(f32) -> BandLevels,
    ) -> Vec<Option<(f64, f64)>> {
        let mut t = PhraseTracker::new(PhraseConfig::default(), 100.0).unwrap();
        let mut out = Vec::new();
        let mut i = 0u64;
        for &(n, db, v) in script {
            for _ in 0..n {
                let mut f = frame(i, db, v);
                if (from..to).contains(&i) {
                    f.bands = bands(db);
                }
                t.update(&f, |e| {
                    if let PhraseEvent::Start { pause, .. } = e {
                        out.push(pause.breath_s);
                    }
                });
                i += 1;
            }
        }
        out
    }

    #[test]
    fn a_burst_shaped_like_a_sibilant_or_a_vowel_tail_is_no_breath() {
        // The breath-like burst of frames 240..275 (22 dB under speech) of the test above.
        let script = [
            (100, -70.0, false),
            (100, -20.0, true),
            (40, -70.0, false),
            (35, -48.0, false),
            (30, -70.0, false),
            (100, -20.0, true),
            (50, -70.0, false),
        ];
        let burst = (240, 275);
        assert!(breaths_with_bands(&script, burst, breathy)[1].is_some());
        // /s/: the high band 10 dB over the mid band.
        let sibilant = |db: f32| BandLevels {
            low_db: db - 25.0,
            mid_db: db - 10.0,
            high_db: db - 0.5,
        };
        assert_eq!(breaths_with_bands(&script, burst, sibilant)[1], None);
        // A vowel's tail or rumble: the low band 8 dB over the mid band.
        let low = |db: f32| BandLevels {
            low_db: db - 0.5,
            mid_db: db - 8.5,
            high_db: db - 20.0,
        };
        assert_eq!(breaths_with_bands(&script, burst, low)[1], None);
    }

    #[test]
    fn a_quiet_initial_consonant_moves_the_onset_back() {
        let ev = run(&[
            (100, -70.0, false),
            (10, -45.0, false), // an /f/ 25 dB under speech
            (100, -20.0, true),
            (50, -70.0, false),
        ]);
        match ev[0] {
            PhraseEvent::Start { onset_s, .. } => assert!((onset_s - 1.0).abs() < 0.011),
            _ => panic!("{ev:?}"),
        }
    }

    #[test]
    fn a_loud_unvoiced_burst_in_a_pause_is_reported_and_bounds_the_pause() {
        let ev = run_all(&[
            (100, -70.0, false),
            (100, -20.0, true),
            (30, -70.0, false),
            (8, -22.0, false), // a click or a word too short to confirm, at 2.3 s
            (40, -70.0, false),
            (100, -20.0, true),
            (50, -70.0, false),
        ]);
        let activity: Vec<f64> = ev
            .iter()
            .filter_map(|e| match e {
                PhraseEvent::Activity { time_s } => Some(*time_s),
                _ => None,
            })
            .collect();
        assert!(activity.iter().any(|t| (t - 2.3).abs() < 0.011), "{ev:?}");
        let last = ev
            .iter()
            .rev()
            .find_map(|e| match e {
                PhraseEvent::Start { pause, .. } => Some(*pause),
                _ => None,
            })
            .unwrap();
        let end = last.last_activity_end_s.expect("the burst is reported");
        assert!((end - 2.38).abs() < 0.011, "{last:?}");
    }

    #[test]
    fn a_breath_before_the_first_phrase_is_seen() {
        let ev = run(&[
            (50, -70.0, false),
            (35, -48.0, false),
            (30, -70.0, false),
            (100, -20.0, true),
            (30, -70.0, false),
        ]);
        match ev[0] {
            PhraseEvent::Start { pause, .. } => assert!(pause.leading && pause.has_breath),
            _ => panic!("{ev:?}"),
        }
    }

    #[test]
    fn nan_levels_are_silence() {
        let ev = run(&[
            (100, f32::NAN, false),
            (100, -20.0, true),
            (50, f32::NAN, false),
        ]);
        assert_eq!(ev.len(), 2, "{ev:?}");
    }
}
