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

/// The chunks of a text (cut as written, its dashes among the breaks) with their texts folded,
/// and the distinct characters left out of them all; a chunk of nothing an ASCII reader can say
/// is dropped (its characters are in the list).
pub fn fold_chunks(mut chunks: Vec<Chunk>) -> (Vec<Chunk>, Vec<char>) {
    let mut left_out: Vec<char> = Vec::new();
    for c in &mut chunks {
        let folded = fold(&c.text);
        c.text = folded.text;
        for l in folded.left_out {
            if !left_out.contains(&l) {
                left_out.push(l);
            }
        }
    }
    chunks.retain(|c| c.text.chars().any(|c| c.is_ascii_alphanumeric()));
    (chunks, left_out)
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
        // Latin Extended-A, in its blocks of one base letter.
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
    // Each range holds the forms of one base letter (Œ, Ĳ and ſ are folded before); the case
    // comes from Unicode itself, not from the offset (ĸ and ŉ have no upper case).
    const BASES: [(char, char, &str, &str); 19] = [
        ('\u{100}', '\u{105}', "A", "a"),
        ('\u{106}', '\u{10d}', "C", "c"),
        ('\u{10e}', '\u{111}', "D", "d"),
        ('\u{112}', '\u{11b}', "E", "e"),
        ('\u{11c}', '\u{123}', "G", "g"),
        ('\u{124}', '\u{127}', "H", "h"),
        ('\u{128}', '\u{131}', "I", "i"),
        ('\u{134}', '\u{135}', "J", "j"),
        ('\u{136}', '\u{138}', "K", "k"),
        ('\u{139}', '\u{142}', "L", "l"),
        ('\u{143}', '\u{14b}', "N", "n"),
        ('\u{14c}', '\u{151}', "O", "o"),
        ('\u{154}', '\u{159}', "R", "r"),
        ('\u{15a}', '\u{161}', "S", "s"),
        ('\u{162}', '\u{167}', "T", "t"),
        ('\u{168}', '\u{173}', "U", "u"),
        ('\u{174}', '\u{175}', "W", "w"),
        ('\u{176}', '\u{178}', "Y", "y"),
        ('\u{179}', '\u{17e}', "Z", "z"),
    ];
    let &(_, _, upper, lower) = BASES.iter().find(|(lo, hi, ..)| (*lo..=*hi).contains(&c))?;
    Some(if c.is_uppercase() { upper } else { lower })
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
        let (folded, left_out) = fold_chunks(vec![
            chunk("Caf\u{e9} \u{2014}"),
            chunk("\u{65e5}\u{672c}."),
            chunk("Zo\u{eb} \u{65e5}."),
        ]);
        let texts: Vec<&str> = folded.iter().map(|c| c.text.as_str()).collect();
        assert_eq!(texts, ["Cafe  - ", "Zoe  ."]);
        assert_eq!(left_out, ['\u{65e5}', '\u{672c}']);
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
