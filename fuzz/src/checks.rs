//! The checks behind the fuzz targets, one function per target, shared with the regression
//! tests (tests/fuzz_regressions.rs includes this file): every input a fuzzer ever crashed on
//! runs through the same function inside `cargo test`. Each panics on a broken guarantee,
//! and only then.

#[path = "../../tests/common/mod.rs"]
#[allow(dead_code)]
mod common;

use std::sync::OnceLock;

use common::{Pair, model};
use spheresweep::batch::{static_times_any, zip_times};
use spheresweep::io::scene_file::SceneFile;
use spheresweep::io::xyz::read_frames;
use spheresweep::sim::{Simulation, World, generate};
use spheresweep::store::{Columns, StoreError};
use spheresweep::{
    Accuracy, Container, Cylinder, Plane, QueryOptions, Shape, Sphere, SphereStore, Static,
};

/// The largest scene [`scene_file`] builds, so that every run stays fast.
pub const MAX_SPHERES: usize = 2000;

fn exercise(scene: SceneFile) {
    if scene.sphere_count().is_some_and(|n| n > MAX_SPHERES) {
        return;
    }
    // A scene of uncounted size (a count missing or overflowing) must be refused by `build`.
    let counted = scene.sphere_count().is_some();
    let Ok((world, run)) = scene.build() else {
        return;
    };
    assert!(counted, "a scene without a sphere count was built");
    let Ok(mut sim) = Simulation::new(world).map_err(|e| scene.locate(e)) else {
        return;
    };
    // One step: the engine polls every 4096 events and is told to stop there.
    let _ = sim.advance_with(run.t_end.min(1e3), &mut |_, _| false);
}

/// Bytes → a scene file, parsed as TOML and as JSON → `build` → `Simulation::new` → at most
/// one step of 4096 events: never a panic, every refusal a `SceneFileError`. Scenes of more
/// than [`MAX_SPHERES`] spheres (counted before anything is generated) are not built.
pub fn scene_file(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(scene) = SceneFile::from_toml_str(text) {
        exercise(scene);
    }
    if let Ok(scene) = SceneFile::from_json_str(text) {
        exercise(scene);
    }
}

/// Bytes → `io::xyz::read_frames`: frames, or an error naming a line of the text; never a
/// panic.
pub fn xyz(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    if let Err(e) = read_frames(&text) {
        // The line is one of the text's (or the one after its end, for a truncated frame).
        let lines = text.lines().count();
        assert!(
            (1..=lines + 1).contains(&e.line),
            "line {} of a {lines}-line text: {e}",
            e.line
        );
    }
}

/// Arbitrary f32 bit patterns → `SphereStore::from_columns`: an error naming a column or a
/// sphere, or a store whose spheres read back bit for bit. The first byte says whether masses
/// are given and which column (if any) is one short; the rest are the rows.
pub fn columns(data: &[u8]) {
    let Some((&shape, rest)) = data.split_first() else {
        return;
    };
    let with_mass = shape & 1 == 1;
    let short = usize::from(shape >> 1) % 16;
    let floats: Vec<f32> = rest
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let width = if with_mass { 8 } else { 7 };
    let n = floats.len() / width;
    let column = |k: usize| -> Vec<f32> {
        let c: Vec<f32> = (0..n).map(|i| floats[i * width + k]).collect();
        if k == short && n > 0 {
            c[..n - 1].to_vec()
        } else {
            c
        }
    };
    let cols: Vec<Vec<f32>> = (0..width).map(column).collect();
    let columns = Columns {
        x: &cols[0],
        y: &cols[1],
        z: &cols[2],
        vx: &cols[3],
        vy: &cols[4],
        vz: &cols[5],
        r: &cols[6],
        m: with_mass.then(|| cols[7].as_slice()),
    };
    match SphereStore::from_columns(&columns) {
        Ok(store) => {
            assert!(short >= width || n == 0, "a short column was accepted");
            assert_eq!(store.len(), n);
            for i in 0..n {
                let s = store.get(i).expect("every sphere is there");
                let given: [f32; 8] =
                    std::array::from_fn(|k| cols.get(k).map_or(1.0, |c: &Vec<f32>| c[i]));
                let (c, v) = (s.centre(), s.velocity());
                let read = [c.x, c.y, c.z, v.x, v.y, v.z, s.radius(), s.mass()];
                assert_eq!(
                    given.map(f32::to_bits),
                    read.map(f32::to_bits),
                    "sphere {i} does not read back bit for bit"
                );
            }
        }
        Err(StoreError::LengthMismatch {
            expected, found, ..
        }) => {
            // The first column (`x`) sets the length the others are held to.
            let (long, short_len) = if short == 0 {
                (found, expected)
            } else {
                (expected, found)
            };
            assert!(short < width && n > 0 && long == n && short_len + 1 == n);
        }
        Err(StoreError::Invalid { index, .. }) => {
            assert!(index < n);
            let bad = (0..width).any(|k| !cols[k][index].is_finite())
                || cols[6][index] < 0.0
                || (with_mass && cols[7][index] <= 0.0);
            assert!(bad, "sphere {index} was refused but its fields are valid");
        }
        Err(e) => panic!("from_columns returned {e}"),
    }
}

