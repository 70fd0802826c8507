//! Collision responses, one type per kind of scene, chosen once when the engine is assembled:
//! [`ReportOnly`] changes nothing, [`Elastic`] is the hard-sphere gas, [`Materials`] looks up
//! each pair of materials (elastic, inelastic with the TC model, sticky clusters).
//! The impulse and the energy it takes: docs/derivations/simulation.md.

use glam::DVec3;

use super::checkpoint::{Decoder, Encoder};
use super::model::{Response, SimError};
use super::persist::Persist;
use crate::contact::Body;
use crate::error::Nums;
use crate::shape::ShapeKind;

/// One sphere's straight-line trajectory, f64: centre `r` at its own time `t`, velocity,
/// radius. 64 bytes, so a neighbour is one cache line.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Trajectory {
    pub r: DVec3,
    pub t: f64,
    pub v: DVec3,
    pub radius: f64,
}

impl Trajectory {
    /// Centre and velocity at time `t` under the uniform acceleration `g`: the parabola
    /// `r + v Δt + g Δt²/2` (a straight line when `g` is zero, to the same bits while `Δt²` is
    /// finite: beyond `Δt ≈ 10¹⁵⁴` it is `0 · ∞ = NaN`, so code without gravity calls
    /// [`on_line`](Self::on_line)).
    #[inline(always)]
    pub fn at(&self, t: f64, g: DVec3) -> (DVec3, DVec3) {
        let dt = t - self.t;
        (self.r + self.v * dt + g * (0.5 * dt * dt), self.v + g * dt)
    }

    /// Centre at time `t` on the straight line (no gravity): `r + v Δt`, as [`Motion::advance`]
    /// moves it (without `at`'s `g Δt²/2`, which is `0 · ∞ = NaN` once `Δt²` overflows).
    #[inline(always)]
    pub fn on_line(&self, t: f64) -> DVec3 {
        self.r + self.v * (t - self.t)
    }
}

/// Everything a response may change.
#[derive(Debug, Clone, Default)]
pub(crate) struct Motion {
    pub bodies: Vec<Trajectory>,
    pub mass: Vec<f64>,
    pub material: Vec<u16>,
    /// Bumped at every velocity change: a prediction made against an older value is stale.
    pub counter: Vec<u32>,
    /// The uniform acceleration every sphere feels (zero without gravity).
    pub g: DVec3,
}

impl Motion {
    /// Moves sphere `s` along its line to time `now` (no gravity: the engine calls
    /// [`advance_falling`](Self::advance_falling) instead when it has some).
    #[inline(always)]
    pub fn advance(&mut self, s: u32, now: f64) {
        let b = &mut self.bodies[s as usize];
        b.r = b.on_line(now);
        b.t = now;
    }

    /// Moves sphere `s` along its parabola under `g` to time `now`.
    #[inline(always)]
    pub fn advance_falling(&mut self, s: u32, now: f64) {
        let b = &mut self.bodies[s as usize];
        (b.r, b.v) = b.at(now, self.g);
        b.t = now;
    }

    /// Gives sphere `s`, which the engine has moved to the collision's time, velocity `v`
    /// from then on (`set_velocity` without moving it again).
    #[inline(always)]
    pub fn set_velocity_in_place(&mut self, s: u32, v: DVec3) {
        self.bodies[s as usize].v = v;
        let c = &mut self.counter[s as usize];
        *c = c.wrapping_add(1);
    }

    /// Gives sphere `s` velocity `v` from `now` on (moving it to `now` first, on its line or
    /// its parabola). Inlined: out of line, its call cost the gas ~90 instructions a collision.
    #[inline(always)]
    pub fn set_velocity(&mut self, s: u32, v: DVec3, now: f64) {
        if self.g == DVec3::ZERO {
            self.advance(s, now);
        } else {
            self.advance_falling(s, now);
        }
        self.set_velocity_in_place(s, v);
    }
}

/// What one collision did.
#[derive(Debug, Clone, Default)]
pub(crate) struct Outcome {
    /// Spheres to predict again (their velocity changed, or a report-only contact).
    pub changed: Vec<u32>,
    /// Kinetic energy taken by the collision.
    pub energy_lost: f64,
    /// `r_ij · Δp_j` (for the pressure virial).
    pub virial: f64,
    /// Normal approach speed before the collision.
    pub approach: f64,
    /// Restitution applied (`0` for sticky; NaN report-only, which applies none), or the
    /// separation speed over the approach where a hop raised it.
    pub restitution: f64,
    /// Whether two clusters (or a cluster and a wall) joined.
    pub joined: bool,
    /// Whether the grazing guard set the impulse (see [`normal_impulse`]).
    pub guarded: bool,
    /// Whether the sphere left a concave wall at the floor angle (see [`leave_wall`]).
    pub slid: bool,
    /// A sphere in inelastic collapse: its dissipating collisions outran its rapid window
    /// [`RAPID_LIMIT`] times over (`Materials::collided`).
    pub collapsing: Option<u32>,
}

