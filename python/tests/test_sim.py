"""The event-driven simulation through Python: the constructors agree with each other, energy
and momentum are conserved in elastic worlds, single collisions follow their closed forms,
events come out as arrays, errors are named, and the GIL is released while it runs."""

import math
import pathlib
import threading
import time

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
    # Elastic collisions in f64: each changes the energy by a few ulps of the pair's energy,
    # so after ~10^4 collisions the relative drift is far below 1e-9 (the bound the Rust
    # module doctest uses for the same kind of gas).
    assert abs(sim.kinetic_energy() - e0) < 1e-9 * e0
    # Momentum: each collision conserves the pair's to rounding (~1e-16 of the pair's |p|).
    scale = math.sqrt(2 * e0 * len(sim))
    assert np.abs(np.array(sim.momentum()) - p0).max() < 1e-9 * scale
    # Positions stay in the periodic box [0, L).
    side = (1000 * 4 / 3 * math.pi * 0.5**3 / 0.3) ** (1 / 3)
    pos = sim.positions
    assert (pos >= 0).all() and (pos < side * (1 + 1e-12)).all()


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
    assert ev["point"][0] == pytest.approx([5.0, 0, 0])
    assert abs(ev["normal"][0][0]) == pytest.approx(1.0)
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
    assert np.isnan(ev["point"]).all()


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
    assert abs(sim.kinetic_energy() - e0) < 1e-9 * e0
    assert (np.linalg.norm(sim.positions, axis=1) <= 20.0 - 0.4 + 1e-9).all()


def test_simulation_errors():
    sim = ss.Simulation.periodic_gas(100, 0.1)
    sim.advance_to(1.0)
    with pytest.raises(ValueError, match="cannot advance to t = 0.5: the simulation is at t = 1"):
        sim.advance_to(0.5)
    with pytest.raises(ValueError, match="cannot advance to t = NaN"):
        sim.advance_to(math.nan)
    with pytest.raises(ValueError, match="packing fraction 0.9 must be in"):
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
    # While one thread advances a simulation for about a second, this thread must keep
    # running: with the GIL held, its longest pause would be the whole call.
    sim = ss.Simulation.periodic_gas(4000, 0.25, seed=9)
    started = time.perf_counter()
    sim.advance_to(0.5)
    per_unit = (time.perf_counter() - started) / 0.5
    t_run = max(0.6 / per_unit, 1.0)  # enough simulated time for ~0.6 s of work
    done = threading.Event()

    def run():
        sim.advance_to(0.5 + t_run)
        done.set()

    worker = threading.Thread(target=run)
    t0 = time.perf_counter()
    worker.start()
    last, longest = t0, 0.0
    while not done.is_set():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
    worker.join()
    duration = time.perf_counter() - t0
    assert duration > 0.3, "the run was too short to tell"
    assert longest < 0.5 * duration, (longest, duration)


def test_from_spheres_in_a_periodic_box_matches_periodic_gas():
    # The spheres of a periodic gas handed back through from_spheres with the same box: the
    # same world, so the same run.
    gas = ss.Simulation.periodic_gas(500, 0.2, seed=6)
    # The generator's box: the volume n (4/3) pi r^3 / phi in its order of operations, cbrt.
    side = float(np.cbrt(500 * 4.0 / 3.0 * math.pi * 0.5**3 / 0.2))
    again = ss.Simulation.from_spheres(gas.positions, gas.velocities, gas.radii, gas.masses,
                                       periodic_box=[side] * 3)
    assert again.engine == gas.engine
    gas.advance_to(2.0)
    again.advance_to(2.0)
    assert gas.stats == again.stats
    assert np.array_equal(gas.positions, again.positions)
    with pytest.raises(ValueError, match="periodic box x"):
        ss.Simulation.from_spheres(gas.positions, gas.velocities, gas.radii, periodic_box=[1.0, side, side])
