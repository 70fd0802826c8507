#!/usr/bin/env python3
"""paired_rate.py -- two builds of the `sim_rate` example, run at the same time, one on each
core, then swapped: the ratio of their collision rates, B over A.

Usage:
    python3 scripts/paired_rate.py [--alone] A B N PHI T [REPS]

    A, B   two `sim_rate` binaries (`cargo build --release -p spheresweep-bench --example
           sim_rate`, copied aside for each version)
    N PHI T  the gas and its simulated time, as `sim_rate N PHI T`
    REPS   pairs of runs (default 10; keep it even, so each build runs as often on each core)

Why: this host is shared, and its speed drifts by 10-30 % within minutes, so two builds timed
one after the other differ by more than the change being measured. Run together, both see the
same host. The two cores are not alike either (one ran a build 25 % faster than the other in
one hour on 2026-12-03), so the builds swap cores every pair, and the summary is the geometric
mean of the ratios, in which each core's speed cancels. Needs `taskset` (util-linux).

--alone: one build at a time on core 0, A then B then B then A and so on, each pair's ratio
from its two runs. Slower, but each build has the caches and memory to itself, as in
`spheresweep bench`: run together, two builds share the L3 and the memory bus, and a build
that moves more bytes loses more to the other (2026-12-05: a change measured 0.94 paired and
1.01 alone at N = 4000, φ = 0.4).

Output: one line, "B/A N=.. phi=.. geomean R median M (each pair's ratio)".
"""
import math
import re
import statistics
import subprocess
import sys


def rate(out: str) -> int:
    m = re.search(r"(\d+) per second", out)
    if not m:
        sys.exit(f"paired_rate.py: no rate in the output: {out!r}")
    return int(m.group(1))


def alone(binary: str, n: str, phi: str, t: str) -> int:
    out = subprocess.run(["taskset", "-c", "0", binary, n, phi, t], stdout=subprocess.PIPE, text=True)
    return rate(out.stdout)


def main() -> None:
    args = sys.argv[1:]
    one_at_a_time = bool(args) and args[0] == "--alone"
    if one_at_a_time:
        args = args[1:]
    if len(args) not in (5, 6):
        sys.exit(__doc__)
    a, b, n, phi, t = args[:5]
    reps = int(args[5]) if len(args) == 6 else 10
    ratios = []
    for k in range(reps):
        if one_at_a_time:
            if k % 2 == 0:
                ra = alone(a, n, phi, t)
                rb = alone(b, n, phi, t)
            else:
                rb = alone(b, n, phi, t)
                ra = alone(a, n, phi, t)
        else:
            core_a, core_b = ("0", "1") if k % 2 == 0 else ("1", "0")
            pa = subprocess.Popen(["taskset", "-c", core_a, a, n, phi, t], stdout=subprocess.PIPE, text=True)
            pb = subprocess.Popen(["taskset", "-c", core_b, b, n, phi, t], stdout=subprocess.PIPE, text=True)
            ra, rb = rate(pa.communicate()[0]), rate(pb.communicate()[0])
        ratios.append(rb / ra)
    geo = math.exp(sum(map(math.log, ratios)) / len(ratios))
    print(
        f"{b.split('/')[-1]}/{a.split('/')[-1]} N={n} phi={phi}{' alone' if one_at_a_time else ''} geomean {geo:.3f} "
        f"median {statistics.median(ratios):.3f}  ({' '.join(f'{r:.2f}' for r in ratios)})"
    )


if __name__ == "__main__":
    main()
