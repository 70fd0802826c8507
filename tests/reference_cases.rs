//! Hand-derived cases for every pair kind and every row of the seed's discussion. Every
//! number below is exact in binary floating point, so the assertions are equalities.

use spheresweep::reference::{
    Roots, Side, earliest_contact, sphere_container, sphere_cylinder, sphere_plane, sphere_sphere,
};
use spheresweep::{Container, Cylinder, Plane, Sphere};

fn ball(c: [f32; 3], v: [f32; 3], r: f32) -> Sphere {
    Sphere::new(c, v, r, 1.0).unwrap()
}

const AT_REST: [f32; 3] = [0.0; 3];

// ---------------------------------------------------------------- sphere – sphere

#[test]
fn spheres_miss_when_discriminant_is_negative() {
    // r0 = (10, 5, 0), v = (−1, 0, 0), D = 2: A = 1, B = −20, C = 125 − 4 = 121,
    // B² − 4AC = 400 − 484 = −84 < 0.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([10.0, 5.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    let q = sphere_sphere::quadratic(&a, &b);
    assert_eq!(
        (q.a, q.b, q.c, q.discriminant()),
        (1.0, -20.0, 121.0, -84.0)
    );
    assert_eq!(q.roots(), Roots::Complex);
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 100.0), None);
}

#[test]
fn spheres_graze_when_discriminant_is_zero() {
    // r0 = (10, 2, 0): C = 104 − 4 = 100, B² − 4AC = 400 − 400 = 0: one root t = 20/2 = 10.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([10.0, 2.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    assert_eq!(
        sphere_sphere::quadratic(&a, &b).roots(),
        Roots::Double(10.0)
    );
    let c = sphere_sphere::first_contact(&a, &b, 100.0).unwrap();
    // At t = 10, B is at (0, 2, 0): touching A at (0, 1, 0); normal on A pushes it to −y.
    assert_eq!(c.time, 10.0);
    assert_eq!(c.other_anchor.to_array(), [0.0, 2.0, 0.0]);
    assert_eq!(c.point.to_array(), [0.0, 1.0, 0.0]);
    assert_eq!(c.normal.to_array(), [0.0, -1.0, 0.0]);
}

#[test]
fn spheres_take_the_smaller_of_two_positive_roots() {
    // r0 = (10, 0, 0), v = (−2, 0, 0), D = 2: A = 4, B = −40, C = 96,
    // B² − 4AC = 1600 − 1536 = 64, t = (40 ∓ 8)/8 = 4 or 6.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0);
    let q = sphere_sphere::quadratic(&a, &b);
    assert_eq!(q.roots(), Roots::Distinct(4.0, 6.0));
    assert_eq!(q.roots().ahead().collect::<Vec<_>>(), [4.0, 6.0]);
    let c = sphere_sphere::first_contact(&a, &b, 100.0).unwrap();
    assert_eq!(
        (c.time, c.centre.x, c.other_anchor.x, c.point.x),
        (4.0, 0.0, 2.0, 1.0)
    );
    // Seed: n̂_B = (r_A − r_B)/‖…‖ = −x (our `normal`), n̂_A = −n̂_B = +x.
    assert_eq!(c.normal.to_array(), [-1.0, 0.0, 0.0]);
}

#[test]
fn spheres_discard_negative_roots() {
    // Separating: v = (+2, 0, 0), B = +40: t = (−40 ∓ 8)/8 = −6 or −4, both behind.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([10.0, 0.0, 0.0], [2.0, 0.0, 0.0], 1.0);
    let roots = sphere_sphere::quadratic(&a, &b).roots();
    assert_eq!(roots, Roots::Distinct(-6.0, -4.0));
    assert_eq!(roots.behind().count(), 2);
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 100.0), None);
}

#[test]
fn spheres_that_overlap_and_approach_touch_at_zero() {
    // r0 = (1, 0, 0), v = (−1, 0, 0), D = 2: A = 1, B = −2, C = −3: roots −1 and 3.
    // Policy: overlapping and moving deeper ⇒ contact at t = 0.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    assert_eq!(
        sphere_sphere::quadratic(&a, &b).roots(),
        Roots::Distinct(-1.0, 3.0)
    );
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 100.0), Some(0.0));
}

#[test]
fn spheres_that_overlap_and_separate_never_touch() {
    // v = (+1, 0, 0): B = 2, roots −3 and 1; t = 1 is where they stop overlapping.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0);
    assert_eq!(
        sphere_sphere::quadratic(&a, &b).roots(),
        Roots::Distinct(-3.0, 1.0)
    );
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 100.0), None);
}

