"""Every public function and constructor, every argument given a value of the wrong type or
out of range: the error names the argument and what it expects (docs/python.md, "Errors"),
as `name: expected ..., got ...`. Also the conversions the docs promise: strings, booleans and
masked arrays refused, empty lists accepted, shapes of the wrong kind refused per argument."""

import math

import numpy as np
import pytest

import spheresweep as ss

ONE = ss.Spheres([[0, 0, 0]], [[0, 0, 0]], [1.0])
TWO = ss.Spheres([[0, 0, 0], [5, 0, 0]], [[1, 0, 0], [0, 0, 0]], [1.0, 1.0])
FLOOR = ss.Plane([0, 0, -5], [0, 0, 1])
PILLAR = ss.Cylinder([9, 0, 0], [9, 0, 1], 1.0)
VESSEL = ss.Container([0, 0, 0], 50.0)
SCENE = ss.Scene(TWO, planes=[FLOOR])
GAS = dict(n=10, phi=0.1)
ARRAYS = dict(centres=[[0, 0, 0]], velocities=[[0, 0, 0]], radii=[1.0])


def sim():
    return ss.Simulation.from_spheres(**ARRAYS)


# (what is called, argument, bad value, exception, message start)
CASES = [
    (lambda **k: ss.zip_times(**{"a": ONE, "b": ONE, **k}), "a", np.zeros(3), TypeError, "a: expected a Spheres, got a 1-D float64 ndarray"),
    (lambda **k: ss.zip_times(**{"a": ONE, "b": ONE, **k}), "b", [1, 2], TypeError, "b: expected a Spheres, got list"),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "t_max", "3", TypeError, "t_max: expected a real number, got str"),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "t_max", True, TypeError, "t_max: expected a real number, got bool"),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "t_max", -1.0, ValueError, "t_max must be zero or more"),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "accuracy", 3, TypeError, 'accuracy: expected one of "textbook", "stable", "double", got int'),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "accuracy", "exact", ValueError, 'accuracy: unknown accuracy mode "exact"'),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "out", [0.0], TypeError, "out: expected a 1-D float32 numpy array, got list"),
    (lambda **k: ss.zip_times(ONE, ONE, **k), "out", np.empty(1, np.float64), TypeError, "out: expected a 1-D float32 numpy array, got a 1-D float64 ndarray"),
    (lambda **k: ss.pair_times(**{"s": TWO, "i": [0], "j": [1], **k}), "s", "spheres", TypeError, "s: expected a Spheres, got str"),
    (lambda **k: ss.pair_times(**{"s": TWO, "i": [0], "j": [1], **k}), "i", [0.5], TypeError, "i: dtype float64 is not an integer type"),
    (lambda **k: ss.pair_times(**{"s": TWO, "i": [0], "j": [1], **k}), "j", [True], TypeError, "j: dtype bool is not an integer type"),
    (lambda **k: ss.pair_times(**{"s": TWO, "i": [0], "j": [1], **k}), "i", np.array([2**63], np.uint64), ValueError, "i[0]: index 9223372036854775808 is not in 0..=4294967295"),
    (lambda **k: ss.pair_times(**{"s": TWO, "i": [0], "j": [1], **k}), "j", np.array([-1], np.int8), ValueError, "j[0]: index -1 is not in 0..=4294967295"),
    (lambda **k: ss.pair_times(TWO, [0], [1], **k), "t_max", "x", TypeError, "t_max: expected a real number"),
    (lambda **k: ss.static_times(**{"s": TWO, "shapes": [FLOOR], **k}), "s", 1, TypeError, "s: expected a Spheres, got int"),
    (lambda **k: ss.static_times(**{"s": TWO, "shapes": [FLOOR], **k}), "shapes", 5, TypeError, "shapes: expected a sequence of shapes, got int"),
    (lambda **k: ss.static_times(TWO, [FLOOR], **k), "accuracy", b"stable", TypeError, "accuracy: expected one of"),
    (lambda **k: ss.Scene(**{"spheres": TWO, **k}), "spheres", np.zeros((2, 3)), TypeError, "spheres: expected a Spheres, got a 2-D float64 ndarray"),
    (lambda **k: ss.Scene(TWO, **k), "planes", [PILLAR], TypeError, "planes[0]: expected a Plane, got Cylinder"),
    (lambda **k: ss.Scene(TWO, **k), "cylinders", [FLOOR], TypeError, "cylinders[0]: expected a Cylinder, got Plane"),
    (lambda **k: ss.Scene(TWO, **k), "containers", 3, TypeError, "containers: expected a sequence of shapes, got int"),
    (lambda **k: ss.first_contacts(**{"scene": SCENE, **k}), "scene", TWO, TypeError, "scene: expected a Scene, got Spheres"),
    (lambda **k: ss.first_contacts(SCENE, **k), "geometry", 1, TypeError, "geometry: expected True or False, got int"),
    (lambda **k: ss.first_contacts(SCENE, **k), "t_max", [1.0], TypeError, "t_max: expected a real number, got list"),
    (lambda **k: ss.all_contacts(**{"scene": SCENE, "t_max": 1.0, **k}), "scene", None, TypeError, "scene: expected a Scene, got NoneType"),
    (lambda **k: ss.all_contacts(**{"scene": SCENE, "t_max": 1.0, **k}), "t_max", None, TypeError, "t_max: expected a real number, got NoneType"),
    (lambda **k: ss.all_contacts(SCENE, t_max=1.0, **k), "geometry", "yes", TypeError, "geometry: expected True or False, got str"),
    (lambda **k: ss.Plane(**{"point": [0, 0, 0], "normal": [0, 0, 1], **k}), "point", ["a", "b", "c"], TypeError, "point: dtype <U1 is not a real number type"),
    (lambda **k: ss.Plane(**{"point": [0, 0, 0], "normal": [0, 0, 1], **k}), "normal", [True, False, False], TypeError, "normal: dtype bool is not a real number type"),
    (lambda **k: ss.Cylinder(**{"p1": [0, 0, 0], "p2": [0, 0, 1], "radius": 1.0, **k}), "radius", "1", TypeError, "radius: expected a real number, got str"),
    (lambda **k: ss.Cylinder(**{"p1": [0, 0, 0], "p2": [0, 0, 1], "radius": 1.0, **k}), "p2", [0, 0], ValueError, "p2: expected shape (3,), got (2,)"),
    (lambda **k: ss.Container(**{"centre": [0, 0, 0], "radius": 1.0, **k}), "radius", True, TypeError, "radius: expected a real number, got bool"),
    (lambda **k: ss.Container(**{"centre": [0, 0, 0], "radius": 1.0, **k}), "centre", "origin", TypeError, "centre: dtype <U6 is not a real number type"),
    (lambda **k: ss.Spheres(**{**ARRAYS, **k}), "centres", [["1", "2", "3"]], TypeError, "centres: dtype <U1 is not a real number type"),
    (lambda **k: ss.Spheres(**{**ARRAYS, **k}), "radii", [True], TypeError, "radii: dtype bool is not a real number type"),
    (lambda **k: ss.Spheres(**{**ARRAYS, **k}), "masses", np.ma.masked_array([1.0], mask=[True]), TypeError, "masses: a masked array"),
    (lambda **k: ss.Spheres.from_columns(**{**dict(zip(["x", "y", "z", "vx", "vy", "vz", "r"], [[0.0]] * 6 + [[1.0]])), **k}), "vy", ["0"], TypeError, "vy: dtype <U1"),
    (lambda **k: ss.Simulation.periodic_gas(**{**GAS, **k}), "n", -1, ValueError, "n: -1 is not a count >= 0"),
    (lambda **k: ss.Simulation.periodic_gas(**{**GAS, **k}), "n", 10.0, TypeError, "n: expected an integer, got float"),
    (lambda **k: ss.Simulation.periodic_gas(**{**GAS, **k}), "phi", "0.1", TypeError, "phi: expected a real number, got str"),
    (lambda **k: ss.Simulation.periodic_gas(**GAS, **k), "seed", -1, ValueError, "seed: -1 is not in 0..=18446744073709551615"),
    (lambda **k: ss.Simulation.periodic_gas(**GAS, **k), "kT", "hot", TypeError, "kT: expected a real number, got str"),
    (lambda **k: ss.Simulation.periodic_gas(**GAS, **k), "radius", [0.5], TypeError, "radius: expected a real number, got list"),
    (lambda **k: ss.Simulation.periodic_gas(**GAS, **k), "record_events", 1, TypeError, "record_events: expected True or False, got int"),
    (lambda **k: ss.Simulation.from_spheres(**{**ARRAYS, **k}), "velocities", np.zeros((1, 3), complex), TypeError, "velocities: dtype complex128 is not a real number type"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "planes", [PILLAR], TypeError, "planes[0]: expected a Plane, got Cylinder"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "containers", [FLOOR], TypeError, "containers[0]: expected a Container, got Plane"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "cylinders", [(VESSEL, 1)], TypeError, "cylinders[0]: expected a Cylinder, got Container"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "periodic_box", "big", TypeError, "periodic_box: dtype <U3 is not a real number type"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "restitution", "0.5", TypeError, "restitution: expected a real number, got str"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "response", 1, TypeError, "response: expected a string, got int"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "tc", "0", TypeError, "tc: expected a real number, got str"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "materials", [True], TypeError, "materials[0]: a material is an integer, got bool"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "pairs", 3, TypeError, "pairs: expected a sequence of (a, b, response), got int"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "record_events", "no", TypeError, "record_events: expected True or False, got str"),
    (lambda **k: ss.Simulation.from_spheres(**ARRAYS, **k), "geometry", 0, TypeError, "geometry: expected True or False, got int"),
    (lambda **k: sim().advance_to(**{"t": 1.0, **k}), "t", "1", TypeError, "t: expected a real number, got str"),
    (lambda **k: sim().advance_to(**{"t": 1.0, **k}), "t", math.inf, ValueError, "t: cannot advance to t = inf: the end time must be finite"),
    (lambda **k: sim().advance_to(1.0, **k), "progress", 5, TypeError, "progress: expected a callable, got int"),
    (lambda **k: sim().advance_to(1.0, **k), "check", 1, TypeError, "check: expected True or False, got int"),
    (lambda **k: sim().restore(**{"data": b"", **k}), "data", "checkpoint", TypeError, "data: expected bytes, got str"),
    (lambda **k: sim().set_velocities(**{"velocities": [[0, 0, 0]], **k}), "velocities", [["a", "b", "c"]], TypeError, "velocities: dtype <U1 is not a real number type"),
    (lambda **k: sim().set_velocities(**{"velocities": [[0, 0, 0]], **k}), "velocities", [[0, 0]], ValueError, "velocities: expected shape (N, 3), got (1, 2)"),
]


