//! Breaths already in a pause: runs of breath-like frames (unvoiced, over the floor by the
//! breath margin, not active), judged by their length, their spectral shape over the room and,
//! when a run starts at the phrase's offset, by rising over its lowest point, in the voice band or
//! in the breath's own bands (a reverberant tail only falls; in a room whose hum carries the voice
//! band's level a breath rises little there, as it adds little to it).

use super::facts::FrameFacts;

/// How far a breath run's level must rise over its lowest point to be more than a reverberant
/// tail when it starts at the phrase's offset, dB.
const BREATH_RISE_DB: f32 = 3.0;

/// What makes a run a breath (from the tracker's settings).
#[derive(Debug, Clone, Copy)]
pub(super) struct BreathRules {
    /// Shortest run that counts, frames.
    pub(super) min_frames: u32,
    /// Highest mean high-over-mid and low-over-mid band level of the run, dB.
    pub(super) max_high_over_mid_db: f32,
    pub(super) max_low_over_mid_db: f32,
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
    /// Sums over the run of its frames' high-over-mid and low-over-mid band levels, dB.
    high_sum: f32,
    low_sum: f32,
}

impl BreathRun {
    /// A run counts as a breath when it has a breath's spectral shape (mean band balance
    /// within the limits) and does not only continue the phrase's decay: a reverberant tail
    /// falls from the offset on, an inhalation after it rises again.
    fn counts(&self, rules: &BreathRules) -> bool {
        let n = self.frames.max(1) as f32;
        let high = self.high_sum / n;
        let shaped =
            high <= rules.max_high_over_mid_db && self.low_sum / n <= rules.max_low_over_mid_db;
        shaped && (!self.from_tail || self.rose)
    }
}

/// The breath runs of the current pause: the one going on and the last one that counted.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct PauseBreaths {
    run: BreathRun,
    /// Frames (start, end) of the last breath run long enough to count, in this pause.
    span: Option<(u64, u64)>,
    seen: bool,
}

impl PauseBreaths {
    /// A new pause: nothing heard yet.
    pub(super) fn restart(&mut self) {
        self.run.frames = 0;
        self.seen = false;
        self.span = None;
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
        let run = &mut self.run;
        if f.breath_level && !f.voiced && !f.active {
            if run.frames == 0 {
                run.start = index;
                run.from_tail = last_offset == Some(index);
                run.min_db = f.level_db;
                run.min_bands_db = f.breath_bands_db;
                run.rose = false;
                run.high_sum = 0.0;
                run.low_sum = 0.0;
            }
            run.frames += 1;
            run.high_sum += f.high_over_mid_db;
            run.low_sum += f.low_over_mid_db;
            run.min_db = run.min_db.min(f.level_db);
            run.min_bands_db = run.min_bands_db.min(f.breath_bands_db);
            if f.level_db >= run.min_db + BREATH_RISE_DB
                || f.breath_bands_db >= run.min_bands_db + BREATH_RISE_DB
            {
                run.rose = true;
            }
        } else {
            if run.frames >= rules.min_frames && run.counts(rules) {
                self.seen = true;
                self.span = Some((run.start, index));
            }
            run.frames = 0;
        }
    }

    /// The breath of the pause that a phrase starting at frame `onset` ends, as frames (start,
    /// end): the last run that counted, or a run still going on with the part before the
    /// onset long enough; `None` when the pause holds no breath.
    pub(super) fn at_onset(&self, onset: u64, rules: &BreathRules) -> Option<(u64, u64)> {
        let run = &self.run;
        let running = run.frames > 0
            && run.counts(rules)
            && onset.saturating_sub(run.start) >= rules.min_frames as u64;
        let has_breath = self.seen || running;
        let span = if running {
            Some((run.start, onset))
        } else {
            self.span
        };
        let breath = span.filter(|_| has_breath);
        debug_assert_eq!(breath.is_some(), has_breath, "a breath has its span");
        breath
    }
}
