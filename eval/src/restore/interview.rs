//! Two speakers in one recording (an interview), restored: the level of the breaths put back
//! before each speaker against the real breaths they replace.
//!
//! Five pairs of Keele speakers ([`PAIRS`], host and guest of the same pair number). Each clip is
//! cut into [`TURNS`] turns [`TURN_LEAD_S`] before a labelled breath or unsure label (the pause's
//! breath goes with the turn it opens, as a speaker breathes before speaking) and the turns
//! alternate, host first, the guest's at [`GUEST_GAINS_DB`] (level with the host, and
//! [`SELF_GUEST_DB`] under: a remote guest on a quieter line). Every other clear breath of each
//! speaker is gated to digital silence, in two renders (odd ones, then even ones), so that every
//! breath is restored once while the voice learns from the real breaths left in. Each breath put
//! back ([`super::put_back`]) is scored as `eval restore` scores a level (output − input
//! over the inserted span, against the real breath with its clip's floor taken out, moved by the
//! turn's gain); extra inserted breaths are not counted here. The same with each Keele speaker as
//! their own guest, [`SELF_GUEST_DB`] under: the two voices breathe alike against their speech, so
//! only the level each breath is measured and played against can part them (breath `k` of both
//! roles is the same real breath, gated in the same render, so the copy restored is never learned
//! from). The built-in voice a render falls back on is fitted without both speakers. Nothing is
//! fitted on it: reported only.

use std::collections::BTreeMap;

use pneuma_core::breathing::reference::ReferenceVoice;
use pneuma_core::breathing::third_octave::{band_level_db, band_powers};
use pneuma_core::engine::EngineConfig;

use super::report::LEVEL_WITHIN_DB;
use super::{added, put_back, reference, render, samples_of, Clip, Cut, Voice};
use crate::stats::median;

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
/// The guest's gain against the host when each speaker is their own guest, dB.
const SELF_GUEST_DB: f64 = -12.0;
/// The guest's gain against the host, dB.
const GUEST_GAINS_DB: [f64; 2] = [0.0, SELF_GUEST_DB];
/// How far before a label a turn starts, seconds: the labels' times are good to about 50 ms.
const TURN_LEAD_S: f64 = 0.05;

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

/// Where `clip` is cut into turns, seconds: 0, for each `k / TURNS` of the clip the nearest
/// start (less [`TURN_LEAD_S`]) of a label after the last cut and outside every clear breath,
/// and its end. An error when fewer than [`TURNS`] turns can be cut.
fn turn_cuts(clip: &Clip) -> Result<Vec<f64>, String> {
    let dur_s = clip.audio.len() as f64 / clip.rate_hz;
    let inside_breath = |t: f64| clip.breaths.iter().any(|&(s, e)| s <= t && t < e);
    let mut cuts = vec![0.0];
    for k in 1..TURNS {
        let at_s = k as f64 * dur_s / TURNS as f64;
        let last_s = cuts[cuts.len() - 1];
        let nearest = clip
            .breaths
            .iter()
            .chain(&clip.unsure)
            .map(|&(s, _)| s - TURN_LEAD_S)
            .filter(|&t| t > last_s && !inside_breath(t))
            .min_by(|a, b| (a - at_s).abs().total_cmp(&(b - at_s).abs()))
            .ok_or_else(|| {
                format!(
                    "{}: no label to cut turn {} of {TURNS} before (an interview needs them)",
                    clip.name,
                    k + 1
                )
            })?;
        cuts.push(nearest);
    }
    cuts.push(dur_s);
    Ok(cuts)
}

