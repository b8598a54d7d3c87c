//! The paper's text chunker (its Figure 3 flow chart): cut text into breath groups.
//!
//! For each chunk:
//! 1. Step through the words, adding their syllables, until the count reaches the target
//!    (`length_utterance_syllables`, rounded, at least 1) or the text runs out (then the rest is
//!    the last chunk). (The flow chart's second loop condition is garbled; we read it as "no
//!    words remain".)
//! 2. Map the position back onto the text: the end of the word that reached the target.
//! 3. Search backward (not before the chunk's start) and forward from there for the nearest
//!    pause markers of each priority.
//! 4. If a **sentence** marker lies within `urgency_limit` characters, break after it; otherwise,
//!    if a **particle** marker does, break after it; otherwise break at the word boundary
//!    ("." is preferred to "_", as the paper's text says; nearer wins within one priority,
//!    backward on ties).
//!
//! Markers: the paper's "." (sentence) and "_" (particle). Other punctuation, unless
//! [`Chunker::paper_markers_only`]: "?" and "!" are sentence markers like "."; "," ";" ":" and
//! dashes are particle markers like "_". Sentence punctuation counts only when followed by white
//! space or the end of the text (so "3.5" and "e.g.x" are not breaks), and, beyond the paper's
//! markers, a "." after an abbreviation (a title, an initial, "p.m.") is none. Underscores are removed
//! from the text sent to the TTS; all other characters are kept.

use super::{count_syllables, LowLevelParams};

/// Why a chunk ends where it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ChunkBreak {
    /// After a sentence marker (".", and "?" "!").
    Sentence,
    /// After a particle marker ("_", and "," ";" ":" dashes).
    Particle,
    /// At a word boundary: no marker within the urgency limit.
    Word,
    /// The text ran out.
    End,
}

/// One breath group.
#[derive(Debug, Clone, PartialEq)]
pub struct Chunk {
    /// The text to speak (underscores removed, white space collapsed).
    pub text: String,
    /// Byte offset of the chunk's start in the input.
    pub start_byte: usize,
    /// Byte offset just after the chunk's end in the input.
    pub end_byte: usize,
    /// Syllables in the chunk.
    pub syllables: u32,
    /// Why it ends here.
    pub break_kind: ChunkBreak,
}

/// Chunker settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Chunker {
    /// Syllables per chunk to aim for (≥ 1).
    pub target_syllables: u32,
    /// How far (characters) a break may move from the target to reach a marker.
    pub urgency_limit_chars: usize,
    /// Only "." and "_" are markers (the paper); otherwise "?!" and ",;:" dashes count too.
    pub paper_markers_only: bool,
}

#[derive(Debug, Clone, Copy)]
struct Word {
    start: usize,
    end: usize,
    syllables: u32,
}

impl Chunker {
    /// Settings from the low-level parameters: target `length_utterance_syllables` (rounded),
    /// urgency `urgency_limit` characters.
    pub fn from_params(params: &LowLevelParams) -> Self {
        Self {
            target_syllables: params.length_utterance_syllables.round().max(1.0) as u32,
            urgency_limit_chars: params.urgency_limit.round().max(0.0) as usize,
            paper_markers_only: false,
        }
    }

    fn marker_priority(&self, text: &str, byte: usize, c: char) -> Option<ChunkBreak> {
        let followed_by_space = text[byte + c.len_utf8()..]
            .chars()
            .next()
            .is_none_or(|n| n.is_whitespace() || matches!(n, '"' | '\'' | ')' | '”' | '’'));
        match c {
            '.' if followed_by_space
                && (self.paper_markers_only || !ends_abbreviation(&text[..byte])) =>
            {
                Some(ChunkBreak::Sentence)
            }
            '_' => Some(ChunkBreak::Particle),
            '?' | '!' if !self.paper_markers_only && followed_by_space => {
                Some(ChunkBreak::Sentence)
            }
            ',' | ';' | ':' | '—' | '–' if !self.paper_markers_only => {
                Some(ChunkBreak::Particle)
            }
            _ => None,
        }
    }