/// A sphere's count of dissipating collisions within the rapid window of its previous one
/// (less one per whole window between two) that marks inelastic collapse (infinitely many
/// collisions in finite time: the TC model prevents it).
pub(crate) const RAPID_LIMIT: u32 = 100_000;

impl Outcome {
    /// Empties the outcome for the next collision, keeping `changed`'s buffer.
    #[inline]
    pub fn clear(&mut self) {
        let mut changed = std::mem::take(&mut self.changed);
        changed.clear();
        *self = Self {
            changed,
            ..Self::default()
        };
    }
}

/// A collision response, chosen once per engine.
pub(crate) trait Responder: Send + Sync + 'static {
    /// Velocities never change; a pair in contact is not reported again until it separates.
    const REPORT_ONLY: bool;
    /// Collisions can lose energy (an inelastic pile can collapse: the TC model's remedy).
    const INELASTIC: bool = false;
    /// The response's name for summaries.
    const NAME: &'static str;
    /// Sphere `i` meets sphere `j` at `now`, both moved there by the engine; `dr = r_j − r_i`
    /// (nearest image).
    fn pair(&mut self, m: &mut Motion, i: u32, j: u32, dr: DVec3, now: f64, out: &mut Outcome);
    /// Sphere `i`, moved to `now` by the engine, meets a static shape there (see [`Wall`]).
    fn wall(&mut self, m: &mut Motion, i: u32, wall: Wall, now: f64, out: &mut Outcome);
    /// The spheres were renumbered: sphere `old` is now `new_of_old[old]`.
    fn permute(&mut self, _new_of_old: &[u32]) {}
    /// Writes the response's state to a checkpoint.
    fn save(&self, _e: &mut Encoder) {}
    /// Reads it back for `n` spheres, checking every index.
    fn load(&mut self, _d: &mut Decoder, _n: usize) -> Result<(), SimError> {
        Ok(())
    }
    /// Whether new velocities (`v(k)` for sphere `k` of `n`) fit the response's state: the
    /// first sphere that does not, and why.
    fn check_velocities(&self, _v: &dyn Fn(u32) -> DVec3, _n: usize) -> Result<(), (u32, String)> {
        Ok(())
    }
    /// The mean time between a sphere's events (known once the engine has predicted them all):
    /// a response that can collapse sets its rapid window from it.
    fn set_time_scale(&mut self, _mean: f64) {}
    /// Report-only scenes: whether `j` is the partner `i` is already touching.
    #[inline(always)]
    fn touching(&self, _i: u32, _j: u32) -> bool {
        false
    }
    /// Report-only scenes: the static shapes sphere `i`'s predictions skip (`NO_SHAPE`).
    #[inline(always)]
    fn shape_touched(&self, _i: u32) -> [Body; 3] {
        [NO_SHAPE; 3]
    }
    /// Every sphere was given a new velocity.
    fn new_velocities(&mut self) {}
}

/// Relative normal speeds below this fraction of the relative speed count as grazing: the
/// impulse then uses this floor, so that rounding can never leave the pair approaching after
/// its collision (which would repeat it at the same time, forever). Energy changes by at most
/// `2⁻⁴⁰` of the pair's relative kinetic energy, only in such collisions.
const GRAZING: f64 = 1.0 / (1u64 << 40) as f64;

/// The normal approach speed `u = −(dv · n̂)` a collision acts on, at least the grazing floor
/// (and whether the floor was used). `dv = v_j − v_i`, `n̂` from `i` to `j` (for a static
/// shape: `dv` the sphere's velocity, `n̂` from the shape to the sphere).
#[inline]
fn normal_impulse(dv: DVec3, n: DVec3) -> (f64, bool) {
    let u = -dv.dot(n);
    let floor = GRAZING * dv.length();
    if u < floor { (floor, true) } else { (u, false) }
}

/// The static shape a sphere meets, as a response sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Wall {
    /// Unit normal from the shape towards the sphere's centre.
    pub n: DVec3,
    /// The shape's material.
    pub material: u16,
    /// Least angle (its sine, `κ`) at which the sphere may leave: `0` for a convex shape (a
    /// plane, a cylinder), which a sphere leaving it never meets again on a straight line; a
    /// container's floor for concave walls ([`leave_wall`]).
    pub floor: f64,
    /// Least normal speed at which the sphere leaves where gravity presses it on, so that a
    /// resting sphere hops ([`hop_off`], `walls::hop_speed`); `0` elsewhere. The TC model
    /// raises it for a resting contact ([`Materials::wall`]).
    pub hop: f64,
    /// Which shape.
    pub body: Body,
}

/// The velocity `v` with its normal part raised to at least `hop` (unchanged when it is
/// already), and the kinetic energy per unit mass that added: a sphere resting on a wall under
/// gravity leaves in hops of a least height instead of meeting the wall again at the same
/// time for ever (docs/derivations/gravity.md, "Resting contact").
#[inline]
pub(crate) fn hop_off(v: DVec3, n: DVec3, hop: f64) -> (DVec3, f64) {
    let w = v.dot(n);
    if w >= hop || w.is_nan() {
        return (v, 0.0);
    }
    let out = v + n * (hop - w);
    (out, 0.5 * (out.length_squared() - v.length_squared()))
}

