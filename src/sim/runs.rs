//! Short runs of `u32` slots, one run per owner (a sphere's list entries),
//! all runs the same capacity in one array: an owner's run is a contiguous slice, a push and a
//! swap-remove are O(1), and a full run makes every run one slot longer (a copy of every run,
//! once for each new longest length: the capacity is the longest run's).

/// Slots after the last run, so that its read in groups of four (`in_fours`) stays inside.
const PAD: usize = 3;

/// The runs and their lengths.
#[derive(Debug, Clone)]
pub(crate) struct Runs {
    cap: usize,
    count: Vec<u32>,
    slots: Vec<u32>,
}

impl Runs {
    /// `owners` empty runs of `cap` slots.
    pub fn new(owners: usize, cap: usize) -> Self {
        Self {
            cap,
            count: super::pages::filled(0, owners),
            slots: super::pages::filled(0, owners * cap + PAD),
        }
    }

    /// Owner `o`'s run.
    #[inline(always)]
    pub fn of(&self, o: usize) -> &[u32] {
        let start = o * self.cap;
        &self.slots[start..start + self.count[o] as usize]
    }

    /// Owner `o`'s run read in whole groups of four (the slots past its end belong to it,
    /// to the next owner or to the padding: each holds a value once written, or zero), and
    /// its length.
    #[inline(always)]
    pub fn in_fours(&self, o: usize) -> (&[u32], usize) {
        let start = o * self.cap;
        let len = self.count[o] as usize;
        (&self.slots[start..start + len.next_multiple_of(4)], len)
    }

    /// Owner `o`'s slots, used or not (where its run will be read).
    #[inline(always)]
    pub fn room(&self, o: usize) -> &[u32] {
        let start = o * self.cap;
        &self.slots[start..start + self.cap]
    }

    /// Appends `v` to owner `o`'s run; returns its slot in the run.
    #[inline]
    pub fn push(&mut self, o: usize, v: u32) -> usize {
        let k = self.count[o] as usize;
        if k == self.cap {
            self.grow();
        }
        self.slots[o * self.cap + k] = v;
        self.count[o] += 1;
        k
    }

    /// Makes owner `o`'s run `values` (growing every run first if it is longer than they are).
    #[inline]
    pub fn set(&mut self, o: usize, values: &[u32]) {
        while values.len() > self.cap {
            self.grow();
        }
        let start = o * self.cap;
        self.slots[start..start + values.len()].copy_from_slice(values);
        self.count[o] = values.len() as u32;
    }

    /// Removes slot `k` of owner `o`'s run; the run's last value moves into it and is
    /// returned (`None` when `k` was the last).
    #[inline]
    pub fn swap_remove(&mut self, o: usize, k: usize) -> Option<u32> {
        let start = o * self.cap;
        let last = self.count[o] as usize - 1;
        self.count[o] -= 1;
        (k != last).then(|| {
            let moved = self.slots[start + last];
            self.slots[start + k] = moved;
            moved
        })
    }

    /// Removes value `v` from owner `o`'s run, if it is there (its first slot).
    #[inline]
    pub fn remove_value(&mut self, o: usize, v: u32) {
        if let Some(k) = self.of(o).iter().position(|&x| x == v) {
            self.swap_remove(o, k);
        }
    }

    /// Empties owner `o`'s run.
    #[inline]
    pub fn clear(&mut self, o: usize) {
        self.count[o] = 0;
    }

    /// New owner `new` takes old owner `order[new]`'s run, each value mapped by `map`.
    pub fn permute(&mut self, order: &[u32], map: impl Fn(u32) -> u32) {
        let mut slots = super::pages::filled(0u32, self.slots.len());
        let mut count = super::pages::filled(0u32, self.count.len());
        for (new, &old) in order.iter().enumerate() {
            let run = self.of(old as usize);
            count[new] = run.len() as u32;
            for (slot, &v) in slots[new * self.cap..].iter_mut().zip(run) {
                *slot = map(v);
            }
        }
        (self.slots, self.count) = (slots, count);
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        (self.slots.capacity() + self.count.capacity()) * 4
    }

    /// One more slot for every run (the runs keep their values): the capacity is the longest
    /// run's.
    #[cold]
    fn grow(&mut self) {
        let cap = self.cap + 1;
        let mut slots = super::pages::filled(0u32, self.count.len() * cap + PAD);
        for (o, &c) in self.count.iter().enumerate() {
            let c = c as usize;
            slots[o * cap..o * cap + c]
                .copy_from_slice(&self.slots[o * self.cap..o * self.cap + c]);
        }
        self.slots = slots;
        self.cap = cap;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_push_remove_grow_and_permute() {
        let mut r = Runs::new(3, 2);
        for v in 0..11 {
            assert_eq!(r.push(1, v), v as usize);
        }
        r.push(0, 100);
        assert_eq!(r.of(1), (0..11).collect::<Vec<_>>());
        // The last value fills the hole; removing the last moves nothing.
        assert_eq!(r.swap_remove(1, 3), Some(10));
        assert_eq!(r.swap_remove(1, 9), None);
        assert_eq!(r.of(1), [0, 1, 2, 10, 4, 5, 6, 7, 8]);
        r.remove_value(1, 5);
        r.remove_value(1, 42);
        assert_eq!(r.of(1), [0, 1, 2, 10, 4, 8, 6, 7]);
        assert_eq!(r.of(0), [100]);
        r.permute(&[2, 0, 1], |v| v + 1);
        assert!(r.of(0).is_empty());
        assert_eq!(r.of(1), [101]);
        assert_eq!(r.of(2), [1, 2, 3, 11, 5, 9, 7, 8]);
        r.clear(2);
        assert!(r.of(2).is_empty());
    }

    /// A run read in groups of four holds the run first, then slots that were written or are
    /// zero, and the last owner's read stays inside the slots, also after growing and
    /// renumbering.
    #[test]
    fn a_run_read_in_fours_is_the_run_then_written_or_zero_slots() {
        let mut r = Runs::new(3, 3);
        for v in 1..=3 {
            r.push(2, v);
        }
        r.push(1, 7);
        let (four, len) = r.in_fours(2);
        assert_eq!((four, len), (&[1, 2, 3, 0][..], 3));
        let (four, len) = r.in_fours(1);
        assert_eq!((four, len), (&[7, 0, 0, 1][..], 1));
        assert_eq!(r.in_fours(0), (&[][..], 0));
        r.push(2, 4);
        r.push(2, 5);
        assert_eq!(r.in_fours(2), (&[1, 2, 3, 4, 5, 0, 0, 0][..], 5));
        r.remove_value(2, 5);
        assert_eq!(r.in_fours(2), (&[1, 2, 3, 4][..], 4));
        r.permute(&[2, 1, 0], |v| v);
        assert_eq!(r.in_fours(2), (&[][..], 0));
        assert_eq!(r.in_fours(0).1, 4);
    }

    #[test]
    fn a_run_set_longer_than_the_capacity_grows_them_all_and_keeps_the_others() {
        let mut r = Runs::new(3, 2);
        r.push(0, 5);
        r.push(2, 6);
        r.push(2, 7);
        let long: Vec<u32> = (10..17).collect();
        r.set(1, &long);
        assert_eq!(r.of(1), &long[..]);
        assert_eq!((r.of(0), r.of(2)), (&[5][..], &[6, 7][..]));
        // A shorter set replaces the run, it does not append.
        r.set(1, &[3]);
        assert_eq!(r.of(1), [3]);
        r.set(1, &[]);
        assert!(r.of(1).is_empty());
    }
}
