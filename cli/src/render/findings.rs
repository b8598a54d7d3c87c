//! What a render found out about its input that the user should know, though nothing failed
//! (the exit status stays 0): no speech at all, mostly something else than speech (music,
//! singing, noise), channels that cancel when mixed to mono, an input that holds no signal
//! (digital silence or dither, noise-shaped too), an input too short to tell speech in, or an
//! input so quiet that the voicing cannot hear most of its speech, samples that are not numbers
//! (NaN, ±∞ in a float file: the engine hears and writes them as 0), speech that ran out of air
//! with no pause to breathe in (breaths cut with their pauses). Each is a [`Finding`]: a line of
//! the summary (`warning: …`) and a short word in the batch table.
//!
//! The channel check ([`ChannelEnergy`]) sums each channel's power and the power of their mean
//! (the mono mix the engine analyses) while the blocks pass; the speech figures come from the
//! engine ([`SpeechSummary`]).

use pneuma_core::analysis::{no_signal_peak_db, quiet_peak_db, Biquad};
use pneuma_core::breathing::{RESERVE_DECAY_S, RESERVE_LUNG};
use pneuma_core::engine::{SpeechSummary, MAX_CHANNELS};
use pneuma_core::settings::analysis::SILENCE_DB;
use pneuma_core::speech::JUDGE_WINDOW_S;

/// The mono mix is this far under the channels' mean power: they cancel, dB.
const ANTIPHASE_DB: f64 = 20.0;
/// Channels quieter than this hold nothing to cancel, dBFS (mean power).
const SILENT_CHANNEL_DB: f64 = -90.0;
/// The lung under this is drawn past its reserve: the speech has run on well past its breath
/// group's plan (about 3.5 s at the reserve's time constant [`RESERVE_DECAY_S`]).
const OUT_OF_AIR_LUNG: f32 = RESERVE_LUNG / 2.0;
/// Speech with the lung under [`OUT_OF_AIR_LUNG`] for this long before a breath fills it again
/// is told, seconds: the reserve's own time constant. Not fitted: at most 0.9 s on the speech
/// files tried (Keele's ten voices, the seven styletalk clips, the example voice, PTDB takes in
/// noise); 8 s on the Keele voices whose breaths were cut with their pauses and got none back.
const OUT_OF_AIR_S: f64 = RESERVE_DECAY_S as f64;

/// What to do when the sound is a voice that the speech decision does not take for speech.
const ANY_VOICE: &str = "if it is a voice all the same (through a voice changer, sung), render \
     it with --any-sound";

/// Something the user should know about a render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Finding {
    /// The channels cancel when mixed to mono.
    Antiphase,
    /// No speech was heard (silence, music, noise): no breath was placed.
    NoSpeech {
        /// Phrases of voiced sound were heard (and judged not speech).
        phrases: bool,
    },
    /// Speech in only this share of the time with sound.
    MostlyNotSpeech {
        /// Share of the frames with sound that are speech, 0..1.
        speech_share: f64,
    },
    /// The input holds no signal: its peak lies at the level of dither (digital silence, or
    /// the dither of an export of silence).
    NoSignal {
        /// The mono mix's peak, dBFS (−∞ when every sample is zero).
        peak_db: f64,
        /// Its sound lies above this only (noise-shaped dither), Hz ([`VOICE_BAND_TOP_HZ`] or
        /// under it at low rates); `None` for silence or plain dither.
        shaped_above_hz: Option<f64>,
    },
    /// No speech was heard in an input shorter than the speech decision's window
    /// ([`JUDGE_WINDOW_S`]): too short to tell.
    TooShort {
        /// The input's length, seconds.
        length_s: f64,
    },
    /// The input's peak lies so low that the voicing hears little of any speech in it.
    Quiet {
        /// The mono mix's peak, dBFS.
        peak_db: f64,
    },
    /// Samples that are NaN or ±∞ (a float file's), heard and written as 0.
    NonFinite {
        /// How many, over the channels rendered.
        samples: u64,
        /// Every other sample is zero: the output is silence.
        rest_silent: bool,
    },
    /// The `--breath-like` file holds little or no speech (music, noise, another sound): a
    /// breath voice learned from it is not the speaker's.
    BreathLikeNotSpeech {
        /// Share of its frames with sound that are speech, 0..1.
        speech_share: f64,
        /// Too little to learn from: the voice was not learned from it.
        unused: bool,
    },
    /// Speech went on with the lung drawn past its reserve for this long before a breath: no
    /// pause was long enough, or clear enough of other sound, for a breath.
    OutOfAir {
        /// Seconds of speech with the lung under [`OUT_OF_AIR_LUNG`] in the longest such run.
        speech_s: f64,
        /// Where that run starts in the input, seconds.
        from_s: f64,
        /// The shortest breath a pause can take (a catch breath), seconds.
        catch_breath_min_s: f64,
    },
}

