"""Out of memory is a MemoryError, never an aborted interpreter: each case runs in a child
process under an address-space limit (`ulimit -v`), so that a refusal that fails shows as
the child dying (exit 134, "memory allocation ... failed") instead of taking pytest down.
A scene query too large (its contacts, for `all_contacts`) is refused before anything is
allocated, with the estimate in the message."""

import resource
import subprocess
import sys
import textwrap

import pytest

LIMIT = 3 << 30  # 3 GiB of address space: the interpreter, NumPy and the extension fit


def run_limited(code, limit=LIMIT):
    """Runs `code` in a child Python whose address space is capped at `limit` bytes; returns
    (exit code, stdout, stderr)."""

    def cap():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    out = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                         text=True, timeout=600, preexec_fn=cap)
    return out.returncode, out.stdout, out.stderr


PREAMBLE = """
import numpy as np, spheresweep as ss
def report(f):
    try:
        f()
    except MemoryError as e:
        print("MemoryError:", e)
    else:
        print("no error")
"""


def expect_memory_error(body, *needles):
    code, out, err = run_limited(PREAMBLE + textwrap.dedent(body))
    assert code == 0, (code, err[-2000:])
    assert out.startswith("MemoryError:"), out + err[-2000:]
    for needle in needles:
        assert needle in out, out
    return out


def test_an_infinite_window_on_1e5_spheres_runs_in_bounded_memory():
    # 10^5 spheres of radius 0.3 filling about 1 % of their box, t_max = inf: n (n - 1) / 2 =
    # 4 999 950 000 pairs, which a list of candidates would hold in about 56 GiB. The query
    # answers by successive windows, then brute-force rows for the spheres still open, in
    # memory linear in n: here under the child's 3 GiB cap, and its peak stays below 1 GB.
    code, out, err = run_limited(PREAMBLE + textwrap.dedent("""
        import resource
        rng = np.random.default_rng(1)
        n = 100_000
        side = (n * 4 / 3 * np.pi * 0.3**3 / 0.01) ** (1 / 3)
        s = ss.Spheres(rng.uniform(0, side, (n, 3)), rng.uniform(-1, 1, (n, 3)), np.full(n, 0.3))
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        hits = ss.first_contacts(ss.Scene(s))
        after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        touching = int((hits.kind != 255).sum())
        print("touching", touching, "grew_kb", after - before)
    """))
    assert code == 0, (code, err[-2000:])
    words = out.split()
    touching, grew_kb = int(words[1]), int(words[3])
    assert 0 < touching < 100_000, out
    assert grew_kb < 1_000_000, out  # under 1 GB more than before the query


def test_all_contacts_too_many_to_return_is_refused():
    # 3·10^4 spheres of radius 0.3 crowded in a unit box: most pairs overlap and about half
    # approach, so the answer alone is of the order of 10^8 contacts, many GiB; refused before
    # the query runs, with the estimate. (The candidate pairs themselves are never held.)
    out = expect_memory_error("""
        rng = np.random.default_rng(2)
        n = 30_000
        s = ss.Spheres(rng.uniform(0, 1, (n, 3)), rng.uniform(-1, 1, (n, 3)), np.full(n, 0.3))
        report(lambda: ss.all_contacts(ss.Scene(s), t_max=1e4))
    """, "all_contacts: 30000 spheres, t_max = 10000.0, about ", "contacts to return",
        "refused before allocating")
    assert "GiB" in out


def test_spheres_from_a_broadcast_array_too_large():
    # A broadcast float32 array costs nothing; 2·10^8 spheres in a store cost 6.4 GB.
    expect_memory_error("""
        c = np.broadcast_to(np.float32(1.0), (200_000_000, 3))
        r = np.broadcast_to(np.float32(0.5), (200_000_000,))
        report(lambda: ss.Spheres(c, c, r))
    """, "Spheres: 200000000 spheres needs about")


def test_a_float64_array_too_large_to_convert_is_refused_before_numpy_copies_it():
    # 4·10^8 spheres given as float64: their float32 copy (4.8 GB for the centres)
    # is refused by the memory check before NumPy makes it, not by NumPy failing to (or by
    # the system, with the copy made, on a machine with the room).
    expect_memory_error("""
        c = np.broadcast_to(np.float64(1.0), (400_000_000, 3))
        r = np.broadcast_to(np.float64(0.5), (400_000_000,))
        report(lambda: ss.Spheres(c, c, r))
    """, "centres: its 1200000000 values converted to float32 needs about", "refused before allocating")


def test_from_columns_too_large():
    expect_memory_error("""
        x = np.broadcast_to(np.float32(1.0), (200_000_000,))
        report(lambda: ss.Spheres.from_columns(x, x, x, x, x, x, x))
    """, "Spheres.from_columns: 200000000 spheres")


def test_a_static_times_table_too_large():
    # 10^6 spheres (32 MB) against 1000 planes: a float32 table of 4 GB, refused by the
    # allocation itself (no estimate: try_reserve fails under the limit).
    expect_memory_error("""
        n = 1_000_000
        s = ss.Spheres(np.zeros((n, 3)), np.zeros((n, 3)), np.ones(n))
        planes = [ss.Plane([0, 0, -5], [0, 0, 1])] * 1000
        report(lambda: ss.static_times(s, planes))
    """, "static_times: cannot allocate")


def test_simulations_too_large():
    expect_memory_error("""
        report(lambda: ss.Simulation.periodic_gas(1_000_000_000, 0.3))
    """, "periodic_gas: 1000000000 spheres")
    expect_memory_error("""
        c = np.broadcast_to(np.float64(1.0), (100_000_000, 3))
        r = np.broadcast_to(np.float64(0.5), (100_000_000,))
        report(lambda: ss.Simulation.from_spheres(c, c, r))
    """, "Simulation: 100000000 spheres")


def test_the_memory_variable_caps_what_is_available():
    # SPHERESWEEP_MAX_MEMORY (as for the CLI) lowers the figure: a query that fits in memory
    # is refused under a cap of 1 MiB, and a malformed value is named.
    code = PREAMBLE + textwrap.dedent("""
        import os
        rng = np.random.default_rng(3)
        s = ss.Spheres(rng.uniform(0, 50, (3000, 3)), rng.uniform(-1, 1, (3000, 3)), np.full(3000, 0.3))
        report(lambda: ss.first_contacts(ss.Scene(s), t_max=1.0))
        os.environ["SPHERESWEEP_MAX_MEMORY"] = "1M"
        report(lambda: ss.first_contacts(ss.Scene(s), t_max=1.0))
        os.environ["SPHERESWEEP_MAX_MEMORY"] = "lots"
        try:
            ss.first_contacts(ss.Scene(s), t_max=1.0)
        except ValueError as e:
            print("ValueError:", e)
    """)
    code, out, err = run_limited(code, limit=8 << 30)
    assert code == 0, err
    lines = out.splitlines()
    assert lines[0] == "no error"
    assert lines[1].startswith("MemoryError: first_contacts: 3000 spheres, t_max = 1.0")
    assert "1.0 MiB (1048576 B) is available (SPHERESWEEP_MAX_MEMORY)" in lines[1]
    assert lines[2] == 'ValueError: SPHERESWEEP_MAX_MEMORY="lots" is not a size in bytes (e.g. 512M, 8G)'
