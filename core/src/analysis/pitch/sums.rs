//! Window statistics in f64 lanes: the mean and energy of a window ([`WindowStats`]), its plain
//! sum of squares, and the long and three short windows of one frame at once ([`FrameStats`]),
//! each bit-identical to its window's sums taken alone.

/// The mean of one window and its energy about the mean.
#[derive(Debug, Clone, Copy)]
pub(super) struct WindowStats {
    /// Mean of the samples (summed in f64 in [`Lanes`], then rounded to f32).
    pub(super) mean: f32,
    /// Σ (x − mean)², each difference rounded to f32 first, summed in f64 in [`Lanes`].
    pub(super) energy: f64,
}

impl WindowStats {
    pub(super) fn of(window: &[f32]) -> Self {
        let mut sum = Lanes::default();
        sum.add(window, |x| x as f64);
        let mean = (sum.total() / window.len().max(1) as f64) as f32;
        Self {
            mean,
            energy: energy_about(window, mean),
        }
    }
}

/// Σ (x − mean)² over `window`, each difference rounded to f32, summed in [`Lanes`].
#[inline]
pub(super) fn energy_about(window: &[f32], mean: f32) -> f64 {
    let mut e = Lanes::default();
    e.add(window, |x| {
        let t = (x - mean) as f64;
        t * t
    });
    e.total()
}

/// Σ x² of `window` in [`Lanes`].
pub(super) fn square_sum(window: &[f32]) -> f64 {
    let mut s = Lanes::default();
    s.add(window, |x| (x as f64) * (x as f64));
    s.total()
}

/// Lanes of [`Lanes`].
pub(super) const LANES: usize = 8;

/// A sum in f64 over a run of samples kept as [`LANES`] partial sums (sample `i` of the run
/// into lane `i % LANES`, each lane in sample order) and added up at the end in a fixed tree:
/// independent chains that vectorise and overlap, where one serial sum waits on every
/// addition. The same run always gives the same bits.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Lanes([f64; LANES]);

impl Lanes {
    /// Adds `f(x)` for every sample of `xs` (the whole run, or its continuation when the run
    /// so far was a whole number of [`LANES`] long).
    #[inline(always)]
    pub(super) fn add<T: Copy>(&mut self, xs: &[T], f: impl Fn(T) -> f64) {
        let mut l = self.0;
        let chunks = xs.chunks_exact(LANES);
        let tail = chunks.remainder();
        for c in chunks {
            for k in 0..LANES {
                l[k] += f(c[k]);
            }
        }
        for (k, &x) in tail.iter().enumerate() {
            l[k] += f(x);
        }
        self.0 = l;
    }

    /// Adds `v` into lane `lane` (`< LANES`): the sample at index `i` of the run goes into
    /// lane `i % LANES`, in sample order, as [`Lanes::add`] does.
    #[inline(always)]
    pub(super) fn add_at(&mut self, lane: usize, v: f64) {
        self.0[lane] += v;
    }

    /// The sum: the lanes added pairwise.
    #[inline]
    pub(super) fn total(&self) -> f64 {
        let l = self.0;
        ((l[0] + l[1]) + (l[2] + l[3])) + ((l[4] + l[5]) + (l[6] + l[7]))
    }
}

/// [`Lanes`] of four runs of one length at once, sample by sample: sample `i` of each run goes
/// into its lane `i % LANES` ([`LanesX4::add_at`]), the four runs' values in one vector.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct LanesX4([[f64; 4]; LANES]);

impl LanesX4 {
    /// Adds `v[k]` into lane `lane` of run `k`.
    #[inline(always)]
    pub(super) fn add_at(&mut self, lane: usize, v: [f64; 4]) {
        for (l, v) in self.0[lane].iter_mut().zip(v) {
            *l += v;
        }
    }

    /// Run `k`'s sums so far, to go on with alone.
    pub(super) fn run(&self, k: usize) -> Lanes {
        Lanes(self.0.map(|l| l[k]))
    }
}

/// The statistics of the long window and of the three short windows inside it (oldest end,
/// centre, newest end), and the long window's plain sum of squares: each window's sums are
/// exactly its [`WindowStats::of`] sums (the same lanes in the same order, so the results are
/// bit-identical), but the oldest short window's sum is shared with the long window's.
#[derive(Debug, Clone, Copy)]
pub(super) struct FrameStats {
    pub(super) long: WindowStats,
    /// Oldest end, centre, newest end.
    pub(super) short: [WindowStats; 3],
    /// Σ x² of the long window, summed in [`Lanes`] (for [`super::FrameAnalysis::square_sum`]).
    pub(super) square_sum: f64,
}

/// Where the three short windows of `short_len` samples start in a long window of `w`: its
/// oldest end, its centre and its newest end.
pub(super) fn short_starts(w: usize, short_len: usize) -> [usize; 3] {
    [0, (w - short_len) / 2, w - short_len]
}

impl FrameStats {
    /// The short windows start at [`short_starts`]; requires `short_len <= window.len()`.
    pub(super) fn of(window: &[f32], short_len: usize) -> Self {
        let means = frame_means(window, short_len);
        let shorts = short_starts(window.len(), short_len).map(|a| &window[a..a + short_len]);
        Self {
            long: WindowStats {
                mean: means[0],
                energy: energy_about(window, means[0]),
            },
            short: [0, 1, 2].map(|k| WindowStats {
                mean: means[k + 1],
                energy: energy_about(shorts[k], means[k + 1]),
            }),
            square_sum: square_sum(window),
        }
    }
}

/// The means of the long window and of its three short windows (long, oldest end, centre,
/// newest end), each exactly its [`WindowStats::of`] mean, the oldest short window's sum shared
/// with the long window's.
pub(super) fn frame_means(window: &[f32], short_len: usize) -> [f32; 4] {
    let (w, len) = (window.len(), short_len);
    let shorts = short_starts(w, len).map(|a| &window[a..a + len]);
    let plain = |x: f32| x as f64;
    let mut sums = [Lanes::default(); 3];
    for (s, part) in sums.iter_mut().zip(shorts) {
        s.add(part, plain);
    }
    let mut long = Lanes::default();
    if len.is_multiple_of(LANES) {
        // The long window's run so far is the oldest short window's.
        long = sums[0];
        long.add(&window[len..], plain);
    } else {
        long.add(window, plain);
    }
    let mean = |s: &Lanes, n: usize| (s.total() / n.max(1) as f64) as f32;
    [
        mean(&long, w),
        mean(&sums[0], len),
        mean(&sums[1], len),
        mean(&sums[2], len),
    ]
}
