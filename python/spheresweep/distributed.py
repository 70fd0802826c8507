"""Batch queries beyond one machine, on Dask (``dask[distributed]``).

Two kinds of work spread over the workers of a ``distributed.Client``:

* **Sharded batch queries on Parquet datasets** (:func:`zip_times_parquet`,
  :func:`static_contacts_parquet`): the dataset is read with ``dask.dataframe.read_parquet``,
  every partition is answered by one task calling the binding (``zip_times`` or
  ``static_times``), and the input columns plus the result columns of ``docs/query-format.md``
  (``time``; ``kind`` and ``index`` against shapes) are written as a Parquet dataset, row for
  row the single-process answers.
* **The whole-scene query over a scene partitioned in space** (:func:`all_contacts`,
  :func:`first_contacts`): slabs over the spheres' centres at t = 0, each with a halo of every
  sphere that can reach one of its own within ``[0, t_max]`` (:func:`plan_slabs`, derivation in
  ``docs/distributed.md``); each task queries its local scene, and every contact is kept by one
  partition only, so the union is the single-machine answer, bit for bit.

Every function takes a ``client`` or uses the current one (``distributed.get_client``).
"""

from __future__ import annotations

import importlib
import math
import os
import shutil
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np

__all__ = [
    "PAIR_COLUMNS",
    "SPHERE_COLUMNS",
    "HALO_MARGIN",
    "SlabPlan",
    "ParquetSummary",
    "ContactTable",
    "FirstContactTable",
    "reach_halo",
    "halo_width",
    "plan_slabs",
    "zip_times_parquet",
    "static_contacts_parquet",
    "all_contacts",
    "first_contacts",
]

#: Input columns of a pairs dataset, as in ``docs/query-format.md``.
PAIR_COLUMNS = (
    "ax", "ay", "az", "avx", "avy", "avz", "ar",
    "bx", "by", "bz", "bvx", "bvy", "bvz", "br",
)  # fmt: skip
#: Input columns of a spheres dataset (spheres against shapes), as in ``docs/query-format.md``.
SPHERE_COLUMNS = ("x", "y", "z", "vx", "vy", "vz", "r")
#: Relative widening of the derived halo (~1.6 % more halo spheres), on top of the rounding
#: margin of :func:`halo_width`: room for the kernels' f32 rounding with plenty to spare.
HALO_MARGIN = 2.0**-6
_UNIT_ROUNDOFF = 2.0**-24  # float32

# The query files (docs/query-format.md) code the shapes as the binding does (KIND_PLANE 1,
# KIND_CYLINDER 2, KIND_CONTAINER 3) and "none" as 0 (they never report a sphere, KIND_SPHERE 0).
_FILE_KIND_NONE = 0


def _native():
    """The binding, imported when first needed (this module may be imported by the package)."""
    import spheresweep

    return spheresweep


#: What the helpers need beyond the package, and how to install it.
INSTALL_HINT = (
    "pip install 'spheresweep[distributed]' from the wheel (docs/distributed.md), "
    "or pip install 'dask[distributed]' pandas pyarrow"
)


