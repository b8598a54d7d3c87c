//! The breath track: carries out the scheduled breath actions on the output timeline, renders
//! the breath sound ([`BreathVoice`]) and mixes it into the channels with the breath's stereo
//! gains, fades a live breath out at the first active input sample, and keeps the record of
//! every breath (start, end, kind, peak) for [`super::Engine::take_breaths`].

use super::schedule::{BreathAction, CycleAction, Queue, Schedule};
use super::{EngineConfig, MAX_CHANNELS};
use crate::breathing::BreathVoice;
use crate::control::{BreathEvent, BreathKind};

/// Live mode: a breath whose peak stayed under this, dBFS, is an inaudible stub and is not
/// reported.
const LIVE_STUB_PEAK_DB: f32 = -60.0;
/// Live mode: a breath cut by speech before it sounded this long, seconds, is a stub (still in
/// its attack, under the onset that cut it) and is not reported.
const LIVE_STUB_S: f64 = 0.06;
/// Finished breaths kept until collected.
const FINISHED_CAPACITY: usize = 64;

/// Where one block of the stream sits: input/output stream position of its first sample, its
/// range in the caller's buffers and the channels to process.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Block {
    pub(crate) base: u64,
    pub(crate) start: usize,
    pub(crate) n: usize,
    pub(crate) channels: usize,
}

/// The breath being rendered, for `breaths.csv`.
#[derive(Debug, Clone, Copy)]
struct OpenBreath {
    start: u64,
    /// Planned end (input timeline), shortened by a fade-out.
    end: u64,
    kind: BreathKind,
    peak: f32,
    /// Where a fade-out began, if one did.
    fade_from: Option<u64>,
}

/// See the module docs. Allocation-free after `new`.
#[derive(Debug)]
pub(crate) struct BreathTrack {
    voice: BreathVoice,
    /// The breath sound of the current block (mono).
    buffer: Vec<f32>,
    finished: Queue<BreathEvent>,
    sample_rate_hz: f64,
    latency: u64,
    live: bool,
    state: TrackState,
}

/// What [`BreathTrack::reset`] clears.
#[derive(Debug, Clone, Copy)]
struct TrackState {
    open: Option<OpenBreath>,
    /// Channel gains of the breath playing.
    gains: [f32; MAX_CHANNELS],
    /// Live mode: the playing breath is already fading out.
    fading: bool,
}

impl Default for TrackState {
    fn default() -> Self {
        Self {
            open: None,
            gains: [1.0; MAX_CHANNELS],
            fading: false,
        }
    }
}

impl BreathTrack {
    /// A track playing `voice` (prepared for blocks of `max_block`) behind a delay of `latency`
    /// samples. Allocates.
    pub(crate) fn new(
        voice: BreathVoice,
        sample_rate_hz: f64,
        latency: usize,
        live: bool,
        max_block: usize,
    ) -> Self {
        Self {
            voice,
            buffer: vec![0.0; max_block],
            finished: Queue::with_capacity(FINISHED_CAPACITY),
            sample_rate_hz,
            latency: latency as u64,
            live,
            state: TrackState::default(),
        }
    }

    /// Nothing playing, nothing recorded.
    pub(crate) fn reset(&mut self) {
        self.voice.reset();
        self.finished.clear();
        self.state = TrackState::default();
    }

    /// The breath voice (to change its samples).
    pub(crate) fn voice_mut(&mut self) -> &mut BreathVoice {
        &mut self.voice
    }

    /// A breath is playing and not fading out yet.
    pub(crate) fn playing(&self) -> bool {
        self.voice.is_active() && !self.state.fading
    }

    /// Hands every finished breath to `on_breath`, oldest first.
    pub(crate) fn take(&mut self, mut on_breath: impl FnMut(&BreathEvent)) {
        while let Some(b) = self.finished.pop_front() {
            on_breath(&b);
        }
    }

    /// Finished breaths pushed out before they were taken.
    pub(crate) fn dropped(&self) -> u64 {
        self.finished.dropped()
    }