/// Top of the band whose peak tells a signal from noise-shaped dither, Hz: shaped dither puts
/// its power above it (a 16-bit export of silence with sox's `dither -s` peaks at −59 dBFS, its
/// power rising towards 20 kHz), while every voice holds its strongest sound under it.
const VOICE_BAND_TOP_HZ: f64 = 4_000.0;

/// The antiphase warning for a command that `verb`s the input.
pub fn antiphase_message(verb: &str) -> String {
    format!(
        "left and right are in antiphase: {verb} one channel (--channel left or --channel \
         right); mixed to mono they cancel, so nothing was heard"
    )
}

impl Finding {
    /// The summary's line (after `warning: `).
    pub fn message(&self) -> String {
        match self {
            Finding::Antiphase => antiphase_message("render"),
            Finding::NoSpeech { phrases: true } => format!(
                "no speech found (silence, music or noise): breaths go only into the pauses of \
                 speech, so none was inserted; {ANY_VOICE}"
            ),
            Finding::NoSpeech { phrases: false } => "no speech found (no voiced sound: \
                 noise, whispering or other sound): breaths go only into the pauses between \
                 phrases of voiced speech, so none was inserted"
                .into(),
            Finding::MostlyNotSpeech { speech_share } => format!(
                "mostly music or other sound that is not speech (speech in {:.0} % of the time \
                 with sound): breaths went only into the pauses of the speech; {ANY_VOICE}",
                100.0 * speech_share
            ),
            Finding::NoSignal {
                peak_db,
                shaped_above_hz: Some(hz),
            } => format!(
                "the input holds no signal (noise-shaped dither only: peak {peak_db:.0} dBFS, \
                 all of it above {:.1} kHz): there is no speech to place breaths by, and \
                 normalising it would only make the dither loud; check that the right file \
                 (or channel) was exported",
                hz / 1000.0
            ),
            Finding::NoSignal { peak_db, .. } if peak_db.is_finite() => format!(
                "the input holds no signal (silence or dither only, peak {peak_db:.0} dBFS): \
                 there is no speech to place breaths by, and normalising it would only make \
                 the dither loud; check that the right file (or channel) was exported"
            ),
            Finding::NoSignal { .. } => "the input holds no signal (digital silence: every \
                 sample is zero): there is no speech to place breaths by; check that the right \
                 file (or channel) was exported"
                .into(),
            Finding::TooShort { length_s } => format!(
                "the input is only {length_s:.2} s long: too short to tell speech from other \
                 sound ({JUDGE_WINDOW_S} s at least) or to hold a pause, so no breath was \
                 inserted; render the whole recording, not a snippet"
            ),
            Finding::NonFinite {
                samples,
                rest_silent: false,
            } => format!(
                "{samples} samples are not numbers (NaN or infinite, a damaged float export): \
                 they were written as 0"
            ),
            Finding::NonFinite { samples, .. } => format!(
                "{samples} samples are not numbers (NaN or infinite, a damaged float export) \
                 and the others are zero: they were written as 0, so the output is silence and \
                 there is no speech to place breaths by; check that the right file was exported"
            ),
            Finding::OutOfAir {
                speech_s,
                from_s,
                catch_breath_min_s,
            } => format!(
                "the speech ran {speech_s:.1} s from {} with its air used up: no pause was long \
                 enough (a catch breath needs {catch_breath_min_s:.2} s) or clear enough of \
                 other sound for a breath. If breaths were cut out with their pauses (a ripple \
                 delete, \"shorten gaps\"), render the take before that cut: Pneuma puts \
                 breaths only into pauses and never lengthens them",
                crate::plot::time_label(*from_s, from_s.max(60.0))
            ),
            Finding::BreathLikeNotSpeech {
                speech_share,
                unused: true,
            } => format!(
                "the --breath-like file holds no speech (speech in {:.0} % of its time with \
                 sound): the breath voice was not learned from it but, as without it, from the \
                 input; give a raw take of the same speaker, breaths and all",
                100.0 * speech_share
            ),
            Finding::BreathLikeNotSpeech { speech_share, .. } => format!(
                "the --breath-like file is mostly music or other sound that is not speech \
                 (speech in {:.0} % of its time with sound): breaths heard between its other \
                 sounds went into the breath voice too; a raw take of the same speaker, breaths \
                 and all, gives the speaker's own",
                100.0 * speech_share
            ),
            Finding::Quiet { peak_db } => format!(
                "the input is very quiet (its peak lies at {peak_db:.0} dBFS): until the \
                 speaker's level is learnt, frames under {:.0} dBFS are not voiced, so soft \
                 syllables go unheard or pass for breaths, and the breaths come out louder \
                 against the speech than in the same take at a normal level; normalise it first \
                 (e.g. `sox IN OUT gain -n -1`) and render it again",
                SILENCE_DB.default
            ),
        }
    }

