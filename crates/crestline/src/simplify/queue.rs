//! The queue of candidate collapses, ordered by quadric cost (see the module docs of
//! [`crate::simplify`], "Order").

/// A queued candidate, 16 bytes so that the heap stays compact: the cost as the bits of a
/// non-negative `f32` (which sort like the values; costs are computed in `f64` in normalised
/// coordinates, so `f32` keeps their order up to ties), the edge `u v`, and the sum of the
/// version stamps of `u` and `v` when it was queued. Stamps only grow, so an unchanged sum
/// means both are unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) struct Entry {
    pub(super) cost: u32,
    pub(super) u: u32,
    pub(super) v: u32,
    pub(super) stamp: u32,
}

/// The queue of candidate collapses: an exact min-priority queue with lazy deletion.
///
/// It is popped about ten times per collapse, mostly to discard stale entries, and on large
/// meshes all candidates together are far bigger than the caches, where every level of a
/// heap costs a cache miss. So only the cheapest candidates — those not above `threshold` —
/// live in a heap (four children per node: half the depth of a binary heap for about the
/// same cache lines per level); the others wait unordered in `overflow`. When the heap runs
/// dry, the overflow is purged of stale entries and its next [`REFILL`] cheapest move into
/// the heap. Pops come out in exactly the order of one big heap.
pub(super) struct CandidateQueue {
    heap: Vec<Entry>,
    overflow: Vec<Entry>,
    /// Entries up to this one belong in the heap; `None` while the heap holds nothing yet.
    threshold: Option<Entry>,
}

/// How many candidates move from the overflow to the heap at a time (512 KB of entries).
pub(super) const REFILL: usize = 32 * 1024;

impl CandidateQueue {
    pub(super) fn from(entries: Vec<Entry>) -> Self {
        CandidateQueue {
            heap: Vec::new(),
            overflow: entries,
            threshold: None,
        }
    }

    pub(super) fn push(&mut self, entry: Entry) {
        match self.threshold {
            Some(t) if entry <= t => self.push_heap(entry),
            _ => self.overflow.push(entry),
        }
    }

    /// The cheapest entry; `live` tells which overflow entries are still worth keeping when
    /// the heap is refilled (entries it rejects are dropped unseen).
    pub(super) fn pop(&mut self, live: impl Fn(&Entry) -> bool) -> Option<Entry> {
        if self.heap.is_empty() {
            self.refill(live);
        }
        self.pop_heap()
    }

    pub(super) fn refill(&mut self, live: impl Fn(&Entry) -> bool) {
        self.overflow.retain(|e| live(e));
        if self.overflow.is_empty() {
            return;
        }
        let m = REFILL.min(self.overflow.len());
        let (_, &mut pivot, _) = self.overflow.select_nth_unstable(m - 1);
        self.threshold = Some(pivot);
        self.heap.extend(self.overflow.drain(..m));
        // A sorted array is a valid heap.
        self.heap.sort_unstable();
    }

    pub(super) fn push_heap(&mut self, entry: Entry) {
        let mut i = self.heap.len();
        self.heap.push(entry);
        while i > 0 {
            let parent = (i - 1) / 4;
            if self.heap[parent] <= entry {
                break;
            }
            self.heap[i] = self.heap[parent];
            i = parent;
        }
        self.heap[i] = entry;
    }

    pub(super) fn pop_heap(&mut self) -> Option<Entry> {
        let last = self.heap.pop()?;
        let Some(&top) = self.heap.first() else {
            return Some(last);
        };
        // Sift the last entry down from the root along the smallest children.
        let n = self.heap.len();
        let mut i = 0;
        loop {
            let first = 4 * i + 1;
            if first >= n {
                break;
            }
            let mut child = first;
            for c in first + 1..(first + 4).min(n) {
                if self.heap[c] < self.heap[child] {
                    child = c;
                }
            }
            if self.heap[child] >= last {
                break;
            }
            self.heap[i] = self.heap[child];
            i = child;
        }
        self.heap[i] = last;
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queue_pops_in_order_across_refills() {
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as u32
        };
        let entry = |cost: u32, u: u32| Entry {
            cost,
            u,
            v: u + 1,
            stamp: 0,
        };
        // More than two refills' worth. Entries with u % 7 == 3 count as stale: the queue
        // drops them when they pass through a refill, which every initial entry does.
        // Pushed entries (some below, some above the threshold) are all live.
        let entries: Vec<Entry> = (0..3 * REFILL as u32).map(|i| entry(next(), i)).collect();
        let mut reference = std::collections::BinaryHeap::new();
        reference.extend(entries.iter().map(|&e| std::cmp::Reverse(e)));
        let mut queue = CandidateQueue::from(entries);
        let live = |e: &Entry| e.u % 7 != 3;
        let mut popped = 0;
        while let Some(e) = queue.pop(live) {
            let expected = loop {
                let std::cmp::Reverse(r) = reference.pop().unwrap();
                if live(&r) {
                    break r;
                }
            };
            assert_eq!(e, expected);
            popped += 1;
            if popped % 3 == 0 {
                let extra = entry(e.cost + next() % 5000, 7 * (1_000_000 + popped));
                queue.push(extra);
                reference.push(std::cmp::Reverse(extra));
            }
        }
        assert!(reference.iter().all(|r| !live(&r.0)));
        assert!(popped > 2 * REFILL as u32);
    }
}
