//! The static shapes from Python: `Plane`, `Cylinder` and `Container`, each validated once and
//! pickled as its float32 inputs; and the checks that a shape argument holds the right kind.

use pyo3::prelude::*;
use pyo3::types::PyType;

use spheresweep::{ShapeKind, Static};

use crate::args::{real, wrong_type};
use crate::arrays::vector3;
use crate::batch::value_error;

/// A 3-vector as Python shows it: a tuple.
type Triple = (f32, f32, f32);

/// A static infinite plane through `point` with normal `normal` (any non-zero length,
/// normalised here; the sphere is kept on the side the normal points to). Each vector is three
/// real numbers (ints or floats, as a sequence or a NumPy array), rounded to float32.
/// `ValueError` for NaN, infinite or zero-length input, naming the field. Pickles as the
/// float32 inputs, so a rebuilt plane has the same bits.
#[pyclass(frozen, module = "spheresweep._native")]
#[derive(Clone)]
pub struct Plane {
    pub(crate) shape: spheresweep::Plane,
    /// The normal as given (rounded to float32), before normalising: what pickling rebuilds
    /// from, since normalising a normalised vector can change its last bit.
    given_normal: [f32; 3],
}

#[pymethods]
impl Plane {
    #[new]
    fn new(point: &Bound<'_, PyAny>, normal: &Bound<'_, PyAny>) -> PyResult<Self> {
        let given_normal = vector3(normal, "normal")?;
        let shape =
            spheresweep::Plane::new(vector3(point, "point")?, given_normal).map_err(value_error)?;
        Ok(Self {
            shape,
            given_normal,
        })
    }

    /// A point of the plane, as given.
    #[getter]
    fn point(&self) -> Triple {
        self.shape.point().into()
    }

    /// The unit normal: the normal given, normalised (then rounded to float32).
    #[getter]
    fn normal(&self) -> Triple {
        self.shape.normal().into()
    }

    /// Pickling: the class and the float32 point and normal as given, which rebuild the same
    /// bits (the normalised normal would not always: re-normalising can move its last bit).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> (Bound<'py, PyType>, (Triple, Triple)) {
        let me = slf.get();
        (slf.get_type(), (me.point(), me.given_normal.into()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Plane(point={:?}, normal={:?})",
            self.point(),
            self.normal()
        )
    }
}

/// A static infinite cylinder of radius `radius` around the line through `p1` and `p2`
/// (`p1 != p2`). Points are three real numbers each and the radius a real number (ints or
/// floats), rounded to float32. `ValueError` for NaN, infinite or negative input, or
/// `p1 == p2`. Pickles as the float32 inputs (same bits when rebuilt).
#[pyclass(frozen, module = "spheresweep._native")]
#[derive(Clone)]
pub struct Cylinder {
    pub(crate) shape: spheresweep::Cylinder,
    p1: [f32; 3],
    p2: [f32; 3],
}

#[pymethods]
impl Cylinder {
    #[new]
    fn new(
        p1: &Bound<'_, PyAny>,
        p2: &Bound<'_, PyAny>,
        radius: &Bound<'_, PyAny>,
    ) -> PyResult<Self> {
        let (p1, p2) = (vector3(p1, "p1")?, vector3(p2, "p2")?);
        let radius = real(radius, "radius")? as f32;
        let shape = spheresweep::Cylinder::new(p1, p2, radius).map_err(value_error)?;
        Ok(Self { shape, p1, p2 })
    }

    /// First point of the axis, as given.
    #[getter]
    fn p1(&self) -> Triple {
        self.p1.into()
    }

    /// Second point of the axis, as given.
    #[getter]
    fn p2(&self) -> Triple {
        self.p2.into()
    }

    /// Radius.
    #[getter]
    fn radius(&self) -> f32 {
        self.shape.radius()
    }

    /// Pickling: the class and the float32 inputs, which rebuild the same bits.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> (Bound<'py, PyType>, (Triple, Triple, f32)) {
        let me = slf.get();
        (slf.get_type(), (me.p1(), me.p2(), me.radius()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Cylinder(p1={:?}, p2={:?}, radius={:?})",
            self.p1(),
            self.p2(),
            self.radius()
        )
    }
}

/// A static spherical container: the inside of the sphere of `radius` around `centre`; every
/// sphere is meant to move inside it. The centre is three real numbers and the radius a real
/// number (ints or floats), rounded to float32. `ValueError` for NaN, infinite or negative
/// input. Pickles as the float32 inputs (same bits when rebuilt).
#[pyclass(frozen, module = "spheresweep._native")]
#[derive(Clone)]
pub struct Container {
    pub(crate) shape: spheresweep::Container,
}

#[pymethods]
impl Container {
    #[new]
    fn new(centre: &Bound<'_, PyAny>, radius: &Bound<'_, PyAny>) -> PyResult<Self> {
        let centre = vector3(centre, "centre")?;
        let radius = real(radius, "radius")? as f32;
        let shape = spheresweep::Container::new(centre, radius).map_err(value_error)?;
        Ok(Self { shape })
    }

    /// Centre.
    #[getter]
    fn centre(&self) -> Triple {
        self.shape.centre().into()
    }

    /// Inner radius.
    #[getter]
    fn radius(&self) -> f32 {
        self.shape.radius()
    }

    /// Pickling: the class and the float32 inputs, which rebuild the same bits.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> (Bound<'py, PyType>, (Triple, f32)) {
        let me = slf.get();
        (slf.get_type(), (me.centre(), me.radius()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Container(centre={:?}, radius={:?})",
            self.centre(),
            self.radius()
        )
    }
}

/// Which kinds of shape an argument takes.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Takes {
    /// Any static kind (`static_times`' `shapes`).
    Any,
    /// One kind only (`planes=`, `cylinders=`, `containers=`).
    Only(ShapeKind),
}

impl Takes {
    fn describe(self) -> String {
        match self {
            Takes::Any => "a Plane, Cylinder or Container".into(),
            Takes::Only(kind) => {
                let name = kind.name();
                format!("a {}{}", name[..1].to_uppercase(), &name[1..])
            }
        }
    }

    fn accepts(self, shape: &Static) -> bool {
        match self {
            Takes::Any => true,
            Takes::Only(kind) => shape.kind() == kind,
        }
    }
}

/// `obj` as a static shape of a kind `takes` accepts, or a `TypeError` naming `name`.
pub(crate) fn static_shape(obj: &Bound<'_, PyAny>, name: &str, takes: Takes) -> PyResult<Static> {
    let shape = if let Ok(p) = obj.cast::<Plane>() {
        Some(Static::from(p.get().shape))
    } else if let Ok(c) = obj.cast::<Cylinder>() {
        Some(Static::from(c.get().shape))
    } else if let Ok(k) = obj.cast::<Container>() {
        Some(Static::from(k.get().shape))
    } else {
        None
    };
    shape
        .filter(|s| takes.accepts(s))
        .ok_or_else(|| wrong_type(name, &takes.describe(), obj))
}
