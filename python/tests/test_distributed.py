"""spheresweep.distributed on a two-worker LocalCluster: the sharded Parquet queries and the
slab-partitioned scene query give the single-process answers bit for bit, on data built so
that partitions matter (many row groups; many contact pairs straddling slab borders), and a
halo narrower than the derived width loses contacts."""

import math
import os
import warnings

import numpy as np
import pytest

pd = pytest.importorskip("pandas")
pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")
distributed = pytest.importorskip("distributed")

import spheresweep as ss  # noqa: E402
from spheresweep import distributed as sd  # noqa: E402

ACCURACIES = ("textbook", "stable", "double")


@pytest.fixture(scope="module")
def client():
    """Two worker processes with one thread each on 127.0.0.1 (threads if processes fail)."""
    try:
        cluster = distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            host="127.0.0.1",
            processes=True,
            dashboard_address=":0",
        )
    except Exception as e:  # pragma: no cover - only where processes cannot start
        warnings.warn(f"LocalCluster with processes failed ({e}); using threads")
        cluster = distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            host="127.0.0.1",
            processes=False,
            dashboard_address=":0",
        )
    with cluster, distributed.Client(cluster) as c:
        yield c


def bits(a):
    """The float32 bit patterns, so that equality is bit equality (-0.0 != 0.0)."""
    return np.ascontiguousarray(a, dtype=np.float32).view(np.uint32)


# ---------------------------------------------------------------------------------------------
# Sharded Parquet queries


def random_pairs(rng, n):
    """Pairs in a cube of side 8 with speeds up to ~1.7 and radii 0.1-1: a good share touch
    within t_max = 3, many not at all."""
    cols = {}
    for side in "ab":
        for f in ("x", "y", "z"):
            cols[f"{side}{f}"] = rng.uniform(-4, 4, n)
        for f in ("vx", "vy", "vz"):
            cols[f"{side}{f}"] = rng.uniform(-1, 1, n)
        cols[f"{side}r"] = rng.uniform(0.1, 1.0, n)
    # Exactly touching and overlapping pairs among them (time 0 cases).
    cols["bx"][:50] = cols["ax"][:50]
    cols["by"][:50] = cols["ay"][:50]
    cols["bz"][:50] = cols["az"][:50] + 0.5
    return {c: cols[c] for c in sd.PAIR_COLUMNS}


def write_dataset(directory, table, files, row_group_size):
    os.makedirs(directory)
    n = table.num_rows
    step = math.ceil(n / files)
    for k in range(files):
        pq.write_table(
            table.slice(k * step, step),
            os.path.join(directory, f"part.{k:03d}.parquet"),
            row_group_size=row_group_size,
            compression="snappy",
        )


@pytest.mark.parametrize("accuracy", ACCURACIES)
def test_sharded_pairs_match_one_process(client, tmp_path, accuracy):
    rng = np.random.default_rng(17)
    n = 30_000
    cols = random_pairs(rng, n)  # float64: rounded to float32 the same way in both runs
    table = pa.table({**cols, "id": np.arange(n, dtype=np.int64)})
    source = tmp_path / "pairs"
    write_dataset(source, table, files=3, row_group_size=2_500)
    out = tmp_path / "pairs-toi"

    summary = sd.zip_times_parquet(
        source, out, t_max=3.0, accuracy=accuracy, client=client, split_row_groups=True
    )

    assert summary.partitions == 12  # one task per row group: partitioning is exercised
    assert sorted(os.listdir(out)) == [f"part.{k:06d}.parquet" for k in range(12)]
    got = pd.read_parquet(out)
    a = ss.Spheres.from_columns(*[cols[c] for c in sd.PAIR_COLUMNS[:7]])
    b = ss.Spheres.from_columns(*[cols[c] for c in sd.PAIR_COLUMNS[7:]])
    expected = ss.zip_times(a, b, t_max=3.0, accuracy=accuracy)
    assert list(got.columns) == [*sd.PAIR_COLUMNS, "id", "time"]
    assert got["time"].dtype == np.float32
    np.testing.assert_array_equal(got["id"].to_numpy(), np.arange(n))
    np.testing.assert_array_equal(bits(got["time"]), bits(expected))
    for c in sd.PAIR_COLUMNS:  # the inputs carried through unchanged
        np.testing.assert_array_equal(got[c].to_numpy(), cols[c])
    finite = np.isfinite(expected)
    assert 0 < finite.sum() < n and (expected == 0).sum() >= 50
    assert summary.rows == n and summary.contacts == finite.sum()
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".")]  # no staging left


