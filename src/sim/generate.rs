//! Generated starts: a gas on an FCC lattice in a periodic box at a packing fraction, random
//! gases in a box or a container, a cubic lattice, a stream fired from a nozzle. Deterministic
//! for a seed; velocities are Maxwell–Boltzmann with zero total momentum, scaled so that the
//! kinetic energy is exactly `3/2 N kT`.

use glam::DVec3;

use super::cells::Cells;
use super::model::{Boundary, SimError, SphereState, World};
use crate::rng::Rng;

/// `x` to four significant digits, for a derived quantity in a message.
fn round4(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let scale = 10f64.powi(3 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// A generator's refusal of one parameter.
fn refuse<T>(generator: &'static str, field: &'static str, problem: String) -> Result<T, SimError> {
    Err(SimError::Generate {
        generator,
        field,
        problem,
    })
}

/// A generator's radius: finite, greater than 0, and within the range the engine computes in
/// (`MIN_MAGNITUDE` to `MAX_MAGNITUDE`).
fn check_radius(generator: &'static str, radius: f64) -> Result<(), SimError> {
    let problem = if !(radius > 0.0 && radius.is_finite()) {
        "must be finite and greater than 0"
    } else if !super::in_range(radius) {
        super::OUTSIDE_RANGE
    } else {
        return Ok(());
    };
    refuse(
        generator,
        "radius",
        format!("radius = {radius:?} {problem}"),
    )
}

/// A generator's spacing between neighbours: at least a diameter, so that none overlap.
fn check_spacing(generator: &'static str, spacing: f64, radius: f64) -> Result<(), SimError> {
    if spacing >= 2.0 * radius && spacing.is_finite() {
        return Ok(());
    }
    refuse(
        generator,
        "spacing",
        format!(
            "spacing = {spacing:?} must be at least a diameter ({:?})",
            2.0 * radius
        ),
    )
}

/// An empty vector with room for `n` items, or the memory error (never an abort).
pub(crate) fn room<T>(n: usize, what: &str) -> Result<Vec<T>, SimError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n).map_err(|_| SimError::Memory {
        what: format!("{what} ({n} items)"),
        bytes: n.saturating_mul(std::mem::size_of::<T>()),
    })?;
    Ok(v)
}

/// Gaussian velocities for unit-free masses, zero total momentum, kinetic energy `3/2 N kT`.
///
/// ```
/// use glam::DVec3;
/// use spheresweep::sim::{SphereState, generate::thermal_velocities};
/// let (centre, velocity) = (DVec3::ZERO, DVec3::ZERO);
/// let at_rest = SphereState { centre, velocity, radius: 0.5, mass: 2.0, material: 0 };
/// let mut spheres = vec![at_rest; 100];
/// thermal_velocities(&mut spheres, 1.5, 7);
/// let energy: f64 = spheres.iter().map(|s| 0.5 * s.mass * s.velocity.length_squared()).sum();
/// let momentum: DVec3 = spheres.iter().map(|s| s.mass * s.velocity).sum();
/// assert!((energy - 1.5 * 100.0 * 1.5).abs() < 1e-9 * energy && momentum.length() < 1e-9);
/// ```
pub fn thermal_velocities(spheres: &mut [SphereState], kt: f64, seed: u64) {
    let mut rng = Rng::new(seed ^ 0x005e_ed0f_7e3f);
    let n = spheres.len();
    if n == 0 {
        return;
    }
    let mut p = DVec3::ZERO;
    let mut mass = 0.0;
    for s in spheres.iter_mut() {
        s.velocity = DVec3::new(rng.normal(), rng.normal(), rng.normal()) * (kt / s.mass).sqrt();
        p += s.velocity * s.mass;
        mass += s.mass;
    }
    let drift = p / mass;
    let mut ke = 0.0;
    for s in spheres.iter_mut() {
        if n > 1 {
            s.velocity -= drift;
        }
        ke += 0.5 * s.mass * s.velocity.length_squared();
    }
    if ke > 0.0 {
        let scale = (1.5 * n as f64 * kt / ke).sqrt();
        for s in spheres.iter_mut() {
            s.velocity *= scale;
        }
    }
}

