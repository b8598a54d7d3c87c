//! The sources of the podcast recipe (`../shared/data`, never copied into the repository): the
//! speech clips with their speech truth per 10 ms frame, and the music pieces, all at 16 kHz.
//!
//! ## Speech truth (issue 30), from the clean clip before mixing
//! A frame is speech when it lies within [`NEAR_VOICING_FRAMES`] (80 ms) of the reference
//! voicing and holds sound, or when its level is within [`NEAR_SPEECH_LEVEL_DB`] (15 dB) of the
//! clip's speech level.
//! - Reference voicing: the Keele and PTDB laryngograph f0 files (`f0 > 0`), their times moved
//!   by [`REFERENCE_OFFSET_S`] (the data README: the references sit 10–15 ms early), the
//!   reference frame nearest the frame's centre if within 5.1 ms; Keele's `f0 = −1` (uncertain)
//!   counts as unvoiced, and such a frame is left out of every score unless it lies within
//!   80 ms of voicing. Styletalk has no reference: Praat's autocorrelation pitch (10 ms step,
//!   75–500 Hz, its default voicing threshold) on the clean clip, through parselmouth.
//! - Frame level: 10·log10 of the mean square of the frame's 160 samples, dBFS.
//! - Speech level: 10·log10 of the mean power of the reference-voiced frames.
//! - Holds sound: level ≥ max(floor + 6 dB, speech level − 40 dB), floor = the clip's 10th
//!   percentile frame level.

use std::path::Path;

use pneuma_core::speech::resample::resample_to_16k;

/// Praat's pitch track of a 16 kHz signal: `(time_s, f0_hz)` frames, f0 0 when unvoiced.
pub type Praat<'a> = dyn FnMut(&[f32]) -> Result<Vec<(f64, f64)>, String> + 'a;

/// The mixing rate, Hz.
pub const RATE_HZ: f64 = 16_000.0;
/// Samples per label frame (10 ms).
pub const HOP: usize = 160;
/// Label frames per second.
pub const FRAMES_PER_S: f64 = RATE_HZ / HOP as f64;
/// Shift of the laryngograph references' times, seconds.
pub const REFERENCE_OFFSET_S: f64 = 0.012;
/// A reference frame counts for a label frame within this of its centre, seconds.
const REFERENCE_MATCH_S: f64 = 0.0051;
/// Frames either side of reference voicing that count as near it (80 ms).
pub const NEAR_VOICING_FRAMES: usize = 8;
/// Frames this close to the speech level are speech whatever the voicing, dB.
pub const NEAR_SPEECH_LEVEL_DB: f64 = 15.0;
/// "Holds sound": this far over the clip's floor …
const OVER_FLOOR_DB: f64 = 6.0;
/// … and no further than this under its speech level, dB.
const UNDER_SPEECH_DB: f64 = 40.0;

/// The Keele voices.
pub const KEELE: [&str; 10] = [
    "f1nw0000", "f2nw0000", "f3nw0000", "f4nw0000", "f5nw0000", "m1nw0000", "m2nw0000", "m3nw0000",
    "m4nw0000", "m5nw0000",
];
/// PTDB: one 40 dB clip per speaker (a speaker's four 40 dB clips hold the same utterance).
pub const PTDB: [&str; 2] = ["male1car40", "female2car40"];
/// The styletalk clips.
pub const STYLETALK: [&str; 7] = [
    "Obama_clip1",
    "Obama_clip3",
    "andrew_clip_1",
    "andrew_clip_2",
    "feifeili_clip1",
    "feifeili_clip2_short",
    "feifeili_clip3",
];

/// The music pieces (`../shared/data/music/<name>.flac`).
pub const MUSIC: [&str; 6] = [
    "vibe_ace",
    "hungarian_dance_5",
    "humpback_whale",
    "solo_trumpet",
    "robin",
    "lets_go_fishin",
];
/// The sung piece: judged held out, never fitted on.
pub const SUNG_PIECE: &str = "lets_go_fishin";
/// Its sections that hold a sung voice, seconds (by inspection of its spectrogram: glides of
/// sung harmonics with consonant onsets; not annotated by its authors).
pub const SUNG_SECTIONS_S: [(f64, f64); 6] = [
    (11.0, 17.5),
    (21.5, 28.0),
    (33.0, 55.0),
    (63.8, 70.5),
    (74.8, 81.0),
    (86.0, 112.0),
];
/// The clearest of them, which the sung passages take.
pub const CLEAR_SUNG_S: [(f64, f64); 4] = [(11.0, 17.5), (21.5, 28.0), (63.8, 70.5), (74.8, 81.0)];
/// Its instrumental sections, which its intros and outros take.
pub const INSTRUMENTAL_S: [(f64, f64); 2] = [(0.0, 10.8), (113.0, 128.0)];