/// The next f32 from the input (0 once it runs out).
fn take(data: &mut &[u8]) -> f32 {
    let (head, rest) = data.split_at(data.len().min(4));
    *data = rest;
    let mut b = [0u8; 4];
    b[..head.len()].copy_from_slice(head);
    f32::from_le_bytes(b)
}

fn take3(data: &mut &[u8]) -> [f32; 3] {
    [take(data), take(data), take(data)]
}

/// The batch entry point's answer for the pair (`zip_times` or `static_times`), or `None` for
/// a miss (`+∞`); never NaN.
fn batch_time(sphere: &Sphere, other: &Shape, options: QueryOptions) -> Option<f32> {
    let store = SphereStore::from_spheres(&[*sphere]);
    let mut out = [f32::NAN];
    match other {
        Shape::Sphere(b) => zip_times(&store, &SphereStore::from_spheres(&[*b]), options, &mut out),
        other => {
            let shape = Static::try_from(*other).expect("a static shape");
            static_times_any(&store, &shape, options, &mut out)
        }
    }
    .expect("one slot for one pair");
    let t = out[0];
    assert!(
        !t.is_nan(),
        "NaN for valid input: {sphere:?} against {other:?}"
    );
    (t != f32::INFINITY).then_some(t)
}

/// The range tests/narrow_differential.rs draws from, where its criterion is checked: every
/// body within 1e5 + 100 of the origin and within 400 of the moving sphere, velocity
/// components up to 10, non-zero components at least 1e-6 in size, radii 0 or from 0.01 to
/// 10 (containers 20 to 300), windows 1, 10, 100 or none. Outside it the guarantees of [`kernels`] still hold, with the accuracy of
/// docs/derivations/range.md.
fn in_tested_range(sphere: &Sphere, other: &Shape, t_max: f32) -> bool {
    // Uniform draws put no weight below 1e-6 in size: such components (down to subnormals)
    // are docs/derivations/range.md's domain (its own tests), not this criterion's.
    let sized = |x: f32, max: f32| x == 0.0 || (1e-6..=max).contains(&x.abs());
    let near = |p: glam::Vec3| {
        p.to_array().iter().all(|&x| sized(x, 1.001e5)) && p.distance(sphere.centre()) <= 400.0
    };
    let speed = |v: glam::Vec3| v.to_array().iter().all(|&x| sized(x, 10.0));
    let radius = |r: f32| r == 0.0 || (0.01..=10.0).contains(&r);
    let body = |s: &Sphere| near(s.centre()) && speed(s.velocity()) && radius(s.radius());
    let shape = match other {
        Shape::Sphere(b) => body(b),
        Shape::Plane(p) => near(p.point()),
        Shape::Cylinder(c) => near(c.point()) && radius(c.radius()),
        Shape::Container(c) => near(c.centre()) && (20.0..=300.0).contains(&c.radius()),
        _ => false,
    };
    body(sphere) && shape && [1.0, 10.0, 100.0, f32::INFINITY].contains(&t_max)
}

