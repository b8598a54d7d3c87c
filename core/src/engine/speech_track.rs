//! The speech track: the engine's view of the speech decision ([`crate::speech`]). It feeds the
//! [`SpeechDetector`] the stream's mono samples in the analysis order (the samples that complete
//! a frame, then the frame), keeps each frame's speech probability for a few seconds, and judges
//! the phrases the tracker reports:
//! - a phrase is speech when the mean probability of its first [`JUDGE_WINDOW_S`] (or of the
//!   whole phrase when it is shorter) reaches the model's threshold; until that window has been
//!   heard (the plugin's short lookahead sees 0.05–0.15 s of a phrase when the breath before
//!   it must start), by what was heard of it, and Silero's highest probability in it
//!   ([`SpeechTrack::current`], [`SpeechTrack::silero_heard`]); a phrase heard for
//!   [`SILERO_SHOWS_SPEECH_S`] with neither taking any of it for speech is not speech yet
//!   ([`SpeechTrack::heard_no_speech`]);
//! - live mode, which must decide right after a phrase ends, judges the last
//!   [`JUDGE_WINDOW_S`] of the finished phrase ([`SpeechTrack::tail_is_speech`]);
//! - for the body, a phrase judged speech is judged again as it goes on, by its voiced frames
//!   of the last [`JUDGE_WINDOW_S`] (a ring of the voiced frames' probabilities), and its pause
//!   by those before its offset ([`SpeechTrack::voiced_window_is_speech`]).
//!
//! With the decision switched off (`PlacementConfig::speech_only` false) every phrase is
//! speech and nothing is computed. Allocation-free after `new`; the decisions depend on the
//! sample sequence only, so any block partition gives the same judgements.

use crate::analysis::FeatureFrame;
use crate::speech::segments::THRESHOLD as SILERO_THRESHOLD;
use crate::speech::silero::{CHUNK, SILERO_RATE_HZ};
use crate::speech::{RecentSpeech, SpanJudge, SpeechDetector, SpeechModel, JUDGE_WINDOW_S};

/// Frames kept for late judgements, seconds: a phrase reported up to this long after its onset
/// (or a short phrase ended this long ago) is judged from its own frames.
const KEPT_S: f64 = 3.0;

/// Silero's probability reaches its threshold within this of a phrase's onset in 95 % of the
/// phrases of clean speech (215 onsets of Keele's ten voices and the seven styletalk clips
/// through the engine with a 500 ms lookahead: median 0.025 s, 99 % 0.175 s, longest 0.275 s),
/// seconds. A phrase heard this long without Silero or the stacked model taking any of it for
/// speech is something else until its window is judged (a music outro after the last words).
pub(crate) const SILERO_SHOWS_SPEECH_S: f64 = 0.15;

/// What was heard since the last `reset`, for the render's summary.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SpeechSummary {
    /// Analysis frames.
    pub frames: u64,
    /// Frames with sound: above the phrase tracker's silence level, and voiced or standing its
    /// activity margin over the lowest noise floor so far that lies over the silence level (a
    /// steady room or hiss under a voice is no sound here; sustained chords are).
    pub sound_frames: u64,
    /// Frames the decision calls speech.
    pub speech_frames: u64,
    /// Phrases judged, and those judged speech.
    pub phrases: u64,
    /// Phrases judged speech.
    pub speech_phrases: u64,
}

/// Less speech than this share of the frames with sound: no speech heard.
pub const NO_SPEECH_SHARE: f64 = 0.01;
/// Less speech than this share of the frames with sound: mostly something else (music,
/// singing, noise).
pub const MOSTLY_OTHER_SHARE: f64 = 0.5;

impl SpeechSummary {
    /// Share of the frames with sound that the decision calls speech, 0..1 (0 without sound).
    pub fn speech_share(&self) -> f64 {
        if self.sound_frames == 0 {
            0.0
        } else {
            self.speech_frames as f64 / self.sound_frames as f64
        }
    }

    /// No speech was heard: under [`NO_SPEECH_SHARE`] of the time with sound, or no phrase
    /// judged speech.
    pub fn holds_no_speech(&self) -> bool {
        self.speech_share() < NO_SPEECH_SHARE || self.speech_phrases == 0
    }

    /// Speech in under [`MOSTLY_OTHER_SHARE`] of the time with sound (no speech included).
    pub fn mostly_other(&self) -> bool {
        self.speech_share() < MOSTLY_OTHER_SHARE
    }
}