/// Every speech clip, in a fixed order.
pub fn clips() -> Vec<&'static str> {
    KEELE
        .iter()
        .chain(&PTDB)
        .chain(&STYLETALK)
        .copied()
        .collect()
}

/// The speaker of a clip (styletalk clips share speakers).
pub fn speaker_of(clip: &str) -> String {
    if KEELE.contains(&clip) {
        format!("keele_{}", &clip[..2])
    } else if PTDB.contains(&clip) {
        format!("ptdb_{}", clip.trim_end_matches("car40"))
    } else {
        format!("styletalk_{}", clip.split('_').next().unwrap_or(clip))
    }
}

/// A clean speech clip at 16 kHz (a whole number of label frames) with its truth.
#[derive(Debug, Clone)]
pub struct SpeechClip {
    /// The clip's name.
    pub name: String,
    /// Its speaker.
    pub speaker: String,
    /// The audio, 16 kHz.
    pub audio: Vec<f32>,
    /// Speech truth per label frame.
    pub truth: Vec<bool>,
    /// Frames within [`NEAR_VOICING_FRAMES`] of the reference voicing.
    pub near_voicing: Vec<bool>,
    /// Frames that count in scores.
    pub mask: Vec<bool>,
    /// The speech level (mean power of the reference-voiced frames), dBFS.
    pub level_db: f64,
}

/// Reads a file at any rate as 16 kHz mono.
pub fn read_16k(path: &Path) -> Result<Vec<f32>, String> {
    let (x, rate) = pneuma_io::read_mono(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(if f64::from(rate) == RATE_HZ {
        x
    } else {
        resample_to_16k(&x, f64::from(rate))
    })
}

/// Level per label frame, dBFS (10·log10 of the mean square + 1e-12).
pub fn frame_levels_db(x: &[f32]) -> Vec<f64> {
    x.chunks_exact(HOP)
        .map(|f| {
            let p = f.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / HOP as f64;
            10.0 * (p + 1e-12).log10()
        })
        .collect()
}

/// The value at the `q` quantile of `v` (linear interpolation, as numpy's default).
pub fn percentile(v: &[f64], q: f64) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    if s.is_empty() {
        return f64::NAN;
    }
    let pos = q * (s.len() - 1) as f64;
    let (lo, hi) = (pos.floor() as usize, pos.ceil() as usize);
    s[lo] + (s[hi] - s[lo]) * (pos - lo as f64)
}

/// Per label frame of `n`: (voiced, uncertain) from reference frames `(time_s, f0_hz)`, each
/// matched to the frame whose centre is nearest and within 5.1 ms.
pub fn reference_voicing(reference: &[(f64, f64)], n: usize) -> (Vec<bool>, Vec<bool>) {
    let mut voiced = vec![false; n];
    let mut uncertain = vec![false; n];
    if reference.is_empty() {
        return (voiced, uncertain);
    }
    let mut j = 0;
    for k in 0..n {
        let centre = (k as f64 + 0.5) / FRAMES_PER_S;
        while j + 1 < reference.len()
            && (reference[j + 1].0 - centre).abs() <= (reference[j].0 - centre).abs()
        {
            j += 1;
        }
        let (t, f0) = reference[j];
        if (t - centre).abs() <= REFERENCE_MATCH_S {
            voiced[k] = f0 > 0.0;
            uncertain[k] = f0 < 0.0;
        }
    }
    (voiced, uncertain)
}

/// Frames within `r` frames of a set frame.
pub fn dilate(mask: &[bool], r: usize) -> Vec<bool> {
    let n = mask.len();
    (0..n)
        .map(|k| {
            mask[k.saturating_sub(r)..(k + r + 1).min(n)]
                .iter()
                .any(|&m| m)
        })
        .collect()
}

