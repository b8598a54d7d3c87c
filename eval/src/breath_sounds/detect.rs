//! Detection of real inhalations (the engine's "existing breaths") against hand labels, per
//! speaker and overall, and the leave-one-speaker-out fit of the breath shape limits.
//!
//! - **Clips**: every labelled set (`<clip>.wav` in a folder with a labels file, see
//!   [`crate::labels`]). Each clip is analysed once with the default
//!   analysis settings; the phrase tracker then runs over its frames with the settings under
//!   test, exactly as the engine runs it, and its pauses' breath spans are the heard breaths.
//! - **Speaker**: a Keele clip is one speaker; a styletalk clip's speaker is its name before
//!   `_clip` (andrew's two clips are one speaker).
//! - **Scores**: as [`crate::labels`] scores heard breaths: recall over the `breath` labels,
//!   precision over the heard breaths (those over `unsure` labels only not counted).
//! - **Fit** ([`fit_shape`]): the three breath-shape settings (`breath_margin_db`,
//!   `breath_max_high_over_mid_db`, `breath_max_low_over_mid_db`) chosen from a small grid by
//!   the F1 of the pooled counts. **Held out**: for each speaker the settings are fitted on the
//!   other speakers only and scored on that speaker; the held-out counts are the sums over
//!   speakers. The fit on all speakers is the in-sample figure (not a held-out one).

use std::collections::BTreeMap;
use std::path::Path;

use pneuma_core::analysis::{AnalysisConfig, FeatureFrame};
use pneuma_core::phrase::{PhraseConfig, PhraseEvent, PhraseTracker};

use crate::data::{analyse_file, read_labels, wav_files, DataError};
use crate::labels::{score, Counts, Label};

/// One analysed clip with its labels.
pub struct Clip {
    /// Clip name (file stem).
    pub name: String,
    /// Speaker the clip belongs to.
    pub speaker: String,
    /// The clip's feature frames (default analysis settings).
    pub frames: Vec<FeatureFrame>,
    /// Frame rate of `frames`, Hz.
    pub frame_rate_hz: f64,
    /// The clip's labels.
    pub labels: Vec<Label>,
}

/// The speaker of a clip: a styletalk clip's name before `_clip`, else the whole name.
pub fn speaker_of(clip: &str) -> String {
    clip.split("_clip").next().unwrap_or(clip).to_string()
}

/// Loads and analyses every clip of `data` that `labels_path` names. Errors say which file
/// or label is wrong.
pub fn load_set(data: &Path, labels_path: &Path) -> Result<Vec<Clip>, String> {
    let mut by_clip: BTreeMap<String, Vec<Label>> = BTreeMap::new();
    for l in read_labels(labels_path)? {
        by_clip.entry(l.clip.clone()).or_default().push(l);
    }
    // Clips without a row hold no visible breath but still count for false detections.
    let names: Vec<String> = wav_files(data, "the labelled clips (<clip>.wav) the labels name")?
        .iter()
        .filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned()))
        .collect();
    if let Some(c) = by_clip.keys().find(|c| !names.contains(c)) {
        return Err(DataError::UnknownClip {
            labels: labels_path.into(),
            clip: c.clone(),
            data: data.into(),
        }
        .into());
    }
    let config = AnalysisConfig::default();
    names
        .into_iter()
        .map(|name| {
            let frames = analyse_file(&data.join(format!("{name}.wav")), &config)?;
            Ok(Clip {
                speaker: speaker_of(&name),
                labels: by_clip.remove(&name).unwrap_or_default(),
                frame_rate_hz: config.frame_rate_hz,
                frames,
                name,
            })
        })
        .collect()
}

/// The breaths the phrase tracker hears in `clip` with `config`, (start, end) seconds.
pub fn heard(clip: &Clip, config: PhraseConfig) -> Result<Vec<(f64, f64)>, String> {
    let mut t = PhraseTracker::new(config, clip.frame_rate_hz).map_err(|e| e.to_string())?;
    let mut spans = Vec::new();
    for f in &clip.frames {
        t.update(f, |e| {
            if let PhraseEvent::Start { pause, .. } = e {
                spans.extend(pause.breath_s);
            }
        });
    }
    Ok(spans)
}