    /// Whether the render found no speech in its input (none heard, or too short to tell): the
    /// breath-like sounds in its pauses are no speaker's breaths.
    pub fn found_no_speech(&self) -> bool {
        matches!(self, Finding::NoSpeech { .. } | Finding::TooShort { .. })
    }

    /// The batch table's word.
    pub fn short(&self) -> &'static str {
        match self {
            Finding::Antiphase => "antiphase",
            Finding::NoSpeech { .. } => "no speech",
            Finding::MostlyNotSpeech { .. } => "mostly music",
            Finding::NoSignal { .. } => "no signal",
            Finding::TooShort { .. } => "too short",
            Finding::Quiet { .. } => "quiet",
            Finding::NonFinite { .. } => "NaN samples",
            Finding::OutOfAir { .. } => "out of air",
            Finding::BreathLikeNotSpeech { .. } => "breath-like not speech",
        }
    }
}

/// Each channel's power and the power of the mono mix, summed over the input.
#[derive(Debug, Clone, Copy)]
pub struct ChannelEnergy {
    channels: usize,
    sum_sq: [f64; MAX_CHANNELS],
    mix_sq: f64,
    /// Largest magnitude of the mono mix.
    mix_peak: f64,
    /// The mono mix under [`VOICE_BAND_TOP_HZ`] (two 2nd-order Butterworth sections, −6 dB at
    /// the corner), and its largest magnitude.
    voice_band: [Biquad; 2],
    /// The low-pass's corner, Hz.
    voice_band_top_hz: f64,
    voice_band_peak: f64,
    frames: u64,
    /// Samples that were NaN or ±∞, summed as 0 (as the engine hears them).
    non_finite: u64,
}

impl ChannelEnergy {
    /// Nothing summed yet, for an input at `rate_hz`.
    pub fn new(rate_hz: f64) -> Self {
        let corner_hz = VOICE_BAND_TOP_HZ.min(0.45 * rate_hz);
        let section = Biquad::butterworth(corner_hz, rate_hz, false);
        Self {
            channels: 0,
            sum_sq: [0.0; MAX_CHANNELS],
            mix_sq: 0.0,
            mix_peak: 0.0,
            voice_band: [section; 2],
            voice_band_top_hz: corner_hz,
            voice_band_peak: 0.0,
            frames: 0,
            non_finite: 0,
        }
    }

