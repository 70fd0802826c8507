//! Sphere `i`'s neighbours: its list rebuilt from the cells around its shell centre at its
//! shell event (`rebuild_list`, `within_reach`), and its contacts with them predicted in f64,
//! four at a time; the two earliest are kept (`predict_pairs`). A prediction screens its list
//! four entries at a time (`screen`) and answers only the approaching pairs that can meet
//! before the sphere's shell event (`answer`): three in five of the others, at φ = 0.4, would
//! be overtaken by that event (rule 6 of docs/derivations/simulation.md).
//!
//! The loops that load other spheres' records have no branch on what they load: a random
//! branch (is this pair approaching? how many spheres has this cell?) is mispredicted about
//! half the time, and each miss throws away the loads in flight. So each stage is two
//! passes: one that loads everything and writes what passes into a scratch array by an index
//! it advances by the test's outcome, then one over what passed (docs/benchmarks.md,
//! "Loops without data branches"). The tests and answers then take four candidates at a time
//! in `f64x4` lanes ("Fewer instructions around the same events").
//!
//! **Every lane names a sphere.** The passes read whole groups of four, past the entries they
//! count, and load the sphere each lane names without a bounds check (`named`, from `relative`
//! and the rebuild's load of a shell centre). This holds because every `u32` in the engine's cell
//! records, list slots (a list is read in groups of four, past its end: `Runs::in_fours`),
//! `fresh`, `gathered` and `near` is a sphere index below `n` (with a shift code), or
//! zero (sphere 0, with `n ≥ 1` whenever a pass runs): they are written only from the
//! indices `0..n` the cells are filled with (`Engine::new`, `reorder`, a checkpoint's
//! `rebuild`), from each other, and from the zeros they start as; renumbering maps indices
//! below `n` to indices below `n`, and the count is never changed. Every test build checks it
//! at each load (`debug_assert`).

use wide::{f64x4, u32x4, u32x8};

use super::lists::{Before, CODE_BITS, NO_SHIFT, Quotient, Shell, entry, mirror, split};
use super::*;
use crate::sim::cells::HEAD;
use crate::sim::predict::{Kept, arrivals};

/// A neighbour's relative motion from now, as a prediction's passes compute it (`relative`):
/// `r0` and `v` in the first three lanes, the contact distance in the fourth lane of `v`.
#[derive(Debug, Clone, Copy)]
struct Approach {
    r0: f64x4,
    v: f64x4,
    j: u32,
}

/// How many list entries a prediction's first pass wrote to `near` (the pairs to answer), and
/// whether it left out any that cannot meet within its horizon.
struct Screened {
    near: usize,
    beyond: bool,
}

/// Whether the pair is already in contact (a contact is reported once).
fn touching<R: Responder>(responder: &R, i: u32, a: &Approach) -> bool {
    let d = a.v.to_array()[3];
    let (q, d2) = (xyz(a.r0).length_squared(), d * d);
    q < d2 * (1.0 - 1e-9) || responder.touching(i, a.j) && q <= d2 * (1.0 + 1e-9)
}

/// A sphere's body at now as `own_lanes` gives it.
type Own = (f64x4, f64x4);

/// Sphere `i`'s body as lanes of four, its velocity's fourth lane negated: the relative
/// velocity's fourth lane is then the radii's sum, `radiusⱼ − (−radiusᵢ)`, the contact
/// distance, to the bit `radiusᵢ + radiusⱼ` (the sign flip is exact).
#[inline(always)]
fn own_lanes(b: &Trajectory) -> Own {
    let (r, v) = lanes(b);
    (r, v * f64x4::new([1.0, 1.0, 1.0, -1.0]))
}

