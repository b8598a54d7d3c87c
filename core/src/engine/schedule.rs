//! What waits for the output: the analysed frames ([`Pending`]), and what the placement
//! schedules and the breath track and the breathing cycle carry out: breath actions on the
//! input timeline (samples), breathing-cycle actions (seconds); all in
//! [`Queue`]s, a fixed-capacity queue for the audio thread: it never grows after
//! `with_capacity`, a push into a full queue drops the oldest entry (and counts it), and sorted
//! insertion keeps scheduled actions in time order.

use std::collections::VecDeque;

use super::MAX_CHANNELS;
use crate::analysis::FeatureFrame;

/// A feature frame waiting for the output to reach it.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Pending {
    pub(crate) frame: FeatureFrame,
    /// The frame lies in sound judged not speech ([`super::body_gate::BodyGate`]): the body
    /// neither speaks nor moves its head for it.
    pub(crate) other_sound: bool,
    /// Output sample index from which it may be emitted.
    pub(crate) emit_at: u64,
}

/// A breath action on the input timeline (sample index).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum BreathAction {
    /// Start an inhalation of `length` samples with plateau RMS `gain`, spread over the
    /// channels with `gains`, under the recording's band edge `edge_hz` as known when it was
    /// placed (so any block partition plays the same).
    Start {
        length: usize,
        gain: f32,
        /// How far over its level a breath voice plays: the level of the speaker who speaks
        /// next against the recording's speech, dB, as known when it was placed (the speaker
        /// before it while too little of the next phrase is heard: [`super::speaker_level`]).
        speaker_db: f32,
        gains: [f32; MAX_CHANNELS],
        edge_hz: Option<f64>,
    },
    /// Live mode: start an inhalation like `Start` unless the input is active at that sample,
    /// and let the breathing cycle inspire with it (`audible` false: the cycle only).
    LiveStart {
        length: usize,
        gain: f32,
        speaker_db: f32,
        gains: [f32; MAX_CHANNELS],
        edge_hz: Option<f64>,
        audible: bool,
        group_s: f32,
    },
    /// Fade the playing inhalation out.
    FadeOut,
}

/// A breathing-cycle event on the input timeline (seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum CycleAction {
    /// Breathe in for `length_s`, to the lung a breath group of `group_s` seconds of speech
    /// takes ([`crate::breathing::BreathCycle::lung_volume_for`]).
    Inspire { length_s: f32, group_s: f32 },
    /// The stream starts in speech: the speaker breathed in for a group of `group_s` seconds
    /// of speech before it began (the lung is full at once).
    BreathedIn { group_s: f32 },
    /// A phrase starts after one judged other sound (a song, a sting), with no time or no
    /// judgement yet to breathe in before it (live mode; a lookahead too short): if it speaks,
    /// its speaker breathed in under that sound for a group of `group_s` seconds of speech, and
    /// the lung is full when it starts speaking.
    BreathOwed { group_s: f32 },
    /// A phrase starts with `left_s` seconds of speech left in its breath group.
    UtteranceStarts { left_s: f32 },
    /// A phrase ended (the breath is held while the pause lasts).
    SpeechStopped,
}

/// The actions waiting for the output to reach them.
#[derive(Debug, Clone)]
pub(crate) struct Schedule {
    pub(crate) breath: Queue<(u64, BreathAction)>,
    pub(crate) cycle: Queue<(f64, CycleAction)>,
    /// Live mode: the last input sample where activity was seen (input gate or phrase tracker)
    /// that the breathing cycle has not yet been told about.
    pub(crate) activity_unseen: Option<u64>,
    /// Live mode: the speaker is breathing in, in the pause, as of the last frame heard
    /// ([`crate::phrase::PhraseTracker::breathing_in_pause`]): activity seen meanwhile is the
    /// breath's, and does not stop the cycle's inspiration.
    pub(crate) breathing_in: bool,
}

impl Schedule {
    /// Queues of `capacity` actions each. Allocates.
    pub(crate) fn new(capacity: usize) -> Self {
        Self {
            breath: Queue::with_capacity(capacity),
            cycle: Queue::with_capacity(capacity),
            activity_unseen: None,
            breathing_in: false,
        }
    }

