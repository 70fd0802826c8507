//! One chunk of rows through the library: validated into stores by its constructors
//! (`SphereStore::from_columns`), then queried by the batch entry points (`zip_times` for
//! pairs; `static_times` per shape, or `earliest_static_contacts` for a kind with many shapes,
//! for spheres against shapes), with the contact geometry from `contact::contact_at`.

use std::ops::Range;
use std::time::{Duration, Instant};

use rayon::prelude::*;

use spheresweep::batch::{StaticShape, earliest_static_contacts, static_times, zip_times};
use spheresweep::contact::{Contact, contact_at};
use spheresweep::statics::{OfKind, Visitor};
use spheresweep::store::Columns;
use spheresweep::{Body, QueryOptions, Shape, ShapeKind, SphereStore, Statics, StoreError};

use super::layout::{Chunk, KIND_NONE, Results};

/// The static shapes of `--against`, by kind, each in file order.
pub type Shapes = Statics;

/// What one chunk took and found.
#[derive(Debug, Clone, Copy, Default)]
pub struct Tally {
    /// Rows with a contact in the window.
    pub contacts: usize,
    /// Time spent building the stores (every row validated by the library's constructors).
    pub validating: Duration,
    /// Time spent in the batch entry points and on the contact geometry.
    pub querying: Duration,
}

/// Rows validated into one store by one parallel task, and answered by one call of the
/// static entry points: small enough that the per-sphere records those return stay a few MiB,
/// large enough that each call still runs in parallel. A multiple of the lane width, so the
/// lane groups are those of one store over the whole input.
const BLOCK: usize = 1 << 16;

/// The blocks of `n` rows.
fn blocks(n: usize) -> Vec<Range<usize>> {
    (0..n)
        .step_by(BLOCK)
        .map(|a| a..(a + BLOCK).min(n))
        .collect()
}

/// A store from the seven columns `x, y, z, vx, vy, vz, r` starting at column `first` of
/// `chunk`, rows `range`, validated by `SphereStore::from_columns`. A refused row is named
/// with its place, its column and its value.
fn store(
    chunk: &Chunk,
    first: usize,
    names: &[&str],
    range: Range<usize>,
) -> Result<SphereStore, Refusal> {
    let col = |k: usize| &chunk.columns[first + k][range.clone()];
    let columns = Columns {
        x: col(0),
        y: col(1),
        z: col(2),
        vx: col(3),
        vy: col(4),
        vz: col(5),
        r: col(6),
        m: None,
    };
    SphereStore::from_columns(&columns).map_err(|e| match e {
        StoreError::Invalid { index, source } => {
            // The constructor names the field; the column is the component at fault.
            let candidates = match source.field {
                "centre" => 0..3,
                "velocity" => 3..6,
                _ => 6..7,
            };
            let k = candidates
                .clone()
                .find(|&k| !col(k)[index].is_finite())
                .unwrap_or(candidates.start);
            let place = chunk.locate(range.start + index);
            (
                place.row,
                format!(
                    "{place}, column {} = {}: {source}",
                    names[first + k],
                    col(k)[index]
                ),
            )
        }
        other => (chunk.locate(range.start).row, other.to_string()),
    })
}

/// A refused row: its row index (to report the earliest) and the message.
type Refusal = (u64, String);

/// Stores for every block of the chunk, built in parallel; the first refused row in file
/// order is the one reported, whatever the thread count.
fn stores<T: Send>(
    n: usize,
    build: impl Fn(Range<usize>) -> Result<T, Refusal> + Sync,
) -> Result<Vec<(Range<usize>, T)>, String> {
    let built: Vec<Result<(Range<usize>, T), Refusal>> = blocks(n)
        .into_par_iter()
        .map(|r| build(r.clone()).map(|s| (r, s)))
        .collect();
    built.into_iter().collect::<Result<_, _>>().map_err(|e| e.1)
}

/// The contact point and normal as the six geometry columns.
fn geometry_row(c: &Contact) -> [f64; 6] {
    [
        c.point.x, c.point.y, c.point.z, c.normal.x, c.normal.y, c.normal.z,
    ]
}

/// Every pair of rows `a[i]`, `b[i]` of a pairs chunk (`names` the 14 columns): times into
/// `out.time`, geometry if the options ask for it.
pub fn pairs(
    chunk: &Chunk,
    names: &[&str],
    options: QueryOptions,
    out: &mut Results,
) -> Result<Tally, String> {
    let n = chunk.rows();
    let start = Instant::now();
    let stores = stores(n, |r| {
        // Both stores are validated before either is reported: the earlier row is named.
        match (store(chunk, 0, names, r.clone()), store(chunk, 7, names, r)) {
            (Ok(a), Ok(b)) => Ok((a, b)),
            (Err(ea), Err(eb)) => Err(if eb.0 < ea.0 { eb } else { ea }),
            (Err(e), _) | (_, Err(e)) => Err(e),
        }
    })?;
    let validated = Instant::now();
    out.clear();
    out.time.resize(n, 0.0);
    for (range, (a, b)) in &stores {
        let times = &mut out.time[range.clone()];
        zip_times(a, b, options, times).map_err(|e| e.to_string())?;
        if options.geometry() {
            for (i, &t) in times.iter().enumerate() {
                let g = match (t.is_finite(), a.get(i), b.get(i)) {
                    (true, Some(sa), Some(sb)) => {
                        geometry_row(&contact_at(&sa, &Shape::Sphere(sb), f64::from(t)))
                    }
                    _ => [f64::NAN; 6],
                };
                for (col, v) in out.geometry.iter_mut().zip(g) {
                    col.push(v);
                }
            }
        }
    }
    Ok(Tally {
        contacts: out.time.iter().filter(|t| t.is_finite()).count(),
        validating: validated - start,
        querying: validated.elapsed(),
    })
}

