//! The body gate: which control frames lie in sound that is not this speaker's speech (music,
//! singing, noise, as the speech decision judges a phrase), where the body neither speaks nor
//! moves its head (the engine sends the head to rest and clears the speaking flag).
//!
//! A phrase is judged on its first `JUDGE_WINDOW_S` ([`SpeechTrack::current`]), and once more
//! on its own frames when it ends (the judgement the placement keeps, unless the phrase's
//! voiced frames say otherwise, [`SpeechTrack::unsaid`]: a phrase shorter than the
//! window may have been judged on pause frames past its end first). Until it is judged a phrase
//! keeps the flag the one before left (a pause after music stays with the music; after a
//! phrase judged speech, the flag of its voiced frames before its offset, below), unless
//! Silero hears speech in it (speech after music is not held back for a window; Silero takes
//! singing and some noise for speech, which then move the body until the judgement). With a
//! lookahead a stream starts as not speech (no speaker heard yet: a voiced blip in a music
//! intro does not move the head), live mode as speech. Whenever the flag of a phrase changes,
//! the frames from its onset that still wait for the output take it: with a lookahead (the
//! plugin's 500 ms, a render's 8 s) a phrase is gated by its own judgement from its first
//! frames or nearly; live mode (nothing waits) from the moment it is judged. Only frames whose
//! emission lies after the analysed sample are changed, so any block partition gives the same
//! flags. A phrase judged speech goes on to be judged by its voiced frames of the last
//! `JUDGE_WINDOW_S` (when that changes its flag, the frames of the window that still wait for
//! the output take it), and the pause after it by those before its offset
//! ([`SpeechTrack::voiced_window_is_speech`]): speech that runs into singing stops speaking.
//! When that window is not speech and neither are all the phrase's voiced frames so far
//! ([`SpeechTrack::voiced_phrase_is_not_speech`]), the first window was wrong (a sung line that
//! starts like speech): its frames from the onset that still wait for the output take it.
//! A phrase judged not speech stays so while it is heard (a sliding window crosses the
//! threshold now and then in a sung passage); when it ends, the rest of it is judged whole
//! ([`SpeechTrack::tail_turned_speech`]): speech that ran on from music or noise in one phrase
//! speaks from where it turned, on the frames that still wait for the output, with the lung
//! the placement owed it when it followed other sound or began the stream
//! (`CycleAction::BreathOwed`). A phrase shorter than the window is judged on all
//! its frames, its pause on its voiced ones: the two may differ (a blip of noise after a word).
//! No hysteresis: near the threshold the flag may change from frame to frame. Allocation-free.

use super::schedule::{Pending, Queue};
use super::speech_track::SpeechTrack;

/// See the module docs.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BodyGate {
    /// The frame being flagged lies in sound that is not speech: the last judgement made (of a
    /// phrase, of its voiced window, or Silero hearing speech in the phrase being heard).
    other_sound: bool,
    /// The last phrase judgement applied: the phrase's onset, seconds, and whether it is speech.
    applied: Option<(f64, bool)>,
    /// The stream's first frame was flagged.
    started: bool,
    /// The onset of the last phrase judged speech whose voiced frames were found not to be
    /// (flagged from its onset once).
    unsaid: Option<f64>,
}

impl BodyGate {
    /// After analysis frame `pending.back()` (completed by input sample `now`) and its phrase
    /// events, `ended` the phrase that ended at it (onset, offset, judgement): flags that frame
    /// and re-flags the frames waiting for the output from a phrase's onset when its flag
    /// changes, and from its offset by how it ended; `live` mode starts as speech.
    pub(crate) fn frame(
        &mut self,
        speech: &SpeechTrack,
        ended: Option<(f64, f64, bool)>,
        pending: &mut Queue<Pending>,
        now: u64,
        live: bool,
    ) {
        if !self.started {
            self.started = true;
            self.other_sound = !live && speech.enabled();
        }
        let current = speech.current_onset_s().zip(speech.current());
        let judged = ended.map(|(on, _, s)| (on, s)).or(match current {
            Some((onset_s, (speech, true))) => Some((onset_s, speech)),
            _ => None,
        });
        match judged {
            // A phrase ended within its window is judged again on its own frames at its end.
            Some((onset_s, speech)) if self.applied != Some((onset_s, speech)) => {
                self.applied = Some((onset_s, speech));
                self.other_sound = !speech;
                Self::flag_since(pending, onset_s, now, !speech);
            }
            Some(_) => {}
            None => {
                // Silero heard speech in the phrase being heard: speech until it is judged.
                if let (true, Some((onset_s, _))) =
                    (self.other_sound && speech.silero_heard(), current)
                {
                    self.other_sound = false;
                    Self::flag_since(pending, onset_s, now, false);
                }
            }
        }
        // A phrase judged speech goes on to be judged by its voiced frames of the last window
        // (its frames still waiting take a change), and the pause after it by those before
        // its offset.
        // Once that window is not speech, a phrase whose voiced frames so far are not speech
        // either (its first window was the model's mistake) is not speech from its onset.
        match (ended, current) {
            (Some((onset_s, offset_s, true)), _) => {
                if let Some((_, s)) = speech.voiced_window_is_speech(onset_s, Some(offset_s)) {
                    self.other_sound = !s;
                    let unsaid = !s && speech.voiced_phrase_is_not_speech(onset_s, Some(offset_s));
                    let from_s = if unsaid { onset_s } else { offset_s };
                    Self::flag_since(pending, from_s, now, !s);
                }
            }
            (Some((_, _, false)), _) => {
                // Judged not speech by its start, speech to its end from some frame on:
                // speech that ran on from music or noise in one phrase.
                if let Some(from_s) = speech.last_ended_turned_s() {
                    self.other_sound = false;
                    Self::flag_since(pending, from_s, now, false);
                }
            }
            (None, Some((onset_s, (true, true)))) => {
                if let Some((from_s, s)) = speech.voiced_window_is_speech(onset_s, None) {
                    if self.other_sound == s {
                        self.other_sound = !s;
                        Self::flag_since(pending, from_s, now, !s);
                    }
                }
                if self.other_sound
                    && self.unsaid != Some(onset_s)
                    && speech.voiced_phrase_is_not_speech(onset_s, None)
                {
                    self.unsaid = Some(onset_s);
                    Self::flag_since(pending, onset_s, now, true);
                }
            }
            _ => {}
        }
        if let Some(p) = pending.back_mut() {
            p.other_sound = self.other_sound;
        }
    }

    /// Flags the frames from `onset_s` on whose emission lies after input sample `now`.
    fn flag_since(pending: &mut Queue<Pending>, onset_s: f64, now: u64, other_sound: bool) {
        for p in pending.iter_mut() {
            if p.frame.time_s >= onset_s && p.emit_at > now {
                p.other_sound = other_sound;
            }
        }
    }
}
