//! Whether espeak-ng knows a voice before any text is spoken: `espeak-ng -v en-uss` (a typo
//! of `en-us`) and `-v en-us+nonsense` exit 0 and speak in another voice without a word, so
//! `speak` would write a whole take in a voice nobody asked for. The voice is looked up in
//! espeak-ng's own listings (`--voices`, `--voices=mb`, `--voices=variant`) in the forms `-v`
//! takes: a language code, a voice file (`gmw/en-US` or `en-US`), another language a voice
//! speaks, or a voice name (`English (America)`, the listing's underscores read as spaces), in
//! any case; a listed language with a region (`de-DE`, `en-AU`, `es-419`), which espeak-ng
//! speaks in that language; and after a `+`, a variant's file name (`f3`, `Alex`), exactly.

use std::process::Command;

/// What the listings say of `voice`: `Some(true)` known, `Some(false)` not among them, `None`
/// when espeak-ng could not be asked (the synthesis then says what is wrong).
pub fn espeak_knows(voice: &str) -> Option<bool> {
    let list = |which: &str| -> Option<String> {
        let out = Command::new("espeak-ng").arg(which).output().ok()?;
        out.status
            .success()
            .then(|| String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let voices = format!(
        "{}{}",
        list("--voices")?,
        list("--voices=mb").unwrap_or_default()
    );
    let (base, variant) = match voice.split_once('+') {
        Some((b, v)) => (b, Some(v)),
        None => (voice, None),
    };
    let variant_known = match variant {
        None => true,
        Some(v) => variant_names(&list("--voices=variant")?).any(|n| n == v),
    };
    Some(knows_base(&voices, base) && variant_known)
}

/// Whether the `--voices` listing `voices` holds `base` in a form `-v` takes.
fn knows_base(voices: &str, base: &str) -> bool {
    let same = |n: &str| n.eq_ignore_ascii_case(base);
    // A listed language with a region subtag: two letters or three digits (BCP 47).
    let with_region = |n: &str| {
        base.len() > n.len()
            && base[..n.len()].eq_ignore_ascii_case(n)
            && base[n.len()..].strip_prefix('-').is_some_and(|r| {
                (r.len() == 2 && r.bytes().all(|b| b.is_ascii_alphabetic()))
                    || (r.len() == 3 && r.bytes().all(|b| b.is_ascii_digit()))
            })
    };
    rows(voices).any(|row| {
        row.names.iter().any(|n| same(n)) || row.languages.iter().any(|n| same(n) || with_region(n))
    })
}

/// One row of a listing: its languages (its own and the others it speaks) and its other names
/// (its voice file, whole and its last part, and its voice name).
struct Row {
    languages: Vec<String>,
    names: Vec<String>,
}

/// The rows of a listing (columns Pty, Language, Age/Gender, VoiceName, File, Other Languages;
/// the header row left out).
fn rows(listing: &str) -> impl Iterator<Item = Row> + '_ {
    listing.lines().filter_map(|row| {
        let cols: Vec<&str> = row.split_whitespace().collect();
        if cols.len() < 5 || cols[0] == "Pty" {
            return None;
        }
        let mut languages = vec![cols[1].to_owned()];
        // Other languages: "(zh-cmn 5)(zh 5)", each a name and a priority.
        let others = cols[5..].join(" ");
        languages.extend(
            others
                .split('(')
                .filter_map(|o| o.split_whitespace().next())
                .map(str::to_owned),
        );
        let file = cols[4];
        let mut names = vec![file.to_owned(), cols[3].replace('_', " ")];
        if let Some((_, last)) = file.rsplit_once('/') {
            names.push(last.to_owned());
        }
        Some(Row { languages, names })
    })
}

/// The variant names of the `--voices=variant` listing: each file's name after `!v/`.
fn variant_names(listing: &str) -> impl Iterator<Item = &str> {
    listing
        .lines()
        .filter_map(|row| row.split_whitespace().nth(4)?.strip_prefix("!v/"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const VOICES: &str = "\
Pty Language       Age/Gender VoiceName          File                 Other Languages
 2  en-gb           --/M      English_(Great_Britain) gmw/en               (en 2)
 3  en-uk           --/M      english-mb-en1     mb/mb-en1            (en-gb 3)(en 2)
 2  en-us           --/M      English_(America)  gmw/en-US            (en 3)
 5  cmn             --/M      Chinese_(Mandarin) sit/cmn              (zh-cmn 5)(zh 5)
 5  es-419          --/M      Spanish_(Latin_America) roa/es-419
";

    const VARIANTS: &str = "\
Pty Language       Age/Gender VoiceName          File                 Other Languages
 5  variant         --/M      Alex               !v/Alex
 5  variant         --/F      f3                 !v/f3                (en-us 3)
";

    #[test]
    fn the_forms_espeak_ng_takes_pass_and_typos_do_not() {
        for ok in [
            "en-us",
            "EN-US",
            "gmw/en-US",
            "en-US",
            "mb-en1",
            "en",
            "zh",
            "zh-cmn",
            "English (America)",
            "english (america)",
            "de-de",
            "en-AU",
            "en-gb-US",
            "es-419",
        ] {
            // "de-de": no `de` in this listing.
            let want = ok != "de-de";
            assert_eq!(knows_base(VOICES, ok), want, "{ok}");
        }
        for bad in [
            "en-uss",
            "English_(America)",
            "en-u",
            "en-1234",
            "xx",
            "Language",
        ] {
            assert!(!knows_base(VOICES, bad), "{bad}");
        }
    }

    #[test]
    fn variants_are_their_file_names_exactly() {
        let names: Vec<&str> = variant_names(VARIANTS).collect();
        assert_eq!(names, ["Alex", "f3"]);
    }
}
