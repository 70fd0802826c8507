//! proptest invariants of the f64 reference on random and adversarial inputs.
//!
//! Random inputs lie on a 2⁻¹⁰ grid, so every f32 input and every difference of inputs is exact
//! and the invariants that are exact in real arithmetic (swap, translation, Galilean frame) are
//! asserted as equalities. Tolerances elsewhere are derived in
//! docs/derivations/reference-bounds.md.

use glam::DVec3;
use proptest::prelude::*;
use spheresweep::reference::{sphere_container, sphere_cylinder, sphere_plane, sphere_sphere};
use spheresweep::{Container, Cylinder, Plane, Sphere};

const T_MAX: f64 = 64.0;
const EPS: f64 = f64::EPSILON / 2.0; // unit roundoff 2⁻⁵³

fn grid(lim: i32) -> impl Strategy<Value = f32> {
    (-lim * 1024..=lim * 1024).prop_map(|k| k as f32 / 1024.0)
}
fn vec3(lim: i32) -> impl Strategy<Value = [f32; 3]> {
    [grid(lim), grid(lim), grid(lim)]
}
fn radius() -> impl Strategy<Value = f32> {
    (64..=4096).prop_map(|k| k as f32 / 1024.0)
}
/// Adversarial values: zero, tiny, huge, and near-ties, mixed with the grid.
fn nasty() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => grid(100),
        1 => Just(0.0f32),
        1 => prop::sample::select(vec![1e-7f32, -1e-7, 1e-20, 3e5, -3e5, 1e9, 1.0 + f32::EPSILON]),
    ]
}
fn nasty3() -> impl Strategy<Value = [f32; 3]> {
    [nasty(), nasty(), nasty()]
}
fn sphere(lim: i32) -> impl Strategy<Value = Sphere> {
    (vec3(lim), vec3(8), radius()).prop_map(|(c, v, r)| Sphere::new(c, v, r, 1.0).unwrap())
}
fn nasty_sphere() -> impl Strategy<Value = Sphere> {
    (
        nasty3(),
        nasty3(),
        prop_oneof![radius(), Just(0.0f32), Just(1e-7f32), Just(1e4f32)],
    )
        .prop_map(|(c, v, r)| Sphere::new(c, v, r, 1.0).unwrap())
}

/// Sphere `s`'s centre at time `t` relative to `origin`: the centres subtracted in f64 first,
/// so that the check's rounding is of the size of the pair's own vectors (`Sizes::scale`), as
/// docs/derivations/reference-bounds.md assumes, and not of their distance from the origin.
fn from(s: &Sphere, origin: DVec3, t: f64) -> DVec3 {
    (s.centre().as_dvec3() - origin) + s.velocity().as_dvec3() * t
}

/// Sizes of one pair: `‖r0‖`, `‖v‖`, `D`. `scale(t) = ‖r0‖ + ‖v‖ t + D` bounds every vector
/// the reference and the checks form up to time `t`.
struct Sizes {
    r0: f64,
    v: f64,
    d: f64,
}

impl Sizes {
    fn scale(&self, t: f64) -> f64 {
        self.r0 + self.v * t + self.d
    }
}

/// Checks, for one pair, the invariants that hold on any input:
/// - the time is in the window;
/// - the gap `g(t) = ±(dist² − D²)` (positive when apart) computed independently from the
///   positions is never below `−τ` at 65 sampled times in `[0, t)` (or `[0, t_max]` on a
///   miss), unless the bodies start past the contact distance; `τ = 64 ε scale²`;
/// - if well conditioned (`scale(t) ≤ 1000 D`), `dist = D` at the reported root within 1e-9
///   relative (the bound `8 ε (scale/D)² < 9e-10`).
fn check_pair(
    toi: Option<f64>,
    sizes: Sizes,
    gap2: impl Fn(f64) -> f64,
) -> Result<(), TestCaseError> {
    if let Some(t) = toi {
        prop_assert!((0.0..=T_MAX).contains(&t), "t = {t}");
    }
    let scale = sizes.scale(T_MAX);
    let tau = 64.0 * EPS * scale * scale;
    if gap2(0.0) >= 0.0 {
        let end = toi.unwrap_or(T_MAX);
        for k in 0..=64 {
            let tk = end * f64::from(k) / 64.0;
            if tk < end || toi.is_none() {
                prop_assert!(
                    gap2(tk) >= -tau,
                    "closer than D at {tk} < {end}: {}",
                    gap2(tk)
                );
            }
        }
    }
    let d = sizes.d;
    if let Some(t) = toi.filter(|&t| t > 0.0 && sizes.scale(t) <= 1000.0 * d) {
        // dist² − D² = gap2 ⇒ dist − D ≈ gap2 / 2D.
        let rel = gap2(t).abs() / (2.0 * d * d);
        prop_assert!(
            rel <= 1e-9,
            "distance off D by {rel:e} (relative) at t = {t}"
        );
    }
    Ok(())
}