def test_sharded_pairs_errors_name_the_problem(client, tmp_path):
    rng = np.random.default_rng(3)
    cols = random_pairs(rng, 100)
    source = tmp_path / "pairs"
    write_dataset(source, pa.table({k: v for k, v in cols.items() if k != "bvy"}), 1, 100)
    with pytest.raises(ValueError, match="no column bvy"):
        sd.zip_times_parquet(source, tmp_path / "out", client=client)

    bad = dict(cols)
    bad["ar"] = bad["ar"].copy()
    bad["ar"][7] = -1.0
    write_dataset(tmp_path / "bad", pa.table(bad), 1, 100)
    with pytest.raises(ValueError, match="partition 0.*sphere A.*sphere 7"):
        sd.zip_times_parquet(tmp_path / "bad", tmp_path / "out", client=client)
    assert not os.path.exists(tmp_path / "out")

    # A finite float64 beyond float32's range is named by its column and row, not as "NaN or
    # infinite" after a conversion made it inf.
    far = dict(cols)
    far["bx"] = far["bx"].copy()
    far["bx"][9] = 1e300
    write_dataset(tmp_path / "far", pa.table(far), 1, 100)
    with pytest.raises(ValueError, match=r"partition 0.*sphere B.*x\[9\]: 1e300 is beyond float32"):
        sd.zip_times_parquet(tmp_path / "far", tmp_path / "out", client=client)
    assert not os.path.exists(tmp_path / "out")

    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "notes.txt").write_text("mine")
    good = tmp_path / "good"
    write_dataset(good, pa.table(cols), 1, 100)
    with pytest.raises(FileExistsError):
        sd.zip_times_parquet(good, tmp_path / "taken", client=client)
    with pytest.raises(ValueError, match="notes.txt"):
        sd.zip_times_parquet(good, tmp_path / "taken", client=client, overwrite=True)
    assert (tmp_path / "taken" / "notes.txt").read_text() == "mine"


