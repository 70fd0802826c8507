#!/usr/bin/env python3
"""Summarise the broad-phase and whole-query criterion results (target/criterion) as tables
with ratios to parry3d measured in the same group, and draw the scaling plot.

Usage: python3 scripts/broad_table.py [--svg docs/scaling.svg]
Groups read: broad_* (grid, grid-2-threads, parry-bvh-incremental, parry-bvh-rebuild) and
query_* (stable-compact and stable, each also on two threads, parry-bvh-cast_shapes). Times are criterion's medians per
sphere; ratios are within one run, so they hold when the shared machine's speed drifts.
"""
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from criterion_table import read, root  # noqa: E402  (one reader of criterion's files)


def table(group, peer, pairs):
    """One table of `group`: every line's median per sphere, then for each (ours, two) of
    `pairs` the ratio peer / ours and the two-thread speed-up ours / two."""
    rows = read(group)
    if not rows:
        return
    sizes = sorted({n for line in rows.values() for n in line})
    pairs = [(o, t) for o, t in pairs if o in rows]
    print(f"\n**{group}** (ns per sphere; × = {peer} / ours)\n")
    lines = sorted(rows)
    heads = [f"× {peer} ({o})" for o, _ in pairs] + [f"{o}: 2 threads speed-up" for o, _ in pairs]
    print("| N | " + " | ".join(lines + heads) + " |")
    print("|---:|" + "---:|" * (len(lines) + len(heads)))
    for n in sizes:
        cells = [f"{rows[l][n]:.1f}" if n in rows[l] else "–" for l in lines]
        ratios = [
            f"{rows[peer][n] / rows[o][n]:.1f}×" if n in rows.get(peer, {}) and n in rows[o] else "–"
            for o, _ in pairs
        ]
        speeds = [
            f"{rows[o][n] / rows[t][n]:.2f}×" if n in rows.get(t, {}) and n in rows[o] else "–"
            for o, t in pairs
        ]
        print(f"| {n:,} | " + " | ".join(cells + ratios + speeds) + " |")


def svg(path):
    series = []
    colours = ["#1f77b4", "#d62728", "#ff7f0e", "#2ca02c", "#9467bd"]
    wanted = [
        ("broad_gas_phi0.3_travel0.5r", "grid", "grid broad phase"),
        ("broad_gas_phi0.3_travel0.5r", "parry-bvh-incremental", "parry Bvh incremental"),
        ("broad_gas_phi0.3_travel0.5r", "parry-bvh-rebuild", "parry Bvh rebuilt"),
        ("query_gas_phi0.3_travel0.5r", "stable", "whole query (ours)"),
        ("query_gas_phi0.3_travel0.5r", "parry-bvh-cast_shapes", "whole query (parry)"),
    ]
    for (group, line, label), colour in zip(wanted, colours):
        pts = sorted(read(group).get(line, {}).items())
        if pts:
            series.append((label, colour, pts))
    if not series:
        return
    w, h, left, bottom, top, right = 720, 420, 70, 50, 20, 230
    xs = [math.log10(n) for _, _, pts in series for n, _ in pts]
    ys = [math.log10(v) for _, _, pts in series for _, v in pts]
    x0, x1 = math.floor(min(xs)), math.ceil(max(xs))
    y0, y1 = math.floor(min(ys)), math.ceil(max(ys))
    px = lambda x: left + (x - x0) / (x1 - x0) * (w - left - right)
    py = lambda y: h - bottom - (y - y0) / (y1 - y0) * (h - bottom - top)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
        f'font-family="sans-serif" font-size="12">',
        f'<rect width="{w}" height="{h}" fill="white"/>',
    ]
    for d in range(x0, x1 + 1):
        out.append(f'<line x1="{px(d)}" y1="{py(y0)}" x2="{px(d)}" y2="{py(y1)}" stroke="#ddd"/>')
        out.append(f'<text x="{px(d)}" y="{h - bottom + 18}" text-anchor="middle">10^{d}</text>')
    for d in range(y0, y1 + 1):
        out.append(f'<line x1="{px(x0)}" y1="{py(d)}" x2="{px(x1)}" y2="{py(d)}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 8}" y="{py(d) + 4}" text-anchor="end">{10 ** d:g}</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{h - 10}" text-anchor="middle">spheres N</text>')
    out.append(
        f'<text x="16" y="{(top + h - bottom) / 2}" text-anchor="middle" '
        f'transform="rotate(-90 16 {(top + h - bottom) / 2})">ns per sphere (one core)</text>'
    )
    for k, (label, colour, pts) in enumerate(series):
        path_d = " ".join(
            f"{'M' if i == 0 else 'L'}{px(math.log10(n)):.1f},{py(math.log10(v)):.1f}"
            for i, (n, v) in enumerate(pts)
        )
        out.append(f'<path d="{path_d}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for n, v in pts:
            out.append(
                f'<circle cx="{px(math.log10(n)):.1f}" cy="{py(math.log10(v)):.1f}" r="3" fill="{colour}"/>'
            )
        ly = top + 20 + 22 * k
        out.append(f'<line x1="{w - right + 15}" y1="{ly}" x2="{w - right + 40}" y2="{ly}" stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{w - right + 46}" y="{ly + 4}">{label}</text>')
    out.append(
        f'<text x="{w - right + 15}" y="{top + 20 + 22 * len(series) + 10}" fill="#555">'
        "uniform gas, φ = 0.3, half a radius of travel</text>"
    )
    out.append("</svg>")
    pathlib.Path(path).write_text("\n".join(out) + "\n")
    print(f"\nwrote {path}")


groups = sorted(p.name for p in root.glob("broad_*")) if root.exists() else []
for group in groups:
    table(group, "parry-bvh-incremental", [("grid", "grid-2-threads")])
for group in sorted(p.name for p in root.glob("query_*")) if root.exists() else []:
    table(
        group,
        "parry-bvh-cast_shapes",
        [("stable-compact", "stable-compact-2-threads"), ("stable", "stable-2-threads")],
    )
if "--svg" in sys.argv:
    svg(sys.argv[sys.argv.index("--svg") + 1])
