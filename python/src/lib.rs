//! Python bindings of spheresweep (module `spheresweep._native`, re-exported by the Python
//! package `spheresweep`): spheres and shapes from NumPy arrays, the batch times of impact,
//! the whole-scene query and the event-driven simulation, the GIL released during every batch.
//! The Python-facing documentation is docs/python.md and `python/spheresweep/__init__.pyi`.

mod args;
mod arrays;
mod batch;
mod bench;
mod effects;
mod memory;
mod results;
mod scene;
mod shapes;
mod sim;
mod spheres;
mod world;
mod xyz;

use pyo3::prelude::*;

/// The extension module: classes, functions and constants (see docs/python.md).
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<spheres::Spheres>()?;
    m.add_class::<shapes::Plane>()?;
    m.add_class::<shapes::Cylinder>()?;
    m.add_class::<shapes::Container>()?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<results::FirstContacts>()?;
    m.add_class::<results::Contacts>()?;
    m.add_class::<sim::Simulation>()?;
    m.add_function(wrap_pyfunction!(batch::zip_times, m)?)?;
    m.add_function(wrap_pyfunction!(batch::pair_times, m)?)?;
    m.add_function(wrap_pyfunction!(batch::static_times, m)?)?;
    m.add_function(wrap_pyfunction!(scene::first_contacts, m)?)?;
    m.add_function(wrap_pyfunction!(scene::all_contacts, m)?)?;
    m.add_function(wrap_pyfunction!(xyz::read_xyz, m)?)?;
    m.add_function(wrap_pyfunction!(bench::_rust_zip_times_ns, m)?)?;
    m.add("InvariantError", py.get_type::<sim::InvariantError>())?;
    m.add("ACCURACIES", batch::accuracies(py)?)?;
    m.add("KIND_NONE", results::KIND_NONE)?;
    for kind in spheresweep::ShapeKind::ALL {
        let name = format!("KIND_{}", kind.name().to_uppercase());
        m.add(name.as_str(), results::kind_code(kind))?;
    }
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
