#!/usr/bin/env python3
"""check_periodic.py -- a reader of an elastic periodic gas's trajectory that shares no code
with the engine: in every frame, no two spheres (by the minimum image) overlap by more than
2^-16 of their contact distance, and the kinetic energy and momentum (mass as radius cubed)
equal the first frame's within 1e-9 (relative). Exits non-zero on a violation.

Usage:
    python3 scripts/check_periodic.py TRAJECTORY.xyz

    TRAJECTORY.xyz  `spheresweep run`'s extended XYZ of a scene with a periodic boundary
                    (the box from each frame's Lattice; species, pos, velo, radius columns)
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
        L = float(re.search(r'Lattice="([^ ]+)', head).group(1))
        pts = []; e = 0.0; p = [0.0, 0.0, 0.0]
        for _ in range(n):
            w = f.readline().split()
            x, y, z = (float(w[1]) % L, float(w[2]) % L, float(w[3]) % L)
            v = [float(w[4]), float(w[5]), float(w[6])]; r = float(w[7])
            m = r**3
            e += 0.5 * m * sum(c*c for c in v); p = [p[k] + m*v[k] for k in range(3)]
            pts.append((x, y, z, r))
        if e0 is None: e0, p0 = e, p
        drift = max(drift, abs(e - e0) / e0)
        pdrift = max(pdrift, max(abs(p[k] - p0[k]) for k in range(3)) / math.sqrt(2 * e0))
        frames += 1
        nc = max(1, int(L // 1.0)); w = L / nc
        cells = collections.defaultdict(list)
        for k, (x, y, z, r) in enumerate(pts):
            cells[(int(x / w) % nc, int(y / w) % nc, int(z / w) % nc)].append(k)
        for (cx, cy, cz), ks in cells.items():
            seen = set()
            for dx in (-1, 0, 1):
                for dy in (-1, 0, 1):
                    for dz in (-1, 0, 1):
                        key = ((cx+dx) % nc, (cy+dy) % nc, (cz+dz) % nc)
                        if key in seen: continue
                        seen.add(key)
                        for b in cells.get(key, ()):
                            for a in ks:
                                if a < b:
                                    pa, pb = pts[a], pts[b]
                                    d2 = 0.0
                                    for k in range(3):
                                        t = pa[k] - pb[k]; t -= L * round(t / L); d2 += t*t
                                    d = pa[3] + pb[3]
                                    worst = max(worst, (d - math.sqrt(d2)) / d)
print(f"{path}: {frames} frames, deepest overlap {worst:.3e} of d, energy drift {drift:.1e}, momentum drift {pdrift:.1e}")
assert worst <= tol and drift <= 1e-9 and pdrift <= 1e-9, "violation"
