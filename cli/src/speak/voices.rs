//! Whether espeak-ng knows a voice before any text is spoken: `espeak-ng -v en-uss` (a typo
//! of `en-us`) and `-v en+nonsense` exit 0 and speak in another voice without a word, so
//! `speak` would write a whole take in a voice nobody asked for. The voice is looked up in
//! espeak-ng's own listings (`--voices`, `--voices=mb`, `--voices=variant`): its language
//! codes, its voice files and the other languages each voice speaks, as `-v` takes them, with
//! a `+variant` after the voice.

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
    let voices = list("--voices")?;
    let mbrola = list("--voices=mb").unwrap_or_default();
    let (base, variant) = match voice.split_once('+') {
        Some((b, v)) => (b, Some(v)),
        None => (voice, None),
    };
    let base_known = names(&voices).chain(names(&mbrola)).any(|n| same(&n, base));
    let variant_known = match variant {
        None => true,
        Some(v) => names(&list("--voices=variant")?).any(|n| same(&n, v)),
    };
    Some(base_known && variant_known)
}

/// Case-insensitive, as espeak-ng matches them.
fn same(a: &str, b: &str) -> bool {
    a.eq_ignore_ascii_case(b)
}

/// The names `-v` takes from a listing: each row's language, its file (whole and its last
/// part: `gmw/en-US`, `en-US`; a variant's `!v/f3` as `f3`) and its other languages
/// (`(en-gb 3)`). The header row and the priority and age/gender columns are left out.
fn names(listing: &str) -> impl Iterator<Item = String> + '_ {
    listing.lines().skip(1).flat_map(|row| {
        let cols: Vec<&str> = row.split_whitespace().collect();
        let mut out = Vec::new();
        if cols.len() >= 5 {
            out.push(cols[1].to_owned());
            let file = cols[4];
            out.push(file.to_owned());
            if let Some((_, last)) = file.rsplit_once('/') {
                out.push(last.to_owned());
            }
            // Other languages: "(zh-cmn 5)(zh 5)", each a name and a priority.
            let others = cols[5..].join(" ");
            out.extend(
                others
                    .split('(')
                    .filter_map(|o| o.split_whitespace().next())
                    .map(str::to_owned),
            );
        }
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const VOICES: &str = "\
Pty Language       Age/Gender VoiceName          File                 Other Languages
 2  en-gb           --/M      English_(Great_Britain) gmw/en               (en 2)
 3  en-uk           --/M      english-mb-en1     mb/mb-en1            (en-gb 3)(en 2)
 2  en-us           --/M      English_(America)  gmw/en-US            (en 3)
";

    #[test]
    fn a_listing_gives_languages_files_and_other_languages() {
        let all: Vec<String> = names(VOICES).collect();
        for want in [
            "en-gb",
            "gmw/en",
            "en",
            "en-us",
            "gmw/en-US",
            "en-US",
            "mb-en1",
        ] {
            assert!(all.iter().any(|n| n == want), "{want} in {all:?}");
        }
        assert!(!all
            .iter()
            .any(|n| n == "Language" || n == "English_(America)"));
        assert!(!all.iter().any(|n| same(n, "en-uss")));
        // Two other languages run together: both are names.
        let zh = " 5  cmn             --/M      Chinese_(Mandarin) sit/cmn    (zh-cmn 5)(zh 5)";
        let all: Vec<String> = names(&format!("header\n{zh}\n")).collect();
        assert_eq!(all, ["cmn", "sit/cmn", "cmn", "zh-cmn", "zh"]);
    }
}