/// The velocity with which a sphere leaves a wall, `v` being what the response gives it: `v`
/// itself when its component along `n` is at least `κ‖v‖`, else `v` turned towards `n` until
/// it is, keeping its speed (and so its kinetic energy). Inside a concave wall a sphere whose
/// normal speed decays (inelastic bounces) would otherwise meet the wall again after ever
/// shorter chords — infinitely many collisions in finite time, then a chord within the
/// rounding of the kernel's `C`, answered as no contact: the sphere left its vessel. At the
/// floor it slides along the wall in chords of angle `2κ` at its own speed, as a frictionless
/// sphere slides (docs/derivations/simulation.md, "Concave walls"). The flag says it slid so:
/// a convex shape's floor is `κ = 0`, where a rounding below zero is turned to the tangent
/// but is no slide along a floor angle.
#[inline]
pub(crate) fn leave_wall(v: DVec3, n: DVec3, kappa: f64) -> (DVec3, bool) {
    let w = v.dot(n);
    let speed = v.length();
    if w >= kappa * speed || w.is_nan() {
        return (v, false);
    }
    let slid = kappa > 0.0;
    let tangential = v - n * w;
    let t = tangential.length();
    if t == 0.0 {
        // Straight into the wall (no response leaves a sphere so): straight back out.
        return (n * speed, slid);
    }
    let along = speed * (1.0 - kappa * kappa).max(0.0).sqrt() / t;
    (n * (kappa * speed) + tangential * along, slid)
}

/// Report only.
#[derive(Debug, Clone, Default)]
pub(crate) struct ReportOnly {
    /// Each sphere's partner at its last reported contact.
    pub partner: Vec<u32>,
    /// Each sphere's static shapes of its last three reported contacts with one, the latest
    /// first (`NO_SHAPE` for none): a straight line meets a plane, an infinite cylinder or a
    /// container's wall in one interval, so the sphere's predictions skip them until its
    /// velocity is set again (reported again at once, one stalled the clock; at a corner,
    /// where a sphere meets two or three within a rounding of one time, they were given in
    /// turn without end). Older ones are behind it (`walls::Skip`).
    pub shape: Vec<[Body; 3]>,
}

/// No static shape (`ReportOnly::shape`): a sphere is never a static shape.
pub(crate) const NO_SHAPE: Body = Body {
    kind: ShapeKind::Sphere,
    index: u32::MAX,
};

impl ReportOnly {
    /// For `n` spheres, none in contact with anything.
    pub fn new(n: usize) -> Self {
        Self {
            partner: vec![super::cells::NONE; n],
            shape: vec![[NO_SHAPE; 3]; n],
        }
    }
}

/// `v` reordered so that entry `old` lands at `new_of_old[old]`.
fn permuted<T: Copy>(v: &[T], new_of_old: &[u32]) -> Vec<T> {
    let mut out = v.to_vec();
    for (old, &new) in new_of_old.iter().enumerate() {
        out[new as usize] = v[old];
    }
    out
}

/// A sphere index through the renumbering (`NONE` stays).
fn renumbered(i: u32, new_of_old: &[u32]) -> u32 {
    new_of_old.get(i as usize).copied().unwrap_or(i)
}

impl Responder for ReportOnly {
    const REPORT_ONLY: bool = true;
    const NAME: &'static str = "report only";
    fn permute(&mut self, new_of_old: &[u32]) {
        self.partner = permuted(&self.partner, new_of_old)
            .into_iter()
            .map(|p| renumbered(p, new_of_old))
            .collect();
        self.shape = permuted(&self.shape, new_of_old);
    }
    fn save(&self, e: &mut Encoder) {
        for &p in &self.partner {
            e.u32(p);
        }
        for b in self.shape.iter().flatten() {
            b.save(e);
        }
    }
    fn load(&mut self, d: &mut Decoder, n: usize) -> Result<(), SimError> {
        for p in &mut self.partner {
            *p = d.u32()?;
            if *p != u32::MAX && *p as usize >= n {
                return Err(SimError::Checkpoint(format!("partner {p} does not exist")));
            }
        }
        // The engine checks that a shape named exists (`Engine::load`).
        for b in self.shape.iter_mut().flatten() {
            b.load(d)?;
        }
        Ok(())
    }
    fn new_velocities(&mut self) {
        self.shape.fill([NO_SHAPE; 3]);
    }
    #[inline(always)]
    fn shape_touched(&self, i: u32) -> [Body; 3] {
        self.shape[i as usize]
    }
    fn pair(&mut self, m: &mut Motion, i: u32, j: u32, dr: DVec3, _now: f64, out: &mut Outcome) {
        self.partner[i as usize] = j;
        self.partner[j as usize] = i;
        let dv = m.bodies[j as usize].v - m.bodies[i as usize].v;
        out.approach = -dv.dot(dr.normalize_or_zero());
        out.restitution = f64::NAN;
        out.changed.extend([i, j]);
    }
    fn wall(&mut self, m: &mut Motion, i: u32, wall: Wall, _now: f64, out: &mut Outcome) {
        let met = &mut self.shape[i as usize];
        *met = [wall.body, met[0], met[1]];
        out.approach = -m.bodies[i as usize].v.dot(wall.n);
        out.restitution = f64::NAN;
        out.changed.push(i);
    }
    #[inline(always)]
    fn touching(&self, i: u32, j: u32) -> bool {
        self.partner[i as usize] == j
    }
}

