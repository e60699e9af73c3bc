# SPDX-License-Identifier: MIT
"""hdm.feel against the hdm program's `hdm feel --json` on the same model: the same dict, key for
key (the tick timings aside), for a scenario and for a replayed trace; and its errors."""
import json
import subprocess

import numpy as np
import pytest

import hdm


def program_json(exe, *args):
    out = subprocess.run([exe, "feel", *args, "--json"], check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def assert_same_report(mine, theirs):
    assert set(mine) - {"trace_rows"} == set(theirs)
    for key, value in theirs.items():
        if key in ("tick_ns", "trace"):
            continue
        if isinstance(value, float):
            assert mine[key] == pytest.approx(value, rel=1e-12, abs=1e-12), key
        else:
            assert mine[key] == value, key


@pytest.mark.parametrize("scenario,mode", [("slide", "proxy"), ("press", "proxy"), ("press", "sphere")])
def test_feel_gives_the_programs_report(sphere_files, hdm_program, scenario, mode):
    off, path, model = sphere_files
    theirs = program_json(hdm_program, path, "--scenario", scenario, "--mode", mode)
    mine = hdm.feel(hdm.load(path), scenario, mode=mode)
    assert_same_report(mine, theirs)
    assert (mine["ball_radius"] > 0) == (mode == "sphere")
    assert mine["ticks"] > 100 and mine["contact_ticks"] > 0 and mine["pop_throughs"] == 0
    assert hdm.feel(path, scenario)["max_force_n"] == mine["max_force_n"]  # a path works too


def test_feel_replay_and_trace_rows(sphere_files, hdm_program, tmp_path):
    off, path, model = sphere_files
    trace = str(tmp_path / "t.csv")
    program_json(hdm_program, path, "--scenario", "slide", "--trace", trace)
    theirs = program_json(hdm_program, path, "--replay", trace)
    mine = hdm.feel(hdm.load(path), replay=trace, trace=True)
    assert_same_report(mine, theirs)
    rows = mine["trace_rows"]
    assert rows["force"].shape == (mine["ticks"], 3)
    assert np.max(np.linalg.norm(rows["force"], axis=1)) == pytest.approx(mine["max_force_n"], rel=1e-9)


def test_feel_errors(sphere_files, tmp_path):
    off, path, model = sphere_files
    with pytest.raises(ValueError, match="wiggle"):
        hdm.feel(model, "wiggle")
    with pytest.raises(ValueError, match="exactly one"):
        hdm.feel(model)
    with pytest.raises(ValueError, match="mode rigid"):
        hdm.feel(model, "press", mode="rigid")
    with pytest.raises(ValueError, match="ball radius"):
        hdm.feel(model, "press", mode="sphere", radius=-1.0)
    with pytest.raises(ValueError, match=r"\(mode sphere\) only"):
        hdm.feel(model, "press", radius=0.1)
    bad = tmp_path / "bad.csv"
    bad.write_text("time_s,device_x_m,device_y_m,device_z_m\n0,0,0,0\n0.001,nan,0,0\n")
    with pytest.raises(ValueError, match="bad.csv"):
        hdm.feel(model, replay=str(bad))
    from test_hdm import icosphere
    unnamed, _ = hdm.bake(icosphere(1), slabs=20, error_bound=False)
    with pytest.raises(ValueError, match="input="):
        hdm.feel(unnamed, "slide")


@pytest.mark.parametrize("scenario", ["slot", "shaft_edge"])
def test_feel_tool_gives_the_programs_report(hdm_program, scenario):
    theirs = program_json(hdm_program, "--scenario", scenario)
    mine = hdm.feel_tool(scenario)
    assert_same_report(mine, theirs)
    assert mine["contact_ticks"] > 0


def test_feel_tool_errors():
    with pytest.raises(ValueError, match="groove"):
        hdm.feel_tool("groove")
    with pytest.raises(ValueError, match="press_force_n"):
        hdm.feel_tool("slot", press=-1.0)