    /// Cuts `text` into chunks (empty text: no chunks).
    pub fn chunks(&self, text: &str) -> Vec<Chunk> {
        let words: Vec<Word> = words(text);
        let mut out = Vec::new();
        let target = self.target_syllables.max(1);
        let mut wi = 0;
        let mut pos = 0;
        loop {
            while wi < words.len() && words[wi].end <= pos {
                wi += 1;
            }
            if wi >= words.len() {
                break;
            }
            // A break after a marker glued to the next word starts the chunk mid-word.
            let start = pos.max(words[wi].start);
            // 1. Step through syllables until the target is reached.
            let mut syl = 0;
            let mut k = wi;
            while k < words.len() {
                syl += words[k].syllables;
                if syl >= target {
                    break;
                }
                k += 1;
            }
            let (brk, kind) = if k + 1 >= words.len() {
                // The text runs out before (or just as) the target is reached.
                (words[words.len() - 1].end, ChunkBreak::End)
            } else {
                // 2. The target's position in the text: the end of word k.
                self.choose_break(text, start, words[k].end)
            };
            let chunk_text = spoken(&text[start..brk]);
            if !chunk_text.is_empty() {
                out.push(Chunk {
                    syllables: chunk_text.split_whitespace().map(count_syllables).sum(),
                    text: chunk_text,
                    start_byte: start,
                    end_byte: brk,
                    break_kind: kind,
                });
            }
            pos = brk;
        }
        out
    }

    /// Steps 3–4: the break position (byte offset just after it) for a target position `p`.
    fn choose_break(&self, text: &str, start: usize, p: usize) -> (usize, ChunkBreak) {
        let limit = self.urgency_limit_chars;
        let mut best: [Option<(usize, usize)>; 2] = [None, None]; // (distance chars, break byte)
                                                                  // Backward: markers at or before p (the marker char must end at or before p).
        for (dist, (b, c)) in text[start..p].char_indices().rev().enumerate() {
            let byte = start + b;
            if dist > limit {
                break;
            }
            if let Some(kind) = self.marker_priority(text, byte, c) {
                let slot = (kind == ChunkBreak::Particle) as usize;
                let cand = (dist, byte + c.len_utf8());
                if best[slot].is_none() {
                    best[slot] = Some(cand);
                }
            }
        }
        // Forward: markers after p.
        for (dist, (b, c)) in (1usize..).zip(text[p..].char_indices()) {
            let byte = p + b;
            if dist > limit {
                break;
            }
            if let Some(kind) = self.marker_priority(text, byte, c) {
                let slot = (kind == ChunkBreak::Particle) as usize;
                let cand = (dist, byte + c.len_utf8());
                if best[slot].is_none_or(|(d, _)| dist < d) {
                    best[slot] = Some(cand);
                }
            }
        }
        if let Some((_, b)) = best[0] {
            (b, ChunkBreak::Sentence)
        } else if let Some((_, b)) = best[1] {
            (b, ChunkBreak::Particle)
        } else {
            (p, ChunkBreak::Word)
        }
    }
}

/// Titles whose "." ends no sentence: a name follows ("Capt. Thomas Marsh").
const TITLES: [&str; 19] = [
    "mr", "mrs", "ms", "dr", "prof", "capt", "col", "gen", "lt", "sgt", "rev", "hon", "gov", "sen",
    "rep", "st", "mt", "jr", "sr",
];

/// Whether `before` (the text up to a ".") ends with an abbreviation, so that the "." ends no
/// sentence: a title ([`TITLES`]), an initial ("J."), or a word with dots inside ("p.m.",
/// "e.g.", "U.S."). Such a "." ends a sentence now and then ("at 9 p.m. We left"); the chunk
/// then breaks at the next marker or word instead, never inside a name.
fn ends_abbreviation(before: &str) -> bool {
    let word = before
        .rsplit(char::is_whitespace)
        .next()
        .unwrap_or("")
        .trim_start_matches(|c: char| !c.is_alphanumeric());
    let mut chars = word.chars();
    let initial = chars.next().is_some_and(char::is_alphabetic) && chars.next().is_none();
    initial
        || (word.contains('.') && word.chars().all(|c| c.is_alphabetic() || c == '.'))
        || TITLES.contains(&word.to_lowercase().as_str())
}

fn words(text: &str) -> Vec<Word> {
    let mut out = Vec::new();
    let mut start = None;
    for (b, c) in text
        .char_indices()
        .chain(std::iter::once((text.len(), ' ')))
    {
        if c.is_whitespace() {
            if let Some(s) = start.take() {
                out.push(Word {
                    start: s,
                    end: b,
                    syllables: count_syllables(&text[s..b]),
                });
            }
        } else if start.is_none() {
            start = Some(b);
        }
    }
    out
}

fn spoken(s: &str) -> String {
    s.replace('_', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Cuts `text` into breath groups with the settings of `params`
/// ([`Chunker::from_params`]).
pub fn chunk_text(text: &str, params: &LowLevelParams) -> Vec<Chunk> {
    Chunker::from_params(params).chunks(text)
}
