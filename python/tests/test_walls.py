"""Nothing leaves its vessel, seen from Python: the positions read back after every step are
checked here with numpy alone (not the engine's bookkeeping), and `advance_to` raises
`InvariantError` when the wall rules are broken on purpose."""

import numpy as np
import pytest

import spheresweep as ss

# The invariant's tolerance (OVERLAP_TOLERANCE of the Rust API, 2^-16): how far a sphere may
# sit beyond a wall, relative to its radius (docs/derivations/simulation.md, "The invariant
# every run keeps").
TOLERANCE = 2.0**-16
R_VESSEL = 6.0
R = 0.5


def one_sphere(restitution):
    """The case the issue reported: one sphere in an inelastic vessel, escaping at t ~ 15.5."""
    return ss.Simulation.from_spheres([[3, 0, 0]], [[0.3, 1, 0.2]], [R],
                                      containers=[ss.Container([0, 0, 0], R_VESSEL)],
                                      restitution=restitution)


def depth_outside(sim):
    """How far beyond the vessel's wall the farthest sphere reaches, in radii (<= 0 inside)."""
    reach = np.linalg.norm(sim.positions, axis=1) + sim.radii
    return float(np.max((reach - R_VESSEL) / sim.radii))


@pytest.mark.parametrize("restitution", [0.05, 0.3, 0.9])
def test_one_inelastic_sphere_stays_in_its_vessel(restitution):
    sim = one_sphere(restitution)
    worst = -np.inf
    for t in range(1, 301):
        sim.advance_to(float(t), check=False)
        worst = max(worst, depth_outside(sim))
    assert worst <= TOLERANCE, f"the sphere reached {worst:.3e} radii beyond the wall"
    # Long enough to be in the regime that leaked: the normal speed decayed to nothing, and
    # the sphere slides along the wall.
    assert sim.stats["wall_collisions"] > 1000 and sim.stats["slid"] > 0
    assert sim.stats["max_wall_overlap"] <= TOLERANCE
    report = sim.check_invariant()
    assert report["time"] == 300.0 and report["walls"] <= 0


def test_many_inelastic_spheres_stay_in_their_vessel_with_and_without_tc():
    rng = np.random.default_rng(5)
    # 40 spheres on a lattice well inside the vessel, random velocities.
    g = np.arange(-2, 2) * 1.6 + 0.8
    sites = np.stack(np.meshgrid(g, g, g), -1).reshape(-1, 3)[:40]
    for tc in (0.0, 1e-3):
        sim = ss.Simulation.from_spheres(sites, rng.normal(size=(40, 3)), np.full(40, 0.5),
                                         containers=[ss.Container([0, 0, 0], R_VESSEL)],
                                         restitution=0.3, tc=tc)
        worst = -np.inf
        for t in range(1, 101):
            try:
                sim.advance_to(float(t))
            except ValueError as e:
                # Without tc a dense inelastic pile may collapse: it must then be named.
                assert tc == 0.0 and "collapse" in str(e)
                break
            worst = max(worst, depth_outside(sim))
            centres = sim.positions
            d = np.linalg.norm(centres[:, None] - centres[None], axis=2) + np.eye(40) * 9
            assert d.min() >= 1.0 * (1 - TOLERANCE), f"two spheres overlap at t = {t}"
        assert worst <= TOLERANCE
        assert sim.stats["wall_collisions"] > 100


def test_a_broken_wall_rule_is_caught_by_advance_to():
    sim = one_sphere(0.3)
    sim._break_walls_for_testing()
    with pytest.raises(ss.InvariantError, match=r"sphere 0 .*container 0"):
        sim.advance_to(200.0)
    # Unchecked, the same run ends with the sphere outside, as the issue found it.
    sim = one_sphere(0.3)
    sim._break_walls_for_testing()
    sim.advance_to(200.0, check=False)
    assert depth_outside(sim) > 1.0
    with pytest.raises(ss.InvariantError):
        sim.check_invariant()
    assert issubclass(ss.InvariantError, RuntimeError)


def test_check_invariant_reports_depths_within_tolerance():
    sim = ss.Simulation.periodic_gas(300, 0.3, seed=3)
    sim.advance_to(2.0)
    report = sim.check_invariant()
    assert set(report) == {"time", "pairs", "walls"} and report["time"] == 2.0
    assert report["pairs"] <= 0
    with pytest.raises(TypeError, match="check"):
        sim.advance_to(3.0, check=1)
