# SPDX-License-Identifier: MIT
"""Edits against analytic references on the unit sphere: carve is the boolean difference with the
tool ball, add the union with the ridge's ball, paint changes exactly the samples within the brush
radius (brute-force NumPy distances), flatten moves samples towards the tool plane, smooth keeps
the displacements within their former range; undo and redo restore the model bit for bit."""
import numpy as np
import pytest

import hdm

DIRECTION = np.array([0.3, -0.2, 0.93]) / np.linalg.norm([0.3, -0.2, 0.93])


def sample_points(n, seed, radius=1.3):
    """Half of the points spread around the sphere, half in a cube of side 0.3 around the tools."""
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n - n // 2, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    spread = d * rng.uniform(0.5, radius, len(d))[:, None]
    return np.concatenate([spread, DIRECTION + rng.uniform(-0.15, 0.15, (n // 2, 3))])


def near(points, centre, r):
    return np.linalg.norm(points - centre, axis=1) < r


def test_carve_removes_the_tool_ball_from_the_sphere(fresh_sphere):
    model = fresh_sphere
    hip = 0.95 * DIRECTION  # the tool's bottom, 5 % below the surface
    r = 0.15
    out = model.carve(hip[None], r)
    assert out["tool_positions"] == 1 and out["changed"] > 0
    ball = hip + r * DIRECTION  # the tool ball sits on the HIP, along the contact normal (radial)
    p = sample_points(60000, 3)
    q = model.query(p)
    rr = np.linalg.norm(p, axis=1)
    dist = np.linalg.norm(p - ball, axis=1)
    clear = (np.abs(rr - 1) > 0.01) & (np.abs(dist - r) > 0.02)
    expected = (rr < 1) & (dist > r)
    assert np.sum(clear & (dist < r) & (rr < 1)) > 50  # points the carve removed
    np.testing.assert_array_equal(q["inside"][clear], expected[clear])


def test_add_unites_the_ridge_ball_with_the_sphere(fresh_sphere):
    model = fresh_sphere
    outer = np.linalg.norm(model.box, axis=1).min() / np.sqrt(3)  # the slabs' outer reach along a diagonal
    h, r = min(0.03, 0.5 * (outer - 1)), 0.15
    assert h > 0.005
    out = model.add(0.999 * DIRECTION[None], r, height=h)
    assert out["changed"] > 0
    ball = (1 + h - r) * DIRECTION  # top `height` above the surface at the contact
    p = sample_points(60000, 4)
    q = model.query(p)
    rr = np.linalg.norm(p, axis=1)
    dist = np.linalg.norm(p - ball, axis=1)
    clear = (np.abs(rr - 1) > 0.01) & (np.abs(dist - r) > 0.01)
    # Where the ridge meets the sphere the union has a concave crease (a circle), which the samples'
    # linear interpolation fills by a fraction of the grid spacing: points within 0.03 of that
    # circle are left out (one, 0.0105 from both surfaces, was inside by 0.0007).
    c = np.linalg.norm(ball)
    a = (1 + c * c - r * r) / (2 * c)  # the circle's plane along DIRECTION, and its radius
    t = p @ DIRECTION
    to_crease = np.hypot(t - a, np.linalg.norm(p - t[:, None] * DIRECTION, axis=1) - np.sqrt(1 - a * a))
    clear &= to_crease > 0.03
    expected = (rr < 1) | (dist < r)
    assert np.sum(clear & (dist < r) & (rr > 1)) > 5  # points the ridge added
    np.testing.assert_array_equal(q["inside"][clear], expected[clear])


def test_undo_and_redo_restore_the_model_bit_for_bit(fresh_sphere):
    model = fresh_sphere
    p = sample_points(20000, 5)
    before = model.query(p)
    assert not model.undo()  # nothing to undo yet
    model.carve(np.array([0.96 * DIRECTION, 0.96 * np.array([0.0, 0.0, 1.0])]), 0.1)
    after = model.query(p)
    assert np.any(after["inside"] != before["inside"])
    assert model.undo()
    for key in before:
        np.testing.assert_array_equal(model.query(p)[key], before[key])
    assert model.redo()
    for key in after:
        np.testing.assert_array_equal(model.query(p)[key], after[key])
    assert not model.redo()


def test_paint_writes_the_field_exactly_within_the_radius(fresh_sphere):
    model = fresh_sphere
    base = model.field("friction_static").copy()
    pos = model.field("positions")
    assert pos.shape == (len(base), 3) and base.dtype == np.float32
    hip = 0.998 * DIRECTION
    centre = model.query(hip[None])["surface_point"][0]  # the brush centre: the surface contact point
    r = 0.2
    model.paint(hip[None], r, field="friction_static", value=0.9, falloff="constant")
    now = model.field("friction_static")
    d = np.linalg.norm(pos - centre, axis=1)
    # Friction is stored as IEEE binary16: the painted value is NumPy's float16 nearest 0.9.
    assert np.all(now[d < 0.97 * r] == np.float32(np.float16(0.9)))
    np.testing.assert_array_equal(now[d > 1.03 * r], base[d > 1.03 * r])
    assert np.sum(d < 0.97 * r) > 20


def test_paint_colour_covers_the_brush_area(fresh_sphere):
    model = fresh_sphere
    before = model.field("colour")
    colour = (0.1, 0.7, 0.2)
    model.paint((0.998 * DIRECTION)[None], 0.2, colour=colour, falloff="constant")
    after = model.field("colour")
    changed = np.any(after != before, axis=1)
    # A cap of chord radius 0.2 on the unit sphere: area 2π(1 - cos θ), sin θ ≈ 0.2, of 4π.
    theta = 2 * np.arcsin(0.1)
    fraction = (1 - np.cos(theta)) / 2
    assert abs(changed.mean() - fraction) < 0.3 * fraction
    # Stored as 8-bit sRGB: within half a code step of the colour (IEC 61966-2-1 written here).
    def srgb(c):
        return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1 / 2.4) - 0.055)

    assert np.all(np.abs(255 * srgb(after[changed]) - 255 * srgb(np.array(colour))) <= 0.5 + 1e-4)
    assert model.undo()
    np.testing.assert_array_equal(model.field("colour"), before)


def test_flatten_moves_samples_towards_the_tool_plane_and_smooth_stays_in_range(fresh_sphere):
    model = fresh_sphere
    hip = 0.995 * DIRECTION
    contact = model.query(hip[None])
    point, normal = contact["surface_point"][0], contact["normal"][0]
    pos0 = model.field("positions").astype(float)
    r = 0.2
    model.flatten(np.repeat(hip[None], 200, axis=0), r)  # 0.2 s of contact at full pressure
    pos1 = model.field("positions").astype(float)
    d0 = np.abs((pos0 - point) @ normal)
    d1 = np.abs((pos1 - point) @ normal)
    dist = np.linalg.norm(pos0 - point, axis=1)
    inner = dist < 0.5 * r
    assert inner.sum() > 10
    # The tool's plane is normal to the starting surface's grid normal at the contact, which may turn
    # from the query's force-shading normal by a fraction of a degree: 0.5° of slack at each sample's
    # distance from the contact.
    assert np.all(d1[inner] <= 0.5 * d0[inner] + dist[inner] * np.tan(np.radians(0.5)))
    far = dist > 1.5 * r
    np.testing.assert_array_equal(pos1[far], pos0[far])
    # Smooth relaxes towards neighbour means: no displacement leaves the range it had.
    delta0 = model.field("displacement")
    model.smooth(np.repeat(hip[None], 100, axis=0), r)
    delta1 = model.field("displacement")
    assert delta1.min() >= delta0.min() - 1e-6 and delta1.max() <= delta0.max() + 1e-6
    assert np.any(delta1 != delta0)


def test_edit_errors_carry_the_message(fresh_sphere):
    model = fresh_sphere
    with pytest.raises(ValueError, match="knife"):
        hdm.Brush("knife", 0.1)
    with pytest.raises(ValueError, match="radius"):
        model.carve(np.zeros((1, 3)), 0.0)
    with pytest.raises(ValueError, match="path"):
        model.carve(np.zeros((1, 2)), 0.1)
    with pytest.raises(ValueError, match="bogus"):
        model.field("bogus")
    with pytest.raises(ValueError, match="colour"):
        hdm.Brush("paint", 0.1, colour=(2, 0, 0))
    # A path entirely outside the shell changes nothing.
    assert model.carve(np.full((3, 3), 5.0), 0.1)["changed"] == 0
