//! The event calendar: a bucket (calendar) queue of `(time, sphere, version)` entries with
//! lazy deletion. A sphere has one pending event; re-predicting it bumps its version, and the
//! older entry is dropped when it surfaces (the engine compares versions), so no entry is ever
//! searched for or removed.
//!
//! Buckets of width `w` cover one "year" of `nb · w` ahead of the current bucket; entries beyond
//! it wait in an overflow list and are distributed when a new year starts. The current bucket
//! is a binary min-heap, so events leave in exact `(time, sphere)` order whatever the width: the
//! width only sets the cost (about a few entries per bucket is best).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// One scheduled event: when, whose, and which of its predictions.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Entry {
    pub t: f64,
    pub sphere: u32,
    pub version: u32,
}

impl PartialEq for Entry {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Entry {
    /// Reversed, so that `BinaryHeap` pops the earliest: time, then sphere, then version.
    fn cmp(&self, o: &Self) -> Ordering {
        o.t.total_cmp(&self.t)
            .then(o.sphere.cmp(&self.sphere))
            .then(o.version.cmp(&self.version))
    }
}

/// A calendar queue over non-negative, finite times.
#[derive(Debug, Clone)]
pub(crate) struct Calendar {
    inv_width: f64,
    buckets: Vec<Vec<Entry>>,
    mask: u64,
    /// Absolute index of the bucket the heap holds.
    current: u64,
    heap: BinaryHeap<Entry>,
    far: Vec<Entry>,
    len: usize,
}

impl Calendar {
    /// A calendar of `buckets` (rounded up to a power of two) buckets of `width`, starting at
    /// time `t0`.
    pub fn new(width: f64, buckets: usize, t0: f64) -> Self {
        let nb = buckets.max(2).next_power_of_two();
        let inv_width = 1.0 / width;
        Self {
            inv_width,
            buckets: vec![Vec::new(); nb],
            mask: nb as u64 - 1,
            current: (t0 * inv_width) as u64,
            heap: BinaryHeap::new(),
            far: Vec::new(),
            len: 0,
        }
    }

    /// Number of entries, stale ones included.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.len
    }

    #[inline]
    fn bucket_of(&self, t: f64) -> u64 {
        // Saturating float-to-int cast: +∞ and huge times land in the overflow list.
        (t * self.inv_width) as u64
    }

    /// Bytes the calendar holds (buckets, heap, overflow).
    pub fn bytes(&self) -> usize {
        let e = std::mem::size_of::<Entry>();
        self.buckets.capacity() * std::mem::size_of::<Vec<Entry>>()
            + self.buckets.iter().map(Vec::capacity).sum::<usize>() * e
            + (self.heap.capacity() + self.far.capacity()) * e
    }

    /// Schedules an entry (its time must not precede the last popped one).
    #[inline]
    pub fn push(&mut self, e: Entry) {
        self.len += 1;
        let k = self.bucket_of(e.t);
        if k <= self.current {
            self.heap.push(e);
        } else if k - self.current <= self.mask {
            self.buckets[(k & self.mask) as usize].push(e);
        } else {
            self.far.push(e);
        }
    }

    /// The earliest entry, removed.
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        loop {
            if let Some(e) = self.heap.pop() {
                self.len -= 1;
                return Some(e);
            }
            if self.len == 0 {
                return None;
            }
            self.advance();
        }
    }

    /// Moves to the next bucket, with the heap empty. Overflow entries move into the ring at
    /// each new year; when nothing but overflow is left, the calendar jumps to its earliest.
    fn advance(&mut self) {
        if self.far.len() == self.len {
            let first = self.far.iter().map(|e| self.bucket_of(e.t)).min();
            self.current = first.unwrap_or(self.current).saturating_sub(1);
            self.refill_from_far();
        }
        self.current += 1;
        if self.current & self.mask == 0 && !self.far.is_empty() {
            self.refill_from_far();
        }
        let b = &mut self.buckets[(self.current & self.mask) as usize];
        if !b.is_empty() {
            // The heap is empty: it takes the bucket's entries, the bucket the heap's buffer.
            let mut taken = BinaryHeap::from(std::mem::take(b));
            std::mem::swap(&mut taken, &mut self.heap);
            *b = taken.into_vec();
        }
    }

    /// Moves the overflow entries that now fall within a year of the current bucket into the
    /// ring (every overflow entry lies after the current bucket: it was beyond a year when
    /// pushed, and this runs at least once a year).
    #[cold]
    fn refill_from_far(&mut self) {
        let far = std::mem::take(&mut self.far);
        for e in far {
            let k = self.bucket_of(e.t);
            if k - self.current <= self.mask {
                self.buckets[(k & self.mask) as usize].push(e);
            } else {
                self.far.push(e);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// Entries leave in exact (time, sphere) order whatever the width, including times far
    /// beyond one year, equal times and +∞.
    #[test]
    fn pops_in_order_for_any_width() {
        for &width in &[1e-3, 0.1, 1.0, 50.0] {
            let mut rng = Rng::new(7);
            let mut q = Calendar::new(width, 16, 0.0);
            let mut now = 0.0;
            let mut expected: Vec<(f64, u32)> = Vec::new();
            let mut popped = Vec::new();
            for step in 1..4000u32 {
                let t = match step % 97 {
                    0 => f64::INFINITY,
                    1 => now,
                    2 => now + 1e4 * rng.unit(),
                    _ => now + rng.unit(),
                };
                q.push(Entry {
                    t,
                    sphere: step,
                    version: 0,
                });
                expected.push((t, step));
                if step % 3 == 0 {
                    let e = q.pop().unwrap();
                    assert!(e.t >= now, "time went back: {} < {now}", e.t);
                    now = e.t.min(1e12);
                    popped.push((e.t, e.sphere));
                }
            }
            while let Some(e) = q.pop() {
                popped.push((e.t, e.sphere));
            }
            assert_eq!(q.len(), 0);
            // Every entry comes out once, and in time order (pushes never precede the last pop).
            if let Some(k) = popped.windows(2).position(|w| w[0].0 > w[1].0) {
                panic!("width {width}: {:?}", &popped[k.saturating_sub(3)..k + 3]);
            }
            let mut all = popped.clone();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            expected.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            assert_eq!(all, expected, "width {width}");
        }
    }
}
