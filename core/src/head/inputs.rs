//! What the pose model reads from each feature frame: voiced or not, f0 and level, in the units
//! the model's normalisation names. Synthesis and training both run a fresh [`InputTracker`]
//! over a stream, so they see the same inputs.
//!
//! Two normalisations:
//! - [`InputKind::SpeakerMean`] (models trained since issue 32): f0 in semitones (of `f0_hz`)
//!   around the speaker's running mean log f0 over voiced frames; level: `rms_db` around the
//!   running mean `rms_db` of voiced frames on voiced frames and of unvoiced frames on unvoiced
//!   ones. Every input the model reads averages 0 over a speaker, whatever the voice's
//!   register, the recording's loudness or its room noise, so a model whose output at the mean
//!   input is the mean pose keeps that mean pose on any voice. The means start from the first
//!   frames heard (no prior) and then forget with [`CENTRING_TIME_S`]. In a long silence the
//!   unvoiced mean settles on the silence's level, and the model sees an ordinary pause level.
//!   Another voice (an interview's guest, a character voice) is a new speaker: when the mean
//!   f0 of the last [`RECENT_TIME_S`] of voiced frames lies [`NEW_SPEAKER_ST`] from the
//!   running mean, the f0 and voiced level means start again, as at a stream's start; when
//!   the mean level of the last [`RECENT_TIME_S`] of unvoiced frames lies [`NEW_ROOM_DB`] from
//!   theirs (the pauses after a long silence, another room), that mean starts again. So the
//!   last voice's register or room is not carried into the next one's head for half a minute;
//!   a louder stretch of one voice (a shout) starts nothing.
//! - [`InputKind::SpeakerMedian`] (older models): the analyzer's `f0_st` (around the running
//!   median f0, starting from a 150 Hz prior) and `level_db` (around the speech level, for
//!   every frame). A voice whose mean lies off its median, the prior's pull in a short clip,
//!   or a quiet room turn into a constant input offset, and the model's gain into a posture
//!   offset of degrees (issue 32).

use crate::analysis::FeatureFrame;

/// Time constant of the running means, seconds of frames of the class (voiced or unvoiced):
/// the analyzer's speaker statistics forget over 30 s of speech too
/// ([`crate::analysis::SpeakerNormConfig`]).
pub const CENTRING_TIME_S: f64 = 30.0;

/// Time constant of the recent means that tell a new speaker or room, seconds of frames of
/// the class (voiced or unvoiced).
pub const RECENT_TIME_S: f64 = 2.0;
/// A recent mean f0 this far from the running mean is a new speaker, semitones: half an
/// octave. A speaker's phrases wander 1–3 semitones around their mean; men's and women's
/// voices lie 8–12 apart.
pub const NEW_SPEAKER_ST: f64 = 6.0;
/// A recent level of the unvoiced frames this far from their running mean is a new room, dB.
pub const NEW_ROOM_DB: f64 = 10.0;

/// The normalisation names of [`InputKind::SpeakerMean`] in a model file.
pub const SPEAKER_MEAN_NAMES: (&str, &str) = ("st_re_speaker_mean", "db_re_speaker_mean");
/// The normalisation names of [`InputKind::SpeakerMedian`] in a model file.
pub const SPEAKER_MEDIAN_NAMES: (&str, &str) = ("st_re_speaker_median", "db_re_speech_level");

/// Which inputs a model reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InputKind {
    /// f0 and level around the speaker's running means (see the module docs).
    SpeakerMean,
    /// The analyzer's `f0_st` and `level_db`.
    SpeakerMedian,
}

impl InputKind {
    /// The kind a normalisation's (f0, level) names select; `None` for names this build does
    /// not compute.
    pub fn of_names(f0: &str, level: &str) -> Option<InputKind> {
        match (f0, level) {
            n if n == SPEAKER_MEAN_NAMES => Some(InputKind::SpeakerMean),
            n if n == SPEAKER_MEDIAN_NAMES => Some(InputKind::SpeakerMedian),
            _ => None,
        }
    }
}

/// The model input of one frame, clamped to the normalisation's ranges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelInput {
    /// The frame counts as voiced (see [`counts_as_voiced`]).
    pub voiced: bool,
    /// f0 in semitones (0 when unvoiced).
    pub f0_st: f64,
    /// Level in dB.
    pub level_db: f64,
}