/// The truth of a clip from its audio and reference voicing (see the module docs):
/// (truth, mask, speech level dBFS).
pub fn speech_truth(
    audio: &[f32],
    voiced: &[bool],
    uncertain: &[bool],
) -> (Vec<bool>, Vec<bool>, f64) {
    let levels = frame_levels_db(audio);
    let voiced_power: Vec<f64> = levels
        .iter()
        .zip(voiced)
        .filter(|(_, &v)| v)
        .map(|(l, _)| 10f64.powf(l / 10.0))
        .collect();
    let level_db =
        10.0 * (voiced_power.iter().sum::<f64>() / voiced_power.len().max(1) as f64).log10();
    let floor = percentile(&levels, 0.1);
    let holds = (floor + OVER_FLOOR_DB).max(level_db - UNDER_SPEECH_DB);
    let near = dilate(voiced, NEAR_VOICING_FRAMES);
    let truth = levels
        .iter()
        .zip(&near)
        .map(|(&l, &nv)| (nv && l >= holds) || l >= level_db - NEAR_SPEECH_LEVEL_DB)
        .collect();
    let mask = uncertain
        .iter()
        .zip(&near)
        .map(|(&u, &nv)| !u || nv)
        .collect();
    (truth, mask, level_db)
}

/// Reads `time_s,f0_hz` rows (a header line allowed).
pub fn read_f0_csv(text: &str) -> Vec<(f64, f64)> {
    text.lines()
        .filter_map(|l| {
            let (t, f) = l.split_once(',')?;
            Some((t.trim().parse().ok()?, f.trim().parse().ok()?))
        })
        .collect()
}

/// Loads clip `name` from `data` (the shared data folder) with its truth; `praat` gives Praat's
/// `(time_s, f0_hz)` frames of a 16 kHz signal (for styletalk).
pub fn speech_clip(data: &Path, name: &str, praat: &mut Praat<'_>) -> Result<SpeechClip, String> {
    let set = if KEELE.contains(&name) {
        "keele"
    } else if PTDB.contains(&name) {
        "ptdb"
    } else {
        "styletalk"
    };
    let mut audio = read_16k(&data.join(set).join(format!("{name}.wav")))?;
    let n = audio.len() / HOP;
    audio.truncate(n * HOP);
    let reference = if set == "styletalk" {
        praat(&audio)?
    } else {
        let path = data.join(set).join(format!("{name}.f0.csv"));
        let text = crate::data::read_text(&path, crate::data::reference::REFERENCE_FILE)
            .map_err(|e| e.to_string())?;
        read_f0_csv(&text)
            .into_iter()
            .map(|(t, f)| (t + REFERENCE_OFFSET_S, f))
            .collect()
    };
    let (voiced, uncertain) = reference_voicing(&reference, n);
    if !voiced.iter().any(|&v| v) {
        return Err(format!("{name}: the reference voicing has no voiced frame"));
    }
    let (truth, mask, level_db) = speech_truth(&audio, &voiced, &uncertain);
    Ok(SpeechClip {
        name: name.to_string(),
        speaker: speaker_of(name),
        audio,
        truth,
        near_voicing: dilate(&voiced, NEAR_VOICING_FRAMES),
        mask,
        level_db,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truth_is_voicing_with_sound_and_80_ms_either_side_or_near_the_speech_level() {
        // 40 frames: 10 quiet (−80 dB), 10 voiced at −20 dB, 20 at −50 dB (a soft tail).
        let mut audio = Vec::new();
        for (frames, amp) in [(10, 1e-4f32), (10, 0.1414), (20, 0.00447)] {
            for i in 0..frames * HOP {
                audio.push(if i % 2 == 0 { amp } else { -amp });
            }
        }
        let voiced: Vec<bool> = (0..40).map(|k| (10..20).contains(&k)).collect();
        let (truth, mask, level) = speech_truth(&audio, &voiced, &[false; 40]);
        assert!((level + 17.0).abs() < 0.1, "{level}");
        // Frames 2..10 are within 80 ms of voicing but hold no sound (at the floor).
        assert!(!truth[5]);
        // The tail holds sound (over floor + 6, above level − 40): true within 80 ms only.
        assert!(truth[20] && truth[27] && !truth[28], "{truth:?}");
        assert!(mask.iter().all(|&m| m));
        assert_eq!(
            dilate(&[false, true, false, false], 1),
            [true, true, true, false]
        );
        assert!((percentile(&[1.0, 2.0, 3.0, 4.0], 0.1) - 1.3).abs() < 1e-12);
    }
}
