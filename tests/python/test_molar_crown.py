# SPDX-License-Identifier: MIT
"""The molar crown of scripts/molar_crown.py (the studio's burr example drills it): a closed,
outward-wound surface of a sphere's topology, with four cusps around a lower central fossa, that
hdm bakes within its error bound."""
import os
import subprocess
import sys

import numpy as np

import hdm

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "molar_crown.py")


def read_off(path):
    with open(path) as f:
        assert f.readline().strip() == "OFF"
        nv, nf, _ = (int(x) for x in f.readline().split())
        v = np.array([[float(x) for x in f.readline().split()] for _ in range(nv)])
        faces = np.array([[int(x) for x in f.readline().split()] for _ in range(nf)])
    assert np.all(faces[:, 0] == 3)
    return v, faces[:, 1:]


def test_crown_is_closed_outward_with_four_cusps_and_bakes(tmp_path):
    off = str(tmp_path / "molar.off")
    subprocess.run([sys.executable, SCRIPT, off, "--subdivisions", "5"], check=True)
    v, f = read_off(off)
    # Closed and consistently wound: every directed edge once, and its reverse once.
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    keys = set(map(tuple, directed))
    assert len(keys) == len(directed)
    assert all((b, a) in keys for a, b in keys)
    # A sphere's topology (V - E + F = 2) and outward winding (positive divergence-theorem volume).
    assert len(v) - len(directed) // 2 + len(f) == 2
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    assert np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6 > 0
    # Four cusps: in each quadrant of the occlusal side (+y) the highest point stands over the
    # quadrant's diagonal, and the fossa at the centre lies at least 1 mm below every cusp tip.
    top = v[v[:, 1] > 0]
    fossa = top[np.hypot(top[:, 0], top[:, 2]) < 0.3, 1].min()
    for sx in (-1, 1):
        for sz in (-1, 1):
            q = top[(sx * top[:, 0] > 0) & (sz * top[:, 2] > 0)]
            tip = q[q[:, 1].argmax()]
            assert abs(abs(tip[0]) - abs(tip[2])) < 0.3, tip
            assert 1.0 < abs(tip[0]) < 3.0, tip
            assert tip[1] - fossa > 1.0, (tip, fossa)
    _, report = hdm.bake(off)
    assert report["bound_met"]