def _require(module: str):
    """``module`` imported, or a ModuleNotFoundError saying what to install."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as e:
        raise ModuleNotFoundError(
            f"spheresweep.distributed needs {module.split('.')[0]}, which is not installed: "
            f"{INSTALL_HINT}",
            name=e.name,
        ) from e


def _check_query(t_max: float, accuracy: str) -> float:
    """``t_max`` as a float and ``accuracy`` checked on the client, with the binding's own
    messages (a query on no spheres), before any task runs."""
    ss = _native()
    none = ss.Spheres(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.float32), np.zeros(0, np.float32))
    ss.zip_times(none, none, t_max=t_max, accuracy=accuracy)
    return _check_t_max(t_max)


def _client_or_current(client):
    """``client``, or the current ``distributed`` client; a ValueError naming the argument."""
    if client is not None:
        return client
    get_client = _require("distributed").get_client

    try:
        return get_client()
    except ValueError as e:
        raise ValueError(
            "client: no distributed.Client given and none is current "
            "(start one with distributed.Client(...))"
        ) from e


def _check_t_max(t_max: float) -> float:
    t_max = float(t_max)
    if math.isnan(t_max) or t_max < 0:
        raise ValueError(f"t_max: {t_max} is not a time >= 0")
    return t_max


# ---------------------------------------------------------------------------------------------
# Static shapes travel to the workers pickled: each pickles as its float32 inputs, so a worker's
# copy has the same bits as the client's.


def _checked_shapes(shapes: Sequence[Any], name: str) -> list:
    """``shapes`` as a list, each checked to be a ``Plane``, ``Cylinder`` or ``Container``."""
    ss = _native()
    checked = list(shapes)
    for k, shape in enumerate(checked):
        if not isinstance(shape, (ss.Plane, ss.Cylinder, ss.Container)):
            raise TypeError(
                f"{name}[{k}]: expected a Plane, Cylinder or Container, got {type(shape).__name__}"
            )
    return checked


def _by_kind(shapes: list) -> tuple:
    """Planes, cylinders and containers of ``shapes``, in their order within kinds."""
    ss = _native()
    return tuple([s for s in shapes if isinstance(s, kind)]
                 for kind in (ss.Plane, ss.Cylinder, ss.Container))


# ---------------------------------------------------------------------------------------------
# Sharded batch queries on Parquet datasets.


@dataclass(frozen=True)
class ParquetSummary:
    """What a sharded Parquet query did: rows answered, rows with a contact, tasks run."""

    rows: int
    contacts: int
    partitions: int
    destination: str


def _part_name(i: int) -> str:
    """Output file of partition ``i``: zero-padded so that name order is partition order."""
    return f"part.{i:06d}.parquet"


def _float_columns(frame, columns: Sequence[str]) -> list:
    """The named columns of a pandas frame as float32 arrays if they are float32, else float64
    (float16 and float64 are exact in it): the native side rounds float64 to float32
    (to nearest, as NumPy's ``astype``) and names a finite value beyond float32's range by its
    row, where a conversion here would make it ``inf``."""
    def column(c):
        wide = frame[c].dtype != np.float32
        return np.ascontiguousarray(frame[c].to_numpy(dtype=np.float64 if wide else np.float32))

    return [column(c) for c in columns]


def _answer_and_write(frame, apply, args, source, directory, partition_info=None):
    """One task: answers one partition with ``apply`` and writes it as one Parquet file.

    Returns a one-row frame of the rows and the rows with a contact, so that only counts come
    back to the client; an invalid value is a ValueError naming the partition and the row
    within it.
    """
    pd = _require("pandas")
    pa = _require("pyarrow")
    pq = _require("pyarrow.parquet")

    number = 0 if partition_info is None else partition_info["number"]
    try:
        answered = apply(frame, *args)
    except (ValueError, TypeError) as e:
        raise type(e)(f"{source}: partition {number} (rows counted within it): {e}") from e
    table = pa.Table.from_pandas(answered, preserve_index=False)
    # Dictionary encoding only where it can pay: tried on float columns of distinct values it
    # is abandoned after the work, and makes writing about eight times slower.
    dictionary = [f.name for f in table.schema if not pa.types.is_floating(f.type)]
    pq.write_table(
        table,
        os.path.join(directory, _part_name(number)),
        compression="snappy",
        use_dictionary=dictionary,
    )
    time = answered["time"].to_numpy()
    return pd.DataFrame({"rows": [len(time)], "contacts": [int(np.isfinite(time).sum())]})


def _pair_partition(frame, t_max, accuracy):
    """The times of impact of one partition of pairs, appended as ``time``."""
    ss = _native()
    cols = _float_columns(frame, PAIR_COLUMNS)
    sides = []
    for side, columns in (("a", cols[:7]), ("b", cols[7:])):
        try:
            sides.append(ss.Spheres.from_columns(*columns))
        except (ValueError, TypeError) as e:
            raise type(e)(f"sphere {side.upper()} (columns {side}x ... {side}r): {e}") from e
    return frame.assign(time=ss.zip_times(*sides, t_max=t_max, accuracy=accuracy))


def _static_partition(frame, shapes, t_max, accuracy):
    """Each sphere's earliest contact with the shapes, as ``time, kind, index``."""
    ss = _native()
    n = len(frame)
    time = np.full(n, np.inf, dtype=np.float32)
    kind = np.full(n, _FILE_KIND_NONE, dtype=np.uint8)
    index = np.full(n, -1, dtype=np.int64)
    if n and shapes:
        spheres = ss.Spheres.from_columns(*_float_columns(frame, SPHERE_COLUMNS))
        planes, cylinders, containers = _by_kind(shapes)
        ordered = planes + cylinders + containers  # the tie rule's order
        table = ss.static_times(spheres, ordered, t_max=t_max, accuracy=accuracy)
        column = np.argmin(table, axis=1)  # the first of equal times: plane, cylinder, ...
        time = table[np.arange(n), column]
        hit = np.isfinite(time)
        codes = np.array(
            [ss.KIND_PLANE] * len(planes)
            + [ss.KIND_CYLINDER] * len(cylinders)
            + [ss.KIND_CONTAINER] * len(containers),
            dtype=np.uint8,
        )
        starts = np.array(
            [0] * len(planes)
            + [len(planes)] * len(cylinders)
            + [len(planes) + len(cylinders)] * len(containers),
            dtype=np.int64,
        )
        kind = np.where(hit, codes[column], _FILE_KIND_NONE).astype(np.uint8)
        index = np.where(hit, column - starts[column], -1).astype(np.int64)
        time = time.astype(np.float32)
    return frame.assign(time=time, kind=kind, index=index)


def _check_schema(frame_meta, needed: Sequence[str], added: Sequence[str], source: str):
    """Missing, non-float or clashing columns of the input, named before any task runs."""
    present = list(frame_meta.columns)
    for column in needed:
        if column not in present:
            raise ValueError(
                f"{source}: no column {column}: the dataset needs the columns "
                f"{', '.join(needed)}; it has {', '.join(map(str, present))}"
            )
        dtype = frame_meta[column].dtype
        if dtype.kind != "f":
            raise ValueError(
                f"{source}: column {column} has type {dtype}, expected float32 or float64"
            )
    for column in added:
        if column in present:
            raise ValueError(
                f"{source}: the dataset already has a column {column}, which the output adds"
            )


def _local_destination(destination) -> str:
    path = os.fspath(destination)
    if "://" in path:
        raise ValueError(
            f"destination {path}: a path on a filesystem the client and every worker share is "
            "needed (the result is written beside it and renamed into place)"
        )
    return os.path.abspath(path)


def _replace_directory(staged: str, final: str, overwrite: bool) -> None:
    """Renames ``staged`` to ``final``; an existing ``final`` only if ``overwrite`` and it holds
    nothing but Parquet parts (it is moved aside first and removed after)."""
    if os.path.lexists(final):
        if not overwrite:
            raise FileExistsError(f"destination {final} exists (pass overwrite=True to replace it)")
        if not os.path.isdir(final):
            raise ValueError(f"destination {final} exists and is not a directory of Parquet parts")
        strangers = [
            f
            for f in os.listdir(final)
            if not (f.endswith(".parquet") or f in ("_metadata", "_common_metadata"))
        ]
        if strangers:
            raise ValueError(
                f"destination {final} holds {strangers[0]!r}, not only Parquet parts: not replaced"
            )
        aside = _staging_name(final, "old")
        os.rename(final, aside)
        os.rename(staged, final)
        shutil.rmtree(aside, ignore_errors=True)
    else:
        os.rename(staged, final)


def _is_paths(source) -> bool:
    """Whether ``source`` is a path, or a non-empty list or tuple of paths."""
    if isinstance(source, (str, os.PathLike)):
        return True
    return isinstance(source, (list, tuple)) and bool(source) and all(
        isinstance(p, (str, os.PathLike)) for p in source
    )


def _staging_name(final: str, what: str) -> str:
    head, tail = os.path.split(final)
    return os.path.join(head, f".{tail}.{os.getpid()}.{what}")


def _sharded_parquet(source, destination, needed, added, apply, args, client, overwrite,
                     split_row_groups):
    dd = _require("dask.dataframe")
    pd = _require("pandas")

    if not _is_paths(source):
        raise TypeError(
            f"source: expected a path or a list of paths of a Parquet dataset, got "
            f"{type(source).__name__} (write a DataFrame with to_parquet first)"
        )
    client = _client_or_current(client)
    final = _local_destination(destination)
    if os.path.lexists(final) and not overwrite:
        raise FileExistsError(f"destination {final} exists (pass overwrite=True to replace it)")
    label = os.fspath(source) if isinstance(source, (str, os.PathLike)) else repr(
        [os.fspath(p) for p in source]
    )
    frame = dd.read_parquet(source, split_row_groups=split_row_groups)
    _check_schema(frame._meta, needed, added, label)
    staged = _staging_name(final, "tmp")
    shutil.rmtree(staged, ignore_errors=True)
    os.makedirs(staged)
    try:
        counts = frame.map_partitions(
            _answer_and_write,
            apply,
            args,
            label,
            staged,
            meta=pd.DataFrame({"rows": np.empty(0, np.int64), "contacts": np.empty(0, np.int64)}),
            enforce_metadata=False,
        )
        counts = client.compute(counts).result()
        _replace_directory(staged, final, overwrite)
    except BaseException:
        shutil.rmtree(staged, ignore_errors=True)
        raise
    return ParquetSummary(
        int(counts["rows"].sum()), int(counts["contacts"].sum()), int(frame.npartitions), final
    )


def zip_times_parquet(
    source,
    destination,
    *,
    t_max: float = math.inf,
    accuracy: str = "stable",
    client=None,
    overwrite: bool = False,
    split_row_groups: Any = "infer",
) -> ParquetSummary:
    """Times of impact of every pair of a Parquet dataset, one Dask task per partition.

    ``source`` is anything ``dask.dataframe.read_parquet`` reads, with the pair columns
    ``PAIR_COLUMNS`` (float32 or float64; other columns are carried through). ``destination``
    becomes a directory of ``part.NNNNNN.parquet`` files, one per partition in input order:
    the input columns plus ``time`` (float32, ``inf`` for no contact in ``[0, t_max]``), the
    same bits as ``zip_times`` over the whole dataset in one process. It is written beside its
    final path under a temporary name and renamed into place, so it appears whole or not at all
    (it must be on a filesystem every worker shares). Raises ``ValueError`` naming a missing,
    non-float or clashing column before any task runs, and naming the partition and the row
    within it for an invalid value; ``FileExistsError`` if ``destination`` exists and
    ``overwrite`` is false.
    """
    t_max = _check_query(t_max, accuracy)
    return _sharded_parquet(
        source,
        destination,
        PAIR_COLUMNS,
        ("time",),
        _pair_partition,
        (t_max, accuracy),
        client,
        overwrite,
        split_row_groups,
    )


def static_contacts_parquet(
    source,
    destination,
    shapes: Sequence[Any],
    *,
    t_max: float = math.inf,
    accuracy: str = "stable",
    client=None,
    overwrite: bool = False,
    split_row_groups: Any = "infer",
) -> ParquetSummary:
    """Every sphere of a Parquet dataset against static shapes, one Dask task per partition.

    ``source`` has the columns ``SPHERE_COLUMNS``; ``shapes`` is a sequence of ``Plane``,
    ``Cylinder`` and ``Container`` (numbered within their kind in the order given, as in a
    shapes file). The output adds the columns of ``spheresweep query --against``: ``time``
    (float32), ``kind`` (uint8: 1 plane, 2 cylinder, 3 container, 0 none) and ``index`` (int64,
    the shape's index within its kind, -1 none), ties to the plane, then the cylinder, then the
    container, then the lowest index. Output, staging and errors as :func:`zip_times_parquet`.
    """
    t_max = _check_query(t_max, accuracy)
    shapes = _checked_shapes(shapes, "shapes")
    if not shapes:
        raise ValueError("shapes: no shapes given (a query against shapes needs at least one)")
    return _sharded_parquet(
        source,
        destination,
        SPHERE_COLUMNS,
        ("time", "kind", "index"),
        _static_partition,
        (shapes, t_max, accuracy),
        client,
        overwrite,
        split_row_groups,
    )


# ---------------------------------------------------------------------------------------------
# The whole-scene query over slabs with halos.


def reach_halo(velocities, radii, t_max: float) -> float:
    """The derived halo width ``2 max_i (r_i + |v_i| t_max)`` (no margin).

    Two spheres that touch at some ``t`` in ``[0, t_max]`` start at most
    ``(r_i + |v_i| t_max) + (r_j + |v_j| t_max)`` apart, so no more than this along any axis
    (``docs/distributed.md``). Computed in float64 from the float32 values the query sees.
    """
    t_max = _check_t_max(t_max)
    if math.isinf(t_max):
        raise ValueError(
            "t_max: inf has no finite halo; a partitioned query needs a finite window "
            "(for an infinite one use spheresweep.all_contacts on one machine)"
        )
    v = np.asarray(velocities, dtype=np.float32).astype(np.float64).reshape(-1, 3)
    r = np.asarray(radii, dtype=np.float32).astype(np.float64).reshape(-1)
    if len(r) == 0:
        return 0.0
    return 2.0 * float(np.max(r + np.sqrt((v * v).sum(axis=1)) * t_max))


def halo_width(centres, velocities, radii, t_max: float, accuracy: str = "stable") -> float:
    """The halo the partitioned query uses: :func:`reach_halo` widened for rounding.

    A float32 kernel may report a contact for a pair slightly beyond the exact reach (a grazing
    pair, or a time rounded down to ``t_max``). By the bounds of docs/derivations/accuracy.md
    that excess is at most ``8u (X + D)`` for ``stable`` (``X`` the largest coordinate the
    pair occupies, ``D`` the sum of radii, ``u = 2^-24``) and ``4u (X^2 + D^2) / D`` for
    ``textbook`` grazing; the width added is ``HALO_MARGIN h + 2^-16 (X + h)``, and for
    ``textbook`` also ``4u (X^2 + h^2) / (2 r_min)`` (no such term exists for point spheres).
    """
    h = reach_halo(velocities, radii, t_max)
    c = np.asarray(centres, dtype=np.float32).astype(np.float64).reshape(-1, 3)
    if len(c) == 0:
        return 0.0
    v = np.asarray(velocities, dtype=np.float32).astype(np.float64).reshape(-1, 3)
    r = np.asarray(radii, dtype=np.float32).astype(np.float64).reshape(-1)
    reach = float(np.max(np.abs(c))) + float(np.max(np.abs(v))) * math.sqrt(3.0) * t_max
    margin = HALO_MARGIN * h + 2.0**-16 * (reach + h)
    r_min = float(np.min(r))
    if accuracy == "textbook" and r_min > 0:
        margin += 4 * _UNIT_ROUNDOFF * (reach * reach + h * h) / (2 * r_min)
    return h + margin


@dataclass(frozen=True)
class SlabPlan:
    """Slabs along one axis over the centres at t = 0, with equal numbers of owned spheres.

    Partition ``k`` owns the spheres with ``bounds[k-1] <= x < bounds[k]`` (unbounded at the
    ends) and also holds, as its halo, every sphere with ``x`` within ``halo`` of that slab.
    ``members[k]`` lists the global indices it holds in increasing order, ``owned[k]`` which of
    them it owns.
    """

    axis: int
    bounds: np.ndarray
    halo: float
    owner: np.ndarray
    members: tuple
    owned: tuple

    def __repr__(self) -> str:
        held = [len(m) for m in self.members]
        return (
            f"SlabPlan(axis={self.axis}, partitions={self.partitions}, halo={self.halo:.6g}, "
            f"spheres={len(self.owner)}, held per slab={held})"
        )

    @property
    def partitions(self) -> int:
        """Number of slabs."""
        return len(self.members)

    @property
    def halo_fraction(self) -> float:
        """Halo spheres held over all partitions, as a fraction of the spheres."""
        held = sum(len(m) for m in self.members)
        return held / len(self.owner) - 1.0 if len(self.owner) else 0.0


def plan_slabs(
    centres,
    velocities,
    radii,
    *,
    t_max: float,
    partitions: int,
    axis: Optional[int] = None,
    halo: Optional[float] = None,
    accuracy: str = "stable",
) -> SlabPlan:
    """Slabs over the centres at t = 0 and their halos (see :class:`SlabPlan`).

    ``axis`` defaults to the one along which the centres spread most; ``halo`` to
    :func:`halo_width` for ``accuracy``, the derived width widened for rounding. A smaller
    ``halo`` loses contacts across slab borders (exposed for the tests and experiments).
    """
    c = np.asarray(centres, dtype=np.float32).reshape(-1, 3)
    n = len(c)
    partitions = int(partitions)
    if partitions < 1:
        raise ValueError(f"partitions: {partitions} is not a count >= 1")
    if halo is None:
        halo = halo_width(centres, velocities, radii, t_max, accuracy)
    halo = float(halo)
    if not halo >= 0:
        raise ValueError(f"halo: {halo} is not a width >= 0")
    if axis is None:
        axis = int(np.argmax(c.max(axis=0) - c.min(axis=0))) if n else 0
    if axis not in (0, 1, 2):
        raise ValueError(f"axis: {axis} is not 0, 1 or 2")
    x = c[:, axis].astype(np.float64)  # exact; the halo arithmetic below is in float64
    order = np.argsort(x)
    xs = x[order]
    cuts = [(k * n) // partitions for k in range(1, partitions)]
    bounds = xs[cuts] if n else np.zeros(len(cuts))  # no spheres: empty slabs
    owner = np.searchsorted(bounds, x, side="right").astype(np.int32)
    edges = np.concatenate([[-np.inf], bounds, [np.inf]])
    members, owned = [], []
    for k in range(partitions):
        lo = np.searchsorted(xs, edges[k] - halo, side="left")
        hi = np.searchsorted(xs, edges[k + 1] + halo, side="right")
        held = np.sort(order[lo:hi])
        members.append(held)
        owned.append(owner[held] == k)
    return SlabPlan(axis, bounds, halo, owner, tuple(members), tuple(owned))


@dataclass(frozen=True)
class ContactTable:
    """Every contact in the window over all partitions, in the single-machine order (time,
    sphere, kind, index): the columns of ``spheresweep.all_contacts`` with global indices."""

    time: np.ndarray
    sphere: np.ndarray
    kind: np.ndarray
    index: np.ndarray
    point: Optional[np.ndarray]
    normal: Optional[np.ndarray]
    plan: SlabPlan

    def __len__(self) -> int:
        return len(self.time)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(<{len(self)} rows>, {self.plan!r})"


@dataclass(frozen=True)
class FirstContactTable:
    """Each sphere's earliest contact, indexed by global sphere: the columns of
    ``spheresweep.first_contacts`` with global partner indices."""

    time: np.ndarray
    kind: np.ndarray
    index: np.ndarray
    point: Optional[np.ndarray]
    normal: Optional[np.ndarray]
    plan: SlabPlan

    def __len__(self) -> int:
        return len(self.time)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(<{len(self)} rows>, {self.plan!r})"


def _local_scene(part, shapes):
    ss = _native()
    centres, velocities, radii, masses, members, owned = part
    spheres = ss.Spheres(centres, velocities, radii, masses)
    planes, cylinders, containers = _by_kind(shapes)
    return ss.Scene(spheres, planes, cylinders, containers), members, owned


def _global_partners(kind, index, members):
    """Partner indices with local sphere indices mapped to global ones (shapes unchanged)."""
    spheres = kind == _native().KIND_SPHERE
    return np.where(spheres, members[np.where(spheres, index, 0)], index)


def _local_all(part, shapes, t_max, accuracy, geometry):
    """One task: the contacts of one slab's scene that the slab owns, with global indices.

    A sphere pair is kept by the owner of its lower index (``sphere``, since the local scene
    lists its spheres in global order), a static contact by the sphere's owner.
    """
    ss = _native()
    scene, members, owned = _local_scene(part, shapes)
    found = ss.all_contacts(scene, t_max=t_max, accuracy=accuracy, geometry=geometry)
    sphere = np.asarray(found.sphere, dtype=np.int64)
    keep = owned[sphere]
    kind = np.asarray(found.kind)[keep]
    index = np.asarray(found.index)[keep]
    index = _global_partners(kind, index, members)
    out = {
        "time": np.asarray(found.time)[keep],
        "sphere": members[sphere[keep]].astype(np.uint32),
        "kind": kind,
        "index": index.astype(np.int64),
    }
    if geometry:
        out["point"] = np.asarray(found.point)[keep]
        out["normal"] = np.asarray(found.normal)[keep]
    return out


def _local_first(part, shapes, t_max, accuracy, geometry):
    """One task: the earliest contact of each sphere the slab owns, with global indices."""
    ss = _native()
    scene, members, owned = _local_scene(part, shapes)
    found = ss.first_contacts(scene, t_max=t_max, accuracy=accuracy, geometry=geometry)
    kind = np.asarray(found.kind)[owned]
    index = np.asarray(found.index)[owned]
    index = _global_partners(kind, index, members)
    out = {
        "sphere": members[owned],
        "time": np.asarray(found.time)[owned],
        "kind": kind,
        "index": index.astype(np.int64),
    }
    if geometry:
        out["point"] = np.asarray(found.point)[owned]
        out["normal"] = np.asarray(found.normal)[owned]
    return out


def _scatter_slabs(client, centres, velocities, radii, masses, plan):
    """One future per non-empty slab holding its local columns, spread over the workers."""
    parts = []
    for members, owned in zip(plan.members, plan.owned):
        if not owned.any():
            continue
        parts.append(
            (
                centres[members],
                velocities[members],
                radii[members],
                None if masses is None else masses[members],
                members,
                owned,
            )
        )
    return client.scatter(parts, hash=False) if parts else []


def _scene_inputs(centres, velocities, radii, masses):
    """The spheres of a scene query, validated and built once, and their float32 columns
    ``(centres, velocities, radii, masses or None)`` for the slabs."""
    c = np.asarray(centres)
    v = np.asarray(velocities)
    r = np.asarray(radii)
    for name, a, shape in (("centres", c, "(N, 3)"), ("velocities", v, "(N, 3)")):
        if a.ndim != 2 or a.shape[1] != 3:
            raise ValueError(f"{name}: shape {a.shape}, expected {shape}")
    if r.ndim != 1:
        raise ValueError(f"radii: shape {r.shape}, expected (N,)")
    if not (len(c) == len(v) == len(r)):
        raise ValueError(
            f"velocities and radii: {len(v)} and {len(r)} rows, but centres has {len(c)}"
        )
    # Validated as given (a finite value past float32's range is named as such, not as "NaN or
    # infinite" after a rounding) and rounded to float32 once, by the binding, here: the
    # workers and a single-process query see the same bits.
    spheres = _native().Spheres(c, v, r, masses)
    m = None if masses is None else spheres.masses
    return spheres, (spheres.centres, spheres.velocities, spheres.radii, m)


def _scene_query(task, centres, velocities, radii, masses, planes, cylinders, containers,
                 t_max, accuracy, geometry, partitions, axis, halo, client):
    client = _client_or_current(client)
    spheres, (c, v, r, m) = _scene_inputs(centres, velocities, radii, masses)
    # Validated on the client (the spheres as given in `_scene_inputs`, the shapes here), so a
    # bad sphere is named by its global index.
    _native().Scene(spheres, planes, cylinders, containers)
    del spheres
    shapes = (
        _checked_shapes(planes, "planes")
        + _checked_shapes(cylinders, "cylinders")
        + _checked_shapes(containers, "containers")
    )
    if partitions is None:
        partitions = max(1, sum(client.nthreads().values()))
    plan = plan_slabs(
        c, v, r, t_max=t_max, partitions=partitions, axis=axis, halo=halo, accuracy=accuracy
    )
    futures = _scatter_slabs(client, c, v, r, m, plan)
    results = client.gather(
        client.map(task, futures, shapes=shapes, t_max=t_max, accuracy=accuracy,
                   geometry=geometry, pure=False)
    )
    return plan, results


def _join(results, name, dtype, width=None):
    shape = (0,) if width is None else (0, width)
    parts = [p[name] for p in results]
    return np.concatenate(parts) if parts else np.empty(shape, dtype=dtype)


def _single_machine_order(time, sphere):
    """The permutation into the binding's order (time, sphere, kind, index) of the slabs' rows
    concatenated slab by slab.

    Every row of a sphere comes from the one slab owning it, already in (kind, index) order, so a
    stable sort on (time, sphere) alone finishes the job: one 64-bit key, time's bits above the
    sphere's (times are >= 0, whose float32 bits order as the numbers do; -0 counted as 0).
    """
    bits = (np.asarray(time, dtype=np.float32) + np.float32(0)).view(np.uint32)
    key = (bits.astype(np.uint64) << np.uint64(32)) | np.asarray(sphere, dtype=np.uint64)
    return np.argsort(key, kind="stable")


def all_contacts(
    centres,
    velocities,
    radii,
    masses=None,
    *,
    planes: Sequence[Any] = (),
    cylinders: Sequence[Any] = (),
    containers: Sequence[Any] = (),
    t_max: float,
    accuracy: str = "stable",
    geometry: bool = False,
    partitions: Optional[int] = None,
    axis: Optional[int] = None,
    halo: Optional[float] = None,
    client=None,
) -> ContactTable:
    """Every contact in ``[0, t_max]`` of a scene split into slabs, one Dask task per slab.

    The arguments are those of ``spheresweep.Spheres`` and ``spheresweep.Scene``; ``t_max``
    must be finite (the halo grows with it). ``partitions`` defaults to the client's threads.
    The result has the columns of ``spheresweep.all_contacts`` on the whole scene, the same
    rows in the same order with the same float32 bits: each pair once with ``sphere < index``,
    sorted by time, sphere, kind, index. ``halo`` overrides the derived width (see
    :func:`plan_slabs`). Errors as the binding's, naming spheres by their global index.
    """
    t_max = _check_query(t_max, accuracy)
    plan, results = _scene_query(
        _local_all, centres, velocities, radii, masses, planes, cylinders, containers,
        t_max, accuracy, geometry, partitions, axis, halo, client,
    )  # fmt: skip
    time = _join(results, "time", np.float32)
    sphere = _join(results, "sphere", np.uint32)
    kind = _join(results, "kind", np.uint8)
    index = _join(results, "index", np.int64)
    order = _single_machine_order(time, sphere)
    point = normal = None
    if geometry:
        point = _join(results, "point", np.float32, 3)[order]
        normal = _join(results, "normal", np.float32, 3)[order]
    return ContactTable(time[order], sphere[order], kind[order], index[order], point, normal, plan)


def first_contacts(
    centres,
    velocities,
    radii,
    masses=None,
    *,
    planes: Sequence[Any] = (),
    cylinders: Sequence[Any] = (),
    containers: Sequence[Any] = (),
    t_max: float,
    accuracy: str = "stable",
    geometry: bool = False,
    partitions: Optional[int] = None,
    axis: Optional[int] = None,
    halo: Optional[float] = None,
    client=None,
) -> FirstContactTable:
    """The earliest contact of every sphere of a scene split into slabs, one task per slab.

    Arguments as :func:`all_contacts`. Each slab answers for the spheres it owns (every sphere
    that can touch one of them within ``t_max`` is in its halo, so the earliest contact and the
    tie rule see the same candidates as on one machine): the columns of
    ``spheresweep.first_contacts`` on the whole scene, with the same bits.
    """
    t_max = _check_query(t_max, accuracy)
    plan, results = _scene_query(
        _local_first, centres, velocities, radii, masses, planes, cylinders, containers,
        t_max, accuracy, geometry, partitions, axis, halo, client,
    )  # fmt: skip
    n = len(plan.owner)
    time = np.full(n, np.inf, dtype=np.float32)
    kind = np.full(n, _native().KIND_NONE, dtype=np.uint8)
    index = np.full(n, -1, dtype=np.int64)
    point = np.full((n if geometry else 0, 3), np.nan, dtype=np.float32)
    normal = np.full((n if geometry else 0, 3), np.nan, dtype=np.float32)
    for part in results:
        s = part["sphere"]
        time[s] = part["time"]
        kind[s] = part["kind"]
        index[s] = part["index"]
        if geometry:
            point[s] = part["point"]
            normal[s] = part["normal"]
    if not geometry:
        return FirstContactTable(time, kind, index, None, None, plan)
    return FirstContactTable(time, kind, index, point, normal, plan)
