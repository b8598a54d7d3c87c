//! Steps 4 and 5 of a block ([`Stream::output`]): the breath sound and the control frames, up
//! to the sample that completes the next analysis frame or to the block's end, so a frame's
//! events meet the output as of their own sample in any block partition (see `DESIGN.md`,
//! "Inside `Engine::process`").

use super::breath_track::Block;
use super::{ControlFrame, EngineConfig, Stream};

/// How far [`Stream::output`] has carried out one block.
#[derive(Debug, Clone, Copy)]
pub(super) struct Output {
    /// The block.
    pub(super) block: Block,
    /// Samples of the block output so far.
    pub(super) done: usize,
    /// Live mode: samples of the block whose input activity the schedule has been told of.
    pub(super) checked: usize,
}

impl Stream {
    /// Steps 4 and 5 for the block's samples from `out.done` up to `to` (exclusive): the breath
    /// actions due there and the breath sound added to the output, then the control frames
    /// due there, each with its offset in the caller's buffers.
    pub(super) fn output(
        &mut self,
        config: &EngineConfig,
        audio: &mut [&mut [f32]],
        out: &mut Output,
        to: usize,
        on_control: &mut dyn FnMut(&ControlFrame, usize),
    ) {
        let Block {
            base,
            start,
            channels,
            ..
        } = out.block;
        let from = out.done;
        if to <= from {
            return;
        }
        out.done = to;
        self.breaths.render(
            config,
            audio,
            Block {
                base: base + from as u64,
                start: start + from,
                n: to - from,
                channels,
            },
            &self.input_active[from..to],
            &mut self.schedule,
        );
        let end = base + to as u64;
        while let Some(p) = self.pending.front().copied() {
            if p.emit_at >= end {
                break;
            }
            self.pending.pop_front();
            let offset = (p.emit_at.max(base) - base) as usize;
            if self.live && offset >= out.checked {
                self.note_activity(base, out.checked, offset + 1);
                out.checked = offset + 1;
            }
            let breathing = self.cycle.step(&p, &mut self.schedule);
            let f = &p.frame;
            // Music, singing or noise judged not speech: the head rests as in a silence.
            let head = if p.other_sound {
                self.head.process_other_sound(f, self.frame_rate_hz)
            } else {
                self.head.process(f, self.frame_rate_hz)
            };
            let frame = ControlFrame {
                index: f.index,
                time_s: f.time_s,
                f0_hz: f.f0_hz,
                voiced: f.voiced,
                rms_db: f.rms_db,
                level_db: f.level_db,
                speaking: self.cycle.speaking(),
                breathing,
                head,
            };
            on_control(&frame, start + offset);
        }
    }

    /// Live mode: tells the schedule the last active input sample of `input_active[from..to]`
    /// (block starting at input sample `base`), for the breathing cycle.
    pub(super) fn note_activity(&mut self, base: u64, from: usize, to: usize) {
        if let Some(k) = self.input_active[from..to].iter().rposition(|&a| a) {
            self.schedule.note_activity(base + (from + k) as u64);
        }
    }
}