def test_sharded_spheres_against_shapes_match_the_scene_query(client, tmp_path):
    # Spheres on a 10 x 10 lattice of spacing 10 (radii <= 1, sideways drift < 1 within
    # t_max): they never touch each other, so the scene query's first contacts are exactly
    # their first contacts with the shapes, with the library's tie rule.
    rng = np.random.default_rng(5)
    side = 40
    n = side * side
    gx, gy = np.meshgrid(np.arange(side) * 10.0, np.arange(side) * 10.0)
    x, y = gx.ravel(), gy.ravel()
    z = rng.uniform(1.5, 6.0, n)
    vx, vy = rng.uniform(-0.2, 0.2, n), rng.uniform(-0.2, 0.2, n)
    vz = rng.uniform(-2.0, 2.0, n)
    r = rng.uniform(0.2, 1.0, n)
    shapes = [
        ss.Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),  # the floor
        ss.Cylinder([0.0, 200.0, 0.0], [400.0, 200.0, 0.0], 3.0),  # along x at y = 200
        ss.Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),  # the floor again: ties to plane 0
        ss.Plane([0.0, 0.0, 9.0], [0.0, 0.3, -1.0]),  # a tilted ceiling
        ss.Container([200.0, 200.0, 0.0], 280.0),
    ]
    cols = dict(x=x, y=y, z=z, vx=vx, vy=vy, vz=vz, r=r)
    source = tmp_path / "spheres"
    write_dataset(source, pa.table({k: v.astype(np.float32) for k, v in cols.items()}), 2, 300)

    summary = sd.static_contacts_parquet(
        source, tmp_path / "hits", shapes, t_max=4.0, client=client, split_row_groups=True
    )

    got = pd.read_parquet(tmp_path / "hits")
    assert summary.partitions == 6
    spheres = ss.Spheres.from_columns(*[cols[c] for c in sd.SPHERE_COLUMNS])
    planes = [s for s in shapes if isinstance(s, ss.Plane)]
    cylinders = [s for s in shapes if isinstance(s, ss.Cylinder)]
    containers = [s for s in shapes if isinstance(s, ss.Container)]
    scene = ss.Scene(spheres, planes, cylinders, containers)
    first = ss.first_contacts(scene, t_max=4.0)
    scene_kind = np.asarray(first.kind)
    assert not (scene_kind == ss.KIND_SPHERE).any()  # no sphere touches a sphere: the reference holds
    # The same codes for the shapes; "none" is 0 in the query files.
    file_kind = np.where(scene_kind == ss.KIND_NONE, 0, scene_kind)
    np.testing.assert_array_equal(bits(got["time"]), bits(first.time))
    np.testing.assert_array_equal(got["kind"].to_numpy(), file_kind)
    np.testing.assert_array_equal(got["index"].to_numpy(), first.index)
    kinds = set(got["kind"].tolist())
    assert {0, 1, 2, 3} <= kinds  # every kind and no contact all occur


# ---------------------------------------------------------------------------------------------
# The scene partitioned in slabs


def crowded_scene(seed=11, n=10_000):
    """Spheres in a 128 x 16 x 16 box (speeds up to ~1.7, radii 0.2-0.5) with a floor, a tilted
    wall, a pillar and a container: with t_max = 1 many contact pairs straddle slab borders.

    Before them come head-on pairs that make the derived halo tight: the fastest spheres
    (radius 0.5, speed 1.73, so the halo is 2 (0.5 + 1.73 t_max)), the lower index just left of
    a border of the 4- and 8-slab plans (x = 32, 64, 96 give or take a few spacings), its
    partner almost a halo width to the right: they touch just before t_max, and only a slab
    whose halo reaches that far finds them.
    """
    rng = np.random.default_rng(seed)
    centres = rng.uniform([0, 0, 0], [128, 16, 16], (n, 3))
    velocities = rng.uniform(-1, 1, (n, 3))
    radii = rng.uniform(0.2, 0.5, n)
    speed, radius, t_max = 1.73, 0.5, 1.0
    gap = 2 * (radius + speed * t_max) - 0.01  # centres' distance: touch at t = 0.997
    tight_c, tight_v = [], []
    for border in np.quantile(centres[:, 0], [0.25, 0.5, 0.75]):
        for _ in range(8):
            y, z = rng.uniform(1, 15, 2)
            left = border - 0.2
            tight_c += [[left, y, z], [left + gap, y, z]]
            tight_v += [[speed, 0, 0], [-speed, 0, 0]]
    centres = np.concatenate([tight_c, centres])
    velocities = np.concatenate([tight_v, velocities])
    radii = np.concatenate([np.full(len(tight_c), radius), radii])
    shapes = dict(
        planes=[
            ss.Plane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
            ss.Plane([0.0, 16.0, 0.0], [0.2, -1.0, 0.1]),
        ],
        cylinders=[ss.Cylinder([40.0, 8.0, 0.0], [40.0, 8.0, 1.0], 1.5)],
        containers=[ss.Container([64.0, 8.0, 8.0], 65.5)],
    )
    return centres, velocities, radii, shapes


def whole_scene(centres, velocities, radii, shapes):
    return ss.Scene(ss.Spheres(centres, velocities, radii), **shapes)


