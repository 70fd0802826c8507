//! Fetching ahead: while an event runs, the caches are asked for the records of the sphere
//! whose event most likely comes next (the calendar's hint), so that at N = 10⁵, where each
//! is a miss to memory, they arrive while this event's work goes on instead of stalling the
//! next one (docs/benchmarks.md, "Fetching ahead" and "Fetching the rebuild ahead"). A wrong
//! hint costs a few loads.
//!
//! The stages, each a level of the chain of loads the next event will follow: before an
//! event, the next sphere's own records (`fetch_next`); after it, what those records name —
//! its neighbours' bodies, its partner's records, and the cells its list's rebuild will scan
//! (`fetch_next_neighbours`); at the next event, what those name in turn — the partner's
//! neighbours' bodies (`fetch_partner_neighbours`) and the scanned cells' members' shells
//! (`fetch_gathered_shells`). All but the first run only from `FETCH_NEIGHBOURS_FROM`
//! spheres.

use super::*;

/// From how many spheres each event also asks ahead for the next sphere's neighbours, its
/// partner's records and, before a rebuild, the cells and candidates it reads
/// (`fetch_next_neighbours` and the rest): measured at φ = 0.25 against none of them, it cost
/// 15 % at N = 4000, 9 % at 8000 and 4 % at 16 000 (the lines were in the caches already) and
/// gained 6 % at 32 000 (docs/benchmarks.md, "Fetching the rebuild ahead").
#[cfg(not(test))]
pub(super) const FETCH_NEIGHBOURS_FROM: usize = 24_000;
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
    /// Asks for the prediction, body, list and calendar slot of the sphere whose event most
    /// likely comes next.
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
            self.fetch_calendar_lines(next);
        }
    }

    /// Sphere `i`'s calendar slot, read when its bucket becomes the current one.
    #[inline(always)]
    fn fetch_calendar_lines(&self, i: u32) {
        if let Some(line) = self.queue.lines_of(i) {
            prefetch_bytes(line.cast(), 1);
        }
    }

    /// Once `fetch_next`'s lines have most likely come: the bodies of that sphere's list
    /// entries, the calendar slot of the one after it in its bucket, the records of its likely
    /// partner and, when it is about to leave its shell, the cells its list's rebuild will
    /// read.
    #[inline(always)]
    pub(super) fn fetch_next_neighbours(&self) {
        let Some(next) = self.queue.likely_next() else {
            return;
        };
        let n = next as usize;
        if n >= self.best.len() {
            return;
        }
        self.fetch_list_bodies(next);
        if let Some(after) = self.queue.linked_after(next) {
            self.fetch_calendar_lines(after);
        }
        let best = &self.best[n];
        if best.next_event() == NextEvent::Shell {
            self.fetch_cells_at(n, best.shell_t);
        }
        let j = best.pairs[0].j as usize;
        if j < self.best.len() {
            prefetch(&self.best[j]);
            prefetch(&self.m.bodies[j]);
            let room = self.lists.room(j as u32);
            prefetch_bytes(room.as_ptr().cast(), std::mem::size_of_val(room));
        }
    }

    /// Before sphere `i`'s event: when it is a collision, the bodies of the partner's list
    /// entries (its records were asked for by the event before), which its prediction reads
    /// after `i`'s.
    #[inline(always)]
    pub(super) fn fetch_partner_neighbours(&self, i: u32) {
        let Some(best) = self.best.get(i as usize) else {
            return;
        };
        if best.next_event() == NextEvent::Pair && (best.pairs[0].j as usize) < self.best.len() {
            self.fetch_list_bodies(best.pairs[0].j);
        }
    }

    /// The bodies of sphere `i`'s list entries, which its prediction reads.
    #[inline(always)]
    fn fetch_list_bodies(&self, i: u32) {
        for &e in self.lists.of(i) {
            if let Some(b) = self.m.bodies.get(lists::split(e).0 as usize) {
                prefetch(b);
            }
        }
    }

    /// The shells of the first `len` candidates `cells_near` gathered, asked for in one tight
    /// loop so that they come together rather than a few at a time as `within_reach`'s longer
    /// loop reaches them.
    #[inline(always)]
    pub(super) fn fetch_gathered_shells(&self, len: usize) {
        for &e in &self.gathered[..len] {
            if let Some(shell) = self.lists.centre.get(lists::split(e).0 as usize) {
                prefetch(shell);
            }
        }
    }

    /// The records of the 27 cells around where sphere `n` will be at time `t`, which a
    /// rebuild of its list then reads.
    #[inline(always)]
    fn fetch_cells_at(&self, n: usize, t: f64) {
        let (r, _) = self.m.bodies[n].at(t, self.m.g);
        let r = super::wrapped::<PERIODIC>(&self.cells, r);
        let [x, y, z] = self.stencil.cell_parts(self.cells.coords_of(r));
        let records = self.cells.records();
        for pz in z {
            for py in y {
                for px in x {
                    if let Some(record) = records.get(pz + py + px) {
                        prefetch(record);
                    }
                }
            }
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
