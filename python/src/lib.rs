//! Python bindings of spheresweep (module `spheresweep._native`, re-exported by the Python
//! package `spheresweep`): spheres and shapes from NumPy arrays, the batch times of impact,
//! the whole-scene query and the event-driven simulation, the GIL released during every batch.
//! The Python-facing documentation is docs/python.md and `python/spheresweep/__init__.pyi`.

mod arrays;
mod batch;
mod bench;
mod scene;
mod sim;

use pyo3::prelude::*;

/// The extension module: classes, functions and constants (see docs/python.md).
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<batch::Spheres>()?;
    m.add_class::<batch::Plane>()?;
    m.add_class::<batch::Cylinder>()?;
    m.add_class::<batch::Container>()?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<scene::FirstContacts>()?;
    m.add_class::<scene::Contacts>()?;
    m.add_class::<sim::Simulation>()?;
    m.add_function(wrap_pyfunction!(batch::zip_times, m)?)?;
    m.add_function(wrap_pyfunction!(batch::pair_times, m)?)?;
    m.add_function(wrap_pyfunction!(batch::static_times, m)?)?;
    m.add_function(wrap_pyfunction!(scene::first_contacts, m)?)?;
    m.add_function(wrap_pyfunction!(scene::all_contacts, m)?)?;
    m.add_function(wrap_pyfunction!(bench::_rust_zip_times_ns, m)?)?;
    m.add("ACCURACIES", batch::accuracies(py)?)?;
    m.add("KIND_NONE", scene::KIND_NONE)?;
    for kind in spheresweep::ShapeKind::ALL {
        let name = format!("KIND_{}", kind.name().to_uppercase());
        m.add(name.as_str(), scene::kind_code(kind))?;
    }
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
