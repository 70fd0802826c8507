//! Error location: the line of an item or field in the TOML text, and the errors that name
//! the item, the field and the line (the file's items behind the engine's errors too).

use glam::DVec3;

use super::schema::Origin;
use super::{SceneFile, SceneFileError};
use crate::error::ShapeError;
use crate::sim::SimError;

/// One step of a path into the file: a key or an array index.
#[derive(Debug, Clone, Copy)]
pub(super) enum Seg {
    Key(&'static str),
    At(usize),
}
pub(super) use Seg::{At, Key};

impl Origin {
    /// The line of the value at `path` in the TOML text (the key's line for a field, the
    /// header's for an array element); the nearest enclosing item's when the field is absent.
    pub(super) fn line(&self, path: &[Seg]) -> Option<usize> {
        let text = self.toml.as_deref()?;
        let root = toml::de::DeTable::parse(text).ok()?;
        let mut offset = None;
        let mut table = Some(root.get_ref());
        let mut value: Option<&toml::de::DeValue<'_>> = None;
        for seg in path {
            match *seg {
                Key(name) => {
                    let t = table.take().or_else(|| value.and_then(|v| v.as_table()))?;
                    let Some((k, v)) = t.iter().find(|(k, _)| k.get_ref().as_ref() == name) else {
                        break;
                    };
                    offset = Some(k.span().start);
                    value = Some(v.get_ref());
                }
                At(i) => {
                    let Some(e) = value.and_then(|v| v.as_array()).and_then(|a| a.get(i)) else {
                        break;
                    };
                    offset = Some(e.span().start);
                    value = Some(e.get_ref());
                }
            }
        }
        let offset = offset?;
        Some(text.get(..offset)?.matches('\n').count() + 1)
    }

    /// An item that does not make sense, at the line of `path`.
    pub(super) fn item_error(
        &self,
        item: impl Into<String>,
        path: &[Seg],
        problem: String,
    ) -> SceneFileError {
        SceneFileError::Item {
            file: self.file.clone(),
            line: self.line(path),
            item: item.into(),
            problem,
        }
    }

    /// An item the simulation refused, at the line of `path`.
    pub(super) fn sim_error(
        &self,
        item: impl Into<String>,
        path: &[Seg],
        source: SimError,
    ) -> SceneFileError {
        SceneFileError::Sim {
            file: self.file.clone(),
            line: self.line(path),
            item: item.into(),
            source,
        }
    }

    /// An item a shape's constructor refused, at the line of `path`.
    pub(super) fn shape_error(
        &self,
        item: impl Into<String>,
        path: &[Seg],
        source: ShapeError,
    ) -> SceneFileError {
        SceneFileError::Shape {
            file: self.file.clone(),
            line: self.line(path),
            item: item.into(),
            source,
        }
    }
}

impl SceneFile {
    /// [`Origin::item_error`] in this file.
    pub(super) fn item_error(
        &self,
        item: impl Into<String>,
        path: &[Seg],
        problem: String,
    ) -> SceneFileError {
        self.origin.item_error(item, path, problem)
    }

    /// [`Origin::sim_error`] in this file.
    pub(super) fn sim_error(
        &self,
        item: impl Into<String>,
        path: &[Seg],
        source: SimError,
    ) -> SceneFileError {
        self.origin.sim_error(item, path, source)
    }

    /// The item a sphere of the world came from, and its path in the file.
    pub(super) fn sphere_item(&self, index: usize) -> (String, Vec<Seg>) {
        if index < self.sphere.len() {
            return (format!("sphere {index}"), vec![Key("sphere"), At(index)]);
        }
        let mut start = self.sphere.len();
        for (b, g) in self.generate.iter().enumerate() {
            let n = g.count().unwrap_or(0);
            if index < start + n {
                return (
                    format!(
                        "generate {b} ({}), its sphere {}",
                        g.kind.name(),
                        index - start
                    ),
                    vec![Key("generate"), At(b)],
                );
            }
            start += n;
        }
        (format!("sphere {index}"), Vec::new())
    }

    /// Names the items of the file behind an error of
    /// [`Simulation::new`](crate::sim::Simulation::new) or
    /// [`World::validate`](crate::sim::World::validate) on the world [`build`](Self::build) made (overlapping spheres are
    /// named by their `[[sphere]]` or `[[generate]]` entry).
    ///
    /// ```
    /// use spheresweep::io::scene_file::SceneFile;
    /// use spheresweep::sim::Simulation;
    /// let text = "[run]\nt_end = 1\n\
    ///     [[sphere]]\ncentre = [0, 0, 0]\nradius = 1\n\
    ///     [[sphere]]\ncentre = [1, 0, 0]\nradius = 1\n";
    /// let scene = SceneFile::from_toml_str(text)?;
    /// let (world, _) = scene.build()?; // overlaps are the engine's to find
    /// let err = scene.locate(Simulation::new(world).unwrap_err());
    /// assert!(err.to_string().starts_with("line 3: sphere 0 and sphere 1: spheres 0 and 1 overlap"));
    /// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
    /// ```
    pub fn locate(&self, err: SimError) -> SceneFileError {
        match &err {
            SimError::Overlap { a, b, .. } => {
                let (ia, pa) = self.sphere_item(*a);
                let (ib, _) = self.sphere_item(*b);
                self.sim_error(format!("{ia} and {ib}"), &pa, err)
            }
            SimError::Sphere { index, .. } => {
                let (item, path) = self.sphere_item(*index);
                self.sim_error(item, &path, err)
            }
            SimError::Penetrates {
                sphere,
                shape,
                index,
                ..
            } => {
                let (item, path) = self.sphere_item(*sphere);
                self.sim_error(format!("{item} and {shape} {index}"), &path, err)
            }
            SimError::NoRoom {
                sphere, container, ..
            } => {
                let (item, path) = self.sphere_item(*sphere);
                self.sim_error(format!("{item} and container {container}"), &path, err)
            }
            SimError::Box { .. } | SimError::OpenBox { .. } => {
                self.sim_error("boundary", &[Key("boundary")], err)
            }
            SimError::PeriodicShape { shape, index, .. } => {
                let item = format!("{shape} {index}");
                self.sim_error(item, &[Key(shape.name()), At(*index)], err)
            }
            SimError::Range { what } if what.is_boundary() => {
                self.sim_error("boundary", &[Key("boundary")], err)
            }
            _ => self.sim_error("scene", &[], err),
        }
    }

    /// A generator's refusal ([`SimError::Generate`]) in its own words, at the line of the
    /// field it names (the block's line when it names none); any other error as it is.
    pub(super) fn generator_error(&self, item: &str, path: &[Seg], e: SimError) -> SceneFileError {
        match e {
            SimError::Generate { field, problem, .. } => {
                let mut path = path.to_vec();
                if !field.is_empty() {
                    path.push(Key(field));
                }
                self.item_error(item, &path, problem)
            }
            other => self.sim_error(item, path, other),
        }
    }
}

/// A vector in messages: each component as the shortest decimal that reads back (exponent
/// form for very large and small magnitudes).
pub(super) fn show(v: DVec3) -> String {
    format!("[{:?}, {:?}, {:?}]", v.x, v.y, v.z)
}
