//! The seeded podcast recipe (issue 30): episodes built at 16 kHz from real speech and real
//! music ([`sources`](super::sources)), with per-frame labels (10 ms). Only this recipe and its
//! seed are committed; the audio is made on the fly.
//!
//! Every episode, its parts placed on 10 ms frame boundaries (U = a uniform draw):
//! ```text
//! 0.5 s silence
//! INTRO   10 s of the episode's main piece at the voice's level (fades 0.5 s in, 1 s out)
//! gap U(0.8, 1.5) s
//! SEG 1   a speech clip in its condition
//! gap U(0.5, 1.0) s, STING (4 s of another piece, robin's 2.7 s; fades 0.1 s), gap U(0.5, 1.0) s
//! SEG 2
//! gap U(0.5, 1.0) s, STING (a second other piece), gap U(0.8, 1.5) s
//! SUNG    6.5 s of a clear sung section of the sung piece at the voice's level (fades 0.3 s)
//! gap U(0.8, 1.5) s
//! NOISE   5 s of the episode's noise type alone, U(10, 20) dB under the voice (fades 0.3 s)
//! gap U(0.8, 1.5) s
//! SEG 3
//! long silence U(5, 12) s
//! SEG 4
//! gap U(0.8, 1.5) s
//! OUTRO   10 s of the main piece at the voice's level (fades 1 s in, 2 s out)
//! 0.5 s silence
//! ```
//! - The main piece is `MUSIC[episode mod 6]`; the stings take two of the other five, shuffled.
//!   The sung piece's intros and outros take its instrumental sections.
//! - Conditions rotate `clean, bed, noise, bed` from index `episode mod 4`. A **bed** is the
//!   main piece (looped if shorter) U(15, 30) dB under the voice, from 1.5 s before the speech
//!   to 1.5 s after it, fades 0.5 s. **Noise** cycles by episode over pink, babble (six clips of
//!   other speakers at the voice's level), a harmonic drone (f0 U(70, 220) Hz, harmonics 1–12
//!   with 1/k amplitudes below 7.5 kHz) and room tone (brown noise above 30 Hz, a little white,
//!   50 or 60 Hz hum with two harmonics) at U(10, 20) dB SNR, 3 s alone before the speech and
//!   2 s after, fades 0.3 s.
//! - Levels: every speech clip at [`VOICE_DB`] (its speech level); music so that its mean
//!   power over the excerpt's frames within 40 dB of its loudest is the voice's level (minus
//!   the bed's depth); noise by its mean power against the SNR. A white dither at
//!   [`DITHER_DB`] everywhere. A music part's role (what a breath in it is counted as) covers
//!   its frames from the first to the last that sound ([`SILENT_EDGE_DB`]): a sting whose
//!   excerpt ends in a rest ends where its sound does.
//! - Speech clips: four successive seeded permutations of the 19 clips, used in order.

use pneuma_core::rng::SeededRng;

use super::sources::{
    self, frame_levels_db, SpeechClip, CLEAR_SUNG_S, FRAMES_PER_S, HOP, INSTRUMENTAL_S, MUSIC,
    RATE_HZ, SUNG_PIECE, SUNG_SECTIONS_S,
};

/// The recipe's seed.
pub const SEED: u64 = 30;
/// Episodes in the evaluation.
pub const EPISODES: usize = 12;
/// Speech level of every clip, dBFS.
pub const VOICE_DB: f64 = -26.0;
/// The dither, dBFS RMS.
pub const DITHER_DB: f64 = -96.0;
/// A music part's first and last frames this far or more under the voice's level hold none of
/// its sound (a rest at the edge of an excerpt, or its fade's end): they are the silence beside
/// the part, not the part standing alone, dB (−86 dBFS, 10 dB over the dither).
pub const SILENT_EDGE_DB: f64 = 60.0;

/// What a frame holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// Speech alone.
    Speech,
    /// Speech over a music bed.
    SpeechUnderBed,
    /// Speech in noise.
    SpeechInNoise,
    /// Music without speech.
    MusicOnly,
    /// The sung voice of the sung piece, without speech.
    Singing,
    /// Noise without speech.
    NoiseOnly,
    /// Nothing but the dither.
    Silence,
}

