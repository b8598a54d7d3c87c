//! `pneuma eval podcast --write DIR`: the episodes as files, to listen to and render by hand.
//! Per episode `episode_NN.wav` (the mix) and `episode_NN.clean.wav` (the speech alone), 16 kHz
//! mono float, and `episode_NN.labels.csv`, one row per 10 ms label frame: `time_s` (the
//! frame's start), `truth` (speech truth, 0/1), `near_voicing` (within 80 ms of the reference
//! voicing), `class` (what the frame holds, empty where unlabelled), `alone` (1 where music or
//! noise stands alone, outside any speech segment: the frames the body figures count, 0 under
//! a segment or unlabelled), `real_breath` (on a clear labelled breath). No audio of the shared
//! data ever goes into the repository: write outside it.

use std::fmt::Write as _;
use std::path::Path;

use super::real_breaths::RealBreaths;
use super::recipe::Episode;
use super::sources::{FRAMES_PER_S, RATE_HZ};
use crate::data::write_mono_wav;

/// Writes every episode of `episodes` into `dir` (created if missing).
pub fn write_episodes(dir: &Path, episodes: &[Episode], real: &RealBreaths) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for e in episodes {
        let stem = format!("episode_{:02}", e.index);
        write_mono_wav(&dir.join(format!("{stem}.wav")), &e.audio, RATE_HZ as u32)?;
        write_mono_wav(
            &dir.join(format!("{stem}.clean.wav")),
            &e.clean,
            RATE_HZ as u32,
        )?;
        let path = dir.join(format!("{stem}.labels.csv"));
        std::fs::write(&path, labels_csv(e, &real.breath_frames(e)))
            .map_err(|err| format!("{}: {err}", path.display()))?;
    }
    println!("episodes written to {}", dir.display());
    Ok(())
}

/// The label rows of `episode` (see the module docs); `real_breath`: per frame.
fn labels_csv(episode: &Episode, real_breath: &[bool]) -> String {
    let l = &episode.labels;
    let mut out = String::from("time_s,truth,near_voicing,class,alone,real_breath\n");
    for (k, &breath) in real_breath.iter().enumerate().take(episode.frames()) {
        let class = l.class[k].map_or("", |c| c.name());
        let alone = l.stands_alone(k);
        let _ = writeln!(
            out,
            "{:.2},{},{},{class},{},{}",
            k as f64 / FRAMES_PER_S,
            u8::from(l.truth[k]),
            u8::from(l.near_voicing[k]),
            u8::from(alone),
            u8::from(breath),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::podcast::recipe::{Class, Labels, Role};

    #[test]
    fn each_label_frame_is_one_row_with_its_time_and_flags() {
        let labels = Labels {
            truth: vec![false, true, true],
            near_voicing: vec![false, true, false],
            class: vec![Some(Class::MusicOnly), Some(Class::Speech), None],
            role: vec![Some(Role::Intro), None, Some(Role::Bed)],
            ..Labels::default()
        };
        let episode = Episode {
            index: 3,
            main_piece: 0,
            stings: [1, 2],
            audio: vec![0.0; 480],
            clean: vec![0.0; 480],
            labels,
            segments: Vec::new(),
        };
        let csv = labels_csv(&episode, &[false, false, true]);
        let rows: Vec<&str> = csv.lines().collect();
        assert_eq!(rows.len(), 4, "{csv}");
        assert_eq!(rows[1], "0.00,0,0,music only,1,0");
        assert_eq!(rows[2], "0.01,1,1,speech,0,0");
        assert_eq!(rows[3], "0.02,1,0,,0,1");
    }
}
