//! The one quadratic every pair kind reduces to, `A t² + B t + C = 0`, solved literally as the
//! seed writes it, and the contact policy shared by every pair kind (in f64).
//!
//! Policy (docs/derivations/policies.md):
//! - `A = 0` (no relative motion; then `B = 0` too): never a contact, never a division.
//! - The contact is the root where the bodies *arrive* at distance `D`: the smaller root for an
//!   exterior contact, the larger one for a sphere inside a container.
//! - A root `t > 0` inside the window is the contact. A grazing contact (`B² − 4AC = 0`)
//!   counts.
//! - At `t = 0` there is a contact only if the bodies already touch or overlap and no arrival
//!   lies ahead: outside, when they move deeper (`C ≤ 0, B < 0`); inside a container, when the
//!   sphere is at or past the wall (`C ≥ 0`, `A > 0`) and its line does not lead back inside
//!   (`B ≥ 0`, or `B² − 4AC < 0`). Touching and separating, or at rest, is no contact.
//! - Moving towards the contact (`B < 0` outside, `B > 0` inside) with the arrival root
//!   computed at or before 0 is a contact at 0: exactly, the root is ahead, and the computed
//!   one is the literal formula's cancellation within rounding of 0.

use crate::contact::Side;

/// The coefficients of `A t² + B t + C = 0`, exactly as the seed defines them per pair kind.
///
/// ```
/// use spheresweep::{Sphere, reference::{Quadratic, sphere_sphere}};
/// // B 10 ahead of A and closing at speed 2, D = 2: A = 4, B = 2·(10·−2), C = 10² − 2².
/// let a = Sphere::new([0.0; 3], [0.0; 3], 1.0, 1.0)?;
/// let b = Sphere::new([10.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 1.0, 1.0)?;
/// assert_eq!(sphere_sphere::quadratic(&a, &b), Quadratic { a: 4.0, b: -40.0, c: 96.0 });
/// # Ok::<(), spheresweep::ShapeError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadratic {
    /// `A = v·v` (never negative).
    pub a: f64,
    /// `B = 2 r0·v`.
    pub b: f64,
    /// `C = r0·r0 − D²`.
    pub c: f64,
}

/// The seed's classification of the roots of a [`Quadratic`].
///
/// ```
/// use spheresweep::reference::{Quadratic, Roots};
/// assert_eq!(Quadratic { a: 0.0, b: 0.0, c: 1.0 }.roots(), Roots::NoMotion);
/// assert_eq!(Quadratic { a: 1.0, b: 0.0, c: 1.0 }.roots(), Roots::Complex); // t² + 1
/// assert_eq!(Quadratic { a: 1.0, b: -2.0, c: 1.0 }.roots(), Roots::Double(1.0)); // (t − 1)²
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Roots {
    /// `A = 0`: no relative motion (the seed's "division by zero" case): never a contact.
    NoMotion,
    /// `B² − 4AC < 0`: no collision.
    Complex,
    /// `B² − 4AC = 0`: exactly one contact, grazing, at `t = −B / 2A`.
    Double(f64),
    /// `B² − 4AC > 0`: two contacts, `t1 < t2`, `t = (−B ∓ √(B² − 4AC)) / 2A`.
    Distinct(f64, f64),
}

impl Quadratic {
    /// The discriminant `B² − 4AC`, literally.
    ///
    /// ```
    /// use spheresweep::reference::Quadratic;
    /// assert_eq!(Quadratic { a: 1.0, b: -3.0, c: 2.0 }.discriminant(), 1.0); // 9 − 8
    /// ```
    #[inline]
    pub fn discriminant(&self) -> f64 {
        self.b * self.b - 4.0 * self.a * self.c
    }

    /// The roots, classified as the seed does.
    ///
    /// ```
    /// use spheresweep::reference::{Quadratic, Roots};
    /// // t² − 3t + 2 = (t − 1)(t − 2)
    /// let q = Quadratic { a: 1.0, b: -3.0, c: 2.0 };
    /// assert_eq!(q.roots(), Roots::Distinct(1.0, 2.0));
    /// ```
    pub fn roots(&self) -> Roots {
        let Quadratic { a, b, .. } = *self;
        if a == 0.0 {
            return Roots::NoMotion;
        }
        let disc = self.discriminant();
        if disc < 0.0 {
            Roots::Complex
        } else if disc == 0.0 {
            Roots::Double(-b / (2.0 * a))
        } else {
            let sqrt = disc.sqrt();
            Roots::Distinct((-b - sqrt) / (2.0 * a), (-b + sqrt) / (2.0 * a))
        }
    }
}

impl Roots {
    /// All the roots, smallest first.
    ///
    /// ```
    /// use spheresweep::reference::Roots;
    /// assert_eq!(Roots::Distinct(-1.0, 2.0).all().collect::<Vec<_>>(), [-1.0, 2.0]);
    /// assert_eq!(Roots::Complex.all().count(), 0);
    /// ```
    pub fn all(&self) -> impl Iterator<Item = f64> {
        let (first, second) = match *self {
            Roots::NoMotion | Roots::Complex => (None, None),
            Roots::Double(t) => (Some(t), None),
            Roots::Distinct(t1, t2) => (Some(t1), Some(t2)),
        };
        first.into_iter().chain(second)
    }
    /// The roots that lie ahead (`t > 0`): physical contacts.
    ///
    /// ```
    /// use spheresweep::reference::Roots;
    /// assert_eq!(Roots::Distinct(-1.0, 2.0).ahead().collect::<Vec<_>>(), [2.0]);
    /// assert_eq!(Roots::Double(0.0).ahead().count(), 0); // t = 0 is neither ahead nor behind
    /// ```
    pub fn ahead(&self) -> impl Iterator<Item = f64> {
        self.all().filter(|&t| t > 0.0)
    }
    /// The roots that lie behind (`t < 0`): contacts that would have happened in the past,
    /// discarded by the seed.
    ///
    /// ```
    /// use spheresweep::reference::Roots;
    /// assert_eq!(Roots::Distinct(-3.0, -1.0).behind().collect::<Vec<_>>(), [-3.0, -1.0]);
    /// ```
    pub fn behind(&self) -> impl Iterator<Item = f64> {
        self.all().filter(|&t| t < 0.0)
    }
}