/// List entry `e`'s motion relative to sphere `i` (`own`, from `own_lanes`) from `now`,
/// lane by lane the same operations, in the same order, as on `DVec3`: the same bits. The
/// fourth lanes carry, in `r0`, `(tⱼ − tᵢ) + radiusⱼ·dt` (unused), and in `v` the contact
/// distance.
///
/// # Safety
///
/// `e` names a sphere: `split(e).0 < bodies.len()` (the module's "Every lane names a
/// sphere"). The bounds check this spares was 5 % of the gas's instructions and 2 % of its
/// time (docs/benchmarks.md, "Unchecked loads"); `debug_assert` keeps it in tests.
#[inline(always)]
unsafe fn relative<const GRAVITY: bool>(
    bodies: &[Trajectory],
    shift: &ShiftLanes,
    (ri, vi): (f64x4, f64x4),
    now: f64,
    g: f64x4,
    e: u32,
) -> Approach {
    let (j, code) = split(e);
    // SAFETY: the caller's promise.
    let bj = unsafe { named(bodies, j) };
    let dt = now - bj.t;
    let (rj, vj) = lanes(bj);
    let mut r0 = (rj - ri) + shift[usize::from(code)] + vj * f64x4::splat(dt);
    let mut v = vj - vi;
    if GRAVITY {
        // Both fall alike: their relative motion from now on is a straight line.
        r0 += g * f64x4::splat(0.5 * dt * dt);
        v += g * f64x4::splat(dt);
    }
    Approach { r0, v, j }
}

/// Sphere `j`'s record in a per-sphere array, loaded without a bounds check: the passes' one
/// unchecked load, and the check every test build makes of it.
///
/// # Safety
///
/// `j < items.len()` (the module's "Every lane names a sphere").
#[inline(always)]
unsafe fn named<T>(items: &[T], j: u32) -> &T {
    debug_assert!(
        (j as usize) < items.len(),
        "sphere {j} of {}: the lane names no sphere",
        items.len()
    );
    // SAFETY: the caller's promise.
    unsafe { items.get_unchecked(j as usize) }
}

/// The periodic shift of each list entry's code in lanes of four, the fourth zero.
pub(super) type ShiftLanes = [f64x4; super::lists::SHIFT_ROWS];

/// The shift table in lanes of four.
pub(super) fn shift_lanes(shift: [DVec3; super::lists::SHIFT_ROWS]) -> ShiftLanes {
    shift.map(vector_lanes)
}

/// A vector in lanes of four, the fourth zero.
#[inline(always)]
fn vector_lanes(a: DVec3) -> f64x4 {
    f64x4::new([a.x, a.y, a.z, 0.0])
}

/// A body as two lanes of four, as it lies in memory: centre and time, velocity and radius.
#[inline(always)]
fn lanes(b: &Trajectory) -> (f64x4, f64x4) {
    (
        f64x4::new([b.r.x, b.r.y, b.r.z, b.t]),
        f64x4::new([b.v.x, b.v.y, b.v.z, b.radius]),
    )
}

/// A shell centre and its radius as lanes of four, as they lie in memory.
#[inline(always)]
fn shell_lanes(s: &Shell) -> f64x4 {
    f64x4::new([s.c.x, s.c.y, s.c.z, s.radius])
}

/// The first three lanes as a vector.
#[inline(always)]
fn xyz(l: f64x4) -> DVec3 {
    let a = l.to_array();
    DVec3::new(a[0], a[1], a[2])
}

/// The latest time a merge may keep from a list and its completeness: anything for a complete
/// list; for an incomplete one, no later than its last kept candidate (what it left out is
/// no earlier than that).
#[inline]
fn bound((l, complete): ([Candidate; 2], bool)) -> f64 {
    if complete {
        f64::INFINITY
    } else {
        l.iter()
            .rev()
            .find(|c| c.t.is_finite())
            .map_or(f64::NEG_INFINITY, |c| c.t)
    }
}

/// The two earliest of two sorted candidate lists and whether the result holds every
/// candidate. An incomplete list only bounds what it left out (no earlier than its last kept
/// candidate), so nothing later than that bound may be kept from the other list: it could come
/// after a candidate nobody kept.
#[inline]
pub(super) fn merge(
    a: ([Candidate; 2], bool),
    b: ([Candidate; 2], bool),
) -> ([Candidate; 2], bool) {
    let limit = bound(a).min(bound(b));
    // The two least of the four, kept as they come (no sort) by the prediction's own rule.
    let mut kept = Kept::default();
    for c in [a.0[0], a.0[1], b.0[0], b.0[1]] {
        if c.t.is_finite() && c.t <= limit {
            kept.add(c);
        }
    }
    let (out, complete) = kept.result();
    (out, a.1 && b.1 && complete)
}

impl<
    R: Responder,
    const PERIODIC: bool,
    const WALLS: bool,
    const GEOMETRY: bool,
    const GRAVITY: bool,
