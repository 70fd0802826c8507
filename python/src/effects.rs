//! What collisions do in `Simulation.from_spheres`, as a scene file's `[effects]`: the scene's
//! response, materials and per-pair overrides, each error naming the argument.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use spheresweep::sim::{self, Response};

use crate::args::{integer, real, show, text, type_name};

/// The response of a coefficient of restitution in `[0, 1]`: elastic at 1, inelastic below.
fn response_of(restitution: f64, what: &str) -> PyResult<Response> {
    if !(0.0..=1.0).contains(&restitution) {
        return Err(PyValueError::new_err(format!(
            "{what} {} is not in [0, 1]",
            show(restitution)
        )));
    }
    Ok(if restitution == 1.0 {
        Response::Elastic
    } else {
        Response::Inelastic { restitution }
    })
}

/// The scene's response, as a scene file's `[effects]`: `response` by name (`"none"`,
/// `"elastic"`, `"inelastic"` with `restitution` required, `"sticky"`), a `restitution` only
/// with `"inelastic"`; or, without `response`, the one `restitution` implies (elastic at 1 or
/// when absent, inelastic below).
pub(crate) fn scene_response(
    response: Option<&Bound<'_, PyAny>>,
    restitution: Option<&Bound<'_, PyAny>>,
) -> PyResult<Response> {
    let response = response.map(|r| text(r, "response")).transpose()?;
    let restitution = restitution.map(|e| real(e, "restitution")).transpose()?;
    let Some(name) = response else {
        return restitution.map_or(Ok(Response::Elastic), |e| response_of(e, "restitution:"));
    };
    // NaN when absent: then "inelastic" is refused below, and the others ignore it.
    let named = Response::named(&name, restitution.unwrap_or(f64::NAN)).ok_or_else(|| {
        let names = Response::NAMES.map(|n| format!("{n:?}")).join(", ");
        PyValueError::new_err(format!("response: {name:?} is not one of {names}"))
    })?;
    match (named, restitution) {
        (Response::Inelastic { .. }, Some(e)) => {
            response_of(e, "restitution:")?;
            Ok(named)
        }
        (Response::Inelastic { .. }, None) => Err(PyValueError::new_err(
            "restitution: required with response \"inelastic\"",
        )),
        (other, Some(e)) => Err(PyValueError::new_err(format!(
            "restitution: {} given with response {:?} (it applies to \"inelastic\" only)",
            show(e),
            other.name()
        ))),
        (other, None) => Ok(other),
    }
}

/// A material index from Python: an integer in `[0, MAX_MATERIALS)`, or an error naming
/// `what`.
pub(crate) fn material_index(value: &Bound<'_, PyAny>, what: &str) -> PyResult<u16> {
    let i = integer(value, what).map_err(|_| {
        PyTypeError::new_err(format!(
            "{what}: a material is an integer, got {}",
            type_name(value)
        ))
    })?;
    match u16::try_from(i) {
        Ok(m) if usize::from(m) < sim::MAX_MATERIALS => Ok(m),
        _ => Err(PyValueError::new_err(format!(
            "{what}: material {i} is not in [0, {}]",
            sim::MAX_MATERIALS - 1
        ))),
    }
}

/// One entry of `pairs`: `(a, b, response)` with `response` a restitution in `[0, 1]` or
/// `"elastic"` / `"sticky"`.
pub(crate) fn material_pair(item: &Bound<'_, PyAny>, what: &str) -> PyResult<sim::MaterialPair> {
    let parts: Vec<Bound<'_, PyAny>> = item
        .try_iter()
        .and_then(|it| it.collect())
        .ok()
        .filter(|p: &Vec<_>| p.len() == 3)
        .ok_or_else(|| {
            PyTypeError::new_err(format!("{what}: expected a tuple (a, b, response)"))
        })?;
    let a = material_index(&parts[0], &format!("{what}.a"))?;
    let b = material_index(&parts[1], &format!("{what}.b"))?;
    let label = format!("{what}.response");
    let response = if let Ok(name) = parts[2].extract::<String>() {
        match Response::named(&name, f64::NAN) {
            Some(named @ (Response::Elastic | Response::Sticky)) => named,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{label}: {name:?} is not a restitution, \"elastic\" or \"sticky\""
                )));
            }
        }
    } else {
        let e = real(&parts[2], &label).map_err(|_| {
            PyTypeError::new_err(format!(
                "{label}: expected a restitution or \"elastic\" / \"sticky\", got {}",
                type_name(&parts[2])
            ))
        })?;
        response_of(e, &format!("{label}: restitution"))?
    };
    Ok(sim::MaterialPair { a, b, response })
}
