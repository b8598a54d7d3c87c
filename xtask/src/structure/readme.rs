//! The README check: a user's page, not a notebook. `README.md` at the root has at most
//! [`MAX_LINES`] lines of at most [`MAX_CHARS`] characters, and opens with the two commands:
//! its first two fenced code blocks come before its first `## ` heading, the first runs the
//! main job (`cargo run …`), the second the tests (`cargo test`). The details live in
//! `docs/guide/` and the figures in `docs/measurements.md`.

use std::path::Path;

/// The README's path from the root.
pub const README: &str = "README.md";

/// The most lines the README may have.
pub const MAX_LINES: usize = 300;

/// The most characters (not bytes) a README line may have.
pub const MAX_CHARS: usize = 100;

/// What the README check found wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Problem {
    /// There is no README at the root.
    Missing,
    /// More than [`MAX_LINES`] lines.
    TooLong {
        /// Its lines.
        lines: usize,
    },
    /// A line over [`MAX_CHARS`] characters.
    WideLine {
        /// The line's number, from 1.
        line: usize,
        /// Its characters.
        chars: usize,
    },
    /// The opening does not give the two commands first.
    CommandsNotFirst(String),
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Problem::Missing => write!(f, "{README} is missing: write one at the root"),
            Problem::TooLong { lines } => write!(
                f,
                "{README} has {lines} lines (at most {MAX_LINES}): move details to docs/guide/ \
                 and figures to docs/measurements.md"
            ),
            Problem::WideLine { line, chars } => write!(
                f,
                "{README}:{line} has {chars} characters (at most {MAX_CHARS}): wrap it"
            ),
            Problem::CommandsNotFirst(why) => write!(
                f,
                "{README} does not open with the two commands: {why} (the first two code \
                 blocks, before the first `## ` heading: `cargo run …`, then `cargo test`)"
            ),
        }
    }
}

/// The fenced code blocks before the first `## ` heading, each as its non-empty lines.
fn opening_blocks(text: &str) -> Vec<Vec<&str>> {
    let mut blocks = Vec::new();
    let mut open: Option<Vec<&str>> = None;
    for line in text.lines() {
        let fence = line.trim_start().starts_with("```");
        match open.as_mut() {
            Some(block) if fence => {
                blocks.push(std::mem::take(block));
                open = None;
            }
            Some(block) if !line.trim().is_empty() => block.push(line.trim()),
            Some(_) => {}
            None if fence => open = Some(Vec::new()),
            None if line.starts_with("## ") => break,
            None => {}
        }
    }
    blocks
}

/// Whether `line` runs the command `cargo <sub>` (`cargo test`, `cargo run --release …`).
fn runs(line: &str, sub: &str) -> bool {
    let mut words = line.split_whitespace();
    words.next() == Some("cargo") && words.next() == Some(sub)
}

/// The problems of a README's text.
pub fn problems(text: &str) -> Vec<Problem> {
    let mut found = Vec::new();
    let lines = text.lines().count();
    if lines > MAX_LINES {
        found.push(Problem::TooLong { lines });
    }
    for (n, line) in text.lines().enumerate() {
        let chars = line.chars().count();
        if chars > MAX_CHARS {
            found.push(Problem::WideLine { line: n + 1, chars });
        }
    }
    let blocks = opening_blocks(text);
    let why = match blocks.as_slice() {
        [] => Some("no code block before the first `## ` heading".to_owned()),
        [first, ..] if !first.first().is_some_and(|l| runs(l, "run")) => Some(format!(
            "the first code block starts with `{}`, not `cargo run`",
            first.first().copied().unwrap_or("")
        )),
        [_] => Some("only one code block before the first `## ` heading".to_owned()),
        [_, second, ..] if !second.iter().any(|l| runs(l, "test")) => {
            Some("the second code block has no `cargo test`".to_owned())
        }
        _ => None,
    };
    found.extend(why.map(Problem::CommandsNotFirst));
    found
}

/// The problems of the README at `root`.
pub fn check(root: &Path) -> Result<Vec<Problem>, String> {
    let path = root.join(README);
    if !path.is_file() {
        return Ok(vec![Problem::Missing]);
    }
    let text = std::fs::read_to_string(&path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(problems(&text))
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "# Tool\n\nWhat it is.\n\n**Run it**:\n\n```sh\n\
                        cargo run --release -p tool -- go in.wav -o out\n```\n\n\
                        **Test it**:\n\n```sh\ncargo test\n```\n\n## More\n\n```sh\nls\n```\n";

    #[test]
    fn a_readme_that_opens_with_the_two_commands_passes() {
        assert_eq!(problems(GOOD), []);
        // 100 characters, some of them multi-byte, is not too wide.
        let wide_in_bytes = format!("{GOOD}{}\n", "−".repeat(100));
        assert_eq!(problems(&wide_in_bytes), []);
    }

    #[test]
    fn too_many_lines_and_wide_lines_are_reported() {
        let long = format!("{GOOD}{}", "x\n".repeat(MAX_LINES));
        assert_eq!(
            problems(&long),
            [Problem::TooLong {
                lines: GOOD.lines().count() + MAX_LINES
            }]
        );
        let wide = format!("{GOOD}{}\n", "y".repeat(101));
        assert_eq!(
            problems(&wide),
            [Problem::WideLine {
                line: GOOD.lines().count() + 1,
                chars: 101
            }]
        );
    }

    #[test]
    fn the_commands_must_come_first_and_in_order() {
        let not_first =
            |text: &str| matches!(problems(text).as_slice(), [Problem::CommandsNotFirst(_)]);
        // A heading before the commands.
        assert!(not_first(&format!(
            "# Tool\n\n## Install\n\n{}",
            &GOOD[7..]
        )));
        // The tests first.
        assert!(not_first(
            "# Tool\n\n```sh\ncargo test\n```\n\n```sh\ncargo run -p tool\n```\n"
        ));
        // The test command missing, or after the first heading.
        assert!(not_first(&GOOD.replace("cargo test", "make check")));
        assert!(not_first(
            "# Tool\n\n```sh\ncargo run -p tool\n```\n\n## Tests\n\n```sh\ncargo test\n```\n"
        ));
        // No code at all.
        assert!(not_first("# Tool\n\nWords only.\n"));
    }

    #[test]
    fn a_missing_readme_is_reported() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        assert_eq!(check(dir.path()).unwrap(), [Problem::Missing]);
        std::fs::write(dir.path().join(README), GOOD).unwrap();
        assert_eq!(check(dir.path()).unwrap(), []);
    }
}