/// The time of the first of the unbroken run of `frames` (time, Silero's probability; in
/// time order) after `from_s` at or over Silero's threshold that lasts up to the last frame at
/// or before `to_s`; `None` when that last frame is under it.
fn run_reaching(frames: impl Iterator<Item = (f64, f32)>, from_s: f64, to_s: f64) -> Option<f64> {
    let mut run = None;
    for (t, p) in frames.skip_while(|&(t, _)| t <= from_s) {
        if t > to_s {
            break;
        }
        run = if p >= SILERO_THRESHOLD {
            run.or(Some(t))
        } else {
            None
        };
    }
    run
}

/// See the module docs.
#[derive(Debug, Clone)]
pub(crate) struct SpeechTrack {
    detector: Option<SpeechDetector>,
    threshold: f32,
    silence_db: f32,
    /// How far over the noise floor a frame counts as sound in the summary, dB.
    sound_margin_db: f32,
    recent: RecentSpeech,
    /// Silero's probability of the same frames.
    recent_silero: RecentSpeech,
    /// The voiced frames among them, with the stacked model's probability.
    recent_voiced: RecentSpeech,
    state: SpeechTrackState,
}

/// What [`SpeechTrack::reset`] clears besides the detector and the ring.
#[derive(Debug, Clone, Copy)]
struct SpeechTrackState {
    /// The judge of the phrase being spoken (the last one started).
    phrase: Option<SpanJudge>,
    /// Silero's highest probability in the phrase being spoken so far.
    silero_max: f32,
    /// The judgement of the phrase that ended last.
    ended: Option<bool>,
    /// The phrase being spoken, judged speech by its first window, was found not to be by all
    /// its voiced frames at some frame since ([`SpeechTrack::unsaid`]).
    unsaid: bool,
    /// The same of the phrase that ended last, by its voiced frames up to its offset too.
    ended_unsaid: bool,
    /// See [`SpeechTrack::last_ended_turned_s`].
    ended_turned_s: Option<f64>,
    /// Time of the last frame heard, seconds.
    last_frame_s: f64,
    /// The phrase tracker's lowest noise floor over its silence level so far, dBFS (+∞ before
    /// one).
    quietest_floor_db: f32,
    summary: SpeechSummary,
}

impl Default for SpeechTrackState {
    fn default() -> Self {
        Self {
            phrase: None,
            silero_max: 0.0,
            ended: None,
            unsaid: false,
            ended_unsaid: false,
            ended_turned_s: None,
            last_frame_s: 0.0,
            quietest_floor_db: f32::INFINITY,
            summary: SpeechSummary::default(),
        }
    }
}

impl SpeechTrack {
    /// A track for a stream at `sample_rate_hz` with frames at `frame_rate_hz` judging with
    /// `model`; `None` (the decision off) calls everything speech. Its summary counts frames
    /// over `silence_db` and `sound_margin_db` over the noise floor as sound. Allocates.
    pub(crate) fn new(
        model: Option<SpeechModel>,
        sample_rate_hz: f64,
        frame_rate_hz: f64,
        (silence_db, sound_margin_db): (f32, f32),
    ) -> Self {
        let threshold = model
            .as_ref()
            .map_or(SpeechModel::shipped().threshold(), SpeechModel::threshold);
        Self {
            detector: model.map(|m| SpeechDetector::new(m, sample_rate_hz, frame_rate_hz)),
            threshold,
            silence_db,
            sound_margin_db,
            recent: RecentSpeech::new(KEPT_S, frame_rate_hz),
            recent_silero: RecentSpeech::new(KEPT_S, frame_rate_hz),
            recent_voiced: RecentSpeech::new(KEPT_S, frame_rate_hz),
            state: SpeechTrackState::default(),
        }
    }

    /// Back to the start of a stream.
    pub(crate) fn reset(&mut self) {
        if let Some(d) = &mut self.detector {
            d.reset();
        }
        self.recent.reset();
        self.recent_silero.reset();
        self.recent_voiced.reset();
        self.state = SpeechTrackState::default();
    }

    /// The decision is on.
    pub(crate) fn enabled(&self) -> bool {
        self.detector.is_some()
    }

    /// The next mono samples (those up to the one that completes the next frame, or the rest
    /// of a block). Never allocates.
    pub(crate) fn push(&mut self, samples: &[f32]) {
        if let Some(d) = &mut self.detector {
            d.push(samples, |_, _| {});
        }
    }

