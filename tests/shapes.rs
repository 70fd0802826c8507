//! Every constructor rejects bad input with an error naming the shape and field; none panics.

use spheresweep::{Container, Cylinder, Plane, Problem, ShapeKind, Sphere};

const NAN: f32 = f32::NAN;
const INF: f32 = f32::INFINITY;

fn check<T: std::fmt::Debug>(
    r: Result<T, spheresweep::ShapeError>,
    kind: ShapeKind,
    field: &str,
    problem: Problem,
) {
    let e = r.unwrap_err();
    assert_eq!((e.kind, e.field, e.problem), (kind, field, problem));
    assert!(
        e.to_string().starts_with(&format!("{kind} {field} ")),
        "{e}"
    );
}

#[test]
fn sphere_fields() {
    use ShapeKind::Sphere as S;
    let ok = [0.0f32; 3];
    check(
        Sphere::new([NAN, 0.0, 0.0], ok, 1.0, 1.0),
        S,
        "centre",
        Problem::NotFinite,
    );
    check(
        Sphere::new(ok, [0.0, INF, 0.0], 1.0, 1.0),
        S,
        "velocity",
        Problem::NotFinite,
    );
    check(
        Sphere::new(ok, ok, -1.0, 1.0),
        S,
        "radius",
        Problem::Negative,
    );
    check(
        Sphere::new(ok, ok, NAN, 1.0),
        S,
        "radius",
        Problem::NotFinite,
    );
    check(
        Sphere::new(ok, ok, 1.0, 0.0),
        S,
        "mass",
        Problem::NotPositive,
    );
    check(
        Sphere::new(ok, ok, 1.0, -INF),
        S,
        "mass",
        Problem::NotFinite,
    );
    assert!(
        Sphere::new(ok, ok, 0.0, 1.0).is_ok(),
        "a point sphere is valid"
    );
}

#[test]
fn plane_fields() {
    use ShapeKind::Plane as P;
    check(
        Plane::new([0.0, 0.0, NAN], [0.0, 0.0, 1.0]),
        P,
        "point",
        Problem::NotFinite,
    );
    check(
        Plane::new([0.0; 3], [0.0; 3]),
        P,
        "normal",
        Problem::ZeroLength,
    );
    check(
        Plane::new([0.0; 3], [INF, 0.0, 0.0]),
        P,
        "normal",
        Problem::NotFinite,
    );
    // Tiny and huge normals normalise without underflow or overflow.
    let tiny = Plane::new([0.0; 3], [1e-45, 0.0, 0.0]).unwrap();
    let huge = Plane::new([0.0; 3], [3e38, 3e38, 0.0]).unwrap();
    assert_eq!(tiny.normal().to_array(), [1.0, 0.0, 0.0]);
    assert!((huge.normal().length() - 1.0).abs() < 1e-6);
}

#[test]
fn cylinder_fields() {
    use ShapeKind::Cylinder as C;
    let p = [1.0f32, 2.0, 3.0];
    check(Cylinder::new(p, p, 1.0), C, "axis", Problem::ZeroLength);
    check(Cylinder::new([NAN; 3], p, 1.0), C, "p1", Problem::NotFinite);
    check(
        Cylinder::new(p, [0.0, -INF, 0.0], 1.0),
        C,
        "p2",
        Problem::NotFinite,
    );
    check(
        Cylinder::new(p, [0.0; 3], -0.5),
        C,
        "radius",
        Problem::Negative,
    );
    // Axis points at opposite ends of the f32 range: the difference overflows f32, not f64.
    let wide = Cylinder::new([-3e38, 0.0, 0.0], [3e38, 0.0, 0.0], 1.0).unwrap();
    assert_eq!(wide.axis().to_array(), [1.0, 0.0, 0.0]);
}

#[test]
fn container_fields() {
    use ShapeKind::Container as K;
    check(
        Container::new([0.0, NAN, 0.0], 1.0),
        K,
        "centre",
        Problem::NotFinite,
    );
    check(
        Container::new([0.0; 3], -1.0),
        K,
        "radius",
        Problem::Negative,
    );
    check(
        Container::new([0.0; 3], INF),
        K,
        "radius",
        Problem::NotFinite,
    );
}

#[test]
fn cylinder_from_a_point_and_a_direction() {
    use ShapeKind::Cylinder as C;
    let c = Cylinder::from_axis([1e5, 2.0, 3.0], [0.0, 3.0, 4.0], 0.5).unwrap();
    assert_eq!(c.point().to_array(), [1e5, 2.0, 3.0]);
    assert_eq!(c.axis().to_array(), [0.0, 0.6, 0.8]);
    // The two-point form rounds p + s first: the axis tilts far from the origin.
    let two = Cylinder::new([1e5, 0.0, 0.0], [1e5 + 0.003, 0.0, 1.0], 0.5).unwrap();
    let exact = Cylinder::from_axis([1e5, 0.0, 0.0], [0.003, 0.0, 1.0], 0.5).unwrap();
    assert!((two.axis() - exact.axis()).length() > 2e-3);
    check(
        Cylinder::from_axis([0.0; 3], [0.0; 3], 1.0),
        C,
        "axis",
        Problem::ZeroLength,
    );
    check(
        Cylinder::from_axis([f32::NAN, 0.0, 0.0], [0.0, 0.0, 1.0], 1.0),
        C,
        "point",
        Problem::NotFinite,
    );
    check(
        Cylinder::from_axis([0.0; 3], [0.0, f32::INFINITY, 0.0], 1.0),
        C,
        "axis",
        Problem::NotFinite,
    );
    check(
        Cylinder::from_axis([0.0; 3], [0.0, 0.0, 1.0], -1.0),
        C,
        "radius",
        Problem::Negative,
    );
}
