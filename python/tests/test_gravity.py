"""Gravity seen from Python: a ball's bounces and a settling pile, read back with numpy alone
(closed forms of free fall, the positions against the walls), and the energy balance."""

import numpy as np
import pytest

import spheresweep as ss

G = 9.81


def test_a_dropped_ball_follows_free_fall_and_bounces_back_to_its_height():
    h = 2.0
    sim = ss.Simulation.from_spheres([[0, 0, 0.5 + h]], [[0, 0, 0]], [0.5],
                                     planes=[ss.Plane([0, 0, 0], [0, 0, 1])],
                                     gravity=[0, 0, -G])
    t_hit = np.sqrt(2 * h / G)
    for t in np.linspace(0.0, 0.9 * t_hit, 10)[1:]:
        sim.advance_to(float(t))
        z = sim.positions[0, 2]
        assert abs(z - (0.5 + h - 0.5 * G * t * t)) < 1e-12
    # It lands at t_hit and is back at the top, at rest, at 2 t_hit.
    sim.advance_to(2 * t_hit)
    assert abs(sim.positions[0, 2] - (0.5 + h)) < 1e-9
    assert abs(sim.velocities[0, 2]) < 1e-9
    e = sim.energy()
    assert abs(e["total"] - G * (0.5 + h)) < 1e-9
    assert e["potential"] == pytest.approx(G * (0.5 + h))


def test_a_settling_pile_in_a_box_comes_to_rest_inside_it():
    """A floor and four walls (in a round bowl frictionless spheres keep sliding along the
    wall, which no normal impulse can stop: tests/gravity.rs measures that residue). At rest
    it simmers at a bounded rate of events (the hops: docs/derivations/gravity.md,
    "Resting piles"), so it can stay there."""
    rng = np.random.default_rng(3)
    g = np.arange(-2, 2) * 1.2 + 0.6
    sites = np.stack(np.meshgrid(g, g, g + 2.5), -1).reshape(-1, 3)[:40]
    walls = [ss.Plane([0, 0, 0], [0, 0, 1]), ss.Plane([-3, 0, 0], [1, 0, 0]),
             ss.Plane([3, 0, 0], [-1, 0, 0]), ss.Plane([0, -3, 0], [0, 1, 0]),
             ss.Plane([0, 3, 0], [0, -1, 0])]
    sim = ss.Simulation.from_spheres(sites, rng.normal(size=(40, 3)), np.full(40, 0.5),
                                     planes=walls, restitution=0.5, tc=1e-3,
                                     gravity=[0, 0, -G])
    e0 = sim.energy()
    for t in np.arange(1, 41) * 0.25:
        sim.advance_to(float(t))
        p, r = sim.positions, sim.radii
        assert np.min(p[:, 2] - r) >= -2.0**-16 * 0.5
        assert np.max(np.abs(p[:, :2]) + r[:, None]) <= 3.0 + 2.0**-16 * 0.5
    e = sim.energy()
    # At rest: what is left moving is a small fraction of the energy the pile had to lose.
    dropped = e0["kinetic"] + e0["potential"] - e["potential"]
    assert e["kinetic"] < 1e-3 * dropped, (e, e0)
    assert abs(e["total"] - e0["total"]) < 1e-9 * abs(dropped)
    # A pickled simulation goes on bit for bit.
    import pickle
    twin = pickle.loads(pickle.dumps(sim))
    events = sim.stats["collisions"]
    sim.advance_to(11.0)
    twin.advance_to(11.0)
    assert np.array_equal(sim.positions, twin.positions)
    # At rest it simmers: the last second costs no more events than 7 N / tc.
    assert sim.stats["collisions"] - events <= 7 * 40 / 1e-3


def test_gravity_is_refused_with_a_periodic_box():
    with pytest.raises(ValueError, match="periodic"):
        ss.Simulation.from_spheres([[1, 1, 1]], [[0, 0, 0]], [0.5], periodic_box=[5, 5, 5],
                                   gravity=[0, 0, -1])
