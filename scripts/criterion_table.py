#!/usr/bin/env python3
"""Summarise criterion results (target/criterion) as pairs per second and ratios to parry3d.

Usage: python3 scripts/criterion_table.py [group ...]
Prints one Markdown table per group and size: median time per pair, pairs per second, and the
ratio of every line to the parry3d `cast_shapes` line of the same group and size (one run, so
the ratios hold even when the shared machine's absolute speed drifts).
"""
import json
import pathlib
import sys

root = pathlib.Path("target/criterion")


def read(group):
    """Criterion's median time per element of every line of `group`: {line: {size: ns}}."""
    rows = {}
    for est in sorted((root / group).glob("*/new/estimates.json")):
        name = est.parent.parent.name
        line, _, size = name.rpartition("_")
        bench = json.loads((est.parent / "benchmark.json").read_text())
        n = bench["throughput"]["Elements"]
        median_ns = json.loads(est.read_text())["median"]["point_estimate"]
        rows.setdefault(line, {})[int(size)] = median_ns / n
    return rows


if __name__ == "__main__":
    groups = sys.argv[1:] or ["sphere_sphere", "sphere_plane", "sphere_cylinder", "sphere_container"]
    for group in groups:
        by_size = {}
        for line, sizes in read(group).items():
            for size, ns in sizes.items():
                by_size.setdefault(size, []).append((line, ns))
        for size, lines in sorted(by_size.items()):
            peer = dict(lines).get("parry-cast_shapes")
            print(f"\n**{group}, {size} pairs**\n")
            print("| line | ns / pair | M pairs / s | × parry cast_shapes |")
            print("|---|---:|---:|---:|")
            for line, ns in sorted(lines, key=lambda l: l[1]):
                ratio = f"{peer / ns:.1f}" if peer else "–"
                print(f"| {line} | {ns:.3f} | {1e3 / ns:.1f} | {ratio} |")