@pytest.mark.parametrize("call, name, bad, error, message", CASES, ids=[f"{i}-{c[1]}" for i, c in enumerate(CASES)])
def test_each_argument_error_names_the_argument(call, name, bad, error, message):
    with pytest.raises(error) as caught:
        call(**{name: bad})
    assert str(caught.value).startswith(message), str(caught.value)


def test_every_public_callable_has_a_case():
    # Every function and constructor the package exports, and every Simulation method taking
    # arguments, appears in CASES (a new one without a case fails here).
    import inspect

    covered = set()
    for call, *_ in CASES:
        covered |= set(call.__code__.co_names)
    public = {n for n in ss.__all__ if callable(getattr(ss, n)) and not n.startswith("_")}
    # Built or raised by the library, not by hand.
    results = {"FirstContacts", "Contacts", "Simulation", "InvariantError"}
    missing = public - covered - results - {"read_xyz"}
    assert not missing, missing
    for method in ("periodic_gas", "from_spheres", "advance_to", "restore", "set_velocities"):
        assert method in covered
    assert inspect.signature(ss.zip_times).parameters["t_max"].default == math.inf


def test_a_read_only_out_is_named():
    out = np.zeros(2, np.float32)
    out.setflags(write=False)
    with pytest.raises(ValueError, match="^out: the array is read-only"):
        ss.zip_times(TWO, TWO, out=out)