> Engine<R, PERIODIC, WALLS, GEOMETRY, GRAVITY>
{
    /// Sphere `i`'s two earliest contacts with the spheres of its list (or only the entries
    /// `fresh` holds, new to it at its shell event), whether there were no others, and whether
    /// approaching pairs that cannot meet within `horizon` from now (its shell event) were
    /// left out: the first pass screens every entry, the second answers the pairs kept.
    #[inline(always)]
    pub(super) fn predict_pairs(
        &mut self,
        i: u32,
        fresh_only: bool,
        horizon: Option<Quotient>,
    ) -> ([Candidate; 2], bool, bool) {
        let own = own_lanes(&self.m.bodies[i as usize]);
        let Screened { near, beyond } = match horizon {
            None => self.screen_all(i, fresh_only, own),
            Some(horizon) => self.screen(i, fresh_only, horizon, own),
        };
        #[cfg(test)]
        {
            self.left_out += u64::from(beyond);
        }
        let mut kept = Kept::default();
        self.answer(&mut kept, near, own);
        let (pairs, complete) = kept.result();
        (pairs, complete, beyond)
    }

    /// The first pass of a prediction with no horizon: every entry's relative motion from
    /// now, one at a time with no branch on what it loads; the approaching ones
    /// (`r0 · v < 0`) go to `near`. Fewer instructions a list entry than `screen`'s two
    /// tests four at a time, and the same `near`.
    fn screen_all(&mut self, i: u32, fresh_only: bool, own: Own) -> Screened {
        let list = if fresh_only {
            &self.fresh[..self.fresh_len]
        } else {
            self.lists.of(i)
        };
        let room = list.len().next_multiple_of(4);
        if self.near.len() < room {
            self.near.resize(room, 0);
        }
        let g = vector_lanes(self.m.g);
        let mut count = 0;
        for &e in list {
            // SAFETY: a list entry names a sphere.
            let a =
                unsafe { relative::<GRAVITY>(&self.m.bodies, &self.shift, own, self.now, g, e) };
            // The same sums as `DVec3::dot`, in the same order.
            let p = (a.r0 * a.v).to_array();
            let mut keep = (p[0] + p[1]) + p[2] < 0.0;
            if R::REPORT_ONLY {
                keep &= !touching(&self.responder, i, &a);
            }
            self.near[count] = e;
            count += usize::from(keep);
        }
        Screened {
            near: count,
            beyond: false,
        }
    }

    /// The first pass of a prediction: every entry's relative motion from now, four entries
    /// at a time, with no branch on what it loads. The approaching ones (`r0 · v < 0`) go to
    /// `near`, except those that cannot meet within `horizon` (`c + 2bτ > 0`, multiplied by
    /// the horizon's denominator: rule 6 of docs/derivations/simulation.md, "Why no collision
    /// is missed"), which are left out and noted (`Screened::beyond`).
    fn screen(&mut self, i: u32, fresh_only: bool, horizon: Quotient, own: Own) -> Screened {
        let (ri, vi) = own;
        let (list, len) = if fresh_only {
            (&self.fresh[..], self.fresh_len)
        } else {
            self.lists.in_fours(i)
        };
        let now = self.now;
        let room = list.len();
        if self.near.len() < room {
            self.near.resize(room, 0);
        }
        let near = &mut self.near;
        let g = vector_lanes(self.m.g);
        let (twice_num, den) = (f64x4::splat(2.0 * horizon.num), f64x4::splat(horizon.den));
        // SAFETY: every lane names a sphere: list entries, the slots after a list, `fresh`'s
        // zeros (the module's doc).
        let motion = |e: u32| unsafe {
            relative::<GRAVITY>(&self.m.bodies, &self.shift, (ri, vi), now, g, e)
        };
        let mut out = Screened {
            near: 0,
            beyond: false,
        };
        // The list is read in whole groups of four: the lanes past its end (slots after it, or
        // `fresh`'s zeros) name spheres and are not counted. No tail is copied.
        for (c, &four) in list.as_chunks::<4>().0.iter().enumerate() {
            let valid = (1u32 << (len - 4 * c).min(4)) - 1;
            let a = [
                motion(four[0]),
                motion(four[1]),
                motion(four[2]),
                motion(four[3]),
            ];
            // The four entries' `b = r0 · v` and `(c + 2bτ) den` at once, in lanes: `b` the
            // same sums as `DVec3::dot`, in the same order (to the bit as before the horizon).
            let [x, y, z, _] = f64x4::transpose([a[0].r0, a[1].r0, a[2].r0, a[3].r0]);
            let [vx, vy, vz, d] = f64x4::transpose([a[0].v, a[1].v, a[2].v, a[3].v]);
            let b = (x * vx + y * vy) + z * vz;
            let c = z.mul_add(z, y.mul_add(y, x * x)) - d * d;
            let e = c.mul_add(den, twice_num * b);
            let mut approaching = b.simd_lt(f64x4::ZERO).to_bitmask() & valid;
            if R::REPORT_ONLY {
                for (k, a) in a.iter().enumerate() {
                    approaching &= !(u32::from(touching(&self.responder, i, a)) << k);
                }
            }
            let late = e.simd_gt(f64x4::ZERO).to_bitmask();
            // The entries kept moved to the front, in order, and written at once (all four:
            // the next group overwrites those not kept; `near` has room for the list rounded
            // up, and a pass writes no more than it reads).
            let keep = approaching & !late;
            let packed = u32x4::new(four).shuffle(KEPT_FIRST[keep as usize & 15]);
            near[out.near..out.near + 4].copy_from_slice(packed.as_array());
            out.near += keep.count_ones() as usize;
            out.beyond |= approaching & late != 0;
        }
        out
    }

    /// The second pass: the first `count` entries of `near` answered four at a time, their
    /// relative motion computed again as the first pass did (`own` the sphere's, the same
    /// bits) and transposed into the kernel's lanes, into `kept` (`near` has room past the
    /// last, each lane naming a sphere; the lanes past it are not counted). Computing it
    /// again costs less than the first pass writing each pair's 96-byte motion for this one.
    #[inline(always)]
    fn answer(&mut self, kept: &mut Kept, count: usize, own: Own) {
        let now = self.now;
        let g = vector_lanes(self.m.g);
        for (at, four) in self.near[..count.next_multiple_of(4)]
            .as_chunks::<4>()
            .0
            .iter()
            .enumerate()
        {
            // SAFETY: every lane of `near` names a sphere (the module's doc).
            let motion = |e: u32| unsafe {
                relative::<GRAVITY>(&self.m.bodies, &self.shift, own, now, g, e)
            };
            let a = [
                motion(four[0]),
                motion(four[1]),
                motion(four[2]),
                motion(four[3]),
            ];
            let (t, finite) = arrivals(
                [a[0].r0, a[1].r0, a[2].r0, a[3].r0],
                [a[0].v, a[1].v, a[2].v, a[3].v],
            );
            let mut hits = finite & ((1 << (count - 4 * at).min(4)) - 1);
            while hits != 0 {
                let k = hits.trailing_zeros() as usize;
                hits &= hits - 1;
                let j = a[k].j;
                kept.add(Candidate {
                    t: now + t[k],
                    j,
                    counter: self.m.counter[j as usize],
                });
            }
        }
        self.stats.kernels.sphere += count as u64;
    }

    /// Sphere `i`'s new list after its shell event (its centre already moved, into cell
    /// `ci`): every sphere whose centre is within reach. An entry of both the old and the new
    /// list stays where it is in the other sphere's list; a new one is added to it, and an old
    /// one not kept is removed from it. The entries naming a sphere that was not in the old
    /// list go into `fresh` when `track_fresh` (a box of fewer than three cells a side
    /// predicts the whole list and skips it).
    pub(super) fn rebuild_list(&mut self, i: u32, ci: [i32; 3], track_fresh: bool) {
        self.lists.next_epoch();
        let mut old = std::mem::take(&mut self.old);
        old.clear();
        old.extend_from_slice(self.lists.of(i));
        for &e in &old {
            self.lists.mark_old(e);
        }
        let found = self.within_reach(i, ci);
        self.fresh.clear();
        for k in 0..found {
            let e = self.found[k];
            let before = self.lists.match_new(e);
            if before != Before::Same {
                let (j, code) = split(e);
                self.lists.push(j, entry(i, mirror(code)));
            }
            if track_fresh && before == Before::Absent {
                self.fresh.push(e);
            }
        }
        self.fresh_len = self.fresh.len();
        self.fresh.extend_from_slice(&[0; 3]);
        self.fresh.truncate(self.fresh_len.next_multiple_of(4));
        for &e in &old {
            if !self.lists.was_kept(e) {
                let (j, code) = split(e);
                self.lists.remove(j, entry(i, mirror(code)));
            }
        }
        self.old = old;
        self.lists.set(i, &self.found[..found]);
    }

    /// Builds every list from the centres alone (at the start and after loading a
    /// checkpoint): the same lists the shell events keep, since the test is symmetric.
    pub(super) fn build_lists(&mut self) {
        for i in 0..self.m.bodies.len() as u32 {
            self.lists.clear(i);
            let ci = self.cells.coords_of(self.lists.centre[i as usize].c);
            let found = self.within_reach(i, ci);
            for k in 0..found {
                self.lists.push(i, self.found[k]);
            }
        }
    }

    /// Every sphere `j ≠ i` (with its image's shift code) whose shell centre is within
    /// `dᵢⱼ + reach` of `i`'s, from the 27 cells around `i`'s, into the first entries of
    /// `found`; returns how many. The test
    /// computes `(cⱼ − cᵢ) + shift`, the exact negative of what `j` computes for `i`, so the
    /// lists are symmetric to the bit. Two passes with no branch on the data: the entries of
    /// the 27 cells are copied out (`cells_near`), then each is tested, in lanes of four.
    fn within_reach(&mut self, i: u32, ci: [i32; 3]) -> usize {
        let candidates = self.cells_near(i, ci);
        if self.fetch_neighbours {
            self.fetch_gathered_shells(candidates);
        }
        let centre = &self.lists.centre[..];
        let si = centre[i as usize];
        // Lane by lane the operations of `(cⱼ − cᵢ) + shift` on vectors, in the same order:
        // the fourth lane is `radiusⱼ − (−radiusᵢ)`, to the bit `radiusᵢ + radiusⱼ` (and the
        // shift's fourth lane is zero).
        let ci_lanes = f64x4::new([si.c.x, si.c.y, si.c.z, -si.radius]);
        let reach = f64x4::splat(self.lists.reach);
        let own = entry(i, NO_SHIFT);
        // Four candidates at a time: `gathered` has room past the last (`cells_near`); the
        // lanes past it are read and their spheres' centres loaded, so each names a sphere
        // (`cells_near`), but they are not counted.
        let rounded = candidates.next_multiple_of(4);
        let mut found = std::mem::take(&mut self.found);
        if found.len() < rounded {
            found.resize(rounded, 0);
        }
        // Sphere `i` is there once, under the code of no shift, and is not counted. Its
        // images are a box length away, and a periodic box is at least three largest
        // diameters (`assemble.rs`), more than `2rᵢ + reach` (at most 2.9 diameters, and the
        // margins: `PERIODIC_SHELL_CAP`); an open domain has no images.
        let mut len = 0;
        for (at, four) in self.gathered[..rounded]
            .as_chunks::<4>()
            .0
            .iter()
            .enumerate()
        {
            let relative = |k: usize| {
                let (j, code) = split(four[k]);
                // SAFETY: every lane of `gathered` names a sphere (the module's doc).
                let cj = unsafe { named(centre, j) };
                (shell_lanes(cj) - ci_lanes) + self.shift[usize::from(code)]
            };
            let dr = [relative(0), relative(1), relative(2), relative(3)];
            // The same sums as `DVec3::length_squared`, four pairs at once.
            let [x, y, z, sum] = f64x4::transpose(dr);
            let d = sum + reach;
            let within = (x * x + y * y + z * z).simd_le(d * d).to_bitmask();
            let own_lane = u32x4::new(*four).simd_eq(u32x4::splat(own)).to_bitmask();
            let within = within & !own_lane & ((1 << (candidates - 4 * at).min(4)) - 1);
            // The entries kept moved to the front, in order, and written at once.
            let packed = u32x4::new(*four).shuffle(KEPT_FIRST[within as usize & 15]);
            found[len..len + 4].copy_from_slice(packed.as_array());
            len += within.count_ones() as usize;
        }
        self.found = found;
        len
    }

    /// Copies the members of the 27 cells around sphere `i`'s shell centre (in cell `ci`)
    /// into `gathered` as list entries (with their image's shift code); returns how many. A cell
    /// that cannot hold a centre within reach is copied too, but not counted (the next copy
    /// overwrites it): a cell's whole record is copied whatever it holds, so the loop has no
    /// branch on the cells' contents. Every lane copied names a sphere (the count's lane is
    /// copied as sphere 0): the last copy stays past the entries counted, where `within_reach`
    /// reads it. The rare members past a record's seventh go after the rest.
    fn cells_near(&mut self, i: u32, ci: [i32; 3]) -> usize {
        if self.gathered.len() < GATHER_ROOM {
            self.gathered.resize(GATHER_ROOM, 0);
        }
        let si = self.lists.centre[i as usize];
        let far = self.lists.far * self.lists.far;
        let Stencil {
            axes: [ax, ay, az],
            gap,
        } = self.stencil.around(&self.cells, ci, si.c);
        let (cells, spilled) = (&self.cells, &mut self.spilled);
        let records = cells.records();
        spilled.clear();
        let head: &mut [u32; GATHER_ROOM] = (&mut self.gathered[..GATHER_ROOM])
            .try_into()
            .expect("the gathered entries have their room");
        let mut len = 0;
        for z in 0..3 {
            for y in 0..3 {
                // What a row's three cells share.
                let row = az.part[z] + ay.part[y];
                let row_code = az.code[z] + ay.code[y];
                let row_gap = gap[2][z] + gap[1][y];
                let row_inside = az.inside[z] & ay.inside[y];
                for (x, gap_x) in gap[0].into_iter().enumerate() {
                    // A cell beyond an open domain's edge, or farther than the widest reach,
                    // holds nobody within reach: its copy (of cell 0 instead, beyond an edge)
                    // is not counted.
                    let near = row_inside & ax.inside[x] & (row_gap + gap_x <= far);
                    let code = row_code + ax.code[x];
                    let cell = row + ax.part[x];
                    let record = &records[cell];
                    // The record's eight lanes as entries (`entry`, lane by lane), at once;
                    // `len` is at most 26 records' worth, so the mask changes nothing and
                    // spares a bounds check. The count's lane becomes sphere 0: lanes past
                    // `len` are read (and indexed by) `within_reach`, so every lane copied
                    // must name a sphere.
                    let members = u32x8::new(record.0) & MEMBER_LANES;
                    let lanes = (members << CODE_BITS) | u32x8::splat(u32::from(code));
                    let at = len & GATHER_MASK;
                    head[at..at + HEAD + 1].copy_from_slice(lanes.as_array());
                    let count = record.count();
                    if count > HEAD && near {
                        spilled.extend(cells.spill(cell).iter().map(|&j| entry(j, code)));
                    }
                    len += usize::from(near) * count.min(HEAD);
                }
            }
        }
        debug_assert!(len <= 27 * HEAD);
        if !spilled.is_empty() {
            let total = len + spilled.len();
            if self.gathered.len() < total + 4 {
                self.gathered.resize(total + 4, 0);
            }
            self.gathered[len..total].copy_from_slice(spilled);
            len = total;
        }
        len
    }
}

