"""spheresweep: continuous collision detection of moving spheres, eight pairs at a time.

Spheres, planes, infinite cylinders and spherical containers in; times of impact, the
earliest contact of every sphere, or every contact in a window out, as NumPy arrays. The
kernels are the Rust library's, so results are bit for bit those of the Rust API on the same
float32 inputs; the GIL is released while they run. See docs/python.md.

    >>> import numpy as np, spheresweep as ss
    >>> a = ss.Spheres([[0, 0, 0]], [[0, 0, 0]], [1.0])
    >>> b = ss.Spheres([[10, 0, 0]], [[-2, 0, 0]], [1.0])
    >>> ss.zip_times(a, b).tolist()
    [4.0]
"""

from ._native import (
    ACCURACIES,
    KIND_CONTAINER,
    KIND_CYLINDER,
    KIND_NONE,
    KIND_PLANE,
    KIND_SPHERE,
    Container,
    Contacts,
    Cylinder,
    FirstContacts,
    InvariantError,
    Plane,
    Scene,
    Simulation,
    Spheres,
    __version__,
    all_contacts,
    first_contacts,
    pair_times,
    read_xyz,
    static_times,
    zip_times,
)

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
