//! The 8-wide kernels against the f64 reference, every pair kind × accuracy mode: hit/miss
//! agree outside the bands of ill-conditioning, and times agree within the per-case bound of
//! the rounding-error model (tests/common, docs/derivations/accuracy.md).

mod common;

use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

use common::{Kernel, Pair, model};
use proptest::prelude::*;
use proptest::test_runner::TestRunner;
use spheresweep::{Accuracy, Container, Cylinder, Plane, Shape, Sphere};

fn coord() -> impl Strategy<Value = f32> {
    -100.0f32..100.0
}
fn vec3() -> impl Strategy<Value = [f32; 3]> {
    [coord(), coord(), coord()]
}
fn velocity() -> impl Strategy<Value = [f32; 3]> {
    prop_oneof![
        4 => [-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0],
        1 => [-1e-3f32..1e-3, -1e-3f32..1e-3, -1e-3f32..1e-3],
    ]
}
fn radius() -> impl Strategy<Value = f32> {
    prop_oneof![4 => 0.01f32..10.0, 1 => Just(0.0f32)]
}
/// A common offset of the whole scene: none, or up to 1e5 away from the origin.
fn offset() -> impl Strategy<Value = [f32; 3]> {
    prop_oneof![2 => Just([0.0f32; 3]), 1 => [-1e5f32..1e5, -1e5f32..1e5, -1e5f32..1e5]]
}
fn t_max() -> impl Strategy<Value = f32> {
    prop::sample::select(vec![1.0f32, 10.0, 100.0, f32::INFINITY])
}
fn shift(p: [f32; 3], o: [f32; 3]) -> [f32; 3] {
    [p[0] + o[0], p[1] + o[1], p[2] + o[2]]
}
fn sphere_at(o: [f32; 3]) -> impl Strategy<Value = Sphere> {
    (vec3(), velocity(), radius())
        .prop_map(move |(c, v, r)| Sphere::new(shift(c, o), v, r, 1.0).unwrap())
}

fn pairs() -> impl Strategy<Value = Pair> {
    offset().prop_flat_map(|o| {
        let other = prop_oneof![
            sphere_at(o).prop_map(Shape::Sphere),
            (vec3(), vec3())
                .prop_filter_map("zero normal", move |(p, n)| Plane::new(shift(p, o), n).ok())
                .prop_map(Shape::Plane),
            (vec3(), vec3(), radius())
                .prop_filter_map("degenerate axis", move |(a, b, r)| {
                    Cylinder::new(shift(a, o), shift(b, o), r).ok()
                })
                .prop_map(Shape::Cylinder),
            (
                [-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0],
                20.0f32..300.0
            )
                .prop_map(move |(c, r)| Shape::Container(Container::new(shift(c, o), r).unwrap())),
        ];
        (sphere_at(o), other).prop_map(|(sphere, other)| Pair { sphere, other })
    })
}

fn check(pair: &Pair, mode: Accuracy, t_max: f32) -> Result<bool, TestCaseError> {
    let reference = pair.time_of_impact(f64::from(t_max));
    let kernel = pair.kernel(mode, t_max);
    let m = model(pair, mode, f64::from(t_max));
    match (reference, kernel) {
        // Inside the band a container's answer may switch between its root and t = 0: a
        // sphere past the wall with q within rounding of 0 either comes back in (the root) or
        // never does (a contact now; reference::quadratic::in_contact_now).
        (Some(r), Some(k)) if m.ambiguous && (r == 0.0) != (k == 0.0) => {}
        (Some(r), Some(k)) => {
            let err = (f64::from(k) - r).abs();
            prop_assert!(
                err <= m.dt,
                "{mode}: t = {k} vs reference {r}: error {err:e} > bound {:e}\n{pair:?}",
                m.dt
            );
            prop_assert!(k <= t_max && k >= 0.0);
        }
        (None, None) => {}
        (r, k) => prop_assert!(
            m.ambiguous,
            "{mode}: hit/miss differs outside the band: reference {r:?}, kernel {k:?}, \
             q = {:e} ± {:e}\n{pair:?}",
            m.q,
            m.dq
        ),
    }
    Ok(m.ambiguous)
}

