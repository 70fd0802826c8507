//! What the engine's loops over other spheres' records share (a prediction's passes,
//! `pair_prediction.rs`; a rebuild's scan, `list_rebuild.rs`): the unchecked load `named`,
//! and `KEPT_FIRST`, the shuffle that packs the lanes a test kept.
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

use wide::u32x4;

/// Sphere `j`'s record in a per-sphere array, loaded without a bounds check: the passes' one
/// unchecked load, and the check every test build makes of it.
///
/// # Safety
///
/// `j < items.len()` (the module's "Every lane names a sphere").
#[inline(always)]
pub(super) unsafe fn named<T>(items: &[T], j: u32) -> &T {
    debug_assert!(
        (j as usize) < items.len(),
        "sphere {j} of {}: the lane names no sphere",
        items.len()
    );
    // SAFETY: the caller's promise.
    unsafe { items.get_unchecked(j as usize) }
}

/// For each mask of four lanes, the lanes it sets, in order: the shuffle that moves the lanes
/// kept to the front (`screen`, `within_reach`; the lanes after them repeat lane 0 and are not counted).
pub(super) const KEPT_FIRST: [u32x4; 16] = {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
