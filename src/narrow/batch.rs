//! Batch entry points: explicit pair lists, aligned stores, one sphere against a block, and
//! every sphere against every static shape. Each returns the earliest contact per query item
//! in `[0, t_max]`; above [`PARALLEL_MIN`] items the work is split over rayon in fixed chunks,
//! so results are identical for any thread count.

use std::marker::PhantomData;

use rayon::prelude::*;
use wide::{f32x8, f64x4};

use super::lanes::Lanes;
use super::quadratic::{Solver, Stable, Textbook};
use super::sphere_container::{self, ContainerLanes};
use super::sphere_cylinder::{self, CylinderLanes};
use super::sphere_plane::{self, PlaneLanes};
use super::sphere_sphere::{self, SphereLanes};
use crate::reference::{self, Contact};
use crate::store::SphereStore;
use crate::{Accuracy, Container, Cylinder, Plane, Sphere};

/// Query items per batch from which the work runs in parallel.
pub const PARALLEL_MIN: usize = 1 << 15;
/// Query items per parallel task (a multiple of eight).
const CHUNK: usize = 1 << 12;
/// Above this many static shapes of one kind, their indices are not exact in f32 lanes.
const MAX_STATIC: usize = 1 << 24;

/// The time window `[0, t_max]` and the accuracy mode of a query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Query {
    t_max: f32,
    accuracy: Accuracy,
}

impl Query {
    /// A query over `[0, t_max]`.
    ///
    /// # Errors
    /// [`BatchError::Window`] if `t_max` is NaN or negative (`+∞` is allowed).
    pub fn new(t_max: f32, accuracy: Accuracy) -> Result<Self, BatchError> {
        if t_max.is_nan() || t_max < 0.0 {
            return Err(BatchError::Window(t_max));
        }
        Ok(Self { t_max, accuracy })
    }
    /// End of the window.
    pub fn t_max(&self) -> f32 {
        self.t_max
    }
    /// Accuracy mode.
    pub fn accuracy(&self) -> Accuracy {
        self.accuracy
    }
}

/// The earliest contact of one query item: when, and with which body (its index).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstContact {
    /// Time of impact in `[0, t_max]`.
    pub time: f32,
    /// Index of the other body in the slice or store it came from.
    pub other: u32,
}

/// A batch call's arguments do not fit together.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BatchError {
    /// The window's end is NaN or negative.
    #[error("t_max must be zero or more (or +inf), got {0}")]
    Window(f32),
    /// The output slice has the wrong length.
    #[error("output has {found} slots, expected {expected} (one per query item)")]
    OutputLength {
        /// Query items.
        expected: usize,
        /// Output slots.
        found: usize,
    },
    /// Two stores meant to be paired element by element differ in length.
    #[error("the stores differ in length: {a} and {b} spheres")]
    StoreLengths {
        /// First store.
        a: usize,
        /// Second store.
        b: usize,
    },
    /// A pair names a sphere the store does not hold.
    #[error("pair {pair}: sphere index {index} is out of range (the store holds {len})")]
    IndexOutOfRange {
        /// Position of the pair in the list.
        pair: usize,
        /// The bad index.
        index: u32,
        /// Spheres in the store.
        len: usize,
    },
    /// More static shapes of one kind than a lane index holds exactly.
    #[error("{0} static shapes of one kind: at most 2^24 are supported")]
    TooManyShapes(usize),
}

/// Runs `$f::<Lanes, Solver>(args)` for the accuracy mode: one dispatch per batch.
macro_rules! with_mode {
    ($accuracy:expr, $f:ident$(::<$($g:ty),*>)?($($arg:expr),* $(,)?)) => {
        match $accuracy {
            Accuracy::Textbook => $f::<f32x8, Textbook $($(, $g)*)?>($($arg),*),
            Accuracy::Stable => $f::<f32x8, Stable $($(, $g)*)?>($($arg),*),
            Accuracy::Double => $f::<f64x4, Stable $($(, $g)*)?>($($arg),*),
        }
    };
}