#[test]
fn spheres_touching_at_start() {
    // r0 = (2, 0, 0) = D: C = 0. Approaching (B = −4): roots 0 and 4 ⇒ t = 0.
    // Separating (B = +4): roots −4 and 0 ⇒ none. Tangential (B = 0): double root 0 ⇒ none.
    let a = ball([0.0; 3], AT_REST, 1.0);
    let toward = ball([2.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    let away = ball([2.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0);
    let along = ball([2.0, 0.0, 0.0], [0.0, 1.0, 0.0], 1.0);
    assert_eq!(sphere_sphere::time_of_impact(&a, &toward, 9.0), Some(0.0));
    assert_eq!(sphere_sphere::time_of_impact(&a, &away, 9.0), None);
    assert_eq!(
        sphere_sphere::quadratic(&a, &along).roots(),
        Roots::Double(0.0)
    );
    assert_eq!(sphere_sphere::time_of_impact(&a, &along, 9.0), None);
}

/// policies.md, "moving towards the contact with the arrival root computed at `t ≤ 0`": the
/// exact root is ahead by about `C/|B|` (here `10⁻¹⁷/4` and `10⁻¹⁷/8`), which the literal
/// `(−B ∓ √disc)/2A` cancels to 0: a contact now, not a miss.
#[test]
fn closing_in_within_rounding_of_contact_touches_now() {
    let outside = spheresweep::reference::Quadratic {
        a: 1.0,
        b: -4.0,
        c: 1e-17,
    };
    assert_eq!(outside.roots(), Roots::Distinct(0.0, 4.0));
    assert_eq!(earliest_contact(&outside, Side::Exterior, 9.0), Some(0.0));
    let inside = spheresweep::reference::Quadratic {
        a: 1.0,
        b: 8.0,
        c: -1e-17,
    };
    assert_eq!(inside.roots(), Roots::Distinct(-8.0, 0.0));
    assert_eq!(earliest_contact(&inside, Side::Interior, 9.0), Some(0.0));
    // Moving away instead: none, as before.
    let receding = spheresweep::reference::Quadratic { b: 4.0, ..outside };
    assert_eq!(earliest_contact(&receding, Side::Exterior, 9.0), None);
}

#[test]
fn spheres_without_relative_motion_never_touch() {
    // Same velocity: v = 0 ⇒ A = B = 0, even when overlapping (C = 0.25 − 4 < 0).
    let a = ball([0.0; 3], [1.0, 2.0, 3.0], 1.0);
    let b = ball([0.5, 0.0, 0.0], [1.0, 2.0, 3.0], 1.0);
    assert_eq!(sphere_sphere::quadratic(&a, &b).roots(), Roots::NoMotion);
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 100.0), None);
}

#[test]
fn the_window_is_closed_at_both_ends() {
    // Contact at t = 4 (case above): inside [0, 4], outside [0, 3.999].
    let a = ball([0.0; 3], AT_REST, 1.0);
    let b = ball([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0);
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 4.0), Some(4.0));
    assert_eq!(sphere_sphere::time_of_impact(&a, &b, 3.999), None);
    // A window of [0, 0] still reports a contact at t = 0.
    let c = ball([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    assert_eq!(sphere_sphere::time_of_impact(&a, &c, 0.0), Some(0.0));
}

#[test]
fn point_spheres_meeting_head_on_get_the_approach_direction_as_normal() {
    // D = 0: r0 = (4, 0, 0), v = (−2, 0, 0): A = 4, B = −16, C = 16, disc = 0, t = 2.
    // ‖r_A − r_B‖ = 0 at contact: the normal is the limit just before, +v/‖v‖ = −x.
    let a = ball([0.0; 3], AT_REST, 0.0);
    let b = ball([4.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 0.0);
    let c = sphere_sphere::first_contact(&a, &b, 9.0).unwrap();
    assert_eq!((c.time, c.normal.to_array()), (2.0, [-1.0, 0.0, 0.0]));
}

// ---------------------------------------------------------------- sphere in container

#[test]
fn container_exit_time_from_the_centre() {
    // R = 1 in a vessel of 5: D = 4. r0 = 0, v = (0, 2, 0): A = 4, B = 0, C = −16,
    // disc = 256, t = ∓16/8 = −2 or 2: the sphere leaves at the larger root, t = 2.
    let s = ball([0.0; 3], [0.0, 2.0, 0.0], 1.0);
    let k = Container::new([0.0; 3], 5.0).unwrap();
    assert_eq!(
        sphere_container::quadratic(&s, &k).roots(),
        Roots::Distinct(-2.0, 2.0)
    );
    let c = sphere_container::first_contact(&s, &k, 10.0).unwrap();
    assert_eq!((c.time, c.centre.y, c.point.y), (2.0, 4.0, 5.0));
    assert_eq!(c.normal.to_array(), [0.0, -1.0, 0.0]); // pushes back inwards
}

#[test]
fn container_exit_time_off_centre() {
    // r0 = (3, 0, 0), v = (−1, 0, 0), D = 4: A = 1, B = −6, C = −7, disc = 64,
    // t = (6 ∓ 8)/2 = −1 or 7: it crosses the vessel and reaches x = −4 at t = 7.
    let s = ball([3.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    let k = Container::new([0.0; 3], 5.0).unwrap();
    assert_eq!(sphere_container::time_of_impact(&s, &k, 10.0), Some(7.0));
    // Moved with the vessel: same answer.
    let s2 = ball([13.0, 10.0, 10.0], [-1.0, 0.0, 0.0], 1.0);
    let k2 = Container::new([10.0; 3], 5.0).unwrap();
    assert_eq!(sphere_container::time_of_impact(&s2, &k2, 10.0), Some(7.0));
}

#[test]
fn container_wall_touching_at_start() {
    // r0 = (4, 0, 0) = D: C = 0. Outwards (B = 8): roots −8, 0 ⇒ t = 0.
    // Inwards (B = −8): roots 0, 8 ⇒ it crosses and hits the far wall at t = 8.
    let k = Container::new([0.0; 3], 5.0).unwrap();
    let out = ball([4.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0);
    let back = ball([4.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    assert_eq!(sphere_container::time_of_impact(&out, &k, 10.0), Some(0.0));
    assert_eq!(sphere_container::time_of_impact(&back, &k, 10.0), Some(8.0));
}

#[test]
fn container_sphere_at_rest_or_too_large() {
    let k = Container::new([0.0; 3], 5.0).unwrap();
    let rest = ball([1.0, 0.0, 0.0], AT_REST, 1.0);
    assert_eq!(sphere_container::time_of_impact(&rest, &k, 10.0), None);
    // R = 6 > 5: D = −1 < 0, it cannot fit: touching the wall at once.
    let big = ball([0.0; 3], AT_REST, 6.0);
    assert_eq!(sphere_container::time_of_impact(&big, &k, 10.0), Some(0.0));
}

// ---------------------------------------------------------------- sphere – plane

#[test]
fn plane_parallel_motion_never_touches() {
    // v·n̂ = 0 ⇒ A = B = 0 (the seed's division by zero): no contact.
    let p = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap();
    let s = ball([0.0, 0.0, 5.0], [3.0, -1.0, 0.0], 1.0);
    let q = sphere_plane::quadratic(&s, &p);
    assert_eq!((q.a, q.b), (0.0, 0.0));
    assert_eq!(q.roots(), Roots::NoMotion);
    assert_eq!(sphere_plane::time_of_impact(&s, &p, 100.0), None);
}

#[test]
fn point_sphere_on_a_plane_has_one_root() {
    // R = 0, plane z = 1: t = (r_P0 − r_A0)·n̂ / (v_A·n̂) = (1 − 5)/(−2) = 2; and the
    // quadratic: R0 = 4, v = −2, A = 4, B = −16, C = 16, disc = 256 − 256 = 0.
    let p = Plane::new([7.0, 7.0, 1.0], [0.0, 0.0, 1.0]).unwrap();
    let s = ball([0.0, 0.0, 5.0], [1.0, 0.0, -2.0], 0.0);
    assert_eq!(sphere_plane::quadratic(&s, &p).roots(), Roots::Double(2.0));
    let c = sphere_plane::first_contact(&s, &p, 10.0).unwrap();
    assert_eq!(c.time, 2.0);
    assert_eq!(c.point.to_array(), [2.0, 0.0, 1.0]);
    assert_eq!(c.normal.to_array(), [0.0, 0.0, 1.0]); // came from the front
}

#[test]
fn plane_two_roots_from_the_front() {
    // Plane z = 0, R = 1 at z = 5, v = −2: R0 = 5, A = 4, B = −20, C = 24, disc = 16,
    // t = (20 ∓ 4)/8 = 2 (arriving at distance D) or 3 (leaving on the other side).
    let p = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap();
    let s = ball([1.0, 2.0, 5.0], [0.0, 0.0, -2.0], 1.0);
    assert_eq!(
        sphere_plane::quadratic(&s, &p).roots(),
        Roots::Distinct(2.0, 3.0)
    );
    let c = sphere_plane::first_contact(&s, &p, 10.0).unwrap();
    assert_eq!(c.time, 2.0);
    assert_eq!(c.point.to_array(), [1.0, 2.0, 0.0]); // r_P = r_A − R_A n̂_P
    assert_eq!(c.normal.to_array(), [0.0, 0.0, 1.0]);
}

#[test]
fn plane_two_roots_from_behind() {
    // Mirror image: R0 = −5, v = +2, same roots; contact point r_A + R_A n̂_P, normal −n̂_P.
    let p = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap();
    let s = ball([1.0, 2.0, -5.0], [0.0, 0.0, 2.0], 1.0);
    let c = sphere_plane::first_contact(&s, &p, 10.0).unwrap();
    assert_eq!(c.time, 2.0);
    assert_eq!(c.point.to_array(), [1.0, 2.0, 0.0]);
    assert_eq!(c.normal.to_array(), [0.0, 0.0, -1.0]);
}

#[test]
fn plane_moving_away_has_only_negative_roots() {
    // R0 = 5, v = +2: roots −3 and −2, both discarded.
    let p = Plane::new([0.0; 3], [0.0, 0.0, 1.0]).unwrap();
    let s = ball([0.0, 0.0, 5.0], [0.0, 0.0, 2.0], 1.0);
    assert_eq!(
        sphere_plane::quadratic(&s, &p).roots(),
        Roots::Distinct(-3.0, -2.0)
    );
    assert_eq!(sphere_plane::time_of_impact(&s, &p, 10.0), None);
}

#[test]
fn plane_normal_is_normalised_on_construction() {
    // (0, 0, 7) becomes (0, 0, 1): same answers as the unit normal.
    let p = Plane::new([0.0; 3], [0.0, 0.0, 7.0]).unwrap();
    assert_eq!(p.normal().to_array(), [0.0, 0.0, 1.0]);
    let s = ball([0.0, 0.0, 5.0], [0.0, 0.0, -2.0], 1.0);
    assert_eq!(sphere_plane::time_of_impact(&s, &p, 10.0), Some(2.0));
}

// ---------------------------------------------------------------- sphere – cylinder

fn pillar(p1: [f32; 3], p2: [f32; 3]) -> Cylinder {
    Cylinder::new(p1, p2, 1.0).unwrap()
}

#[test]
fn cylinder_two_roots() {
    // Axis z, R_C = 1, R_A = 1 at (6, 0, 3), v = (−1, 0, 0.5): r0 = (6, 0, 0),
    // v_⊥ = (−1, 0, 0), D = 2: A = 1, B = −12, C = 32, disc = 16, t = (12 ∓ 4)/2 = 4 or 8.
    let cyl = pillar([0.0; 3], [0.0, 0.0, 1.0]);
    let s = ball([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0);
    assert_eq!(
        sphere_cylinder::quadratic(&s, &cyl).roots(),
        Roots::Distinct(4.0, 8.0)
    );
    let c = sphere_cylinder::first_contact(&s, &cyl, 10.0).unwrap();
    // At t = 4 the centre is (2, 0, 5); D⃗ = (2, 0, 0), n = +x; contact point (1, 0, 5).
    assert_eq!(c.centre.to_array(), [2.0, 0.0, 5.0]);
    assert_eq!(c.other_anchor.to_array(), [0.0, 0.0, 5.0]);
    assert_eq!(c.point.to_array(), [1.0, 0.0, 5.0]);
    assert_eq!(c.normal.to_array(), [1.0, 0.0, 0.0]);
}

#[test]
fn cylinder_miss_and_graze() {
    // r0 = (6, 3, 0): C = 45 − 4 = 41, disc = 144 − 164 < 0: miss.
    // r0 = (6, 2, 0): C = 40 − 4 = 36, disc = 144 − 144 = 0: graze at t = 6.
    let cyl = pillar([0.0; 3], [0.0, 0.0, 1.0]);
    let miss = ball([6.0, 3.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    let graze = ball([6.0, 2.0, 0.0], [-1.0, 0.0, 0.0], 1.0);
    assert_eq!(
        sphere_cylinder::quadratic(&miss, &cyl).roots(),
        Roots::Complex
    );
    assert_eq!(
        sphere_cylinder::quadratic(&graze, &cyl).roots(),
        Roots::Double(6.0)
    );
    assert_eq!(
        sphere_cylinder::time_of_impact(&graze, &cyl, 10.0),
        Some(6.0)
    );
}

#[test]
fn cylinder_motion_along_the_axis_never_touches() {
    // v = (0, 0, 3) ∥ ŝ: v_⊥ = 0 ⇒ A = B = 0, even when the sphere overlaps the pillar.
    let cyl = pillar([0.0; 3], [0.0, 0.0, 1.0]);
    let s = ball([1.5, 0.0, 0.0], [0.0, 0.0, 3.0], 1.0);
    assert_eq!(
        sphere_cylinder::quadratic(&s, &cyl).roots(),
        Roots::NoMotion
    );
    assert_eq!(sphere_cylinder::time_of_impact(&s, &cyl, 10.0), None);
}

#[test]
fn cylinder_answer_does_not_depend_on_where_the_axis_points_are() {
    // Same axis through (0, 0, 1000) and (0, 0, −5): only the perpendicular part matters.
    let s = ball([6.0, 0.0, 3.0], [-1.0, 0.0, 0.5], 1.0);
    let far = pillar([0.0, 0.0, 1000.0], [0.0, 0.0, -5.0]);
    assert_eq!(sphere_cylinder::time_of_impact(&s, &far, 10.0), Some(4.0));
}

#[test]
fn cylinder_with_a_tilted_axis() {
    // Axis (1, 1, 0)/√2 through the origin, R_C = 0.5, R_A = 0.5 at (0, 0, 5), v = (0, 0, −1):
    // r0 = (0, 0, 5) (already perpendicular), D = 1: A = 1, B = −10, C = 24, disc = 4,
    // t = (10 ∓ 2)/2 = 4. ŝ is not exact in binary: r0 = 5‖ŝ‖² with ‖ŝ‖² = 1 within a few
    // f64 roundings (ε = 2⁻⁵³), so C and t are exact to about 10 ε relative; allow 1e-14.
    let cyl = Cylinder::new([0.0; 3], [1.0, 1.0, 0.0], 0.5).unwrap();
    let s = ball([0.0, 0.0, 5.0], [0.0, 0.0, -1.0], 0.5);
    let t = sphere_cylinder::time_of_impact(&s, &cyl, 10.0).unwrap();
    assert!((t - 4.0).abs() <= 4.0 * 1e-14, "{t}");
}

// ---------------------------------------------------------------- the shared policy

#[test]
fn policy_table_for_both_sides() {
    use spheresweep::reference::Quadratic;
    let q = |a, b, c| Quadratic { a, b, c };
    // (quadratic, side, expected): roots in comments.
    let cases = [
        (q(1.0, -3.0, 2.0), Side::Exterior, Some(1.0)), // 1, 2: arrive at 1
        (q(1.0, -3.0, 2.0), Side::Interior, Some(2.0)), // 1, 2: reach the wall at 2
        (q(1.0, 3.0, 2.0), Side::Exterior, None),       // −2, −1: behind
        (q(1.0, 3.0, 2.0), Side::Interior, Some(0.0)),  // outside the wall, moving out
        (q(1.0, -1.0, -2.0), Side::Exterior, Some(0.0)), // −1, 2: overlap, deeper
        (q(1.0, 1.0, -2.0), Side::Exterior, None),      // −2, 1: overlap, separating
        (q(1.0, 1.0, -2.0), Side::Interior, Some(1.0)), // −2, 1: inside, wall at 1
        (q(0.0, 0.0, -2.0), Side::Exterior, None),      // no motion
        (q(0.0, 0.0, 2.0), Side::Interior, None),       // no motion
        (q(1.0, -1.0, 2.0), Side::Exterior, None),      // disc < 0: passes by
        (q(1.0, -1.0, 2.0), Side::Interior, Some(0.0)), // past the wall, never back in
        (q(1.0, -4.0, 2.0), Side::Interior, Some(2.0 + 2f64.sqrt())), // past, back in at 2 − √2
    ];
    for (quad, side, expected) in cases {
        assert_eq!(
            earliest_contact(&quad, side, 10.0),
            expected,
            "{quad:?} {side:?}"
        );
    }
}
