//! The voicing model as a file: the shipped model (`assets/models/voicing.txt`, embedded), the
//! reader of format versions 1–3 (errors name the line) and the writer, which reads back bit
//! for bit.

use std::sync::OnceLock;

use super::cues::{N_VOICING_FEATURES, VOICING_FEATURES};
use super::model::{Ensemble, Linear, Scorer, VoicingModel, VoicingModelError, MAX_TREE_DEPTH};

/// The shipped model, embedded.
const SHIPPED_MODEL: &str = include_str!("../../../../assets/models/voicing.txt");
/// First line of a model file (after comments): format name and version (3: a logistic
/// regression plus trees).
const FORMAT_LINE: &str = "pneuma-voicing-model 3";
/// The first line of a version 1 file (logistic regression), still read and written.
const FORMAT_LINE_V1: &str = "pneuma-voicing-model 1";
/// The first line of a version 2 file (trees alone), still read and written.
const FORMAT_LINE_V2: &str = "pneuma-voicing-model 2";

impl VoicingModel {
    /// The model shipped in `assets/models/voicing.txt` (embedded; a unit test checks that it
    /// parses).
    pub fn shipped() -> &'static VoicingModel {
        static MODEL: OnceLock<VoicingModel> = OnceLock::new();
        MODEL.get_or_init(|| {
            VoicingModel::parse(SHIPPED_MODEL).expect("the embedded voicing model parses")
        })
    }

    /// Reads a model file of any version; errors name the line.
    ///
    /// File format (text, UTF-8; `#` lines and blank lines are comments). Version 1:
    ///
    /// ```text
    /// pneuma-voicing-model 1
    /// feature <name> mean <m> scale <s> weight <w>     (one per cue, in VOICING_FEATURES order)
    /// bias <b>
    /// threshold_on <on>
    /// threshold_off <off>                               (off ≤ on)
    /// ```
    ///
    /// Version 2 (trees):
    ///
    /// ```text
    /// pneuma-voicing-model 2
    /// trees <count> depth <d> base <b>                  (1 ≤ d ≤ 4)
    /// tree <name> <t> ... <name> <t> leaves <v> ...     (count lines: 2^d − 1 splits breadth
    ///                                                    first, then 2^d leaf values)
    /// threshold_on <on>
    /// threshold_off <off>
    /// ```
    ///
    /// Version 3 (hybrid: the logistic regression's score plus trees):
    ///
    /// ```text
    /// pneuma-voicing-model 3
    /// feature ... / bias <b>                            (as in version 1)
    /// trees <count> depth <d>                           (then the tree lines of version 2)
    /// tree ...
    /// threshold_on <on>
    /// threshold_off <off>
    /// ```
    ///
    /// A split sends a frame whose cue `<name>` is at most `<t>` to its first child. The score
    /// is `base` (version 2) or the logistic score (version 3) plus the leaf each tree reaches.
    /// Every number is a finite decimal (written as the shortest text that reads back as the
    /// same `f32`), every scale positive.
    pub fn parse(text: &str) -> Result<Self, VoicingModelError> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (line, first) = keyed_line(&mut lines, &format!("the format line `{FORMAT_LINE}`"))?;
        let version = match first {
            FORMAT_LINE_V1 => 1,
            FORMAT_LINE_V2 => 2,
            FORMAT_LINE => 3,
            _ => {
                return Err(bad(
                    line,
                    format!("expected `{FORMAT_LINE}` (or version 1 or 2), found `{first}` (not a voicing model, or another version)"),
                ))
            }
        };
        let scorer = match version {
            1 => Scorer::Logistic(parse_linear(&mut lines)?),
            2 => {
                let (line, l) = keyed_line(&mut lines, "the `trees` line")?;
                let t: Vec<&str> = l.split_whitespace().collect();
                let ["trees", n, "depth", d, "base", b] = t[..] else {
                    return Err(bad(
                        line,
                        format!("expected `trees <count> depth <d> base <b>`, found `{l}`"),
                    ));
                };
                let base = number(line, "base", b)?;
                let trees = parse_trees(&mut lines, line, n, d)?;
                Scorer::Trees { base, trees }
            }
            _ => {
                let linear = parse_linear(&mut lines)?;
                let (line, l) = keyed_line(&mut lines, "the `trees` line")?;
                let t: Vec<&str> = l.split_whitespace().collect();
                let ["trees", n, "depth", d] = t[..] else {
                    return Err(bad(
                        line,
                        format!("expected `trees <count> depth <d>`, found `{l}`"),
                    ));
                };
                let trees = parse_trees(&mut lines, line, n, d)?;
                Scorer::Hybrid { linear, trees }
            }
        };
        let (_, on) = keyed_number(&mut lines, "threshold_on")?;
        let (line_off, off) = keyed_number(&mut lines, "threshold_off")?;
        let model = Self::from_scorer(scorer, on, off).map_err(|e| bad(line_off, e.to_string()))?;
        if let Some((line, l)) = lines.next() {
            return Err(bad(
                line,
                format!("unexpected line after threshold_off: `{l}`"),
            ));
        }
        Ok(model)
    }

    /// The model as a file: `notes` (provenance) as leading comment lines, then the format.
    /// [`VoicingModel::parse`] reads it back to the same model, bit for bit.
    pub fn to_text(&self, notes: &[String]) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        for n in notes {
            let _ = writeln!(s, "# {n}");
        }
        let write_linear = |s: &mut String, l: &Linear| {
            for (i, name) in VOICING_FEATURES.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "feature {name} mean {} scale {} weight {}",
                    l.mean[i], l.scale[i], l.weight[i]
                );
            }
            let _ = writeln!(s, "bias {}", l.bias);
        };
        match &self.scorer {
            Scorer::Logistic(linear) => {
                let _ = writeln!(s, "{FORMAT_LINE_V1}");
                write_linear(&mut s, linear);
            }
            Scorer::Trees { base, trees } => {
                let _ = writeln!(s, "{FORMAT_LINE_V2}");
                let _ = writeln!(
                    s,
                    "trees {} depth {} base {base}",
                    trees.count(),
                    trees.depth
                );
                trees.write(&mut s);
            }
            Scorer::Hybrid { linear, trees } => {
                let _ = writeln!(s, "{FORMAT_LINE}");
                write_linear(&mut s, linear);
                let _ = writeln!(s, "trees {} depth {}", trees.count(), trees.depth);
                trees.write(&mut s);
            }
        }
        let _ = writeln!(s, "threshold_on {}", self.threshold_on);
        let _ = writeln!(s, "threshold_off {}", self.threshold_off);
        s
    }
}