/// The cases `check` saw, and per mode (`Accuracy::ALL`'s order) how many fell in a band,
/// where hit/miss is not compared: a band grown too wide would pass every case unseen, so the
/// tests bound these counts.
#[derive(Default)]
struct Bands {
    checked: AtomicU64,
    ambiguous: [AtomicU64; 3],
}

impl Bands {
    /// `check` in every mode, counted; a point sphere against a plane is checked but not
    /// counted: it is exactly grazing (`q = 0`), in a band in every mode by construction, and
    /// `point_sphere_on_a_plane_always_hits` tests it on its own.
    fn check_all(&self, pair: &Pair, t_max: f32) -> Result<(), TestCaseError> {
        let grazing = pair.sphere.radius() == 0.0 && matches!(pair.other, Shape::Plane(_));
        if !grazing {
            self.checked.fetch_add(1, Relaxed);
        }
        for (k, mode) in Accuracy::ALL.into_iter().enumerate() {
            if check(pair, mode, t_max)? && !grazing {
                self.ambiguous[k].fetch_add(1, Relaxed);
            }
        }
        Ok(())
    }

    /// Asserts that in each mode at most `share` of the cases checked were in a band.
    fn at_most(&self, share: [f64; 3]) {
        let n = self.checked.load(Relaxed);
        assert!(n > 0, "no case was checked");
        for (k, mode) in Accuracy::ALL.into_iter().enumerate() {
            let m = self.ambiguous[k].load(Relaxed);
            let most = (share[k] * n as f64).floor() as u64;
            assert!(
                m <= most,
                "{mode}: {m} of {n} cases in a band of ill-conditioning, more than {most} \
                 ({} %): the rounding model's bands have grown",
                share[k] * 100.0
            );
        }
    }
}

/// Runs `test` on `cases` draws of `strategy` (failures persisted and replayed as by
/// `proptest!`), and returns the bands it counted.
fn run<S: Strategy>(
    cases: u32,
    strategy: S,
    test: impl Fn(S::Value, &Bands) -> Result<(), TestCaseError>,
) -> Bands {
    let config = ProptestConfig {
        cases,
        source_file: Some(file!()),
        ..ProptestConfig::default()
    };
    let bands = Bands::default();
    if let Err(e) = TestRunner::new(config).run(&strategy, |v| test(v, &bands)) {
        panic!("{e}");
    }
    bands
}

/// The share of the cases in a band of ill-conditioning, per mode (`textbook`, `stable`,
/// `double`), at most; point spheres against planes, exactly grazing, are not counted
/// ([`Bands::check_all`]). The bands are `O(u)` wide relative to the quantities they bound
/// (tests/common; docs/derivations/accuracy.md, "How many cases the bands hold"): with `u₆₄`
/// no draw should fall in one (none did in eight runs of either test), so 0.05 %; with `u₃₂`
/// the stable bands held 0.04–0.10 % of the cases in those runs, and the textbook bands,
/// quadratic in `X/D`, 1.8–2.3 % (mostly offset scenes). The bounds are at least six
/// binomial deviations above those; the `q` band 10 times too wide breaks textbook's (4 %),
/// 100 times too wide stable's too (0.35 %).
const BANDS_AT_MOST: [f64; 3] = [0.03, 0.0025, 0.0005];

#[test]
fn kernels_agree_with_the_reference() {
    run(30000, (pairs(), t_max()), |(pair, t_max), bands| {
        bands.check_all(&pair, t_max)
    })
    .at_most(BANDS_AT_MOST);
}