/// Whether a frame counts as voiced for the head: the analyzer says so and its f0 and levels
/// are finite numbers (f0 above 0).
pub fn counts_as_voiced(frame: &FeatureFrame) -> bool {
    frame.voiced
        && frame.f0_hz > 0.0
        && frame.f0_hz.is_finite()
        && frame.f0_st.is_finite()
        && frame.rms_db.is_finite()
        && frame.level_db.is_finite()
}

/// A mean that starts as the plain mean of the values seen and then forgets with `time_s`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Forgetting {
    mean: f64,
    count: f64,
}

impl Forgetting {
    /// Adds `x`; the mean including it.
    fn add(&mut self, x: f64, time_s: f64, frame_rate_hz: f64) -> f64 {
        self.count += 1.0;
        let a = (1.0 / self.count).max(1.0 / (time_s * frame_rate_hz));
        self.mean += a * (x - self.mean);
        self.mean
    }
}

/// The running mean ([`CENTRING_TIME_S`]) of a speaker's input, which starts again (as at a
/// stream's start, from the frame that told it) when the recent mean ([`RECENT_TIME_S`]) lies
/// `new_speaker` or more from it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct RunningMean {
    long: Forgetting,
    recent: Forgetting,
}

impl RunningMean {
    /// Adds `x` and returns `x` minus the mean including it, and whether it started again.
    fn centre(&mut self, x: f64, frame_rate_hz: f64, new_speaker: f64) -> (f64, bool) {
        let recent = self.recent.add(x, RECENT_TIME_S, frame_rate_hz);
        let mean = self.long.add(x, CENTRING_TIME_S, frame_rate_hz);
        let again = (recent - mean).abs() >= new_speaker;
        if again {
            *self = Self::default();
            self.recent.add(x, RECENT_TIME_S, frame_rate_hz);
            self.long.add(x, CENTRING_TIME_S, frame_rate_hz);
        }
        (x - self.long.mean, again)
    }
}

/// The per-stream state that turns feature frames into model inputs. Allocation-free.
#[derive(Debug, Clone, PartialEq)]
pub struct InputTracker {
    kind: InputKind,
    f0_range: [f64; 2],
    level_range: [f64; 2],
    f0: RunningMean,
    voiced_level: RunningMean,
    unvoiced_level: RunningMean,
}

impl InputTracker {
    /// A tracker of `kind` inputs clamped to `f0_st_range` and `level_db_range` (a model's
    /// normalisation makes its own: `Normalisation::input_tracker`).
    pub fn new(kind: InputKind, f0_st_range: [f64; 2], level_db_range: [f64; 2]) -> InputTracker {
        InputTracker {
            kind,
            f0_range: f0_st_range,
            level_range: level_db_range,
            f0: RunningMean::default(),
            voiced_level: RunningMean::default(),
            unvoiced_level: RunningMean::default(),
        }
    }

    /// Back to the start of a stream (no speaker heard).
    pub fn reset(&mut self) {
        self.f0 = RunningMean::default();
        self.voiced_level = RunningMean::default();
        self.unvoiced_level = RunningMean::default();
    }

