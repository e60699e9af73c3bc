# SPDX-License-Identifier: MIT
"""The Python module against independent references: an analytic sphere, brute-force NumPy
distances to the input mesh, round trips through files, and hdm's error messages."""
import os

import numpy as np
import pytest

import hdm

DATA = os.environ.get("HDM_DATA_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "data", "meshes"))


def icosphere(subdivisions):
    """Unit icosphere: (V, 3) float64 vertices on the sphere, (F, 3) faces counter-clockwise from outside."""
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                mid[key] = len(verts) - 1
            return mid[key]

        f = [tri for a, b, c in f for tri in ((a, middle(a, b), middle(c, a)), (b, middle(b, c), middle(a, b)),
                                                (c, middle(c, a), middle(b, c)),
                                                (middle(a, b), middle(b, c), middle(c, a)))]
    return np.array(verts), np.array(f, dtype=np.int64)


@pytest.fixture(scope="module")
def sphere():
    model, report = hdm.bake(icosphere(4))
    return model, report


def test_bake_report_meets_the_default_bound(sphere):
    model, report = sphere
    assert report["bound_met"]
    assert report["invalid_slabs"] == 0 and model.invalid_slabs == 0
    assert report["slabs"] == model.slab_count > 0
    assert max(report["fidelity"]["max_pct"], report["fidelity"]["max_back_pct"]) <= 0.2


def test_query_matches_the_analytic_sphere(sphere):
    model, _ = sphere
    rng = np.random.default_rng(7)
    d = rng.normal(size=(20000, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    r = rng.uniform(0.0, 1.6, 20000)
    p = d * r[:, None]
    q = model.query(p)
    assert q["inside"].dtype == bool and q["slab"].dtype == np.int32
    assert q["surface_point"].shape == (20000, 3) and q["normal"].shape == (20000, 3)
    # The icosphere's facets lie within 1 - cos(edge/2) ~ 0.2 % of the unit sphere: away from that
    # band, inside means r < 1.
    clear = np.abs(r - 1) > 0.01
    assert np.all(q["inside"][clear] == (r[clear] < 1))
    shell = q["slab"] >= 0
    assert shell.sum() > 1000
    assert np.allclose(np.linalg.norm(q["surface_point"][shell], axis=1), 1.0, atol=0.005)
    cos = np.sum(q["normal"][shell] * d[shell], axis=1)
    assert np.all(cos > np.cos(np.radians(10)))
    # depth: the distance below the surface's tangent plane, about 1 - r near the surface
    near = shell & (np.abs(r - 1) < 0.02)
    assert np.allclose(q["depth"][near], 1 - r[near], atol=0.003)
    assert np.all(np.isnan(q["depth"][~shell]))


def test_non_finite_points_are_in_no_slab(sphere):
    model, _ = sphere
    q = model.query(np.array([[np.nan, 0, 0], [np.inf, 0, 0], [0.0, 0.0, 0.0]]))
    assert list(q["slab"][:2]) == [-1, -1]
    assert not q["inside"][0] and not q["inside"][1]
    assert q["inside"][2]


def test_an_open_sheet_is_judged_by_the_side_of_its_surface(tmp_path):
    """An open model encloses nothing: a point in no slab is inside when it lies behind the nearest
    face of the surface (hdm check's rule for open inputs). Reference: the analytic height field."""
    from conftest import write_off
    n = 40
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    height = lambda x, y: 0.05 * np.sin(2 * np.pi * x) * np.sin(2 * np.pi * y)
    v = np.column_stack([x.ravel(), y.ravel(), height(x, y).ravel()])
    f = []
    for i in range(n):
        for j in range(n):
            a = i * (n + 1) + j  # counter-clockwise seen from +z: the material lies below
            f += [(a, a + n + 1, a + n + 2), (a, a + n + 2, a + 1)]
    off = str(tmp_path / "sheet.off")
    write_off(off, v, f)
    model, _ = hdm.bake(off)
    rng = np.random.default_rng(11)
    p = np.column_stack([rng.uniform(0.2, 0.8, 4000), rng.uniform(0.2, 0.8, 4000), rng.uniform(-0.5, 0.5, 4000)])
    q = model.query(p)
    outside_shells = q["slab"] < 0
    assert outside_shells.sum() > 2000  # most points lie beyond the slabs' shells
    below = p[:, 2] < height(p[:, 0], p[:, 1])
    np.testing.assert_array_equal(q["inside"][outside_shells], below[outside_shells])


def test_save_and_load_round_trip(sphere, tmp_path):
    model, _ = sphere
    path = str(tmp_path / "sphere.hdm")
    model.save(path)
    again = hdm.load(path)
    p = np.random.default_rng(3).uniform(-1.2, 1.2, (5000, 3))
    a, b = model.query(p), again.query(p)
    for key in a:
        np.testing.assert_array_equal(a[key], b[key])
    v1, f1 = model.surface()
    v2, f2 = again.surface()
    np.testing.assert_array_equal(f1, f2)
    np.testing.assert_allclose(v1, v2, rtol=0, atol=1e-6)


def distance_to_triangles(p, a, b, c):
    """Distance from point p (3,) to each triangle (a, b, c: (M, 3) corners), by brute force: the
    projection when it falls inside, else the nearest of the three edges."""
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1)[:, None]
    s = np.sum((p - a) * n, axis=1)
    h = p - s[:, None] * n

    def left(x, y):
        return np.sum(np.cross(y - x, h - x) * n, axis=1) >= 0

    d = np.where(left(a, b) & left(b, c) & left(c, a), np.abs(s), np.inf)
    for x, y in ((a, b), (b, c), (c, a)):
        e = y - x
        t = np.clip(np.sum((p - x) * e, axis=1) / np.sum(e * e, axis=1), 0, 1)
        d = np.minimum(d, np.linalg.norm(p - (x + t[:, None] * e), axis=1))
    return d


def read_off(path):
    with open(path) as f:
        words = [w for line in f for w in line.split("#")[0].split()]
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    v = np.array(words[4:4 + 3 * nv], float).reshape(nv, 3)
    rows, k = [], 4 + 3 * nv
    for _ in range(nf):
        n = int(words[k])
        rows.append([int(w) for w in words[k + 1:k + 1 + n]][:3])
        k += 1 + n
    return v, np.array(rows)


def test_bunny_surface_lies_within_the_bound_of_the_input():
    path = os.path.join(DATA, "bunny00.off")
    model, report = hdm.bake(path)
    assert report["bound_met"] and report["input_triangles"] == 75408
    v, f = read_off(path)
    diag = np.linalg.norm(v.max(0) - v.min(0))
    sv, _ = model.surface()
    pick = sv[np.random.default_rng(5).choice(len(sv), 60, replace=False)]
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    best = np.array([distance_to_triangles(x, a, b, c).min() for x in pick])
    assert np.all(100 * best / diag <= report["fidelity"]["max_pct"] + 1e-6)


def test_export_writes_the_surface(sphere, tmp_path):
    model, _ = sphere
    out = tmp_path / "sphere.ply"
    model.export(str(out))
    assert out.read_bytes().startswith(b"ply")


def test_errors_carry_hdm_messages(tmp_path):
    v, f = icosphere(1)
    bad = f.copy()
    bad[0, 0] = 10**6
    with pytest.raises(ValueError, match="faces: row 0 names vertex 1000000"):
        hdm.bake((v, bad))
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        hdm.bake((v[:, :2], f))
    missing = str(tmp_path / "nothing.off")
    with pytest.raises((OSError, ValueError), match="nothing.off"):
        hdm.bake(missing)
    with pytest.raises((OSError, ValueError), match="nothing.hdm"):
        hdm.load(str(tmp_path / "nothing.hdm"))
    model, _ = hdm.bake((v, f), slabs=20, error_bound=False)
    with pytest.raises(ValueError, match="points"):
        model.query(np.zeros((4, 2)))