    /// The next analysis frame (after the samples that completed it), with the phrase
    /// tracker's noise floor before it (dBFS, voice band): its speech probability (1 when the
    /// decision is off).
    pub(crate) fn frame(&mut self, f: &FeatureFrame, floor_db: f32) -> f32 {
        let (p, silero_p) = match &mut self.detector {
            Some(d) => {
                let s = d.frame(f.voiced, f.rms_db);
                (s.speech_p, s.silero_p)
            }
            None => (1.0, 1.0),
        };
        self.recent.push(f.time_s, p);
        self.recent_silero.push(f.time_s, silero_p);
        if f.voiced {
            self.recent_voiced.push(f.time_s, p);
        }
        self.state.last_frame_s = f.time_s;
        if let Some(j) = &mut self.state.phrase {
            j.add(f.time_s, p);
            if f.time_s >= j.start_s() {
                self.state.silero_max = self.state.silero_max.max(silero_p);
            }
        }
        if !self.state.unsaid && self.current() == Some((true, true)) {
            self.state.unsaid = self
                .current_onset_s()
                .is_some_and(|on| self.voiced_phrase_is_not_speech(on, None));
        }
        let s = &mut self.state.summary;
        s.frames += 1;
        // Sound stands over the quietest floor of the stream so far (the floor climbs into
        // sustained chords within seconds; a floor in digital silence is no room's), or is
        // voiced (chords from the first frame); a steady room or hiss at the floor is not.
        if floor_db.is_finite() && floor_db > self.silence_db {
            self.state.quietest_floor_db = self.state.quietest_floor_db.min(floor_db);
        }
        if f.rms_db > self.silence_db
            && (f.voiced || f.band_db >= self.state.quietest_floor_db + self.sound_margin_db)
        {
            s.sound_frames += 1;
            s.speech_frames += u64::from(p >= self.threshold);
        }
        p
    }

    /// A phrase started at `onset_s` (reported now, after the frame that confirmed it).
    pub(crate) fn phrase_started(&mut self, onset_s: f64) {
        self.state.phrase = Some(self.recent.judge_from(onset_s));
        self.state.unsaid = false;
        self.state.silero_max = self
            .recent_silero
            .iter()
            .filter(|&(t, _)| t >= onset_s)
            .fold(0.0, |m, (_, p)| m.max(p));
    }

    /// The phrase being spoken, judged by what was heard of its window so far: `(speech,
    /// complete)`, `None` before its first frame (always speech when the decision is off).
    pub(crate) fn current(&self) -> Option<(bool, bool)> {
        if !self.enabled() {
            return Some((true, true));
        }
        let j = self.state.phrase?;
        Some((j.is_speech(self.threshold)?, j.is_complete()))
    }

    /// The phrase from `onset_s` judged by its voiced frames in the last [`JUDGE_WINDOW_S`]
    /// before `end_s` (its offset: `[end_s − window, end_s)`), or up to now while it is being
    /// spoken (`end_s` `None`: `(now − window, now]`): their mean probability against the
    /// threshold, with where the window starts, seconds. `None` when that window holds no
    /// voiced frame (a gap between words says nothing); always speech when the decision is
    /// off. The body follows it on a phrase judged speech: speech that runs into singing or a
    /// sting stops moving the body once they bring the window's mean under the threshold.
    /// Breath placement keeps the first window's judgement (unless the phrase is
    /// [`SpeechTrack::unsaid`]).
    pub(crate) fn voiced_window_is_speech(
        &self,
        onset_s: f64,
        end_s: Option<f64>,
    ) -> Option<(f64, bool)> {
        let from_s = (end_s.unwrap_or(self.state.last_frame_s) - JUDGE_WINDOW_S).max(onset_s);
        if !self.enabled() {
            return Some((from_s, true));
        }
        let mean = match end_s {
            Some(end_s) => self.recent_voiced.mean_between(from_s, end_s),
            None => self.recent_voiced.mean_since(from_s),
        };
        mean.map(|m| (from_s, m >= self.threshold))
    }