    /// Renders the breath sound for the output block and adds it to the channels, carrying out
    /// the breath actions due in it; `input_active` (live mode) marks the block's active input
    /// samples. A live start pushes its inspiration into the schedule's cycle actions.
    pub(crate) fn render(
        &mut self,
        config: &EngineConfig,
        audio: &mut [&mut [f32]],
        block: Block,
        input_active: &[bool],
        schedule: &mut Schedule,
    ) {
        let Block {
            base,
            start,
            n,
            channels,
        } = block;
        let end = base + n as u64;
        // Output sample o plays input sample o - latency.
        let in_base = base.saturating_sub(self.latency);
        let warm = self.latency.saturating_sub(base).min(n as u64) as usize;
        if !self.voice.is_active()
            && schedule
                .breath
                .front()
                .is_none_or(|&(t, _)| t + self.latency >= end)
        {
            return;
        }
        // Taken out for the loop (no allocation) and put back at the end.
        let mut breath = std::mem::take(&mut self.buffer);
        let buf = &mut breath[..n];
        buf.fill(0.0);
        let mut pos = warm;
        let mut active_from = n;
        let mut active_to = 0;
        loop {
            let mut next = schedule
                .breath
                .front()
                .map(|&(t, a)| ((t.max(in_base) - in_base) as usize + warm, a))
                .filter(|&(off, _)| off < n);
            // Breaths switched off (the plugin's bypass) fade a breath playing at once; live:
            // the first active input sample under a breath not yet fading fades it.
            let mut gated = false;
            if !config.placement.insert_breaths && self.playing() {
                next = Some((pos, BreathAction::FadeOut));
                gated = true;
            } else if self.live && self.playing() {
                let until = next.map_or(n, |(off, _)| off);
                if let Some(k) = input_active[pos..until].iter().position(|&a| a) {
                    next = Some((pos + k, BreathAction::FadeOut));
                    gated = true;
                }
            }
            let stop = next.map_or(n, |(off, _)| off);
            if self.voice.is_active() && stop > pos {
                active_from = active_from.min(pos);
                active_to = stop;
                self.voice.render_add(&mut buf[pos..stop]);
            }
            pos = stop;
            let Some((_, action)) = next else { break };
            if !gated {
                schedule.breath.pop_front();
            }
            let at = in_base + pos as u64 - warm as u64;
            let action = match action {
                // Live: speech is back where the breath was due: neither sound nor inspiration.
                BreathAction::LiveStart { .. } if input_active[pos] => continue,
                BreathAction::LiveStart {
                    length,
                    gain,
                    speaker_db,
                    gains,
                    edge_hz,
                    audible,
                    group_s,
                } => {
                    let rate = self.sample_rate_hz;
                    schedule.cycle.insert_sorted((
                        at as f64 / rate,
                        CycleAction::Inspire {
                            length_s: (length as f64 / rate) as f32,
                            group_s,
                        },
                    ));
                    if !audible || !config.placement.insert_breaths {
                        continue;
                    }
                    BreathAction::Start {
                        length,
                        gain,
                        speaker_db,
                        gains,
                        edge_hz,
                    }
                }
                other => other,
            };
            match action {
                // Placed while breaths were on: nothing sounds once they are off.
                BreathAction::Start { .. } if !config.placement.insert_breaths => {}
                BreathAction::Start {
                    length,
                    gain,
                    speaker_db,
                    gains,
                    edge_hz,
                } => {
                    // Close the previous breath's record before the new one starts.
                    if self.state.open.is_some() {
                        let peak = buf[active_from.min(pos)..pos]
                            .iter()
                            .fold(0.0f32, |m, x| m.max(x.abs()));
                        let g_max = self.max_channel_gain(channels);
                        if let Some(b) = &mut self.state.open {
                            b.peak = b.peak.max(peak * g_max);
                        }
                        self.close_breath();
                    }
                    let mouth = config.breathing.map().mouth_share();
                    // A learned voice plays at its learned level, moved by the user's level and
                    // breathing sound and to the level of the speaker who speaks next (as the
                    // placement knew it: `BreathAction::Start::speaker_db`).
                    let default_level_db = super::PlacementConfig::default().breath_level_db;
                    self.voice.set_learned_offset_db(f64::from(
                        config.breath_level_re_speech_db() - default_level_db + speaker_db,
                    ));
                    self.state.fading = false;
                    self.voice.set_upper_edge_hz(edge_hz);
                    self.voice.start(mouth, length, gain);
                    self.state.gains = gains;
                    self.state.open = Some(OpenBreath {
                        start: at,
                        end: at + length as u64,
                        kind: self.voice.kind(),
                        peak: 0.0,
                        fade_from: None,
                    });
                    active_from = active_from.min(pos);
                }
                BreathAction::FadeOut if self.state.fading => {}
                BreathAction::FadeOut => {
                    self.state.fading = true;
                    let fade = (config.placement.live_fade_s as f64 * self.sample_rate_hz)
                        .round()
                        .max(1.0) as usize;
                    self.voice.fade_out(fade);
                    if let Some(b) = &mut self.state.open {
                        b.end = b.end.min(at + fade as u64);
                        b.fade_from.get_or_insert(at);
                    }
                }
                BreathAction::LiveStart { .. } => unreachable!("turned into Start above"),
            }
        }
        if active_from < active_to {
            let peak = buf[active_from..active_to]
                .iter()
                .fold(0.0f32, |m, x| m.max(x.abs()));
            let g_max = self.max_channel_gain(channels);
            if let Some(b) = &mut self.state.open {
                b.peak = b.peak.max(peak * g_max);
            }
            for (c, chan) in audio.iter_mut().take(channels).enumerate() {
                let g = self.state.gains[c];
                let out = &mut chan[start + active_from..start + active_to];
                for (y, b) in out.iter_mut().zip(&buf[active_from..active_to]) {
                    // Only where the breath sounds: adding 0 would turn −0.0 into +0.0.
                    if *b != 0.0 {
                        *y += g * b;
                    }
                }
            }
        }
        self.buffer = breath;
        if !self.voice.is_active() {
            self.close_breath();
        }
    }

    fn max_channel_gain(&self, channels: usize) -> f32 {
        self.state.gains[..channels]
            .iter()
            .fold(0.0, |m, g| m.max(*g))
    }

    /// Files the current breath (if any) as finished, with its planned (or faded) end; a live
    /// stub is dropped (see `LIVE_STUB_*`).
    pub(crate) fn close_breath(&mut self) {
        if let Some(b) = self.state.open.take() {
            let peak_db = crate::analysis::amplitude_to_db(b.peak as f64);
            let rate = self.sample_rate_hz;
            let sounded_s = (b.fade_from.unwrap_or(b.end).saturating_sub(b.start)) as f64 / rate;
            if self.live
                && (peak_db.is_nan() || peak_db < LIVE_STUB_PEAK_DB || sounded_s < LIVE_STUB_S)
            {
                return;
            }
            self.finished.push_back(BreathEvent {
                start_s: b.start as f64 / rate,
                end_s: b.end.max(b.start) as f64 / rate,
                kind: b.kind,
                peak_db,
            });
        }
    }
}