def straddling_pairs(contacts, plan):
    """Sphere-sphere contacts whose two spheres are owned by different slabs."""
    pairs = np.asarray(contacts.kind) == ss.KIND_SPHERE
    s = np.asarray(contacts.sphere, dtype=np.int64)[pairs]
    o = np.asarray(contacts.index)[pairs]
    return int((plan.owner[s] != plan.owner[o]).sum())


@pytest.mark.parametrize("accuracy", ACCURACIES)
def test_partitioned_all_contacts_match_one_machine(client, accuracy):
    centres, velocities, radii, shapes = crowded_scene()
    t_max = 1.0
    got = sd.all_contacts(
        centres, velocities, radii, **shapes, t_max=t_max, accuracy=accuracy,
        geometry=True, partitions=8, client=client,
    )  # fmt: skip
    expected = ss.all_contacts(
        whole_scene(centres, velocities, radii, shapes), t_max=t_max, accuracy=accuracy,
        geometry=True,
    )  # fmt: skip

    assert got.plan.partitions == 8 and got.plan.axis == 0
    assert straddling_pairs(expected, got.plan) >= 150  # the borders are exercised
    every_kind = {ss.KIND_SPHERE, ss.KIND_PLANE, ss.KIND_CYLINDER, ss.KIND_CONTAINER}
    assert every_kind <= set(np.asarray(expected.kind).tolist())
    np.testing.assert_array_equal(bits(got.time), bits(expected.time))
    np.testing.assert_array_equal(got.sphere, expected.sphere)
    np.testing.assert_array_equal(got.kind, expected.kind)
    np.testing.assert_array_equal(got.index, expected.index)
    np.testing.assert_array_equal(bits(got.point), bits(expected.point))
    np.testing.assert_array_equal(bits(got.normal), bits(expected.normal))


def test_partitioned_first_contacts_match_one_machine(client):
    centres, velocities, radii, shapes = crowded_scene(seed=12)
    t_max = 1.0
    got = sd.first_contacts(
        centres, velocities, radii, **shapes, t_max=t_max, geometry=True, partitions=8,
        client=client,
    )  # fmt: skip
    expected = ss.first_contacts(
        whole_scene(centres, velocities, radii, shapes), t_max=t_max, geometry=True
    )
    kind = np.asarray(expected.kind)
    partner = np.asarray(expected.index)
    sphere_hits = np.nonzero(kind == ss.KIND_SPHERE)[0]
    # Spheres whose first contact is owned by another slab: the halo must provide them.
    assert (got.plan.owner[sphere_hits] != got.plan.owner[partner[sphere_hits]]).sum() >= 150
    np.testing.assert_array_equal(bits(got.time), bits(expected.time))
    np.testing.assert_array_equal(got.kind, kind)
    np.testing.assert_array_equal(got.index, partner)
    np.testing.assert_array_equal(bits(got.point), bits(expected.point))
    np.testing.assert_array_equal(bits(got.normal), bits(expected.normal))


def test_a_halo_below_the_derived_width_loses_contacts(client):
    centres, velocities, radii, shapes = crowded_scene(seed=13)
    t_max = 1.0
    derived = sd.reach_halo(velocities, radii, t_max)
    assert derived == pytest.approx(2 * (0.5 + 1.73 * t_max), rel=1e-6)  # the tight pairs' reach
    full = sd.all_contacts(
        centres, velocities, radii, **shapes, t_max=t_max, partitions=4, client=client
    )
    assert full.plan.halo >= derived  # the default is the derived width, widened
    expected = ss.all_contacts(whole_scene(centres, velocities, radii, shapes), t_max=t_max)
    np.testing.assert_array_equal(full.sphere, expected.sphere)
    np.testing.assert_array_equal(bits(full.time), bits(expected.time))
    full_rows = set(zip(full.sphere.tolist(), full.kind.tolist(), full.index.tolist()))
    lost = {}
    for fraction in (0.9, 0.5, 0.0):
        narrow = sd.all_contacts(
            centres, velocities, radii, **shapes, t_max=t_max, partitions=4,
            halo=fraction * derived, client=client,
        )  # fmt: skip
        rows = set(zip(narrow.sphere.tolist(), narrow.kind.tolist(), narrow.index.tolist()))
        assert rows < full_rows  # a strict subset: contacts lost, none invented
        missing = np.array(sorted(full_rows - rows))
        # Every lost contact is a pair across a border, never a static contact.
        assert (missing[:, 1] == ss.KIND_SPHERE).all()
        assert (full.plan.owner[missing[:, 0]] != full.plan.owner[missing[:, 2]]).all()
        lost[fraction] = len(missing)
    # 10 % less than the derived width already loses the tight pairs (24 of them at 3 borders).
    assert 0 < lost[0.9] < lost[0.5] < lost[0.0]


