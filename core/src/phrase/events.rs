//! What the phrase tracker reports: [`PhraseEvent`]s, and the [`Pause`] a phrase start ends.

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
    /// The part of `breath_s` before the first active frame it spans (an unvoiced blip louder
    /// than a breath: the run of breath-like frames went on after it), when long enough to
    /// count as a breath; all of it without a blip; `None` for a breath heard only as a held
    /// run (see [`super::breath_run`]: its edges hold more room than breath). What a breath
    /// voice learns from: a blip's power would outweigh the breath's in the span's mean.
    pub breath_clean_s: Option<(f64, f64)>,
    /// End of the last activity inside the pause that did not become a phrase (a noise burst, a
    /// word too short to confirm), seconds; `None` when the pause was quiet. Nothing should be
    /// placed over it.
    pub last_activity_end_s: Option<f64>,
    /// Start of an unvoiced burst just before the onset that begins the phrase's speech (a
    /// leading /s/ whose stop closure outlasts the run gap), seconds: the speech starts there,
    /// and nothing should be placed over it. Not part of `last_activity_end_s`.
    pub lead_in_s: Option<f64>,
    /// Digital silence touching the heard breath (`breath_s`), after it or else before it: an
    /// editor's cut or a closed noise gate took the rest of that breath (a recorded room never
    /// falls that low), seconds; `None` without a heard breath or without such a stretch.
    pub gated_s: Option<(f64, f64)>,
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
