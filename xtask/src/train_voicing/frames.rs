//! The training material of the voicing model: every analyzer frame's cues (the analyzer's
//! own, [`pneuma_core::VOICING_FEATURES`], computed from the audio alone) and the labelled
//! frames a reference maps to, at each data set's known reference offset.

use pneuma_core::analysis::LEVEL_VS_GATE;
use pneuma_core::{AnalysisConfig, Analyzer, VoicingFeatures, VOICING_FEATURES};
use pneuma_eval::data::reference::Source;

/// Index of the `log_f0` cue (the chosen period) among the cues.
const LOG_F0: usize = cue_index("log_f0");

/// The index of the cue `name` in [`VOICING_FEATURES`] (the build fails when there is none).
const fn cue_index(name: &str) -> usize {
    let mut i = 0;
    while i < VOICING_FEATURES.len() {
        let (a, b) = (VOICING_FEATURES[i].as_bytes(), name.as_bytes());
        if a.len() == b.len() {
            let mut k = 0;
            while k < a.len() && a[k] == b[k] {
                k += 1;
            }
            if k == a.len() {
                return i;
            }
        }
        i += 1;
    }
    panic!("not a voicing cue")
}

/// Tracker time = reference time + this, per data set (the offsets `eval-pitch` searches).
pub(crate) const KEELE_OFFSET_MS: i32 = -10;
/// Tracker time = reference time + this for PTDB.
pub(crate) const PTDB_OFFSET_MS: i32 = 15;

/// Frame rates the cues are gathered at (the shipped one and Praat's usual 5 ms step, which
/// `eval-pitch` also checks): one model serves both, the cues change a little with the rate.
pub(crate) const FRAME_RATES_HZ: [f64; 2] = [120.0, 200.0];

/// One clip's training material: per analyzer frame its cues, whether the model sees it, and
/// the labelled frames (frame index, voiced).
pub(crate) struct ClipFrames {
    pub speaker: String,
    /// Data set and noise condition (`keele clean`, `ptdb car 10 dB`, ...).
    pub(crate) condition: String,
    /// Frames per second the cues were gathered at.
    pub(crate) frame_rate_hz: f64,
    /// Weight of each of its labelled frames (see [`WEIGHTING`]).
    pub(crate) weight: f64,
    pub(crate) features: Vec<VoicingFeatures>,
    pub(crate) seen: Vec<bool>,
    pub(crate) labels: Vec<(usize, bool)>,
    /// Frames whose reference is voiced but whose chosen period is off by more than 20 %:
    /// voiced or not, each is a frame error (gross or voicing), so they teach the fit nothing,
    /// but the thresholds are scored as the eval scores them (FFE), where a decision to voice
    /// one costs the same as missing it.
    pub(crate) wrong_pitch: Vec<usize>,
}

/// Gathers the cues and labels of every clip of `sources` (references at `offset_ms`).
pub(crate) fn gather(
    set: &str,
    sources: &[Source],
    offset_ms: i32,
    frame_rate_hz: f64,
    out: &mut Vec<ClipFrames>,
) -> Result<(), String> {
    let config = AnalysisConfig {
        frame_rate_hz,
        ..AnalysisConfig::default()
    };
    let silence_db = config.silence_db;
    for s in sources {
        let mut a = Analyzer::new(config.clone()).map_err(|e| e.to_string())?;
        a.prepare(s.rate as f64, 4096).map_err(|e| e.to_string())?;
        let mut features = Vec::new();
        let mut seen = Vec::new();
        let mut keep = |f: &pneuma_core::FeatureFrame, v: &VoicingFeatures| {
            features.push(*v);
            // A period was found (its clarity is positive) and the frame passes the silence
            // and level gates: only such frames reach the model.
            seen.push(v[1] > 0.0 && f.rms_db >= silence_db && v[LEVEL_VS_GATE] >= 0.0);
        };
        for block in s.audio.chunks(4096) {
            a.process_with_features(block, &mut keep)
                .map_err(|e| e.to_string())?;
        }
        a.finish_with_features(&mut keep)
            .map_err(|e| e.to_string())?;
        let mut labels = Vec::new();
        let mut wrong_pitch = Vec::new();
        for &(t, f_ref) in &s.reference {
            if f_ref < 0.0 {
                continue;
            }
            let k = ((t + offset_ms as f64 / 1000.0) * frame_rate_hz).round();
            if k < 0.0 || k as usize >= features.len() {
                continue;
            }
            let k = k as usize;
            if !seen[k] {
                continue;
            }
            if f_ref == 0.0 {
                labels.push((k, false));
            } else {
                let f0 = chosen_f0_hz(&features[k]);
                if (f0 / f_ref - 1.0).abs() <= 0.2 {
                    labels.push((k, true));
                } else {
                    wrong_pitch.push(k);
                }
            }
        }
        out.push(ClipFrames {
            speaker: s.speaker.clone(),
            condition: format!("{set} {}", s.condition.label()),
            frame_rate_hz,
            weight: 1.0,
            features,
            seen,
            labels,
            wrong_pitch,
        });
    }
    Ok(())
}

/// The chosen f0 back from the `log_f0` cue (exact within 37.5–600 Hz, the searched range).
pub(crate) fn chosen_f0_hz(f: &VoicingFeatures) -> f32 {
    150.0 * f[LOG_F0].exp2()
}
