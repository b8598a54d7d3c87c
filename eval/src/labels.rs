//! Breath labels: spans of real inhalations marked by hand in real speech (times only, never
//! audio; `assets/labels/*.csv`), their file format, and the scores of heard breaths against
//! them.
//!
//! A `breath` label is a clear inhalation, an `unsure` one noise in a pause that may be a
//! breath, a lip noise or a reverberant tail. A `breath` label is found when a heard breath
//! overlaps it (recall); a heard breath that overlaps a `breath` label is true, one that
//! overlaps no label is false, one that overlaps only `unsure` labels is not counted
//! (precision).

use crate::stats::overlaps;

/// How sure a label is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LabelKind {
    /// A clear inhalation.
    Breath,
    /// Maybe a breath: neither counted as found nor as false.
    Unsure,
}

/// One labelled span.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// Clip name (file stem).
    pub clip: String,
    /// Start, seconds.
    pub start_s: f64,
    /// End, seconds.
    pub end_s: f64,
    /// How sure.
    pub kind: LabelKind,
}

/// Parses the labels file: a header `clip,start_s,end_s,kind`, then one row per span; `#`
/// starts a comment line.
pub fn parse_labels(text: &str) -> Result<Vec<Label>, String> {
    let mut rows = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
    match rows.next() {
        Some((_, h)) if h.trim() == "clip,start_s,end_s,kind" => {}
        _ => return Err("the first row must be the header clip,start_s,end_s,kind".into()),
    }
    rows.map(|(i, l)| {
        let line = i + 1;
        let f: Vec<&str> = l.split(',').map(str::trim).collect();
        if f.len() != 4 {
            return Err(format!("line {line}: 4 fields expected, found {}", f.len()));
        }
        let num = |s: &str, what: &str| {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| format!("line {line}: {what} {s:?} is not a time in seconds"))
        };
        let (start_s, end_s) = (num(f[1], "start_s")?, num(f[2], "end_s")?);
        if end_s <= start_s {
            return Err(format!(
                "line {line}: end_s {end_s} is not after start_s {start_s}"
            ));
        }
        let kind = match f[3] {
            "breath" => LabelKind::Breath,
            "unsure" => LabelKind::Unsure,
            k => return Err(format!("line {line}: kind {k:?}: use breath or unsure")),
        };
        Ok(Label {
            clip: f[0].to_string(),
            start_s,
            end_s,
            kind,
        })
    })
    .collect()
}

/// Detection counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// `breath` labels.
    pub labelled: usize,
    /// `breath` labels a heard breath overlaps.
    pub found: usize,
    /// Heard breaths over a `breath` label.
    pub heard_true: usize,
    /// Heard breaths over no label.
    pub heard_false: usize,
}

impl Counts {
    /// Adds `o`'s counts.
    pub fn add(&mut self, o: Counts) {
        self.labelled += o.labelled;
        self.found += o.found;
        self.heard_true += o.heard_true;
        self.heard_false += o.heard_false;
    }

    /// Recall, 0..1 (0 without labels).
    pub fn recall(&self) -> f64 {
        self.found as f64 / self.labelled.max(1) as f64
    }

    /// Precision, 0..1 (0 without heard breaths).
    pub fn precision(&self) -> f64 {
        self.heard_true as f64 / (self.heard_true + self.heard_false).max(1) as f64
    }

    /// F1 of recall and precision (0 when both are 0).
    pub fn f1(&self) -> f64 {
        let (r, p) = (self.recall(), self.precision());
        if r + p > 0.0 {
            2.0 * r * p / (r + p)
        } else {
            0.0
        }
    }

    /// `found/labelled (r %), true/heard (p %)`.
    pub fn describe(&self) -> String {
        format!(
            "recall {:>2}/{:<2} ({:>3.0} %)  precision {:>2}/{:<2} ({:>3.0} %)",
            self.found,
            self.labelled,
            100.0 * self.recall(),
            self.heard_true,
            self.heard_true + self.heard_false,
            100.0 * self.precision()
        )
    }
}

/// Scores heard spans against a clip's labels.
pub fn score(labels: &[Label], heard: &[(f64, f64)]) -> Counts {
    let mut c = Counts::default();
    for l in labels.iter().filter(|l| l.kind == LabelKind::Breath) {
        c.labelled += 1;
        if heard.iter().any(|&h| overlaps(h, (l.start_s, l.end_s))) {
            c.found += 1;
        }
    }
    for &h in heard {
        let over: Vec<LabelKind> = labels
            .iter()
            .filter(|l| overlaps(h, (l.start_s, l.end_s)))
            .map(|l| l.kind)
            .collect();
        if over.contains(&LabelKind::Breath) {
            c.heard_true += 1;
        } else if over.is_empty() {
            c.heard_false += 1;
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_parse_and_bad_rows_say_which_line() {
        let ok =
            parse_labels("# by eye\nclip,start_s,end_s,kind\na,1.0,1.4,breath\nb,2,2.5,unsure\n")
                .unwrap();
        assert_eq!(ok.len(), 2);
        assert_eq!(ok[1].kind, LabelKind::Unsure);
        assert_eq!((ok[0].start_s, ok[0].end_s), (1.0, 1.4));
        let err = parse_labels("clip,start_s,end_s,kind\na,1.0,0.5,breath\n").unwrap_err();
        assert!(err.contains("line 2") && err.contains("not after"), "{err}");
        let err = parse_labels("clip,start_s,end_s,kind\na,1.0,1.5,sigh\n").unwrap_err();
        assert!(err.contains("breath or unsure"), "{err}");
        assert!(parse_labels("a,1,2,breath\n")
            .unwrap_err()
            .contains("header"));
    }

    fn label(start_s: f64, end_s: f64, kind: LabelKind) -> Label {
        Label {
            clip: "c".into(),
            start_s,
            end_s,
            kind,
        }
    }

    #[test]
    fn scores_count_found_true_false_and_leave_unsure_out() {
        let labels = [
            label(1.0, 1.4, LabelKind::Breath),
            label(3.0, 3.4, LabelKind::Breath),
            label(5.0, 5.4, LabelKind::Unsure),
        ];
        let heard = [(1.2, 1.5), (5.1, 5.2), (7.0, 7.3)];
        let c = score(&labels, &heard);
        assert_eq!(
            c,
            Counts {
                labelled: 2,
                found: 1,
                heard_true: 1,
                heard_false: 1
            }
        );
        assert_eq!((c.recall(), c.precision()), (0.5, 0.5));
        assert!((c.f1() - 0.5).abs() < 1e-12);
    }
}
