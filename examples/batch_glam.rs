//! Batch queries for a game or physics engine that keeps its bodies as `glam::Vec3` arrays:
//! positions, velocities and an `f32` radius slice.
//!
//! ```sh
//! cargo run --release --example batch_glam              # 20 000 bodies, 120 frames
//! cargo run --example batch_glam -- --small             # 2 000 bodies, 20 frames (CI)
//! cargo run --example batch_glam -- --out DIR           # where frames.csv goes
//! ```
//!
//! The store keeps spheres in blocks of eight per column (what the 8-wide kernels load), so an
//! interleaved `[Vec3]` is copied into it once, when it is built; after that each frame updates
//! it in place with `set_centre` / `set_velocity` (no allocation), and the answers come back as
//! plain `f32` times and `glam::DVec3` contact geometry. Each frame of `1/60 s`:
//!
//! 1. the library's broad phase, [`broad::Grid`] (a uniform grid over the frame's swept boxes,
//!    kept between frames), lists candidate pairs;
//! 2. [`batch::pair_times`] answers every candidate within the frame (`t_max = dt`);
//! 3. [`batch::earliest_static_contacts`] answers every body against the arena's six walls;
//! 4. the game responds: equal-mass elastic bounces at the contact time, with the normal from
//!    [`contact_at`] (the first contact of each body in the frame; later ones wait for the next
//!    frame).
//!
//! At the end one fast probe is swept through the arena with [`batch::earliest_sphere_contact`].
//!
//! What it checks (exit code 1 with the reason on failure):
//!
//! - after the in-place update the store holds exactly the glam values;
//! - in the first frame every pair time is bit for bit the single-pair [`time_of_impact`];
//! - at every reported pair contact the centres, moved in f64 with glam, are `r_a + r_b` apart
//!   within the `stable` mode's geometric bound `8u (coordinates + D) + V u t`
//!   (docs/derivations/accuracy.md, "Where the bodies are at the reported time"; u = 2⁻²⁴);
//!   A contact deferred from an earlier frame is reported at `t = 0` with the bodies already
//!   overlapping (a game's simplification, not the library's): those are counted and only
//!   checked to be touching or overlapping;
//! - the probe's earliest contact is the minimum of [`batch::one_against_times`].

mod common;

use std::fmt::Write as _;
use std::time::Instant;

use common::{Args, check, write_atomic};
use glam::{DVec3, Vec3};
use spheresweep::broad::{Grid, GridOptions};
use spheresweep::contact::contact_at;
use spheresweep::rng::Rng;
use spheresweep::{
    Accuracy, Plane, QueryOptions, Shape, ShapeKind, Sphere, SphereStore, batch, time_of_impact,
};

/// Half the arena's side (metres); the arena is `[-H, H]² × [0, 10]`.
const H: f32 = 50.0;
const HEIGHT: f32 = 10.0;
/// One frame.
const DT: f32 = 1.0 / 60.0;

/// The game's state: plain glam arrays, as an engine would keep them.
struct Bodies {
    position: Vec<Vec3>,
    velocity: Vec<Vec3>,
    radius: Vec<f32>,
}