/// The room `gathered` always has: the records of 27 cells and one more copy, below a power
/// of two (`GATHER_MASK`) and its copy.
const GATHER_ROOM: usize = GATHER_MASK + 1 + HEAD + 1;

/// For each mask of four lanes, the lanes it sets, in order: the shuffle that moves the lanes
/// kept to the front (`within_reach`; the lanes after them repeat lane 0 and are not counted).
const KEPT_FIRST: [u32x4; 16] = {
    let mut table = [u32x4::new([0; 4]); 16];
    let mut mask = 0;
    while mask < 16 {
        let mut lanes = [0u32; 4];
        let (mut at, mut k) = (0, 0);
        while k < 4 {
            if mask >> k & 1 == 1 {
                lanes[at] = k as u32;
                at += 1;
            }
            k += 1;
        }
        table[mask] = u32x4::new(lanes);
        mask += 1;
    }
    table
};

/// Keeps a record's seven member lanes and zeroes its count's (`cells_near`).
const MEMBER_LANES: u32x8 = u32x8::new([!0, !0, !0, !0, !0, !0, !0, 0]);

/// One less than a power of two above every length the records of 26 cells can fill.
const GATHER_MASK: usize = 255;

/// The 3 × 3 × 3 cells around a shell centre, per axis and offset −1, 0, +1: a cell's index,
/// shift code, gap and whether it is inside the domain are sums (and) of its three axes' parts.
struct Stencil<'a> {
    /// Each axis' parts, borrowed from the table (a copy through the stack, stored and
    /// reloaded in pieces of other widths, stalled every rebuild on the store buffer).
    axes: [&'a AxisPart; 3],
    /// The squared distance from the centre to the neighbour cell's slab: a lower bound for
    /// any centre in it, or its image. A cell farther than the widest reach holds nobody within
    /// reach (`far` has a margin above the faces' rounding).
    gap: [[f64; 3]; 3],
}