fn check_output(expected: usize, out: &[f32]) -> Result<(), BatchError> {
    if out.len() == expected {
        Ok(())
    } else {
        Err(BatchError::OutputLength {
            expected,
            found: out.len(),
        })
    }
}

/// One lane group of a batch: it writes the results for items `i .. i + out.len()`
/// (`out.len() ≤ WIDTH`, shorter only at the tail). A trait rather than a closure so that
/// `#[inline(always)]` puts the whole kernel inside the driver's loop.
trait LaneKernel: Sync {
    /// One result per query item.
    type Item: Copy + Send;
    /// Items per lane group.
    const WIDTH: usize;
    fn write(&self, i: usize, out: &mut [Self::Item]);
}

/// Stores the first `out.len()` lanes of `t` (all of them but at the tail).
#[inline(always)]
fn store_lanes<L: Lanes>(t: L, out: &mut [f32]) {
    if out.len() == L::WIDTH {
        t.store(out);
    } else {
        let mut tail = [0.0f32; 8];
        t.store(&mut tail);
        out.copy_from_slice(&tail[..out.len()]);
    }
}

/// Fills `out` lane group by lane group, in parallel chunks above [`PARALLEL_MIN`].
#[inline(always)]
fn fill<K: LaneKernel>(out: &mut [K::Item], kernel: &K) {
    if out.len() >= PARALLEL_MIN {
        out.par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(k, chunk)| fill_range(k * CHUNK, chunk, kernel));
    } else {
        fill_range(0, out, kernel);
    }
}

#[inline(always)]
fn fill_range<K: LaneKernel>(offset: usize, out: &mut [K::Item], kernel: &K) {
    // Exact chunks: full groups have a length known at compile time, so `store_lanes`'
    // tail check folds away in the hot loop; only the remainder takes the tail path.
    let mut parts = out.chunks_exact_mut(K::WIDTH);
    let mut i = offset;
    for part in &mut parts {
        kernel.write(i, part);
        i += K::WIDTH;
    }
    let rest = parts.into_remainder();
    if !rest.is_empty() {
        kernel.write(i, rest);
    }
}

struct Zip<'a, L, S> {
    a: &'a SphereStore,
    b: &'a SphereStore,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver> LaneKernel for Zip<'_, L, S> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        store_lanes(
            sphere_sphere::time_of_impact::<L, S>(&self.a.lanes(i), &self.b.lanes(i), self.t_max),
            out,
        );
    }
}

struct Listed<'a, L, S> {
    store: &'a SphereStore,
    pairs: &'a [[u32; 2]],
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver> LaneKernel for Listed<'_, L, S> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        let group = &self.pairs[i..i + out.len()];
        let a = self.store.gather::<L>(group.iter().map(|p| p[0] as usize));
        let b = self.store.gather::<L>(group.iter().map(|p| p[1] as usize));
        store_lanes(
            sphere_sphere::time_of_impact::<L, S>(&a, &b, self.t_max),
            out,
        );
    }
}

struct OneAgainst<'a, L, S> {
    one: SphereLanes<L>,
    block: &'a SphereStore,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver> LaneKernel for OneAgainst<'_, L, S> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        store_lanes(
            sphere_sphere::time_of_impact::<L, S>(&self.one, &self.block.lanes(i), self.t_max),
            out,
        );
    }
}

struct AgainstStatic<'a, L: Lanes, S, K: StaticShape> {
    spheres: &'a SphereStore,
    shape: K::Lanes<L>,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver, K: StaticShape> LaneKernel for AgainstStatic<'_, L, S, K> {
    type Item = f32;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [f32]) {
        store_lanes(
            K::time_of_impact::<L, S>(&self.spheres.lanes(i), &self.shape, self.t_max),
            out,
        );
    }
}

