//! Batch queries from plain Rust slices: one `Vec<f32>` per column, as a file reader, NumPy or
//! Arrow would hand them over.
//!
//! ```sh
//! cargo run --release --example batch_slices            # 200 000 pairs
//! cargo run --example batch_slices -- --small           # 5 000 pairs (what CI runs)
//! cargo run --example batch_slices -- --out DIR         # where results.csv goes
//! ```
//!
//! What it shows, in order:
//!
//! 1. columns `x, y, z, vx, vy, vz, r` → [`SphereStore::from_columns`] (validated once, here);
//! 2. [`batch::zip_times`]: sphere `i` of one store against sphere `i` of the other;
//! 3. [`batch::pair_times`]: an explicit list of index pairs into one store;
//! 4. spheres against a floor, a pillar and a vessel: [`batch::static_times`] (one shape, into a
//!    buffer you own) and [`batch::earliest_static_contacts`] (the earliest of many shapes);
//! 5. what a bad input gives: an error naming the sphere and the field.
//!
//! What it checks (it exits non-zero with the reason if any check fails):
//!
//! - head-on pairs and spheres aimed straight at each shape against their closed forms
//!   (`t = (d − r_a − r_b) / closing speed`), within the `stable` mode's bound for such
//!   well-conditioned times, 18 ulps (docs/derivations/accuracy.md, "Time in ulps");
//! - every batch answer is bit for bit the single-item [`time_of_impact`] of the same pair;
//! - `zip_times` and `pair_times` agree bit for bit, and `earliest_static_contacts` is the
//!   minimum of the per-shape `static_times` (ties to the lowest index);
//! - the bad inputs are refused with messages that name the sphere and the field.

mod common;

use std::fmt::Write as _;
use std::time::Instant;

use common::{Args, check, write_atomic};
use spheresweep::rng::Rng;
use spheresweep::store::Columns;
use spheresweep::{
    Accuracy, Container, Cylinder, Plane, QueryOptions, Shape, SphereStore, batch, time_of_impact,
};

/// One column per field, owned: what a reader of a file or an array library produces.
#[derive(Default)]
struct SphereColumns {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    vx: Vec<f32>,
    vy: Vec<f32>,
    vz: Vec<f32>,
    r: Vec<f32>,
}

impl SphereColumns {
    fn push(&mut self, c: [f32; 3], v: [f32; 3], r: f32) {
        self.x.push(c[0]);
        self.y.push(c[1]);
        self.z.push(c[2]);
        self.vx.push(v[0]);
        self.vy.push(v[1]);
        self.vz.push(v[2]);
        self.r.push(r);
    }

    /// Borrowed views of the columns: no copy until the store is built. No mass column: every
    /// mass is 1.
    fn columns(&self) -> Columns<'_> {
        Columns {
            x: &self.x,
            y: &self.y,
            z: &self.z,
            vx: &self.vx,
            vy: &self.vy,
            vz: &self.vz,
            r: &self.r,
            m: None,
        }
    }
}

/// A head-on pair whose time of impact is known in closed form.
struct HeadOn {
    distance: f32,
    ra: f32,
    rb: f32,
    closing_speed: f32,
}

impl HeadOn {
    /// `t = (d − r_a − r_b) / s`, in f64 from the f32 inputs.
    fn time(&self) -> f64 {
        (f64::from(self.distance) - f64::from(self.ra) - f64::from(self.rb))
            / f64::from(self.closing_speed)
    }
}

/// The `stable` mode's bound on a well-conditioned time: 18 u relative, u = 2⁻²⁴
/// (docs/derivations/accuracy.md, "Time in ulps"), plus half an ulp for rounding the exact time
/// to f32 when it is compared.
fn within_stable_bound(got: f32, exact: f64) -> bool {
    let u = f64::from(f32::EPSILON) / 2.0;
    (f64::from(got) - exact).abs() <= 18.5 * u * exact.abs()
}

