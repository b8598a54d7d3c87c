//! With the real breaths left in: the uncut recording rendered as `pneuma render` does
//! (the voice learned from the whole file) and as the plugin does (learned as it goes). A real
//! breath the engine hears (one of its existing breaths overlaps the label) gets no inserted
//! breath and the breathing cycle inspires on it; an inserted breath that overlaps a labelled
//! real breath is a *doubled* breath, audible on top of the real one. Clear and unsure labels
//! are counted apart (an unsure label is breath-like noise that may be a breath: a breath
//! inserted over it doubles it too, if it is one). Nothing here is fitted: every figure is
//! held out.

use std::collections::BTreeMap;

use super::{Clip, Voice};
use crate::stats::{median, overlaps};

/// A render of an uncut clip: its inserted breaths and the breaths it heard in the input.
#[derive(Debug, Clone, Default)]
pub struct UncutRender {
    /// Inserted breaths (start, end), seconds.
    pub inserted: Vec<(f64, f64)>,
    /// Breaths heard in the input (start, end), seconds.
    pub heard: Vec<(f64, f64)>,
    /// The lung of each control frame (time in the input, seconds; 0..1).
    pub lung: Vec<(f64, f32)>,
}

/// The figures of one speaker or of all.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LeftIn {
    /// Clear labelled breaths.
    pub labelled: usize,
    /// Of them, heard by the engine.
    pub heard: usize,
    /// Inserted breaths overlapping a clear labelled breath.
    pub doubled: usize,
    /// Unsure labels.
    pub unsure: usize,
    /// Inserted breaths overlapping an unsure label (and no clear one).
    pub doubled_unsure: usize,
    /// Inserted breaths in all.
    pub inserted: usize,
}

impl LeftIn {
    fn add(&mut self, o: LeftIn) {
        self.labelled += o.labelled;
        self.heard += o.heard;
        self.doubled += o.doubled;
        self.unsure += o.unsure;
        self.doubled_unsure += o.doubled_unsure;
        self.inserted += o.inserted;
    }

    /// Share of the clear labelled breaths heard.
    pub fn heard_share(&self) -> f64 {
        self.heard as f64 / self.labelled.max(1) as f64
    }
}

/// The figures of one clip's uncut render.
pub fn score(clear: &[(f64, f64)], unsure: &[(f64, f64)], render: &UncutRender) -> LeftIn {
    let on = |labels: &[(f64, f64)], s: (f64, f64)| labels.iter().any(|&l| overlaps(l, s));
    LeftIn {
        labelled: clear.len(),
        heard: clear
            .iter()
            .filter(|&&l| render.heard.iter().any(|&h| overlaps(l, h)))
            .count(),
        doubled: render.inserted.iter().filter(|&&s| on(clear, s)).count(),
        unsure: unsure.len(),
        doubled_unsure: render
            .inserted
            .iter()
            .filter(|&&s| !on(clear, s) && on(unsure, s))
            .count(),
        inserted: render.inserted.len(),
    }
}

/// Prints the table for the renders with `voice` and returns the overall figures.
pub fn print(
    clips: &[Clip],
    renders: &BTreeMap<(String, Voice), UncutRender>,
    voice: Voice,
    what: &str,
) -> LeftIn {
    let mut per: BTreeMap<&str, LeftIn> = BTreeMap::new();
    for clip in clips {
        let r = &renders[&(clip.name.clone(), voice)];
        per.entry(clip.speaker.as_str())
            .or_default()
            .add(score(&clip.breaths, &clip.unsure, r));
    }
    println!("\n== real breaths left in (the uncut recording rendered), {what}, HELD OUT");
    println!("speaker       labelled heard doubled  unsure doubled inserted");
    let mut all = LeftIn::default();
    let row = |name: &str, f: &LeftIn| {
        println!(
            "{name:<13} {:>8} {:>5} {:>7} {:>7} {:>7} {:>8}",
            f.labelled, f.heard, f.doubled, f.unsure, f.doubled_unsure, f.inserted
        );
    };
    for (speaker, f) in &per {
        row(speaker, f);
        all.add(*f);
    }
    row("all", &all);
    println!("(heard: clear labels the engine heard as breaths; doubled: inserted breaths over a clear label, then over an unsure one)");
    print_over_room(clips, renders, voice);
    all
}

/// How far the clear labelled breaths stand over the room (their level against the noise
/// floor's, both in the third-octave bands), those heard apart from those doubled: a breath
/// that the room masks cannot be heard, and one inserted over it is heard alone.
fn print_over_room(clips: &[Clip], renders: &BTreeMap<(String, Voice), UncutRender>, voice: Voice) {
    let (mut heard, mut doubled) = (Vec::new(), Vec::new());
    for clip in clips {
        let r = &renders[&(clip.name.clone(), voice)];
        for (&label, level_db) in clip.breaths.iter().zip(&clip.real_levels_db) {
            let over_db = level_db - clip.room_level_db;
            if r.inserted.iter().any(|&s| overlaps(label, s)) {
                doubled.push(over_db);
            } else if r.heard.iter().any(|&h| overlaps(label, h)) {
                heard.push(over_db);
            }
        }
    }
    doubled.sort_by(f64::total_cmp);
    heard.sort_by(f64::total_cmp);
    if let (Some(lowest), false) = (heard.first(), doubled.is_empty()) {
        let list: Vec<String> = doubled.iter().map(|d| format!("{d:.1}")).collect();
        println!(
            "  over the room (breath level against the noise floor's): doubled breaths [{}] dB; \
             heard ones median {:.1} dB, lowest {lowest:.1} dB",
            list.join(" "),
            median(&heard)
        );
    }
}

/// The targets with the real breaths left in.
pub fn targets(f: &LeftIn) -> Vec<(&'static str, bool, String)> {
    vec![
        (
            "no inserted breath over a labelled real breath",
            f.doubled == 0,
            format!("{} of {} inserted", f.doubled, f.inserted),
        ),
        (
            "real breaths heard ≥ 0.9",
            f.heard_share() >= 0.9,
            format!("{}/{} = {:.2}", f.heard, f.labelled, f.heard_share()),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_heard_doubled_and_unsure_apart() {
        let clear = [(1.0, 1.4), (3.0, 3.3), (5.0, 5.5)];
        let unsure = [(7.0, 7.2)];
        let render = UncutRender {
            // Over the second clear breath, over the unsure one, in a pause with neither.
            inserted: vec![(3.1, 3.5), (6.9, 7.1), (9.0, 9.3)],
            // The first breath heard, the third touched at its end only (not heard).
            heard: vec![(1.05, 1.35), (5.5, 5.6)],
            lung: Vec::new(),
        };
        let f = score(&clear, &unsure, &render);
        assert_eq!(
            f,
            LeftIn {
                labelled: 3,
                heard: 1,
                doubled: 1,
                unsure: 1,
                doubled_unsure: 1,
                inserted: 3,
            }
        );
        let t = targets(&f);
        assert!(!t[0].1 && !t[1].1, "{t:?}");
        let clean = LeftIn {
            labelled: 10,
            heard: 9,
            ..LeftIn::default()
        };
        assert!(targets(&clean).iter().all(|t| t.1));
    }
}