impl Class {
    /// Every class, in order.
    pub const ALL: [Class; 7] = [
        Class::Speech,
        Class::SpeechUnderBed,
        Class::SpeechInNoise,
        Class::MusicOnly,
        Class::Singing,
        Class::NoiseOnly,
        Class::Silence,
    ];

    /// True for the speech classes.
    pub fn is_speech(self) -> bool {
        matches!(
            self,
            Class::Speech | Class::SpeechUnderBed | Class::SpeechInNoise
        )
    }

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Class::Speech => "speech",
            Class::SpeechUnderBed => "speech under a bed",
            Class::SpeechInNoise => "speech in noise",
            Class::MusicOnly => "music only",
            Class::Singing => "singing",
            Class::NoiseOnly => "noise only",
            Class::Silence => "silence",
        }
    }
}

/// What part of the episode a sound other than the speech belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The intro (music).
    Intro,
    /// A sting between segments (music).
    Sting,
    /// A music bed under a segment, with its lead-in and lead-out.
    Bed,
    /// The sung passage.
    Sung,
    /// The outro (music).
    Outro,
    /// The noise under a segment, with its lead-in and lead-out.
    NoiseBed,
    /// Noise alone between segments.
    NoiseAlone,
}

impl Role {
    /// True for music or noise standing alone, outside any speech segment: the spans no breath
    /// may touch.
    pub fn stands_alone(self) -> bool {
        !matches!(self, Role::Bed | Role::NoiseBed)
    }
}

/// A noise type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Noise {
    /// 1/f noise.
    Pink,
    /// Six other speakers.
    Babble,
    /// A steady harmonic drone.
    Drone,
    /// Room tone with mains hum.
    Room,
}

impl Noise {
    /// In the order episodes cycle through them.
    pub const ALL: [Noise; 4] = [Noise::Pink, Noise::Babble, Noise::Drone, Noise::Room];

    /// Its name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Noise::Pink => "pink",
            Noise::Babble => "babble",
            Noise::Drone => "drone",
            Noise::Room => "room",
        }
    }
}

/// A segment's condition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Condition {
    /// Speech alone.
    Clean,
    /// Over a bed this many dB under the voice.
    Bed(f64),
    /// In noise at this SNR, dB.
    Noise(Noise, f64),
}

impl Condition {
    /// Its description in reports: `clean`, `bed 24 dB down`, `pink 18 dB`.
    pub fn describe(self) -> String {
        match self {
            Condition::Clean => "clean".to_string(),
            Condition::Bed(db) => format!("bed {db:.0} dB down"),
            Condition::Noise(noise, snr) => format!("{} {snr:.0} dB", noise.name()),
        }
    }
}

/// One speech segment of an episode.
#[derive(Debug, Clone)]
pub struct Segment {
    /// The clip.
    pub clip: String,
    /// Its speaker's index in the episode set's speaker list.
    pub speaker: usize,
    /// The condition.
    pub condition: Condition,
    /// First and one-past-last label frame of the clip.
    pub frames: (usize, usize),
}

/// Per label frame (10 ms) of an episode.
#[derive(Debug, Clone, Default)]
pub struct Labels {
    /// Speech truth.
    pub truth: Vec<bool>,
    /// Within 80 ms of the reference voicing (a part of the truth; the rest is speech by its
    /// level alone).
    pub near_voicing: Vec<bool>,
    /// Frames that count in scores.
    pub mask: Vec<bool>,
    /// What the frame holds.
    pub class: Vec<Option<Class>>,
    /// The music piece sounding (index in [`MUSIC`]).
    pub piece: Vec<Option<usize>>,
    /// Its role, where its sound is (none on a music part's silent first and last frames,
    /// [`SILENT_EDGE_DB`]).
    pub role: Vec<Option<Role>>,
    /// The speaker's index, inside a clip.
    pub speaker: Vec<Option<usize>>,
    /// The segment's index, inside a clip.
    pub segment: Vec<Option<usize>>,
    /// The noise sounding.
    pub noise: Vec<Option<Noise>>,
}