/// The interview of `host` and `guest` (the guest's turns `guest_db` under): its audio and its
/// clear breaths; an error when a clear breath would straddle two turns.
fn build(host: &Clip, guest: &Clip, guest_db: f64) -> Result<(Vec<f32>, Vec<Placed>), String> {
    let turns = |c: &Clip| -> Result<Vec<(f64, f64)>, String> {
        let cuts = turn_cuts(c)?;
        Ok(cuts.windows(2).map(|w| (w[0], w[1])).collect())
    };
    let (h, g) = (turns(host)?, turns(guest)?);
    let mut audio = Vec::new();
    let mut placed = Vec::new();
    for k in 0..TURNS {
        for (clip, role, gain_db, (t0, t1)) in [
            (host, Role::Host, 0.0, h[k]),
            (guest, Role::Guest, guest_db, g[k]),
        ] {
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
    let want = host.breaths.len() + guest.breaths.len();
    if placed.len() != want {
        return Err(format!(
            "{} / {}: {} of {want} clear breaths inside a turn",
            host.name,
            guest.name,
            placed.len()
        ));
    }
    Ok((audio, placed))
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
    fallback: &ReferenceVoice,
) -> Result<Vec<(Role, Option<f64>)>, String> {
    let spans: Vec<(f64, f64)> = placed.iter().map(|p| p.span_s).collect();
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
        let input = Cut::Gated.apply(audio, rate_hz, &spans, &which);
        let r = render(
            config,
            &input,
            audio,
            rate_hz,
            voice,
            fallback,
            phase as u64,
        )?;
        let added = added(&r, &input);
        let mut used = vec![false; r.breaths.len()];
        for &i in &which {
            let level_db = put_back(&r, &mut used, placed[i].span_s).map(|j| {
                let b = &r.breaths[j];
                let powers =
                    band_powers(samples_of(&added, rate_hz, (b.start_s, b.end_s)), rate_hz);
                band_level_db(&powers, rate_hz) - placed[i].real_db
            });
            out.push((placed[i].role, level_db));
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

/// Prints the interview restore of the [`PAIRS`] among `clips` and of each of their speakers
/// as their own guest (see the module docs), rendered with `config`, for the voice learned from
/// the whole file and the one learned as it goes.
pub fn report(config: &EngineConfig, clips: &[Clip]) -> Result<(), String> {
    let find = |name: &str| clips.iter().find(|c| c.name == name);
    let pairs: Vec<(&Clip, &Clip)> = PAIRS
        .iter()
        .filter_map(|&(h, g)| Some((find(h)?, find(g)?)))
        .collect();
    if pairs.is_empty() {
        let (h, g) = PAIRS[0];
        println!("\ninterview restore: none of the Keele pairs ({h} and {g}, ...) found");
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
            restore_set(config, clips, &pairs, guest_db, voice, true)?;
        }
        let selves: Vec<(&Clip, &Clip)> =
            pairs.iter().flat_map(|&(h, g)| [(h, h), (g, g)]).collect();
        println!("{what}, each speaker as their own guest {SELF_GUEST_DB:+} dB:");
        restore_set(config, clips, &selves, SELF_GUEST_DB, voice, false)?;
    }
    Ok(())
}

/// Restores the interviews of `pairs` (host, guest) with the guest `guest_db` under and
/// prints the levels, each pair's when `each`, and all pairs'; the built-in voice a render
/// falls back on is fitted on the other speakers of `clips`.
fn restore_set(
    config: &EngineConfig,
    clips: &[Clip],
    pairs: &[(&Clip, &Clip)],
    guest_db: f64,
    voice: Voice,
    each: bool,
) -> Result<(), String> {
    let mut all: BTreeMap<Role, Vec<Option<f64>>> = BTreeMap::new();
    for &(host, guest) in pairs {
        if host.rate_hz != guest.rate_hz {
            return Err(format!(
                "{} and {}: rates differ ({} and {} Hz); an interview needs one",
                host.name, guest.name, host.rate_hz, guest.rate_hz
            ));
        }
        let fallback = reference::fit(
            clips
                .iter()
                .filter(|c| c.speaker != host.speaker && c.speaker != guest.speaker),
        )
        .ok_or("no other speaker's breath to fit the built-in voice on")?;
        let (audio, placed) = build(host, guest, guest_db)?;
        let levels = restore(config, &audio, host.rate_hz, &placed, voice, &fallback)?;
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
