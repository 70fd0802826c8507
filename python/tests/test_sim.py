"""The event-driven simulation through Python: the constructors agree with each other, energy
and momentum are conserved in elastic worlds, single collisions follow their closed forms,
events come out as arrays, errors are named, and the GIL is released while it runs."""

import math
import pathlib
import pickle
import re
import threading
import time
import warnings

import numpy as np
import pytest

import spheresweep as ss

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_scene_file_and_periodic_gas_build_the_same_world():
    # scenes/hard_sphere_gas.toml asks for periodic_gas(n=4000, phi=0.25, radius=0.5, kT=1,
    # seed=1): the two constructors must give the same spheres.
    a = ss.Simulation.from_scene_file(str(ROOT / "scenes" / "hard_sphere_gas.toml"))
    b = ss.Simulation.periodic_gas(4000, 0.25, radius=0.5, kT=1.0, seed=1)
    assert a.t_end == 50.0 and b.t_end is None
    assert len(a) == len(b) == 4000
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.velocities, b.velocities)
    assert a.engine == b.engine
    # And run alike, collision for collision.
    a.advance_to(0.5)
    b.advance_to(0.5)
    assert a.stats == b.stats
    assert np.array_equal(a.positions, b.positions)


def test_periodic_gas_conserves_energy_and_momentum():
    sim = ss.Simulation.periodic_gas(1000, 0.3, seed=4)
    e0, p0 = sim.kinetic_energy(), np.array(sim.momentum())
    v = sim.velocities
    assert sim.positions.shape == (1000, 3) and sim.positions.dtype == np.float64
    # Thermal velocities at kT = 1 with zero total momentum: E = (3N - 3)/2 kT on average;
    # the check is only that the numbers read back are the state's.
    assert e0 == pytest.approx(0.5 * (sim.masses[:, None] * v * v).sum(), rel=1e-12)
    sim.advance_to(5.0)
    stats = sim.stats
    assert sim.time == 5.0
    assert stats["collisions"] == stats["pair_collisions"] > 5000
    assert stats["wall_collisions"] == 0 and stats["energy_lost"] == 0.0
    # Elastic collisions in f64 round each pair's new energy by a few eps = 2^-52 of random
    # sign: a random walk, |dE|/E <= c eps sqrt(K) with c = 8 over K collisions
    # (docs/derivations/simulation.md, "Energy drift of an elastic gas").
    assert abs(sim.kinetic_energy() - e0) < drift_bound(stats["collisions"]) * e0
    # Momentum: bounded the same way, on the scale of the spheres' momenta.
    scale = math.sqrt(2 * e0 * len(sim))
    assert np.abs(np.array(sim.momentum()) - p0).max() < drift_bound(stats["collisions"]) * scale
    # Positions are wrapped into the periodic box [0, L) of the generator (sim.box, exact).
    side = sim.box[0]
    assert sim.box == (side, side, side)
    pos = sim.positions
    assert (pos >= 0).all() and (pos < side).all()


def drift_bound(collisions):
    """docs/derivations/simulation.md's bound on the relative energy drift of an elastic gas
    after `collisions` collisions: 8 eps sqrt(K), eps = 2^-52."""
    return 8 * 2.0**-52 * math.sqrt(collisions)


def test_head_on_collision_closed_form():
    # Two unit spheres 10 apart approaching at 1 each: contact when the gap 8 closes at
    # relative speed 2, t = 4; equal masses exchange velocities.
    sim = ss.Simulation.from_spheres(
        [[0, 0, 0], [10, 0, 0]], [[1, 0, 0], [-1, 0, 0]], [1.0, 1.0], record_events=True, geometry=True
    )
    sim.advance_to(6.0)
    ev = sim.take_events()
    assert len(ev["time"]) == 1
    assert ev["time"][0] == pytest.approx(4.0, abs=1e-12)
    assert (int(ev["sphere"][0]), int(ev["kind"][0]), int(ev["index"][0])) in {(0, ss.KIND_SPHERE, 1), (1, ss.KIND_SPHERE, 0)}
    assert ev["approach"][0] == pytest.approx(2.0)
    assert ev["restitution"][0] == 1.0 and ev["energy_lost"][0] == 0.0
    assert [ev["point_x"][0], ev["point_y"][0], ev["point_z"][0]] == pytest.approx([5.0, 0, 0])
    assert abs(ev["normal_x"][0]) == pytest.approx(1.0)
    # After: velocities exchanged, positions moved on for 2 time units.
    assert sim.velocities == pytest.approx(np.array([[-1, 0, 0], [1, 0, 0]]))
    assert sim.positions == pytest.approx(np.array([[2, 0, 0], [8, 0, 0]]))
    assert sim.stats["pair_collisions"] == 1
    # Events are taken once.
    assert len(sim.take_events()["time"]) == 0