impl Ensemble {
    /// The `tree` lines of the file format.
    fn write(&self, s: &mut String) {
        use std::fmt::Write as _;
        let n_leaves = self.n_leaves();
        for (tree_splits, tree_leaves) in self
            .splits
            .chunks_exact(n_leaves - 1)
            .zip(self.leaves.chunks_exact(n_leaves))
        {
            s.push_str("tree");
            for sp in tree_splits {
                let _ = write!(s, " {} {}", VOICING_FEATURES[sp.feature], sp.threshold);
            }
            s.push_str(" leaves");
            for v in tree_leaves {
                let _ = write!(s, " {v}");
            }
            s.push('\n');
        }
    }
}

/// A line error.
fn bad(line: usize, message: String) -> VoicingModelError {
    VoicingModelError::Line { line, message }
}

/// `text` as a finite number, or the error naming `key` and the line.
fn number(line: usize, key: &str, text: &str) -> Result<f32, VoicingModelError> {
    text.parse::<f32>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| bad(line, format!("{key} {text:?} is not a finite number")))
}

/// The `feature` lines and the `bias` line of a logistic regression.
fn parse_linear<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
) -> Result<Linear, VoicingModelError> {
    let (mut mean, mut scale, mut weight) = (
        [0.0; N_VOICING_FEATURES],
        [0.0; N_VOICING_FEATURES],
        [0.0; N_VOICING_FEATURES],
    );
    for (i, name) in VOICING_FEATURES.iter().enumerate() {
        let (line, l) = keyed_line(lines, &format!("the line of feature {name}"))?;
        let t: Vec<&str> = l.split_whitespace().collect();
        let shape = t.len() == 8
            && t[0] == "feature"
            && t[2] == "mean"
            && t[4] == "scale"
            && t[6] == "weight";
        if !shape {
            return Err(bad(
                line,
                format!("expected `feature {name} mean <m> scale <s> weight <w>`, found `{l}`"),
            ));
        }
        if t[1] != *name {
            return Err(bad(
                line,
                format!(
                    "expected feature {name} here (features come in a fixed order), found {}",
                    t[1]
                ),
            ));
        }
        mean[i] = number(line, "mean", t[3])?;
        scale[i] = number(line, "scale", t[5])?;
        weight[i] = number(line, "weight", t[7])?;
        if scale[i] <= 0.0 {
            return Err(bad(line, format!("scale {} must be positive", t[5])));
        }
    }
    let (_, bias) = keyed_number(lines, "bias")?;
    Ok(Linear {
        mean,
        scale,
        weight,
        bias,
    })
}

