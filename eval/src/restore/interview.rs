//! Two speakers in one recording (an interview), restored: the level of the breaths put back
//! before each speaker against the real breaths they replace.
//!
//! Five pairs of Keele speakers ([`PAIRS`], host and guest of the same pair number). Each clip
//! is cut into [`TURNS`] turns just before a labelled breath (the pause's breath goes with the
//! turn it opens, as a speaker breathes before speaking) and the turns alternate, host first,
//! the guest's at [`GUEST_GAINS_DB`] (level with the host, and 12 dB under: a remote guest on
//! a quieter line). Every other clear breath of each speaker is gated to digital silence, in
//! two renders (odd ones, then even ones), so that every breath is restored once while the
//! voice learns from the real breaths left in. Each breath put back (within
//! [`super::PUT_BACK_S`]) is scored as `eval restore` scores a level (output − input over the
//! inserted span, against the real breath with its clip's floor taken out, moved by the turn's
//! gain). The same with each Keele speaker as their own guest, 12 dB under: the two voices
//! breathe alike against their speech, so only the level each breath is measured and played
//! against can part them. Nothing is fitted on it: reported only.

use pneuma_core::breathing::third_octave::{band_level_db, band_powers};
use pneuma_core::engine::EngineConfig;

use super::{render, samples_of, Clip, Cut, Voice, PUT_BACK_S};
use crate::stats::median;
use pneuma_core::breathing::reference::ReferenceVoice;
use std::collections::BTreeMap;

/// Host and guest clips of the five pairs.
pub const PAIRS: [(&str, &str); 5] = [
    ("m1nw0000", "f1nw0000"),
    ("m2nw0000", "f2nw0000"),
    ("m3nw0000", "f3nw0000"),
    ("m4nw0000", "f4nw0000"),
    ("m5nw0000", "f5nw0000"),
];
/// Turns each speaker's clip is cut into.
const TURNS: usize = 3;
/// The guest's gain against the host, dB.
const GUEST_GAINS_DB: [f64; 2] = [0.0, -12.0];
/// How far before a labelled breath a turn starts, seconds.
const TURN_LEAD_S: f64 = 0.02;
/// Within this many dB of the real breath a breath counts as level with it (the issue's ±4 dB).
const LEVEL_WITHIN_DB: f64 = 4.0;

/// Which speaker a breath belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Role {
    Host,
    Guest,
}

/// A clear labelled breath in the interview: its speaker, span (seconds, interview time) and
/// real level (floor taken out, the turn's gain applied), dBFS.
struct Placed {
    role: Role,
    span_s: (f64, f64),
    real_db: f64,
}

/// Where `clip` is cut into turns, seconds: 0, the starts (less [`TURN_LEAD_S`]) of the
/// labelled breaths nearest to each `k / TURNS` of the clip, its end.
fn turn_cuts(clip: &Clip) -> Vec<f64> {
    let dur_s = clip.audio.len() as f64 / clip.rate_hz;
    let mut cuts = vec![0.0];
    for k in 1..TURNS {
        let at_s = k as f64 * dur_s / TURNS as f64;
        let nearest = clip
            .breaths
            .iter()
            .chain(&clip.unsure)
            .map(|&(s, _)| (s - TURN_LEAD_S).max(0.0))
            .min_by(|a, b| (a - at_s).abs().total_cmp(&(b - at_s).abs()));
        if let Some(t) = nearest.filter(|&t| t > *cuts.last().unwrap_or(&0.0)) {
            cuts.push(t);
        }
    }
    cuts.push(dur_s);
    cuts
}

/// The interview of `host` and `guest` (the guest's turns `guest_db` under): its audio and its
/// clear breaths.
fn build(host: &Clip, guest: &Clip, guest_db: f64) -> (Vec<f32>, Vec<Placed>) {
    let turns = |c: &Clip| {
        let cuts = turn_cuts(c);
        cuts.windows(2).map(|w| (w[0], w[1])).collect::<Vec<_>>()
    };
    let (h, g) = (turns(host), turns(guest));
    let mut audio = Vec::new();
    let mut placed = Vec::new();
    for k in 0..h.len().max(g.len()) {
        for (clip, role, gain_db, turn) in [
            (host, Role::Host, 0.0, h.get(k)),
            (guest, Role::Guest, guest_db, g.get(k)),
        ] {
            let Some(&(t0, t1)) = turn else { continue };
            let offset_s = audio.len() as f64 / clip.rate_hz - t0;
            let gain = 10f64.powf(gain_db / 20.0) as f32;
            audio.extend(
                samples_of(&clip.audio, clip.rate_hz, (t0, t1))
                    .iter()
                    .map(|v| v * gain),
            );
            for (&(s, e), &db) in clip.breaths.iter().zip(&clip.real_levels_db) {
                if t0 <= s && e <= t1 {
                    placed.push(Placed {
                        role,
                        span_s: (s + offset_s, e + offset_s),
                        real_db: db + gain_db,
                    });
                }
            }
        }
    }
    (audio, placed)
}

