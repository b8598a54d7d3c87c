//! The syllable counter's exact-match accuracy on the committed word list
//! (`core/src/breathing/syllable_words.txt`), overall and on the words the rules handle alone
//! (not in the counter's exception table).

use pneuma_core::breathing::{count_syllables, count_syllables_text};

const LIST: &str = include_str!("../../src/breathing/syllable_words.txt");
const SOURCE: &str = include_str!("../../src/breathing/syllables.rs");

#[test]
fn exact_match_accuracy_is_at_least_90_percent() {
    let mut total = 0;
    let mut right = 0;
    let mut rules_total = 0;
    let mut rules_right = 0;
    let mut misses = Vec::new();
    let mut held_out = false;
    let (mut held_total, mut held_right) = (0, 0);
    for line in LIST.lines() {
        let line = line.trim();
        if line.starts_with("# Harder words") {
            held_out = true;
        }
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let (word, n) = line.split_once(' ').expect("`word count` lines");
        let n: u32 = n.trim().parse().expect("a count");
        let got = count_syllables(word);
        let exception = SOURCE.contains(&format!("(\"{word}\","));
        total += 1;
        held_total += usize::from(held_out);
        held_right += usize::from(held_out && got == n);
        rules_total += usize::from(!exception);
        if got == n {
            right += 1;
            rules_right += usize::from(!exception);
        } else {
            misses.push(format!("{word}: {got} (want {n})"));
        }
    }
    let acc = right as f64 / total as f64;
    let rules_acc = rules_right as f64 / rules_total as f64;
    eprintln!(
        "syllable counter: {right}/{total} = {:.1} % exact; rules alone {rules_right}/{rules_total} = {:.1} %; held-out hard words {held_right}/{held_total} = {:.1} %; misses: {}",
        100.0 * acc,
        100.0 * rules_acc,
        100.0 * held_right as f64 / held_total as f64,
        misses.join(", ")
    );
    assert!(total >= 500, "the list has {total} words");
    assert!(acc >= 0.90, "accuracy {:.3}", acc);
    assert!(rules_acc >= 0.90, "rules-only accuracy {:.3}", rules_acc);
    assert!(held_total >= 50 && held_right as f64 >= 0.85 * held_total as f64);
}

#[test]
fn text_counts_sum_words_and_skip_punctuation() {
    assert_eq!(
        count_syllables_text("Hello, world. _ The table!"),
        2 + 1 + 1 + 2
    );
    assert_eq!(count_syllables_text(""), 0);
    assert_eq!(count_syllables("Table,"), 2);
    assert_eq!(count_syllables("WALKED"), 1);
}
