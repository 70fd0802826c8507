//! World assembly: each table checked and turned into the [`World`]'s parts (run settings,
//! materials, effects, boundary, static shapes, listed spheres), each error naming its item.

use glam::DVec3;

use super::locate::Seg::{self, At, Key};
use super::locate::show;
use super::schema::{ContainerTable, CylinderTable, MaterialTable, Origin, PlaneTable};
use super::{BoundaryKind, RunSettings, SceneFile, SceneFileError, SphereTable};
use crate::Statics;
use crate::sim::{
    BEYOND_RANGE, Boundary, Effects, MaterialPair, OUTSIDE_RANGE, Response, SphereState, World,
    bounded3, in_range,
};
use crate::{Container, Cylinder, Plane};

impl SceneFile {
    pub(super) fn run_settings(&self) -> Result<RunSettings, SceneFileError> {
        let r = &self.run;
        if !(r.t_end.is_finite() && r.t_end > 0.0) {
            return Err(self.item_error(
                "run",
                &[Key("run"), Key("t_end")],
                format!("t_end = {:?} must be finite and greater than 0", r.t_end),
            ));
        }
        if let Some(every) = r.snapshot_every
            && !(every.is_finite() && every > 0.0)
        {
            return Err(self.item_error(
                "run",
                &[Key("run"), Key("snapshot_every")],
                format!("snapshot_every = {every:?} must be finite and greater than 0"),
            ));
        }
        Ok(RunSettings {
            t_end: r.t_end,
            snapshot_every: r.snapshot_every,
            seed: r.seed,
        })
    }

    pub(super) fn materials(&self) -> Result<Vec<String>, SceneFileError> {
        self.origin.material_names(&self.material)
    }

    /// The response a table names, with its `restitution`: required by `"inelastic"` (in
    /// `[0, 1]`), refused with any other response.
    fn response(
        &self,
        name: &str,
        restitution: Option<f64>,
        item: &str,
        path: &[Seg],
    ) -> Result<Response, SceneFileError> {
        let field = |key| {
            let mut at = path.to_vec();
            at.push(Key(key));
            at
        };
        // NaN when absent: then "inelastic" is refused below, and the others ignore it.
        let Some(response) = Response::named(name, restitution.unwrap_or(f64::NAN)) else {
            // Refused when parsed (`response_name`); reached by tables built in code only.
            let names = Response::NAMES.map(|n| format!("{n:?}")).join(", ");
            return Err(self.item_error(
                item,
                &field("response"),
                format!("response = {name:?} is not one of {names}"),
            ));
        };
        match (response, restitution) {
            (Response::Inelastic { .. }, Some(e)) if (0.0..=1.0).contains(&e) => Ok(response),
            (Response::Inelastic { .. }, Some(e)) => Err(self.item_error(
                item,
                &field("restitution"),
                format!("restitution = {e:?} must be in [0, 1]"),
            )),
            (Response::Inelastic { .. }, None) => Err(self.item_error(
                item,
                path,
                "response = \"inelastic\" needs `restitution` (in [0, 1])".into(),
            )),
            (other, Some(_)) => Err(self.item_error(
                item,
                &field("restitution"),
                format!(
                    "restitution applies only to response = \"inelastic\", not {:?}",
                    other.name()
                ),
            )),
            (other, None) => Ok(other),
        }
    }

    pub(super) fn effects(&self, names: &[String]) -> Result<Effects, SceneFileError> {
        let e = &self.effects;
        let response = self.response(&e.response, e.restitution, "effects", &[Key("effects")])?;
        if !(e.tc.is_finite() && e.tc >= 0.0) {
            return Err(self.item_error(
                "effects",
                &[Key("effects"), Key("tc")],
                format!("tc = {:?} must be finite and at least 0", e.tc),
            ));
        }
        let gravity = DVec3::from_array(e.gravity.unwrap_or([0.0; 3]));
        if !gravity.is_finite() {
            return Err(self.item_error(
                "effects",
                &[Key("effects"), Key("gravity")],
                format!(
                    "gravity = {:?} must be finite",
                    e.gravity.unwrap_or_default()
                ),
            ));
        }
        let mut pairs = Vec::with_capacity(e.pair.len());
        for (i, p) in e.pair.iter().enumerate() {
            let item = format!("effects.pair {i}");
            let path = [Key("effects"), Key("pair"), At(i)];
            let at = |k| [Key("effects"), Key("pair"), At(i), Key(k)];
            let a = self
                .origin
                .material_index(names, Some(&p.a), &item, &at("a"))?;
            let b = self
                .origin
                .material_index(names, Some(&p.b), &item, &at("b"))?;
            let r = self.response(&p.response, p.restitution, &item, &path)?;
            if r == Response::ReportOnly {
                return Err(self.item_error(
                    item,
                    &at("response"),
                    "response = \"none\" applies to a whole scene ([effects] response), not to one pair".into(),
                ));
            }
            if response == Response::ReportOnly {
                return Err(self.item_error(
                    item,
                    &path,
                    "[effects] response = \"none\" reports contacts only: a pair cannot change that".into(),
                ));
            }
            pairs.push(MaterialPair { a, b, response: r });
        }
        Ok(Effects {
            response,
            pairs,
            tc: e.tc,
            geometry: e.geometry,
            record_events: e.record_events,
            gravity,
        })
    }