/// One axis' part of the stencil around a cell coordinate, for offsets −1, 0, +1.
#[derive(Debug, Clone, Copy, Default)]
struct AxisPart {
    /// The axis' part of the cell index: the wrapped coordinate times the axis' stride (0
    /// outside an open domain: cell 0 stands in).
    part: [usize; 3],
    /// The axis' part of the shift code: its digit (0, 1, 2 for −1, 0, +1 box lengths) times
    /// 1, 3 or 9.
    code: [u8; 3],
    /// Whether the axis' coordinate is inside the domain (always, periodic).
    inside: [bool; 3],
}

/// Each axis' stencil parts, per cell coordinate, made once for the grid: a rebuild looks its
/// stencil up instead of wrapping nine coordinates.
#[derive(Debug, Clone, Default)]
pub(super) struct StencilTable {
    axes: [Vec<AxisPart>; 3],
}

impl StencilTable {
    /// The table of `cells`, wrapping (`periodic`) or marking the cells beyond an open domain's
    /// edge as outside.
    pub(super) fn new(cells: &Cells, periodic: bool) -> Self {
        let n = cells.n;
        let stride = [1, n[0] as usize, n[0] as usize * n[1] as usize];
        let axes = [0, 1, 2].map(|k| {
            (0..n[k])
                .map(|at| {
                    let mut axis = AxisPart::default();
                    for (o, d) in (-1..=1).enumerate() {
                        let (mut c, mut digit, mut inside) = (at + d, 1u8, true);
                        if c < 0 || c >= n[k] {
                            if periodic {
                                let wrap = if c < 0 { 1 } else { -1 };
                                c += wrap * n[k];
                                digit = (1 - wrap) as u8;
                            } else {
                                (c, inside) = (0, false);
                            }
                        }
                        axis.part[o] = c as usize * stride[k];
                        axis.code[o] = digit * [1, 3, 9][k];
                        axis.inside[o] = inside;
                    }
                    axis
                })
                .collect()
        });
        Self { axes }
    }