/// `n` spheres of radius `radius` (mass 1, material 0) on the sites of an FCC lattice filling a
/// periodic cube at packing fraction `phi` (sites beyond `n` left empty, chosen at random), with
/// thermal velocities at `kt`. Sets `world.boundary` to the periodic box.
///
/// ```
/// use spheresweep::sim::{World, generate};
/// let mut world = World::default();
/// generate::periodic_gas(&mut world, 4000, 0.25, 0.5, 1.0, 1)?;
/// assert_eq!(world.spheres.len(), 4000);
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
pub fn periodic_gas(
    world: &mut World,
    n: usize,
    phi: f64,
    radius: f64,
    kt: f64,
    seed: u64,
) -> Result<(), SimError> {
    // FCC touches at φ = π/(3√2) ≈ 0.7405 when every site is filled.
    const G: &str = "periodic gas";
    if n == 0 || n > 1 << 28 {
        return refuse(G, "n", format!("n = {n} must be in 1..=2^28"));
    }
    if !(phi > 0.0 && phi < 0.7) {
        return refuse(
            G,
            "phi",
            format!("phi = {phi:?} must be above 0 and below 0.7"),
        );
    }
    check_radius(G, radius)?;
    if !(kt >= 0.0 && kt.is_finite()) {
        return refuse(
            G,
            "temperature",
            format!("temperature = {kt:?} must be finite and at least 0"),
        );
    }
    let m = ((n as f64 / 4.0).cbrt().ceil() as usize).max(1);
    let sphere_volume = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    let side = (n as f64 * sphere_volume / phi).cbrt();
    // The engine needs a box of at least three diameters a side (its cells).
    let needed = 3.0 * 2.0 * radius * (1.0 + 1e-6);
    if side < needed {
        let fewest = (needed.powi(3) * phi / sphere_volume).ceil();
        return refuse(
            G,
            "n",
            format!(
                "the box side from n = {n} and phi = {phi:?} is {}, less than three diameters \
                 ({:?}): use more spheres (at least {fewest}) or a lower phi",
                round4(side),
                6.0 * radius
            ),
        );
    }
    let a = side / m as f64;
    if a / std::f64::consts::SQRT_2 < 2.0 * radius * (1.0 + 1e-9) {
        return refuse(
            G,
            "phi",
            format!("packing fraction {phi:?} is too dense for {n} spheres on {m}³ FCC cells"),
        );
    }
    let mut sites = room(4 * m * m * m, "a periodic gas's lattice sites")?;
    let basis = [
        [0.0, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.5, 0.0, 0.5],
        [0.0, 0.5, 0.5],
    ];
    for x in 0..m {
        for y in 0..m {
            for z in 0..m {
                for b in basis {
                    let p = DVec3::new(
                        x as f64 + b[0] + 0.25,
                        y as f64 + b[1] + 0.25,
                        z as f64 + b[2] + 0.25,
                    );
                    sites.push(p * a);
                }
            }
        }
    }
    let mut rng = Rng::new(seed);
    // Keep n sites: a partial Fisher–Yates shuffle chooses which.
    for k in 0..n {
        let pick = k + ((rng.unit() * (sites.len() - k) as f64) as usize).min(sites.len() - k - 1);
        sites.swap(k, pick);
    }
    sites.truncate(n);

    let mut spheres: Vec<SphereState> = sites
        .into_iter()
        .map(|centre| SphereState {
            centre,
            velocity: DVec3::ZERO,
            radius,
            mass: 1.0,
            material: 0,
        })
        .collect();
    thermal_velocities(&mut spheres, kt, seed);
    world.spheres.extend(spheres);
    world.boundary = Boundary::Periodic {
        size: DVec3::splat(side),
    };
    Ok(())
}