/// The `count` `tree` lines of depth `depth` (both as written on the `trees` line, `line`).
fn parse_trees<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    line: usize,
    count: &str,
    depth: &str,
) -> Result<Ensemble, VoicingModelError> {
    let count = count
        .parse::<usize>()
        .map_err(|_| bad(line, format!("tree count {count:?} is not a whole number")))?;
    let depth = depth
        .parse::<usize>()
        .ok()
        .filter(|d| (1..=MAX_TREE_DEPTH).contains(d))
        .ok_or_else(|| {
            bad(
                line,
                format!("depth {depth:?} is not a whole number in 1..={MAX_TREE_DEPTH}"),
            )
        })?;
    let n_leaves = 1usize << depth;
    let mut splits = Vec::with_capacity(count * (n_leaves - 1));
    let mut leaves = Vec::with_capacity(count * n_leaves);
    let mut last = line;
    for k in 0..count {
        let (line, l) = keyed_line(lines, &format!("tree {} of {count}", k + 1))?;
        last = line;
        let t: Vec<&str> = l.split_whitespace().collect();
        let expected = 1 + 2 * (n_leaves - 1) + 1 + n_leaves;
        if t.len() != expected || t[0] != "tree" || t[2 * n_leaves - 1] != "leaves" {
            return Err(bad(
                line,
                format!(
                    "tree {} of {count}: expected `tree` then {} pairs `<cue> <threshold>`, `leaves` and {n_leaves} numbers (depth {depth}), found `{l}`",
                    k + 1,
                    n_leaves - 1
                ),
            ));
        }
        for pair in t[1..2 * n_leaves - 1].chunks_exact(2) {
            let feature = VOICING_FEATURES
                .iter()
                .position(|n| *n == pair[0])
                .ok_or_else(|| {
                    bad(
                        line,
                        format!(
                            "unknown cue {:?} (the cues are {})",
                            pair[0],
                            VOICING_FEATURES.join(", ")
                        ),
                    )
                })?;
            splits.push((feature, number(line, "threshold", pair[1])?));
        }
        for v in &t[2 * n_leaves..] {
            leaves.push(number(line, "leaf", v)?);
        }
    }
    Ensemble::new(depth, splits, leaves).map_err(|e| bad(last, e.to_string()))
}

/// The next content line of a model file, or the error naming what is missing.
fn keyed_line<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    what: &str,
) -> Result<(usize, &'a str), VoicingModelError> {
    lines.next().ok_or_else(|| VoicingModelError::Truncated {
        missing: what.to_string(),
    })
}

/// The next content line, which must read `<key> <number>`.
fn keyed_number<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    key: &str,
) -> Result<(usize, f32), VoicingModelError> {
    let (line, l) = keyed_line(lines, &format!("the `{key}` line"))?;
    match l.split_whitespace().collect::<Vec<_>>()[..] {
        [k, v] if k == key => number(line, key, v).map(|v| (line, v)),
        _ => Err(bad(line, format!("expected `{key} <number>`, found `{l}`"))),
    }
}

#[cfg(test)]
mod tests {
    use super::super::model::tests::{hybrid, logistic, two_trees};
    use super::*;

    #[test]
    fn the_shipped_model_parses_and_reads_back_bit_for_bit() {
        let m = VoicingModel::parse(SHIPPED_MODEL).unwrap();
        let text = m.to_text(&[]);
        assert_eq!(VoicingModel::parse(&text).unwrap(), m);
        // The shipped file is exactly what the writer makes of it, apart from its notes.
        let body: String = SHIPPED_MODEL
            .lines()
            .filter(|l| !l.starts_with('#'))
            .map(|l| format!("{l}\n"))
            .collect();
        assert_eq!(body, text);
        // Both versions read back bit for bit.
        for m in [logistic(), two_trees(), hybrid()] {
            assert_eq!(VoicingModel::parse(&m.to_text(&["n".into()])).unwrap(), m);
        }
        assert!(hybrid().to_text(&[]).starts_with(FORMAT_LINE));
        assert!(logistic().to_text(&[]).starts_with(FORMAT_LINE_V1));
        assert!(two_trees().to_text(&[]).starts_with(FORMAT_LINE_V2));
    }

