//! The worlds a Python `Simulation` is built from: a scene file's, or the arrays and shapes of
//! `from_spheres` (checked and named as Python passes them), and the arrays that rebuild one.

use glam::DVec3;
use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use spheresweep::io::scene_file::{SceneFile, SceneFileError};
use spheresweep::sim::{SphereState, World};

use crate::args::{self, optional};
use crate::arrays::{Expect, floats, row3};
use crate::batch::value_error;
use crate::effects::material_index;
use crate::memory;
use crate::scene::shape_items;
use crate::shapes::Takes;
use crate::sim::simulation_bytes;

/// A scene file's error as Python raises it: `OSError` when it cannot be read, `ValueError`
/// for the rest.
pub(crate) fn scene_file_error(e: SceneFileError) -> PyErr {
    match e {
        SceneFileError::Read { .. } => PyOSError::new_err(e.to_string()),
        e => value_error(e),
    }
}

/// The simulation of a scene file's text (the world, the end time).
pub(crate) fn scene_file_world(file: &SceneFile) -> PyResult<(World, f64)> {
    if let Some(n) = file.sphere_count() {
        memory::check(&format!("scene file: {n} spheres"), simulation_bytes(n))?;
    }
    let (world, run) = file.build().map_err(scene_file_error)?;
    Ok((world, run.t_end))
}

/// The world of `from_spheres`' arguments (see there).
#[allow(clippy::too_many_arguments)]
pub(crate) fn spheres_world(
    centres: &Bound<'_, PyAny>,
    velocities: &Bound<'_, PyAny>,
    radii: &Bound<'_, PyAny>,
    masses: Option<&Bound<'_, PyAny>>,
    materials: Option<&Bound<'_, PyAny>>,
) -> PyResult<World> {
    let c = floats::<f64>(centres, "centres", Expect::Rows3)?;
    let v = floats::<f64>(velocities, "velocities", Expect::Rows3)?;
    let r = floats::<f64>(radii, "radii", Expect::Column)?;
    let m = optional(masses)
        .map(|m| floats::<f64>(m, "masses", Expect::Column))
        .transpose()?;
    let n = c.as_array().shape()[0];
    memory::check(&format!("Simulation: {n} spheres"), simulation_bytes(n))?;
    let (c, v, r) = (c.as_array(), v.as_array(), r.as_array());
    let m = m.as_ref().map(|m| m.as_array());
    let material: Vec<u16> = match optional(materials) {
        None => memory::filled(n, 0, "materials")?,
        Some(list) => list
            .try_iter()
            .map_err(|_| args::wrong_type("materials", "a sequence of integers", list))?
            .enumerate()
            .map(|(i, x)| material_index(&x?, &format!("materials[{i}]")))
            .collect::<PyResult<_>>()?,
    };
    for (name, len) in [("velocities", v.shape()[0]), ("radii", r.shape()[0])]
        .into_iter()
        .chain(m.as_ref().map(|m| ("masses", m.shape()[0])))
        .chain(optional(materials).map(|_| ("materials", material.len())))
    {
        if len != n {
            return Err(PyValueError::new_err(format!(
                "{name}: {len} entries, expected {n} (one per sphere, as centres)"
            )));
        }
    }
    let mut spheres = memory::with_capacity(n, "Simulation spheres")?;
    spheres.extend((0..n).map(|i| SphereState {
        centre: DVec3::from_array(row3(&c, i)),
        velocity: DVec3::from_array(row3(&v, i)),
        radius: r[[i]],
        mass: m.as_ref().map_or(1.0, |m| m[[i]]),
        material: material[i],
    }));
    Ok(World {
        spheres,
        ..World::default()
    })
}

/// The world's shapes from `planes=`, `cylinders=`, `containers=`: each item a shape of that
/// kind or a `(shape, material)` tuple. Returns the items as given (for pickling).
pub(crate) fn add_shapes<'py>(
    py: Python<'py>,
    world: &mut World,
    items: Option<&Bound<'py, PyAny>>,
    name: &str,
    takes: Takes,
) -> PyResult<Bound<'py, PyTuple>> {
    let Some(items) = optional(items) else {
        return Ok(PyTuple::empty(py));
    };
    let list: Vec<Bound<'py, PyAny>> = items
        .try_iter()
        .map_err(|_| args::wrong_type(name, "a sequence of shapes", items))?
        .collect::<PyResult<_>>()?;
    for (k, item) in list.iter().enumerate() {
        let label = format!("{name}[{k}]");
        // A shape, or a (shape, material) tuple.
        let (shape, material) = match item.cast::<PyTuple>() {
            Ok(t) if t.len() == 2 => (
                t.get_item(0)?,
                material_index(&t.get_item(1)?, &format!("{label}.material"))?,
            ),
            _ => (item.clone(), 0),
        };
        let one = PyTuple::new(py, [shape])?;
        let (_, shapes) = shape_items(py, Some(one.as_any()), &label, takes)
            .map_err(|e| rename_item(py, e, &format!("{label}[0]"), &label))?;
        world.statics.push_static(shapes[0], material);
    }
    PyTuple::new(py, list)
}

/// `e` with the item's label `from` replaced by `to` (a one-item check names its item).
pub(crate) fn rename_item(py: Python<'_>, e: PyErr, from: &str, to: &str) -> PyErr {
    let message = e.value(py).to_string().replacen(from, to, 1);
    if e.is_instance_of::<pyo3::exceptions::PyTypeError>(py) {
        pyo3::exceptions::PyTypeError::new_err(message)
    } else {
        PyValueError::new_err(message)
    }
}

/// Materials are numbered: as many as the largest index used (names "0", "1", ...); none
/// listed when every index is 0, as in every other world of one material (so that checkpoints
/// pass between them).
pub(crate) fn name_materials(world: &mut World) {
    let used = world
        .spheres
        .iter()
        .map(|s| s.material)
        .chain(world.statics.iter().map(|(_, _, &m)| m))
        .chain(world.effects.pairs.iter().flat_map(|p| [p.a, p.b]))
        .max()
        .unwrap_or(0);
    if used > 0 {
        world.materials = (0..=used).map(|i| i.to_string()).collect();
    }
}

/// The world's starting centres, velocities, radii and masses as float64 arrays: what
/// `from_spheres` rebuilds the same world from.
pub(crate) fn start_arrays<'py>(
    py: Python<'py>,
    spheres: &[SphereState],
) -> PyResult<Bound<'py, PyTuple>> {
    let n = spheres.len();
    let rows = |f: fn(&SphereState) -> DVec3| {
        let data: Vec<f64> = spheres.iter().flat_map(|s| f(s).to_array()).collect();
        Array2::from_shape_vec((n, 3), data)
            .expect("3 per sphere")
            .into_pyarray(py)
    };
    let r: Vec<f64> = spheres.iter().map(|s| s.radius).collect();
    let m: Vec<f64> = spheres.iter().map(|s| s.mass).collect();
    PyTuple::new(
        py,
        [
            rows(|s| s.centre).into_any(),
            rows(|s| s.velocity).into_any(),
            r.into_pyarray(py).into_any(),
            m.into_pyarray(py).into_any(),
        ],
    )
}