/// `n` non-overlapping spheres placed at random (random sequential addition) with centres in
/// the region `inside` accepts within the box `[lo, hi]`, random directions at `speed`.
/// Fails, naming the count reached, if 1000 attempts in a row find no room.
///
/// ```
/// use glam::DVec3;
/// use spheresweep::sim::generate::random_spheres;
/// // 50 spheres of radius 0.5 in a ball of radius 5 about the origin, at speed 2.
/// let inside = |p: DVec3| p.length() < 4.5;
/// let (lo, hi) = (DVec3::splat(-5.0), DVec3::splat(5.0));
/// let spheres = random_spheres(lo, hi, &inside, 50, 0.5, 2.0, 0, 1)?;
/// for (i, a) in spheres.iter().enumerate() {
///     assert!(a.centre.length() < 4.5 && (a.velocity.length() - 2.0).abs() < 1e-12);
///     assert!(spheres[..i].iter().all(|b| a.centre.distance(b.centre) >= 1.0)); // no overlap
/// }
/// // 100 of them cannot fit in a box of side 2.
/// assert!(random_spheres(DVec3::ZERO, DVec3::splat(2.0), &|_| true, 100, 0.5, 1.0, 0, 1).is_err());
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn random_spheres(
    lo: DVec3,
    hi: DVec3,
    inside: &dyn Fn(DVec3) -> bool,
    n: usize,
    radius: f64,
    speed: f64,
    material: u16,
    seed: u64,
) -> Result<Vec<SphereState>, SimError> {
    const G: &str = "random spheres";
    check_radius(G, radius)?;
    if !speed.is_finite() {
        return refuse(G, "speed", format!("speed = {speed:?} must be finite"));
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return refuse(G, "lo", format!("the region [{lo}, {hi}] must be finite"));
    }
    let mut rng = Rng::new(seed);
    let mut cells = Cells::new(
        lo,
        (hi - lo).max(DVec3::splat(2.0 * radius)),
        2.0 * radius,
        4 * n + 64,
    );
    let mut out: Vec<SphereState> = room(n, "random spheres")?;
    let mut misses = 0;
    while out.len() < n {
        let p = DVec3::new(
            rng.range(lo.x, hi.x),
            rng.range(lo.y, hi.y),
            rng.range(lo.z, hi.z),
        );
        let free = inside(p) && {
            let c = cells.coords_of(p);
            let mut free = true;
            'cells: for d in 0..27 {
                let q = [c[0] + d % 3 - 1, c[1] + d / 3 % 3 - 1, c[2] + d / 9 - 1];
                if (0..3).any(|k| q[k] < 0 || q[k] >= cells.n[k]) {
                    continue;
                }
                for j in cells.members(cells.index(q)) {
                    if out[j as usize].centre.distance_squared(p)
                        < 4.0 * radius * radius * (1.0 + 1e-9)
                    {
                        free = false;
                        break 'cells;
                    }
                }
            }
            free
        };
        if free {
            cells.insert(out.len() as u32, cells.coords_of(p));
            out.push(SphereState {
                centre: p,
                velocity: rng.direction() * speed,
                radius,
                mass: 1.0,
                material,
            });
            misses = 0;
        } else {
            misses += 1;
            if misses > 1000 {
                return refuse(
                    G,
                    "",
                    format!(
                        "no room for sphere {} of {n} after 1000 attempts (too dense for random \
                         placement)",
                        out.len()
                    ),
                );
            }
        }
    }
    Ok(out)
}

