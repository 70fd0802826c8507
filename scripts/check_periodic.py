#!/usr/bin/env python3
"""check_periodic.py -- a reader of an elastic periodic gas's trajectory that shares no code
with the engine: in every frame, no two spheres (by the minimum image) overlap by more than
2^-16 of their contact distance, and the kinetic energy and momentum (mass as radius cubed)
equal the first frame's within 1e-9 (relative). Exits non-zero on a violation.

Usage:
    python3 scripts/check_periodic.py TRAJECTORY.xyz

    TRAJECTORY.xyz  `spheresweep run`'s extended XYZ of a scene with a periodic boundary
                    (an orthogonal box, from each frame's Lattice; species, pos, velo, radius)
"""
import sys, math, collections, re
if len(sys.argv) != 2:
    sys.exit(__doc__)
path = sys.argv[1]
tol = 2.0**-16
worst = 0.0; frames = 0; e0 = p0 = None; drift = pdrift = 0.0
with open(path) as f:
    while True:
        line = f.readline()
        if not line: break
        n = int(line); head = f.readline()
        lat = [float(x) for x in re.search(r'Lattice="([^"]+)"', head).group(1).split()]
        box = (lat[0], lat[4], lat[8])  # an orthogonal box: the lattice's diagonal
        pts = []; e = 0.0; p = [0.0, 0.0, 0.0]
        for _ in range(n):
            w = f.readline().split()
            pos = [float(w[1 + k]) % box[k] for k in range(3)]
            v = [float(w[4]), float(w[5]), float(w[6])]; r = float(w[7])
            m = r**3
            e += 0.5 * m * sum(c*c for c in v); p = [p[k] + m*v[k] for k in range(3)]
            pts.append((pos[0], pos[1], pos[2], r))
        if e0 is None: e0, p0 = e, p
        drift = max(drift, abs(e - e0) / e0)
        pdrift = max(pdrift, max(abs(p[k] - p0[k]) for k in range(3)) / math.sqrt(2 * e0))
        frames += 1
        # Cells at least one largest diameter wide: any two spheres in contact are in
        # neighbouring cells (or the same one).
        dmax = 2 * max(q[3] for q in pts)
        nc = [max(1, int(box[k] // dmax)) for k in range(3)]
        cw = [box[k] / nc[k] for k in range(3)]
        cells = collections.defaultdict(list)
        for k, (x, y, z, r) in enumerate(pts):
            cells[tuple(int(q / cw[a]) % nc[a] for a, q in enumerate((x, y, z)))].append(k)
        for (cx, cy, cz), ks in cells.items():
            seen = set()
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for dz in (-1, 0, 1):
                        key = ((cx+dx) % nc[0], (cy+dy) % nc[1], (cz+dz) % nc[2])
                        if key in seen: continue
                        seen.add(key)
                        for b in cells.get(key, ()):
                            for a in ks:
                                if a < b:
                                    pa, pb = pts[a], pts[b]
                                    d2 = 0.0
                                    for k in range(3):
                                        t = pa[k] - pb[k]; t -= box[k] * round(t / box[k]); d2 += t*t
                                    d = pa[3] + pb[3]
                                    worst = max(worst, (d - math.sqrt(d2)) / d)
print(f"{path}: {frames} frames, deepest overlap {worst:.3e} of d, energy drift {drift:.1e}, momentum drift {pdrift:.1e}")
assert worst <= tol and drift <= 1e-9 and pdrift <= 1e-9, "violation"