/// Time of impact of `a[i]` with `b[i]` for every `i`, into `out[i]` (`+∞`: no contact).
/// The fastest layout: both stores are read as contiguous columns.
///
/// # Errors
/// If the stores differ in length or `out` does not have one slot per pair.
///
/// ```
/// use spheresweep::{Accuracy, Sphere, SphereStore, narrow::{Query, zip_times}};
/// let a = SphereStore::from_spheres(&[Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?]);
/// let b = SphereStore::from_spheres(&[Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?]);
/// let mut out = [0.0];
/// zip_times(&a, &b, Query::new(100.0, Accuracy::Stable)?, &mut out)?;
/// assert_eq!(out, [4.0]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn zip_times(
    a: &SphereStore,
    b: &SphereStore,
    query: Query,
    out: &mut [f32],
) -> Result<(), BatchError> {
    if a.len() != b.len() {
        return Err(BatchError::StoreLengths {
            a: a.len(),
            b: b.len(),
        });
    }
    check_output(a.len(), out)?;
    fn run<L: Lanes, S: Solver>(a: &SphereStore, b: &SphereStore, t: f32, out: &mut [f32]) {
        let (t_max, solver) = (L::splat(t), PhantomData::<S>);
        fill(
            out,
            &Zip {
                a,
                b,
                t_max,
                solver,
            },
        );
    }
    with_mode!(query.accuracy, run(a, b, query.t_max, out));
    Ok(())
}

/// Time of impact of every listed pair `[i, j]` of spheres of `store`, into `out`.
///
/// # Errors
/// If an index is out of range or `out` does not have one slot per pair.
pub fn pair_times(
    store: &SphereStore,
    pairs: &[[u32; 2]],
    query: Query,
    out: &mut [f32],
) -> Result<(), BatchError> {
    check_output(pairs.len(), out)?;
    for (pair, ij) in pairs.iter().enumerate() {
        if let Some(&index) = ij.iter().find(|&&k| k as usize >= store.len()) {
            return Err(BatchError::IndexOutOfRange {
                pair,
                index,
                len: store.len(),
            });
        }
    }
    fn run<L: Lanes, S: Solver>(store: &SphereStore, pairs: &[[u32; 2]], t: f32, o: &mut [f32]) {
        let (t_max, solver) = (L::splat(t), PhantomData::<S>);
        fill(
            o,
            &Listed {
                store,
                pairs,
                t_max,
                solver,
            },
        );
    }
    with_mode!(query.accuracy, run(store, pairs, query.t_max, out));
    Ok(())
}

/// Time of impact of `sphere` with every sphere of `block`, into `out`.
///
/// # Errors
/// If `out` does not have one slot per sphere of `block`.
pub fn one_against_times(
    sphere: &Sphere,
    block: &SphereStore,
    query: Query,
    out: &mut [f32],
) -> Result<(), BatchError> {
    check_output(block.len(), out)?;
    fn run<L: Lanes, S: Solver>(s: &Sphere, block: &SphereStore, t: f32, out: &mut [f32]) {
        let (t_max, one, solver) = (L::splat(t), SphereLanes::splat(s), PhantomData::<S>);
        fill(
            out,
            &OneAgainst {
                one,
                block,
                t_max,
                solver,
            },
        );
    }
    with_mode!(query.accuracy, run(sphere, block, query.t_max, out));
    Ok(())
}

/// The earliest contact of `sphere` with any sphere of `block` (ties: the lowest index).
/// If `sphere` is itself in `block`, it does not touch itself (no relative motion).
pub fn first_contact_against(
    sphere: &Sphere,
    block: &SphereStore,
    query: Query,
) -> Option<FirstContact> {
    let mut times = vec![0.0; block.len()];
    one_against_times(sphere, block, query, &mut times).expect("one slot per sphere");
    earliest(&times)
}

fn earliest(times: &[f32]) -> Option<FirstContact> {
    let (other, &time) =
        times
            .iter()
            .enumerate()
            .fold(None, |best: Option<(usize, &f32)>, (j, t)| match best {
                Some((_, b)) if b <= t => best,
                _ if t.is_finite() => Some((j, t)),
                _ => best,
            })?;
    Some(FirstContact {
        time,
        other: other as u32,
    })
}