def test_bounce_on_a_floor_with_restitution():
    # A ball of radius 1 at height 3 falling at 2 meets the floor at t = 1 and leaves at
    # half its speed.
    floor = ss.Plane([0, 0, 0], [0, 0, 1])
    sim = ss.Simulation.from_spheres([[0, 0, 3]], [[0, 0, -2]], [1.0], planes=[floor], restitution=0.5, record_events=True)
    sim.advance_to(3.0)
    ev = sim.take_events()
    assert ev["kind"].tolist() == [ss.KIND_PLANE] and ev["index"].tolist() == [0]
    assert ev["time"][0] == pytest.approx(1.0, abs=1e-12)
    assert sim.velocities[0] == pytest.approx([0, 0, 1.0])
    assert sim.positions[0] == pytest.approx([0, 0, 3.0])
    # Energy lost: 1/2 m (2^2 - 1^2) = 1.5.
    assert sim.stats["energy_lost"] == pytest.approx(1.5)
    assert sim.kinetic_energy() == pytest.approx(0.5)
    # Without geometry the points are NaN.
    assert all(np.isnan(ev[f"{c}_{a}"]).all() for c in ("point", "normal") for a in "xyz")


def test_elastic_gas_in_a_container_conserves_energy():
    rng = np.random.default_rng(2)
    # 200 spheres on a cubic lattice (spacing 2, radius 0.4) inside a container of radius 20.
    g = np.arange(-4, 4) * 2.0 + 1.0
    sites = np.stack(np.meshgrid(g, g, g), -1).reshape(-1, 3)[:200]
    v = rng.normal(size=(200, 3))
    sim = ss.Simulation.from_spheres(sites, v, np.full(200, 0.4), rng.uniform(0.5, 2, 200),
                                     containers=[ss.Container([0, 0, 0], 20.0)])
    e0 = sim.kinetic_energy()
    sim.advance_to(20.0)
    assert sim.stats["wall_collisions"] > 10 and sim.stats["pair_collisions"] > 10
    assert abs(sim.kinetic_energy() - e0) < drift_bound(sim.stats["collisions"]) * e0
    assert (np.linalg.norm(sim.positions, axis=1) <= 20.0 - 0.4 + 1e-9).all()


def test_simulation_errors():
    sim = ss.Simulation.periodic_gas(100, 0.1)
    sim.advance_to(1.0)
    with pytest.raises(ValueError, match="cannot advance to t = 0.5: the simulation is at t = 1"):
        sim.advance_to(0.5)
    with pytest.raises(ValueError, match="t: cannot advance to t = nan: the end time must be finite"):
        sim.advance_to(math.nan)
    with pytest.raises(ValueError, match=r"periodic gas: phi = 0.9 must be above 0 and below 0.7"):
        ss.Simulation.periodic_gas(100, 0.9)
    with pytest.raises(ValueError, match="spheres 0 and 1 overlap"):
        ss.Simulation.from_spheres([[0, 0, 0], [1, 0, 0]], np.zeros((2, 3)), [1.0, 1.0])
    with pytest.raises(ValueError, match="sphere 1: radius"):
        ss.Simulation.from_spheres([[0, 0, 0], [5, 0, 0]], np.zeros((2, 3)), [1.0, -1.0])
    with pytest.raises(ValueError, match="restitution: 1.5 is not in"):
        ss.Simulation.from_spheres([[0, 0, 0]], [[0, 0, 0]], [1.0], restitution=1.5)
    with pytest.raises(TypeError, match="centres: dtype"):
        ss.Simulation.from_spheres(np.zeros((1, 3), bool), [[0, 0, 0]], [1.0])
    with pytest.raises(OSError, match="no-such-scene.toml"):
        ss.Simulation.from_scene_file("no-such-scene.toml")