/// A stream fired from a nozzle: `n` spheres in a column behind `origin` along `direction`
/// (spacing `spacing` between centres, at least a diameter), each with velocity `speed` along
/// the direction tilted at random by up to `spread` radians, and a random sideways offset of up
/// to `jitter`.
///
/// ```
/// use glam::DVec3;
/// use spheresweep::sim::generate::nozzle;
/// // Ten spheres fired along +x from the origin, straight (no spread, no jitter), 1.5 apart.
/// let jet = nozzle(DVec3::ZERO, DVec3::X, 10, 0.5, 3.0, 1.5, 0.0, 0.0, 0, 1)?;
/// assert!(jet.iter().all(|s| (s.velocity - DVec3::new(3.0, 0.0, 0.0)).length() < 1e-12));
/// // The last one 9 spacings behind, give or take the jitter along the stream, (1.5 − 1)/2.
/// assert!((jet[9].centre.x + 13.5).abs() <= 0.25);
/// assert!(nozzle(DVec3::ZERO, DVec3::X, 10, 0.5, 3.0, 0.9, 0.0, 0.0, 0, 1).is_err()); // overlapping
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn nozzle(
    origin: DVec3,
    direction: DVec3,
    n: usize,
    radius: f64,
    speed: f64,
    spacing: f64,
    spread: f64,
    jitter: f64,
    material: u16,
    seed: u64,
) -> Result<Vec<SphereState>, SimError> {
    const G: &str = "nozzle";
    let dir = direction.normalize_or_zero();
    if !direction.is_finite() || dir == DVec3::ZERO {
        return refuse(
            G,
            "direction",
            if direction.is_finite() {
                "direction = [0, 0, 0] has no direction".to_string()
            } else {
                format!("direction = {direction} must be finite")
            },
        );
    }
    check_radius(G, radius)?;
    if !speed.is_finite() {
        return refuse(G, "speed", format!("speed = {speed:?} must be finite"));
    }
    check_spacing(G, spacing, radius)?;
    if !(jitter >= 0.0 && jitter < spacing) {
        return refuse(
            G,
            "jitter",
            format!("jitter = {jitter:?} must be at least 0 and below the spacing ({spacing:?})"),
        );
    }
    if !spread.is_finite() {
        return refuse(G, "spread", format!("spread = {spread:?} must be finite"));
    }
    let mut out = room(n, "a nozzle's spheres")?;
    let mut rng = Rng::new(seed);
    let side = rng.perpendicular(dir);
    let up = dir.cross(side);
    // Columns spaced a diameter apart sideways never overlap: the jitter stays within half
    // the spacing minus a diameter along the stream.
    let along_jitter = ((spacing - 2.0 * radius) / 2.0).max(0.0);
    out.extend((0..n).map(|k| {
        let angle = rng.unit() * std::f64::consts::TAU;
        let off = (side * angle.cos() + up * angle.sin()) * (jitter * rng.unit());
        let centre = origin - dir * (k as f64 * spacing)
            + dir * rng.range(-along_jitter, along_jitter)
            + off;
        let tilt = spread * rng.unit().sqrt();
        let a2 = rng.unit() * std::f64::consts::TAU;
        let v = (dir * tilt.cos() + (side * a2.cos() + up * a2.sin()) * tilt.sin()) * speed;
        SphereState {
            centre,
            velocity: v,
            radius,
            mass: 1.0,
            material,
        }
    }));
    Ok(out)
}

/// Spheres on a simple cubic lattice: `counts` per axis from `lo`, `spacing` apart (at least a
/// diameter), random directions at `speed`.
///
/// ```
/// use glam::DVec3;
/// use spheresweep::sim::generate::cubic_lattice;
/// let spheres = cubic_lattice(DVec3::ZERO, [2, 3, 4], 1.5, 0.5, 1.0, 0, 1)?;
/// assert_eq!(spheres.len(), 24);
/// assert_eq!(spheres[1].centre, DVec3::new(1.5, 0.0, 0.0)); // x varies fastest
/// # Ok::<(), spheresweep::sim::SimError>(())
/// ```
pub fn cubic_lattice(
    lo: DVec3,
    counts: [usize; 3],
    spacing: f64,
    radius: f64,
    speed: f64,
    material: u16,
    seed: u64,
) -> Result<Vec<SphereState>, SimError> {
    const G: &str = "lattice";
    check_radius(G, radius)?;
    check_spacing(G, spacing, radius)?;
    if !(lo.is_finite() && speed.is_finite()) {
        let field = if lo.is_finite() { "speed" } else { "lo" };
        return refuse(G, field, format!("{field} must be finite"));
    }
    let count = counts.iter().try_fold(1usize, |a, &c| a.checked_mul(c));
    let mut rng = Rng::new(seed);
    let mut out = room(count.unwrap_or(usize::MAX), "a lattice's spheres")?;
    for z in 0..counts[2] {
        for y in 0..counts[1] {
            for x in 0..counts[0] {
                let centre = lo + DVec3::new(x as f64, y as f64, z as f64) * spacing;
                out.push(SphereState {
                    centre,
                    velocity: rng.direction() * speed,
                    radius,
                    mass: 1.0,
                    material,
                });
            }
        }
    }
    Ok(out)
}