fn main() {
    if let Err(message) = run() {
        eprintln!("batch_glam: {message}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse("batch_glam")?;
    let (n, frames) = if args.small {
        (2_000, 20)
    } else {
        (20_000, 120)
    };
    let frame = QueryOptions::new(DT, Accuracy::Stable).map_err(|e| e.to_string())?;

    // The game's bodies in glam arrays: on random sites of a lattice 1.5 m apart, jittered by
    // up to 0.15 m, radii up to 0.6 m, so that none overlaps another or a wall at the start.
    let mut rng = Rng::new(33);
    let spacing = 1.5f32;
    let per_side = (2.0 * H / spacing) as usize - 1;
    let layers = (HEIGHT / spacing) as usize - 1;
    let mut sites: Vec<Vec3> = (0..per_side * per_side * layers)
        .map(|k| {
            let (x, y, z) = (
                k % per_side,
                k / per_side % per_side,
                k / (per_side * per_side),
            );
            Vec3::new(-H, -H, 0.0)
                + spacing * Vec3::new(x as f32 + 1.0, y as f32 + 1.0, z as f32 + 1.0)
        })
        .collect();
    if sites.len() < n {
        return Err(format!(
            "{n} bodies do not fit on the {} lattice sites",
            sites.len()
        ));
    }
    for k in 0..n {
        // A partial Fisher–Yates shuffle: the first n sites, at random.
        let last = sites.len() - 1;
        let pick = k + (rng.unit() * (sites.len() - k) as f64) as usize;
        sites.swap(k, pick.min(last));
    }
    let mut bodies = Bodies {
        position: Vec::with_capacity(n),
        velocity: Vec::with_capacity(n),
        radius: Vec::with_capacity(n),
    };
    for &site in &sites[..n] {
        let r = rng.range(0.2, 0.6) as f32;
        let p = site + rng.cube(0.15).as_vec3();
        bodies.position.push(p);
        bodies.velocity.push(rng.cube(4.0).as_vec3());
        bodies.radius.push(r);
    }

    // Built once: the one copy from interleaved Vec3s into the store's blocks.
    let mut store = SphereStore::with_capacity(n);
    for i in 0..n {
        let (p, v, r) = (bodies.position[i], bodies.velocity[i], bodies.radius[i]);
        store.push(
            &Sphere::new(p.to_array(), v.to_array(), r, 1.0)
                .map_err(|e| format!("body {i}: {e}"))?,
        );
    }

    // The arena's walls, normals pointing inwards.
    let walls = [
        (Vec3::new(0.0, 0.0, 0.0), Vec3::Z),
        (Vec3::new(0.0, 0.0, HEIGHT), Vec3::NEG_Z),
        (Vec3::new(-H, 0.0, 0.0), Vec3::X),
        (Vec3::new(H, 0.0, 0.0), Vec3::NEG_X),
        (Vec3::new(0.0, -H, 0.0), Vec3::Y),
        (Vec3::new(0.0, H, 0.0), Vec3::NEG_Y),
    ]
    .map(|(point, normal)| Plane::new(point.to_array(), normal.to_array()));
    let walls: Vec<Plane> = walls
        .into_iter()
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;

    let u = f64::from(f32::EPSILON) / 2.0;
    let (mut pairs, mut times) = (Vec::new(), Vec::new());
    let (mut kernel_seconds, mut pair_contacts, mut wall_contacts, mut candidates) =
        (0.0f64, 0u64, 0u64, 0u64);
    let mut broad_seconds = 0.0f64;
    let mut grid = Grid::new(); // reused: a scene that moved a little re-sorts quickly
    let mut deferred = 0u64; // contacts reported at t = 0, the bodies already overlapping
    let mut csv = String::from("frame,candidate_pairs,pair_contacts,wall_contacts\n");
    for f in 0..frames {
        // 1. This frame's state into the store, in place.
        for i in 0..n {
            store
                .set_centre(i, bodies.position[i].to_array())
                .and_then(|()| store.set_velocity(i, bodies.velocity[i].to_array()))
                .map_err(|e| format!("frame {f}, body {i}: {e}"))?;
        }
        if f == 0 {
            let same = (0..n).all(|i| {
                let s = store.get(i).expect("i < n");
                s.centre() == bodies.position[i] && s.velocity() == bodies.velocity[i]
            });
            check(same, || {
                "the store does not hold the glam values after set_centre / set_velocity".into()
            })?;
        }

        // 2. Candidate pairs from the game's broad phase, answered in one batch.
        let start = Instant::now();
        grid.build(&store, DT, GridOptions::default());
        // The grid lists pairs as positions in its cell order; order[] maps them to bodies.
        let order = grid.order();
        pairs.clear();
        pairs.extend(grid.pairs().iter().map(|&[p, q]| {
            let (i, j) = (order[p as usize], order[q as usize]);
            [i.min(j), i.max(j)]
        }));
        broad_seconds += start.elapsed().as_secs_f64();
        times.clear();
        times.resize(pairs.len(), 0.0);
        let start = Instant::now();
        batch::pair_times(&store, &pairs, frame, &mut times).map_err(|e| e.to_string())?;
        let to_walls = batch::earliest_static_contacts(&store, &walls, frame);
        kernel_seconds += start.elapsed().as_secs_f64();
        candidates += pairs.len() as u64;

        if f == 0 {
            for (k, &[i, j]) in pairs.iter().enumerate() {
                let (a, b) = (
                    store.get(i as usize).unwrap(),
                    store.get(j as usize).unwrap(),
                );
                let one = time_of_impact(&a, &Shape::Sphere(b), frame).unwrap_or(f32::INFINITY);
                check(one.to_bits() == times[k].to_bits(), || {
                    format!(
                        "frame 0, pair {i}–{j}: time_of_impact {one}, pair_times {}",
                        times[k]
                    )
                })?;
            }
        }

        // 3. Respond: each body's first contact of the frame, earliest first.
        let mut hits: Vec<(f32, usize)> = (0..pairs.len())
            .filter(|&k| times[k].is_finite())
            .map(|k| (times[k], k))
            .collect();
        hits.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut moved_at = vec![None::<f32>; n]; // when a body's velocity changed this frame
        let mut frame_pairs = 0;
        for (t, k) in hits {
            let [i, j] = pairs[k].map(|x| x as usize);
            if moved_at[i].is_some() || moved_at[j].is_some() {
                continue; // its trajectory already changed: the next frame asks again
            }
            let (a, b) = (store.get(i).unwrap(), store.get(j).unwrap());
            let contact = contact_at(&a, &Shape::Sphere(b), f64::from(t));
            // The centres at t, moved by us in f64 with glam, are r_a + r_b apart.
            let (ca, cb) = (
                a.centre().as_dvec3() + a.velocity().as_dvec3() * f64::from(t),
                b.centre().as_dvec3() + b.velocity().as_dvec3() * f64::from(t),
            );
            let d = f64::from(a.radius() + b.radius());
            let coords = ca.abs().max_element().max(cb.abs().max_element());
            let speed = (a.velocity() - b.velocity()).as_dvec3().length();
            let bound = 8.0 * u * (coords + d) + speed * u * f64::from(t);
            let gap = (ca - cb).length() - d;
            if t == 0.0 && gap < 0.0 {
                deferred += 1;
            }
            let touching = if t == 0.0 {
                gap <= bound
            } else {
                gap.abs() <= bound
            };
            check(touching, || {
                format!(
                    "frame {f}, pair {i}–{j} at t = {t}: the centres are {gap:e} from touching, bound {bound:e}"
                )
            })?;
            // Equal masses, elastic: exchange the velocity components along the normal.
            let n_hat = contact.normal.as_vec3(); // pushes a away from b
            let (va, vb) = (bodies.velocity[i], bodies.velocity[j]);
            let exchange = (va - vb).dot(n_hat) * n_hat;
            if (va - vb).dot(n_hat) < 0.0 {
                bodies.velocity[i] = va - exchange;
                bodies.velocity[j] = vb + exchange;
            }
            moved_at[i] = Some(t);
            moved_at[j] = Some(t);
            frame_pairs += 1;
        }
        let mut frame_walls = 0;
        for (i, hit) in to_walls.iter().enumerate() {
            let Some(hit) = hit else { continue };
            if moved_at[i].is_some() {
                continue;
            }
            let normal = walls[hit.body.index as usize].normal();
            let v = bodies.velocity[i];
            if v.dot(normal) < 0.0 {
                bodies.velocity[i] = v - 2.0 * v.dot(normal) * normal;
                moved_at[i] = Some(hit.time);
                frame_walls += 1;
            }
        }
        // 4. Advance: straight to the contact with the old velocity, then on with the new one.
        for (i, (stored, moved)) in store.iter().zip(&moved_at).enumerate() {
            let t = moved.unwrap_or(DT);
            bodies.position[i] += stored.velocity() * t + bodies.velocity[i] * (DT - t);
        }
        pair_contacts += frame_pairs;
        wall_contacts += frame_walls;
        writeln!(csv, "{f},{},{frame_pairs},{frame_walls}", pairs.len()).expect("a String");
    }

    println!(
        "{n} bodies, {frames} frames of {DT:.4} s: {candidates} candidate pairs, {pair_contacts} pair and {wall_contacts} wall contacts answered ({deferred} deferred from an earlier frame)"
    );
    println!(
        "per frame: kernels {:.2} ms (pair_times on the candidates, every body against the six walls), broad phase {:.2} ms",
        kernel_seconds * 1e3 / frames as f64,
        broad_seconds * 1e3 / frames as f64
    );
    check(pair_contacts > 0 && wall_contacts > 0, || {
        format!("the scene should have pair and wall contacts: {pair_contacts} and {wall_contacts}")
    })?;

    // A fast probe swept through the arena: its earliest contact with any body, with geometry.
    let probe =
        Sphere::new([-H + 1.0, 0.0, 5.0], [60.0, 0.5, 0.0], 0.5, 1.0).map_err(|e| e.to_string())?;
    for i in 0..n {
        store
            .set_centre(i, bodies.position[i].to_array())
            .map_err(|e| e.to_string())?;
        store
            .set_velocity(i, bodies.velocity[i].to_array())
            .map_err(|e| e.to_string())?;
    }
    let window = QueryOptions::new(2.0, Accuracy::Stable).map_err(|e| e.to_string())?;
    let hit = batch::earliest_sphere_contact(&probe, &store, window.with_geometry(true));
    let mut all = vec![0.0f32; n];
    batch::one_against_times(&probe, &store, window, &mut all).map_err(|e| e.to_string())?;
    let first = all
        .iter()
        .enumerate()
        .filter(|(_, t)| t.is_finite())
        .min_by(|x, y| x.1.total_cmp(y.1).then(x.0.cmp(&y.0)));
    check(
        hit.map(|h| (h.body.index as usize, h.time)) == first.map(|(j, &t)| (j, t)),
        || {
            format!(
                "the probe: earliest_sphere_contact {hit:?}, minimum of one_against_times {first:?}"
            )
        },
    )?;
    if let Some(hit) = hit {
        let g = hit.geometry.expect("asked for geometry");
        let (point, normal): (DVec3, DVec3) = (g.point, g.normal);
        println!(
            "probe: first hits {} {} at t = {:.4} s, at {:.3} with normal {:.3}",
            ShapeKind::Sphere,
            hit.body.index,
            hit.time,
            point.as_vec3(),
            normal.as_vec3()
        );
    } else {
        println!("probe: crosses the arena without touching a body");
    }

    let path = write_atomic(&args.out, "frames.csv", &csv)?;
    println!("wrote {}", path.display());
    Ok(())
}
