"""Binding overhead of ``spheresweep.zip_times``: the Python call against the Rust batch call
on the same stores, in the same process.

For each size N, spheres A and B (float32, random, about a third of the pairs touching) are
built once. Then, interleaved round by round so that both see the same machine state:

- ``rust``: ``ss._native._rust_zip_times_ns`` times ``batch::zip_times`` alone in Rust (GIL
  released, ``Instant`` around the call), into the same reused float32 array the Python
  ``out=`` call writes, or into a vector it allocates per call (``rust, new out``);
- ``python``: ``ss.zip_times(a, b)`` timed with ``time.perf_counter_ns`` around the call: the
  argument parsing, the GIL release, a new float32 output array (its pages first touched by the
  kernels) and the wrapping into a NumPy array;
- ``python out=``: ``ss.zip_times(a, b, out=buf)`` into a reused array (no allocation).

Best of ``--rounds`` each. The overhead per call is ``python - rust``; per pair it is that
divided by N. Run:

    target/python-venv/bin/python python/bench/bench_binding.py [--rounds 30] [--sizes ...]
"""

import argparse
import json
import math
import os
import platform
import time

import numpy as np

import spheresweep as ss
from spheresweep import _native


def spheres(rng, n, offset=None):
    centres = rng.uniform(-100, 100, (n, 3)).astype(np.float32)
    if offset is not None:
        centres = (offset + rng.uniform(-6, 6, (n, 3))).astype(np.float32)
    velocities = rng.uniform(-2, 2, (n, 3)).astype(np.float32)
    radii = rng.uniform(0.2, 1.0, n).astype(np.float32)
    return centres, ss.Spheres(centres, velocities, radii)


def measure(n, rounds, accuracy="stable"):
    rng = np.random.default_rng(n)
    ca, a = spheres(rng, n)
    _, b = spheres(rng, n, offset=ca)
    buf = np.empty(n, np.float32)
    # Warm up every path once (pages, rayon threads, caches).
    ss.zip_times(a, b, accuracy=accuracy)
    ss.zip_times(a, b, accuracy=accuracy, out=buf)
    _native._rust_zip_times_ns(a, b, math.inf, accuracy, 1, buf)
    rust, rust_fresh, py, py_out = [], [], [], []
    for _ in range(rounds):
        rust.append(_native._rust_zip_times_ns(a, b, math.inf, accuracy, 1, buf)[0])
        rust_fresh.append(_native._rust_zip_times_ns(a, b, math.inf, accuracy, 1)[0])
        t0 = time.perf_counter_ns()
        times = ss.zip_times(a, b, accuracy=accuracy)
        py.append(time.perf_counter_ns() - t0)
        del times
        t0 = time.perf_counter_ns()
        ss.zip_times(a, b, accuracy=accuracy, out=buf)
        py_out.append(time.perf_counter_ns() - t0)
    # The Python result is the Rust one (same bits) — a benchmark of a wrong answer is void.
    check = ss.zip_times(a, b, accuracy=accuracy)
    assert np.array_equal(check.view(np.uint32), buf.view(np.uint32))
    hits = int(np.isfinite(check).sum())
    return dict(n=n, rust_ns=min(rust), rust_fresh_ns=min(rust_fresh), python_ns=min(py), python_out_ns=min(py_out), hits=hits)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=30)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1_000, 10_000, 100_000, 1_000_000])
    parser.add_argument("--json", help="also write the results here")
    args = parser.parse_args()
    rows = [measure(n, args.rounds) for n in args.sizes]
    print(f"# spheresweep {ss.__version__}, Python {platform.python_version()}, "
          f"numpy {np.__version__}, {os.cpu_count()} CPUs, best of {args.rounds} rounds, stable mode")
    print("| pairs | Rust, reused out | Rust, new out | Python, out= | Python, new out | overhead per call (out=) | per pair | Python out= / Rust | Python / Rust new out |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        n, rust, fresh = r["n"], r["rust_ns"], r["rust_fresh_ns"]
        py, out = r["python_ns"], r["python_out_ns"]
        print(f"| {n:,} | {rust / 1e3:.1f} µs | {fresh / 1e3:.1f} µs | {out / 1e3:.1f} µs | {py / 1e3:.1f} µs | "
              f"{(out - rust) / 1e3:.1f} µs | {(out - rust) / n:.3f} ns | {out / rust:.3f} | {py / fresh:.3f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
