//! The engine's large per-sphere arrays on 2 MiB pages where Linux gives them (transparent
//! huge pages): a collision reads a few dozen spheres' records spread over megabytes, and on
//! 4 KiB pages those reads also miss the TLB. At N = 108 000 the gas ran 1.02–1.12× faster
//! over five measurements of a noisy host, at N ≤ 32 000 no measurable change
//! (docs/benchmarks.md, "Huge pages"). Each array is advised (`MADV_HUGEPAGE`) and its pages
//! gathered into huge ones at once (`MADV_COLLAPSE`, Linux 6.1 on): memory the allocator
//! reuses was already touched on small pages, which the first advice alone would leave as
//! they are. The advice changes how the kernel backs the memory, never its contents;
//! elsewhere (another system, huge pages off, an older kernel) the arrays are the same, on
//! small pages.

/// Arrays smaller than this are left alone: a small scene's whole state fits the TLB, and
/// gathering the 2 MiB around each small array would copy megabytes for nothing.
const SMALLEST: usize = 256 << 10;

/// `n` copies of `value`, as `vec![value; n]`, on huge pages where the system gives them.
pub(crate) fn filled<T: Clone>(value: T, n: usize) -> Vec<T> {
    let v = vec![value; n];
    settle(&v);
    v
}

/// The values of `iter`, collected, on huge pages where the system gives them.
pub(crate) fn collected<T>(iter: impl IntoIterator<Item = T>) -> Vec<T> {
    let v: Vec<T> = iter.into_iter().collect();
    settle(&v);
    v
}

/// Asks for the 2 MiB pages that `v`'s allocation reaches into (arrays of at least
/// [`SMALLEST`] bytes) to be huge, now and from now on. The pages at either end are shared
/// with the allocator's other blocks, which stay as they are but for their backing: that is
/// how the arrays smaller than 2 MiB (the calendar's, the counters) get huge pages at all.
/// Best effort: advice refused changes nothing.
pub(crate) fn settle<T>(v: &Vec<T>) {
    let bytes = v.capacity() * std::mem::size_of::<T>();
    if bytes < SMALLEST {
        return;
    }
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // The huge page size on x86-64 (and most aarch64) Linux.
        const HUGE: usize = 2 << 20;
        let start = v.as_ptr() as usize;
        let lo = start / HUGE * HUGE;
        let hi = (start + bytes).next_multiple_of(HUGE);
        for advice in [libc::MADV_HUGEPAGE, libc::MADV_COLLAPSE] {
            // SAFETY: `madvise` reads and writes no Rust value: the two advices only mark how
            // the kernel backs the pages of `[lo, hi)` and move their contents into huge pages
            // unchanged (unlike `MADV_DONTNEED` or `MADV_FREE`, which would discard them). The
            // range's whole pages beyond `v` belong to other allocations or to none; they are
            // left as they were but for their backing, and unmapped parts make the call
            // return an error, which is ignored. `lo` is page-aligned, as `madvise` requires.
            unsafe {
                libc::madvise(lo as *mut libc::c_void, hi - lo, advice);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The helpers give the same vectors as `vec!` and `collect`, large or small, and the
    /// values around a settled array are unchanged.
    #[test]
    fn the_vectors_are_the_ones_asked_for() {
        let before: Vec<u64> = (0..1000).collect();
        for n in [0, 1, 1000, 3 << 20] {
            assert_eq!(filled(7u32, n), vec![7u32; n]);
            assert_eq!(collected(0..n as u64), (0..n as u64).collect::<Vec<_>>());
        }
        let big: Vec<u64> = (0..(1 << 20)).collect();
        settle(&big);
        assert!(big.iter().enumerate().all(|(k, &x)| x == k as u64));
        assert_eq!(before, (0..1000).collect::<Vec<u64>>());
    }
}