    /// The phrase `(onset_s, offset_s)` just ended, judged not speech by its first window, is
    /// speech from some frame on to its end: the first kept frame at or over the threshold
    /// from which the mean probability of every frame to the offset reaches it too, and that of
    /// the window ([`JUDGE_WINDOW_S`]) from it, at least two windows before the offset; that
    /// frame's time. `None` when no
    /// frame is (or the decision is off). Speech that runs on from a music intro or noise in
    /// one phrase (the host speaks as the intro fades out): the body speaks on it where its
    /// frames still wait for the output (a render's 8 s). Judged on the whole rest of the
    /// phrase, not a sliding window, which crosses the threshold now and then in a sung
    /// passage. Only the last [`KEPT_S`] of the phrase is kept: speech that began earlier in
    /// the phrase is taken from where that begins. Kept for [`SpeechTrack::last_ended_turned_s`].
    pub(crate) fn tail_turned_speech(&self, onset_s: f64, offset_s: f64) -> Option<f64> {
        if !self.enabled() {
            return None;
        }
        let frames = || {
            self.recent
                .iter()
                .filter(move |&(t, _)| t > onset_s && t < offset_s)
        };
        let (mut left_sum, mut left_n) =
            frames().fold((0.0f64, 0u32), |(s, n), (_, p)| (s + f64::from(p), n + 1));
        let threshold = f64::from(self.threshold);
        for (t, p) in frames() {
            if offset_s - t < 2.0 * JUDGE_WINDOW_S {
                return None;
            }
            // The window from it is speech too: a frame of the music before the speech that
            // crosses the threshold is no turn, however strong the speech after it.
            let window_is_speech = || {
                self.recent
                    .mean_between(t, t + JUDGE_WINDOW_S)
                    .is_some_and(|m| m >= self.threshold)
            };
            if f64::from(p) >= threshold
                && left_sum >= threshold * f64::from(left_n)
                && window_is_speech()
            {
                return Some(t);
            }
            left_sum -= f64::from(p);
            left_n -= 1;
        }
        None
    }

    /// The phrase from `onset_s` is not speech by all its voiced frames up to `end_s` (its
    /// offset) or up to now (`None`): their mean probability lies under the threshold, and none
    /// of them has left the ring ([`KEPT_S`] of voiced frames). False with the decision off.
    /// Music or singing whose first window the model took for speech is told by the rest.
    pub(crate) fn voiced_phrase_is_not_speech(&self, onset_s: f64, end_s: Option<f64>) -> bool {
        self.enabled()
            && self.recent_voiced.holds_since(onset_s)
            && self
                .recent_voiced
                .mean_between(onset_s, end_s.unwrap_or(f64::INFINITY))
                .is_some_and(|m| m < self.threshold)
    }

    /// Onset of the phrase being spoken, seconds (`None` between phrases).
    pub(crate) fn current_onset_s(&self) -> Option<f64> {
        self.state.phrase.map(|j| j.start_s())
    }

    /// Silero's probability reached its own threshold (0.5) in what was heard of the phrase
    /// being spoken (always true when the decision is off). The stacked model's threshold needs
    /// more than a phrase's first chunks; Silero's own is what a phrase's first 0.1 s can say.
    pub(crate) fn silero_heard(&self) -> bool {
        !self.enabled() || self.state.silero_max >= SILERO_THRESHOLD
    }

    /// The phrase being spoken while neither Silero nor the stacked model has taken any of it
    /// for speech: its onset and how long it has been heard, seconds (`None` once either did,
    /// before any phrase, and with the decision off). Its window is complete only after
    /// [`JUDGE_WINDOW_S`] has been heard.
    fn unspoken(&self) -> Option<(f64, f64)> {
        let j = self.state.phrase?;
        (self.enabled() && !self.silero_heard() && j.is_speech(self.threshold) != Some(true))
            .then(|| (j.start_s(), self.state.last_frame_s - j.start_s()))
    }

    /// The phrase being spoken has been heard for [`SILERO_SHOWS_SPEECH_S`] and neither Silero
    /// nor the stacked model took any of it for speech: before its window is judged, it is not
    /// speech.
    pub(crate) fn heard_no_speech(&self) -> bool {
        self.unspoken()
            .is_some_and(|(_, heard_s)| heard_s >= SILERO_SHOWS_SPEECH_S)
    }

    /// The phrase starting at `onset_s` is the one being spoken, and too little of it has been
    /// heard to tell: neither Silero nor the stacked model took any of it for speech, and it
    /// has been heard for less than [`SILERO_SHOWS_SPEECH_S`].
    pub(crate) fn too_early_to_tell(&self, onset_s: f64) -> bool {
        self.unspoken()
            .is_some_and(|(start_s, heard_s)| start_s == onset_s && heard_s < SILERO_SHOWS_SPEECH_S)
    }

    /// Where the speech of the phrase the tracker starts at `onset_s` began by Silero: the
    /// first frame after `from_s` (the pause's start) of the unbroken run of frames at or over
    /// Silero's threshold that reaches the onset, less one chunk and the resampler's latency (a
    /// chunk's probability arrives when the chunk completes), never before `from_s`. In noise or
    /// under a bed the tracker hears a soft onset late (a consonant, the first syllable's rise)
    /// while Silero already hears speech. `onset_s` when the frame before the onset was not
    /// called speech, or with the decision off. Call it when the phrase is reported: it reads
    /// the last [`KEPT_S`] of frames.
    pub(crate) fn speech_onset_s(&self, from_s: f64, onset_s: f64) -> f64 {
        let Some(d) = &self.detector else {
            return onset_s;
        };
        let lag_s = CHUNK as f64 / SILERO_RATE_HZ + d.latency_s();
        run_reaching(self.recent_silero.iter(), from_s, onset_s)
            .map_or(onset_s, |t| (t - lag_s).clamp(from_s, onset_s))
    }