    /// Bytes the table holds (a few per cell along each axis).
    pub(super) fn bytes(&self) -> usize {
        self.axes
            .iter()
            .map(|a| a.capacity() * std::mem::size_of::<AxisPart>())
            .sum()
    }

    /// The indices of the 27 cells around cell `ci` (each axis' three parts, summed as in
    /// `cells_near`): for fetching ahead.
    #[inline]
    pub(super) fn cell_parts(&self, ci: [i32; 3]) -> [[usize; 3]; 3] {
        self.axes_at(ci).map(|axis| axis.part)
    }

    /// Each axis' parts at cell `ci`.
    #[inline]
    fn axes_at(&self, ci: [i32; 3]) -> [&AxisPart; 3] {
        let axis = |k: usize| &self.axes[k][ci[k] as usize];
        [axis(0), axis(1), axis(2)]
    }

    /// The stencil around centre `c`, in cell `ci`.
    #[inline]
    fn around(&self, cells: &Cells, ci: [i32; 3], c: DVec3) -> Stencil<'_> {
        let gap = |k: usize| {
            let below = c[k] - (cells.lo[k] + f64::from(ci[k]) * cells.w[k]);
            let above = cells.w[k] - below;
            [below * below, 0.0, above * above]
        };
        Stencil {
            axes: self.axes_at(ci),
            gap: [gap(0), gap(1), gap(2)],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// The unchecked load's guard fires in a test build on an entry that names no sphere
    /// (and lets one that does through, to the same motion as `DVec3` arithmetic).
    #[test]
    #[cfg(debug_assertions)]
    fn an_entry_naming_no_sphere_stops_a_test_build() {
        let body = Trajectory {
            r: DVec3::new(1.0, 2.0, 3.0),
            t: 0.5,
            v: DVec3::new(-1.0, 0.0, 2.0),
            radius: 0.5,
        };
        let bodies = [body];
        let shift = shift_lanes(super::super::lists::shifts(DVec3::splat(10.0), false));
        let own = own_lanes(&Trajectory {
            t: 1.0,
            ..Trajectory::default()
        });
        let zero = f64x4::ZERO;
        // SAFETY: entry 0 names sphere 0 of one.
        let a = unsafe { relative::<false>(&bodies, &shift, own, 1.0, zero, entry(0, NO_SHIFT)) };
        assert_eq!(xyz(a.r0), body.r + body.v * 0.5);
        let past = std::panic::catch_unwind(|| {
            // SAFETY: not kept, on purpose: a test build checks the promise before the load.
            unsafe { relative::<false>(&bodies, &shift, own, 1.0, zero, entry(1, NO_SHIFT)) }
        });
        let message = past.expect_err("an entry past the last sphere is caught");
        let text = message
            .downcast_ref::<String>()
            .expect("a formatted message");
        assert!(text.contains("names no sphere"), "{text}");
    }

    /// The cells fetched ahead of a rebuild (`cell_parts`) are the 27 around the cell,
    /// wrapped, in a periodic grid: each index is that of the neighbour cell's coordinates.
    #[test]
    fn the_cells_fetched_ahead_are_the_27_around() {
        let cells = Cells::new(DVec3::ZERO, DVec3::new(5.0, 4.0, 3.0), 1.0, 1000);
        assert_eq!(cells.n, [5, 4, 3]);
        let table = StencilTable::new(&cells, true);
        for ci in [[0, 0, 0], [4, 3, 2], [2, 1, 1]] {
            let [x, y, z] = table.cell_parts(ci);
            for (dz, pz) in (-1..=1).zip(z) {
                for (dy, py) in (-1..=1).zip(y) {
                    for (dx, px) in (-1..=1).zip(x) {
                        let wrap = |k: usize, d: i32| (ci[k] + d).rem_euclid(cells.n[k]);
                        let c = [wrap(0, dx), wrap(1, dy), wrap(2, dz)];
                        assert_eq!(pz + py + px, cells.index(c), "{ci:?} + {dx},{dy},{dz}");
                    }
                }
            }
        }
    }

    /// Every mask's shuffle puts the lanes it sets first, in order, as a filter would.
    #[test]
    fn kept_first_moves_the_kept_lanes_to_the_front_in_order() {
        let four = [11, 22, 33, 44];
        for (mask, &shuffle) in KEPT_FIRST.iter().enumerate() {
            let packed = u32x4::new(four).shuffle(shuffle).to_array();
            let kept: Vec<u32> = (0..4)
                .filter(|k| mask >> k & 1 == 1)
                .map(|k| four[k])
                .collect();
            assert_eq!(packed[..kept.len()], kept[..], "mask {mask:04b}");
        }
    }

    /// The merge by its definition: sort the four, keep the first two within the lists'
    /// bound (`bound`, shared with `merge`: this test is of the selection).
    fn merged_by_sorting(
        a: ([Candidate; 2], bool),
        b: ([Candidate; 2], bool),
    ) -> ([Candidate; 2], bool) {
        let limit = bound(a).min(bound(b));
        let mut all: Vec<Candidate> = [a.0[0], a.0[1], b.0[0], b.0[1]]
            .into_iter()
            .filter(|c| c.t.is_finite() && c.t <= limit)
            .collect();
        all.sort_by(|x, y| x.t.total_cmp(&y.t).then(x.j.cmp(&y.j)));
        let mut out = [Candidate::NONE; 2];
        for (slot, c) in out.iter_mut().zip(&all) {
            *slot = *c;
        }
        (out, a.1 && b.1 && all.len() <= 2)
    }

    /// A sorted list of up to two candidates, times drawn from a few values so that ties
    /// in time (and in time and partner) are common.
    fn list(rng: &mut Rng) -> ([Candidate; 2], bool) {
        let mut pick = || {
            if rng.unit() < 0.25 {
                Candidate::NONE
            } else {
                Candidate {
                    t: (rng.unit() * 4.0).floor(),
                    j: (rng.unit() * 3.0) as u32,
                    counter: 0,
                }
            }
        };
        let mut l = [pick(), pick()];
        if l[1].before(&l[0]) {
            l.swap(0, 1);
        }
        (l, rng.unit() < 0.5)
    }

    #[test]
    fn merge_keeps_the_two_earliest_within_the_bound_as_sorting_would() {
        let mut rng = Rng::new(11);
        for _ in 0..100_000 {
            let (a, b) = (list(&mut rng), list(&mut rng));
            assert_eq!(merge(a, b), merged_by_sorting(a, b), "{a:?} {b:?}");
        }
    }
}
