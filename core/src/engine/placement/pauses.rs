//! What a pause holds, as pure rules of the placement: the rest of a breath a cut or a gate
//! split, and a quiet sound (a bed's note) between phrases of speech taken into the pause
//! around it.

use super::{Seen, MIN_BREATH_S};
use crate::breathing::learned::MAX_LEVEL_RE_SPEECH_DB;
use crate::phrase::Pause;

/// A heard breath beside a gated stretch is a cut one's remnant when it is shorter than this
/// share of the breath the pause would get: a noise gate that opens for a whole breath leaves
/// digital silence on both sides of it too, and that breath must not be doubled.
const REMNANT_SHARE: f64 = 0.5;

/// Where the rest of a breath that a cut or a gate split goes back: into the gated stretch
/// `gated` that touches the heard part `heard` ([`Pause::gated_s`]), after it or before it, as
/// long as a breath (`want_s`) less the heard part, inside `(after_s, end_limit_s)` and from
/// `earliest_s` on. `None` when the heard part is a whole breath (at least [`REMNANT_SHARE`]
/// of `want_s`) or when less than [`MIN_BREATH_S`] fits. All in seconds.
pub(super) fn rest_of_cut_breath(
    heard: (f64, f64),
    gated: (f64, f64),
    want_s: f64,
    (after_s, end_limit_s): (f64, f64),
    earliest_s: f64,
) -> Option<(f64, f64)> {
    let heard_s = heard.1 - heard.0;
    if heard_s >= REMNANT_SHARE * want_s {
        return None;
    }
    let rest_s = want_s - heard_s;
    let (start_s, end_s) = if gated.0 >= heard.0 {
        // The cut began inside the breath: its rest followed the heard part.
        let start_s = gated.0.max(heard.1).max(earliest_s);
        (start_s, (start_s + rest_s).min(gated.1).min(end_limit_s))
    } else {
        // The cut ended inside the breath: its start came before the heard part.
        let end_s = gated.1.min(heard.0).min(end_limit_s);
        (
            (end_s - rest_s).max(gated.0).max(after_s).max(earliest_s),
            end_s,
        )
    };
    (end_s - start_s >= MIN_BREATH_S).then_some((start_s, end_s))
}

/// How far under the speech before it a sound judged not speech lies, at most, to be part of
/// the pause rather than a phrase ([`quiet_between`]), dB: as far as a breath lies at its
/// loudest (the voiced median of the sound against the mean power of the phrase before it).
const QUIET_SOUND_RE_SPEECH_DB: f64 = MAX_LEVEL_RE_SPEECH_DB;

/// Phrase `ph` is a sound between phrases of speech rather than a phrase: it ended judged not
/// speech, the phrase before it was judged speech (`speech_before`), and its voiced frames'
/// median lies [`QUIET_SOUND_RE_SPEECH_DB`] or more under `speech_db`, the level of that
/// speech (dBFS). A voiced sound: a bed's note; an unvoiced burst has no voiced median.
pub(super) fn quiet_between(ph: &Seen, speech_before: Option<bool>, speech_db: f32) -> bool {
    ph.speech == Some(false)
        && speech_before == Some(true)
        && ph
            .own_db
            .is_some_and(|db| f64::from(db) <= f64::from(speech_db) + QUIET_SOUND_RE_SPEECH_DB)
}

/// The pause from the start of `quiet`'s pause to the onset of `next`: `quiet` (a phrase
/// judged not speech, as far under the speech as a breath) taken as part of the pause around
/// it. The heard breath (with its gated stretch) is the later one; nothing is placed before
/// the activity heard in either part (a breath may lie over `quiet` itself, a bed's note).
pub(super) fn pause_across(quiet: &Pause, next: &Pause) -> Pause {
    let heard = if next.breath_s.is_some() { next } else { quiet };
    Pause {
        start_s: quiet.start_s,
        end_s: next.end_s,
        leading: quiet.leading,
        has_breath: heard.has_breath,
        breath_s: heard.breath_s,
        breath_clean_s: heard.breath_clean_s,
        last_activity_end_s: next.last_activity_end_s.or(quiet.last_activity_end_s),
        lead_in_s: next.lead_in_s,
        gated_s: heard.gated_s,
    }
}
