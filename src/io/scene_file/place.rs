//! Sphere placement: the `[[generate]]` blocks, each checked and handed to its generator in
//! `sim::generate`; a `random` block is kept clear of the spheres already placed and of the
//! static shapes.

use glam::DVec3;

use super::locate::Seg::{At, Key};
use super::locate::show;
use super::{GenerateKind, GenerateTable, MAX_SPHERES, SceneFile, SceneFileError};
use crate::sim::{Boundary, SimError, SphereState, World, generate};

impl SceneFile {
    pub(super) fn generated(
        &self,
        world: &mut World,
        mut periodic_size: Option<DVec3>,
        base_seed: u64,
    ) -> Result<(), SceneFileError> {
        let mut total = world.spheres.len();
        for (b, g) in self.generate.iter().enumerate() {
            let item = format!("generate {b} ({})", g.kind.name());
            let block = [Key("generate"), At(b)];
            let path = |k| [Key("generate"), At(b), Key(k)];
            // Fields that do not belong to the kind, then the ones it needs.
            let (required, optional) = g.kind.fields();
            for f in g.set_fields() {
                if !required.contains(&f) && !optional.contains(&f) {
                    return Err(self.item_error(
                        &item,
                        &path(f),
                        format!(
                            "`{f}` does not apply to kind = {:?} (it takes {}; and material, seed, mass)",
                            g.kind.name(),
                            required
                                .iter()
                                .chain(optional)
                                .copied()
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ));
                }
            }
            let set = g.set_fields();
            if let Some(missing) = required.iter().find(|f| !set.contains(f)) {
                return Err(self.item_error(
                    &item,
                    &path("kind"),
                    format!(
                        "kind = {:?} needs `{missing}` (it needs {})",
                        g.kind.name(),
                        required.join(", ")
                    ),
                ));
            }
            let count = g.count().unwrap_or(usize::MAX);
            if count == 0 || count > MAX_SPHERES - total.min(MAX_SPHERES) {
                let field = if g.kind == GenerateKind::Lattice {
                    "counts"
                } else {
                    "n"
                };
                return Err(self.item_error(
                    &item,
                    &path(field),
                    format!(
                        "{field} must give between 1 and {} spheres in all (this block: {})",
                        MAX_SPHERES,
                        g.count()
                            .map_or("more than 2^64".to_string(), |c| c.to_string())
                    ),
                ));
            }
            total += count;
            let material = self.origin.material_index(
                &world.materials,
                g.material.as_deref(),
                &item,
                &path("material"),
            )?;
            let mass = g.mass.unwrap_or(1.0);
            if !(mass.is_finite() && mass > 0.0) {
                return Err(self.item_error(
                    &item,
                    &path("mass"),
                    format!("mass = {mass:?} must be finite and greater than 0"),
                ));
            }
            let seed = g.seed.unwrap_or(base_seed.wrapping_add(b as u64));
            let sim = |e: SimError| self.generator_error(&item, &block, e);
            // Every required field is set (checked above); `req` reads one.
            let req = |v: Option<f64>| v.unwrap_or(f64::NAN);
            let req3 = |v: Option<[f64; 3]>| DVec3::from_array(v.unwrap_or([f64::NAN; 3]));
            let radius = req(g.radius);
            let mut spheres = match g.kind {
                GenerateKind::PeriodicGas => {
                    if world.boundary != (Boundary::Periodic { size: DVec3::ZERO })
                        || periodic_size.is_some()
                    {
                        let problem = if matches!(world.boundary, Boundary::Periodic { .. }) {
                            "the periodic box is already set (by [boundary] size or an earlier periodic_gas): a periodic_gas sets it from n and phi"
                        } else {
                            "periodic_gas needs [boundary] kind = \"periodic\" (without size: the gas sets it)"
                        };
                        return Err(self.item_error(&item, &block, problem.into()));
                    }
                    let mut tmp = World::default();
                    let kt = g.temperature.unwrap_or(1.0);
                    generate::periodic_gas(&mut tmp, count, req(g.phi), radius, kt, seed)
                        .map_err(sim)?;
                    world.boundary = tmp.boundary;
                    if let Boundary::Periodic { size } = tmp.boundary {
                        periodic_size = Some(size);
                    }
                    // The generator's masses are 1: keep kT for the mass asked for.
                    let scale = 1.0 / mass.sqrt();
                    for s in &mut tmp.spheres {
                        s.velocity *= scale;
                    }
                    tmp.spheres
                }
                GenerateKind::Random => {
                    self.random_block(g, b, &item, world, periodic_size, material, seed)?
                }
                GenerateKind::Nozzle => {
                    let spacing = g.spacing.unwrap_or(2.2 * radius);
                    generate::nozzle(
                        req3(g.origin),
                        req3(g.direction),
                        count,
                        radius,
                        req(g.speed),
                        spacing,
                        g.spread.unwrap_or(0.0),
                        g.jitter.unwrap_or(0.0),
                        material,
                        seed,
                    )
                    .map_err(sim)?
                }
                GenerateKind::Lattice => generate::cubic_lattice(
                    req3(g.lo),
                    g.counts.unwrap_or([0; 3]),
                    req(g.spacing),
                    radius,
                    g.speed.unwrap_or(0.0),
                    material,
                    seed,
                )
                .map_err(sim)?,
            };
            for s in &mut spheres {
                s.material = material;
                s.mass = mass;
            }
            // Generators check their own parameters; anything they pass through unchecked
            // (a NaN speed, say) is named here rather than as a global sphere index.
            if let Some(k) = spheres.iter().position(|s| {
                !(s.centre.is_finite()
                    && s.velocity.is_finite()
                    && s.radius > 0.0
                    && s.radius.is_finite())
            }) {
                return Err(self.item_error(
                    &item,
                    &block,
                    format!("its sphere {k} is not finite (check radius, speed and positions)"),
                ));
            }
            world.spheres.extend(spheres);
        }
        Ok(())
    }

    #[allow(clippy::too_many_arguments)]
    fn random_block(
        &self,
        g: &GenerateTable,
        b: usize,
        item: &str,
        world: &World,
        periodic_size: Option<DVec3>,
        material: u16,
        seed: u64,
    ) -> Result<Vec<SphereState>, SceneFileError> {
        let path = |k| [Key("generate"), At(b), Key(k)];
        // A radius that is not finite and positive is refused by the generator, naming it.
        let radius = g.radius.unwrap_or(f64::NAN);
        let (mut lo, mut hi) = match (g.lo, g.hi) {
            (Some(lo), Some(hi)) => (DVec3::from_array(lo), DVec3::from_array(hi)),
            (None, None) => (DVec3::NEG_INFINITY, DVec3::INFINITY),
            (Some(_), None) => {
                return Err(self.item_error(item, &path("lo"), "`lo` needs `hi`".into()));
            }
            (None, Some(_)) => {
                return Err(self.item_error(item, &path("hi"), "`hi` needs `lo`".into()));
            }
        };
        let vessel = match g.inside {
            Some(k) => match world.containers.get(k) {
                Some(c) => {
                    let (centre, r) = (c.shape.centre().as_dvec3(), f64::from(c.shape.radius()));
                    lo = lo.max(centre - r);
                    hi = hi.min(centre + r);
                    Some((centre, r))
                }
                None => {
                    return Err(self.item_error(
                        item,
                        &path("inside"),
                        format!(
                            "inside = {k}: there are {} containers (counted from 0)",
                            world.containers.len()
                        ),
                    ));
                }
            },
            None => None,
        };
        if let Some(size) = periodic_size {
            // Keep every sphere whole inside the box, so none overlaps its neighbour's image.
            lo = lo.max(DVec3::splat(radius));
            hi = hi.min(size - radius);
        }
        if g.lo.is_none() && vessel.is_none() && periodic_size.is_none() {
            return Err(self.item_error(
                item,
                &path("kind"),
                "kind = \"random\" needs a region: `lo` and `hi`, or `inside` (a container index)"
                    .into(),
            ));
        }
        if !(lo.is_finite() && hi.is_finite() && (hi - lo).is_finite() && hi.cmpgt(lo).all()) {
            return Err(self.item_error(
                item,
                &path(if g.lo.is_some() { "hi" } else { "inside" }),
                format!(
                    "the region from {} to {} is empty or not finite",
                    show(lo),
                    show(hi)
                ),
            ));
        }
        // Room beside every sphere already placed, and clear of every static shape.
        let occupied = Occupied::new(&world.spheres);
        let margin = 1e-9 * radius;
        let inside = |p: DVec3| {
            occupied.is_free(p, radius)
                && world.containers.iter().all(|c| {
                    let d = p.distance(c.shape.centre().as_dvec3());
                    d + radius + margin <= f64::from(c.shape.radius())
                })
                && world.planes.iter().all(|q| {
                    let n = q.shape.normal().as_dvec3().normalize();
                    (p - q.shape.point().as_dvec3()).dot(n).abs() >= radius + margin
                })
                && world.cylinders.iter().all(|c| {
                    let s = c.shape.axis().as_dvec3().normalize();
                    let x = p - c.shape.point().as_dvec3();
                    (x - s * x.dot(s)).length() >= f64::from(c.shape.radius()) + radius + margin
                })
        };
        generate::random_spheres(
            lo,
            hi,
            &inside,
            g.n.unwrap_or(0),
            radius,
            g.speed.unwrap_or(0.0),
            material,
            seed,
        )
        .map_err(|e| self.generator_error(item, &[Key("generate"), At(b)], e))
    }
}

/// Spheres already placed, hashed on a grid, to keep a random block clear of them.
struct Occupied<'a> {
    spheres: &'a [SphereState],
    cell: f64,
    reach: f64,
    grid: std::collections::HashMap<[i64; 3], Vec<u32>>,
}