/// Two bodies of masses `ma`, `mb` (either may be infinite) exchange the impulse that turns the
/// normal approach speed `u` into `−e·u`: the velocity changes of each, the energy lost and
/// `r·Δp_b` for the virial (with `dist = |r|`).
#[inline]
fn exchange(ma: f64, mb: f64, u: f64, e: f64, n: DVec3, dist: f64) -> (DVec3, DVec3, f64, f64) {
    // Reduced mass; an infinite mass leaves the other's.
    let mu = if ma.is_infinite() {
        mb
    } else if mb.is_infinite() {
        ma
    } else {
        ma * mb / (ma + mb)
    };
    let j = (1.0 + e) * mu * u; // impulse on b, along +n
    let dva = if ma.is_infinite() {
        DVec3::ZERO
    } else {
        -n * (j / ma)
    };
    let dvb = if mb.is_infinite() {
        DVec3::ZERO
    } else {
        n * (j / mb)
    };
    (dva, dvb, 0.5 * mu * u * u * (1.0 - e * e), j * dist)
}

/// What an elastic collision of two free spheres changes: their velocities, `w = u |dr|` (the
/// approach speed times the distance), the virial `r·Δp`, and whether the grazing floor was used.
#[derive(Debug, Clone, Copy)]
struct ElasticExchange {
    dvi: DVec3,
    dvj: DVec3,
    w: f64,
    virial: f64,
    guarded: bool,
}

/// The elastic exchange of two spheres of finite masses `mi`, `mj` (a world's masses are
/// within the range), `dv = vⱼ − vᵢ`, `dr` from `i` to `j`, written with `dr` unnormalised:
/// `Δvⱼ = dr · (2w / |dr|²) · mᵢ/(mᵢ + mⱼ)` with `w = −dv·dr`, the same impulse as
/// [`exchange`] with `n̂ = dr/|dr|`, `u = w/|dr|` and `e = 1`, and the same grazing floor
/// (`u ≥ 2⁻⁴⁰ |dv|`, compared squared). Only the division by `|dr|²` lies between the
/// colliding velocities and the new ones; the masses' shares do not depend on them
/// (docs/derivations/simulation.md, "The elastic exchange").
#[inline(always)]
fn elastic_exchange(mi: f64, mj: f64, dv: DVec3, dr: DVec3) -> ElasticExchange {
    let q = dr.length_squared();
    let w = -dv.dot(dr);
    let floor_squared = GRAZING * GRAZING * dv.length_squared() * q;
    let guarded = w < 0.0 || w * w < floor_squared;
    let w = if guarded { floor_squared.sqrt() } else { w };
    let s = 2.0 * w / q;
    let total = mi + mj;
    ElasticExchange {
        dvi: dr * -(s * (mj / total)),
        dvj: dr * (s * (mi / total)),
        w,
        virial: 2.0 * (mi * mj / total) * w,
        guarded,
    }
}

/// Every collision elastic, every sphere free: the hard-sphere gas.
#[derive(Debug, Clone, Default)]
pub(crate) struct Elastic;

impl Responder for Elastic {
    const REPORT_ONLY: bool = false;
    const NAME: &'static str = "elastic";
    // The velocities by `elastic_exchange`, with no square root or division by a mass on the
    // way from the collision to the next predictions; the approach speed, for the event log,
    // beside it (the engine's overlap computes the same `dr.length()`: one square root).
    #[inline(always)]
    fn pair(&mut self, m: &mut Motion, i: u32, j: u32, dr: DVec3, _now: f64, out: &mut Outcome) {
        let (bi, bj) = (m.bodies[i as usize], m.bodies[j as usize]);
        let (mi, mj) = (m.mass[i as usize], m.mass[j as usize]);
        let e = elastic_exchange(mi, mj, bj.v - bi.v, dr);
        m.set_velocity_in_place(i, bi.v + e.dvi);
        m.set_velocity_in_place(j, bj.v + e.dvj);
        let u = e.w / dr.length();
        (out.virial, out.approach, out.restitution, out.guarded) = (e.virial, u, 1.0, e.guarded);
        out.changed.extend([i, j]);
    }
    #[inline]
    fn wall(&mut self, m: &mut Motion, i: u32, wall: Wall, _now: f64, out: &mut Outcome) {
        let v = m.bodies[i as usize].v;
        let (u, guarded) = normal_impulse(v, wall.n);
        let (v, slid) = leave_wall(v + wall.n * (2.0 * u), wall.n, wall.floor);
        let (v, added) = hop_off(v, wall.n, wall.hop);
        let energy_lost = if added > 0.0 {
            -added * m.mass[i as usize]
        } else {
            0.0
        };
        m.set_velocity_in_place(i, v);
        (out.energy_lost, out.approach, out.restitution) = (energy_lost, u, 1.0);
        (out.guarded, out.slid) = (guarded, slid);
        out.changed.push(i);
    }
}

