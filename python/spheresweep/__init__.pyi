"""Type stubs of spheresweep (the extension module spheresweep._native, re-exported)."""

import os
from typing import Any, Callable, Dict, List, Literal, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__all__ = [
    "ACCURACIES",
    "KIND_CONTAINER",
    "KIND_CYLINDER",
    "KIND_NONE",
    "KIND_PLANE",
    "KIND_SPHERE",
    "Container",
    "Contacts",
    "Cylinder",
    "FirstContacts",
    "InvariantError",
    "Plane",
    "Scene",
    "Simulation",
    "Spheres",
    "__version__",
    "all_contacts",
    "first_contacts",
    "pair_times",
    "read_xyz",
    "static_times",
    "zip_times",
]

__version__: str

ACCURACIES: Tuple[str, str, str]
"""The accuracy modes, cheapest first: ("textbook", "stable", "double")."""

KIND_NONE: int
"""Kind code of "no contact" (255; ``index`` is -1 there)."""
KIND_SPHERE: int
"""Kind code of a sphere (0, as the Rust ``ShapeKind`` and the checkpoint)."""
KIND_PLANE: int
"""Kind code of a plane (1, as in the query files)."""
KIND_CYLINDER: int
"""Kind code of a cylinder (2)."""
KIND_CONTAINER: int
"""Kind code of a container (3)."""

_Accuracy = Literal["textbook", "stable", "double"]
_ArrayLike = npt.ArrayLike
_Vector3 = Union[Sequence[float], npt.NDArray[np.floating[Any]], npt.NDArray[np.integer[Any]]]
_F32 = npt.NDArray[np.float32]
_F64 = npt.NDArray[np.float64]

@final
class Spheres:
    """Moving spheres in float32, validated once and kept in the library's column store.

    ``centres`` and ``velocities`` are ``(N, 3)``, ``radii`` and ``masses`` ``(N,)`` (every
    mass 1 without it). float32 arrays are read in place at any strides; float64 (or any other
    floating or integer dtype) is converted to float32 once, rounding to nearest; lists of ints
    or floats go through ``numpy.asarray(x, dtype=float32)``. ``TypeError`` for a dtype that is
    not real numbers (bool, complex, ...), ``ValueError`` for a wrong shape, mismatched lengths
    or an invalid sphere (named by index and field). Pickles to the same bits.
    """

    def __new__(
        cls,
        centres: _ArrayLike,
        velocities: _ArrayLike,
        radii: _ArrayLike,
        masses: Optional[_ArrayLike] = None,
    ) -> "Spheres": ...
    @staticmethod
    def from_columns(
        x: _ArrayLike,
        y: _ArrayLike,
        z: _ArrayLike,
        vx: _ArrayLike,
        vy: _ArrayLike,
        vz: _ArrayLike,
        r: _ArrayLike,
        m: Optional[_ArrayLike] = None,
    ) -> "Spheres":
        """Spheres from separate ``(N,)`` columns (the layout of Parquet and Arrow tables)."""
    def __len__(self) -> int: ...
    def __getitem__(self, key: Union[int, slice, npt.ArrayLike], /) -> "Spheres":
        """The selected spheres (int, slice, index array or boolean mask), copied."""
    def __eq__(self, value: object, /) -> bool: ...
    @property
    def centres(self) -> _F32:
        """Centres at t = 0: a new float32 ``(N, 3)`` array."""
    @property
    def velocities(self) -> _F32:
        """Velocities: a new float32 ``(N, 3)`` array."""
    @property
    def radii(self) -> _F32:
        """Radii: a new float32 ``(N,)`` array."""
    @property
    def masses(self) -> _F32:
        """Masses: a new float32 ``(N,)`` array."""

@final
class Plane:
    """A static infinite plane through ``point`` with normal ``normal`` (any non-zero length,
    normalised). Each vector is three real numbers (ints or floats, a sequence or an array),
    rounded to float32. Pickles as the inputs given, so a rebuilt plane has the same bits."""

    def __new__(cls, point: _Vector3, normal: _Vector3) -> "Plane": ...
    @property
    def point(self) -> Tuple[float, float, float]:
        """A point of the plane, as given (in float32)."""
    @property
    def normal(self) -> Tuple[float, float, float]:
        """The unit normal: the normal given, normalised (then rounded to float32)."""

