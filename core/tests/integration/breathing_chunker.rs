//! The text chunker: every branch of the paper's flow chart, the extra punctuation, and that no
//! word is lost or repeated.

use pneuma_core::breathing::{chunk_text, ChunkBreak, Chunker, LowLevelParams};

fn chunker(target: u32, limit: usize) -> Chunker {
    Chunker {
        target_syllables: target,
        urgency_limit_chars: limit,
        paper_markers_only: false,
    }
}

fn texts(c: &Chunker, s: &str) -> Vec<(String, ChunkBreak)> {
    c.chunks(s)
        .into_iter()
        .map(|c| (c.text, c.break_kind))
        .collect()
}

#[test]
fn short_text_is_one_chunk() {
    let got = texts(&chunker(10, 20), "  one two three.  ");
    assert_eq!(got, vec![("one two three.".into(), ChunkBreak::End)]);
    assert!(chunker(10, 20).chunks("   ").is_empty());
}

#[test]
fn sentence_marker_backward_within_the_limit() {
    let got = texts(
        &chunker(4, 10),
        "one two three. four five six seven eight nine ten",
    );
    assert_eq!(got[0], ("one two three.".into(), ChunkBreak::Sentence));
}

#[test]
fn sentence_marker_forward_within_the_limit() {
    let got = texts(
        &chunker(4, 10),
        "one two three four five. six seven eight nine ten",
    );
    assert_eq!(
        got[0],
        ("one two three four five.".into(), ChunkBreak::Sentence)
    );
}

#[test]
fn particle_marker_when_no_sentence_marker_is_near() {
    let got = texts(
        &chunker(4, 8),
        "one two three_ four five six seven eight nine ten eleven twelve. end",
    );
    assert_eq!(got[0], ("one two three".into(), ChunkBreak::Particle));
    // The underscore is not spoken.
    assert!(got.iter().all(|(t, _)| !t.contains('_')));
}

#[test]
fn word_boundary_when_both_markers_lie_beyond_the_limit() {
    let got = texts(
        &chunker(3, 5),
        "one two three four five six seven eight nine ten. eleven",
    );
    assert_eq!(got[0], ("one two three".into(), ChunkBreak::Word));
    assert_eq!(got[1], ("four five six".into(), ChunkBreak::Word));
}

#[test]
fn sentence_marker_is_preferred_to_a_nearer_particle() {
    let got = texts(&chunker(4, 10), "one two three. four_ five six seven eight");
    assert_eq!(got[0], ("one two three.".into(), ChunkBreak::Sentence));
}

#[test]
fn other_punctuation() {
    // "?" and "!" are sentence markers, "," ";" ":" particle markers.
    let got = texts(
        &chunker(4, 10),
        "one two three? four five six seven eight nine",
    );
    assert_eq!(got[0].1, ChunkBreak::Sentence);
    let got = texts(
        &chunker(4, 10),
        "one two three, four five six seven eight nine",
    );
    assert_eq!(got[0], ("one two three,".into(), ChunkBreak::Particle));
    // With the paper's markers only, a comma is just a character.
    let paper = Chunker {
        paper_markers_only: true,
        ..chunker(4, 10)
    };
    let got = texts(&paper, "one two three, four five six seven eight nine");
    assert_eq!(got[0], ("one two three, four".into(), ChunkBreak::Word));
    // A decimal point is not a sentence end.
    let got = texts(
        &chunker(2, 10),
        "it costs 3.5 euros and more and more and more",
    );
    assert_ne!(got[0].0, "it costs 3.");
}

#[test]
fn a_title_an_initial_or_a_dotted_abbreviation_ends_no_sentence() {
    let paper = Chunker {
        paper_markers_only: true,
        ..chunker(5, 20)
    };
    for (text, abbreviation) in [
        (
            "Her grandfather, Capt. Thomas Marsh, kept the light",
            "Capt.",
        ),
        ("they met with J. Smith, late at night, alone", "J."),
        ("we left at 9 p.m. near the cafe, alone again", "p.m."),
    ] {
        // The paper's markers break after the abbreviation's "." (the nearest "." to the
        // target): a breath between a title and its name.
        let got = texts(&paper, text);
        assert!(got[0].0.ends_with(abbreviation), "{got:?}");
        // With the other punctuation, no chunk ends there.
        let got = texts(&chunker(5, 20), text);
        assert!(
            got.iter().all(|(c, _)| !c.ends_with(abbreviation)),
            "{text}: {got:?}"
        );
    }
    // A sentence still ends at a word's ".".
    let got = texts(&chunker(3, 10), "the keeper slept. Thomas woke");
    assert_eq!(got[0], ("the keeper slept.".into(), ChunkBreak::Sentence));
}

#[test]
fn no_word_is_lost_or_repeated() {
    let text = "Breathing is vital for animals. What about virtual characters? Does the \
                perceivable presence or absence of this behavior play a role in how they are \
                perceived_ is breathing movement, frequency, sound etc. effective at conveying \
                state and trait related information; these questions motivate the research.";
    for preset in pneuma_core::breathing::Preset::ALL {
        let params: LowLevelParams = preset.params().map();
        let chunks = chunk_text(text, &params);
        assert!(chunks.len() >= 2, "{preset}");
        let joined: Vec<String> = chunks
            .iter()
            .flat_map(|c| {
                c.text
                    .split_whitespace()
                    .map(str::to_owned)
                    .collect::<Vec<_>>()
            })
            .collect();
        let original: Vec<String> = text
            .replace('_', " ")
            .split_whitespace()
            .map(str::to_owned)
            .collect();
        assert_eq!(joined, original, "{preset}");
        for w in chunks.windows(2) {
            assert!(w[0].end_byte <= w[1].start_byte);
        }
        // Chunks stay near the target (the urgency limit bounds the overshoot).
        let target = params.length_utterance_syllables;
        for c in &chunks[..chunks.len() - 1] {
            assert!(
                (c.syllables as f32) < target + params.urgency_limit,
                "{preset}: {} syllables in {:?}",
                c.syllables,
                c.text
            );
        }
    }
}