def test_scene_file_errors_name_the_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[run]\nt_end = 1.0\n\n[[sphere]]\ncentre = [0, 0, 0]\nvelocity = [0, 0, 0]\nradius = -1.0\n')
    with pytest.raises(ValueError, match=r"bad.toml:7: sphere 0: radius"):
        ss.Simulation.from_scene_file(str(bad))


def test_advance_releases_the_gil():
    # While one thread advances a simulation, this thread must run Python code. Observable
    # states only, no timings: the worker's progress callback (called during advance_to)
    # sees whether this thread has finished its loop meanwhile, and then stops the run. With
    # the GIL held through advance_to, this thread could not run until advance_to returned:
    # the callback would never see the loop done and the run would go to its end.
    sim = ss.Simulation.periodic_gas(4000, 0.25, seed=9)
    started, looped, seen = threading.Event(), threading.Event(), []

    class Enough(Exception):
        pass

    def progress(now):
        started.set()
        if looped.is_set():
            seen.append(now)
            raise Enough

    def run():
        try:
            sim.advance_to(50.0, progress=progress)
        except Enough:
            pass

    worker = threading.Thread(target=run)
    worker.start()
    assert started.wait(120)
    count = 0
    while count < 10_000:
        count += 1
    looped.set()
    worker.join()
    assert seen and seen[0] < 50.0, "the loop ran only after advance_to had finished"
    assert sim.time == seen[0]  # stopped where the callback raised, between two events


def test_from_spheres_in_a_periodic_box_matches_periodic_gas():
    # The spheres of a periodic gas handed back through from_spheres with the same box: the
    # same world, so the same run.
    gas = ss.Simulation.periodic_gas(500, 0.2, seed=6)
    # The generator's box, as it reports it (recomputing it here differed in the last bit).
    side = gas.box[0]
    again = ss.Simulation.from_spheres(gas.positions, gas.velocities, gas.radii, gas.masses,
                                       periodic_box=[side] * 3)
    assert again.engine == gas.engine
    gas.advance_to(2.0)
    again.advance_to(2.0)
    assert gas.stats == again.stats
    assert np.array_equal(gas.positions, again.positions)
    with pytest.raises(ValueError, match="periodic box x"):
        ss.Simulation.from_spheres(gas.positions, gas.velocities, gas.radii, periodic_box=[1.0, side, side])


def test_restore_goes_on_as_the_saved_simulation_would():
    a = ss.Simulation.periodic_gas(500, 0.3, seed=7)
    a.advance_to(1.0)
    saved = a.checkpoint()
    a.advance_to(2.0)
    after = (a.positions, a.velocities, a.stats)
    # Restored into a simulation built the same way, and also into `a` itself (back in time).
    b = ss.Simulation.periodic_gas(500, 0.3, seed=7)
    for sim in (a, b):
        sim.restore(saved)
        assert sim.time == 1.0
        sim.advance_to(2.0)
        assert np.array_equal(sim.positions, after[0])
        assert np.array_equal(sim.velocities, after[1])
        assert sim.stats == after[2]


def test_restore_takes_the_state_of_the_same_system_from_other_starting_points():
    # The checkpoint holds every position and velocity: a gas of the same spheres in the same
    # box (another seed) takes it and goes on as the saved one.
    a = ss.Simulation.periodic_gas(200, 0.3, seed=1)
    b = ss.Simulation.periodic_gas(200, 0.3, seed=2)
    b.advance_to(1.0)
    a.restore(b.checkpoint())
    assert a.time == 1.0 and np.array_equal(a.positions, b.positions)
    a.advance_to(2.0)
    b.advance_to(2.0)
    assert np.array_equal(a.velocities, b.velocities) and a.stats == b.stats


