"""Throughput of spheresweep.distributed against one process, and Dask's cost per task.

    python python/bench/bench_distributed.py [--pairs 4000000] [--spheres 1000000] [--quick]

Measures, on a LocalCluster of two single-threaded worker processes on 127.0.0.1:

* Dask's overhead per task (tasks that do nothing, submitted in one batch);
* a Parquet dataset of pairs: one process (pyarrow read, ``zip_times``, pyarrow write) against
  ``zip_times_parquet`` at several partition sizes (row groups of the input);
* the whole-scene query: ``spheresweep.all_contacts`` in one process against
  ``distributed.all_contacts`` over 2 … 64 slabs, with the halo fraction of each.

Each figure is the best of ``--repeat`` runs (the machine may be shared). Prints Markdown tables.
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import tempfile
import time

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

import spheresweep as ss
from spheresweep import distributed as sd


def best(repeat, run, budget=30.0):
    """The fastest of ``repeat`` runs (fewer once ``budget`` seconds are spent) and its value."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        value = run()
        times.append(time.perf_counter() - t0)
        if sum(times) > budget:
            break
    return min(times), value


def noop(x):
    return x


def task_overhead(client, tasks, repeat):
    def run():
        client.gather(client.map(noop, range(tasks), pure=False))

    run()  # warm
    seconds, _ = best(repeat, run)
    return seconds / tasks


def pairs_dataset(directory, n, rows_per_group, seed=1):
    rng = np.random.default_rng(seed)
    cols = {}
    for side in "ab":
        for f in ("x", "y", "z"):
            cols[f"{side}{f}"] = rng.uniform(-10, 10, n).astype(np.float32)
        for f in ("vx", "vy", "vz"):
            cols[f"{side}{f}"] = rng.uniform(-1, 1, n).astype(np.float32)
        cols[f"{side}r"] = rng.uniform(0.1, 1.0, n).astype(np.float32)
    table = pa.table({c: cols[c] for c in sd.PAIR_COLUMNS})
    os.makedirs(directory)
    pq.write_table(
        table, os.path.join(directory, "pairs.parquet"), row_group_size=rows_per_group,
        compression="snappy", use_dictionary=False,
    )  # fmt: skip
    return table


def one_process_pairs(source, out):
    table = pq.read_table(source)
    cols = [table.column(c).to_numpy() for c in sd.PAIR_COLUMNS]
    a = ss.Spheres.from_columns(*cols[:7])
    b = ss.Spheres.from_columns(*cols[7:])
    t = ss.zip_times(a, b, t_max=math.inf)
    pq.write_table(
        table.append_column("time", pa.array(t)), out, compression="snappy", use_dictionary=False
    )
    return t


def bench_pairs(client, work, n, groups, repeat):
    rows = []
    base = None
    for group in groups:
        source = os.path.join(work, f"pairs-{group}")
        shutil.rmtree(source, ignore_errors=True)
        pairs_dataset(source, n, group)
        if base is None:
            base, _ = best(repeat, lambda: one_process_pairs(source, os.path.join(work, "one.parquet")))
        out = os.path.join(work, "pairs-out")
        seconds, summary = best(
            repeat,
            lambda: sd.zip_times_parquet(
                source, out, client=client, overwrite=True, split_row_groups=True
            ),
        )
        rows.append((group, summary.partitions, seconds))
        shutil.rmtree(source)
    print(f"\n### {n:,} pairs, Parquet in and out (snappy)\n")
    print(f"one process (pyarrow read, zip_times, write without dictionaries): {base:.3f} s, {n / base / 1e6:.2f} M pairs/s\n")
    print("| rows per partition | tasks | 2 workers | per task | M pairs/s | vs one process |")
    print("|---|---|---|---|---|---|")
    for group, tasks, seconds in rows:
        print(
            f"| {group:,} | {tasks} | {seconds:.3f} s | {seconds / tasks * 1e3:.1f} ms | "
            f"{n / seconds / 1e6:.2f} | {base / seconds:.2f}x |"
        )


def scene(n, seed=2):
    """Spheres at a packing fraction of ~0.1 in a box 8 times as long as it is wide."""
    rng = np.random.default_rng(seed)
    radii = rng.uniform(0.2, 0.5, n).astype(np.float32)
    volume = (4 / 3) * math.pi * float(np.mean(radii.astype(np.float64) ** 3)) * n / 0.1
    width = (volume / 8) ** (1 / 3)
    centres = rng.uniform([0, 0, 0], [8 * width, width, width], (n, 3)).astype(np.float32)
    velocities = rng.uniform(-1, 1, (n, 3)).astype(np.float32)
    return centres, velocities, radii, 8 * width


def bench_scene(client, n, slabs, t_max, repeat):
    c, v, r, length = scene(n)
    whole = ss.Scene(ss.Spheres(c, v, r))
    base, expected = best(repeat, lambda: ss.all_contacts(whole, t_max=t_max))
    base_with_build, _ = best(
        repeat, lambda: ss.all_contacts(ss.Scene(ss.Spheres(c, v, r)), t_max=t_max)
    )
    print(f"\n### whole-scene query, {n:,} spheres, box {length:.0f} long, t_max {t_max}\n")
    print(
        f"one process: {base:.3f} s query ({base_with_build:.3f} s with building the scene), "
        f"{len(expected.time):,} contacts; halo {sd.halo_width(c, v, r, t_max):.2f}\n"
    )
    print("| slabs | spheres per slab | slab width | halo fraction | 2 workers | vs one process |")
    print("|---|---|---|---|---|---|")
    for k in slabs:
        seconds, got = best(
            repeat, lambda: sd.all_contacts(c, v, r, t_max=t_max, partitions=k, client=client)
        )
        assert np.array_equal(got.time, expected.time) and np.array_equal(got.index, expected.index)
        print(
            f"| {k} | {n // k:,} | {length / k:.1f} | {got.plan.halo_fraction:.1%} | "
            f"{seconds:.3f} s | {base_with_build / seconds:.2f}x |"
        )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=4_000_000)
    parser.add_argument("--spheres", type=int, default=1_000_000)
    parser.add_argument("--t-max", type=float, default=1.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes, one run each")
    args = parser.parse_args()
    if args.quick:
        args.pairs //= 10
        args.spheres //= 10
        args.repeat = 1

    from distributed import Client, LocalCluster

    with LocalCluster(
        n_workers=2, threads_per_worker=1, host="127.0.0.1", processes=True,
        dashboard_address=":0",
    ) as cluster, Client(cluster) as client:  # fmt: skip
        per_task = task_overhead(client, 2000, args.repeat)
        print("### Dask on this machine\n")
        print(f"{os.cpu_count()} cores; 2 worker processes, 1 thread each")
        print(f"overhead per task (no-op tasks, 2000 in one batch): {per_task * 1e3:.3f} ms")
        work = tempfile.mkdtemp(prefix="bench-distributed-")
        try:
            n = args.pairs
            groups = [g for g in (n // 2, n // 8, n // 32, n // 128, n // 512) if g >= 500]
            bench_pairs(client, work, n, groups, args.repeat)
            bench_scene(client, args.spheres, (2, 4, 8, 16, 32, 64), args.t_max, args.repeat)
        finally:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
