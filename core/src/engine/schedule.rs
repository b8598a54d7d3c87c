//! A fixed-capacity queue for the audio thread: it never grows after `with_capacity`, a push
//! into a full queue drops the oldest entry (and counts it), and sorted insertion keeps
//! scheduled actions in time order.

use std::collections::VecDeque;

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

    pub(crate) fn front(&self) -> Option<&T> {
        self.items.front()
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
