//! What a render found out about its input that the user should know, though nothing failed
//! (the exit status stays 0): no speech at all, mostly something else than speech (music,
//! singing, noise), channels that cancel when mixed to mono, an input that holds no signal
//! (digital silence or dither), or an input so quiet that the voicing cannot hear most of its
//! speech. Each is a [`Finding`]: a line of the summary (`warning: …`) and a short word in the
//! batch table.
//!
//! The channel check ([`ChannelEnergy`]) sums each channel's power and the power of their mean
//! (the mono mix the engine analyses) while the blocks pass; the speech figures come from the
//! engine ([`SpeechSummary`]).

use pneuma_core::engine::{SpeechSummary, MAX_CHANNELS};
use pneuma_core::settings::analysis::SILENCE_DB;

/// The mono mix is this far under the channels' mean power: they cancel, dB.
const ANTIPHASE_DB: f64 = 20.0;
/// Channels quieter than this hold nothing to cancel, dBFS (mean power).
const SILENT_CHANNEL_DB: f64 = -90.0;
/// An input whose peak lies less than this over the voicing's silence level (`silence_db`:
/// frames under it are never voiced) is quiet, dB. A voice's peak stands 15–21 dB over the
/// median RMS of its voiced frames on the speech of `../shared/data`, so at this margin the
/// median voiced frame lies about 10 dB over the silence level and the softer ones under it.
const SPEECH_CREST_DB: f64 = 30.0;
/// Less speech than this share of the frames with sound: no speech found.
const NO_SPEECH_SHARE: f64 = 0.01;
/// Less speech than this share of the frames with sound: mostly not speech.
const MOSTLY_OTHER_SHARE: f64 = 0.5;

/// Something the user should know about a render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Finding {
    /// The channels cancel when mixed to mono.
    Antiphase,
    /// No speech was heard (silence, music, noise): no breath was placed.
    NoSpeech,
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
    },
    /// The input's peak lies so low that the voicing hears little of any speech in it.
    Quiet {
        /// The mono mix's peak, dBFS.
        peak_db: f64,
    },
}

/// The quietest peak at which speech is heard in full, dBFS.
fn quiet_peak_db() -> f64 {
    f64::from(SILENCE_DB.default) + SPEECH_CREST_DB
}

/// A 16-bit file's least step, full scale.
const STEP_16_BIT: f64 = 1.0 / 32768.0;
/// Peaks under this many 16-bit steps are dither: an export of silence with TPDF dither
/// rounds to one step (sox's default, −90 dBFS) or two (−84 dBFS); four leave 6 dB over that
/// and lie 26 dB under the quietest speech the measurements render (a Keele take 30 dB down,
/// peak −52 dBFS). A 24-bit or float file that low may hold a real signal, 78 dB under full
/// scale; noise-shaped dither (up to −54 dBFS) is not told apart by its peak and is said quiet.
const DITHER_PEAK_STEPS: f64 = 4.0;

/// The peak under which an input holds no signal (silence or dither only), dBFS: −78 dBFS.
/// Normalising such an input would raise its dither to full-scale noise.
fn no_signal_peak_db() -> f64 {
    20.0 * (DITHER_PEAK_STEPS * STEP_16_BIT).log10()
}

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
            Finding::NoSpeech => "no speech found (silence, music or noise): breaths go only \
                 into the pauses of speech, so none was inserted"
                .into(),
            Finding::MostlyNotSpeech { speech_share } => format!(
                "mostly music or other sound that is not speech (speech in {:.0} % of the time \
                 with sound): breaths went only into the pauses of the speech",
                100.0 * speech_share
            ),
            Finding::NoSignal { peak_db } if peak_db.is_finite() => format!(
                "the input holds no signal (silence or dither only, peak {peak_db:.0} dBFS): \
                 there is no speech to place breaths by, and normalising it would only make \
                 the dither loud; check that the right file (or channel) was exported"
            ),
            Finding::NoSignal { .. } => "the input holds no signal (digital silence: every \
                 sample is zero): there is no speech to place breaths by; check that the right \
                 file (or channel) was exported"
                .into(),
            Finding::Quiet { peak_db } => format!(
                "the input is very quiet (its peak lies at {peak_db:.0} dBFS): frames under \
                 {:.0} dBFS are never voiced, so much of its speech goes unheard; normalise it \
                 first (e.g. `sox IN OUT gain -n -1`) and render it again",
                SILENCE_DB.default
            ),
        }
    }

    /// The batch table's word.
    pub fn short(&self) -> &'static str {
        match self {
            Finding::Antiphase => "antiphase",
            Finding::NoSpeech => "no speech",
            Finding::MostlyNotSpeech { .. } => "mostly music",
            Finding::NoSignal { .. } => "no signal",
            Finding::Quiet { .. } => "quiet",
        }
    }
}