def test_partitioned_query_refusals(client):
    centres, velocities, radii, shapes = crowded_scene(n=50)
    with pytest.raises(ValueError, match="t_max: inf"):
        sd.all_contacts(centres, velocities, radii, t_max=math.inf, client=client)
    with pytest.raises(ValueError, match="partitions: 0"):
        sd.all_contacts(centres, velocities, radii, t_max=1.0, partitions=0, client=client)
    bad = radii.copy()
    bad[42] = np.nan
    with pytest.raises(ValueError, match="42"):
        sd.first_contacts(centres, velocities, bad, t_max=1.0, client=client)


def test_no_spheres_give_empty_answers(client):
    none3, none = np.zeros((0, 3)), np.zeros(0)
    hits = sd.all_contacts(none3, none3, none, t_max=1.0, partitions=4, client=client)
    first = sd.first_contacts(none3, none3, none, t_max=1.0, partitions=4, client=client)
    assert len(hits) == 0 and len(first) == 0 and hits.plan.partitions == 4


def test_arguments_are_checked_before_any_task(client, tmp_path):
    centres, velocities, radii, _ = crowded_scene(n=50)
    # The binding's own message, raised on the client: no partition is blamed.
    for call in (
        lambda: sd.all_contacts(centres, velocities, radii, t_max=1.0, accuracy="exact", client=client),
        lambda: sd.first_contacts(centres, velocities, radii, t_max=1.0, accuracy="exact", client=client),
        lambda: sd.zip_times_parquet(tmp_path / "in", tmp_path / "out", accuracy="exact", client=client),
    ):
        with pytest.raises(ValueError, match=r'^accuracy: unknown accuracy mode "exact"'):
            call()
    frame = pd.DataFrame({c: [0.0] for c in sd.PAIR_COLUMNS})
    with pytest.raises(TypeError, match="^source: expected a path or a list of paths of a Parquet dataset, got DataFrame"):
        sd.zip_times_parquet(frame, tmp_path / "out", client=client)


def test_without_dask_the_helpers_say_what_to_install():
    import subprocess
    import sys

    code = (
        "import sys; sys.modules['distributed'] = None; sys.modules['dask'] = None\n"
        "import numpy as np\n"
        "from spheresweep import distributed as sd\n"
        "try:\n"
        "    sd.all_contacts(np.zeros((2, 3)), np.zeros((2, 3)), np.ones(2), t_max=1.0)\n"
        "except ModuleNotFoundError as e:\n"
        "    print(e)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("spheresweep.distributed needs distributed, which is not installed: "
                                 "pip install 'spheresweep[distributed]'"), out.stdout


def test_a_scene_value_past_float32_is_named_as_the_binding_names_it(client):
    # Validated before the rounding to float32 (which made 1e300 an infinity, warned of by
    # NumPy, and named it "NaN or infinite").
    centres = np.random.default_rng(3).random((100, 3))
    centres[99] = [1e300, 0, 0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"centres\[99, 0\]: 1e300 is beyond float32"):
            sd.all_contacts(
                centres, np.zeros((100, 3)), np.full(100, 0.1), t_max=1.0, client=client
            )