impl Labels {
    /// Frame `k` holds music or noise standing alone, outside any speech segment
    /// ([`Role::stands_alone`]).
    pub fn stands_alone(&self, k: usize) -> bool {
        self.role[k].is_some_and(|r| r.stands_alone())
    }
}

/// One episode: the mix, the clean speech track and the labels.
#[derive(Debug, Clone)]
pub struct Episode {
    /// Its index.
    pub index: usize,
    /// The main piece (index in [`MUSIC`]).
    pub main_piece: usize,
    /// The two sting pieces.
    pub stings: [usize; 2],
    /// The mix, 16 kHz.
    pub audio: Vec<f32>,
    /// The speech alone, 16 kHz.
    pub clean: Vec<f32>,
    /// The labels.
    pub labels: Labels,
    /// The speech segments.
    pub segments: Vec<Segment>,
}

impl Episode {
    /// Its length in label frames.
    pub fn frames(&self) -> usize {
        self.labels.truth.len()
    }

    /// The music pieces it holds.
    pub fn pieces(&self) -> Vec<usize> {
        let mut p = vec![self.main_piece, self.stings[0], self.stings[1]];
        if let Some(s) = MUSIC.iter().position(|m| *m == SUNG_PIECE) {
            p.push(s);
        }
        p.sort_unstable();
        p.dedup();
        p
    }
}

/// Everything the recipe draws from.
pub struct Library {
    /// The speech clips, in [`sources::clips`] order.
    pub clips: Vec<SpeechClip>,
    /// The speakers, sorted.
    pub speakers: Vec<String>,
    /// The music pieces at 16 kHz, in [`MUSIC`] order.
    pub music: Vec<Vec<f32>>,
}

/// Frames of `s` seconds.
fn frames(s: f64) -> usize {
    (s * FRAMES_PER_S).round() as usize
}

/// A draw in [a, b).
fn uniform(rng: &mut SeededRng, a: f64, b: f64) -> f64 {
    a + (b - a) * rng.uniform()
}

/// An integer in [a, b).
fn integer(rng: &mut SeededRng, a: usize, b: usize) -> usize {
    a + ((rng.uniform() * (b - a) as f64) as usize).min(b - a - 1)
}

fn shuffle<T>(rng: &mut SeededRng, v: &mut [T]) {
    for i in (1..v.len()).rev() {
        let j = integer(rng, 0, i + 1);
        v.swap(i, j);
    }
}

fn db_gain(db: f64) -> f32 {
    10f64.powf(db / 20.0) as f32
}

/// Linear fades in and out.
fn fade(x: &mut [f32], in_s: f64, out_s: f64) {
    let (a, b) = ((in_s * RATE_HZ) as usize, (out_s * RATE_HZ) as usize);
    let n = x.len();
    for (i, v) in x.iter_mut().take(a.min(n)).enumerate() {
        *v *= i as f32 / (a - 1).max(1) as f32;
    }
    for i in 0..b.min(n) {
        x[n - 1 - i] *= i as f32 / (b - 1).max(1) as f32;
    }
}

/// A piece's level: the mean power of its frames within 40 dB of its loudest, dB.
fn music_level_db(x: &[f32]) -> f64 {
    let levels = frame_levels_db(x);
    let top = levels.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let power: Vec<f64> = levels
        .iter()
        .filter(|&&l| l >= top - 40.0)
        .map(|l| 10f64.powf(l / 10.0))
        .collect();
    10.0 * (power.iter().sum::<f64>() / power.len().max(1) as f64 + 1e-20).log10()
}

/// Mean power of a signal, dB.
fn power_db(x: &[f32]) -> f64 {
    let p = x.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>() / x.len().max(1) as f64;
    10.0 * (p + 1e-30).log10()
}

