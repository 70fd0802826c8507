//! Sphere placement: the `[[generate]]` blocks, each checked and handed to its generator in
//! `sim::generate`; a `random` block is kept clear of the spheres already placed and of the
//! static shapes.

use glam::DVec3;

use super::locate::Seg::{self, At, Key};
use super::locate::show;
use super::{GenerateKind, GenerateTable, MAX_SPHERES, SceneFile, SceneFileError};
use crate::Container;
use crate::sim::{Boundary, SimError, SphereState, World, generate};

/// One `[[generate]]` block ready to place: its table and index, its name in messages, and
/// what its checks settled.
struct Block<'a> {
    table: &'a GenerateTable,
    index: usize,
    /// `generate 2 (random)`.
    item: String,
    count: usize,
    material: u16,
    mass: f64,
    seed: u64,
}

impl Block<'_> {
    /// The block's path in the file.
    fn path(&self) -> [Seg; 2] {
        [Key("generate"), At(self.index)]
    }

    /// One of its fields' path.
    fn field(&self, key: &'static str) -> [Seg; 3] {
        [Key("generate"), At(self.index), Key(key)]
    }
}

/// A required field (every one is set once the block is checked).
fn required(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

/// A required vector field.
fn required3(v: Option<[f64; 3]>) -> DVec3 {
    DVec3::from_array(v.unwrap_or([f64::NAN; 3]))
}

impl SceneFile {
    /// Places each `[[generate]]` block's spheres after the world's, in file order: checked,
    /// generated, given the block's material and mass, and checked finite.
    pub(super) fn generated(
        &self,
        world: &mut World,
        mut periodic_size: Option<DVec3>,
        base_seed: u64,
    ) -> Result<(), SceneFileError> {
        let mut total = world.spheres.len();
        for (index, table) in self.generate.iter().enumerate() {
            let block = self.checked_block(index, table, total, &world.materials, base_seed)?;
            total += block.count;
            let mut spheres = match table.kind {
                GenerateKind::PeriodicGas => {
                    self.periodic_gas_block(&block, world, &mut periodic_size)?
                }
                GenerateKind::Random => self.random_block(&block, world, periodic_size)?,
                GenerateKind::Nozzle => self.nozzle_block(&block)?,
                GenerateKind::Lattice => self.lattice_block(&block)?,
            };
            for s in &mut spheres {
                s.material = block.material;
                s.mass = block.mass;
            }
            self.check_finite(&block, &spheres)?;
            world.spheres.extend(spheres);
        }
        Ok(())
    }

    /// A block's fields checked against its kind, its count against the spheres placed
    /// before it (`total`), then its material, mass and seed.
    fn checked_block<'a>(
        &self,
        index: usize,
        table: &'a GenerateTable,
        total: usize,
        materials: &[String],
        base_seed: u64,
    ) -> Result<Block<'a>, SceneFileError> {
        let item = format!("generate {index} ({})", table.kind.name());
        let path = |k| [Key("generate"), At(index), Key(k)];
        self.check_kind_fields(&item, index, table)?;
        let count = table.count().unwrap_or(usize::MAX);
        if count == 0 || count > MAX_SPHERES - total.min(MAX_SPHERES) {
            let field = if table.kind == GenerateKind::Lattice {
                "counts"
            } else {
                "n"
            };
            let asked = table
                .count()
                .map_or("more than 2^64".to_string(), |c| c.to_string());
            return Err(self.item_error(
                &item,
                &path(field),
                format!(
                    "{field} must give between 1 and {MAX_SPHERES} spheres in all (this block: {asked})"
                ),
            ));
        }
        let material = self.origin.material_index(
            materials,
            table.material.as_deref(),
            &item,
            &path("material"),
        )?;
        let mass = table.mass.unwrap_or(1.0);
        if !(mass.is_finite() && mass > 0.0) {
            return Err(self.item_error(
                &item,
                &path("mass"),
                format!("mass = {mass:?} must be finite and greater than 0"),
            ));
        }
        Ok(Block {
            table,
            index,
            item,
            count,
            material,
            mass,
            seed: table.seed.unwrap_or(base_seed.wrapping_add(index as u64)),
        })
    }

    /// Fields that do not belong to the block's kind, then the ones it needs.
    fn check_kind_fields(
        &self,
        item: &str,
        index: usize,
        table: &GenerateTable,
    ) -> Result<(), SceneFileError> {
        let path = |k| [Key("generate"), At(index), Key(k)];
        let kind = table.kind.name();
        let (required, optional) = table.kind.fields();
        let set = table.set_fields();
        if let Some(f) = set
            .iter()
            .find(|f| !required.contains(f) && !optional.contains(f))
        {
            let takes = required.iter().chain(optional).copied();
            return Err(self.item_error(
                item,
                &path(f),
                format!(
                    "`{f}` does not apply to kind = {kind:?} (it takes {}; and material, seed, mass)",
                    takes.collect::<Vec<_>>().join(", ")
                ),
            ));
        }
        if let Some(missing) = required.iter().find(|f| !set.contains(f)) {
            return Err(self.item_error(
                item,
                &path("kind"),
                format!(
                    "kind = {kind:?} needs `{missing}` (it needs {})",
                    required.join(", ")
                ),
            ));
        }
        Ok(())
    }

    /// A generator's refusal, named by the block.
    fn refused(&self, block: &Block<'_>) -> impl Fn(SimError) -> SceneFileError {
        move |e| self.generator_error(&block.item, &block.path(), e)
    }

    /// A `periodic_gas` block: the gas sets the periodic box from `n` and `phi`, so the
    /// boundary must be periodic without a size, and no earlier gas may have set it.
    fn periodic_gas_block(
        &self,
        block: &Block<'_>,
        world: &mut World,
        periodic_size: &mut Option<DVec3>,
    ) -> Result<Vec<SphereState>, SceneFileError> {
        let g = block.table;
        if world.boundary != (Boundary::Periodic { size: DVec3::ZERO }) || periodic_size.is_some() {
            let problem = if matches!(world.boundary, Boundary::Periodic { .. }) {
                "the periodic box is already set (by [boundary] size or an earlier periodic_gas): a periodic_gas sets it from n and phi"
            } else {
                "periodic_gas needs [boundary] kind = \"periodic\" (without size: the gas sets it)"
            };
            return Err(self.item_error(&block.item, &block.path(), problem.into()));
        }
        let mut gas = World::default();
        let (phi, radius) = (required(g.phi), required(g.radius));
        let kt = g.temperature.unwrap_or(1.0);
        generate::periodic_gas(&mut gas, block.count, phi, radius, kt, block.seed)
            .map_err(self.refused(block))?;
        world.boundary = gas.boundary;
        if let Boundary::Periodic { size } = gas.boundary {
            *periodic_size = Some(size);
        }
        // The generator's masses are 1: keep kT for the mass asked for.
        let scale = 1.0 / block.mass.sqrt();
        for s in &mut gas.spheres {
            s.velocity *= scale;
        }
        Ok(gas.spheres)
    }

    /// A `nozzle` block.
    fn nozzle_block(&self, block: &Block<'_>) -> Result<Vec<SphereState>, SceneFileError> {
        let g = block.table;
        let radius = required(g.radius);
        generate::nozzle(
            required3(g.origin),
            required3(g.direction),
            block.count,
            radius,
            required(g.speed),
            g.spacing.unwrap_or(2.2 * radius),
            g.spread.unwrap_or(0.0),
            g.jitter.unwrap_or(0.0),
            block.material,
            block.seed,
        )
        .map_err(self.refused(block))
    }

    /// A `lattice` block.
    fn lattice_block(&self, block: &Block<'_>) -> Result<Vec<SphereState>, SceneFileError> {
        let g = block.table;
        generate::cubic_lattice(
            required3(g.lo),
            g.counts.unwrap_or([0; 3]),
            required(g.spacing),
            required(g.radius),
            g.speed.unwrap_or(0.0),
            block.material,
            block.seed,
        )
        .map_err(self.refused(block))
    }

    /// Generators check their own parameters; anything they pass through unchecked (a NaN
    /// speed, say) is named here by its block rather than as a global sphere index.
    fn check_finite(
        &self,
        block: &Block<'_>,
        spheres: &[SphereState],
    ) -> Result<(), SceneFileError> {
        let whole = |s: &SphereState| {
            s.centre.is_finite() && s.velocity.is_finite() && s.radius > 0.0 && s.radius.is_finite()
        };
        match spheres.iter().position(|s| !whole(s)) {
            Some(k) => Err(self.item_error(
                &block.item,
                &block.path(),
                format!("its sphere {k} is not finite (check radius, speed and positions)"),
            )),
            None => Ok(()),
        }
    }

    /// A `random` block: spheres at random in its region (`lo`..`hi`, the inside of a
    /// container, the periodic box), each clear of the spheres already placed and of every
    /// static shape.
    fn random_block(
        &self,
        block: &Block<'_>,
        world: &World,
        periodic_size: Option<DVec3>,
    ) -> Result<Vec<SphereState>, SceneFileError> {
        let g = block.table;
        // A radius that is not finite and positive is refused by the generator, naming it.
        let radius = required(g.radius);
        let (lo, hi) = self.random_region(block, world, periodic_size)?;
        // Room beside every sphere already placed, and clear of every static shape.
        let occupied = Occupied::new(&world.spheres);
        let margin = 1e-9 * radius;
        // Each kind's own gap (its kernel file's `normal_gap`): inside a container, either side
        // of a plane, outside a cylinder.
        let clear = |p: DVec3| {
            occupied.is_free(p, radius)
                && (world.statics.iter()).all(|(_, s, _)| s.normal_gap(p, radius).1 >= margin)
        };
        let speed = g.speed.unwrap_or(0.0);
        let (n, material, seed) = (block.count, block.material, block.seed);
        generate::random_spheres(lo, hi, &clear, n, radius, speed, material, seed)
            .map_err(self.refused(block))
    }

    /// The box a `random` block draws centres from: `lo`..`hi`, cut to the bounds of the
    /// container it fills (`inside`), and to the periodic box less a radius (so that no
    /// sphere overlaps its neighbour's image); refused unless finite and not empty.
    fn random_region(
        &self,
        block: &Block<'_>,
        world: &World,
        periodic_size: Option<DVec3>,
    ) -> Result<(DVec3, DVec3), SceneFileError> {
        let (g, item) = (block.table, &block.item);
        let radius = required(g.radius);
        let (mut lo, mut hi) = match (g.lo, g.hi) {
            (Some(lo), Some(hi)) => (DVec3::from_array(lo), DVec3::from_array(hi)),
            (None, None) => (DVec3::NEG_INFINITY, DVec3::INFINITY),
            (Some(_), None) => {
                return Err(self.item_error(item, &block.field("lo"), "`lo` needs `hi`".into()));
            }
            (None, Some(_)) => {
                return Err(self.item_error(item, &block.field("hi"), "`hi` needs `lo`".into()));
            }
        };
        if let Some(k) = g.inside {
            let containers = world.statics.of::<Container>().shapes();
            let Some(c) = containers.get(k) else {
                let problem = match containers.len() {
                    0 => format!("inside = {k}: the scene has no container"),
                    1 => format!("inside = {k}: the scene has one container, 0"),
                    n => format!("inside = {k}: there are {n} containers, 0 to {}", n - 1),
                };
                return Err(self.item_error(item, &block.field("inside"), problem));
            };
            let (centre, r) = (c.centre().as_dvec3(), f64::from(c.radius()));
            lo = lo.max(centre - r);
            hi = hi.min(centre + r);
        }
        if let Some(size) = periodic_size {
            lo = lo.max(DVec3::splat(radius));
            hi = hi.min(size - radius);
        }
        if g.lo.is_none() && g.inside.is_none() && periodic_size.is_none() {
            return Err(self.item_error(
                item,
                &block.field("kind"),
                "kind = \"random\" needs a region: `lo` and `hi`, or `inside` (a container index)"
                    .into(),
            ));
        }
        if !(lo.is_finite() && hi.is_finite() && (hi - lo).is_finite() && hi.cmpgt(lo).all()) {
            return Err(self.item_error(
                item,
                &block.field(if g.lo.is_some() { "hi" } else { "inside" }),
                format!(
                    "the region from {} to {} is empty or not finite",
                    show(lo),
                    show(hi)
                ),
            ));
        }
        Ok((lo, hi))
    }
}

/// Spheres already placed, hashed on a grid, to keep a random block clear of them: a point
/// query ("is a sphere of this radius at `p` clear of all of them?") over an unbounded region.
/// Neither of the library's other grids fits: `broad::Grid` answers pairs of swept f32 boxes,
/// not points; `sim::cells::Cells` is a dense box with one slot count for every cell, so listed
/// spheres clustered far apart (its box spans both clusters, most cells empty, a few holding
/// thousands) would cost cells × the fullest cell's count in memory. A hash of the occupied
/// cells costs memory in the spheres alone.
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