    /// Sets the world's boundary; returns the periodic size if one was given.
    pub(super) fn boundary(&self, world: &mut World) -> Result<Option<DVec3>, SceneFileError> {
        let Some(b) = &self.boundary else {
            return Ok(None);
        };
        let at = |k| [Key("boundary"), Key(k)];
        let not_for = |field: &'static str, set: bool| {
            if set {
                Err(self.item_error(
                    "boundary",
                    &at(field),
                    format!(
                        "`{field}` does not apply to kind = {:?}",
                        match b.kind {
                            BoundaryKind::Open => "open",
                            BoundaryKind::Box => "box",
                            BoundaryKind::Periodic => "periodic",
                        }
                    ),
                ))
            } else {
                Ok(())
            }
        };
        let finite = |field: &'static str, v: [f64; 3]| {
            let v = DVec3::from_array(v);
            if v.is_finite() {
                Ok(v)
            } else {
                Err(self.item_error(
                    "boundary",
                    &at(field),
                    format!("{field} = {} must be finite", show(v)),
                ))
            }
        };
        match b.kind {
            BoundaryKind::Open => {
                not_for("size", b.size.is_some())?;
                not_for("lo", b.lo.is_some())?;
                not_for("hi", b.hi.is_some())?;
                world.boundary = Boundary::Open;
                Ok(None)
            }
            BoundaryKind::Box => {
                not_for("size", b.size.is_some())?;
                let (Some(lo), Some(hi)) = (b.lo, b.hi) else {
                    return Err(self.item_error(
                        "boundary",
                        &at("kind"),
                        "kind = \"box\" needs `lo` and `hi`".into(),
                    ));
                };
                let (lo, hi) = (finite("lo", lo)?, finite("hi", hi)?);
                if !hi.cmpgt(lo).all() {
                    return Err(self.item_error(
                        "boundary",
                        &at("hi"),
                        format!(
                            "hi = {} must exceed lo = {} on every axis",
                            show(hi),
                            show(lo)
                        ),
                    ));
                }
                world.boundary = Boundary::OpenBox { lo, hi };
                Ok(None)
            }
            BoundaryKind::Periodic => {
                not_for("lo", b.lo.is_some())?;
                not_for("hi", b.hi.is_some())?;
                let size = match b.size {
                    Some(s) => {
                        let s = finite("size", s)?;
                        if !s.cmpgt(DVec3::ZERO).all() {
                            return Err(self.item_error(
                                "boundary",
                                &at("size"),
                                format!("size = {} must be greater than 0 on every axis", show(s)),
                            ));
                        }
                        Some(s)
                    }
                    None => None,
                };
                world.boundary = Boundary::Periodic {
                    size: size.unwrap_or(DVec3::ZERO),
                };
                Ok(size)
            }
        }
    }

    pub(super) fn shapes(&self, world: &mut World) -> Result<(), SceneFileError> {
        world.statics = self.origin.static_shapes(
            &world.materials,
            &self.plane,
            &self.cylinder,
            &self.container,
        )?;
        Ok(())
    }

    pub(super) fn listed_sphere(
        &self,
        i: usize,
        s: &SphereTable,
        names: &[String],
    ) -> Result<SphereState, SceneFileError> {
        let item = format!("sphere {i}");
        let path = |k| [Key("sphere"), At(i), Key(k)];
        let material =
            self.origin
                .material_index(names, s.material.as_deref(), &item, &path("material"))?;
        let bad = |field: &'static str, problem: String| {
            Err(self.item_error(&item, &path(field), format!("{field} {problem}")))
        };
        let (centre, velocity) = (DVec3::from_array(s.centre), DVec3::from_array(s.velocity));
        if !centre.is_finite() {
            return bad("centre", format!("= {} must be finite", show(centre)));
        }
        if !velocity.is_finite() {
            return bad("velocity", format!("= {} must be finite", show(velocity)));
        }
        if !(s.radius.is_finite() && s.radius > 0.0) {
            return bad(
                "radius",
                format!("= {:?} must be finite and greater than 0", s.radius),
            );
        }
        if !(s.mass.is_finite() && s.mass > 0.0) {
            return bad(
                "mass",
                format!("= {:?} must be finite and greater than 0", s.mass),
            );
        }
        // The range the engine computes in (`World::validate`'s test), said with the value.
        if !bounded3(centre) {
            return bad("centre", format!("= {} {BEYOND_RANGE}", show(centre)));
        }
        if !bounded3(velocity) {
            return bad("velocity", format!("= {} {BEYOND_RANGE}", show(velocity)));
        }
        if !in_range(s.radius) {
            return bad("radius", format!("= {:?} {OUTSIDE_RANGE}", s.radius));
        }
        if !in_range(s.mass) {
            return bad("mass", format!("= {:?} {OUTSIDE_RANGE}", s.mass));
        }
        Ok(SphereState {
            centre,
            velocity,
            radius: s.radius,
            mass: s.mass,
            material,
        })
    }
}

