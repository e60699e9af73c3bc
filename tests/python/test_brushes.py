# SPDX-License-Identifier: MIT
"""Every registered brush (hdm.brushes()) through Python on the unit sphere: hdm.Brush takes its
name, its Model method strokes, and the model changes as that brush should (carve never raises,
add never lowers, smooth stays within the former range, paint changes only its field, towards the
value). The expectations are written here, one per brush name: a brush without one fails."""
import numpy as np
import pytest

import hdm

DIRECTION = np.array([0.3, -0.2, 0.93]) / np.linalg.norm([0.3, -0.2, 0.93])
TANGENT = np.cross(DIRECTION, [0.0, 0.0, 1.0]) / np.linalg.norm(np.cross(DIRECTION, [0.0, 0.0, 1.0]))
PAINTED = 0.9
FIELDS = ["displacement", "friction_static", "friction_dynamic", "stiffness", "roughness", "colour"]


def path(depth):
    """200 tool positions (0.2 s at 1 kHz) sliding 0.1 over the sphere, `depth` below its surface."""
    t = np.linspace(0, 0.1, 200)[:, None]
    d = DIRECTION + t * TANGENT
    return (1 - depth) * d / np.linalg.norm(d, axis=1)[:, None]


def changed(before, after):
    return {k for k in FIELDS if not np.array_equal(before[k], after[k])}


def expect_carve(b, a):
    assert changed(b, a) == {"displacement"}
    assert np.all(a["displacement"] <= b["displacement"])
    assert np.any(a["displacement"] < b["displacement"])


def expect_add(b, a):
    assert changed(b, a) == {"displacement"}
    assert np.all(a["displacement"] >= b["displacement"])
    assert np.any(a["displacement"] > b["displacement"])


def expect_smooth(b, a):
    assert changed(b, a) == {"displacement"}
    d = b["displacement"]
    assert a["displacement"].min() >= d.min() and a["displacement"].max() <= d.max()


def expect_flatten(b, a):
    assert changed(b, a) == {"displacement"}


def expect_paint(b, a):
    assert changed(b, a) == {"friction_static"}
    moved = a["friction_static"] != b["friction_static"]
    assert moved.sum() > 10
    assert np.all(np.abs(a["friction_static"][moved] - PAINTED) < np.abs(b["friction_static"][moved] - PAINTED))


EXPECTED = {"carve": expect_carve, "add": expect_add, "smooth": expect_smooth, "flatten": expect_flatten,
            "paint": expect_paint, "drill": expect_carve}  # drill removes material, like carve


def brush_kwargs(info, model):
    """The keyword arguments of the parameters the brush reads, from its registry entry."""
    kw = {}
    params = info["params"]
    if "height" in params:
        outer = np.linalg.norm(model.box, axis=1).min() / np.sqrt(3)  # the slabs' outer reach
        kw["height"] = min(0.03, 0.5 * (outer - 1))
    if "resilience" in params:
        kw["resilience"] = 0.005
    if "field" in params:
        kw["field"], kw["value"] = "friction_static", PAINTED
    return kw


def test_the_registry_lists_brushes_with_their_parameters():
    brushes = hdm.brushes()
    assert len(brushes) >= 5
    names = [b["name"] for b in brushes]
    assert len(set(names)) == len(names)
    for b in brushes:
        assert {"radius", "strength", "falloff"} <= set(b["params"])
        lo, hi, lo_open = b["params"]["radius"]
        assert lo == 0 and lo_open and hi == np.inf
        assert b["falloff"] in ("constant", "linear", "smooth")
        assert hdm.Brush(b["name"], 0.1).tool == b["name"]


@pytest.mark.parametrize("info", hdm.brushes(), ids=lambda b: b["name"])
def test_every_brush_strokes_as_it_should(info, sphere_files):
    name = info["name"]
    assert name in EXPECTED, f"no expectation for the brush '{name}': add one to this test"
    for how in ("method", "stroke"):
        model = hdm.load(sphere_files[1])
        before = {k: model.field(k).copy() for k in FIELDS}
        kw = brush_kwargs(info, model)
        if how == "method":
            out = getattr(model, name)(path(0.04), 0.1, **kw)
        else:
            out = model.stroke(path(0.04), hdm.Brush(name, 0.1, **kw))
        assert out["tool_positions"] == 200 and out["changed"] > 0
        EXPECTED[name](before, {k: model.field(k) for k in FIELDS})
        assert model.undo()
        for k in FIELDS:
            np.testing.assert_array_equal(model.field(k), before[k])


@pytest.mark.parametrize("info", hdm.brushes(), ids=lambda b: b["name"])
def test_every_brush_refuses_out_of_range_parameters(info):
    with pytest.raises(ValueError, match="radius"):
        hdm.Brush(info["name"], -0.1)
    with pytest.raises(ValueError, match="strength"):
        hdm.Brush(info["name"], 0.1, strength=1.5)
    with pytest.raises(ValueError, match="pressure_force_n"):
        hdm.Brush(info["name"], 0.1, pressure_force_n=0)
    with pytest.raises(ValueError, match="wear_coefficient"):
        hdm.Brush(info["name"], 0.1, wear_coefficient=0)
    with pytest.raises(ValueError, match="rpm"):
        hdm.Brush(info["name"], 0.1, rpm=-5)