def test_none_means_the_default():
    a, b = ss.zip_times(TWO, TWO, t_max=None, accuracy=None), ss.zip_times(TWO, TWO)
    assert np.array_equal(a, b)


def test_empty_lists_are_empty_arrays():
    assert ss.pair_times(TWO, [], []).shape == (0,)
    empty = ss.Spheres([], [], [])
    assert len(empty) == 0 and empty.centres.shape == (0, 3)


def test_pandas_columns_are_read_and_string_columns_refused():
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame({"x": [0.0, 5.0], "r": [1.0, 1.0], "name": ["a", "b"]})
    zeros = pd.Series([0.0, 0.0])
    s = ss.Spheres.from_columns(frame["x"], zeros, zeros, zeros, zeros, zeros, frame["r"])
    assert s.centres[:, 0].tolist() == [0.0, 5.0]
    with pytest.raises(TypeError, match="r: dtype object is not a real number type"):
        ss.Spheres.from_columns(frame["x"], zeros, zeros, zeros, zeros, zeros, frame["name"])


def test_help_shows_the_defaults():
    import inspect

    sig = inspect.signature(ss.first_contacts)
    assert str(sig) == "(scene, *, t_max=inf, accuracy='stable', geometry=False)"
    assert "Ellipsis" not in str(inspect.signature(ss.zip_times))


def test_reprs_show_tuples():
    assert repr(PILLAR) == "Cylinder(p1=(9.0, 0.0, 0.0), p2=(9.0, 0.0, 1.0), radius=1.0)"
    assert repr(FLOOR) == "Plane(point=(0.0, 0.0, -5.0), normal=(0.0, 0.0, 1.0))"


def test_times_print_briefly():
    s = ss.Simulation.from_spheres(**ARRAYS)
    s.advance_to(1e300)
    assert repr(s).startswith("Simulation(<1 spheres, t = 1e300,")
    with pytest.raises(ValueError, match=r"^t: cannot advance to t = 1\.0: the simulation is at t = 1e300"):
        s.advance_to(1.0)