def test_restore_refuses_other_systems_and_damage_and_keeps_the_state():
    a = ss.Simulation.periodic_gas(200, 0.3, seed=1)
    a.advance_to(0.5)
    before = (a.time, a.positions)
    damaged = bytearray(a.checkpoint())
    damaged[len(damaged) // 2] ^= 1
    # Another system: a denser box, or more spheres.
    others = [
        ss.Simulation.periodic_gas(200, 0.25, seed=1),
        ss.Simulation.periodic_gas(300, 0.3, seed=1),
    ]
    for data, message in [(o.checkpoint(), "another world") for o in others] + [
        (bytes(damaged), "checkpoint"),
        (b"", "checkpoint: truncated"),
    ]:
        with pytest.raises(ValueError, match=message):
            a.restore(data)
        assert a.time == before[0] and np.array_equal(a.positions, before[1])
    # The same spheres with other effects are another system; with the same effects, the same.
    args = (a.positions, a.velocities, np.full(200, 0.5))
    box = 2 * a.positions.max() + 2
    elastic = ss.Simulation.from_spheres(*args, periodic_box=[box] * 3)
    for kw in [dict(restitution=0.9), dict(response="sticky"), dict(tc=1e-3), dict(materials=[1] * 200)]:
        with pytest.raises(ValueError, match="another world"):
            elastic.restore(ss.Simulation.from_spheres(*args, periodic_box=[box] * 3, **kw).checkpoint())
    same = ss.Simulation.from_spheres(*args, periodic_box=[box] * 3)
    same.advance_to(0.5)
    elastic.restore(same.checkpoint())
    assert elastic.time == 0.5 and np.array_equal(elastic.positions, same.positions)


def _head_on(**kw):
    # Two unit spheres 10 apart approaching at 1 each (contact at t = 4), equal masses.
    return ss.Simulation.from_spheres(
        [[0, 0, 0], [10, 0, 0]], [[1, 0, 0], [-1, 0, 0]], [1.0, 1.0], **kw
    )


def test_a_pair_of_materials_has_its_own_restitution():
    # Materials 0 and 1 meet with e = 0.5: the relative velocity (2) reverses at half speed,
    # the centre of mass (at rest) stays at rest, so each leaves at 0.5.
    sim = _head_on(materials=[0, 1], pairs=[(1, 0, 0.5)])
    sim.advance_to(6.0)
    assert sim.velocities == pytest.approx(np.array([[-0.5, 0, 0], [0.5, 0, 0]]))
    # Energy lost: 1/2 mu (1 - e^2) v_rel^2 with mu = 1/2: 1/4 * 3/4 * 4 = 0.75.
    assert sim.stats["energy_lost"] == pytest.approx(0.75)
    # The same spheres both of material 0 collide as the scene says (elastic).
    sim = _head_on(materials=[0, 0], pairs=[(1, 0, 0.5)])
    sim.advance_to(6.0)
    assert sim.velocities == pytest.approx(np.array([[-1, 0, 0], [1, 0, 0]]))


def test_a_sticky_pair_joins_into_one_cluster_with_the_momentum():
    # Unequal masses 1 and 3 at +1 and -1: the cluster moves at (1 - 3) / 4 = -0.5.
    sim = ss.Simulation.from_spheres(
        [[0, 0, 0], [10, 0, 0]], [[1, 0, 0], [-1, 0, 0]], [1.0, 1.0], [1.0, 3.0],
        materials=[2, 5], pairs=[(2, 5, "sticky")],
    )  # fmt: skip
    p0 = np.array(sim.momentum())
    sim.advance_to(8.0)
    assert sorted(map(sorted, sim.clusters())) == [[0, 1]]
    assert sim.velocities == pytest.approx(np.array([[-0.5, 0, 0], [-0.5, 0, 0]]))
    assert np.array(sim.momentum()) == pytest.approx(p0)
    # Joined at contact (t = 4, x = 4 and 6), then moved together: the gap stays 2.
    assert sim.positions[1, 0] - sim.positions[0, 0] == pytest.approx(2.0)


def test_a_shape_of_its_own_material_and_the_scene_response():
    # The floor is of material 1; pair (0, 1) has e = 0.25: the ball falling at 2 leaves at
    # 0.5. The scene's own response (restitution 1) would have bounced it at 2.
    floor = ss.Plane([0, 0, 0], [0, 0, 1])
    sim = ss.Simulation.from_spheres(
        [[0, 0, 3]], [[0, 0, -2]], [1.0], planes=[(floor, 1)], pairs=[(0, 1, 0.25)]
    )
    sim.advance_to(2.0)
    assert sim.velocities[0] == pytest.approx([0, 0, 0.5])
    sim = ss.Simulation.from_spheres([[0, 0, 3]], [[0, 0, -2]], [1.0], planes=[(floor, 1)])
    sim.advance_to(2.0)
    assert sim.velocities[0] == pytest.approx([0, 0, 2.0])


def test_response_none_reports_contacts_and_changes_nothing():
    sim = _head_on(response="none", record_events=True)
    sim.advance_to(12.0)
    # The spheres pass through each other: velocities unchanged, energy kept exactly.
    assert sim.velocities.tolist() == [[1, 0, 0], [-1, 0, 0]]
    assert sim.positions == pytest.approx(np.array([[12, 0, 0], [-2, 0, 0]]))
    assert sim.kinetic_energy() == 1.0
    ev = sim.take_events()
    assert ev["time"][0] == pytest.approx(4.0, abs=1e-12)
    # "inelastic" takes its coefficient from restitution.
    sim = _head_on(response="inelastic", restitution=0.0)
    sim.advance_to(6.0)
    assert sim.velocities == pytest.approx(np.zeros((2, 3)))


def test_material_and_effect_errors_name_the_argument():
    c, v, r = [[0, 0, 0], [10, 0, 0]], np.zeros((2, 3)), [1.0, 1.0]
    cases = [
        (dict(materials=[0]), ValueError, r"materials: 1 entries, expected 2"),
        (dict(materials=[0, -1]), ValueError, r"materials\[1\]: material -1 is not in \[0, 1023\]"),
        (dict(materials=[0, 70000]), ValueError, r"materials\[1\]: material 70000"),
        # The engine keeps a response per pair of materials: 1024 at most (not a 69 GB table).
        (dict(materials=[0, 1024]), ValueError, r"materials\[1\]: material 1024 is not in \[0, 1023\]"),
        (dict(pairs=[(0, 65535, 0.5)]), ValueError, r"pairs\[0\].b: material 65535"),
        (dict(materials=[0, 1.5]), TypeError, r"materials\[1\]: a material is an integer"),
        (dict(pairs=[(0, 1)]), TypeError, r"pairs\[0\]: expected a tuple \(a, b, response\)"),
        (dict(pairs=[(0, 1, 2.0)]), ValueError, r"pairs\[0\].response: restitution 2"),
        (dict(pairs=[(0, 1, "bouncy")]), ValueError, r"pairs\[0\].response: \"bouncy\""),
        (dict(pairs=[(0, -3, 0.5)]), ValueError, r"pairs\[0\].b: material -3"),
        (dict(response="bouncy"), ValueError, r"response: \"bouncy\" is not one of"),
        (dict(response="inelastic", restitution=-0.5), ValueError, r"restitution: -0.5"),
        (dict(response="sticky", restitution=0.5), ValueError, r"restitution: 0.5 given with response \"sticky\""),
        (dict(response="elastic", restitution=1.0), ValueError, r"restitution: 1.0 given with response \"elastic\""),
        (dict(response="inelastic"), ValueError, r"restitution: required with response \"inelastic\""),
        (dict(tc=-1.0), ValueError, r"tc: -1"),
        (dict(tc=math.inf), ValueError, r"tc: inf"),
        (dict(planes=[(ss.Plane([0, 0, -5], [0, 0, 1]), -2)]), ValueError, r"planes\[0\].material: material -2"),
        (dict(planes=[(ss.Plane([0, 0, -5], [0, 0, 1]), 1, 2)]), TypeError, r"planes\[0\]: expected a Plane"),
    ]
    for kw, error, message in cases:
        with pytest.raises(error, match=message):
            ss.Simulation.from_spheres(c, v, r, **kw)
    # A pair in a scene that only reports contacts is refused by the world's validation.
    with pytest.raises(ValueError, match="the scene's response is `none`"):
        ss.Simulation.from_spheres(c, v, r, response="none", pairs=[(0, 0, 0.5)])


_READ_WHILE_ADVANCING = """
import threading
import spheresweep as ss

sim = ss.Simulation.periodic_gas(4000, 0.25, seed=9)
sim.advance_to(0.2)
errors = []

def run():
    try:
        for k in range(1, 6):
            sim.advance_to(0.2 + 0.2 * k)
    except Exception as e:
        errors.append(e)

worker = threading.Thread(target=run)
worker.start()
times = []
while worker.is_alive() and len(times) < 100_000:
    times.append(sim.time)
    assert sim.positions.shape == (4000, 3)
worker.join()
assert not errors, errors
assert abs(sim.time - 1.2) < 1e-12 and times, (sim.time, len(times))
assert times == sorted(times), "a read saw time go backwards"
print("reads", len(times))
"""


def test_reading_a_simulation_another_thread_advances_does_not_deadlock():
    # The reader waits for the simulation's lock without the GIL; holding the GIL while it
    # waited would deadlock with the advancing thread taking the GIL back (the old behaviour
    # hung here). Run in a child process, so that a deadlock fails the test instead of hanging.
    import subprocess
    import sys

    try:
        out = subprocess.run([sys.executable, "-c", _READ_WHILE_ADVANCING], capture_output=True,
                             text=True, timeout=120)
    except subprocess.TimeoutExpired:
        pytest.fail("deadlock: reading while another thread advances hung for 120 s")
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("reads ")


def test_restore_takes_a_checkpoint_that_differs_only_in_record_events():
    # Recording events is not part of the system: a checkpoint of a gas that records none
    # restores into the same gas that records them, and both go on alike.
    quiet = ss.Simulation.periodic_gas(200, 0.3, seed=4)
    loud = ss.Simulation.periodic_gas(200, 0.3, seed=4, record_events=True)
    quiet.advance_to(1.0)
    loud.restore(quiet.checkpoint())
    quiet.advance_to(2.0)
    loud.advance_to(2.0)
    assert np.array_equal(loud.positions, quiet.positions)
    events = loud.take_events()
    assert len(events["time"]) > 0 and events["time"].min() > 1.0


def test_set_velocities_restarts_at_another_temperature():
    sim = ss.Simulation.periodic_gas(300, 0.2, seed=2)
    sim.advance_to(1.0)
    e = sim.kinetic_energy()
    sim.set_velocities(2 * sim.velocities)
    assert sim.kinetic_energy() == 4 * e  # doubling is exact in floating point
    sim.advance_to(2.0)
    # Elastic: the new energy is kept from there on.
    assert sim.kinetic_energy() == pytest.approx(4 * e, rel=drift_bound(sim.stats["collisions"]))
    # At rest, nothing moves.
    sim.set_velocities(np.zeros((300, 3)))
    before = sim.positions
    sim.advance_to(3.0)
    assert np.array_equal(sim.positions, before)
    with pytest.raises(ValueError, match=r"velocities: 2 rows, expected 300"):
        sim.set_velocities(np.zeros((2, 3)))
    bad = np.zeros((300, 3))
    bad[7, 1] = np.nan
    with pytest.raises(ValueError, match="sphere 7"):
        sim.set_velocities(bad)
    with pytest.raises(TypeError, match="velocities"):
        sim.set_velocities("fast")


def test_images_and_unwrapped_positions_follow_a_free_flight():
    # Two spheres far apart in a periodic box of 10, flying without a collision: the unwrapped
    # centre is start + v t, and the images count the faces crossed.
    start = np.array([[1.0, 1.0, 1.0], [6.0, 6.0, 6.0]])
    v = np.array([[3.0, 0.0, 0.0], [0.0, -2.0, 0.0]])
    sim = ss.Simulation.from_spheres(start, v, [0.5, 0.5], periodic_box=[10, 10, 10])
    sim.advance_to(7.0)
    assert sim.stats["pair_collisions"] == 0
    assert sim.images().tolist() == [[2, 0, 0], [0, -1, 0]]
    assert np.allclose(sim.unwrapped_positions(), start + 7.0 * v, atol=1e-12)
    assert (sim.positions >= 0).all() and (sim.positions <= 10).all()
    # Centres given outside the box are wrapped in, and counted from where they were given.
    away = start + np.array([[-20.0, 30.0, 0.0], [0.0, 10.0, -10.0]])
    outside = ss.Simulation.from_spheres(away, v, [0.5, 0.5], periodic_box=[10, 10, 10])
    assert outside.images().tolist() == [[-2, 3, 0], [0, 1, -1]]
    outside.advance_to(7.0)
    assert np.allclose(outside.unwrapped_positions(), away + 7.0 * v, atol=1e-12)
    assert np.allclose(outside.positions, sim.positions, atol=1e-12)
    # In open space the images are zero and nothing is unwrapped.
    free = ss.Simulation.from_spheres(start, v, [0.5, 0.5])
    free.advance_to(7.0)
    assert free.images().tolist() == [[0, 0, 0]] * 2 and free.box is None
    assert np.array_equal(free.unwrapped_positions(), free.positions)


def test_spheres_that_fly_apart_finish_at_once_and_say_when():
    # Two spheres receding in open space: after a few dozen shell events nothing can happen
    # any more; advancing to 1e20 is then immediate, and the centres are on their lines.
    start = np.array([[0.0, 0.0, 0.0], [3.0, 0.0, 0.0]])
    v = np.array([[-1.0, 0.5, 0.0], [1.0, 0.0, -0.25]])
    sim = ss.Simulation.from_spheres(start, v, [0.5, 0.5])
    assert sim.flown_apart is None
    sim.advance_to(1e20)
    assert sim.flown_apart == 0.0  # nothing ever happened
    assert np.allclose(sim.positions, start + 1e20 * v, rtol=1e-15, atol=0)
    with pytest.raises(ValueError, match=r"the run can go on to t = 1.2676506002282\d*e30"):
        sim.advance_to(1e300)
    assert sim.time == 1e20
    # New velocities wake it (turned towards each other, they would meet again).
    sim.set_velocities(-v)
    assert sim.flown_apart is None
    # Refused on the way (parked during the advance): left at the last event processed,
    # before its reach, from where the time the message names can be reached.
    fresh = ss.Simulation.from_spheres(start, v, [0.5, 0.5])
    with pytest.raises(ValueError, match=r"the run can go on to t = (\S+)") as refused:
        fresh.advance_to(1e300)
    reach = float(re.search(r"go on to t = (\S+)", str(refused.value)).group(1))
    assert 0 < fresh.time < 1e3 and fresh.flown_apart == 0.0
    fresh.advance_to(reach)
    assert fresh.time == reach


def test_spheres_far_from_the_origin_are_warned_of(tmp_path):
    # At 1e12 a coordinate rounds by 2^-13, past the contact tolerance 2^-16 of a diameter 1:
    # a RuntimeWarning names the first sphere (the array's row, or the scene file's line), and the
    # build goes on; at the origin there is none.
    far = np.array([[1e12, 0.3, 0.0], [1e12 + 3.0, 0.0, 0.0]])
    v = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    with pytest.warns(RuntimeWarning, match=r"centres\[0\]: its coordinate 1e12 rounds.*\(and 1 other sphere\)"):
        sim = ss.Simulation.from_spheres(far, v, [0.5, 0.5])
    sim.advance_to(2.0)
    # Unpickled (on a worker, say), it does not warn again.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        back = pickle.loads(pickle.dumps(sim))
    assert np.array_equal(back.positions, sim.positions)
    scene = tmp_path / "far.toml"
    scene.write_text(
        "[run]\nt_end = 2\n\n[[sphere]]\ncentre = [1e12, 0.3, 0]\nradius = 0.5\n\n"
        "[[sphere]]\ncentre = [1.000000000003e12, 0, 0]\nradius = 0.5\n"
    )
    with pytest.warns(RuntimeWarning, match=r"far.toml:4: sphere 0: its coordinate"):
        ss.Simulation.from_scene_file(str(scene))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ss.Simulation.from_spheres(far - [1e12, 0.0, 0.0], v, [0.5, 0.5])
