//! Scoring a tracker against a reference: every track on a 1 ms grid, each reference frame
//! (10 ms) scored on the tracker's nearest frame at a global offset; the frame counts behind
//! FFE, VDE, GPE and the fine error, with where the errors lie (onsets, offsets, octaves).

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::data::reference::Condition;

/// The scoring grid: every tracker's f0 at each millisecond is that of its frame nearest in time.
pub(crate) const GRID_S: f64 = 0.001;

/// One tracker's output on the 1 ms scoring grid: f0 in Hz, 0 = unvoiced.
pub(crate) type Track = Vec<f32>;

/// Pneuma's per-frame internals kept for `--dump`: voicing confidence, RMS dBFS, level around
/// the speech level in dB.
pub(crate) type Internals = Vec<[f32; 3]>;

/// One evaluated clip: a file of a data set, clean or with generated noise.
pub(crate) struct Clip {
    /// File stem, with `+<noise><snr>` when the noise was added here.
    pub(crate) name: String,
    /// Index into the evaluated data sets.
    pub(crate) data_set: usize,
    pub(crate) speaker: String,
    pub(crate) condition: Condition,
    pub(crate) internals: Internals,
    pub(crate) reference: Vec<(f64, f32)>,
    pub(crate) tracks: Vec<Track>,
}

#[derive(Default, Clone)]
pub(crate) struct Counts {
    pub(crate) frames: u64,
    pub(crate) voicing_errors: u64,
    /// Voicing errors where the reference is unvoiced.
    pub(crate) false_voiced: u64,
    pub(crate) both_voiced: u64,
    pub(crate) gross: u64,
    pub(crate) cents: Vec<f32>,
    /// Missed voiced frames in the first / last [`EDGE_FRAMES`] reference frames of a voiced
    /// run, and elsewhere.
    pub(crate) miss_onset: u64,
    pub(crate) miss_offset: u64,
    pub(crate) miss_inner: u64,
    /// False voiced frames within [`EDGE_FRAMES`] before a voiced run, after one, and elsewhere.
    pub(crate) fa_before: u64,
    pub(crate) fa_after: u64,
    pub(crate) fa_inner: u64,
    /// Gross errors near an octave up (ratio 1.7–2.3), an octave down (0.43–0.59), and others.
    pub(crate) gross_up: u64,
    pub(crate) gross_down: u64,
    pub(crate) gross_other: u64,
    /// Frames voiced in both whose reference f0 is below [`LOW_F0_HZ`], and their gross errors.
    pub(crate) low_voiced: u64,
    pub(crate) low_gross: u64,
}

impl Counts {
    pub(crate) fn vde(&self) -> f64 {
        self.voicing_errors as f64 / self.frames.max(1) as f64
    }
    pub(crate) fn gpe(&self) -> f64 {
        self.gross as f64 / self.both_voiced.max(1) as f64
    }
    pub(crate) fn ffe(&self) -> f64 {
        (self.voicing_errors + self.gross) as f64 / self.frames.max(1) as f64
    }
    pub(crate) fn fine_cents(&self) -> f64 {
        let mut c = self.cents.clone();
        if c.is_empty() {
            return f64::NAN;
        }
        c.sort_by(f32::total_cmp);
        c[c.len() / 2] as f64
    }
    pub(crate) fn add(&mut self, o: &Counts) {
        self.frames += o.frames;
        self.voicing_errors += o.voicing_errors;
        self.false_voiced += o.false_voiced;
        self.both_voiced += o.both_voiced;
        self.gross += o.gross;
        self.cents.extend_from_slice(&o.cents);
        self.miss_onset += o.miss_onset;
        self.miss_offset += o.miss_offset;
        self.miss_inner += o.miss_inner;
        self.fa_before += o.fa_before;
        self.fa_after += o.fa_after;
        self.fa_inner += o.fa_inner;
        self.gross_up += o.gross_up;
        self.gross_down += o.gross_down;
        self.gross_other += o.gross_other;
        self.low_voiced += o.low_voiced;
        self.low_gross += o.low_gross;
    }

    /// One line of the error breakdown, in % of all frames (gross errors of low-f0 frames in %
    /// of those frames).
    pub(crate) fn breakdown(&self) -> String {
        let pct = |n: u64| n as f64 * 100.0 / self.frames.max(1) as f64;
        format!(
            "miss on/off/in {:5.2} {:5.2} {:5.2} | fa before/after/in {:5.2} {:5.2} {:5.2} | gross up/down/other {:5.2} {:5.2} {:5.2} | low-f0 gpe {:5.1}% of {}",
            pct(self.miss_onset),
            pct(self.miss_offset),
            pct(self.miss_inner),
            pct(self.fa_before),
            pct(self.fa_after),
            pct(self.fa_inner),
            pct(self.gross_up),
            pct(self.gross_down),
            pct(self.gross_other),
            self.low_gross as f64 * 100.0 / self.low_voiced.max(1) as f64,
            self.low_voiced
        )
    }
}

/// Reference frames (10 ms each) at the edge of a voiced run that count as onset / offset.
pub(crate) const EDGE_FRAMES: usize = 3;

/// Reference f0 under which a frame counts as low (creaky or deep male voice), Hz.
pub(crate) const LOW_F0_HZ: f32 = 100.0;