/// Already touching or past the contact distance at `t = 0`, with no arrival ahead to wait
/// for: a contact now.
///
/// - Outside: overlapping or touching (`C ≤ 0`) and approaching (`B < 0`).
/// - Inside a container: at or past the wall (`C ≥ 0`), moving (`A > 0`), and the line does
///   not lead back inside: moving outwards or tangentially (`B ≥ 0`: both roots are behind),
///   or inwards too slowly ever to get back inside (`B < 0` with `B² − 4AC < 0`: no root). In
///   the second case the sphere would stay through the wall for ever; until 2026-12-01 it was
///   answered "no contact", and a sphere whose inelastic bounces had decayed to a normal speed
///   within the rounding of `C` left its vessel (docs/derivations/simulation.md, "Concave
///   walls").
///
/// ```
/// use spheresweep::reference::{Quadratic, Side, quadratic::in_contact_now};
/// // Touching (C = 0) and approaching (B < 0) from outside: a contact at t = 0.
/// assert!(in_contact_now(Side::Exterior, &Quadratic { a: 1.0, b: -2.0, c: 0.0 }));
/// // Touching and separating (B > 0): none.
/// assert!(!in_contact_now(Side::Exterior, &Quadratic { a: 1.0, b: 2.0, c: 0.0 }));
/// // At the wall of a container, moving tangentially (B = 0, A > 0): leaving at once.
/// assert!(in_contact_now(Side::Interior, &Quadratic { a: 1.0, b: 0.0, c: 0.0 }));
/// // Just past the wall, moving inwards too slowly to get back in (B² < 4AC): now.
/// assert!(in_contact_now(Side::Interior, &Quadratic { a: 1.0, b: -1e-9, c: 1e-15 }));
/// // Past the wall and moving inwards fast enough (B² > 4AC): it comes back, not now.
/// assert!(!in_contact_now(Side::Interior, &Quadratic { a: 1.0, b: -1e-6, c: 1e-15 }));
/// ```
#[inline]
pub fn in_contact_now(side: Side, q: &Quadratic) -> bool {
    match side {
        Side::Exterior => q.c <= 0.0 && q.b < 0.0,
        Side::Interior => q.c >= 0.0 && q.a > 0.0 && (q.b >= 0.0 || q.discriminant() < 0.0),
    }
}

/// Moving towards the contact distance: closing in from outside (`B < 0`), or towards the
/// wall from inside a container (`B > 0`).
#[inline]
fn towards_contact(side: Side, q: &Quadratic) -> bool {
    match side {
        Side::Exterior => q.b < 0.0,
        Side::Interior => q.b > 0.0,
    }
}

/// The earliest admissible time of impact in `[0, t_max]`, or `None`, by the policy above.
///
/// ```
/// use spheresweep::reference::{earliest_contact, Quadratic, Side};
/// let q = Quadratic { a: 1.0, b: -3.0, c: 2.0 }; // roots 1 and 2
/// assert_eq!(earliest_contact(&q, Side::Exterior, 10.0), Some(1.0));
/// assert_eq!(earliest_contact(&q, Side::Interior, 10.0), Some(2.0));
/// assert_eq!(earliest_contact(&q, Side::Exterior, 0.5), None);
/// // Closing in from 10⁻¹⁷ outside: the literal smaller root rounds to 0, a contact now.
/// let q = Quadratic { a: 1.0, b: -2.0, c: 1e-17 };
/// assert_eq!(earliest_contact(&q, Side::Exterior, 10.0), Some(0.0));
/// // 10⁻¹⁷ inside a container's wall and moving outwards: the larger root rounds to 0.
/// let q = Quadratic { a: 1.0, b: 2.0, c: -1e-17 };
/// assert_eq!(earliest_contact(&q, Side::Interior, 10.0), Some(0.0));
/// ```
pub fn earliest_contact(q: &Quadratic, side: Side, t_max: f64) -> Option<f64> {
    let arrival = match q.roots() {
        Roots::NoMotion => return None,
        Roots::Complex => None,
        Roots::Double(t) => Some(t),
        Roots::Distinct(t1, t2) => Some(match side {
            Side::Exterior => t1,
            Side::Interior => t2,
        }),
    };
    let t = match arrival {
        Some(t) if t > 0.0 => t,
        _ if in_contact_now(side, q) => 0.0,
        // Moving towards the contact with the arrival computed at or before now: outside,
        // `C > 0` and `B < 0` put both roots ahead; inside, `C < 0` and `B > 0` put `t2`
        // ahead; so the computed arrival `≤ 0` is the literal formula's cancellation within
        // rounding of 0 (`C ≈ 5·10⁻¹⁷`: fuzz/regressions/kernels/
        // textbook-sphere-touching-a-line-at-start). The bodies touch now.
        Some(_) if towards_contact(side, q) => 0.0,
        _ => return None,
    };
    (t <= t_max).then_some(t)
}
