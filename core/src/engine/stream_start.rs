//! Whether a stream starts inside sound: an edit that cut into a word leaves its end (a /s/, a
//! vowel's tail) at the very start of the file, before the first phrase. The phrase tracker
//! learns its floor from the first frames, so it hears no activity there, and the stretch passed
//! for a leading silence that got a breath on the word. What a cut word has and a room, a bed
//! or a steady noise at the start does not: its level falls after it, and it lies near the
//! speech.
//!
//! [`StreamStart`] keeps the median level of the stream's first [`STREAM_EDGE_S`] (at least
//! [`MIN_EDGE_FRAMES`]) and the quietest frame after it until the first phrase starts; the
//! stream starts inside sound when that edge lies at least [`FALL_DB`] over the quietest frame
//! and within [`IN_SOUND_DB`] of the speech's level as measured when the pause is decided (the
//! last complete phrase's, else the voiced frames of the one being spoken, else the loudest
//! voiced frame of the first phrase seen ahead). Allocation-free.

/// The start of the stream that tells whether it starts inside sound, seconds.
pub(crate) const STREAM_EDGE_S: f64 = 0.05;
/// Most frames of the edge kept (240 frames per second at most: 12).
const EDGE_FRAMES: usize = 16;
/// Fewest frames of the edge: at 30 frames per second [`STREAM_EDGE_S`] holds two, the first
/// half padding, and one click would decide.
const MIN_EDGE_FRAMES: usize = 3;
/// How far the level falls after the edge when the edge is a sound's end, dB: a room, a bed or
/// a steady noise varies by a few dB, a word's end falls into its closure or the pause.
pub(crate) const FALL_DB: f32 = 10.0;
/// How close to the first phrase's level the edge lies when it is speech, dB: a word's quietest
/// consonants lie 10–20 dB under the vowels; a room's tone 30 dB or more under the speech in
/// every recording in `../shared/data`.
pub(crate) const IN_SOUND_DB: f32 = 20.0;
/// The level a frame of digital silence counts with, dBFS.
const SILENCE_FLOOR_DB: f32 = crate::analysis::LEVEL_FLOOR_DB;

/// See the module docs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StreamStart {
    edge_db: [f32; EDGE_FRAMES],
    edge_frames: usize,
    /// The quietest frame after the edge so far, dBFS.
    quietest_db: f32,
    /// The first phrase has started: nothing more is kept.
    closed: bool,
}

impl Default for StreamStart {
    fn default() -> Self {
        Self {
            edge_db: [0.0; EDGE_FRAMES],
            edge_frames: 0,
            quietest_db: f32::INFINITY,
            closed: false,
        }
    }
}

impl StreamStart {
    /// Hears the analysis frame at `time_s` of level `rms_db`.
    pub(crate) fn frame(&mut self, time_s: f64, rms_db: f32) {
        if self.closed {
            return;
        }
        let db = if rms_db.is_nan() {
            SILENCE_FLOOR_DB
        } else {
            rms_db.max(SILENCE_FLOOR_DB)
        };
        if time_s < STREAM_EDGE_S || self.edge_frames < MIN_EDGE_FRAMES {
            if self.edge_frames < EDGE_FRAMES {
                self.edge_db[self.edge_frames] = db;
                self.edge_frames += 1;
            }
        } else {
            self.quietest_db = self.quietest_db.min(db);
        }
    }

    /// The first phrase started: the start is known.
    pub(crate) fn close(&mut self) {
        self.closed = true;
    }

    /// No phrase has started yet: the stream is in the silence (or the sound) before its first.
    pub(crate) fn before_first_phrase(&self) -> bool {
        !self.closed
    }

    /// Whether the stream started inside sound, against the first phrase's level `phrase_db`.
    pub(crate) fn in_sound(&self, phrase_db: f32) -> bool {
        if self.edge_frames == 0 {
            return false;
        }
        let mut edge = self.edge_db;
        let edge = &mut edge[..self.edge_frames];
        let (_, &mut median_db, _) = edge.select_nth_unstable_by(edge.len() / 2, f32::total_cmp);
        median_db >= self.quietest_db + FALL_DB && median_db > phrase_db - IN_SOUND_DB
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start(levels: &[(f64, f32)]) -> StreamStart {
        let mut s = StreamStart::default();
        for &(t, db) in levels {
            s.frame(t, db);
        }
        s.close();
        s
    }

    #[test]
    fn a_cut_word_is_sound_a_steady_room_or_a_click_is_not() {
        for rate_hz in [30.0, 120.0, 240.0] {
            let frames = |edge: f32, after: f32| -> Vec<(f64, f32)> {
                (0..30)
                    .map(|i| {
                        let t = i as f64 / rate_hz;
                        (t, if t < STREAM_EDGE_S { edge } else { after })
                    })
                    .collect()
            };
            // A /s/ at -30 dBFS falling into a closure at -46: sound, beside speech at -23.
            assert!(start(&frames(-30.0, -46.0)).in_sound(-23.0), "{rate_hz}");
            // Room noise 15 dB under the speech throughout: no fall.
            assert!(!start(&frames(-38.0, -39.0)).in_sound(-23.0), "{rate_hz}");
            // A quiet room: far under the speech.
            assert!(!start(&frames(-60.0, -75.0)).in_sound(-23.0), "{rate_hz}");
            // A loud take's speech: the same /s/ lies 30 dB under it.
            assert!(!start(&frames(-30.0, -46.0)).in_sound(0.0), "{rate_hz}");
            // One click in a quiet room's first frame: the median is the room.
            let mut click = frames(-70.0, -72.0);
            click[0].1 = -10.0;
            assert!(!start(&click).in_sound(-23.0), "{rate_hz}");
        }
        // Frames after the first phrase started are not heard.
        let mut s = StreamStart::default();
        s.frame(0.0, -30.0);
        s.close();
        s.frame(0.1, -90.0);
        assert!(!s.in_sound(-23.0));
    }
}
