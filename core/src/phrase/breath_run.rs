//! Breaths already in a pause: runs of breath-like frames (unvoiced, over the floor by the
//! breath margin, not active), judged by their length, their spectral shape over the room, how
//! noise-like they are (not a music bed's tones, [`BREATH_MIN_FLATNESS`]) and,
//! when a run starts at the phrase's offset, by rising over its lowest point, in the voice band or
//! in the breath's own bands (a reverberant tail only falls; in a room whose hum carries the voice
//! band's level a breath rises little there, as it adds little to it).
//!
//! Two runs are followed side by side: a *strict* one of frames over the breath margin, and a
//! *held* one that starts as the strict one does but carries on through frames over a share of
//! the margin ([`BREATH_HOLD_SHARE`]). In a noisy room a breath a few dB over the room dips
//! under the margin now and then, and its strict runs are too short to count. A pause's breath
//! is its strict run; when none counts, its held run still marks a breath already there
//! (nothing is inserted over it), but the breath voice does not learn from it: a held run's
//! edges hold more room than breath. A held run that starts while the phrase's decay is open
//! ([`TAIL_CLOSED_S`]) never counts: its dips would let a tail's ripple pass for a rise.

use super::facts::FrameFacts;

/// How far a breath run's level must rise over its lowest point to be more than a reverberant
/// tail when it starts at the phrase's offset, dB.
const BREATH_RISE_DB: f32 = 3.0;

/// Share of the breath margin a frame must keep to carry on a breath run that has begun: a
/// breath a few dB over a noisy room dips under the margin now and then, and a run cut at every
/// dip is never long enough to count (half the margin: 3 dB at the default 6 dB).
pub(super) const BREATH_HOLD_SHARE: f32 = 0.5;
/// How long the level must stay under the hold after a phrase's offset before a held run that
/// starts is no longer the phrase's decay, seconds: a tail's ripple dips under the hold for a
/// frame or two and comes back.
pub(super) const TAIL_CLOSED_S: f32 = 0.025;
/// Lowest mean spectral flatness of the mid band ([`crate::analysis::BandLevels::mid_flatness`])
/// over a run that is a breath: an inhalation is noise, while a music bed under the voice that
/// swells in a pause, a chord or a sung note is tonal. The 56 clear labelled inhalations of the
/// Keele and styletalk clips read 0.28 to 0.57 as runs (median 0.38; white noise 0.56), a
/// string bed's swells in a restored voice's pauses 0.06 to 0.12. A breath partly masked by a
/// tonal bed reads between the two, and a breath the rule misses is one inserted over it: so
/// the limit sits low, at 0.1 (0.2 lost 13 of the labelled real breaths `eval podcast` heard
/// under beds and drones; see `docs/measurements.md`, 7 December 2026).
pub(super) const BREATH_MIN_FLATNESS: f32 = 0.1;
/// How long a strict run must have lasted to be a breath under way, seconds: a breath's noise
/// is sustained, a click or a lip smack lasts a frame or two. Live mode starts no inserted
/// breath over one (it would double a real breath the detector has not confirmed yet).
pub const BREATH_UNDER_WAY_S: f32 = 0.03;

/// What makes a run a breath (from the tracker's settings).
#[derive(Debug, Clone, Copy)]
pub(super) struct BreathRules {
    /// Shortest run that counts, frames.
    pub(super) min_frames: u32,
    /// Shortest strict run that is a breath under way ([`BREATH_UNDER_WAY_S`]), frames.
    pub(super) under_way_frames: u32,
    /// Frames under the hold after the offset that close the phrase's decay
    /// ([`TAIL_CLOSED_S`]).
    pub(super) tail_closed_frames: u32,
    /// Highest mean high-over-mid and low-over-mid band level of the run, dB.
    pub(super) max_high_over_mid_db: f32,
    pub(super) max_low_over_mid_db: f32,
    /// Lowest mean mid-band flatness of a breath run ([`BREATH_MIN_FLATNESS`]).
    pub(super) min_flatness: f32,
}

/// The run of breath-like frames going on.
#[derive(Debug, Clone, Copy, Default)]
struct BreathRun {
    /// Frames in the run (0 = none going on).
    frames: u32,
    /// Its first frame.
    start: u64,
    /// The run continues the phrase's decay (it starts at the offset): a reverberant tail
    /// unless its level rises again.
    from_tail: bool,
    /// Lowest level of the run so far, in the voice band and in the breath bands, dBFS.
    min_db: f32,
    min_bands_db: f32,
    /// The run's level rose [`BREATH_RISE_DB`] over its lowest point (in either band).
    rose: bool,
    /// Sums over the run of its frames' high-over-mid and low-over-mid band levels, dB, and
    /// of their mid-band flatness.
    high_sum: f32,
    low_sum: f32,
    flat_sum: f32,
    /// The first active frame heard while the run went on (an unvoiced blip it spans).
    blip: Option<u64>,
}