    #[test]
    fn malformed_version_3_files_are_rejected_naming_the_line() {
        let good = hybrid().to_text(&["a note".into()]);
        let n = good.lines().count();
        // From 0: line 0 the note, 1 the format, then the features, then (at `b`) the bias,
        // the `trees` line and the two trees, then the thresholds.
        let b = 2 + N_VOICING_FEATURES;
        assert_eq!(
            line_of(&with(&good, b + 1, "trees 2 depth 2 base 0.5")),
            b + 2
        );
        assert_eq!(line_of(&with(&good, b + 1, "trees 2 depth 5")), b + 2);
        assert_eq!(line_of(&with(&good, b, "bias x")), b + 1);
        let tree = good.lines().nth(b + 2).unwrap();
        assert_eq!(
            line_of(&with(&good, b + 3, &tree.replace("leaves", "leafs"))),
            b + 4
        );
        assert_eq!(line_of(&with(&good, n - 1, "threshold_off 2")), n);
        // A version 3 file without its trees: the thresholds come where the `trees` line must.
        let no_trees: Vec<&str> = good.lines().filter(|l| !l.starts_with("tree")).collect();
        assert_eq!(line_of(&no_trees.join("\n")), b + 2);
    }

    /// The 1-based line of a parse error (panics on anything else).
    fn line_of(text: &str) -> usize {
        match VoicingModel::parse(text) {
            Err(VoicingModelError::Line { line, .. }) => line,
            other => panic!("expected a line error, got {other:?}"),
        }
    }

    /// `text` with its line `i` (from 0) replaced by `l`.
    fn with(text: &str, i: usize, l: &str) -> String {
        let mut v: Vec<&str> = text.lines().collect();
        v[i] = l;
        v.join("\n")
    }

    #[test]
    fn malformed_version_1_files_are_rejected_naming_the_line() {
        let good = logistic().to_text(&["a note".into()]);
        let n = good.lines().count();
        // `with` counts from 0, the messages from 1: line 1 is the note, line 2 the format,
        // 3.. the features.
        assert_eq!(line_of(&with(&good, 1, "pneuma-voicing-model 4")), 2);
        assert_eq!(
            line_of(&with(
                &good,
                2,
                "feature long_clarity mean x scale 1 weight 1"
            )),
            3
        );
        // The second feature line naming the first feature: out of order.
        assert_eq!(
            line_of(&with(
                &good,
                3,
                "feature long_clarity mean 0 scale 1 weight 1"
            )),
            4
        );
        assert_eq!(
            line_of(&with(
                &good,
                4,
                "feature short_clarity mean 0 scale 0 weight 1"
            )),
            5
        );
        assert_eq!(line_of(&with(&good, n - 1, "threshold_off 99")), n);
        let e = VoicingModel::parse(&with(
            &good,
            2,
            "feature long_clarity mean NaN scale 1 weight 1",
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("line 3") && e.contains("cargo xtask train-voicing"),
            "{e}"
        );
        let cut: Vec<&str> = good.lines().take(n - 2).collect();
        assert!(matches!(
            VoicingModel::parse(&cut.join("\n")),
            Err(VoicingModelError::Truncated { .. })
        ));
    }

    #[test]
    fn malformed_version_2_files_are_rejected_naming_the_line() {
        let good = two_trees().to_text(&["a note".into()]);
        let n = good.lines().count();
        // Line 2 the format, 3 the `trees` line, 4 and 5 the trees, then the thresholds.
        assert_eq!(line_of(&with(&good, 2, "trees 2 depth 9 base 0")), 3);
        assert_eq!(line_of(&with(&good, 2, "trees 2 base 0 depth 2")), 3);
        let tree = good.lines().nth(3).unwrap();
        assert_eq!(
            line_of(&with(&good, 3, &tree.replace("long_clarity", "loudness"))),
            4
        );
        assert_eq!(line_of(&with(&good, 4, &format!("{tree} 1"))), 5);
        assert_eq!(
            line_of(&with(&good, 4, &tree.replace("leaves", "leafs"))),
            5
        );
        assert_eq!(line_of(&with(&good, 3, &tree.replace("-2", "inf"))), 4);
        assert_eq!(line_of(&with(&good, n - 1, "threshold_off 2")), n);
        // A third tree announced but missing: the file ends early.
        let e = VoicingModel::parse(&with(&good, 2, "trees 3 depth 2 base 0.5")).unwrap_err();
        assert_eq!(line_of(&with(&good, 2, "trees 3 depth 2 base 0.5")), n - 1);
        assert!(e.to_string().contains("tree 3 of 3"), "{e}");
        let cut: Vec<&str> = good.lines().take(4).collect();
        let e = VoicingModel::parse(&cut.join("\n")).unwrap_err();
        assert!(
            matches!(e, VoicingModelError::Truncated { .. })
                && e.to_string().contains("tree 2 of 2"),
            "{e}"
        );
    }
}
