//! Pitch references: folders of `<clip>.wav` + `<clip>.f0.csv` (laryngograph f0 every 10 ms),
//! PTDB-TUG excerpts (noise and SNR in the clip name, `male1white10`) or clean clips such as
//! Keele's (`f1nw0000`, uncertain frames marked −1), with seeded noise added to clean clips.
//! Read by `cargo xtask eval-pitch`, `eval-pauses` and `train-voicing`.

use std::path::{Path, PathBuf};

use pneuma_io::CappedReadError;

use super::DataError;
use crate::noise;

/// The noises PTDB-TUG's excerpts are recorded in, as their clip names spell them.
pub const PTDB_NOISES: [&str; 4] = ["cafeteria", "car", "traffic", "white"];

/// A noise condition: the noise type and its SNR, or clean (`snr_db` = None).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Condition {
    /// `clean`, a PTDB noise ([`PTDB_NOISES`]) or an added one
    /// ([`crate::noise::ADDED_NOISES`]).
    pub noise: String,
    /// The SNR, dB (`None`: clean).
    pub snr_db: Option<u32>,
}

impl Condition {
    /// No noise.
    pub fn clean() -> Self {
        Self {
            noise: "clean".into(),
            snr_db: None,
        }
    }
    /// As the tables print it: `white 10 dB`, `clean`.
    pub fn label(&self) -> String {
        match self.snr_db {
            Some(snr) => format!("{} {snr} dB", self.noise),
            None => self.noise.clone(),
        }
    }
}

/// The clips of a PTDB-style folder: every `<clip>` with both `<clip>.wav` and `<clip>.f0.csv`,
/// sorted; an error when the folder is missing or there is none.
pub fn list_clips(data: &Path) -> Result<Vec<String>, DataError> {
    let mut names: Vec<String> = std::fs::read_dir(data)
        .map_err(|source| DataError::Folder {
            path: data.into(),
            source,
            holds: "<clip>.wav + <clip>.f0.csv: ../shared/data/ptdb or ../shared/data/keele in a checkout beside shared/",
        })?
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter_map(|n| n.strip_suffix(".wav").map(str::to_string))
        .filter(|n| data.join(format!("{n}.f0.csv")).exists())
        .collect();
    names.sort();
    if names.is_empty() {
        return Err(DataError::Empty {
            path: data.into(),
            what: "<clip>.wav with its <clip>.f0.csv",
        });
    }
    Ok(names)
}

/// What a reference `<clip>.f0.csv` is, for the errors.
pub const REFERENCE_FILE: &str = "a pitch reference (time_s,f0_hz)";

/// Reads a reference `<clip>.f0.csv`: a header, then `time_s,f0_hz` rows (0 unvoiced, −1
/// uncertain).
pub fn read_reference(path: &Path) -> Result<Vec<(f64, f32)>, DataError> {
    let bad = |reason: String| DataError::Reference {
        path: path.into(),
        reason,
    };
    let text = super::read_text(path, REFERENCE_FILE).map_err(|e| match e {
        CappedReadError::Io { source, .. } => bad(source.to_string()),
        other => DataError::TextFile(other),
    })?;
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let (t, f) = l
                .split_once(',')
                .ok_or_else(|| bad(format!("bad row {l:?}")))?;
            Ok((
                t.trim()
                    .parse()
                    .map_err(|_| bad(format!("bad time {t:?}")))?,
                f.trim().parse().map_err(|_| bad(format!("bad f0 {f:?}")))?,
            ))
        })
        .collect()
}

/// The noise and SNR in a PTDB-style clip name (`male1white10` → `white`, 10).
pub fn split_name(stem: &str) -> Option<(String, u32)> {
    let digits = stem.trim_end_matches(|c: char| !c.is_ascii_digit());
    let snr_start = digits.rfind(|c: char| !c.is_ascii_digit())? + 1;
    let snr: u32 = stem[snr_start..].parse().ok()?;
    let head = &stem[..snr_start];
    for noise in PTDB_NOISES {
        if head.ends_with(noise) {
            return Some((noise.to_string(), snr));
        }
    }
    None
}