/// Arbitrary f32 bit patterns for one pair (the first byte picks the kind: sphere–sphere,
/// –plane, –cylinder, –container) and a window, in every accuracy mode through the public
/// batch entry points: for every input the constructors accept, never a panic, never NaN, a
/// time within `[0, t_max]` or none. In the range the differential tests cover
/// (tests/narrow_differential.rs), the time agrees with the f64 reference within the
/// rounding-error model of tests/common (docs/derivations/accuracy.md), and hit/miss agrees
/// outside its bands of ill-conditioning: the same criterion, not a looser one.
pub fn kernels(data: &[u8]) {
    let Some((&kind, mut data)) = data.split_first() else {
        return;
    };
    let Ok(sphere) = Sphere::new(take3(&mut data), take3(&mut data), take(&mut data), 1.0) else {
        return;
    };
    let other = match kind % 4 {
        0 => Sphere::new(take3(&mut data), take3(&mut data), take(&mut data), 1.0)
            .map(Shape::Sphere)
            .ok(),
        1 => Plane::new(take3(&mut data), take3(&mut data))
            .map(Shape::Plane)
            .ok(),
        2 => Cylinder::new(take3(&mut data), take3(&mut data), take(&mut data))
            .map(Shape::Cylinder)
            .ok(),
        _ => Container::new(take3(&mut data), take(&mut data))
            .map(Shape::Container)
            .ok(),
    };
    let Some(other) = other else {
        return;
    };
    let t_max = take(&mut data);
    for mode in Accuracy::ALL {
        let Ok(options) = QueryOptions::new(t_max, mode) else {
            assert!(
                t_max.is_nan() || t_max < 0.0,
                "the window [0, {t_max}] was refused"
            );
            return;
        };
        let time = batch_time(&sphere, &other, options);
        if let Some(t) = time {
            assert!(
                (0.0..=t_max).contains(&t),
                "{mode}: t = {t} outside [0, {t_max}] for {sphere:?} against {other:?}"
            );
        }
        if in_tested_range(&sphere, &other, t_max) {
            let pair = Pair { sphere, other };
            let reference = pair.time_of_impact(f64::from(t_max));
            let m = model(&pair, mode, f64::from(t_max));
            match (reference, time) {
                // Inside the band a container's answer may switch between its root and t = 0
                // (tests/narrow_differential.rs `check`; reference::quadratic::in_contact_now).
                (Some(r), Some(k)) if m.ambiguous && (r == 0.0) != (k == 0.0) => {}
                (Some(r), Some(k)) => assert!(
                    (f64::from(k) - r).abs() <= m.dt,
                    "{mode}: t = {k} vs reference {r}: beyond the bound {:e}\n{pair:?}",
                    m.dt
                ),
                (None, None) => {}
                (r, k) => assert!(
                    m.ambiguous,
                    "{mode}: hit/miss differs outside the band: reference {r:?}, kernel {k:?} \
                     (q = {:e}, δq = {:e})\n{pair:?}",
                    m.q, m.dq
                ),
            }
        }
    }
}

/// A periodic gas of 24 spheres, and a checkpoint of it after some collisions.
fn world_and_checkpoint() -> &'static (World, Vec<u8>) {
    static CELL: OnceLock<(World, Vec<u8>)> = OnceLock::new();
    CELL.get_or_init(|| {
        let mut world = World::default();
        generate::periodic_gas(&mut world, 24, 0.2, 0.5, 1.0, 5).expect("a valid gas");
        let mut sim = Simulation::new(world.clone()).expect("a valid world");
        sim.advance_to(0.5).expect("a short run");
        let bytes = sim.checkpoint();
        (world, bytes)
    })
}

/// FNV-1a, as the checkpoint format's trailer (src/sim/checkpoint.rs).
fn checksum(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Bytes → `Simulation::restore` into a small world, and one step if restored: never a
/// panic. Inputs whose first byte is even are taken as they are; the others overwrite part
/// of a real checkpoint of that world (at an offset the next two bytes give, cut there if
/// bit 1 is set) and carry a correct checksum, so that the fuzzer reaches the decoding of
/// every field behind the checksum.
pub fn checkpoint(data: &[u8]) {
    let (world, valid) = world_and_checkpoint();
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let bytes = if mode & 1 == 0 {
        rest.to_vec()
    } else {
        let Some((offset, patch)) = rest.split_first_chunk::<2>() else {
            return;
        };
        let mut body = valid[..valid.len() - 8].to_vec();
        let at = usize::from(u16::from_le_bytes(*offset)) % (body.len() + 1);
        let end = (at + patch.len()).min(body.len());
        body[at..end].copy_from_slice(&patch[..end - at]);
        if mode & 2 == 2 {
            body.truncate(end);
        } else if at + patch.len() > end {
            body.extend_from_slice(&patch[end - at..]);
        }
        let sum = checksum(&body);
        body.extend_from_slice(&sum.to_le_bytes());
        body
    };
    if let Ok(mut sim) = Simulation::restore(world.clone(), &bytes) {
        let t = sim.time();
        if t.is_finite() && t < 1e300 {
            let _ = sim.advance_with(t + 1.0, &mut |_, _| false);
        }
    }
}