/// A response per pair of materials, the TC model and sticky clusters.
#[derive(Debug, Clone)]
pub(crate) struct Materials {
    /// `n × n` responses.
    table: Vec<Response>,
    n: usize,
    tc: f64,
    /// Each sphere's last collision time (for the TC model).
    last: Vec<f64>,
    /// Each sphere's cluster (a sphere's own index while it is alone).
    pub cluster: Vec<u32>,
    /// Members of clusters of two or more, by cluster id.
    members: Vec<Vec<u32>>,
    /// Cluster masses (`∞` once stuck to a static shape).
    cmass: Vec<f64>,
    /// Each sphere's count towards a collapse (`collided`).
    rapid: Vec<u32>,
    /// `2⁻²⁰` of the mean time between a sphere's events.
    rapid_window: f64,
}

impl Materials {
    pub fn new(table: Vec<Response>, n: usize, tc: f64, masses: &[f64]) -> Self {
        let count = masses.len();
        Self {
            table,
            n,
            tc,
            last: vec![f64::NEG_INFINITY; count],
            cluster: (0..count as u32).collect(),
            members: vec![Vec::new(); count],
            cmass: masses.to_vec(),
            rapid: vec![0; count],
            rapid_window: 0.0,
        }
    }

    /// Sphere `s` collided at `now` with restitution `e` (with another sphere if `pair`): the
    /// TC model's clock, and the collapse watch. A dissipating collision within the window
    /// ([`Materials::rapid_window`]) of the sphere's previous one adds one to its count, a
    /// later one takes off one per whole window elapsed; at [`RAPID_LIMIT`] it is a collapse.
    /// An elastic collision (the TC model's, among others) ends the count, so a resting stack
    /// that chatters elastically is not taken for one. Under gravity a wall collision is not
    /// counted: a sphere sliding round a bowl meets the wall many times a window without
    /// collapsing (docs/derivations/gravity.md, "Resting piles").
    #[inline]
    fn collided(&mut self, m: &Motion, s: u32, now: f64, e: f64, pair: bool, out: &mut Outcome) {
        let k = s as usize;
        if e >= 1.0 {
            self.rapid[k] = 0;
        } else if pair || m.g == DVec3::ZERO {
            let leak = ((now - self.last[k]) / self.rapid_window(m, k)).floor();
            // NaN (no window yet, or no previous collision) ends the count too.
            self.rapid[k] = if leak < f64::from(self.rapid[k]) + 1.0 {
                self.rapid[k] + 1 - leak as u32
            } else {
                0
            };
            if self.rapid[k] >= RAPID_LIMIT {
                out.collapsing = Some(s);
            }
        }
        self.last[k] = now;
    }

    /// The collapse watch's window for sphere `k`: `2⁻²⁰` of the mean time between events, and
    /// under gravity at least an eighth of the flight of the rounding hop off a floor
    /// (`walls::rounding_hop_time`), capped at `tc` (a dissipating collision is at least `tc`
    /// after the sphere's previous one). Without TC a pile whose only floor is that hop grinds
    /// at a steady rate, many collisions a hop, instead of converging: a collapse all the same.
    #[inline]
    fn rapid_window(&self, m: &Motion, k: usize) -> f64 {
        let b = &m.bodies[k];
        let hop = super::walls::rounding_hop_time(m.g, b.r, b.radius) / 8.0;
        let tc = if self.tc > 0.0 {
            self.tc
        } else {
            f64::INFINITY
        };
        self.rapid_window.max(hop.min(tc))
    }

    /// The TC model's hop speed under gravity, `‖g‖·tc/2` less `2⁻²⁰` of it (`0` without
    /// either): off a level floor the flight then lasts `tc (1 − 2⁻²⁰)`, so that the contact it
    /// comes back to is a resting one whatever the rounding, and hops again (with `‖g‖·tc/2`
    /// the flight was `tc` to the last bits and rounding chose: docs/derivations/gravity.md,
    /// "Resting contact").
    #[inline]
    fn rest_hop(&self, g: DVec3) -> f64 {
        0.5 * g.length() * self.tc * (1.0 - 1.0 / (1u64 << 20) as f64)
    }

    /// Under gravity, for a collision the TC model made elastic (within `tc` of a sphere's
    /// last): the velocity changes `(dvi, dvj)` and the energy lost of a pair collision, raised
    /// so that the pair separates at least at the hop speed `‖g‖·tc/2` (momentum kept, the
    /// energy added taken from the loss), and the separation speed when it was raised. A
    /// contact between spheres pressed together by the weight above them then recurs no sooner
    /// than about `tc`, as a wall contact does ([`Materials::wall`]), instead of chattering
    /// ever faster as the pile's last motion drains away; a pair meeting for the first time in
    /// `tc` (two grains touching in free fall) keeps its coefficient and loses energy
    /// (docs/derivations/gravity.md, "Resting piles").
    #[inline]
    fn pair_hop(
        &self,
        g: DVec3,
        n: DVec3,
        (mi, mj): (f64, f64),
        relative: f64,
        (dvi, dvj, lost): (DVec3, DVec3, f64),
    ) -> (DVec3, DVec3, f64, Option<f64>) {
        if mi.is_infinite() || mj.is_infinite() {
            return (dvi, dvj, lost, None);
        }
        let hop = self.rest_hop(g);
        let apart = relative + (dvj - dvi).dot(n);
        if apart >= hop {
            return (dvi, dvj, lost, None);
        }
        let mu = mi * mj / (mi + mj);
        let impulse = mu * (hop - apart);
        let added = 0.5 * mu * (hop * hop - apart * apart);
        (
            dvi - n * (impulse / mi),
            dvj + n * (impulse / mj),
            lost - added,
            Some(hop),
        )
    }

