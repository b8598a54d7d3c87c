//! Text for a TTS that reads ASCII only (festival's `text2wave`).
//!
//! festival reads its input byte by byte as an 8-bit English text: each byte of a UTF-8 "é"
//! becomes a pause or a spelled letter, so "café" is said "caf", a pause, and "naïve" as
//! nonsense. [`fold`] writes accented Latin letters as their base letters ("cafe", "naive",
//! "Strasse"), typographic quotes, dashes and spaces as their ASCII forms, common symbols as
//! words ("€5" as "euro 5"), drops what is invisible (soft hyphens, zero-width spaces, a byte
//! order mark, combining accents), and leaves out what has no ASCII spelling, listing it so the
//! user is told (never silently lost).

use pneuma_core::breathing::Chunk;

/// A text folded to ASCII and the characters that had no ASCII form.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Folded {
    /// The text in ASCII: every character of the input folded, or a space for one left out.
    pub text: String,
    /// The distinct characters left out, in the order of their first appearance.
    pub left_out: Vec<char>,
}

/// Folds `text` to ASCII (see the module's documentation).
pub fn fold(text: &str) -> Folded {
    let mut out = String::with_capacity(text.len());
    let mut left_out = Vec::new();
    for c in text.chars() {
        if c.is_ascii() {
            out.push(c);
        } else if let Some(s) = ascii_form(c) {
            out.push_str(s);
        } else {
            out.push(' ');
            if !left_out.contains(&c) {
                left_out.push(c);
            }
        }
    }
    Folded {
        text: out,
        left_out,
    }
}

/// The chunks of a text (cut as written, its dashes among the breaks) with their texts folded;
/// a chunk of nothing an ASCII reader can say (named by [`fold`]'s list) is dropped.
pub fn fold_chunks(mut chunks: Vec<Chunk>) -> Vec<Chunk> {
    for c in &mut chunks {
        c.text = fold(&c.text).text;
    }
    chunks.retain(|c| c.text.chars().any(|c| c.is_ascii_alphanumeric()));
    chunks
}

/// The ASCII form of a non-ASCII character, where it has one (empty for an invisible one).
fn ascii_form(c: char) -> Option<&'static str> {
    Some(match c {
        // Invisible: soft hyphen, zero-width spaces and joiners, word joiner, byte order mark,
        // combining accents (a decomposed "é" is "e" and one of these).
        '\u{ad}' | '\u{200b}'..='\u{200d}' | '\u{2060}' | '\u{feff}' | '\u{300}'..='\u{36f}' => "",
        // Punctuation and spaces a word processor writes.
        '\u{a0}' | '\u{2000}'..='\u{200a}' | '\u{202f}' | '\u{3000}' => " ",
        '\u{2018}' | '\u{2019}' | '\u{201a}' | '\u{201b}' | '\u{2032}' | '\u{b4}' => "'",
        '\u{201c}' | '\u{201d}' | '\u{201e}' | '\u{201f}' | '\u{2033}' | '\u{ab}' | '\u{bb}' => {
            "\""
        }
        // A hyphen inside a word stays one, as does a minus sign ("-3"); a dash between words
        // stays a dash.
        '\u{2010}' | '\u{2011}' | '\u{2212}' => "-",
        '\u{2012}'..='\u{2015}' => " - ",
        '\u{2026}' => "...",
        '\u{bf}' => "?",
        '\u{a1}' => "!",
        '\u{2022}' | '\u{b7}' | '\u{b6}' => " ",
        // Symbols festival would drop, as the words a reader says.
        '€' => " euro ",
        '£' => " pound ",
        '¥' => " yen ",
        '¢' => " cents ",
        '°' => " degrees ",
        '×' => " times ",
        '÷' => " divided by ",
        '±' => " plus or minus ",
        '½' => " one half ",
        '¼' => " one quarter ",
        '¾' => " three quarters ",
        '§' => " section ",
        '©' => " copyright ",
        '®' | '™' => "",
        'µ' => "micro",
        'ª' => "a",
        'º' => "o",
        // Letters of the Latin-1 supplement.
        'À'..='Å' => "A",
        'Æ' => "AE",
        'Ç' => "C",
        'È'..='Ë' => "E",
        'Ì'..='Ï' => "I",
        'Ð' => "D",
        'Ñ' => "N",
        'Ò'..='Ö' | 'Ø' => "O",
        'Ù'..='Ü' => "U",
        'Ý' => "Y",
        'Þ' => "Th",
        'ß' => "ss",
        'à'..='å' => "a",
        'æ' => "ae",
        'ç' => "c",
        'è'..='ë' => "e",
        'ì'..='ï' => "i",
        'ð' => "d",
        'ñ' => "n",
        'ò'..='ö' | 'ø' => "o",
        'ù'..='ü' => "u",
        'ý' | 'ÿ' => "y",
        'þ' => "th",
        // Latin Extended-A, in its blocks of one base letter (upper and lower case alternate).
        'Œ' => "OE",
        'œ' => "oe",
        'Ĳ' => "IJ",
        'ĳ' => "ij",
        'ſ' => "s",
        '\u{100}'..='\u{17e}' => latin_extended_a(c)?,
        // Romanian's comma-below letters, and the capital sharp s.
        'Ș' => "S",
        'ș' => "s",
        'Ț' => "T",
        'ț' => "t",
        'ẞ' => "SS",
        _ => return None,
    })
}