/// Inserted − real level of each breath of `placed` restored in the interview `audio` (rate
/// `rate_hz`) rendered with `voice`, every other breath of each speaker gated per render;
/// `None` for a breath not put back.
fn restore(
    config: &EngineConfig,
    audio: &[f32],
    rate_hz: f64,
    placed: &[Placed],
    voice: Voice,
    held_out: &ReferenceVoice,
) -> Result<Vec<(Role, Option<f64>)>, String> {
    let mut out = Vec::new();
    for phase in 0..2 {
        let mut seen: BTreeMap<Role, usize> = BTreeMap::new();
        let which: Vec<usize> = (0..placed.len())
            .filter(|&i| {
                let n = seen.entry(placed[i].role).or_default();
                *n += 1;
                (*n - 1) % 2 == phase
            })
            .collect();
        let spans: Vec<(f64, f64)> = placed.iter().map(|p| p.span_s).collect();
        let input = Cut::Gated.apply(audio, rate_hz, &spans, &which);
        let r = render(
            config,
            &input,
            audio,
            rate_hz,
            voice,
            held_out,
            phase as u64,
        )?;
        let added: Vec<f32> = r.audio[0].iter().zip(&input).map(|(o, i)| o - i).collect();
        let mut used = vec![false; r.breaths.len()];
        for &i in &which {
            let (s, e) = placed[i].span_s;
            let best = (0..r.breaths.len())
                .filter(|&j| {
                    !used[j]
                        && r.breaths[j].start_s < e + PUT_BACK_S
                        && s - PUT_BACK_S < r.breaths[j].end_s
                })
                .max_by(|&a, &b| {
                    let ov = |j: usize| r.breaths[j].end_s.min(e) - r.breaths[j].start_s.max(s);
                    ov(a).total_cmp(&ov(b))
                });
            let level = best.map(|j| {
                used[j] = true;
                let b = &r.breaths[j];
                let powers =
                    band_powers(samples_of(&added, rate_hz, (b.start_s, b.end_s)), rate_hz);
                band_level_db(&powers, rate_hz) - placed[i].real_db
            });
            out.push((placed[i].role, level));
        }
    }
    Ok(out)
}

/// "median (share within ±4 dB, n)" of the levels put back, and how many were not.
fn summary(levels: &[Option<f64>]) -> String {
    let put: Vec<f64> = levels.iter().flatten().copied().collect();
    if put.is_empty() {
        return format!("none put back of {}", levels.len());
    }
    let within = put.iter().filter(|d| d.abs() <= LEVEL_WITHIN_DB).count();
    format!(
        "{:+5.1} dB ({:3.0} % within ±{LEVEL_WITHIN_DB} dB, n {}{})",
        median(&put),
        100.0 * within as f64 / put.len() as f64,
        put.len(),
        match levels.len() - put.len() {
            0 => String::new(),
            n => format!(", {n} not put back"),
        }
    )
}

/// Prints the interview restore of the [`PAIRS`] among `clips` (see the module docs), and of
/// each Keele speaker as their own guest (the same turns, the guest's 12 dB under: the two
/// voices breathe alike against their speech, so only the level each breath is measured and
/// played against can part them), for the voice learned from the whole file and the one
/// learned as it goes; `held_out`: the built-in voices fitted without each speaker (the
/// host's is the fall-back before a breath is heard).
pub fn report(clips: &[Clip], held_out: &BTreeMap<String, ReferenceVoice>) -> Result<(), String> {
    let find = |name: &str| clips.iter().find(|c| c.name == name);
    let pairs: Vec<(&Clip, &Clip)> = PAIRS
        .iter()
        .filter_map(|&(h, g)| Some((find(h)?, find(g)?)))
        .collect();
    if pairs.is_empty() {
        println!("\ninterview restore: none of the Keele pairs (m1nw0000 and f1nw0000, ...) found");
        return Ok(());
    }
    println!(
        "\n== interview restore (reported only, HELD OUT): {} Keele pairs, host and guest in \
         {TURNS} alternating turns each, every other breath of each gated in turn; inserted − \
         real level, median",
        pairs.len()
    );
    for (voice, what) in [
        (Voice::Learned, "voice learned from the whole file"),
        (Voice::AsItGoes, "learned as it goes (plugin, lookahead)"),
    ] {
        for guest_db in GUEST_GAINS_DB {
            println!("{what}, guest {guest_db:+} dB:");
            restore_set(&pairs, guest_db, voice, held_out, true)?;
        }
        let selves: Vec<(&Clip, &Clip)> =
            pairs.iter().flat_map(|&(h, g)| [(h, h), (g, g)]).collect();
        let guest_db = GUEST_GAINS_DB[1];
        println!("{what}, each speaker as their own guest {guest_db:+} dB:");
        restore_set(&selves, guest_db, voice, held_out, false)?;
    }
    Ok(())
}

/// Restores the interviews of `pairs` (host, guest) with the guest `guest_db` under and
/// prints the levels, each pair's when `each`, and all pairs'.
fn restore_set(
    pairs: &[(&Clip, &Clip)],
    guest_db: f64,
    voice: Voice,
    held_out: &BTreeMap<String, ReferenceVoice>,
    each: bool,
) -> Result<(), String> {
    let config = EngineConfig::default();
    let mut all: BTreeMap<Role, Vec<Option<f64>>> = BTreeMap::new();
    for &(host, guest) in pairs {
        if host.rate_hz != guest.rate_hz {
            return Err(format!(
                "{} and {}: rates differ ({} and {} Hz); an interview needs one",
                host.name, guest.name, host.rate_hz, guest.rate_hz
            ));
        }
        let (audio, placed) = build(host, guest, guest_db);
        let h = &held_out[&host.speaker];
        let levels = restore(&config, &audio, host.rate_hz, &placed, voice, h)?;
        let of = |role: Role| -> Vec<Option<f64>> {
            levels
                .iter()
                .filter(|(r, _)| *r == role)
                .map(|&(_, l)| l)
                .collect()
        };
        if each {
            println!(
                "  {} / {}: host {}, guest {}",
                host.name,
                guest.name,
                summary(&of(Role::Host)),
                summary(&of(Role::Guest))
            );
        }
        for role in [Role::Host, Role::Guest] {
            all.entry(role).or_default().extend(of(role));
        }
    }
    println!(
        "  all: host {}, guest {}",
        summary(&all[&Role::Host]),
        summary(&all[&Role::Guest])
    );
    Ok(())
}