/// One clip's audio as read or generated, before any tracker ran.
pub struct Source {
    /// File stem, with `+<noise><snr>` when the noise was added here.
    pub name: String,
    /// The speaker (the clip name without its noise and SNR).
    pub speaker: String,
    /// The noise condition.
    pub condition: Condition,
    /// The audio, mono.
    pub audio: Vec<f32>,
    /// Its sample rate, Hz.
    pub rate: u32,
    /// The reference frames: (time s, f0 Hz).
    pub reference: Vec<(f64, f32)>,
    /// The file on disk (Praat reads files); None for generated audio until written.
    pub wav: Option<PathBuf>,
}

/// A data set's clips: every readable file, plus (for clean sets, unless `clean_only`) each
/// clip with every added noise at every SNR. Unreadable files are listed in `skipped`.
pub fn load_data_set(
    dir: &Path,
    clean_only: bool,
    skipped: &mut Vec<String>,
) -> Result<Vec<Source>, DataError> {
    let mut sources = Vec::new();
    for name in list_clips(dir)? {
        let wav = dir.join(format!("{name}.wav"));
        let (audio, rate) = match pneuma_io::wav::read_mono(&wav) {
            Ok(v) => v,
            Err(e) => {
                skipped.push(format!("{}: {e}", wav.display()));
                continue;
            }
        };
        let (speaker, condition) = match split_name(&name) {
            Some((noise, snr)) => {
                let head = name.trim_end_matches(|c: char| c.is_ascii_digit());
                let speaker = head
                    .strip_suffix(noise.as_str())
                    .unwrap_or(head)
                    .to_string();
                (
                    speaker,
                    Condition {
                        noise,
                        snr_db: Some(snr),
                    },
                )
            }
            None => (name.clone(), Condition::clean()),
        };
        let reference = read_reference(&dir.join(format!("{name}.f0.csv")))?;
        sources.push(Source {
            name,
            speaker,
            condition,
            audio,
            rate,
            reference,
            wav: Some(wav),
        });
    }
    if clean_only {
        return Ok(sources);
    }
    let clean: Vec<usize> = (0..sources.len())
        .filter(|&i| sources[i].condition.snr_db.is_none())
        .collect();
    let mut noisy = Vec::new();
    for (n, &i) in clean.iter().enumerate() {
        let others: Vec<&[f32]> = clean
            .iter()
            .filter(|&&j| j != i && sources[j].rate == sources[i].rate)
            .map(|&j| sources[j].audio.as_slice())
            .collect();
        let s = &sources[i];
        for (k, kind) in noise::ADDED_NOISES.iter().enumerate() {
            let added = noise::make_noise(kind, s.audio.len(), &others, 1 + (n * 16 + k) as u64);
            for snr in noise::ADDED_SNRS_DB {
                noisy.push(Source {
                    name: format!("{}+{kind}{snr}", s.name),
                    speaker: s.speaker.clone(),
                    condition: Condition {
                        noise: kind.to_string(),
                        snr_db: Some(snr),
                    },
                    audio: noise::mix_at_snr(&s.audio, &added, snr),
                    rate: s.rate,
                    reference: s.reference.clone(),
                    wav: None,
                });
            }
        }
    }
    sources.extend(noisy);
    Ok(sources)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ptdb_names_carry_noise_and_snr_and_keele_names_none() {
        assert_eq!(split_name("male1white10"), Some(("white".into(), 10)));
        assert_eq!(
            split_name("female2cafeteria0"),
            Some(("cafeteria".into(), 0))
        );
        assert_eq!(split_name("f1nw0000"), None);
    }

    #[test]
    fn a_missing_data_folder_says_what_it_should_hold_and_where_it_lives() {
        let missing = Path::new("no/such/shared/data/ptdb");
        let e = list_clips(missing).unwrap_err().to_string();
        assert!(e.contains("no/such/shared/data/ptdb"), "{e}");
        assert!(
            e.contains("<clip>.f0.csv") && e.contains("beside shared/"),
            "{e}"
        );
        let mut skipped = Vec::new();
        let loaded = load_data_set(missing, true, &mut skipped);
        assert!(matches!(loaded, Err(DataError::Folder { .. })));
    }
}