/// An excerpt of `seconds` from `m` (from a uniform start; looped when shorter), or from one of
/// `sections`: the audio and the source time of each of its label frames' centres.
fn excerpt(
    rng: &mut SeededRng,
    m: &[f32],
    seconds: f64,
    sections: Option<&[(f64, f64)]>,
) -> (Vec<f32>, Vec<f64>) {
    let n = frames(seconds) * HOP;
    let (a, b) = match sections {
        Some(s) => {
            let (a, b) = s[integer(rng, 0, s.len())];
            (
                (a * RATE_HZ) as usize,
                ((b * RATE_HZ) as usize).min(m.len()),
            )
        }
        None => (0, m.len()),
    };
    let len = b - a;
    let idx: Vec<usize> = if len >= n {
        let s = integer(rng, a, b - n + 1);
        (s..s + n).collect()
    } else {
        let s = integer(rng, 0, len);
        (0..n).map(|i| a + (s + i) % len).collect()
    };
    let times = idx
        .iter()
        .skip(HOP / 2)
        .step_by(HOP)
        .map(|&i| i as f64 / RATE_HZ)
        .collect();
    (idx.iter().map(|&i| m[i]).collect(), times)
}

/// Per label frame of an excerpt of the sung piece: whether the song holds a sung voice there.
fn sung_frames(times: &[f64]) -> Vec<bool> {
    times
        .iter()
        .map(|t| SUNG_SECTIONS_S.iter().any(|&(a, b)| (a..b).contains(t)))
        .collect()
}

/// 1/f noise (Paul Kellet's filter of white noise).
fn pink(rng: &mut SeededRng, n: usize) -> Vec<f32> {
    let mut filter = pneuma_core::rng::PinkFilter::default();
    (0..n).map(|_| filter.step(rng.normal()) as f32).collect()
}

/// A steady harmonic drone.
fn drone(rng: &mut SeededRng, n: usize) -> Vec<f32> {
    let f0 = uniform(rng, 70.0, 220.0);
    let tau = 2.0 * std::f64::consts::PI;
    let harmonics: Vec<(f64, f64)> = (1..=12)
        .filter(|&k| f64::from(k) * f0 < RATE_HZ / 2.0 - 500.0)
        .map(|k| (f64::from(k), uniform(rng, 0.0, tau)))
        .collect();
    (0..n)
        .map(|i| {
            let t = i as f64 / RATE_HZ;
            harmonics
                .iter()
                .map(|&(k, ph)| (tau * k * f0 * t + ph).sin() / k)
                .sum::<f64>() as f32
        })
        .collect()
}

/// Room tone: brown noise above 30 Hz, a little white, mains hum with two harmonics.
fn room(rng: &mut SeededRng, n: usize) -> Vec<f32> {
    let leak = (-2.0 * std::f64::consts::PI * 30.0 / RATE_HZ).exp();
    let mut s = 0.0f64;
    let mut x: Vec<f64> = (0..n)
        .map(|_| {
            s = leak * s + rng.normal();
            s
        })
        .collect();
    let rms = (x.iter().map(|v| v * v).sum::<f64>() / n.max(1) as f64)
        .sqrt()
        .max(1e-12);
    x.iter_mut().for_each(|v| *v /= rms);
    let hum_hz = if rng.uniform() < 0.5 { 50.0 } else { 60.0 };
    let tau = 2.0 * std::f64::consts::PI;
    let hum = |t: f64| {
        (1..=3)
            .map(|k| (tau * f64::from(k) * hum_hz * t).sin() / f64::from(k))
            .sum::<f64>()
    };
    // RMS of the hum: sqrt((1 + 1/4 + 1/9) / 2).
    let hum_rms = ((1.0 + 0.25 + 1.0 / 9.0) / 2.0f64).sqrt();
    x.iter()
        .enumerate()
        .map(|(i, &v)| {
            let t = i as f64 / RATE_HZ;
            (v + 0.05 * rng.normal() + 0.3 * hum(t) / hum_rms) as f32
        })
        .collect()
}

/// An episode under construction: parts placed at label frames.
struct Builder {
    audio: Vec<f32>,
    clean: Vec<f32>,
    labels: Labels,
    /// The next free frame.
    pos: usize,
}