/// Hand-derived cases answered exactly by every mode (all values are exact in binary).
#[test]
fn exact_cases_in_every_mode() {
    let ball = |c: [f32; 3], v: [f32; 3], r: f32| Sphere::new(c, v, r, 1.0).unwrap();
    let cases = [
        // sphere–sphere, t = 4 (reference_cases.rs)
        (
            ball([0.0; 3], [0.0; 3], 1.0),
            Shape::Sphere(ball([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0)),
            Some(4.0),
        ),
        // overlapping, approaching: 0; separating: none
        (
            ball([0.0; 3], [0.0; 3], 1.0),
            Shape::Sphere(ball([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0)),
            Some(0.0),
        ),
        (
            ball([0.0; 3], [0.0; 3], 1.0),
            Shape::Sphere(ball([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0)),
            None,
        ),
        // no relative motion
        (
            ball([0.0; 3], [1.0; 3], 1.0),
            Shape::Sphere(ball([0.5, 0.0, 0.0], [1.0; 3], 1.0)),
            None,
        ),
        // plane from the front at 2, parallel motion never
        (
            ball([1.0, 2.0, 5.0], [0.0, 0.0, -2.0], 1.0),
            Shape::Plane(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap()),
            Some(2.0),
        ),
        (
            ball([0.0, 0.0, 5.0], [3.0, -1.0, 0.0], 1.0),
            Shape::Plane(Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap()),
            None,
        ),
        // point sphere on a plane: (1 − 5)/(−2) = 2
        (
            ball([0.0, 0.0, 5.0], [1.0, 0.0, -2.0], 0.0),
            Shape::Plane(Plane::new([7.0, 7.0, 1.0], [0.0, 0.0, 1.0]).unwrap()),
            Some(2.0),
        ),
        // cylinder at 4; along the axis never
        (
            ball([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0),
            Shape::Cylinder(Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0).unwrap()),
            Some(4.0),
        ),
        (
            ball([1.5, 0.0, 0.0], [0.0, 0.0, 3.0], 1.0),
            Shape::Cylinder(Cylinder::new([0.0; 3], [0.0, 0.0, 1.0], 1.0).unwrap()),
            None,
        ),
        // container exits: 2 and 7; at the wall moving out: 0; too big: 0
        (
            ball([0.0; 3], [0.0, 2.0, 0.0], 1.0),
            Shape::Container(Container::new([0.0; 3], 5.0).unwrap()),
            Some(2.0),
        ),
        (
            ball([3.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0),
            Shape::Container(Container::new([0.0; 3], 5.0).unwrap()),
            Some(7.0),
        ),
        (
            ball([4.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0),
            Shape::Container(Container::new([0.0; 3], 5.0).unwrap()),
            Some(0.0),
        ),
        (
            ball([0.0; 3], [0.0; 3], 6.0),
            Shape::Container(Container::new([0.0; 3], 5.0).unwrap()),
            Some(0.0),
        ),
    ];
    for (sphere, other, expected) in cases {
        let pair = Pair { sphere, other };
        for mode in Accuracy::ALL {
            assert_eq!(pair.kernel(mode, 100.0), expected, "{mode} {pair:?}");
        }
    }
}

/// Bodies closing in from within rounding of contact (a new user's trial, 2026-12-07): in
/// f32 the literal `textbook` root `(−B ∓ √disc)/2A` cancels to `t ≤ 0` and the textbook
/// kernel answered none, where the others hit within `10⁻⁵`; a sphere then left its container.
/// Every mode now hits each, within the model's bound of the reference.
#[test]
fn closing_in_from_within_rounding_of_contact_is_a_hit_in_every_mode() {
    let ball = |c: [f32; 3], v: [f32; 3], r: f32| Sphere::new(c, v, r, 1.0).unwrap();
    let cases = [
        (
            ball(
                [-1.066_741_8, 1.394_534, -1.183_227_1],
                [1.556_234_7, 0.500_362_04, 0.021_106_685],
                1.483_226_9,
            ),
            Shape::Plane(Plane::new([0.0, 0.0, 0.3], [0.0, 0.0, 1.0]).unwrap()),
        ),
        (
            ball(
                [-2.082_564_6, -4.128_495, -4.423_045_6],
                [-0.860_212_2, -0.756_590_1, -1.509_870_2],
                1.113_020_2,
            ),
            Shape::Container(Container::new([0.1, -0.3, 0.2], 7.5).unwrap()),
        ),
        (
            ball(
                [-2.968_662_7, -3.236_746_5, 3.923_958],
                [-2.350_431, 0.301_671_95, -1.150_322_6],
                1.426_205_6,
            ),
            Shape::Sphere(ball(
                [-5.549_704_6, -2.780_023_6, 3.148_502],
                [0.361_639_38, -1.577_906_3, -1.573_797_5],
                1.307_236_3,
            )),
        ),
        (
            ball(
                [-1.978_376_7, -4.440_256, 1.777_090_1],
                [-1.145_725_7, -0.254_963_73, -0.003_214_094_3],
                0.562_539_4,
            ),
            Shape::Sphere(ball(
                [-2.500_066, -5.216_861_2, 1.288_757_7],
                [-0.097_182_214, 1.707_222_3, -0.120_502_934],
                0.492_801_1,
            )),
        ),
    ];
    for (sphere, other) in cases {
        let pair = Pair { sphere, other };
        assert!(pair.time_of_impact(100.0).is_some(), "reference: {pair:?}");
        for mode in Accuracy::ALL {
            assert!(pair.kernel(mode, 100.0).is_some(), "{mode}: none\n{pair:?}");
            check(&pair, mode, 100.0).unwrap();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(10000))]

    /// A point sphere approaching a plane grazes it exactly (B² − 4AC = 0 in exact arithmetic,
    /// which the literal formula may round either way). `Stable` and `Double` compute
    /// `q = v² D² = 0` with no cancellation: always a hit, at `t = (r_P0 − r_A0)·n̂ / (v_A·n̂)`
    /// within `δt/t ≤ δR0/|R0| + δv/|v·n̂| + 3u` (δR0 = K u X, δv = K u ‖v‖).
    #[test]
    fn point_sphere_on_a_plane_always_hits(c in vec3(), v in velocity(), p in vec3(), n in vec3()) {
        let Ok(plane) = Plane::new(p, n) else { return Ok(()) };
        let nn = plane.normal().as_dvec3();
        let r0 = (glam::Vec3::from(c).as_dvec3() - plane.point().as_dvec3()).dot(nn);
        let vn = glam::Vec3::from(v).as_dvec3().dot(nn);
        prop_assume!(r0 * vn != 0.0);
        // Head for the plane: flip the velocity if it points away.
        let (v, vn) = if r0 * vn > 0.0 { (v.map(|x| -x), -vn) } else { (v, vn) };
        let sphere = Sphere::new(c, v, 0.0, 1.0).unwrap();
        let pair = Pair { sphere, other: Shape::Plane(plane) };
        let t = -r0 / vn;
        for mode in [Accuracy::Stable, Accuracy::Double] {
            let x = pair.operand_scale(mode);
            let u = if mode == Accuracy::Double { common::U64 } else { common::U32 };
            let bound = t * (common::K * u * (x / r0.abs() + pair.speed() / vn.abs()) + 3.0 * u)
                + common::U32 * t;
            let k = pair.kernel(mode, f32::INFINITY);
            prop_assert!(k.is_some(), "{mode}: point sphere missed the plane");
            let err = (f64::from(k.unwrap()) - t).abs();
            prop_assert!(err <= bound, "{mode}: {err:e} > {bound:e}");
        }
    }
}

/// `pair` with every position and radius multiplied by `2^kx` and every velocity by `2^kv`
/// (powers of two: exact in f32 while the values stay finite and normal), or `None` when a
/// value would overflow or lose bits to underflow.
fn scaled(pair: &Pair, kx: i32, kv: i32) -> Option<Pair> {
    let (sx, sv) = (2f32.powi(kx), 2f32.powi(kv));
    let ok = |x: f32, s: f32| {
        let y = x * s;
        (y.is_finite() && (y == 0.0 || y.is_normal()) && y / s == x).then_some(y)
    };
    let v3 = |v: glam::Vec3, s: f32| Some([ok(v.x, s)?, ok(v.y, s)?, ok(v.z, s)?]);
    let s = &pair.sphere;
    let sphere = Sphere::new(
        v3(s.centre(), sx)?,
        v3(s.velocity(), sv)?,
        ok(s.radius(), sx)?,
        1.0,
    )
    .ok()?;
    let other = match pair.other {
        Shape::Sphere(b) => Shape::Sphere(
            Sphere::new(
                v3(b.centre(), sx)?,
                v3(b.velocity(), sv)?,
                ok(b.radius(), sx)?,
                1.0,
            )
            .ok()?,
        ),
        Shape::Plane(p) => {
            Shape::Plane(Plane::new(v3(p.point(), sx)?, p.normal().to_array()).ok()?)
        }
        Shape::Cylinder(c) => Shape::Cylinder(
            Cylinder::from_axis(v3(c.point(), sx)?, c.axis().to_array(), ok(c.radius(), sx)?)
                .ok()?,
        ),
        Shape::Container(k) => {
            Shape::Container(Container::new(v3(k.centre(), sx)?, ok(k.radius(), sx)?).ok()?)
        }
        _ => return None,
    };
    Some(Pair { sphere, other })
}

/// Every scale from 2⁻¹²⁰ to 2¹²⁰ (about 10⁻³⁶ … 10³⁶): positions and radii, velocities,
/// or both together. The f64 reference holds every such input exactly; each mode either
/// stays in the f32 range where its rounding model holds or answers the lane in f64, so
/// the same error model bounds it at every scale — no wrong hit/miss outside the band, no
/// time (a false `t = 0` included) outside the bound — and the bands hold no more of the
/// cases than at scale 1 ([`BANDS_AT_MOST`]).
#[test]
fn kernels_agree_with_the_reference_at_every_scale() {
    let strategy = (pairs(), -120i32..=120, -120i32..=120, 0u8..3);
    run(20000, strategy, |(pair, kx, kv, which), bands| {
        let (kx, kv) = match which {
            0 => (kx, kx), // everything together: times unchanged
            1 => (kx, 0),  // positions and radii alone
            _ => (0, kv),  // speeds alone
        };
        let Some(pair) = scaled(&pair, kx, kv) else {
            return Ok(());
        };
        let t_max = 10f32 * 2f32.powi(kx - kv);
        prop_assume!(t_max.is_normal());
        bands.check_all(&pair, t_max)
    })
    .at_most(BANDS_AT_MOST);
}

/// A sphere touching the inside of its container and moving exactly tangentially, and one that
/// fits exactly and moves: `g(t) = A t² + C` grows at once, so both leave the vessel at once
/// (docs/derivations/policies.md). Every mode and the reference say `t = 0`.
#[test]
fn tangential_exact_fit_and_stranded_container_contacts_are_at_zero() {
    let vessel = Shape::Container(Container::new([0.0; 3], 5.0).unwrap());
    let cases = [
        Sphere::new([4.0, 0.0, 0.0], [0.0, 1.0, 0.0], 1.0, 1.0).unwrap(),
        Sphere::new([0.0; 3], [0.0, 0.0, 3.0], 5.0, 1.0).unwrap(),
        Sphere::new([1e-3, 0.0, 0.0], [0.0, 2.0, 0.0], 5.0, 1.0).unwrap(),
    ];
    for sphere in cases {
        let pair = Pair {
            sphere,
            other: vessel,
        };
        assert_eq!(pair.time_of_impact(10.0), Some(0.0), "{pair:?}");
        for mode in Accuracy::ALL {
            assert_eq!(pair.kernel(mode, 10.0), Some(0.0), "{mode} {pair:?}");
        }
    }
    // Past the wall and moving inwards too slowly ever to get back inside (q < 0): a contact
    // now, in every mode; under the policy of before 2026-12-01 this was "no contact" and the
    // sphere left its vessel (docs/derivations/simulation.md, "Concave walls").
    let slow = Sphere::new([5.5001, 0.0, 0.0], [-1e-6, 1.0, 0.0], 0.5, 1.0).unwrap();
    let pair = Pair {
        sphere: slow,
        other: Shape::Container(Container::new([0.0; 3], 6.0).unwrap()),
    };
    assert_eq!(pair.time_of_impact(10.0), Some(0.0), "{pair:?}");
    for mode in Accuracy::ALL {
        assert_eq!(pair.kernel(mode, 10.0), Some(0.0), "{mode} {pair:?}");
    }
    // Fast enough inwards, it comes back inside and meets the wall across the vessel.
    let back = Sphere::new([5.5001, 0.0, 0.0], [-0.1, 1.0, 0.0], 0.5, 1.0).unwrap();
    let pair = Pair {
        sphere: back,
        ..pair
    };
    let t = pair.time_of_impact(10.0).unwrap();
    assert!(t > 1.0, "{t}");
    for mode in Accuracy::ALL {
        assert!(pair.kernel(mode, 10.0).is_some_and(|k| k > 1.0), "{mode}");
    }
    // Outside, the same tangential motion separates: no contact.
    let ball = Shape::Sphere(Sphere::new([2.0, 0.0, 0.0], [0.0; 3], 1.0, 1.0).unwrap());
    let tangent = Sphere::new([0.0; 3], [0.0, 1.0, 0.0], 1.0, 1.0).unwrap();
    let pair = Pair {
        sphere: tangent,
        other: ball,
    };
    assert_eq!(pair.time_of_impact(10.0), None);
    for mode in Accuracy::ALL {
        assert_eq!(pair.kernel(mode, 10.0), None, "{mode}");
    }
}