/// For every reference frame: frames since the current voicing run began and frames until it
/// ends (0 = first / last frame of the run); runs that touch the clip's ends count from far away,
/// so they are never "at an edge" there.
pub(crate) fn run_positions(reference: &[(f64, f32)]) -> Vec<(usize, usize)> {
    const FAR: usize = 1 << 20;
    let n = reference.len();
    let voiced: Vec<bool> = reference.iter().map(|r| r.1 > 0.0).collect();
    let mut from_start = vec![0usize; n];
    let mut to_end = vec![0usize; n];
    if n == 0 {
        return Vec::new();
    }
    from_start[0] = FAR;
    to_end[n - 1] = FAR;
    for i in 1..n {
        if voiced[i] == voiced[i - 1] {
            from_start[i] = from_start[i - 1] + 1;
        }
    }
    for i in (0..n - 1).rev() {
        if voiced[i] == voiced[i + 1] {
            to_end[i] = to_end[i + 1] + 1;
        }
    }
    from_start.into_iter().zip(to_end).collect()
}

pub(crate) fn score(reference: &[(f64, f32)], track: &Track, offset_ms: i32) -> Counts {
    let mut c = Counts::default();
    let positions = run_positions(reference);
    for (&(t, f_ref), &(from_start, to_end)) in reference.iter().zip(&positions) {
        // Keele marks uncertain frames −1: they are left out of every score.
        if f_ref < 0.0 {
            continue;
        }
        let k = ((t + offset_ms as f64 / 1000.0) / GRID_S).round() as i64;
        let f = if k >= 0 && (k as usize) < track.len() {
            track[k as usize]
        } else {
            0.0
        };
        c.frames += 1;
        let (rv, tv) = (f_ref > 0.0, f > 0.0);
        if rv != tv {
            c.voicing_errors += 1;
            c.false_voiced += u64::from(tv);
            // In an unvoiced run, "from_start" counts frames after the previous voiced run and
            // "to_end" frames before the next one (runs at the clip's ends count as inner).
            if rv {
                if from_start < EDGE_FRAMES {
                    c.miss_onset += 1;
                } else if to_end < EDGE_FRAMES {
                    c.miss_offset += 1;
                } else {
                    c.miss_inner += 1;
                }
            } else if to_end < EDGE_FRAMES {
                c.fa_before += 1;
            } else if from_start < EDGE_FRAMES {
                c.fa_after += 1;
            } else {
                c.fa_inner += 1;
            }
        } else if rv {
            c.both_voiced += 1;
            let low = f_ref < LOW_F0_HZ;
            c.low_voiced += u64::from(low);
            let cents = 1200.0 * (f / f_ref).log2();
            let ratio = f / f_ref;
            if (ratio - 1.0).abs() > 0.2 {
                c.gross += 1;
                c.low_gross += u64::from(low);
                if (1.7..=2.3).contains(&ratio) {
                    c.gross_up += 1;
                } else if (0.43..=0.59).contains(&ratio) {
                    c.gross_down += 1;
                } else {
                    c.gross_other += 1;
                }
            } else {
                c.cents.push(cents.abs());
            }
        }
    }
    c
}

/// Spreads frames at `times_s` (ascending) onto the 1 ms grid (`grid_len` points): each grid
/// time takes the frame nearest to it (compared in whole microseconds, so a time exactly
/// between two frames takes the earlier one), or the default (0, i.e. unvoiced) before the
/// first or after the last frame by more than half a frame step (`step_s`). (Between frames
/// the nearest always counts: Praat prints its times rounded to 10 µs, so a grid time halfway
/// between two of its frames may lie a few µs beyond half a step from both.)
pub(crate) fn on_grid<T: Copy + Default>(
    times_s: &[f64],
    frames: &[T],
    step_s: f64,
    grid_len: usize,
) -> Vec<T> {
    let us = |t: f64| (t * 1e6).round() as i64;
    let times: Vec<i64> = times_s.iter().map(|&t| us(t)).collect();
    let half_step = us(step_s) / 2;
    (0..grid_len)
        .map(|k| {
            let t = k as i64 * us(GRID_S);
            let after = times.partition_point(|&x| x < t);
            let nearest = match (after.checked_sub(1), times.get(after)) {
                (Some(i), Some(&later)) if t - times[i] <= later - t => Some(i),
                (_, Some(_)) => Some(after),
                (Some(i), None) => Some(i),
                (None, None) => None,
            };
            let inside =
                times.first().is_some_and(|&a| a <= t) && times.last().is_some_and(|&b| t <= b);
            nearest
                .filter(|&i| inside || (times[i] - t).abs() <= half_step)
                .map_or_else(T::default, |i| frames[i])
        })
        .collect()
}

/// Frame times `k / frame_rate_hz` for `n` frames.
pub(crate) fn frame_times(n: usize, frame_rate_hz: f64) -> Vec<f64> {
    (0..n).map(|k| k as f64 / frame_rate_hz).collect()
}

/// Grid points covering a clip of `duration_s`.
pub(crate) fn grid_len(duration_s: f64) -> usize {
    (duration_s / GRID_S).ceil() as usize
}

/// Summed counts of `clips` for every tracker.
pub(crate) fn total<'a>(
    clips: impl IntoIterator<Item = &'a Clip>,
    trackers: usize,
    offset: i32,
) -> Vec<Counts> {
    let mut row = vec![Counts::default(); trackers];
    for clip in clips {
        for (i, tr) in clip.tracks.iter().enumerate() {
            row[i].add(&score(&clip.reference, tr, offset));
        }
    }
    row
}

/// One data set's figures, kept for the checks.
pub(crate) struct SetResult {
    pub(crate) dir: PathBuf,
    pub(crate) offset: i32,
    pub(crate) by_condition: BTreeMap<Condition, Vec<Counts>>,
    /// Per speaker at the cleanest SNR (clean, else the highest).
    pub(crate) by_speaker: BTreeMap<String, Vec<Counts>>,
    pub(crate) all: Vec<Counts>,
}