impl Builder {
    fn grow(&mut self, frames: usize) {
        if self.labels.truth.len() < frames {
            let n = frames;
            self.audio.resize(n * HOP, 0.0);
            self.clean.resize(n * HOP, 0.0);
            let l = &mut self.labels;
            l.truth.resize(n, false);
            l.near_voicing.resize(n, false);
            l.mask.resize(n, true);
            l.class.resize(n, None);
            l.piece.resize(n, None);
            l.role.resize(n, None);
            l.speaker.resize(n, None);
            l.segment.resize(n, None);
            l.noise.resize(n, None);
        }
    }

    /// Adds `x` from frame `start`; returns its length in frames.
    fn add(&mut self, start: usize, x: &[f32]) -> usize {
        let n = x.len() / HOP;
        self.grow(start + n);
        for (y, v) in self.audio[start * HOP..(start + n) * HOP].iter_mut().zip(x) {
            *y += v;
        }
        n
    }

    fn gap(&mut self, rng: &mut SeededRng, a: f64, b: f64) {
        self.pos += frames(uniform(rng, a, b));
    }
}

/// The label frames of a music part `x` from its first to its last that sound (over
/// [`SILENT_EDGE_DB`] under the voice); empty when none does.
fn sounding_frames(x: &[f32]) -> std::ops::Range<usize> {
    let levels = frame_levels_db(x);
    let sounding = |l: &f64| *l > VOICE_DB - SILENT_EDGE_DB;
    match (
        levels.iter().position(sounding),
        levels.iter().rposition(sounding),
    ) {
        (Some(first), Some(last)) => first..last + 1,
        _ => 0..0,
    }
}

