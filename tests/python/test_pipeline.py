# SPDX-License-Identifier: MIT
"""hdm.bake() and `hdm bake` run one bake (bake_input()): the same file gives the same model, byte for
byte, also for an input the preparation changes (an open surface that crosses a closed one)."""
import subprocess

import numpy as np

import hdm

from conftest import write_off
from test_hdm import icosphere


def cap_through_sphere():
    """An open spherical cap (the faces of a unit icosphere above z = -0.3) and a closed sphere of
    radius 0.6 passing through its side."""
    v, f = icosphere(3)
    keep = np.all(v[f][:, :, 2] > -0.3, axis=1)
    f = f[keep]
    used = np.unique(f)
    remap = -np.ones(len(v), dtype=np.int64)
    remap[used] = np.arange(len(used))
    cap_v, cap_f = v[used], remap[f]
    ball_v, ball_f = icosphere(3)
    ball_v = ball_v * 0.6 + np.array([0.8, 0.0, 0.5])
    return np.vstack([cap_v, ball_v]), np.vstack([cap_f, ball_f + len(cap_v)])


def test_bake_matches_hdm_bake_byte_for_byte(tmp_path, hdm_program):
    mesh = str(tmp_path / "cap_sphere.off")
    write_off(mesh, *cap_through_sphere())
    cli = tmp_path / "cli.hdm"
    subprocess.run([hdm_program, "bake", mesh, "-o", str(cli)], check=True, capture_output=True)
    model, report = hdm.bake(mesh)
    assert report["self_intersections"] > 0  # the input crosses itself: the preparation has work to do
    py = tmp_path / "python.hdm"
    model.save(str(py))
    assert cli.read_bytes() == py.read_bytes()