/// The checks a static-shape group needs alone (a shapes file) as in a whole scene: material
/// names and the shapes, each error located in the text.
impl Origin {
    /// The names `[[material]]` declares, in index order (`"default"` when none is).
    pub(super) fn material_names(
        &self,
        tables: &[MaterialTable],
    ) -> Result<Vec<String>, SceneFileError> {
        if tables.is_empty() {
            return Ok(vec!["default".into()]);
        }
        if tables.len() > crate::sim::MAX_MATERIALS {
            let max = crate::sim::MAX_MATERIALS;
            return Err(self.item_error(
                format!("material {max}"),
                &[Key("material"), At(max)],
                format!("at most {max} materials"),
            ));
        }
        let mut names: Vec<String> = Vec::with_capacity(tables.len());
        for (i, m) in tables.iter().enumerate() {
            let path = [Key("material"), At(i), Key("name")];
            if m.name.trim().is_empty() {
                return Err(self.item_error(
                    format!("material {i}"),
                    &path,
                    "name is empty".into(),
                ));
            }
            if let Some(j) = names.iter().position(|n| *n == m.name) {
                return Err(self.item_error(
                    format!("material {i}"),
                    &path,
                    format!("name {:?} is already material {j}", m.name),
                ));
            }
            names.push(m.name.clone());
        }
        Ok(names)
    }

    /// The index of a material named by `item` (the first when `name` is `None`).
    pub(super) fn material_index(
        &self,
        names: &[String],
        name: Option<&str>,
        item: &str,
        path: &[Seg],
    ) -> Result<u16, SceneFileError> {
        let Some(name) = name else { return Ok(0) };
        match names.iter().position(|n| n == name) {
            // At most MAX_MATERIALS names (checked in `material_names`).
            Some(i) => Ok(i as u16),
            None => Err(self.item_error(
                item,
                path,
                format!(
                    "material {name:?} is not declared (declared: {})",
                    names
                        .iter()
                        .map(|n| format!("{n:?}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// The static shapes of the `[[plane]]`, `[[cylinder]]` and `[[container]]` tables, each
    /// with its material's index among `names`.
    pub(super) fn static_shapes(
        &self,
        names: &[String],
        planes: &[PlaneTable],
        cylinders: &[CylinderTable],
        containers: &[ContainerTable],
    ) -> Result<Statics<u16>, SceneFileError> {
        let mut out = Statics::new();
        let f32s = |v: [f64; 3]| v.map(|x| x as f32);
        // Shapes are stored in f32: a finite value beyond its range would round to infinite,
        // which the constructor could only call "NaN or infinite".
        let fits = |item: &str, path: &[Seg], key: &str, values: &[f64]| match values
            .iter()
            .find(|x| x.is_finite() && x.abs() > f64::from(f32::MAX))
        {
            Some(x) => Err(self.item_error(
                item,
                path,
                format!(
                    "{key} holds {x:e}, beyond the range of f32 (magnitudes up to 3.4e38), \
                         in which shapes are stored"
                ),
            )),
            None => Ok(()),
        };
        for (i, p) in planes.iter().enumerate() {
            let item = format!("plane {i}");
            let path = |k| [Key("plane"), At(i), Key(k)];
            let material =
                self.material_index(names, p.material.as_deref(), &item, &path("material"))?;
            fits(&item, &path("point"), "point", &p.point)?;
            fits(&item, &path("normal"), "normal", &p.normal)?;
            let shape = Plane::new(f32s(p.point), f32s(p.normal))
                .map_err(|e| self.shape_error(&item, &path(e.field), e))?;
            out.push(shape, material);
        }
        for (i, c) in cylinders.iter().enumerate() {
            let item = format!("cylinder {i}");
            let path = |k| [Key("cylinder"), At(i), Key(k)];
            let material =
                self.material_index(names, c.material.as_deref(), &item, &path("material"))?;
            fits(&item, &path("p1"), "p1", &c.p1)?;
            fits(&item, &path("p2"), "p2", &c.p2)?;
            fits(&item, &path("radius"), "radius", &[c.radius])?;
            let shape = Cylinder::new(f32s(c.p1), f32s(c.p2), c.radius as f32).map_err(|e| {
                let field = if e.field == "axis" { "p2" } else { e.field };
                self.shape_error(&item, &path(field), e)
            })?;
            out.push(shape, material);
        }
        for (i, c) in containers.iter().enumerate() {
            let item = format!("container {i}");
            let path = |k| [Key("container"), At(i), Key(k)];
            let material =
                self.material_index(names, c.material.as_deref(), &item, &path("material"))?;
            fits(&item, &path("centre"), "centre", &c.centre)?;
            fits(&item, &path("radius"), "radius", &[c.radius])?;
            let shape = Container::new(f32s(c.centre), c.radius as f32)
                .map_err(|e| self.shape_error(&item, &path(e.field), e))?;
            out.push(shape, material);
        }
        Ok(out)
    }
}