/// Builds episode `index`, drawing from `rng` and taking clips from `clip_cycle`.
fn build(
    lib: &Library,
    index: usize,
    rng: &mut SeededRng,
    clip_cycle: &mut std::collections::VecDeque<usize>,
) -> Episode {
    let sung_piece = MUSIC.iter().position(|m| *m == SUNG_PIECE).unwrap_or(0);
    let main = index % MUSIC.len();
    let mut others: Vec<usize> = (0..MUSIC.len()).filter(|&p| p != main).collect();
    shuffle(rng, &mut others);
    let stings = [others[0], others[1]];
    let noise = Noise::ALL[index % Noise::ALL.len()];
    let cycle = ["clean", "bed", "noise", "bed"];
    let mut b = Builder {
        audio: Vec::new(),
        clean: Vec::new(),
        labels: Labels::default(),
        pos: frames(0.5),
    };
    let mut segments = Vec::new();
    let music_part = |b: &mut Builder,
                      rng: &mut SeededRng,
                      piece: usize,
                      seconds: f64,
                      role: Role,
                      fades: (f64, f64),
                      sections: Option<&[(f64, f64)]>| {
        let (mut x, times) = excerpt(rng, &lib.music[piece], seconds, sections);
        let g = db_gain(VOICE_DB - music_level_db(&x));
        x.iter_mut().for_each(|v| *v *= g);
        fade(&mut x, fades.0, fades.1);
        let start = b.pos;
        let n = b.add(start, &x);
        let sung = (piece == sung_piece).then(|| sung_frames(&times));
        let sounding = sounding_frames(&x);
        for k in 0..n {
            b.labels.piece[start + k] = Some(piece);
            if sounding.contains(&k) {
                b.labels.role[start + k] = Some(role);
            }
            if sung.as_ref().is_some_and(|s| s[k]) {
                b.labels.class[start + k] = Some(Class::Singing);
            }
        }
        b.pos = start + n;
    };
    let instrumental = (main == sung_piece).then_some(&INSTRUMENTAL_S[..]);
    music_part(
        &mut b,
        rng,
        main,
        10.0,
        Role::Intro,
        (0.5, 1.0),
        instrumental,
    );
    b.gap(rng, 0.8, 1.5);
    let mut segment = |b: &mut Builder, rng: &mut SeededRng, k: usize| {
        let c = clip_cycle.pop_front().unwrap_or(0);
        let clip = &lib.clips[c];
        let speaker = lib
            .speakers
            .iter()
            .position(|s| *s == clip.speaker)
            .unwrap_or(0);
        let g = db_gain(VOICE_DB - clip.level_db);
        let x: Vec<f32> = clip.audio.iter().map(|v| v * g).collect();
        let n = x.len() / HOP;
        let (condition, lead, tail) = match cycle[(index + k) % cycle.len()] {
            "bed" => {
                let depth = uniform(rng, 15.0, 30.0);
                let lead = frames(1.5);
                let (mut bed, times) = excerpt(
                    rng,
                    &lib.music[main],
                    (n + 2 * lead) as f64 / FRAMES_PER_S,
                    None,
                );
                let g = db_gain(VOICE_DB - depth - music_level_db(&bed));
                bed.iter_mut().for_each(|v| *v *= g);
                fade(&mut bed, 0.5, 0.5);
                let start = b.pos;
                let m = b.add(start, &bed);
                let sung = (main == sung_piece).then(|| sung_frames(&times));
                for j in 0..m {
                    b.labels.piece[start + j] = Some(main);
                    b.labels.role[start + j] = Some(Role::Bed);
                    if sung.as_ref().is_some_and(|s| s[j]) {
                        b.labels.class[start + j] = Some(Class::Singing);
                    }
                }
                (Condition::Bed(depth), lead, lead)
            }
            "noise" => {
                let snr = uniform(rng, 10.0, 20.0);
                let (lead, tail) = (frames(3.0), frames(2.0));
                let len = (n + lead + tail) * HOP;
                let mut z = noise_of(lib, rng, noise, len, &clip.speaker);
                let g = db_gain(VOICE_DB - snr - power_db(&z));
                z.iter_mut().for_each(|v| *v *= g);
                fade(&mut z, 0.3, 0.3);
                let start = b.pos;
                let m = b.add(start, &z);
                for j in 0..m {
                    b.labels.noise[start + j] = Some(noise);
                    b.labels.role[start + j] = Some(Role::NoiseBed);
                }
                (Condition::Noise(noise, snr), lead, tail)
            }
            _ => (Condition::Clean, 0, 0),
        };
        let start = b.pos + lead;
        b.add(start, &x);
        for (y, v) in b.clean[start * HOP..(start + n) * HOP].iter_mut().zip(&x) {
            *y += v;
        }
        for j in 0..n {
            let f = start + j;
            b.labels.truth[f] = clip.truth[j];
            b.labels.near_voicing[f] = clip.near_voicing[j];
            b.labels.mask[f] = clip.mask[j];
            b.labels.speaker[f] = Some(speaker);
            b.labels.segment[f] = Some(k);
        }
        segments.push(Segment {
            clip: clip.name.clone(),
            speaker,
            condition,
            frames: (start, start + n),
        });
        b.pos = start + n + tail;
    };
    segment(&mut b, rng, 0);
    b.gap(rng, 0.5, 1.0);
    let sting_s = |p: usize| if MUSIC[p] == "robin" { 2.7 } else { 4.0 };
    music_part(
        &mut b,
        rng,
        stings[0],
        sting_s(stings[0]),
        Role::Sting,
        (0.1, 0.1),
        None,
    );
    b.gap(rng, 0.5, 1.0);
    segment(&mut b, rng, 1);
    b.gap(rng, 0.5, 1.0);
    music_part(
        &mut b,
        rng,
        stings[1],
        sting_s(stings[1]),
        Role::Sting,
        (0.1, 0.1),
        None,
    );
    b.gap(rng, 0.8, 1.5);
    music_part(
        &mut b,
        rng,
        sung_piece,
        6.5,
        Role::Sung,
        (0.3, 0.3),
        Some(&CLEAR_SUNG_S),
    );
    b.gap(rng, 0.8, 1.5);
    segment(&mut b, rng, 2);
    b.gap(rng, 5.0, 12.0);
    segment(&mut b, rng, 3);
    b.gap(rng, 0.8, 1.5);
    music_part(
        &mut b,
        rng,
        main,
        10.0,
        Role::Outro,
        (1.0, 2.0),
        instrumental,
    );
    b.pos += frames(0.5);
    b.grow(b.pos);
    let dither = db_gain(DITHER_DB);
    for y in b.audio.iter_mut() {
        *y += dither * rng.normal() as f32;
    }
    let l = &mut b.labels;
    for f in 0..l.truth.len() {
        let sung = l.class[f] == Some(Class::Singing);
        l.class[f] = Some(if l.truth[f] {
            if l.piece[f].is_some() {
                Class::SpeechUnderBed
            } else if l.noise[f].is_some() {
                Class::SpeechInNoise
            } else {
                Class::Speech
            }
        } else if l.piece[f].is_some() {
            if sung {
                Class::Singing
            } else {
                Class::MusicOnly
            }
        } else if l.noise[f].is_some() {
            Class::NoiseOnly
        } else {
            Class::Silence
        });
    }
    Episode {
        index,
        main_piece: main,
        stings,
        audio: b.audio,
        clean: b.clean,
        labels: b.labels,
        segments,
    }
}