fn main() {
    if let Err(message) = run() {
        eprintln!("batch_slices: {message}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = Args::parse("batch_slices")?;
    let n = if args.small { 5_000 } else { 200_000 };
    let options = QueryOptions::new(100.0, Accuracy::Stable).map_err(|e| e.to_string())?;

    // --- Two sets of spheres as plain columns: pair i is a[i] against b[i]. ---------------
    // The first pairs are head-on along x (their times are known exactly); the rest are random
    // spheres in a 20-unit box with velocity components up to 2.
    let head_on: Vec<HeadOn> = (0..8)
        .map(|k| HeadOn {
            distance: 10.0 + 3.0 * k as f32,
            ra: 0.5 + 0.25 * k as f32,
            rb: 1.0,
            closing_speed: 1.5 + 0.5 * k as f32,
        })
        .collect();
    let (mut a, mut b) = (SphereColumns::default(), SphereColumns::default());
    for (k, h) in head_on.iter().enumerate() {
        // Sphere a moves at +s/2, sphere b at −s/2: the closing speed is s.
        let y = 5.0 * k as f32;
        a.push([0.0, y, 0.0], [h.closing_speed / 2.0, 0.0, 0.0], h.ra);
        b.push(
            [h.distance, y, 0.0],
            [-h.closing_speed / 2.0, 0.0, 0.0],
            h.rb,
        );
    }
    let mut rng = Rng::new(16);
    for _ in head_on.len()..n {
        // Partners start within 4 units of each other, so that many of them meet.
        let ca = rng.cube(10.0);
        let cb = ca + rng.cube(4.0);
        for (cols, c) in [(&mut a, ca), (&mut b, cb)] {
            let v = rng.cube(2.0).as_vec3().to_array();
            cols.push(c.as_vec3().to_array(), v, rng.range(0.1, 1.0) as f32);
        }
    }

    // --- Columns → stores: every value validated once, here. ------------------------------
    let store_a = SphereStore::from_columns(&a.columns()).map_err(|e| e.to_string())?;
    let store_b = SphereStore::from_columns(&b.columns()).map_err(|e| e.to_string())?;

    // --- zip_times: a[i] against b[i], into a buffer we own. ------------------------------
    let mut zipped = vec![0.0f32; n];
    batch::zip_times(&store_a, &store_b, options, &mut zipped).map_err(|e| e.to_string())?;
    // Timed on a second call: above 32 768 pairs the first one also starts rayon's threads.
    let start = Instant::now();
    batch::zip_times(&store_a, &store_b, options, &mut zipped).map_err(|e| e.to_string())?;
    let zip_seconds = start.elapsed().as_secs_f64();
    let hits = zipped.iter().filter(|t| t.is_finite()).count();
    println!(
        "zip_times: {n} pairs in {:.2} ms ({:.1} M pairs/s), {hits} meet within t_max = {}",
        zip_seconds * 1e3,
        n as f64 / zip_seconds / 1e6,
        options.t_max()
    );

    for (i, h) in head_on.iter().enumerate() {
        let exact = h.time();
        check(within_stable_bound(zipped[i], exact), || {
            format!(
                "head-on pair {i}: zip_times gave {}, the closed form (d − r_a − r_b)/s is {exact}",
                zipped[i]
            )
        })?;
    }
    println!(
        "  head-on pair 0: t = {} (closed form (10 − 0.5 − 1)/1.5 = {:.7})",
        zipped[0],
        head_on[0].time()
    );

    // --- pair_times: the same pairs as an index list into one store. ----------------------
    // One store holding a then b; pair i is [i, n + i].
    let mut all = SphereColumns::default();
    for cols in [&a, &b] {
        all.x.extend(&cols.x);
        all.y.extend(&cols.y);
        all.z.extend(&cols.z);
        all.vx.extend(&cols.vx);
        all.vy.extend(&cols.vy);
        all.vz.extend(&cols.vz);
        all.r.extend(&cols.r);
    }
    let store_all = SphereStore::from_columns(&all.columns()).map_err(|e| e.to_string())?;
    let pairs: Vec<[u32; 2]> = (0..n as u32).map(|i| [i, n as u32 + i]).collect();
    let mut listed = vec![0.0f32; n];
    batch::pair_times(&store_all, &pairs, options, &mut listed).map_err(|e| e.to_string())?;
    let differ = (0..n)
        .find(|&i| zipped[i].to_bits() != listed[i].to_bits())
        .map(|i| (i, zipped[i], listed[i]));
    check(differ.is_none(), || {
        let (i, z, l) = differ.unwrap();
        format!("pair {i}: zip_times gave {z}, pair_times {l}")
    })?;
    println!("pair_times: the same {n} pairs as an index list, bit for bit the same times");

    // --- Every batch answer is the single-pair query's. -----------------------------------
    for (i, (sa, sb)) in store_a.iter().zip(store_b.iter()).enumerate() {
        let one = time_of_impact(&sa, &Shape::Sphere(sb), options).unwrap_or(f32::INFINITY);
        check(one.to_bits() == zipped[i].to_bits(), || {
            format!(
                "pair {i}: time_of_impact gave {one}, the batch {}",
                zipped[i]
            )
        })?;
    }
    println!("time_of_impact: every one of the {n} pairs, bit for bit the batch's time");

    // --- Spheres against static shapes. ----------------------------------------------------
    // A floor at z = 0, a vertical pillar of radius 1 through (30, 0), a vessel of radius 60
    // centred at the origin. The first three spheres aim straight at one shape each.
    let floor = Plane::new([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]).map_err(|e| e.to_string())?;
    let pillar =
        Cylinder::new([30.0, 0.0, 0.0], [30.0, 0.0, 1.0], 1.0).map_err(|e| e.to_string())?;
    let vessel = Container::new([0.0, 0.0, 0.0], 60.0).map_err(|e| e.to_string())?;
    let mut movers = SphereColumns::default();
    movers.push([-20.0, -20.0, 12.0], [0.0, 0.0, -2.0], 0.5); // floor: (12 − 0.5)/2
    movers.push([20.0, 0.0, 5.0], [2.5, 0.0, 0.0], 0.5); // pillar: (10 − 1 − 0.5)/2.5
    movers.push([0.0, 10.0, 30.0], [0.0, 4.0, 0.0], 1.0); // vessel: |c + v t| = 59
    let aimed = [
        ("floor", (12.0 - 0.5) / 2.0),
        ("pillar", (10.0 - 1.0 - 0.5) / 2.5),
        // (10 + 4t)² + 30² = 59²  ⇒  t = (√(59² − 30²) − 10) / 4.
        ("vessel", ((59.0f64 * 59.0 - 900.0).sqrt() - 10.0) / 4.0),
    ];
    for _ in aimed.len()..n {
        let c = rng.cube(20.0).as_vec3().to_array();
        let v = (rng.cube(1.0) * 3.0).as_vec3().to_array();
        let c = [c[0], c[1], c[2].abs() + 1.0]; // above the floor
        movers.push(c, v, rng.range(0.1, 1.0) as f32);
    }
    let spheres = SphereStore::from_columns(&movers.columns()).map_err(|e| e.to_string())?;

    // One shape at a time, into buffers we own (no allocation in a hot loop).
    let (mut to_floor, mut to_pillar, mut to_vessel) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    batch::static_times(&spheres, &floor, options, &mut to_floor).map_err(|e| e.to_string())?;
    batch::static_times(&spheres, &pillar, options, &mut to_pillar).map_err(|e| e.to_string())?;
    batch::static_times(&spheres, &vessel, options, &mut to_vessel).map_err(|e| e.to_string())?;
    for (k, (shape, exact)) in aimed.iter().enumerate() {
        let got = [to_floor[k], to_pillar[k], to_vessel[k]][k];
        check(within_stable_bound(got, *exact), || {
            format!("sphere {k} aimed at the {shape}: static_times gave {got}, closed form {exact}")
        })?;
        println!("  sphere {k} reaches the {shape} at t = {got} (closed form {exact:.7})");
    }
    let shapes: [(&str, Shape, &[f32]); 3] = [
        ("floor", floor.into(), &to_floor),
        ("pillar", pillar.into(), &to_pillar),
        ("vessel", vessel.into(), &to_vessel),
    ];
    for (name, shape, times) in &shapes {
        for (i, sphere) in spheres.iter().enumerate() {
            let one = time_of_impact(&sphere, shape, options).unwrap_or(f32::INFINITY);
            check(one.to_bits() == times[i].to_bits(), || {
                format!(
                    "sphere {i} against the {name}: time_of_impact gave {one}, static_times {}",
                    times[i]
                )
            })?;
        }
    }
    println!(
        "static_times: {n} spheres against a floor, a pillar and a vessel, each = time_of_impact"
    );

    // The earliest of several shapes of one kind per sphere: three pillars here.
    let pillars = [
        pillar,
        Cylinder::new([-30.0, 0.0, 0.0], [-30.0, 0.0, 1.0], 1.0).map_err(|e| e.to_string())?,
        Cylinder::new([0.0, 30.0, 0.0], [0.0, 30.0, 1.0], 2.0).map_err(|e| e.to_string())?,
    ];
    let earliest = batch::earliest_static_contacts(&spheres, &pillars, options);
    let mut per_pillar = vec![vec![0.0f32; n]; pillars.len()];
    for (p, out) in pillars.iter().zip(&mut per_pillar) {
        batch::static_times(&spheres, p, options, out).map_err(|e| e.to_string())?;
    }
    for (i, hit) in earliest.iter().enumerate() {
        // The minimum over the pillars; on a tie, the lowest index.
        let best = (0..pillars.len()).fold(None, |best: Option<(usize, f32)>, j| {
            let t = per_pillar[j][i];
            match best {
                Some((_, b)) if b <= t => best,
                _ if t.is_finite() => Some((j, t)),
                _ => best,
            }
        });
        let got = hit.map(|h| (h.body.index as usize, h.time));
        check(got == best, || {
            format!(
                "sphere {i}: earliest_static_contacts gave {got:?}, the per-pillar minimum {best:?}"
            )
        })?;
    }
    let hit_pillars = earliest.iter().flatten().count();
    println!(
        "earliest_static_contacts: {hit_pillars} of {n} spheres reach one of 3 pillars; each the minimum of static_times"
    );

    // --- Bad input: the error names the sphere and the field. -----------------------------
    let mut bad = SphereColumns::default();
    for k in 0..6 {
        bad.push([k as f32 * 3.0, 0.0, 0.0], [0.0; 3], 1.0);
    }
    bad.y[3] = f32::NAN;
    let nan = SphereStore::from_columns(&bad.columns())
        .unwrap_err()
        .to_string();
    println!("a NaN in column y of sphere 3:    {nan}");
    check(nan.contains("sphere 3") && nan.contains("centre"), || {
        format!("the NaN error does not name sphere 3 and its centre: {nan:?}")
    })?;
    bad.y[3] = 0.0;
    bad.r[5] = -1.0;
    let negative = SphereStore::from_columns(&bad.columns())
        .unwrap_err()
        .to_string();
    println!("a negative radius for sphere 5:   {negative}");
    check(
        negative.contains("sphere 5") && negative.contains("radius"),
        || format!("the radius error does not name sphere 5 and its radius: {negative:?}"),
    )?;
    bad.r[5] = 1.0;
    bad.vz.pop();
    let short = SphereStore::from_columns(&bad.columns())
        .unwrap_err()
        .to_string();
    println!("column vz one entry short:        {short}");
    check(short.contains("vz"), || {
        format!("the length error does not name column vz: {short:?}")
    })?;

    // --- Results to a file. -----------------------------------------------------------------
    let mut csv = String::from("pair,time\n");
    for (i, t) in zipped.iter().enumerate() {
        writeln!(csv, "{i},{t}").expect("writing to a String");
    }
    let path = write_atomic(&args.out, "results.csv", &csv)?;
    println!("wrote {} (inf: no contact within t_max)", path.display());
    Ok(())
}