/// A static shape kind that every sphere is tested against: planes, cylinders, containers.
pub trait StaticShape: Sync {
    /// The shape splatted across lanes, prepared once per batch.
    type Lanes<L: Lanes>: Sync;
    /// Prepares the lanes.
    fn splat<L: Lanes>(&self) -> Self::Lanes<L>;
    /// The kernel for this kind.
    fn time_of_impact<L: Lanes, S: Solver>(s: &SphereLanes<L>, k: &Self::Lanes<L>, t: L) -> L;
    /// The contact geometry at time `t`, from the f64 reference.
    fn contact_at(sphere: &Sphere, shape: &Self, t: f64) -> Contact;
}

impl StaticShape for Plane {
    type Lanes<L: Lanes> = PlaneLanes<L>;
    fn splat<L: Lanes>(&self) -> PlaneLanes<L> {
        PlaneLanes::splat(self)
    }
    #[inline(always)]
    fn time_of_impact<L: Lanes, S: Solver>(s: &SphereLanes<L>, p: &PlaneLanes<L>, t: L) -> L {
        sphere_plane::time_of_impact::<L, S>(s, p, t)
    }
    fn contact_at(sphere: &Sphere, shape: &Self, t: f64) -> Contact {
        reference::sphere_plane::contact_at(sphere, shape, t)
    }
}

impl StaticShape for Cylinder {
    type Lanes<L: Lanes> = CylinderLanes<L>;
    fn splat<L: Lanes>(&self) -> CylinderLanes<L> {
        CylinderLanes::splat(self)
    }
    #[inline(always)]
    fn time_of_impact<L: Lanes, S: Solver>(s: &SphereLanes<L>, c: &CylinderLanes<L>, t: L) -> L {
        sphere_cylinder::time_of_impact::<L, S>(s, c, t)
    }
    fn contact_at(sphere: &Sphere, shape: &Self, t: f64) -> Contact {
        reference::sphere_cylinder::contact_at(sphere, shape, t)
    }
}

impl StaticShape for Container {
    type Lanes<L: Lanes> = ContainerLanes<L>;
    fn splat<L: Lanes>(&self) -> ContainerLanes<L> {
        ContainerLanes::splat(self)
    }
    #[inline(always)]
    fn time_of_impact<L: Lanes, S: Solver>(s: &SphereLanes<L>, k: &ContainerLanes<L>, t: L) -> L {
        sphere_container::time_of_impact::<L, S>(s, k, t)
    }
    fn contact_at(sphere: &Sphere, shape: &Self, t: f64) -> Contact {
        reference::sphere_container::contact_at(sphere, shape, t)
    }
}

/// Time of impact of every sphere of `spheres` with one static `shape`, into `out`: no
/// allocation, the layout for a hot loop against one floor, pillar or vessel.
///
/// # Errors
/// If `out` does not have one slot per sphere.
pub fn static_times<K: StaticShape>(
    spheres: &SphereStore,
    shape: &K,
    query: Query,
    out: &mut [f32],
) -> Result<(), BatchError> {
    check_output(spheres.len(), out)?;
    fn run<L: Lanes, S: Solver, K: StaticShape>(
        spheres: &SphereStore,
        shape: &K,
        t: f32,
        out: &mut [f32],
    ) {
        let (t_max, shape, solver) = (L::splat(t), shape.splat::<L>(), PhantomData::<S>);
        let kernel = AgainstStatic::<L, S, K> {
            spheres,
            shape,
            t_max,
            solver,
        };
        fill(out, &kernel);
    }
    with_mode!(query.accuracy, run::<K>(spheres, shape, query.t_max, out));
    Ok(())
}

