//! [`SilentRuns`]: the stretches of a pause that are digital silence (under [`GATED_DB`]), at a
//! cut's dither ([`CUT_CEILING_DB`], lower under a quiet speaker) or far under the room
//! ([`UNDER_ROOM_DB`]: a breath an editor attenuated), and the one that touches the pause's
//! heard breath. A recorded room rarely falls that low between phrases; an editor's
//! cut or a closed noise gate does, so a breath-like run with such a stretch right beside it
//! is what a cut left of a breath ([`super::Pause::gated_s`]).

/// Voice-band level under which a frame is digital silence, dBFS: under a 16-bit file's
/// quantisation noise (about −101 dBFS over the full band), so only zeros (or a cut's dither)
/// reach it, never a room. A quiet room's pauses near a 16-bit floor lie far over it; the
/// tracker's own silence level (`phrase_silence_db`, −75 dBFS) would take them for a cut.
pub(super) const GATED_DB: f32 = -110.0;

/// Voice-band level under which a stretch of a pause is what a cut left (a 16-bit export's TPDF
/// dither lies at about −96 dBFS over the full band and lower in the voice band; a gate's
/// residue), dBFS, for speech at the tracker's `QUIET_SPEECH_DB` (−30 dBFS) or louder; under a
/// quieter speaker it moves down with the speech level, so a quiet take's room stays a room.
/// A recorded room at a normal gain lies that low only when it is within a few dB of a 16-bit
/// file's least step, or after a denoiser: pauses that quiet are taken as cut (a breath heard
/// beside one is a remnant, see [`super::Pause::gated_s`]); the noise floor still learns from
/// them, unlike digital silence ([`GATED_DB`]).
pub(super) const CUT_CEILING_DB: f32 = -90.0;

/// How far under the room's noise floor (the lowest level of the last 3 s, before the frame) a
/// frame of a pause lies when an editor lowered it, dB: a breath attenuated by 20–40 dB (a
/// de-breath tool's setting, not a gate) falls under the room it was recorded in, and a
/// recorded room never falls that far under its own floor within a few seconds.
pub(super) const UNDER_ROOM_DB: f32 = 20.0;

/// Longest time under the room taken as an editor's (a breath lasts under a second, 0.8 s at
/// most in `../shared/data`), seconds, counted over every frame under it since the room was
/// last heard ([`ROOM_HEARD_S`]), across phrases: a level that stays that low is the room's
/// own from then on (a fan switched off, a denoiser's floor, a music bed that stopped under
/// the voice, whose later pauses and word gaps all lie under the old room), and the noise
/// floor learns it.
pub(super) const UNDER_ROOM_MAX_S: f32 = 1.0;

/// How long frames must lie at the room (neither under it, nor speech, nor a cut) for the room
/// to be heard again, seconds: an edit leaves the room around what it lowered, while a
/// vowel's decay passes the room's level in a frame or two.
pub(super) const ROOM_HEARD_S: f32 = 0.05;

/// Most a breath-like run and a stretch of digital silence may lie apart and still touch (a
/// gate's release, a frame's rounding), seconds.
pub(super) const TOUCH_S: f64 = 0.05;

/// Stretches kept per pause: the last ones (a breath lies beside one of the last two).
const KEPT: usize = 4;

/// The silent frames of one pause, tracked frame by frame (first and one-past-last frame).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct SilentRuns {
    /// First frame of the stretch going on.
    current: Option<u64>,
    /// The last finished stretches, oldest first.
    runs: [(u64, u64); KEPT],
    len: usize,
}

impl SilentRuns {
    /// Forgets the pause (a phrase ended: a new pause starts).
    pub(super) fn restart(&mut self) {
        *self = Self::default();
    }

    /// Takes frame `index` of the pause (frames in order), silent or not.
    pub(super) fn track(&mut self, index: u64, silent: bool) {
        match (silent, self.current) {
            (true, None) => self.current = Some(index),
            (false, Some(start)) => {
                if self.len == KEPT {
                    self.runs.copy_within(1.., 0);
                    self.len -= 1;
                }
                self.runs[self.len] = (start, index);
                self.len += 1;
                self.current = None;
            }
            _ => {}
        }
    }

    /// The stretch that touches the run `breath` (frames, within `touch` frames), up to frame
    /// `onset` (a stretch still going ends there): the one after it, else the one before it.
    pub(super) fn beside(&self, breath: (u64, u64), onset: u64, touch: u64) -> Option<(u64, u64)> {
        let going = self.current.filter(|&s| s < onset).map(|s| (s, onset));
        let clamp = |r: (u64, u64)| Some((r.0.min(onset), r.1.min(onset))).filter(|(a, b)| b > a);
        let runs = || {
            self.runs[..self.len]
                .iter()
                .copied()
                .chain(going)
                .filter_map(clamp)
        };
        let near = |a: u64, b: u64| a.abs_diff(b) <= touch;
        runs()
            .find(|r| near(r.0, breath.1))
            .or_else(|| runs().find(|r| near(r.1, breath.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tracks frames 0..n, silent where `silent` says.
    fn runs(n: u64, silent: impl Fn(u64) -> bool) -> SilentRuns {
        let mut r = SilentRuns::default();
        for k in 0..n {
            r.track(k, silent(k));
        }
        r
    }

    #[test]
    fn the_stretch_after_the_breath_is_found_first_then_the_one_before() {
        // Silent at 2..10 and from 20 on; a breath run at 10..20.
        let r = runs(30, |k| (2..10).contains(&k) || k >= 20);
        assert_eq!(r.beside((10, 20), 30, 1), Some((20, 30)));
        // The onset cuts the stretch going on.
        assert_eq!(r.beside((10, 20), 25, 1), Some((20, 25)));
        // Nothing after a breath at 10..18 within a frame: the stretch before it.
        assert_eq!(r.beside((10, 18), 30, 1), Some((2, 10)));
        // Nothing touching.
        assert_eq!(r.beside((13, 16), 30, 1), None);
        let mut r = r;
        r.restart();
        assert_eq!(r.beside((10, 20), 30, 1), None);
    }

    #[test]
    fn only_the_last_stretches_are_kept() {
        // Six one-frame stretches at 0, 2, 4, 6, 8, 10; the first two are forgotten.
        let r = runs(12, |k| k % 2 == 0 && k <= 10);
        assert_eq!(r.beside((1, 1), 12, 0), None);
        assert_eq!(r.beside((5, 5), 12, 0), Some((4, 5)));
        assert_eq!(r.beside((11, 11), 12, 0), Some((10, 11)));
    }
}
