//! Extended XYZ from Python, through the library's reader and writer (`spheresweep::io::xyz`,
//! the format `spheresweep run` writes and OVITO and ASE read): frames into arrays, and a
//! simulation's state appended as a frame.

use std::io::Write;
use std::path::Path;

use glam::DVec3;
use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use spheresweep::io::xyz;
use spheresweep::sim::SphereState;

use crate::memory;

/// Every frame of the extended XYZ file at `path` (as `spheresweep run` writes its
/// `trajectory.xyz`), as a list of dicts of arrays: `time` (float), `positions` and
/// `velocities` float64 `(N, 3)`, `radii`, `masses` float64 `(N,)`, `materials` uint16
/// `(N,)`, and `box` (the periodic lengths as a tuple, or `None`). Read by the library's
/// reader: every value has the bits the writer had. The files record no masses: `masses` is
/// read from a `mass:R:1` column when another tool's file has one, else 1.0 each. `OSError` if the file cannot be read,
/// `ValueError` naming the line for anything malformed.
#[pyfunction]
pub fn read_xyz<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyList>> {
    let size = std::fs::metadata(&path)
        .map_err(|e| PyOSError::new_err(format!("cannot read {}: {e}", path.display())))?
        .len();
    // The text, and its frames at about as many bytes as the text (a line per sphere).
    memory::check(
        &format!("read_xyz: {}", path.display()),
        (3 * size) as usize,
    )?;
    let text = std::fs::read_to_string(&path)
        .map_err(|e| PyOSError::new_err(format!("cannot read {}: {e}", path.display())))?;
    let frames = xyz::read_frames(&text)
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    drop(text);
    let list = PyList::empty(py);
    for frame in frames {
        let d = PyDict::new(py);
        d.set_item("time", frame.time)?;
        let s = &frame.spheres;
        let rows = |f: fn(&SphereState) -> DVec3| {
            let data: Vec<f64> = s.iter().flat_map(|x| f(x).to_array()).collect();
            Array2::from_shape_vec((s.len(), 3), data)
                .expect("3 per sphere")
                .into_pyarray(py)
        };
        d.set_item("positions", rows(|x| x.centre))?;
        d.set_item("velocities", rows(|x| x.velocity))?;
        d.set_item(
            "radii",
            s.iter()
                .map(|x| x.radius)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "masses",
            s.iter()
                .map(|x| x.mass)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "materials",
            s.iter()
                .map(|x| x.material)
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item("box", frame.periodic_box.map(|b| (b.x, b.y, b.z)))?;
        list.append(d)?;
    }
    Ok(list)
}

/// Appends one frame of `spheres` at `time` to the file at `path` (created if absent), as
/// the CLI writes its trajectory.
pub(crate) fn append_frame(
    path: &Path,
    spheres: &[SphereState],
    time: f64,
    periodic_box: Option<DVec3>,
) -> PyResult<()> {
    let io =
        |e: std::io::Error| PyOSError::new_err(format!("cannot write {}: {e}", path.display()));
    let file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .map_err(io)?;
    let mut out = std::io::BufWriter::new(file);
    xyz::write_frame(&mut out, spheres, time, periodic_box).map_err(io)?;
    out.flush().map_err(io)
}
