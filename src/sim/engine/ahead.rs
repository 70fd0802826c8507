//! Fetching ahead: while an event runs, the caches are asked for the records of the sphere
//! whose event most likely comes next (the calendar's hint), so that at N = 10⁵, where each
//! is a miss to memory, they arrive while this event's work goes on instead of stalling the
//! next one (docs/benchmarks.md, "Fetching ahead"). A wrong hint costs a few loads.

use super::*;

/// From how many spheres each event also asks for the next sphere's neighbours' bodies and
/// its partner's records (`fetch_next_neighbours`): at N = 32 000, φ = 0.25 (9 MB of records)
/// that cost 4.5 % (its instructions; the lines were in the caches already), at
/// N = 108 000 (32 MB, this machine's whole L3) it gained 7 % (docs/benchmarks.md).
#[cfg(not(test))]
pub(super) const FETCH_NEIGHBOURS_FROM: usize = 64_000;
/// In tests, from 64 spheres: the gases of the brute-force checks run it, the smallest
/// scenes do not.
#[cfg(test)]
pub(super) const FETCH_NEIGHBOURS_FROM: usize = 64;

/// Asks for every cache line of `x`, without waiting for them.
#[inline(always)]
fn prefetch<T>(x: &T) {
    prefetch_bytes((x as *const T).cast(), std::mem::size_of::<T>());
}

/// Asks for every cache line of the `len` bytes from `first`, without waiting for them.
#[inline(always)]
fn prefetch_bytes(first: *const i8, len: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let mut at = 0;
        while at < len.next_multiple_of(64) {
            // SAFETY: a prefetch reads nothing the program sees and cannot fault, whatever
            // the address (and this one is within or one line past a live object).
            unsafe { _mm_prefetch::<_MM_HINT_T0>(first.wrapping_add(at.min(len - 1))) };
            at += 64;
        }
    }
}

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Asks for the prediction, body and list of the sphere whose event most likely
    /// comes next.
    #[inline(always)]
    pub(super) fn fetch_next(&self) {
        let Some(next) = self.queue.likely_next() else {
            return;
        };
        let n = next as usize;
        if n < self.best.len() {
            prefetch(&self.best[n]);
            prefetch(&self.m.bodies[n]);
            let room = self.lists.room(next);
            prefetch_bytes(room.as_ptr().cast(), std::mem::size_of_val(room));
        }
    }

    /// Once `fetch_next`'s lines have most likely come: the bodies of that sphere's list
    /// entries, and the records of its likely partner.
    #[inline(always)]
    pub(super) fn fetch_next_neighbours(&self) {
        let Some(next) = self.queue.likely_next() else {
            return;
        };
        let n = next as usize;
        if n >= self.best.len() {
            return;
        }
        for &e in self.lists.of(next) {
            if let Some(b) = self.m.bodies.get((e >> lists::CODE_BITS) as usize) {
                prefetch(b);
            }
        }
        let j = self.best[n].pairs[0].j as usize;
        if j < self.best.len() {
            prefetch(&self.best[j]);
            prefetch(&self.m.bodies[j]);
            let room = self.lists.room(j as u32);
            prefetch_bytes(room.as_ptr().cast(), std::mem::size_of_val(room));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fetching ahead changes nothing the program sees, for any length, empty or not
    /// aligned, at the end of an allocation, and for a hint naming no sphere.
    #[test]
    fn prefetching_reads_nothing_and_any_length_is_fine() {
        let bytes: Vec<u8> = (0..=255).collect();
        for len in [0, 1, 63, 64, 65, 200] {
            for at in [0, 1, 255 - len.min(255)] {
                let s = &bytes[at..(at + len).min(256)];
                prefetch_bytes(s.as_ptr().cast(), s.len());
            }
        }
        prefetch(&bytes[255]);
        prefetch(&());
        assert!(bytes.iter().enumerate().all(|(k, &b)| b as usize == k));
    }
}