    fn response(&self, a: u16, b: u16) -> Response {
        self.table[usize::from(a) * self.n + usize::from(b)]
    }

    /// The members of the cluster `c`.
    pub fn members(&self, c: u32) -> &[u32] {
        let m = &self.members[c as usize];
        if m.is_empty() {
            std::slice::from_ref(&self.cluster[c as usize])
        } else {
            m
        }
    }

    /// Every cluster of two or more spheres.
    pub fn clusters(&self) -> impl Iterator<Item = &[u32]> {
        self.members
            .iter()
            .filter(|m| !m.is_empty())
            .map(Vec::as_slice)
    }

    /// Whether one of `spheres` collided less than `tc` before `now`: the TC model makes the
    /// collision elastic (and, under gravity, gives it the hop).
    #[inline]
    fn resting(&self, now: f64, spheres: &[u32]) -> bool {
        spheres
            .iter()
            .any(|&s| now - self.last[s as usize] < self.tc)
    }

    /// Gives every member of cluster `c` the velocity `v`.
    fn move_cluster(&self, m: &mut Motion, c: u32, v: DVec3, now: f64, out: &mut Outcome) {
        for &s in self.members(c) {
            m.set_velocity(s, v, now);
            out.changed.push(s);
        }
    }

    /// Joins cluster `b` into cluster `a`.
    fn join(&mut self, a: u32, b: u32) -> u32 {
        let (a, b) = if self.members(a).len() >= self.members(b).len() {
            (a, b)
        } else {
            (b, a)
        };
        let moved: Vec<u32> = self.members(b).to_vec();
        if self.members[a as usize].is_empty() {
            self.members[a as usize].push(a);
        }
        for &s in &moved {
            self.cluster[s as usize] = a;
        }
        self.members[a as usize].extend(moved);
        self.members[b as usize] = Vec::new();
        let mb = self.cmass[b as usize];
        self.cmass[a as usize] += mb;
        a
    }
}