@final
class Cylinder:
    """A static infinite cylinder of ``radius`` around the line through ``p1`` and ``p2``.
    Points and radius are real numbers (ints or floats), rounded to float32; pickles to the
    same bits."""

    def __new__(cls, p1: _Vector3, p2: _Vector3, radius: float) -> "Cylinder": ...
    @property
    def p1(self) -> Tuple[float, float, float]: ...
    @property
    def p2(self) -> Tuple[float, float, float]: ...
    @property
    def radius(self) -> float: ...

@final
class Container:
    """The inside of the sphere of ``radius`` around ``centre``; spheres move inside it.
    Centre and radius are real numbers (ints or floats), rounded to float32; pickles to the
    same bits."""

    def __new__(cls, centre: _Vector3, radius: float) -> "Container": ...
    @property
    def centre(self) -> Tuple[float, float, float]: ...
    @property
    def radius(self) -> float: ...

_Shape = Union[Plane, Cylinder, Container]

def zip_times(
    a: Spheres,
    b: Spheres,
    *,
    t_max: float = ...,
    accuracy: _Accuracy = "stable",
    out: Optional[_F32] = None,
) -> _F32:
    """Time of impact of ``a[i]`` with ``b[i]`` for every ``i``: float32 ``(N,)``, ``inf`` where
    the pair does not touch in ``[0, t_max]`` (``t_max`` rounded to float32, default ``inf``).
    ``out``, a C-contiguous float32 ``(N,)`` array, is written in place and returned. The GIL
    is released while the kernels run."""

def pair_times(
    s: Spheres,
    i: _ArrayLike,
    j: _ArrayLike,
    *,
    t_max: float = ...,
    accuracy: _Accuracy = "stable",
    out: Optional[_F32] = None,
) -> _F32:
    """Time of impact of each pair ``(i[k], j[k])`` of spheres of ``s``: float32 ``(P,)``."""

def static_times(
    s: Spheres,
    shapes: Sequence[_Shape],
    *,
    t_max: float = ...,
    accuracy: _Accuracy = "stable",
) -> _F32:
    """Time of impact of every sphere with each shape: float32 ``(N, len(shapes))``."""

@final
class Scene:
    """Spheres and the static shapes around them, for ``first_contacts`` and ``all_contacts``.
    Pickles to the same bits (spheres and shapes)."""

    def __new__(
        cls,
        spheres: Spheres,
        planes: Optional[Sequence[Plane]] = None,
        cylinders: Optional[Sequence[Cylinder]] = None,
        containers: Optional[Sequence[Container]] = None,
    ) -> "Scene": ...
    def __len__(self) -> int: ...
    @property
    def spheres(self) -> Spheres:
        """The scene's spheres (a copy)."""
    @property
    def shapes(self) -> Tuple[Tuple[Plane, ...], Tuple[Cylinder, ...], Tuple[Container, ...]]:
        """The planes, cylinders and containers as given."""

@final
class FirstContacts:
    """The earliest contact of every sphere, indexed by sphere."""

    time: _F32
    """float32 ``(N,)``: time of impact, ``inf`` for none."""
    kind: npt.NDArray[np.uint8]
    """uint8 ``(N,)``: ``KIND_*`` of the body touched, ``KIND_NONE`` for none."""
    index: npt.NDArray[np.int64]
    """int64 ``(N,)``: index of the body within its kind, -1 for none."""
    point: Optional[_F32]
    """float32 ``(N, 3)`` contact points (NaN for none) with ``geometry=True``, else None."""
    normal: Optional[_F32]
    """float32 ``(N, 3)`` unit normals pushing the sphere away, or None."""
    def __new__(
        cls,
        time: _F32,
        kind: npt.NDArray[np.uint8],
        index: npt.NDArray[np.int64],
        point: Optional[_F32] = None,
        normal: Optional[_F32] = None,
    ) -> "FirstContacts":
        """For unpickling: the columns as they were."""
    def __len__(self) -> int: ...
    def as_dict(self) -> Dict[str, npt.NDArray[Any]]:
        """1-D columns: time, kind, index, and point_x ... normal_z with geometry."""
    def to_pandas(self) -> Any:
        """A pandas DataFrame of ``as_dict()``, one row per sphere."""