    /// Adds one block, one slice per channel (as the engine gets them), `n` frames.
    pub fn add(&mut self, planar: &[Vec<f32>], n: usize) {
        let channels = planar.len().min(MAX_CHANNELS);
        self.channels = channels;
        if channels == 0 {
            return;
        }
        for i in 0..n {
            let mut mix = 0.0f64;
            for (c, chan) in planar.iter().take(channels).enumerate() {
                let x = if chan[i].is_finite() {
                    f64::from(chan[i])
                } else {
                    self.non_finite += 1;
                    0.0
                };
                self.sum_sq[c] += x * x;
                mix += x;
            }
            mix /= channels as f64;
            self.mix_sq += mix * mix;
            self.mix_peak = self.mix_peak.max(mix.abs());
            let low = self.voice_band.iter_mut().fold(mix, |x, f| f.process(x));
            self.voice_band_peak = self.voice_band_peak.max(low.abs());
        }
        self.frames += n as u64;
    }

    /// The channels hold sound that cancels when mixed to mono.
    pub fn antiphase(&self) -> bool {
        if self.channels < 2 || self.frames == 0 {
            return false;
        }
        let n = self.frames as f64;
        let mean_db = |sum: f64| 10.0 * (sum / n).max(1e-30).log10();
        let channels_db = mean_db(self.sum_sq[..self.channels].iter().sum::<f64>())
            - 10.0 * (self.channels as f64).log10();
        channels_db > SILENT_CHANNEL_DB && mean_db(self.mix_sq) < channels_db - ANTIPHASE_DB
    }

    /// The mono mix's peak, dBFS (−∞ for silence or no input).
    pub fn peak_db(&self) -> f64 {
        20.0 * self.mix_peak.log10()
    }

    /// The peak of the mono mix under [`VOICE_BAND_TOP_HZ`], dBFS.
    pub fn voice_band_peak_db(&self) -> f64 {
        20.0 * self.voice_band_peak.log10()
    }
}

/// The findings of a render of `length_s` seconds: samples that are not numbers, then the
/// channels, the level and the speech (a quiet input's speech findings follow from its level,
/// and are left out). An input of only zeros and non-finite samples is said once, as such.
pub fn findings(energy: &ChannelEnergy, speech: &SpeechSummary, length_s: f64) -> Vec<Finding> {
    let rest_silent = energy.mix_peak == 0.0;
    if energy.non_finite > 0 && rest_silent {
        return vec![Finding::NonFinite {
            samples: energy.non_finite,
            rest_silent,
        }];
    }
    let non_finite = (energy.non_finite > 0).then_some(Finding::NonFinite {
        samples: energy.non_finite,
        rest_silent,
    });
    non_finite
        .into_iter()
        .chain(signal_findings(energy, speech, length_s))
        .collect()
}

/// The longest run of speech on an emptied lung ([`OUT_OF_AIR_LUNG`]), from the control
/// frames in order: a run lasts until a breath fills the lung over it again; its speaking
/// frames count.
#[derive(Debug, Clone, Copy, Default)]
pub struct AirRun {
    /// The run going on: its first frame's time and its speaking frames.
    current: Option<(f64, u64)>,
    /// The longest run so far: its first frame's time and its speaking frames.
    longest: (f64, u64),
}

impl AirRun {
    /// One control frame at `time_s`.
    pub fn frame(&mut self, time_s: f64, speaking: bool, lung: f32) {
        if lung >= OUT_OF_AIR_LUNG {
            self.current = None;
            return;
        }
        let run = self.current.get_or_insert((time_s, 0));
        run.1 += u64::from(speaking);
        if run.1 > self.longest.1 {
            self.longest = *run;
        }
    }

    /// The out-of-air finding for frames `frame_s` apart, when the longest run holds
    /// [`OUT_OF_AIR_S`] of speech or more.
    pub fn finding(&self, frame_s: f64, catch_breath_min_s: f64) -> Option<Finding> {
        let speech_s = self.longest.1 as f64 * frame_s;
        (speech_s >= OUT_OF_AIR_S).then_some(Finding::OutOfAir {
            speech_s,
            from_s: self.longest.0,
            catch_breath_min_s,
        })
    }
}