/// For every sphere of `spheres`, its earliest contact with any of `shapes` (ties: the
/// lowest index). A scene without shapes of a kind never runs that kind's kernel.
///
/// # Errors
/// [`BatchError::TooManyShapes`] above 2²⁴ shapes.
///
/// ```
/// use spheresweep::{Accuracy, Plane, Sphere, SphereStore, narrow::{first_contacts, Query}};
/// let floor = [Plane::new([0.0; 3], [0.0, 0.0, 1.0])?];
/// let balls = SphereStore::from_spheres(&[Sphere::new([0.0, 0.0, 3.0], [0.0, 0.0, -1.0], 1.0, 1.0)?]);
/// let hits = first_contacts(&balls, &floor, Query::new(10.0, Accuracy::Stable)?)?;
/// assert_eq!(hits[0].unwrap().time, 2.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn first_contacts<K: StaticShape>(
    spheres: &SphereStore,
    shapes: &[K],
    query: Query,
) -> Result<Vec<Option<FirstContact>>, BatchError> {
    if shapes.len() > MAX_STATIC {
        return Err(BatchError::TooManyShapes(shapes.len()));
    }
    let mut out = vec![None; spheres.len()];
    if !shapes.is_empty() {
        with_mode!(
            query.accuracy,
            run_first::<K>(spheres, shapes, query.t_max, &mut out)
        );
    }
    Ok(out)
}

/// Every sphere of a lane group against every prepared shape: the earliest, lowest index.
struct FirstOf<'a, L: Lanes, S, K: StaticShape> {
    spheres: &'a SphereStore,
    shapes: Vec<K::Lanes<L>>,
    t_max: L,
    solver: PhantomData<S>,
}

impl<L: Lanes, S: Solver, K: StaticShape> LaneKernel for FirstOf<'_, L, S, K> {
    type Item = Option<FirstContact>;
    const WIDTH: usize = L::WIDTH;
    #[inline(always)]
    fn write(&self, i: usize, out: &mut [Option<FirstContact>]) {
        let s = self.spheres.lanes::<L>(i);
        let mut best = L::splat(f32::INFINITY);
        let mut best_j = L::splat(0.0);
        for (j, shape) in self.shapes.iter().enumerate() {
            let t = K::time_of_impact::<L, S>(&s, shape, self.t_max);
            let sooner = t.lt(best);
            best = L::select(sooner, t, best);
            best_j = L::select(sooner, L::splat(j as f32), best_j);
        }
        let (mut times, mut which) = ([0.0f32; 8], [0.0f32; 8]);
        best.store(&mut times);
        best_j.store(&mut which);
        for ((slot, time), j) in out.iter_mut().zip(times).zip(which) {
            *slot = time.is_finite().then_some(FirstContact {
                time,
                other: j as u32,
            });
        }
    }
}

fn run_first<L: Lanes, S: Solver, K: StaticShape>(
    spheres: &SphereStore,
    shapes: &[K],
    t: f32,
    out: &mut [Option<FirstContact>],
) {
    let kernel = FirstOf::<L, S, K> {
        spheres,
        shapes: shapes.iter().map(K::splat).collect(),
        t_max: L::splat(t),
        solver: PhantomData,
    };
    fill(out, &kernel);
}

/// [`first_contacts`] with the contact point and normal of every hit, computed by the f64
/// reference at the reported time (only for the hits: the kernels compute times only).
///
/// # Errors
/// As [`first_contacts`].
pub fn first_contacts_with_geometry<K: StaticShape>(
    spheres: &SphereStore,
    shapes: &[K],
    query: Query,
) -> Result<Vec<Option<(FirstContact, Contact)>>, BatchError> {
    let firsts = first_contacts(spheres, shapes, query)?;
    Ok(firsts
        .into_iter()
        .enumerate()
        .map(|(i, first)| {
            let first = first?;
            let sphere = spheres.get(i).expect("index below len");
            let contact = K::contact_at(&sphere, &shapes[first.other as usize], first.time.into());
            Some((first, contact))
        })
        .collect())
}