@final
class Contacts:
    """Every contact in a window, one row each, sorted by time, then sphere, then body."""

    time: _F32
    sphere: npt.NDArray[np.uint32]
    kind: npt.NDArray[np.uint8]
    index: npt.NDArray[np.int64]
    """For two spheres ``sphere < index``; each pair appears once."""
    point: Optional[_F32]
    normal: Optional[_F32]
    def __new__(
        cls,
        time: _F32,
        sphere: npt.NDArray[np.uint32],
        kind: npt.NDArray[np.uint8],
        index: npt.NDArray[np.int64],
        point: Optional[_F32] = None,
        normal: Optional[_F32] = None,
    ) -> "Contacts":
        """For unpickling: the columns as they were."""
    def __len__(self) -> int: ...
    def as_dict(self) -> Dict[str, npt.NDArray[Any]]:
        """1-D columns: time, sphere, kind, index, and point_x ... normal_z with geometry."""
    def to_pandas(self) -> Any:
        """A pandas DataFrame of ``as_dict()``, one row per contact."""

def first_contacts(
    scene: Scene,
    *,
    t_max: float = ...,
    accuracy: _Accuracy = "stable",
    geometry: bool = False,
) -> FirstContacts:
    """For every sphere, its earliest contact in ``[0, t_max]`` (ties: spheres, then planes,
    cylinders, containers, each by index)."""

def all_contacts(
    scene: Scene,
    *,
    t_max: float,
    accuracy: _Accuracy = "stable",
    geometry: bool = False,
) -> Contacts:
    """Every contact in ``[0, t_max]``: each sphere pair once, every sphere with every shape."""

class InvariantError(RuntimeError):
    """The state broke the invariant every run keeps (a bug in spheresweep): the message
    names the sphere, the other body and the time."""

