//! Timings of several contenders interleaved round by round (ours on one thread, ours on two,
//! the peer): a burst of load from elsewhere on a shared machine falls on all of them alike,
//! and the best of each is taken over the same stretch of time.

use std::time::{Duration, Instant};

use rayon::ThreadPool;

/// One contender: the pool it runs in, the shortest a timing of it may be, and its work.
pub struct Timed<'a> {
    pub pool: &'a ThreadPool,
    pub min: Duration,
    pub work: &'a mut (dyn FnMut() + Send),
}

/// The best ns per item of each contender over `rounds` rounds, every round timing each
/// contender once in turn (after one untimed call of each).
pub fn best_ns<const K: usize>(
    items: usize,
    rounds: usize,
    mut contenders: [Timed<'_>; K],
) -> [f64; K] {
    for c in &mut contenders {
        let work = &mut *c.work;
        c.pool.install(work);
    }
    let mut best = [f64::INFINITY; K];
    for _ in 0..rounds {
        for (c, best) in contenders.iter_mut().zip(&mut best) {
            let (min, work) = (c.min, &mut *c.work);
            *best = best.min(c.pool.install(|| timing_ns(items, min, work)));
        }
    }
    best
}

/// One timing of `work`, repeated until at least `min` has passed (once at least): ns per item.
pub fn timing_ns(items: usize, min: Duration, work: &mut dyn FnMut()) -> f64 {
    let (start, mut reps) = (Instant::now(), 0u32);
    while reps == 0 || start.elapsed() < min {
        work();
        reps += 1;
    }
    start.elapsed().as_secs_f64() * 1e9 / (f64::from(reps) * items as f64)
}
