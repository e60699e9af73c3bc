#!/usr/bin/env python3
"""Writes a molar crown as a closed triangle mesh (OFF): a rounded block with four cusps around a
central fossa, occlusal surface up (+y), 10 x 10 mm across and 8.6 mm tall in model units of
millimetres (scripts/molar_burr_example.sh drills it in the studio).

The vertices of a subdivided icosahedron are pushed out along their directions to a
superellipsoid (the crown's body), then the occlusal side is raised by the cusps: four
half-ellipsoid domes at the corners of a square about the centre, joined to each other and to
the body's top by a smooth maximum, so that the central fossa is the crease where the four domes
meet and each dome is convex down to its foot. The relief is blended in over the upper half. The
script checks that the surface stays star-shaped about the origin (every face seen from it from
outside), so the mesh is closed, manifold and free of self-intersections, wound outward.

Usage: molar_crown.py OUT.off [--subdivisions N]
"""
import argparse

import numpy as np

BODY = np.array([5.0, 3.0, 5.0])  # superellipsoid semi-axes x, y, z [mm]
BODY_POWER = 4.0                  # its exponent: 2 an ellipsoid, larger a boxier block
CUSP_AT = 1.8                     # cusp centres at (±CUSP_AT, ±CUSP_AT) in x, z [mm]
CUSP_HEIGHT, CUSP_RADIUS = 2.6, 2.9  # a dome's height over the body's top and its base radius [mm]
SMOOTHING = 0.15                     # how far the smooth maximum rounds the grooves and the fossa [mm]


def icosphere(subdivisions):
    """Unit icosphere: vertices (n, 3) on the unit sphere, faces (m, 3) wound outward."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(subdivisions):
        midpoint = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                m = verts[a] + verts[b]
                verts.append(m / np.linalg.norm(m))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        nf = []
        for a, b, c in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = nf
    return np.array(verts), np.array(faces, dtype=np.int64)


def occlusal_height(x, z):
    """Height the cusps add over the crown's body at (x, z) [mm]: four half-ellipsoid domes (convex
    all the way down, most curved at their feet) and the body's top (0), joined by a smooth maximum
    (a log-sum-exp over SMOOTHING)."""
    heights = [np.zeros_like(x)]
    for sx in (-1, 1):
        for sz in (-1, 1):
            d2 = (x - sx * CUSP_AT) ** 2 + (z - sz * CUSP_AT) ** 2
            heights.append(CUSP_HEIGHT * np.sqrt(np.maximum(1 - d2 / CUSP_RADIUS ** 2, 0)))
    return SMOOTHING * np.log(np.sum(np.exp(np.array(heights) / SMOOTHING), axis=0))


def crown(subdivisions):
    """The crown's vertices (n, 3) [mm] and faces (m, 3)."""
    d, faces = icosphere(subdivisions)
    body = np.sum((np.abs(d) / BODY) ** BODY_POWER, axis=1) ** (-1 / BODY_POWER)
    p = body[:, None] * d
    # The occlusal relief, blended in smoothly from the crown's equator (d_y = 0.3) to its top (0.7).
    s = np.clip((d[:, 1] - 0.3) / 0.4, 0, 1)
    blend = s * s * (3 - 2 * s)
    p[:, 1] += blend * occlusal_height(p[:, 0], p[:, 2])
    # Star-shaped about the origin (every face seen from it from outside): closed, no self-intersection.
    a, b, c = p[faces[:, 0]], p[faces[:, 1]], p[faces[:, 2]]
    if not np.all(np.einsum("ij,ij->i", np.cross(b - a, c - a), a + b + c) > 0):
        raise ValueError("the occlusal relief folds the surface over")
    return p, faces


def write_off(path, verts, faces):
    """Writes the triangle mesh (verts, faces) to an OFF file."""
    with open(path, "w") as f:
        f.write(f"OFF\n{len(verts)} {len(faces)} 0\n")
        np.savetxt(f, verts, fmt="%.6f")
        np.savetxt(f, np.hstack([np.full((len(faces), 1), 3), faces]), fmt="%d")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="output OFF file")
    ap.add_argument("--subdivisions", type=int, default=6, help="icosahedron subdivisions (6: 81920 faces)")
    a = ap.parse_args()
    verts, faces = crown(a.subdivisions)
    write_off(a.out, verts, faces)


if __name__ == "__main__":
    main()