/// The base letter of a Latin Extended-A letter (U+0100–U+017E), in its case.
fn latin_extended_a(c: char) -> Option<&'static str> {
    // Each range holds the forms of one base letter (Œ, Ĳ and ſ are folded before).
    const BASES: [(char, char, char); 19] = [
        ('\u{100}', '\u{105}', 'a'),
        ('\u{106}', '\u{10d}', 'c'),
        ('\u{10e}', '\u{111}', 'd'),
        ('\u{112}', '\u{11b}', 'e'),
        ('\u{11c}', '\u{123}', 'g'),
        ('\u{124}', '\u{127}', 'h'),
        ('\u{128}', '\u{131}', 'i'),
        ('\u{134}', '\u{135}', 'j'),
        ('\u{136}', '\u{138}', 'k'),
        ('\u{139}', '\u{142}', 'l'),
        ('\u{143}', '\u{14b}', 'n'),
        ('\u{14c}', '\u{151}', 'o'),
        ('\u{154}', '\u{159}', 'r'),
        ('\u{15a}', '\u{161}', 's'),
        ('\u{162}', '\u{167}', 't'),
        ('\u{168}', '\u{173}', 'u'),
        ('\u{174}', '\u{175}', 'w'),
        ('\u{176}', '\u{178}', 'y'),
        ('\u{179}', '\u{17e}', 'z'),
    ];
    const UPPER: [&str; 26] = [
        "A", "B", "C", "D", "E", "F", "G", "H", "I", "J", "K", "L", "M", "N", "O", "P", "Q", "R",
        "S", "T", "U", "V", "W", "X", "Y", "Z",
    ];
    const LOWER: [&str; 26] = [
        "a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l", "m", "n", "o", "p", "q", "r",
        "s", "t", "u", "v", "w", "x", "y", "z",
    ];
    let &(_, _, base) = BASES.iter().find(|(lo, hi, _)| (*lo..=*hi).contains(&c))?;
    let i = usize::from(base as u8 - b'a');
    // The case from Unicode itself, not from the offset (ĸ and ŉ have no upper case).
    Some(if c.is_uppercase() { UPPER[i] } else { LOWER[i] })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accented_letters_fold_to_their_base_letters_in_their_case() {
        let f = fold(
            "Café, naïve Zoë; STRAẞE? Straße. Łódź, Ångström, Dvořák, Œuvre, Ĳssel, Timișoara, \
             cafe\u{301}, hy\u{ad}phen, \u{feff}well\u{2011}known",
        );
        assert_eq!(
            f.text,
            "Cafe, naive Zoe; STRASSE? Strasse. Lodz, Angstrom, Dvorak, OEuvre, IJssel, Timisoara, \
             cafe, hyphen, well-known"
        );
        assert!(f.left_out.is_empty(), "{:?}", f.left_out);
    }

    #[test]
    fn typographic_punctuation_becomes_ascii_and_the_rest_is_listed_once() {
        let f = fold(
            "He said \u{201c}hello\u{201d} \u{2014} twice\u{2026} It\u{2019}s 日本 日, €5 at \u{2212}20°.",
        );
        assert_eq!(
            f.text,
            "He said \"hello\"  -  twice... It's     ,  euro 5 at -20 degrees ."
        );
        assert_eq!(f.left_out, vec!['日', '本']);
        assert!(f.text.is_ascii());
    }

    #[test]
    fn chunks_are_folded_and_one_of_nothing_sayable_is_dropped() {
        let chunk = |text: &str| Chunk {
            text: text.to_owned(),
            start_byte: 0,
            end_byte: text.len(),
            syllables: 3,
            break_kind: pneuma_core::breathing::ChunkBreak::Sentence,
        };
        let folded = fold_chunks(vec![
            chunk("Caf\u{e9} \u{2014}"),
            chunk("\u{65e5}\u{672c}."),
            chunk("Zo\u{eb}."),
        ]);
        let texts: Vec<&str> = folded.iter().map(|c| c.text.as_str()).collect();
        assert_eq!(texts, ["Cafe  - ", "Zoe."]);
    }

    #[test]
    fn every_latin_1_and_extended_a_letter_folds_to_an_ascii_letter() {
        for c in ('\u{c0}'..='\u{17f}').filter(|c| c.is_alphabetic()) {
            let f = fold(&c.to_string());
            assert!(
                f.left_out.is_empty() && f.text.chars().all(|a| a.is_ascii_alphabetic()),
                "{c} (U+{:04X}) -> {:?}",
                c as u32,
                f.text
            );
        }
    }
}