/// Each channel's power and the power of the mono mix, summed over the input.
#[derive(Debug, Clone, Copy, Default)]
pub struct ChannelEnergy {
    channels: usize,
    sum_sq: [f64; MAX_CHANNELS],
    mix_sq: f64,
    /// Largest magnitude of the mono mix.
    mix_peak: f64,
    frames: u64,
}

impl ChannelEnergy {
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
                let x = f64::from(chan[i]);
                self.sum_sq[c] += x * x;
                mix += x;
            }
            mix /= channels as f64;
            self.mix_sq += mix * mix;
            self.mix_peak = self.mix_peak.max(mix.abs());
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
}

/// The findings of a render: the channels, then the level, then the speech (a quiet input's
/// speech findings follow from its level, and are left out).
pub fn findings(energy: &ChannelEnergy, speech: &SpeechSummary) -> Vec<Finding> {
    if energy.antiphase() {
        return vec![Finding::Antiphase];
    }
    let peak_db = energy.peak_db();
    // Silence or dither is no quiet speech: normalising it would make it noise.
    if peak_db < no_signal_peak_db() {
        return vec![Finding::NoSignal { peak_db }];
    }
    if peak_db < quiet_peak_db() {
        return vec![Finding::Quiet { peak_db }];
    }
    let share = if speech.sound_frames == 0 {
        0.0
    } else {
        speech.speech_frames as f64 / speech.sound_frames as f64
    };
    if share < NO_SPEECH_SHARE || speech.speech_phrases == 0 {
        vec![Finding::NoSpeech]
    } else if share < MOSTLY_OTHER_SHARE {
        vec![Finding::MostlyNotSpeech {
            speech_share: share,
        }]
    } else {
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn energy(left: &[f32], right: &[f32]) -> ChannelEnergy {
        let mut e = ChannelEnergy::default();
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
        let mut mono = ChannelEnergy::default();
        mono.add(std::slice::from_ref(&x), x.len());
        assert!(!mono.antiphase());
    }

    /// A mono tone peaking at `peak`.
    fn tone(peak: f32) -> ChannelEnergy {
        let x: Vec<f32> = (0..4800).map(|i| (i as f32 * 0.05).sin() * peak).collect();
        let mut e = ChannelEnergy::default();
        e.add(std::slice::from_ref(&x), x.len());
        e
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
        assert_eq!(findings(&e, &s(0, 0, 0)), [Finding::NoSpeech]);
        assert_eq!(findings(&e, &s(900, 5, 1)), [Finding::NoSpeech]);
        assert_eq!(findings(&e, &s(900, 300, 0)), [Finding::NoSpeech]);
        assert_eq!(
            findings(&e, &s(900, 300, 3)),
            [Finding::MostlyNotSpeech {
                speech_share: 300.0 / 900.0
            }]
        );
        assert_eq!(findings(&e, &s(900, 700, 8)), []);
        assert!(Finding::Antiphase.message().contains("render one channel"));
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
        let quiet = findings(&tone(0.005), &speech);
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
        assert_eq!(findings(&tone(0.25), &speech), [Finding::NoSpeech]);
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
        let step = STEP_16_BIT as f32;
        for (peak, said) in [(step, "peak -90 dBFS"), (2.0 * step, "peak -84 dBFS")] {
            let found = findings(&tone(peak), &speech);
            assert!(matches!(found[..], [Finding::NoSignal { .. }]), "{found:?}");
            let m = found[0].message();
            assert!(m.contains("holds no signal (silence or dither only") && m.contains(said));
            assert!(!m.contains("normalise it"), "{m}");
            assert_eq!(found[0].short(), "no signal");
        }
        let zeros = findings(&tone(0.0), &speech);
        assert!(matches!(zeros[..], [Finding::NoSignal { .. }]), "{zeros:?}");
        assert!(zeros[0].message().contains("every sample is zero"));
        // Eight steps (-72 dBFS) over the silence level: quiet, not nothing.
        let faint = findings(&tone(8.0 * step), &speech);
        assert!(matches!(faint[..], [Finding::Quiet { .. }]), "{faint:?}");
    }
}