impl<'a> Occupied<'a> {
    fn new(spheres: &'a [SphereState]) -> Self {
        let reach = spheres.iter().map(|s| s.radius).fold(0.0, f64::max);
        let cell = (2.0 * reach).max(f64::MIN_POSITIVE);
        let mut grid: std::collections::HashMap<[i64; 3], Vec<u32>> = Default::default();
        for (i, s) in spheres.iter().enumerate() {
            grid.entry(Self::key(s.centre, cell))
                .or_default()
                .push(i as u32);
        }
        Self {
            spheres,
            cell,
            reach,
            grid,
        }
    }

    fn key(p: DVec3, cell: f64) -> [i64; 3] {
        // Saturating casts: far-away points share the edge cells.
        (p / cell).floor().to_array().map(|x| x as i64)
    }

    fn is_free(&self, p: DVec3, radius: f64) -> bool {
        if self.spheres.is_empty() {
            return true;
        }
        let span = ((radius + self.reach) / self.cell).ceil().min(64.0) as i64;
        let c = Self::key(p, self.cell);
        if span >= 64 {
            return self
                .spheres
                .iter()
                .all(|s| s.centre.distance(p) >= s.radius + radius);
        }
        for dx in -span..=span {
            for dy in -span..=span {
                for dz in -span..=span {
                    let k = [
                        c[0].saturating_add(dx),
                        c[1].saturating_add(dy),
                        c[2].saturating_add(dz),
                    ];
                    if let Some(members) = self.grid.get(&k)
                        && members.iter().any(|&j| {
                            let s = &self.spheres[j as usize];
                            s.centre.distance(p) < (s.radius + radius) * (1.0 + 1e-9)
                        })
                    {
                        return false;
                    }
                }
            }
        }
        true
    }
}