/// `n` samples of noise `kind` (babble without speaker `exclude`).
fn noise_of(lib: &Library, rng: &mut SeededRng, kind: Noise, n: usize, exclude: &str) -> Vec<f32> {
    match kind {
        Noise::Pink => pink(rng, n),
        Noise::Drone => drone(rng, n),
        Noise::Room => room(rng, n),
        Noise::Babble => babble(lib, rng, n, exclude),
    }
}

/// Six clips of speakers other than `exclude`, at the voice's level, from random circular
/// offsets, summed.
fn babble(lib: &Library, rng: &mut SeededRng, n: usize, exclude: &str) -> Vec<f32> {
    let mut others: Vec<usize> = (0..lib.clips.len())
        .filter(|&c| lib.clips[c].speaker != exclude)
        .collect();
    shuffle(rng, &mut others);
    let mut out = vec![0.0f32; n];
    for &c in others.iter().take(6) {
        let clip = &lib.clips[c];
        let g = db_gain(VOICE_DB - clip.level_db);
        let s = integer(rng, 0, clip.audio.len());
        for (i, y) in out.iter_mut().enumerate() {
            *y += g * clip.audio[(s + i) % clip.audio.len()];
        }
    }
    out
}

/// Every episode of the recipe.
pub fn episodes(lib: &Library) -> Vec<Episode> {
    let mut rng = SeededRng::new(SEED);
    let mut cycle = std::collections::VecDeque::new();
    for _ in 0..4 {
        let mut p: Vec<usize> = (0..lib.clips.len()).collect();
        shuffle(&mut rng, &mut p);
        cycle.extend(p);
    }
    (0..EPISODES)
        .map(|e| build(lib, e, &mut rng, &mut cycle))
        .collect()
}

/// The speakers of a set of clips, sorted.
pub fn speakers(clips: &[SpeechClip]) -> Vec<String> {
    let mut s: Vec<String> = clips.iter().map(|c| c.speaker.clone()).collect();
    s.sort();
    s.dedup();
    s
}

/// The library from the shared data folder.
pub fn library(data: &std::path::Path, praat: &mut sources::Praat<'_>) -> Result<Library, String> {
    let clips = sources::clips()
        .into_iter()
        .map(|c| sources::speech_clip(data, c, praat))
        .collect::<Result<Vec<_>, _>>()?;
    let music = MUSIC
        .iter()
        .map(|m| sources::read_16k(&data.join("music").join(format!("{m}.flac"))))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Library {
        speakers: speakers(&clips),
        clips,
        music,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A part at the voice's level framed by `quiet_db` (dBFS) noise before and after.
    fn part(quiet_db: f64) -> Vec<f32> {
        let mut rng = SeededRng::new(7);
        let mut x = Vec::new();
        for (frames, db) in [(10, quiet_db), (20, VOICE_DB), (12, quiet_db)] {
            let g = db_gain(db);
            x.extend((0..frames * HOP).map(|_| g * rng.normal() as f32));
        }
        x
    }

    #[test]
    fn a_part_sounds_from_its_first_to_its_last_audible_frame() {
        assert_eq!(sounding_frames(&part(DITHER_DB)), 10..30);
        // Quiet music (50 dB under the voice) still sounds: only silence is cut off.
        assert_eq!(sounding_frames(&part(VOICE_DB - 50.0)), 0..42);
        assert_eq!(sounding_frames(&vec![0.0; 5 * HOP]), 0..0);
    }
}