/// Counts per speaker for `config`.
pub fn per_speaker(
    clips: &[Clip],
    config: PhraseConfig,
) -> Result<BTreeMap<String, Counts>, String> {
    let mut m: BTreeMap<String, Counts> = BTreeMap::new();
    for c in clips {
        let h = heard(c, config)?;
        m.entry(c.speaker.clone())
            .or_default()
            .add(score(&c.labels, &h));
    }
    Ok(m)
}

/// Sum of counts over speakers, optionally without one.
fn pooled(m: &BTreeMap<String, Counts>, without: Option<&str>) -> Counts {
    let mut c = Counts::default();
    for (s, v) in m {
        if Some(s.as_str()) != without {
            c.add(*v);
        }
    }
    c
}

/// The breath-shape limits the fit chooses (see [`PhraseConfig`]), dB. The level rule
/// (`breath_margin_db`) is not fitted: it stays at its default.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Shape {
    /// `breath_max_high_over_mid_db`.
    pub max_high_db: f32,
    /// `breath_max_low_over_mid_db`.
    pub max_low_db: f32,
}

impl Shape {
    /// `base` with these limits.
    pub fn apply(&self, base: PhraseConfig) -> PhraseConfig {
        PhraseConfig {
            breath_max_high_over_mid_db: self.max_high_db,
            breath_max_low_over_mid_db: self.max_low_db,
            ..base
        }
    }

    /// No shape limits: the level-only rule the tracker had before.
    pub fn off() -> Self {
        Self {
            max_high_db: 40.0,
            max_low_db: 40.0,
        }
    }
}

impl std::fmt::Display for Shape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "high-over-mid ≤ {} dB, low-over-mid ≤ {} dB",
            self.max_high_db, self.max_low_db
        )
    }
}

/// Grid of `breath_max_high_over_mid_db` values the fit tries (40 = off).
pub const MAX_HIGH_GRID_DB: [f32; 10] = [-6.0, -4.5, -3.0, -1.5, 0.0, 1.5, 3.0, 5.0, 8.0, 40.0];
/// Grid of `breath_max_low_over_mid_db` values the fit tries (40 = off).
pub const MAX_LOW_GRID_DB: [f32; 10] = [-6.0, -4.5, -3.0, -1.5, 0.0, 1.5, 3.0, 5.0, 8.0, 40.0];

/// Every grid point.
pub fn grid() -> Vec<Shape> {
    MAX_HIGH_GRID_DB
        .iter()
        .flat_map(|&max_high_db| {
            MAX_LOW_GRID_DB.iter().map(move |&max_low_db| Shape {
                max_high_db,
                max_low_db,
            })
        })
        .collect()
}

/// The result of the leave-one-speaker-out fit.
pub struct Fit {
    /// The grid point fitted on all speakers.
    pub all: Shape,
    /// Counts of that point on all speakers (in-sample).
    pub fitted: Counts,
    /// Per speaker: the point fitted without it, and its counts on it (held out).
    pub held_out: BTreeMap<String, (Shape, Counts)>,
}

impl Fit {
    /// The held-out counts summed over speakers.
    pub fn held_out_total(&self) -> Counts {
        let mut c = Counts::default();
        self.held_out.values().for_each(|(_, v)| c.add(*v));
        c
    }
}

