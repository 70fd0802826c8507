"""Results as tables (pandas), Spheres as a sequence (len, indexing, masks, ==), and pickling
of contacts and of simulations."""

import pickle

import numpy as np
import pytest

import spheresweep as ss

pd = pytest.importorskip("pandas")


def scene(n=200, seed=4):
    rng = np.random.default_rng(seed)
    s = ss.Spheres(rng.uniform(-8, 8, (n, 3)), rng.uniform(-2, 2, (n, 3)), rng.uniform(0.2, 0.8, n))
    return ss.Scene(s, planes=[ss.Plane([0, 0, -9], [0, 0, 1])])


def test_events_are_a_table_one_row_per_event():
    sim = ss.Simulation.periodic_gas(500, 0.3, seed=2, record_events=True)
    sim.advance_to(1.0)
    events = sim.take_events()
    frame = pd.DataFrame(events)
    k = len(events["time"])
    assert k > 100 and frame.shape == (k, 13)
    assert list(frame.columns) == ["time", "sphere", "kind", "index", "approach", "restitution",
                                   "energy_lost", "point_x", "point_y", "point_z", "normal_x",
                                   "normal_y", "normal_z"]
    assert (frame["kind"] == ss.KIND_SPHERE).all() and frame["time"].is_monotonic_increasing


def test_contacts_to_pandas_and_as_dict():
    found = ss.all_contacts(scene(), t_max=2.0, geometry=True)
    frame = found.to_pandas()
    assert len(frame) == len(found) > 10
    assert np.array_equal(frame["point_y"].to_numpy(), found.point[:, 1])
    assert np.array_equal(frame["sphere"].to_numpy(), found.sphere)
    first = ss.first_contacts(scene(), t_max=2.0)
    d = first.as_dict()
    assert list(d) == ["time", "kind", "index"] and len(first.to_pandas()) == 200


def test_contacts_pickle():
    for found in (ss.all_contacts(scene(), t_max=2.0, geometry=True),
                  ss.first_contacts(scene(), t_max=2.0)):
        back = pickle.loads(pickle.dumps(found))
        assert type(back) is type(found) and len(back) == len(found)
        for name, column in found.as_dict().items():
            assert np.array_equal(back.as_dict()[name], column, equal_nan=True)


def test_spheres_len_indexing_masks_and_equality():
    s = scene().spheres
    assert len(s) == 200
    assert s[3].centres.tolist() == [s.centres[3].tolist()]
    assert s[-1] == s[199:]
    assert s[10:20] == ss.Spheres(s.centres[10:20], s.velocities[10:20], s.radii[10:20],
                                  s.masses[10:20])
    fast = np.linalg.norm(s.velocities, axis=1) > 2
    picked = s[fast]
    assert len(picked) == fast.sum() and np.array_equal(picked.radii, s.radii[fast])
    assert s[[5, 2]].radii.tolist() == [s.radii[5], s.radii[2]]
    assert s == scene().spheres and s != s[1:] and s != "spheres"
    with pytest.raises(IndexError):
        s[200]
    with pytest.raises(IndexError):
        s[np.ones(3, bool)]


@pytest.mark.parametrize("build", [
    lambda: ss.Simulation.periodic_gas(300, 0.3, seed=5, record_events=True),
    lambda: ss.Simulation.from_spheres([[0, 0, 3], [3, 0, 3]], [[1, 0, -1], [-1, 0, 0]], [1.0, 1.0],
                                       planes=[(ss.Plane([0, 0, 0], [0, 0, 1]), 1)],
                                       pairs=[(0, 1, 0.5)], restitution=0.9),
])
def test_a_pickled_simulation_goes_on_as_the_original(build):
    sim = build()
    sim.advance_to(1.0)
    back = pickle.loads(pickle.dumps(sim))
    assert back.time == 1.0 and back.engine == sim.engine
    # The events recorded and not yet taken travel with it (the gas has hundreds by now).
    ours, theirs = sim.take_events(), back.take_events()
    assert ours.keys() == theirs.keys()
    assert all(np.array_equal(ours[k], theirs[k], equal_nan=True) for k in ours)
    sim.advance_to(3.0)
    back.advance_to(3.0)
    assert np.array_equal(back.positions, sim.positions) and back.stats == sim.stats


def test_a_scene_file_simulation_pickles(tmp_path):
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    sim = ss.Simulation.from_scene_file(str(root / "scenes" / "hard_sphere_gas.toml"))
    sim.advance_to(0.2)
    back = pickle.loads(pickle.dumps(sim))
    assert back.t_end == sim.t_end and np.array_equal(back.positions, sim.positions)