fn check_sphere_sphere(a: &Sphere, b: &Sphere) -> Result<(), TestCaseError> {
    let toi = sphere_sphere::time_of_impact(a, b, T_MAX);
    let d = f64::from(a.radius()) + f64::from(b.radius());
    let sizes = Sizes {
        r0: (b.centre() - a.centre()).as_dvec3().length(),
        v: (b.velocity() - a.velocity()).as_dvec3().length(),
        d,
    };
    let (r0, v) = (
        b.centre().as_dvec3() - a.centre().as_dvec3(),
        b.velocity().as_dvec3() - a.velocity().as_dvec3(),
    );
    check_pair(toi, sizes, |t| (r0 + v * t).length_squared() - d * d)?;
    // Swapping A and B negates r0 and v: bit-for-bit the same quadratic and time.
    prop_assert_eq!(toi, sphere_sphere::time_of_impact(b, a, T_MAX));
    Ok(())
}

fn check_container(s: &Sphere, k: &Container) -> Result<(), TestCaseError> {
    let toi = sphere_container::time_of_impact(s, k, T_MAX);
    let d = f64::from(k.radius()) - f64::from(s.radius());
    if d <= 0.0 {
        prop_assert_eq!(toi, Some(0.0), "a sphere that does not fit touches at once");
        return Ok(());
    }
    let sizes = Sizes {
        r0: (s.centre() - k.centre()).as_dvec3().length(),
        v: s.velocity().as_dvec3().length(),
        d,
    };
    let centre = k.centre().as_dvec3();
    check_pair(toi, sizes, |t| d * d - from(s, centre, t).length_squared())
}

fn check_plane(s: &Sphere, p: &Plane) -> Result<(), TestCaseError> {
    let toi = sphere_plane::time_of_impact(s, p, T_MAX);
    let d = f64::from(s.radius());
    let (n, point) = (p.normal().as_dvec3().normalize(), p.point().as_dvec3());
    let sizes = Sizes {
        r0: (s.centre() - p.point()).as_dvec3().length(),
        v: s.velocity().as_dvec3().length(),
        d,
    };
    if d == 0.0 {
        return Ok(()); // a point sphere's D = 0: no relative scale for the distance check
    }
    check_pair(toi, sizes, |t| from(s, point, t).dot(n).powi(2) - d * d)
}

fn check_cylinder(s: &Sphere, c: &Cylinder) -> Result<(), TestCaseError> {
    let toi = sphere_cylinder::time_of_impact(s, c, T_MAX);
    let d = f64::from(s.radius()) + f64::from(c.radius());
    let (axis, point) = (c.axis().as_dvec3().normalize(), c.point().as_dvec3());
    let sizes = Sizes {
        r0: (s.centre() - c.point()).as_dvec3().length(),
        v: s.velocity().as_dvec3().length(),
        d,
    };
    check_pair(toi, sizes, |t| {
        let x = from(s, point, t);
        (x - axis * x.dot(axis)).length_squared() - d * d
    })
}

fn moved(s: &Sphere, dx: [f32; 3], dv: [f32; 3]) -> Sphere {
    let c = s.centre() + glam::Vec3::from(dx);
    let v = s.velocity() + glam::Vec3::from(dv);
    Sphere::new(c.into(), v.into(), s.radius(), s.mass()).unwrap()
}