    /// Nothing scheduled.
    pub(crate) fn reset(&mut self) {
        self.breath.clear();
        self.cycle.clear();
        self.activity_unseen = None;
        self.breathing_in = false;
    }

    /// Live mode: activity at input sample `at`.
    pub(crate) fn note_activity(&mut self, at: u64) {
        self.activity_unseen = Some(self.activity_unseen.map_or(at, |u| u.max(at)));
    }

    /// Actions pushed out of full queues.
    pub(crate) fn dropped(&self) -> u64 {
        self.breath.dropped() + self.cycle.dropped()
    }
}

/// A bounded FIFO that never allocates after construction.
#[derive(Debug, Clone)]
pub(crate) struct Queue<T> {
    items: VecDeque<T>,
    capacity: usize,
    dropped: u64,
}

impl<T: Copy> Queue<T> {
    /// A queue holding at most `capacity` (≥ 1) items.
    pub(crate) fn with_capacity(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Self {
            items: VecDeque::with_capacity(capacity),
            capacity,
            dropped: 0,
        }
    }

    pub(crate) fn clear(&mut self) {
        self.items.clear();
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = &T> {
        self.items.iter()
    }

    pub(crate) fn iter_mut(&mut self) -> impl Iterator<Item = &mut T> {
        self.items.iter_mut()
    }

    pub(crate) fn front(&self) -> Option<&T> {
        self.items.front()
    }

    pub(crate) fn front_mut(&mut self) -> Option<&mut T> {
        self.items.front_mut()
    }

    pub(crate) fn back_mut(&mut self) -> Option<&mut T> {
        self.items.back_mut()
    }

    /// True when the next push drops the oldest item.
    pub(crate) fn is_full(&self) -> bool {
        self.items.len() >= self.capacity
    }

    pub(crate) fn pop_front(&mut self) -> Option<T> {
        self.items.pop_front()
    }

    /// Keeps only the items for which `keep` is true (order kept, no allocation).
    pub(crate) fn retain(&mut self, keep: impl FnMut(&T) -> bool) {
        self.items.retain(keep);
    }

    #[allow(dead_code)]
    pub(crate) fn len(&self) -> usize {
        self.items.len()
    }

    /// Items dropped because the queue was full (since construction; `clear` keeps the count).
    pub(crate) fn dropped(&self) -> u64 {
        self.dropped
    }

    fn make_room(&mut self) {
        if self.items.len() >= self.capacity {
            self.items.pop_front();
            self.dropped += 1;
        }
    }

    /// Appends `item`, dropping the oldest when full.
    pub(crate) fn push_back(&mut self, item: T) {
        self.make_room();
        self.items.push_back(item);
    }
}

impl<K: PartialOrd + Copy, V: Copy> Queue<(K, V)> {
    /// Inserts `item` after every entry whose key is not greater (stable time order), dropping
    /// the oldest when full.
    pub(crate) fn insert_sorted(&mut self, item: (K, V)) {
        self.make_room();
        let at = self
            .items
            .iter()
            .position(|e| e.0 > item.0)
            .unwrap_or(self.items.len());
        self.items.insert(at, item);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sorted_insert_keeps_time_order_and_is_stable() {
        let mut q: Queue<(u64, char)> = Queue::with_capacity(8);
        for item in [(5, 'a'), (2, 'b'), (5, 'c'), (9, 'd'), (0, 'e')] {
            q.insert_sorted(item);
        }
        let order: Vec<_> = std::iter::from_fn(|| q.pop_front()).collect();
        assert_eq!(
            order,
            vec![(0, 'e'), (2, 'b'), (5, 'a'), (5, 'c'), (9, 'd')]
        );
    }

    #[test]
    fn a_full_queue_drops_the_oldest_and_never_grows() {
        let mut q: Queue<u32> = Queue::with_capacity(3);
        let cap = q.items.capacity();
        for i in 0..10 {
            q.push_back(i);
        }
        assert_eq!(q.len(), 3);
        assert_eq!(q.dropped(), 7);
        assert_eq!(q.front(), Some(&7));
        assert_eq!(q.items.capacity(), cap);
    }
}