/// The findings of the channels, the level and the speech.
fn signal_findings(energy: &ChannelEnergy, speech: &SpeechSummary, length_s: f64) -> Vec<Finding> {
    if energy.antiphase() {
        return vec![Finding::Antiphase];
    }
    let peak_db = energy.peak_db();
    // Silence or dither is no quiet speech: normalising it would make it noise. Noise-shaped
    // dither peaks higher, with nothing in the voice's band.
    if peak_db < no_signal_peak_db() {
        return vec![Finding::NoSignal {
            peak_db,
            shaped_above_hz: None,
        }];
    }
    if peak_db < quiet_peak_db() && energy.voice_band_peak_db() < no_signal_peak_db() {
        return vec![Finding::NoSignal {
            peak_db,
            shaped_above_hz: Some(energy.voice_band_top_hz),
        }];
    }
    if peak_db < quiet_peak_db() {
        return vec![Finding::Quiet { peak_db }];
    }
    if speech.holds_no_speech() && length_s < JUDGE_WINDOW_S {
        vec![Finding::TooShort { length_s }]
    } else if speech.holds_no_speech() {
        vec![Finding::NoSpeech {
            phrases: speech.phrases > 0,
        }]
    } else if speech.mostly_other() {
        vec![Finding::MostlyNotSpeech {
            speech_share: speech.speech_share(),
        }]
    } else {
        Vec::new()
    }
}

