//! Fitting the built-in breath voice ([`ReferenceVoice`]) to the labelled real breaths of a
//! set of speakers: the shape and level each speaker's breaths have on average, the spread of
//! breaths around their own speaker's mean, and the speakers' speech spectrum the channel
//! colouring compares a recording with. `cargo xtask train-breath-voice` fits it on every
//! labelled speaker and writes `assets/models/breath_voice.json`; `pneuma eval restore` fits it
//! again without each speaker it scores (held out).
//!
//! Every speaker weighs the same: per band, the reference shape is the mean over speakers of
//! each speaker's mean breath shape; the level under the speech is the median over speakers of
//! each speaker's median; the spreads are pooled within speakers (how one speaker's breaths
//! vary, not how speakers differ); the speech spectrum is the mean over speakers of each
//! speaker's mean voiced long-term spectrum (each relative to its own mean over the bands).

use std::collections::BTreeMap;

use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::breathing::reference::{ReferenceVoice, VERSION};
use pneuma_core::breathing::third_octave::{Bands, BANDS};

use super::Clip;
use crate::stats::median;

/// Largest spread per band or of the level, dB (as the learned voice's).
const MAX_SD_DB: f64 = 4.0;

/// One speaker's figures.
#[derive(Default)]
struct Speaker {
    shapes: Vec<Bands>,
    levels_db: Vec<f64>,
    lengths_s: Vec<f64>,
    ltas: Vec<Bands>,
}

fn mean_of(v: &[Bands]) -> Bands {
    std::array::from_fn(|k| v.iter().map(|b| b[k]).sum::<f64>() / v.len() as f64)
}

/// `b` less its mean over the bands.
fn centred(b: &Bands) -> Bands {
    let m = b.iter().sum::<f64>() / BANDS as f64;
    b.map(|x| x - m)
}

/// Pooled within-group standard deviation of `groups` (each a list of values).
fn pooled_sd<'a>(groups: impl Iterator<Item = Vec<f64>> + 'a) -> f64 {
    let (mut ss, mut dof) = (0.0, 0.0);
    for g in groups {
        if g.len() < 2 {
            continue;
        }
        let m = g.iter().sum::<f64>() / g.len() as f64;
        ss += g.iter().map(|x| (x - m).powi(2)).sum::<f64>();
        dof += g.len() as f64 - 1.0;
    }
    if dof > 0.0 {
        (ss / dof).sqrt()
    } else {
        f64::NAN
    }
}

/// The reference voice of the labelled breaths of `clips` (`None` without a breath).
pub fn fit<'a>(clips: impl IntoIterator<Item = &'a Clip>) -> Option<ReferenceVoice> {
    let mut speakers: BTreeMap<&str, Speaker> = BTreeMap::new();
    for c in clips {
        if !c.speech_db.is_finite() || c.speech_ltas_db.iter().any(|d| !d.is_finite()) {
            continue;
        }
        let s = speakers.entry(&c.speaker).or_default();
        s.ltas.push(centred(&c.speech_ltas_db));
        for (i, &(a, b)) in c.breaths.iter().enumerate() {
            s.shapes.push(c.real_shapes[i]);
            s.levels_db.push(c.real_levels_db[i] - c.speech_db);
            s.lengths_s.push(b - a);
        }
    }
    speakers.retain(|_, s| !s.shapes.is_empty());
    if speakers.is_empty() {
        return None;
    }
    let shape_db = mean_of(
        &speakers
            .values()
            .map(|s| mean_of(&s.shapes))
            .collect::<Vec<_>>(),
    );
    let shape_sd_db: Bands = std::array::from_fn(|k| {
        pooled_sd(
            speakers
                .values()
                .map(|s| s.shapes.iter().map(|b| b[k]).collect()),
        )
        .min(MAX_SD_DB)
    });
    let level_re_speech_db = median(
        &speakers
            .values()
            .map(|s| median(&s.levels_db))
            .collect::<Vec<_>>(),
    );
    let level_sd_db = pooled_sd(speakers.values().map(|s| s.levels_db.clone())).min(MAX_SD_DB);
    let lengths: Vec<f64> = speakers
        .values()
        .flat_map(|s| s.lengths_s.clone())
        .collect();
    let length_s = median(&lengths);
    let m = lengths.iter().sum::<f64>() / lengths.len() as f64;
    let length_sd_s =
        (lengths.iter().map(|x| (x - m).powi(2)).sum::<f64>() / lengths.len() as f64).sqrt();
    let speech_ltas_db = mean_of(
        &speakers
            .values()
            .map(|s| mean_of(&s.ltas))
            .collect::<Vec<_>>(),
    );
    Some(ReferenceVoice {
        version: VERSION,
        voice: LearnedVoice {
            breaths: lengths.len(),
            shape_db,
            shape_sd_db,
            level_re_speech_db,
            level_sd_db,
            speech_db: 0.0,
            length_s,
            length_sd_s,
        },
        speech_ltas_db,
        speakers: speakers.len(),
        colour_by_channel: true,
    })
}