    /// The phrase from `onset_s` ended at `offset_s`: its judgement by its first
    /// [`JUDGE_WINDOW_S`] (the whole phrase when shorter). Counted in the summary.
    pub(crate) fn phrase_ended(&mut self, onset_s: f64, offset_s: f64) -> bool {
        let speech = if !self.enabled() {
            true
        } else if offset_s - onset_s < JUDGE_WINDOW_S {
            // The running judge may hold frames past the end (the end is confirmed late).
            self.recent
                .mean_between(onset_s, offset_s)
                .is_some_and(|m| m >= self.threshold)
        } else {
            self.state
                .phrase
                .and_then(|j| j.is_speech(self.threshold))
                .unwrap_or(false)
        };
        self.state.ended_unsaid = speech
            && (self.state.unsaid || self.voiced_phrase_is_not_speech(onset_s, Some(offset_s)));
        self.state.ended_turned_s = if speech {
            None
        } else {
            self.tail_turned_speech(onset_s, offset_s)
        };
        self.state.phrase = None;
        self.state.unsaid = false;
        self.state.ended = Some(speech);
        let s = &mut self.state.summary;
        s.phrases += 1;
        s.speech_phrases += u64::from(speech);
        speech
    }

    /// The phrase being spoken was judged speech by its first window, and at some frame since
    /// all its voiced frames so far were not speech ([`SpeechTrack::voiced_phrase_is_not_speech`]):
    /// a sung line that starts like speech. Kept for the rest of the phrase, so a decision
    /// taken seconds later (a whole-file render's pause, when its voiced frames have left the
    /// ring) still knows it.
    pub(crate) fn unsaid(&self) -> bool {
        self.state.unsaid
    }

    /// [`SpeechTrack::unsaid`] of the phrase that ended last, or its voiced frames up to its
    /// offset not speech.
    pub(crate) fn last_ended_unsaid(&self) -> bool {
        self.state.ended_unsaid
    }

    /// Where the phrase that ended last, judged not speech, turned to speech to its end
    /// ([`SpeechTrack::tail_turned_speech`]), seconds.
    pub(crate) fn last_ended_turned_s(&self) -> Option<f64> {
        self.state.ended_turned_s
    }

    /// The judgement of the phrase that ended last ([`SpeechTrack::phrase_ended`]).
    pub(crate) fn last_ended(&self) -> Option<bool> {
        self.state.ended
    }

    /// Live mode: the phrase from `onset_s` that ended at `offset_s` was speech by its last
    /// [`JUDGE_WINDOW_S`] (the whole phrase when shorter).
    pub(crate) fn tail_is_speech(&self, onset_s: f64, offset_s: f64) -> bool {
        !self.enabled()
            || self
                .recent
                .mean_between((offset_s - JUDGE_WINDOW_S).max(onset_s), offset_s)
                .is_some_and(|m| m >= self.threshold)
    }

    /// What was heard since the last reset.
    pub(crate) fn summary(&self) -> SpeechSummary {
        self.state.summary
    }
}

#[cfg(test)]
mod tests {
    use super::run_reaching;

    fn frames(ps: &[f32]) -> impl Iterator<Item = (f64, f32)> + '_ {
        ps.iter().enumerate().map(|(i, &p)| (i as f64 * 0.01, p))
    }

    #[test]
    fn the_run_that_reaches_the_onset_is_found_from_its_start() {
        let ps = [0.9, 0.1, 0.2, 0.6, 0.8, 0.9, 0.95, 0.9];
        // Frames 3..=6 are at or over 0.5 up to the onset at 0.06 s.
        assert_eq!(run_reaching(frames(&ps), -1.0, 0.06), Some(0.03));
        // The pause starts at 0.04 s: the run is cut there.
        assert_eq!(run_reaching(frames(&ps), 0.04, 0.06), Some(0.05));
    }

    #[test]
    fn no_run_when_the_frame_before_the_onset_is_not_speech() {
        let ps = [0.9, 0.9, 0.2, 0.1];
        assert_eq!(run_reaching(frames(&ps), -1.0, 0.03), None);
        assert_eq!(run_reaching(frames(&ps), -1.0, 0.01), Some(0.0));
    }
}