/// What the speech of a `--breath-like` file says about learning the breath voice from it:
/// nothing when it is mostly speech, a note when it is mostly something else, and `unused`
/// when it holds no speech (as [`findings`] would say of it rendered).
pub fn breath_like_finding(speech: &SpeechSummary) -> Option<Finding> {
    let unused = speech.holds_no_speech();
    (unused || speech.mostly_other()).then_some(Finding::BreathLikeNotSpeech {
        speech_share: speech.speech_share(),
        unused,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A render long enough for the speech decision, seconds.
    const LONG_S: f64 = 10.0;
    /// No speech, with phrases heard (the summaries below all hold 10).
    const NO_SPEECH: Finding = Finding::NoSpeech { phrases: true };

    fn energy(left: &[f32], right: &[f32]) -> ChannelEnergy {
        let mut e = ChannelEnergy::new(48_000.0);
        e.add(&[left.to_vec(), right.to_vec()], left.len());
        e
    }

    #[test]
    fn channels_that_cancel_are_antiphase_and_others_are_not() {
        let x: Vec<f32> = (0..4800).map(|i| (i as f32 * 0.05).sin() * 0.3).collect();
        let minus: Vec<f32> = x.iter().map(|v| -v).collect();
        let half: Vec<f32> = x.iter().map(|v| -0.5 * v).collect();
        let silent = vec![0.0f32; x.len()];
        assert!(energy(&x, &minus).antiphase());
        // Partly cancelling (6 dB down) or one silent channel is not antiphase.
        assert!(!energy(&x, &half).antiphase());
        assert!(!energy(&x, &silent).antiphase());
        assert!(!energy(&silent, &silent).antiphase());
        let mut mono = ChannelEnergy::new(48_000.0);
        mono.add(std::slice::from_ref(&x), x.len());
        assert!(!mono.antiphase());
    }

    /// A mono tone peaking at `peak`.
    fn tone(peak: f32) -> ChannelEnergy {
        let x: Vec<f32> = (0..4800).map(|i| (i as f32 * 0.05).sin() * peak).collect();
        let mut e = ChannelEnergy::new(48_000.0);
        e.add(std::slice::from_ref(&x), x.len());
        e
    }

    #[test]
    fn speech_out_of_air_for_the_reserves_time_constant_is_told() {
        // 100 frames a second; the lung under half its reserve while speaking in two runs of
        // 3 s (with a pause inside the first that brings no breath) parted by a breath: 3 s at
        // most, not told; then one run of 8 s from 20 s.
        let frame_s = 0.01;
        let mut air = AirRun::default();
        let mut feed = |from_s: f64, to_s: f64, speaking: bool, lung: f32| {
            let (a, b) = ((from_s / frame_s) as u64, (to_s / frame_s) as u64);
            for k in a..b {
                air.frame(k as f64 * frame_s, speaking, lung);
            }
            air
        };
        feed(0.0, 1.5, true, 0.3);
        feed(1.5, 3.0, true, 0.02);
        feed(3.0, 3.5, false, 0.02);
        feed(3.5, 5.0, true, 0.02);
        feed(5.0, 5.5, false, 0.5);
        let short = feed(5.5, 8.5, true, 0.02);
        assert_eq!(short.finding(frame_s, 0.15), None);
        assert_eq!(
            feed(10.0, 20.0, true, 0.5).finding(frame_s, 0.15),
            None,
            "a full lung"
        );
        let f = feed(20.0, 28.0, true, 0.01)
            .finding(frame_s, 0.15)
            .expect("told");
        let Finding::OutOfAir {
            speech_s, from_s, ..
        } = f
        else {
            panic!("{f:?}")
        };
        assert!(
            (speech_s - 8.0).abs() < 0.02 && (from_s - 20.0).abs() < 0.02,
            "{f:?}"
        );
        assert_eq!(f.short(), "out of air");
        let m = f.message();
        for words in [
            "ran 8.0 s from 0:20",
            "needs 0.15 s",
            "ripple delete",
            "never lengthens",
        ] {
            assert!(m.contains(words), "{words}: {m}");
        }
    }

    #[test]
    fn speech_shares_give_no_speech_mostly_music_or_nothing() {
        let s = |sound_frames, speech_frames, speech_phrases| SpeechSummary {
            frames: 1000,
            sound_frames,
            speech_frames,
            phrases: 10,
            speech_phrases,
        };
        let e = tone(0.25);
        assert_eq!(findings(&e, &s(0, 0, 0), LONG_S), [NO_SPEECH]);
        assert_eq!(findings(&e, &s(900, 5, 1), LONG_S), [NO_SPEECH]);
        assert_eq!(findings(&e, &s(900, 300, 0), LONG_S), [NO_SPEECH]);
        assert_eq!(
            findings(&e, &s(900, 300, 3), LONG_S),
            [Finding::MostlyNotSpeech {
                speech_share: 300.0 / 900.0
            }]
        );
        assert_eq!(findings(&e, &s(900, 700, 8), LONG_S), []);
        // No speech in a snippet shorter than the decision's window: too short, not no speech.
        let short = findings(&e, &s(3, 0, 0), 0.03);
        assert_eq!(short, [Finding::TooShort { length_s: 0.03 }]);
        assert!(
            short[0].message().contains("only 0.03 s long"),
            "{}",
            short[0].message()
        );
        // Speech heard in a short input is no finding.
        assert_eq!(findings(&e, &s(30, 25, 1), 0.3), []);
        assert!(Finding::Antiphase.message().contains("render one channel"));
        assert!(NO_SPEECH.message().ends_with("render it with --any-sound"));
        // No phrase at all (nothing voiced): --any-sound would change nothing.
        let no_phrase = SpeechSummary {
            phrases: 0,
            ..s(900, 0, 0)
        };
        assert_eq!(
            findings(&e, &no_phrase, LONG_S),
            [Finding::NoSpeech { phrases: false }]
        );
        let none = Finding::NoSpeech { phrases: false }.message();
        assert!(
            none.contains("no voiced sound") && !none.contains("--any-sound"),
            "{none}"
        );
    }

    #[test]
    fn a_quiet_input_is_said_before_its_speech_and_silence_is_not_quiet() {
        let speech = SpeechSummary {
            frames: 1000,
            sound_frames: 900,
            speech_frames: 5,
            phrases: 10,
            speech_phrases: 1,
        };
        // Peak -46 dBFS: quiet; the speech finding it causes is left out.
        let quiet = findings(&tone(0.005), &speech, LONG_S);
        assert!(
            matches!(quiet[..], [Finding::Quiet { peak_db }] if (peak_db + 46.0).abs() < 0.1),
            "{quiet:?}"
        );
        assert!(
            quiet[0].message().contains("normalise it"),
            "{}",
            quiet[0].message()
        );
        // Peak -12 dBFS: the speech finding as before.
        assert_eq!(findings(&tone(0.25), &speech, LONG_S), [NO_SPEECH]);
    }

    #[test]
    fn samples_that_are_not_numbers_are_counted_and_never_called_zero() {
        let speech = SpeechSummary::default();
        let mut nan = ChannelEnergy::new(48_000.0);
        nan.add(&[vec![f32::NAN; 480]], 480);
        let found = findings(&nan, &speech, LONG_S);
        let expected = Finding::NonFinite {
            samples: 480,
            rest_silent: true,
        };
        assert_eq!(found, vec![expected]);
        assert!(!found[0].message().contains("every sample is zero"));
        let mut some = tone(0.5);
        some.add(&[vec![f32::INFINITY, f32::NAN]], 2);
        let found = findings(&some, &speech, LONG_S);
        assert!(
            found[0].message().starts_with("2 samples are not numbers"),
            "{found:?}"
        );
        assert!(found[0].message().ends_with("written as 0"), "{found:?}");
    }

    #[test]
    fn silence_and_dither_hold_no_signal_and_are_not_told_to_normalise() {
        let speech = SpeechSummary {
            frames: 1000,
            sound_frames: 0,
            speech_frames: 0,
            phrases: 0,
            speech_phrases: 0,
        };
        // 16-bit TPDF dither of silence: one or two steps (-90.3, -84.3 dBFS); all zeros.
        let step = 1.0 / 32768.0f32;
        for (peak, said) in [(step, "peak -90 dBFS"), (2.0 * step, "peak -84 dBFS")] {
            let found = findings(&tone(peak), &speech, LONG_S);
            assert!(matches!(found[..], [Finding::NoSignal { .. }]), "{found:?}");
            let m = found[0].message();
            assert!(m.contains("holds no signal (silence or dither only") && m.contains(said));
            assert!(!m.contains("normalise it"), "{m}");
            assert_eq!(found[0].short(), "no signal");
        }
        let zeros = findings(&tone(0.0), &speech, LONG_S);
        assert!(matches!(zeros[..], [Finding::NoSignal { .. }]), "{zeros:?}");
        assert!(zeros[0].message().contains("every sample is zero"));
        // Noise-shaped dither (white noise differenced twice: its power rises 12 dB per octave
        // to the Nyquist frequency) peaking at -59 dBFS holds no signal; a voice-band tone at
        // that peak is quiet.
        let mut seed = 1u32;
        let white: Vec<f32> = (0..48_000)
            .map(|_| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (seed >> 8) as f32 / (1u32 << 24) as f32 - 0.5
            })
            .collect();
        let shaped: Vec<f32> = white.windows(3).map(|w| w[2] - 2.0 * w[1] + w[0]).collect();
        let top = shaped.iter().fold(0.0f32, |m, v| m.max(v.abs()));
        let at = 10f32.powf(-59.0 / 20.0) / top;
        let shaped: Vec<f32> = shaped.iter().map(|v| v * at).collect();
        let mut e = ChannelEnergy::new(48_000.0);
        e.add(std::slice::from_ref(&shaped), shaped.len());
        let found = findings(&e, &speech, LONG_S);
        assert!(
            matches!(found[..], [Finding::NoSignal { shaped_above_hz: Some(hz), .. }] if hz == 4e3),
            "{found:?}"
        );
        assert!(found[0]
            .message()
            .contains("noise-shaped dither only: peak -59 dBFS"));
        let voice_band = findings(&tone(10f32.powf(-59.0 / 20.0)), &speech, LONG_S);
        assert!(
            matches!(voice_band[..], [Finding::Quiet { .. }]),
            "{voice_band:?}"
        );
        // Eight steps (-72 dBFS) over the silence level: quiet, not nothing.
        let faint = findings(&tone(8.0 * step), &speech, LONG_S);
        assert!(matches!(faint[..], [Finding::Quiet { .. }]), "{faint:?}");
    }
}