impl BreathRun {
    /// A run counts as a breath when it has a breath's spectral shape (mean band balance
    /// within the limits) and does not only continue the phrase's decay: a reverberant tail
    /// falls from the offset on, an inhalation after it rises again.
    /// A `held` run (see the module docs) never continues the decay: its dips would let a
    /// tail's ripple pass for a rise.
    fn counts(&self, rules: &BreathRules, held: bool) -> bool {
        let low = self.low_sum / self.frames.max(1) as f32;
        self.noise_not_fricative(rules) && low <= rules.max_low_over_mid_db && self.past_tail(held)
    }

    /// The run's mean high band over its mid band lies within the breath's limit (/s/, /ʃ/ and
    /// /f/ lie far over it), and it is noise, not tones ([`BREATH_MIN_FLATNESS`]).
    fn noise_not_fricative(&self, rules: &BreathRules) -> bool {
        let n = self.frames.max(1) as f32;
        self.high_sum / n <= rules.max_high_over_mid_db && self.flat_sum / n >= rules.min_flatness
    }

    /// The run does not only continue the phrase's decay (see [`BreathRun::counts`]).
    fn past_tail(&self, held: bool) -> bool {
        !self.from_tail || (self.rose && !held)
    }
}

/// One kind of breath run of the current pause: the one going on and the last one that counted.
#[derive(Debug, Clone, Copy, Default)]
struct RunTrack {
    /// The held kind (see the module docs).
    held: bool,
    run: BreathRun,
    /// The last breath run long enough to count, in this pause: frames (start, end), and its
    /// first blip if it spans one.
    counted: Option<((u64, u64), Option<u64>)>,
}

/// The breath runs of the current pause, strict and held (see the module docs).
#[derive(Debug, Clone, Copy)]
pub(super) struct PauseBreaths {
    strict: RunTrack,
    held: RunTrack,
    /// Frames in a row under the hold since the offset, until the decay is closed (`None`).
    tail_quiet: Option<u32>,
}

impl Default for PauseBreaths {
    fn default() -> Self {
        Self {
            strict: RunTrack::default(),
            held: RunTrack {
                held: true,
                ..RunTrack::default()
            },
            tail_quiet: None,
        }
    }
}

/// A breath heard in a pause, as frames (start, end).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct HeardRun {
    /// The breath.
    pub(super) span: (u64, u64),
    /// The part of it before its first blip (an active frame it spans), when long enough to
    /// count: a voice learns from this part only, as a blip's power would outweigh the breath's
    /// in the span's mean.
    pub(super) clean: Option<(u64, u64)>,
}

impl RunTrack {
    fn restart(&mut self) {
        self.run.frames = 0;
        self.counted = None;
    }

    fn blip(&mut self, index: u64) {
        if self.run.frames > 0 && self.run.blip.is_none() {
            self.run.blip = Some(index);
        }
    }

    /// Takes frame `index` with its facts `f`; `loud` when its level carries this kind of run,
    /// `in_tail` when a run starting at it continues the phrase's decay.
    fn track(
        &mut self,
        index: u64,
        f: FrameFacts,
        (loud, in_tail): (bool, bool),
        rules: &BreathRules,
    ) {
        let run = &mut self.run;
        if loud && !f.voiced && !f.active {
            if run.frames == 0 {
                run.start = index;
                run.from_tail = in_tail;
                run.min_db = f.level_db;
                run.min_bands_db = f.breath_bands_db;
                run.rose = false;
                run.high_sum = 0.0;
                run.low_sum = 0.0;
                run.flat_sum = 0.0;
                run.blip = None;
            }
            run.frames += 1;
            run.high_sum += f.high_over_mid_db;
            run.low_sum += f.low_over_mid_db;
            run.flat_sum += f.mid_flatness;
            run.min_db = run.min_db.min(f.level_db);
            run.min_bands_db = run.min_bands_db.min(f.breath_bands_db);
            if f.level_db >= run.min_db + BREATH_RISE_DB
                || f.breath_bands_db >= run.min_bands_db + BREATH_RISE_DB
            {
                run.rose = true;
            }
        } else {
            self.close(index, rules);
        }
    }

    fn close(&mut self, index: u64, rules: &BreathRules) {
        let run = &mut self.run;
        if run.frames >= rules.min_frames && run.counts(rules, self.held) {
            self.counted = Some(((run.start, index), run.blip));
        }
        run.frames = 0;
    }

    /// A breath counted in this pause, or the run going on counts already.
    fn heard_so_far(&self, rules: &BreathRules) -> bool {
        self.counted.is_some() || self.counting(rules)
    }

