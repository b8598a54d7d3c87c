//! A small Rust lexer for the structure check: identifiers, `::`, punctuation and string
//! literals with their line numbers; comments (doc comments included), character literals,
//! lifetimes and numbers are dropped. It is not a full lexer: it only has to find module
//! declarations, `use` trees and paths, and never mistake text in a comment or a string for
//! code.

/// One token of a source file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Token {
    /// An identifier or keyword (raw identifiers without their `r#`).
    Ident(String),
    /// The path separator `::`.
    PathSep,
    /// A string literal's contents (escapes left as written).
    Str(String),
    /// Any other punctuation character.
    Punct(char),
}

/// A token and the 1-based line it starts on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Spanned {
    /// The token.
    pub token: Token,
    /// Its line.
    pub line: usize,
}

/// Splits `source` into tokens.
pub fn tokenize(source: &str) -> Vec<Spanned> {
    let chars: Vec<char> = source.chars().collect();
    let mut out = Vec::new();
    let mut line = 1;
    let mut i = 0;
    let at = |k: usize| chars.get(k).copied().unwrap_or('\0');
    while i < chars.len() {
        let c = chars[i];
        let start_line = line;
        let mut push = |token| {
            out.push(Spanned {
                token,
                line: start_line,
            })
        };
        if c == '\n' {
            line += 1;
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c == '/' && at(i + 1) == '/' {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && at(i + 1) == '*' {
            // Block comments nest.
            let mut depth = 0;
            while i < chars.len() {
                if chars[i] == '/' && at(i + 1) == '*' {
                    depth += 1;
                    i += 2;
                } else if chars[i] == '*' && at(i + 1) == '/' {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    line += usize::from(chars[i] == '\n');
                    i += 1;
                }
            }
        } else if let Some((text, end)) = raw_string(&chars, i) {
            line += text.matches('\n').count();
            push(Token::Str(text));
            i = end;
        } else if c == '"' || (c == 'b' && at(i + 1) == '"') {
            let mut k = if c == 'b' { i + 2 } else { i + 1 };
            let mut text = String::new();
            while k < chars.len() && chars[k] != '"' {
                if chars[k] == '\\' {
                    text.push(chars[k]);
                    k += 1;
                }
                line += usize::from(at(k) == '\n');
                text.push(at(k));
                k += 1;
            }
            push(Token::Str(text));
            i = k + 1;
        } else if c == '\'' || (c == 'b' && at(i + 1) == '\'') {
            // A character literal ('x', '\n', '\u{..}', b'x') or a lifetime / label ('a).
            let k = if c == 'b' { i + 1 } else { i };
            if at(k + 1) == '\\' {
                // Past the backslash and the escaped character, to the closing quote.
                let mut e = k + 3;
                while e < chars.len() && chars[e] != '\'' {
                    e += 1;
                }
                i = e + 1;
            } else if at(k + 2) == '\'' {
                i = k + 3;
            } else {
                i = k + 1;
                while i < chars.len() && is_ident_char(chars[i]) {
                    i += 1;
                }
            }
        } else if c.is_ascii_digit() {
            // Numbers, with suffixes, hex digits, underscores and exponents.
            while i < chars.len()
                && (is_ident_char(chars[i])
                    || (chars[i] == '.' && at(i + 1).is_ascii_digit())
                    || ((chars[i] == '-' || chars[i] == '+') && matches!(at(i - 1), 'e' | 'E')))
            {
                i += 1;
            }
        } else if is_ident_start(c) {
            let mut k = i;
            if c == 'r' && at(i + 1) == '#' && is_ident_start(at(i + 2)) {
                k += 2;
            }
            let mut e = k;
            while e < chars.len() && is_ident_char(chars[e]) {
                e += 1;
            }
            push(Token::Ident(chars[k..e].iter().collect()));
            i = e;
        } else if c == ':' && at(i + 1) == ':' {
            push(Token::PathSep);
            i += 2;
        } else {
            push(Token::Punct(c));
            i += 1;
        }
    }
    out
}

/// A raw string (`r"…"`, `r#"…"#`, `br#"…"#`) starting at `i`: its text and the index after it.
fn raw_string(chars: &[char], i: usize) -> Option<(String, usize)> {
    let mut k = i;
    if chars.get(k) == Some(&'b') {
        k += 1;
    }
    if chars.get(k) != Some(&'r') {
        return None;
    }
    k += 1;
    let mut hashes = 0;
    while chars.get(k) == Some(&'#') {
        hashes += 1;
        k += 1;
    }
    if chars.get(k) != Some(&'"') {
        return None;
    }
    let body = k + 1;
    let mut e = body;
    while e < chars.len() {
        if chars[e] == '"' && (0..hashes).all(|h| chars.get(e + 1 + h) == Some(&'#')) {
            return Some((chars[body..e].iter().collect(), e + 1 + hashes));
        }
        e += 1;
    }
    Some((chars[body..].iter().collect(), chars.len()))
}

fn is_ident_start(c: char) -> bool {
    c == '_' || c.is_alphabetic()
}

fn is_ident_char(c: char) -> bool {
    c == '_' || c.is_alphanumeric()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn idents(source: &str) -> Vec<String> {
        tokenize(source)
            .into_iter()
            .filter_map(|t| match t.token {
                Token::Ident(s) => Some(s),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn comments_strings_chars_and_lifetimes_hide_no_code_and_show_none() {
        let src =
            "//! see crate::a\n/* crate::b /* nested */ still::comment */ let s = \"crate::c\";\n\
                   let r = r#\"crate::d \"\"#; fn f<'a>(x: &'a str) -> char { '\\'' }\n\
                   let n = 1.5e-3f64 + 0x9E37_79B9; crate::e::f();";
        assert_eq!(
            idents(src),
            [
                "let", "s", "let", "r", "fn", "f", "x", "str", "char", "let", "n", "crate", "e",
                "f"
            ]
        );
        let lines: Vec<usize> = tokenize(src)
            .into_iter()
            .filter(|t| t.token == Token::Ident("e".into()))
            .map(|t| t.line)
            .collect();
        assert_eq!(lines, [4]);
    }
}