/// Fits the shape settings on `clips` by the pooled F1, leave-one-speaker-out. Ties go to the
/// first point in [`grid`] order.
pub fn fit_shape(clips: &[Clip], base: PhraseConfig) -> Result<Fit, String> {
    let scored: Vec<(Shape, BTreeMap<String, Counts>)> = grid()
        .into_iter()
        .map(|p| per_speaker(clips, p.apply(base)).map(|m| (p, m)))
        .collect::<Result<_, _>>()?;
    let best = |without: Option<&str>| {
        scored
            .iter()
            .map(|(p, m)| (*p, pooled(m, without).f1()))
            .fold(None, |acc: Option<(Shape, f64)>, (p, f)| match acc {
                Some((_, bf)) if bf >= f => acc,
                _ => Some((p, f)),
            })
            .map(|(p, _)| p)
            .expect("a non-empty grid")
    };
    let all = best(None);
    let fitted = pooled(&per_speaker(clips, all.apply(base))?, None);
    let speakers: Vec<String> = scored[0].1.keys().cloned().collect();
    let mut held_out = BTreeMap::new();
    for s in speakers {
        let p = best(Some(&s));
        let m = per_speaker(clips, p.apply(base))?;
        held_out.insert(s.clone(), (p, m[&s]));
    }
    Ok(Fit {
        all,
        fitted,
        held_out,
    })
}

/// Loads both labelled sets (styletalk, Keele), prints detection per speaker and overall for
/// today's level-only rule and for the default settings, and the leave-one-speaker-out fit.
/// Returns whether the targets are met.
pub fn report(sets: &[(&Path, &Path)]) -> Result<bool, String> {
    let mut clips = Vec::new();
    for (data, labels) in sets {
        clips.extend(load_set(data, labels)?);
    }
    let level_only = Shape::off().apply(PhraseConfig::default());
    let base = per_speaker(&clips, level_only)?;
    let now = per_speaker(&clips, PhraseConfig::default())?;
    let fit = fit_shape(&clips, PhraseConfig::default())?;
    println!("\ndetection of real breaths per speaker (labels: styletalk + Keele)");
    println!(
        "{:<10} {:<44} {:<44} held out (fitted without the speaker)",
        "speaker", "level only (before the shape rule)", "default settings"
    );
    for (s, c) in &now {
        let (p, h) = fit.held_out[s];
        println!(
            "{s:<10} {:<44} {:<44} {}  [{p}]",
            base[s].describe(),
            c.describe(),
            h.describe(),
        );
    }
    let held = fit.held_out_total();
    println!(
        "{:<10} {:<44} {:<44} {}",
        "all",
        pooled(&base, None).describe(),
        pooled(&now, None).describe(),
        held.describe()
    );
    println!(
        "fit on all speakers (in-sample, not a held-out figure): {}: {}",
        fit.all,
        fit.fitted.describe()
    );
    let level_only = pooled(&base, None);
    let checks = [
        (
            format!(
                "held-out recall {:.2} ≥ {MIN_HELD_OUT_RECALL}",
                held.recall()
            ),
            held.recall() >= MIN_HELD_OUT_RECALL,
        ),
        (
            format!(
                "held-out precision {:.2} ≥ {MIN_HELD_OUT_PRECISION}",
                held.precision()
            ),
            held.precision() >= MIN_HELD_OUT_PRECISION,
        ),
        (
            format!(
                "held-out F1 {:.3} > level-only F1 {:.3}",
                held.f1(),
                level_only.f1()
            ),
            held.f1() > level_only.f1(),
        ),
    ];
    println!("\ndetection targets (on the held-out figures):");
    for (what, ok) in &checks {
        println!("  {} {what}", if *ok { "ok  " } else { "MISS" });
    }
    Ok(checks.iter().all(|(_, ok)| *ok))
}

/// Held-out recall the detection must reach (measured 0.82 when the target was set).
pub const MIN_HELD_OUT_RECALL: f64 = 0.75;
/// Held-out precision the detection must reach (measured 0.84 when the target was set, 0.85
/// after merging the learned voicing).
pub const MIN_HELD_OUT_PRECISION: f64 = 0.75;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn speakers_of_styletalk_clips_join_and_keele_clips_stand_alone() {
        assert_eq!(speaker_of("andrew_clip_1"), "andrew");
        assert_eq!(speaker_of("andrew_clip_2"), "andrew");
        assert_eq!(speaker_of("Obama_clip3"), "Obama");
        assert_eq!(speaker_of("m3nw0000"), "m3nw0000");
    }
}