    /// A run is going on, long enough to be under way, not only the phrase's decay, noise and
    /// not a fricative (its mean high band over its mid band within the breath's limit: /s/,
    /// /ʃ/ and /f/ before a word lie far over it). The low band is not asked for: a run's shape is
    /// its mean from its first frame, and a breath's first frames (a nasal onset, the room's
    /// hum under it) often hold it over that limit for a tenth of a second or more.
    fn under_way(&self, rules: &BreathRules) -> bool {
        let run = &self.run;
        run.frames >= rules.under_way_frames
            && run.noise_not_fricative(rules)
            && run.past_tail(self.held)
    }

    /// The run going on counts as a breath already (its length and shape).
    fn counting(&self, rules: &BreathRules) -> bool {
        self.run.frames >= rules.min_frames && self.run.counts(rules, self.held)
    }

    fn at_onset(&self, onset: u64, rules: &BreathRules) -> Option<HeardRun> {
        let run = &self.run;
        let min = rules.min_frames as u64;
        let (span, blip) = if run.frames > 0
            && run.counts(rules, self.held)
            && onset.saturating_sub(run.start) >= min
        {
            ((run.start, onset), run.blip)
        } else {
            let ((a, b), blip) = self.counted?;
            ((a, b.min(onset)), blip)
        };
        let long_enough = |&(a, b): &(u64, u64)| b >= a + min;
        long_enough(&span).then(|| HeardRun {
            span,
            clean: Some((span.0, blip.map_or(span.1, |k| k.min(span.1)))).filter(long_enough),
        })
    }
}

impl PauseBreaths {
    /// A new pause: nothing heard yet.
    pub(super) fn restart(&mut self) {
        self.strict.restart();
        self.held.restart();
        self.tail_quiet = Some(0);
    }

    /// An active frame at `index` (a candidate phrase starts on it): a run going on spans a blip
    /// if it resumes after it.
    pub(super) fn blip(&mut self, index: u64) {
        self.strict.blip(index);
        self.held.blip(index);
    }

    /// Takes frame `index` with its facts `f`; `last_offset` is the frame the pause began at
    /// (`None` before the first phrase).
    pub(super) fn track(
        &mut self,
        index: u64,
        f: FrameFacts,
        last_offset: Option<u64>,
        rules: &BreathRules,
    ) {
        let at_offset = last_offset == Some(index);
        self.strict
            .track(index, f, (f.breath_level, at_offset), rules);
        // The held run starts where a strict one would, and carries on through the dips. While
        // the phrase's decay is open (from the offset until the level has stayed under the hold
        // for `tail_closed_frames`), a held run that starts is the decay's own: it may start
        // under the margin, and never counts.
        let in_tail = self.tail_quiet.is_some() || at_offset;
        self.tail_quiet = match self.tail_quiet {
            Some(n) if !f.breath_held => Some(n + 1).filter(|&n| n < rules.tail_closed_frames),
            other => other.map(|_| 0),
        };
        let going = self.held.run.frames > 0;
        let held = f.breath_level || ((going || in_tail) && f.breath_held);
        self.held.track(index, f, (held, in_tail), rules);
    }

    /// Ends the runs going on (if any) before frame `index`: judged, and the pause's breath
    /// when one counts. The tracker also ends them before a voiced run of active frames that
    /// died in the pause (a word too short to confirm): breath heard again after such a word is
    /// a new run, never one breath spanning the word.
    pub(super) fn close(&mut self, index: u64, rules: &BreathRules) {
        self.strict.close(index, rules);
        self.held.close(index, rules);
    }

    /// A breath has been heard in this pause so far, strict or held: what the pause would
    /// report as its breath ([`PauseBreaths::at_onset`]) if the next phrase started now.
    pub(super) fn heard_so_far(&self, rules: &BreathRules) -> bool {
        self.strict.heard_so_far(rules) || self.held.heard_so_far(rules)
    }

    /// A strict run is going on and has lasted [`BREATH_UNDER_WAY_S`]: breath-like sound the
    /// pause holds now, a breath or not (yet) one.
    /// (The held run, carried on through 3 dB over the room, would take a noisy room's swells
    /// for breaths.)
    pub(super) fn under_way(&self, rules: &BreathRules) -> bool {
        self.strict.under_way(rules)
    }

    /// A strict run going on counts as a breath already: the speaker is breathing in now.
    pub(super) fn breathing_in(&self, rules: &BreathRules) -> bool {
        self.strict.counting(rules)
    }

    /// The breath of the pause that a phrase starting at frame `onset` ends: a strict run still
    /// going on with the part before the onset long enough, or else the last strict run that
    /// counted, cut at the onset (the onset moves back over a quiet consonant) and still long
    /// enough; when no strict run counts, the held run found the same way, with no clean part
    /// (nothing to learn from); `None` when the pause holds no breath.
    pub(super) fn at_onset(&self, onset: u64, rules: &BreathRules) -> Option<HeardRun> {
        self.strict.at_onset(onset, rules).or_else(|| {
            self.held
                .at_onset(onset, rules)
                .map(|h| HeardRun { clean: None, ..h })
        })
    }
}