    /// The model input of the next frame of the stream, at `frame_rate_hz`. A frame with a
    /// non-finite level counts as unvoiced at the lowest level and teaches nothing.
    pub fn next(&mut self, frame: &FeatureFrame, frame_rate_hz: f64) -> ModelInput {
        let voiced = counts_as_voiced(frame);
        let (f0, level) = match self.kind {
            InputKind::SpeakerMedian => {
                let level = if frame.level_db.is_finite() {
                    frame.level_db as f64
                } else {
                    f64::NEG_INFINITY
                };
                (if voiced { frame.f0_st as f64 } else { 0.0 }, level)
            }
            InputKind::SpeakerMean if voiced => {
                let st = super::metrics::f0_semitones(frame.f0_hz as f64);
                let (f0, new_voice) = self.f0.centre(st, frame_rate_hz, NEW_SPEAKER_ST);
                // A new voice is new in its level too.
                if new_voice {
                    self.voiced_level = RunningMean::default();
                }
                // Only a new voice starts the voiced level again: a shout is the same voice.
                let level =
                    self.voiced_level
                        .centre(frame.rms_db as f64, frame_rate_hz, f64::INFINITY);
                (f0, level.0)
            }
            InputKind::SpeakerMean if frame.rms_db.is_finite() => (
                0.0,
                self.unvoiced_level
                    .centre(frame.rms_db as f64, frame_rate_hz, NEW_ROOM_DB)
                    .0,
            ),
            InputKind::SpeakerMean => (0.0, f64::NEG_INFINITY),
        };
        ModelInput {
            voiced,
            f0_st: f0.clamp(self.f0_range[0], self.f0_range[1]),
            level_db: level.clamp(self.level_range[0], self.level_range[1]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::head::model_file::Normalisation;

    fn frame(voiced: bool, f0_hz: f32, rms_db: f32) -> FeatureFrame {
        FeatureFrame {
            voiced,
            f0_hz,
            rms_db,
            // The analyzer's own normalisation, deliberately off: the speaker-mean inputs
            // must not read it.
            f0_st: 5.0,
            level_db: 7.0,
            ..FeatureFrame::default()
        }
    }

    fn mean_norm() -> Normalisation {
        Normalisation::default()
    }

    #[test]
    fn every_input_averages_zero_over_a_steady_speaker() {
        // A low voice alternating 90 / 110 Hz, voiced at −20 and −14 dBFS, pauses at −50 dBFS:
        // after the first frames every input is centred on the speaker's own means.
        let mut t = mean_norm().input_tracker();
        let mut sums = [0.0; 3];
        for i in 0..12_000 {
            let hi = i % 40 < 20;
            let voiced = i % 100 < 60;
            let f = if voiced {
                frame(
                    true,
                    if hi { 110.0 } else { 90.0 },
                    if hi { -14.0 } else { -20.0 },
                )
            } else {
                frame(false, 0.0, if hi { -48.0 } else { -52.0 })
            };
            let x = t.next(&f, 120.0);
            assert_eq!(x.voiced, voiced);
            if i >= 2400 {
                let k = if voiced { 0 } else { 2 };
                sums[k] += if voiced { x.f0_st } else { x.level_db };
                if voiced {
                    sums[1] += x.level_db;
                }
            }
        }
        let voiced_n = 9600.0 * 0.6;
        let unvoiced_n = 9600.0 * 0.4;
        let means = [sums[0] / voiced_n, sums[1] / voiced_n, sums[2] / unvoiced_n];
        assert!(means.iter().all(|m| m.abs() < 0.1), "{means:?}");
    }

    #[test]
    fn a_long_silence_settles_to_an_ordinary_level_and_bad_frames_teach_nothing() {
        let mut t = mean_norm().input_tracker();
        for _ in 0..600 {
            t.next(&frame(true, 200.0, -20.0), 120.0);
            t.next(&frame(false, 0.0, -45.0), 120.0);
        }
        // Digital silence: far below the pauses at first (clamped to the range's floor) ...
        let first = t.next(&frame(false, 0.0, -120.0), 120.0);
        assert_eq!(first.level_db, mean_norm().level_db_range[0]);
        // ... and an ordinary level once the silence has lasted a few time constants.
        let mut last = first;
        for _ in 0..(5.0 * CENTRING_TIME_S * 120.0) as usize {
            last = t.next(&frame(false, 0.0, -120.0), 120.0);
        }
        assert!(last.level_db.abs() < 1.0, "{last:?}");
        let before = t.clone();
        let nan = t.next(&frame(false, 0.0, f32::NAN), 120.0);
        assert!(!nan.voiced && nan.level_db == mean_norm().level_db_range[0]);
        assert_eq!(t, before);
    }

    /// Mean f0 and level inputs over `seconds` of a voice at `f0_hz` and `rms_db` (voiced
    /// 60 % of the frames, pauses at `pause_db`), after `t` has heard what came before.
    fn voice_means(
        t: &mut InputTracker,
        seconds: f64,
        (f0_hz, rms_db, pause_db): (f32, f32, f32),
    ) -> [f64; 3] {
        let (mut sums, mut counts) = ([0.0; 3], [0.0; 3]);
        for i in 0..(seconds * 120.0) as usize {
            // Intonation: ±2 semitones over a second, ±3 dB.
            let swing = ((i % 120) as f32 / 120.0 * std::f32::consts::TAU).sin();
            let voiced = i % 100 < 60;
            let f = if voiced {
                frame(
                    true,
                    f0_hz * 2f32.powf(2.0 * swing / 12.0),
                    rms_db + 3.0 * swing,
                )
            } else {
                frame(false, 0.0, pause_db + swing)
            };
            let x = t.next(&f, 120.0);
            let k = if voiced { [0, 1] } else { [2, 2] };
            sums[k[0]] += if voiced { x.f0_st } else { x.level_db };
            sums[1] += if voiced { x.level_db } else { 0.0 };
            counts[k[0]] += 1.0;
            counts[1] += if voiced { 1.0 } else { 0.0 };
        }
        std::array::from_fn(|k| sums[k] / counts[k])
    }

    #[test]
    fn a_new_voice_is_centred_within_seconds_not_half_a_minute() {
        // A high voice for a minute, then a low, louder one (an octave down, 12 dB up): the
        // low voice's inputs average near 0 from a few seconds after it starts.
        let mut t = mean_norm().input_tracker();
        voice_means(&mut t, 60.0, (220.0, -26.0, -50.0));
        voice_means(&mut t, 5.0, (110.0, -14.0, -50.0));
        let after = voice_means(&mut t, 10.0, (110.0, -14.0, -50.0));
        assert!(after[0].abs() < 1.0 && after[1].abs() < 1.5, "{after:?}");
        // A speaker's own intonation starts nothing again: the same voice for a minute
        // averages 0 as before.
        let mut t = mean_norm().input_tracker();
        voice_means(&mut t, 10.0, (220.0, -26.0, -50.0));
        let same = voice_means(&mut t, 50.0, (220.0, -26.0, -50.0));
        assert!(same.iter().all(|m| m.abs() < 0.2), "{same:?}");
    }

    #[test]
    fn one_speakers_intonation_and_a_shout_start_nothing_again() {
        // Phrase-level drift of ±3.5 semitones over 8 s: no restart of the f0 mean in five
        // minutes.
        let mut f0 = RunningMean::default();
        let mut restarts = 0;
        for i in 0..(300.0 * 72.0) as usize {
            let t = i as f64 / 72.0;
            let st = 3.5 * (std::f64::consts::TAU * t / 8.0).sin();
            restarts += usize::from(f0.centre(st, 72.0, NEW_SPEAKER_ST).1);
        }
        assert_eq!(restarts, 0);
        // 8 s of a voice raised 15 dB starts the level mean nothing again.
        let mut t = mean_norm().input_tracker();
        voice_means(&mut t, 30.0, (220.0, -26.0, -50.0));
        voice_means(&mut t, 8.0, (220.0, -11.0, -50.0));
        let after = voice_means(&mut t, 2.0, (220.0, -26.0, -50.0));
        // After it the level reads a few dB low, as a running mean does, not as a restart on
        // the raised voice would (about -13 dB).
        assert!(after[1] > -6.0, "{after:?}");
    }

    #[test]
    fn pauses_after_a_long_silence_are_ordinary_pauses_within_seconds() {
        // Speech, 25 s of digital silence, speech again: its pauses (the room, 70 dB over the
        // silence) read as ordinary pause levels within seconds, not 70 dB loud for half a
        // minute.
        let mut t = mean_norm().input_tracker();
        voice_means(&mut t, 30.0, (220.0, -26.0, -50.0));
        voice_means(&mut t, 25.0, (0.0, -120.0, -120.0));
        voice_means(&mut t, 5.0, (110.0, -26.0, -50.0));
        let after = voice_means(&mut t, 10.0, (110.0, -26.0, -50.0));
        assert!(after[2].abs() < 1.5, "{after:?}");
    }

    #[test]
    fn older_models_read_the_analyzer_normalisation() {
        let mut norm = mean_norm();
        norm.f0 = SPEAKER_MEDIAN_NAMES.0.into();
        norm.level = SPEAKER_MEDIAN_NAMES.1.into();
        let mut t = norm.input_tracker();
        let x = t.next(&frame(true, 200.0, -20.0), 120.0);
        assert_eq!((x.f0_st, x.level_db), (5.0, 7.0));
    }
}