@final
class Simulation:
    """A running event-driven simulation in float64, collisions in exact time order."""

    @staticmethod
    def from_scene_file(path: Union[str, "os.PathLike[str]"]) -> "Simulation":
        """The simulation of a scene file (TOML, or JSON by extension); a ``RuntimeWarning``
        names a sphere so far from the origin that its contacts may overlap past the
        tolerance, or a shape its rounding to float32 moves by more than 2⁻¹⁰ of the smallest
        radius."""
    @staticmethod
    def periodic_gas(
        n: int,
        phi: float,
        radius: float = 0.5,
        kT: float = 1.0,
        seed: int = 0,
        record_events: bool = False,
    ) -> "Simulation":
        """``n`` hard spheres at packing fraction ``phi`` in a periodic cube, elastic."""
    @staticmethod
    def from_spheres(
        centres: _ArrayLike,
        velocities: _ArrayLike,
        radii: _ArrayLike,
        masses: Optional[_ArrayLike] = None,
        *,
        planes: Optional[Sequence[Union[Plane, Tuple[Plane, int]]]] = None,
        cylinders: Optional[Sequence[Union[Cylinder, Tuple[Cylinder, int]]]] = None,
        containers: Optional[Sequence[Union[Container, Tuple[Container, int]]]] = None,
        periodic_box: Optional[_Vector3] = None,
        restitution: Optional[float] = None,
        response: Optional[Literal["none", "elastic", "inelastic", "sticky"]] = None,
        tc: float = 0.0,
        materials: Optional[_ArrayLike] = None,
        pairs: Optional[Sequence[Tuple[int, int, Union[float, str]]]] = None,
        record_events: bool = False,
        geometry: bool = False,
        gravity: Optional[_Vector3] = None,
    ) -> "Simulation":
        """Spheres given as float64 arrays among static shapes, open or periodic.

        ``restitution`` alone: elastic when absent or 1, inelastic below. ``response``:
        "none", "elastic", "inelastic" (``restitution`` required) or "sticky";
        ``tc``: the TC model's duration; ``materials``: a material index per sphere, a shape
        may be a ``(shape, material)`` tuple; ``pairs``: ``(a, b, restitution | "elastic" |
        "sticky")`` overrides per pair of materials; ``gravity``: a uniform acceleration
        (refused with ``periodic_box`` and "sticky"). A ``RuntimeWarning`` names a sphere so
        far from the origin that its contacts may overlap past the tolerance."""
    def advance_to(
        self,
        t: float,
        *,
        progress: Optional[Callable[[float], Any]] = None,
        check: bool = True,
    ) -> None:
        """Processes every collision up to ``t`` (GIL released). Ctrl-C raises
        KeyboardInterrupt between two events (the simulation usable); ``progress(time)`` is
        called at most ten times a second and once with ``t`` at the end. With ``check`` the
        state reached is checked against the invariant (InvariantError if broken)."""
    def check_invariant(self) -> Dict[str, float]:
        """``{"time", "pairs", "walls"}``: the deepest overlap of a pair and of a sphere with
        a shape, over its tolerance (``<= 0`` when nothing overlaps, at most 1 within the
        tolerance); InvariantError beyond it."""
    def _break_walls_for_testing(self) -> None: ...
    def set_velocities(self, velocities: _ArrayLike) -> None:
        """A new velocity for every sphere, float64 ``(N, 3)``; every event predicted again."""
    def images(self) -> npt.NDArray[np.int64]:
        """int64 ``(N, 3)``: crossings of each face of the periodic box (+1 out the upper)."""
    def unwrapped_positions(self) -> _F64:
        """``positions + images() * box``: centres the periodic box did not wrap."""
    @property
    def time(self) -> float: ...
    @property
    def flown_apart(self) -> Optional[float]:
        """Once an open scene's spheres have flown apart for good, the time of the last thing
        that happened (0.0 if nothing did); None until then."""
    @property
    def t_end(self) -> Optional[float]:
        """The scene file's ``[run] t_end``, or None."""
    @property
    def box(self) -> Optional[Tuple[float, float, float]]:
        """The periodic box's lengths, or None in open space."""
    def __len__(self) -> int: ...
    @property
    def positions(self) -> _F64:
        """float64 ``(N, 3)`` centres now (wrapped into a periodic box)."""
    @property
    def velocities(self) -> _F64: ...
    @property
    def radii(self) -> _F64: ...
    @property
    def masses(self) -> _F64: ...
    def kinetic_energy(self) -> float: ...
    def potential_energy(self) -> float:
        """``sum(-m g . r)`` in the uniform gravity (0 without)."""
    def energy(self) -> Dict[str, float]:
        """``{"kinetic", "potential", "lost", "total"}``: ``total`` stays what it was."""
    def momentum(self) -> Tuple[float, float, float]: ...
    @property
    def stats(self) -> Dict[str, Union[int, float]]:
        """Counters: collisions, pair_collisions, wall_collisions, crossings, stale,
        predictions, kernels_*, energy_lost, virial, max_overlap, max_wall_overlap, slid,
        joins, guarded."""
    @property
    def pressure(self) -> Optional[Dict[str, float]]:
        """Periodic boxes: p, z (PV/(NkT)), phi, kt and carnahan_starling (that equation of
        state's Z at phi) from the collision virial since the start; None otherwise."""
    @property
    def engine(self) -> str: ...
    def memory_bytes(self) -> int: ...
    def clusters(self) -> List[List[int]]: ...
    def checkpoint(self) -> bytes: ...
    def restore(self, data: bytes) -> None:
        """The state ``checkpoint`` saved, of the same system (radii, masses, materials,
        shapes, boundary, effects); ValueError otherwise."""
    def take_events(self) -> Dict[str, npt.NDArray[Any]]:
        """Recorded collisions since the last call, 1-D columns of K rows: time, sphere, kind,
        index, approach, restitution, energy_lost, point_x, point_y, point_z, normal_x,
        normal_y, normal_z (``pandas.DataFrame`` of it is a table)."""
    def write_xyz(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Appends the state now as one extended XYZ frame (the CLI's trajectory format)."""
    @staticmethod
    def _unpickle(constructor: str, how: Any, state: bytes) -> "Simulation": ...
    def __reduce__(self) -> Any: ...

def read_xyz(path: Union[str, "os.PathLike[str]"]) -> List[Dict[str, Any]]:
    """Every frame of an extended XYZ file: time, positions, velocities (N, 3), radii,
    masses (1.0 each unless the file has a mass column: trajectories record none),
    materials (N,), box (tuple or None)."""
