# SPDX-License-Identifier: MIT
"""Direct light on the Cornell ceiling behind the lamp, by quadrature, for the smooth-normal case.

The room of cornellBox_Vinc3r has corner-averaged vertex normals, so the ceiling's shading
normal leans up to 45 deg towards the room; the only direct light reaching the ceiling comes
from the 1 cm high sides of the lamp box, at grazing incidence to the geometric surface. This
integrates L = albedo / pi * int L_e max(0, wi.n_shading) cos_light / r^2 dA over the four
side faces (emitting to the front, L_e = 1), keeping only directions above the geometric
surface (as xrsc's xs_side_ok does), for the pixels of compare.py's "ceiling behind lamp"
region, and prints it next to the region means of a direct-only render:

    python3 bench/cycles/compare.py cornell-lambert --bounces 1 --work W --out O
    python3 bench/cycles/ceiling_direct.py W

`ceiling_direct.py W back-wall` does the same for the "back wall" region (z = -2, flat normal
+z, lit by the lamp's bottom face and sides, nothing in between), for a
`compare.py cornell-lambert-flat --bounces 1` render.
"""
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402

ALBEDO = 0.8
EYE = np.array([0.0, 1.5, 4.4])  # render_cycles.py's viewpoint of this scene
# ceiling vertices (glTF mesh 3, primitive 0) and their normals, as in the file
VERTS = {4: ((2, 3, 2), (-0.71, -0.71, 0)), 5: ((-2, 3, -2), (0.58, -0.58, 0.58)),
         6: ((2, 3, -2), (-0.58, -0.58, 0.58)), 7: ((-2, 3, 2), (0.71, -0.71, 0))}


def lamp_sides(n=300, m=20):
    s = (np.arange(n) + 0.5) / n * 0.75 - 0.375
    h = 2.99 + (np.arange(m) + 0.5) / m * 0.01
    S, H = np.meshgrid(s, h)
    c = np.full_like(S, 0.375)
    faces = [((0, 0, -1), (S, H, -c)), ((0, 0, 1), (S, H, c)), ((-1, 0, 0), (-c, H, S)),
             ((1, 0, 0), (c, H, S))]
    return [(np.array(nl, float), np.stack(q, -1).reshape(-1, 3)) for nl, q in faces], \
        (0.75 / n) * (0.01 / m)


def shading_normal(p):
    for tri in ((4, 5, 6), (4, 7, 5)):
        a, b, c = (np.array(VERTS[i][0], float) for i in tri)
        m = np.array([[b[0] - a[0], c[0] - a[0]], [b[2] - a[2], c[2] - a[2]]])
        l = np.linalg.solve(m, [p[0] - a[0], p[2] - a[2]])
        w = np.array([1 - l.sum(), l[0], l[1]])
        if (w >= -1e-9).all():
            n = sum(w[k] * np.array(VERTS[tri[k]][1]) for k in range(3))
            return n / np.linalg.norm(n)
    raise ValueError("not on the ceiling")


def direct(p, faces, da):
    ns, e = shading_normal(p), 0.0
    for nl, q in faces:
        d = q - p
        r2 = (d * d).sum(1)
        wi = d / np.sqrt(r2)[:, None]
        cl, cg, cs = -(wi @ nl), -wi[:, 1], wi @ ns
        e += np.sum(np.where((cl > 0) & (cg > 0) & (cs > 0), cl * cs / r2, 0.0)) * da
    return ALBEDO / np.pi * e


def lamp_bottom(n=200):
    s = (np.arange(n) + 0.5) / n * 0.75 - 0.375
    x, z = np.meshgrid(s, s)
    q = np.stack([x, np.full_like(x, 2.99), z], -1).reshape(-1, 3)
    return np.array([0.0, -1.0, 0.0]), q, (0.75 / n) ** 2


def back_wall(work):
    sides, da = lamp_sides()
    emitters = [lamp_bottom()] + [(nl, q, da) for nl, q in sides]
    t = np.tan(np.radians(compare.FOV_DEG / 2))
    _, x0, y0, x1, y1 = [r for r in compare.CORNELL_REGIONS if r[0] == "back wall"][0]
    vals = []
    for py in range(y0, y1):
        for px in range(x0, x1):
            u, v = (px + 0.5) / compare.RES, (py + 0.5) / compare.RES
            d = np.array([(2 * u - 1) * t, (1 - 2 * v) * t, -1.0])
            p = EYE + (-2.0 - EYE[2]) / d[2] * d
            e = 0.0
            for nl, q, dq in emitters:
                dd = q - p
                r2 = (dd * dd).sum(1)
                wi = dd / np.sqrt(r2)[:, None]
                cl, cr = -(wi @ nl), wi[:, 2]
                e += np.sum(np.where((cl > 0) & (cr > 0), cl * cr / r2, 0.0)) * dq
            vals.append(ALBEDO / np.pi * e)
    return np.mean(vals), (x0, y0, x1, y1)


def main():
    work = sys.argv[1]
    if len(sys.argv) > 2 and sys.argv[2] == "back-wall":
        q, (x0, y0, x1, y1) = back_wall(work)
        print("quadrature (flat normal, unoccluded): %.4e" % q)
        for who in ("xrsc", "cycles"):
            imgs = [compare.read_pfm(f) for f in glob.glob(os.path.join(work, who, "*.pfm"))]
            g = np.mean(imgs, axis=0)[y0:y1, x0:x1, 1]
            print("%-6s region mean (G): %.4e" % (who, g.mean()))
        return
    faces, da = lamp_sides()
    t = np.tan(np.radians(compare.FOV_DEG / 2))
    _, x0, y0, x1, y1 = [r for r in compare.CORNELL_REGIONS if r[0] == "ceiling behind lamp"][0]
    vals = []
    for py in range(y0, y1):
        for px in range(x0, x1):
            u, v = (px + 0.5) / compare.RES, (py + 0.5) / compare.RES
            d = np.array([(2 * u - 1) * t, (1 - 2 * v) * t, -1.0])
            vals.append(direct(EYE + (3.0 - EYE[1]) / d[1] * d, faces, da))
    print("quadrature (shading-normal cosine, geometric side test): %.4e" % np.mean(vals))
    for who in ("xrsc", "cycles"):
        imgs = [compare.read_pfm(f) for f in glob.glob(os.path.join(work, who, "*.pfm"))]
        g = np.mean(imgs, axis=0)[y0:y1, x0:x1, 1]
        print("%-6s region mean (G): %.4e" % (who, g.mean()))


if __name__ == "__main__":
    main()