/// The earliest contact so far of each sphere of a block: time, kind code, index.
type Best = (f32, u8, u32);

/// Shapes of one kind up to which each shape is answered by `static_times` into a reused
/// buffer of times; more go through `earliest_static_contacts`, whose lane groups skip the
/// shapes they cannot reach but which returns a 128-byte record per sphere. Both give the same
/// bits: the same kernels, and the same rule (the earliest, then the lowest index).
const ONE_BY_ONE: usize = 4;

/// Offers the contacts of one kind to `best` (kinds offered in tie order: a later kind, or a
/// later shape of a kind, wins only at a strictly earlier time, as the library's first-contact
/// queries break ties).
fn offer<K: StaticShape>(
    store: &SphereStore,
    shapes: &[K],
    options: QueryOptions,
    best: &mut [Best],
    times: &mut Vec<f32>,
) -> Result<(), String> {
    let options = options.with_geometry(false);
    let code = K::KIND.code();
    if shapes.len() <= ONE_BY_ONE {
        times.resize(store.len(), 0.0);
        for (j, shape) in (0u32..).zip(shapes) {
            static_times(store, shape, options, times).map_err(|e| e.to_string())?;
            for (slot, &t) in best.iter_mut().zip(times.iter()) {
                if t < slot.0 {
                    *slot = (t, code, j);
                }
            }
        }
        return Ok(());
    }
    let hits = earliest_static_contacts(store, shapes, options);
    for (slot, hit) in best.iter_mut().zip(hits) {
        if let Some(h) = hit
            && h.time < slot.0
        {
            *slot = (h.time, code, h.body.index);
        }
    }
    Ok(())
}

/// [`offer`] for each kind of shape in turn, in tie order; the first error is kept.
struct Offer<'a> {
    store: &'a SphereStore,
    options: QueryOptions,
    best: &'a mut [Best],
    times: &'a mut Vec<f32>,
    result: Result<(), String>,
}

impl Visitor<()> for Offer<'_> {
    fn visit<K: StaticShape>(&mut self, shapes: &OfKind<K, ()>) {
        if self.result.is_ok() {
            self.result = offer(
                self.store,
                shapes.shapes(),
                self.options,
                self.best,
                self.times,
            );
        }
    }
}

/// Every sphere of a spheres chunk (`names` its 7 columns) against every shape: the earliest
/// contact's time, kind and index (ties: planes, cylinders, containers, then the lowest
/// index), geometry if asked for.
pub fn statics(
    chunk: &Chunk,
    names: &[&str],
    shapes: &Shapes,
    options: QueryOptions,
    out: &mut Results,
) -> Result<Tally, String> {
    let n = chunk.rows();
    let start = Instant::now();
    let stores = stores(n, |r| store(chunk, 0, names, r))?;
    let validated = Instant::now();
    out.clear();
    let mut best = Vec::with_capacity(BLOCK.min(n));
    let mut times = Vec::with_capacity(BLOCK.min(n));
    for (range, store) in &stores {
        best.clear();
        best.resize(range.len(), (f32::INFINITY, KIND_NONE, 0));
        let mut each = Offer {
            store,
            options,
            best: &mut best,
            times: &mut times,
            result: Ok(()),
        };
        shapes.visit(&mut each);
        each.result?;
        for (i, &(time, kind, index)) in best.iter().enumerate() {
            let hit = time.is_finite();
            out.time.push(time);
            out.kind.push(if hit { kind } else { KIND_NONE });
            out.index.push(if hit { i64::from(index) } else { -1 });
            if options.geometry() {
                let shape: Option<Shape> = ShapeKind::from_code(kind)
                    .and_then(|k| shapes.get(Body::new(k, index)))
                    .map(|(s, ())| s.into());
                let g = match (hit, shape, store.get(i)) {
                    (true, Some(shape), Some(sphere)) => {
                        geometry_row(&contact_at(&sphere, &shape, f64::from(time)))
                    }
                    _ => [f64::NAN; 6],
                };
                for (col, v) in out.geometry.iter_mut().zip(g) {
                    col.push(v);
                }
            }
        }
    }
    Ok(Tally {
        contacts: out.time.iter().filter(|t| t.is_finite()).count(),
        validating: validated - start,
        querying: validated.elapsed(),
    })
}