impl Responder for Materials {
    const REPORT_ONLY: bool = false;
    const INELASTIC: bool = true;
    const NAME: &'static str = "materials";
    fn set_time_scale(&mut self, mean: f64) {
        self.rapid_window = mean / (1u64 << 20) as f64;
    }
    fn permute(&mut self, new_of_old: &[u32]) {
        // Cluster ids are sphere indices: both the arrays and the ids they hold move.
        self.last = permuted(&self.last, new_of_old);
        self.rapid = permuted(&self.rapid, new_of_old);
        self.cmass = permuted(&self.cmass, new_of_old);
        self.cluster = permuted(&self.cluster, new_of_old)
            .into_iter()
            .map(|c| renumbered(c, new_of_old))
            .collect();
        let mut members = vec![Vec::new(); self.members.len()];
        for (old, m) in self.members.iter_mut().enumerate() {
            members[new_of_old[old] as usize] =
                m.iter().map(|&s| renumbered(s, new_of_old)).collect();
        }
        self.members = members;
    }
    fn save(&self, e: &mut Encoder) {
        for k in 0..self.cluster.len() {
            e.f64(self.last[k]);
            e.u32(self.rapid[k]);
            e.u32(self.cluster[k]);
            e.f64(self.cmass[k]);
            e.len(self.members[k].len());
            for &s in &self.members[k] {
                e.u32(s);
            }
        }
    }
    fn load(&mut self, d: &mut Decoder, n: usize) -> Result<(), SimError> {
        let bad = |what: String| Err(SimError::Checkpoint(what));
        for k in 0..n {
            self.last[k] = d.f64()?;
            self.rapid[k] = d.u32()?.min(RAPID_LIMIT);
            self.cluster[k] = d.u32()?;
            if self.cluster[k] as usize >= n {
                return bad(format!("cluster {} does not exist", self.cluster[k]));
            }
            self.cmass[k] = d.f64()?;
            let len = d.len(4, "cluster members")?;
            if len > n {
                return bad(format!("cluster of {len} members in a world of {n}"));
            }
            self.members[k] = (0..len).map(|_| d.u32()).collect::<Result<_, _>>()?;
            if self.members[k].iter().any(|&s| s as usize >= n) {
                return bad("a cluster member does not exist".into());
            }
        }
        Ok(())
    }
    fn check_velocities(&self, v: &dyn Fn(u32) -> DVec3, _n: usize) -> Result<(), (u32, String)> {
        for members in self.clusters() {
            let first = v(members[0]);
            let stuck = self.cmass[self.cluster[members[0] as usize] as usize].is_infinite();
            for &s in members {
                if stuck && v(s) != DVec3::ZERO {
                    return Err((
                        s,
                        "its cluster is stuck to a static shape: its velocity must be zero".into(),
                    ));
                }
                if v(s) != first {
                    return Err((
                        s,
                        format!(
                            "a cluster moves as one: give it the velocity of its other members \
                             ({})",
                            Nums(first.to_array())
                        ),
                    ));
                }
            }
        }
        // A single sphere stuck to a shape.
        for (s, &c) in self.cluster.iter().enumerate() {
            if self.members[c as usize].is_empty()
                && self.cmass[c as usize].is_infinite()
                && v(s as u32) != DVec3::ZERO
            {
                return Err((
                    s as u32,
                    "it is stuck to a static shape: its velocity must be zero".into(),
                ));
            }
        }
        Ok(())
    }
    fn pair(&mut self, m: &mut Motion, i: u32, j: u32, dr: DVec3, now: f64, out: &mut Outcome) {
        let (ci, cj) = (self.cluster[i as usize], self.cluster[j as usize]);
        let (vi, vj) = (m.bodies[i as usize].v, m.bodies[j as usize].v);
        let (mi, mj) = (self.cmass[ci as usize], self.cmass[cj as usize]);
        let dist = dr.length();
        let n = dr / dist;
        let (u, guarded) = normal_impulse(vj - vi, n);
        out.approach = u;
        out.guarded = guarded;
        let response = self.response(m.material[i as usize], m.material[j as usize]);
        let resting = self.resting(now, &[i, j]);
        let e = match response {
            Response::ReportOnly | Response::Elastic => 1.0,
            Response::Inelastic { .. } if resting => 1.0,
            Response::Inelastic { restitution } => restitution,
            Response::Sticky => {
                // Common velocity conserving momentum; a stuck cluster (infinite mass) holds.
                let v = if mi.is_infinite() || mj.is_infinite() {
                    DVec3::ZERO
                } else {
                    (vi * mi + vj * mj) / (mi + mj)
                };
                let rel = vj - vi;
                let mu = if mi.is_infinite() {
                    mj
                } else if mj.is_infinite() {
                    mi
                } else {
                    mi * mj / (mi + mj)
                };
                out.energy_lost = 0.5 * mu * rel.length_squared();
                out.virial = mu * u * dist;
                out.restitution = 0.0;
                out.joined = true;
                let c = self.join(ci, cj);
                self.move_cluster(m, c, v, now, out);
                self.collided(m, i, now, 0.0, true, out);
                self.collided(m, j, now, 0.0, true, out);
                return;
            }
        };
        let (dvi, dvj, lost, virial) = exchange(mi, mj, u, e, n, dist);
        let (dvi, dvj, lost, hopped) = if resting && m.g != DVec3::ZERO {
            self.pair_hop(m.g, n, (mi, mj), (vj - vi).dot(n), (dvi, dvj, lost))
        } else {
            (dvi, dvj, lost, None)
        };
        self.collided(m, i, now, e, true, out);
        self.collided(m, j, now, e, true, out);
        out.energy_lost = lost;
        out.virial = virial;
        out.restitution = hopped.map_or(e, |w| w / u);
        if !mi.is_infinite() {
            self.move_cluster(m, ci, vi + dvi, now, out);
        }
        if !mj.is_infinite() {
            self.move_cluster(m, cj, vj + dvj, now, out);
        }
    }