fn plane() -> impl Strategy<Value = Plane> {
    (vec3(50), vec3(1)).prop_filter_map("zero normal", |(p, n)| Plane::new(p, n).ok())
}
fn cylinder() -> impl Strategy<Value = Cylinder> {
    (vec3(50), vec3(50), radius())
        .prop_filter_map("degenerate axis", |(a, b, r)| Cylinder::new(a, b, r).ok())
}
fn container() -> impl Strategy<Value = Container> {
    (vec3(20), (40..=120).prop_map(|r| r as f32)).prop_map(|(c, r)| Container::new(c, r).unwrap())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10000))]

    #[test]
    fn sphere_sphere_invariants(a in sphere(100), b in sphere(100)) {
        check_sphere_sphere(&a, &b)?;
    }

    #[test]
    fn sphere_sphere_adversarial(a in nasty_sphere(), b in nasty_sphere()) {
        check_sphere_sphere(&a, &b)?;
    }

    #[test]
    fn sphere_sphere_frame_invariance(a in sphere(100), b in sphere(100), dx in vec3(1000), dv in vec3(8)) {
        // Grid inputs: r0 and v are bit-for-bit unchanged, so the time must be too.
        let t = sphere_sphere::time_of_impact(&a, &b, T_MAX);
        prop_assert_eq!(t, sphere_sphere::time_of_impact(&moved(&a, dx, dv), &moved(&b, dx, dv), T_MAX));
    }

    #[test]
    fn container_invariants(s in sphere(30), k in container()) {
        check_container(&s, &k)?;
    }

    #[test]
    fn container_adversarial(s in nasty_sphere(), k in container()) {
        check_container(&s, &k)?;
    }

    #[test]
    fn container_translation(s in sphere(30), k in container(), dx in vec3(1000)) {
        let k2 = Container::new((k.centre() + glam::Vec3::from(dx)).into(), k.radius()).unwrap();
        prop_assert_eq!(sphere_container::time_of_impact(&s, &k, T_MAX),
            sphere_container::time_of_impact(&moved(&s, dx, [0.0; 3]), &k2, T_MAX));
    }

    #[test]
    fn plane_invariants(s in sphere(100), p in plane()) {
        check_plane(&s, &p)?;
    }

    #[test]
    fn plane_adversarial(s in nasty_sphere(), p in plane()) {
        check_plane(&s, &p)?;
    }

    #[test]
    fn plane_translation(s in sphere(100), (pt, n) in (vec3(50), vec3(1)), dx in vec3(1000)) {
        // Both planes from the same raw normal: same normalised f32 normal.
        let Ok(p) = Plane::new(pt, n) else { return Ok(()) };
        let p2 = Plane::new((p.point() + glam::Vec3::from(dx)).into(), n).unwrap();
        prop_assert_eq!(sphere_plane::time_of_impact(&s, &p, T_MAX),
            sphere_plane::time_of_impact(&moved(&s, dx, [0.0; 3]), &p2, T_MAX));
    }

    #[test]
    fn cylinder_invariants(s in sphere(100), c in cylinder()) {
        check_cylinder(&s, &c)?;
    }

    #[test]
    fn cylinder_adversarial(s in nasty_sphere(), c in cylinder()) {
        check_cylinder(&s, &c)?;
    }

    #[test]
    fn cylinder_translation(s in sphere(100), (a, b, r) in (vec3(50), vec3(50), radius()), dx in vec3(1000)) {
        // Grid points: p2 − p1 is the same exact difference before and after the move.
        let Ok(c1) = Cylinder::new(a, b, r) else { return Ok(()) };
        let shift = |p: [f32; 3]| (glam::Vec3::from(p) + glam::Vec3::from(dx)).into();
        let c2 = Cylinder::new(shift(a), shift(b), r).unwrap();
        prop_assert_eq!(sphere_cylinder::time_of_impact(&s, &c1, T_MAX),
            sphere_cylinder::time_of_impact(&moved(&s, dx, [0.0; 3]), &c2, T_MAX));
    }
}