    fn wall(&mut self, m: &mut Motion, i: u32, wall: Wall, now: f64, out: &mut Outcome) {
        let c = self.cluster[i as usize];
        let v = m.bodies[i as usize].v;
        let n = wall.n;
        let (u, guarded) = normal_impulse(v, n);
        out.approach = u;
        out.guarded = guarded;
        let mc = self.cmass[c as usize];
        let resting = self.resting(now, &[i]);
        let e = match self.response(m.material[i as usize], wall.material) {
            Response::ReportOnly | Response::Elastic => 1.0,
            Response::Inelastic { .. } if resting => 1.0,
            Response::Inelastic { restitution } => restitution,
            Response::Sticky => {
                out.energy_lost = 0.5 * mc * v.length_squared();
                out.restitution = 0.0;
                out.joined = true;
                self.cmass[c as usize] = f64::INFINITY;
                self.move_cluster(m, c, DVec3::ZERO, now, out);
                self.collided(m, i, now, 0.0, false, out);
                return;
            }
        };
        self.collided(m, i, now, e, false, out);
        out.restitution = e;
        out.energy_lost = 0.5 * mc * u * u * (1.0 - e * e);
        let (v, slid) = leave_wall(v + n * ((1.0 + e) * u), n, wall.floor);
        // The TC model's hop only for a contact within `tc` of the sphere's last (a resting
        // one; see `pair_hop`); rounding's everywhere gravity presses.
        let hop = if resting {
            wall.hop.max(self.rest_hop(m.g))
        } else {
            wall.hop
        };
        let (v, added) = hop_off(v, n, hop);
        if added > 0.0 {
            out.energy_lost -= added * mc;
            out.restitution = hop / u;
        }
        out.slid = slid;
        self.move_cluster(m, c, v, now, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// A random pair's masses, relative velocity and separation, across scales: masses over
    /// twelve binary orders, the velocity's direction anywhere against `dr` (often nearly
    /// perpendicular to it: grazing).
    fn pair(rng: &mut Rng) -> (f64, f64, DVec3, DVec3) {
        let scale = |rng: &mut Rng| 2f64.powf(rng.range(-6.0, 6.0));
        let (mi, mj) = (scale(rng), scale(rng));
        let dr = rng.direction() * scale(rng);
        let dv = if rng.unit() < 0.3 {
            // Perpendicular to `dr` to rounding, or within an angle of `10⁻¹⁷` to `10⁻¹¹`
            // (about the floor, `2⁻⁴⁰ ≈ 9·10⁻¹³`), approaching or not.
            let n = dr.normalize();
            let tilt = [0.0, 1e-17, 1e-15, 1e-13, 1e-12, 1e-11][(rng.unit() * 6.0) as usize];
            (rng.perpendicular(n) + n * (tilt * rng.range(-1.0, 1.0))) * scale(rng)
        } else {
            rng.direction() * scale(rng)
        };
        (mi, mj, dv, dr)
    }

    /// The square-root-free elastic exchange gives the impulse of the general one (`exchange`
    /// with `n̂ = dr/|dr|`, `e = 1`) within the rounding bound of "The elastic exchange"
    /// (docs/derivations/simulation.md): `64 u |dv|` (`u = 2⁻⁵³`) on each velocity change, the
    /// same grazing floor's decision away from its threshold, and the virial within `64 u` of
    /// its scale.
    #[test]
    fn the_elastic_exchange_is_the_general_impulse_within_its_rounding_bound() {
        let mut rng = Rng::new(7);
        let bound = 32.0 * f64::EPSILON;
        for _ in 0..200_000 {
            let (mi, mj, dv, dr) = pair(&mut rng);
            let dist = dr.length();
            let n = dr / dist;
            let (u, guarded) = normal_impulse(dv, n);
            let (dvi, dvj, _, virial) = exchange(mi, mj, u, 1.0, n, dist);
            let e = elastic_exchange(mi, mj, dv, dr);
            let scale = dv.length();
            assert!(
                (e.dvi - dvi).length() <= bound * scale && (e.dvj - dvj).length() <= bound * scale,
                "{mi} {mj} {dv} {dr}: {:?} against {dvi} {dvj}",
                (e.dvi, e.dvj)
            );
            let reduced = mi * mj / (mi + mj);
            assert!(
                (e.virial - virial).abs() <= bound * 2.0 * reduced * scale * dist,
                "{mi} {mj} {dv} {dr}: virial {} against {virial}",
                e.virial
            );
            // The floor's decision agrees except within rounding of its threshold.
            let margin = (u - GRAZING * scale).abs();
            if margin > bound * scale {
                assert_eq!(e.guarded, guarded, "{mi} {mj} {dv} {dr}");
            }
        }
    }

    /// After the exchange a pair no longer approaches, and momentum is kept, however grazing or
    /// receding it came in (the floor's purpose: a pair still approaching would collide again
    /// at the same time, forever); the grazing pairs are counted, so the case is met.
    #[test]
    fn after_an_elastic_exchange_the_pair_recedes_and_keeps_its_momentum() {
        let mut rng = Rng::new(8);
        let mut floored = 0;
        for _ in 0..200_000 {
            let (mi, mj, dv, dr) = pair(&mut rng);
            let e = elastic_exchange(mi, mj, dv, dr);
            let after = dv + e.dvj - e.dvi;
            assert!(after.dot(dr) > 0.0, "{mi} {mj} {dv} {dr}: {after}");
            let momentum = e.dvi * mi + e.dvj * mj;
            let kick = (e.dvj * mj).length();
            assert!(
                momentum.length() <= 8.0 * f64::EPSILON * kick,
                "{momentum} of {kick}"
            );
            floored += usize::from(e.guarded);
        }
        assert!(floored > 10_000, "{floored} grazing or receding pairs");
    }

    /// A sphere left heading a rounding into a convex shape (floor `κ = 0`) is turned to the
    /// tangent but not counted as sliding (the summary said spheres slid along a container in
    /// a scene with none); at a concave wall's floor angle it is counted.
    #[test]
    fn only_a_concave_walls_floor_counts_as_sliding() {
        let (n, v) = (DVec3::Z, DVec3::new(1.0, 0.0, -1e-17));
        let (out, slid) = leave_wall(v, n, 0.0);
        assert!(!slid && out.z == 0.0 && (out.length() - v.length()).abs() < 1e-15);
        let (out, slid) = leave_wall(v, n, 1e-3);
        assert!(slid && (out.z - 1e-3 * v.length()).abs() < 1e-18);
        assert!(!leave_wall(DVec3::new(1.0, 0.0, 0.5), n, 1e-3).1);
    }
}
