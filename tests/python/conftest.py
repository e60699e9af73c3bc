# SPDX-License-Identifier: MIT
"""Shared fixtures of the Python module's tests: an icosphere written to an OFF file and baked from
it (so the model's source names a file, as `hdm feel` needs), and the hdm program when it is built."""
import os
import shutil

import numpy as np
import pytest

import hdm

from test_hdm import icosphere


def write_off(path, v, f):
    with open(path, "w") as out:
        out.write(f"OFF\n{len(v)} {len(f)} 0\n")
        out.writelines(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in v)
        out.writelines(f"3 {a} {b} {c}\n" for a, b, c in f)


@pytest.fixture(scope="session")
def sphere_files(tmp_path_factory):
    """(path of a unit icosphere OFF, path of its baked .hdm, the Model): the sphere of radius 1 at the origin."""
    d = tmp_path_factory.mktemp("sphere")
    off = str(d / "sphere.off")
    write_off(off, *icosphere(4))
    model, report = hdm.bake(off)
    assert report["bound_met"]
    path = str(d / "sphere.hdm")
    model.save(path)
    return off, path, model


@pytest.fixture()
def fresh_sphere(sphere_files):
    """A model of its own to edit (loaded from the saved file)."""
    return hdm.load(sphere_files[1])


@pytest.fixture(scope="session")
def hdm_program():
    """Path of the hdm program next to the module's build, or skip when it was not built."""
    exe = os.path.join(os.environ.get("HDM_BIN_DIR", ""), "hdm")
    if not os.access(exe, os.X_OK):
        exe = shutil.which("hdm")
    if not exe:
        pytest.skip("the hdm program is not built (HDM_BIN_DIR)")
    return exe


def radial_angle_deg(vectors, points):
    """Angle [deg] between each row of vectors and the radial direction of the row of points."""
    a = vectors / np.linalg.norm(vectors, axis=1)[:, None]
    b = points / np.linalg.norm(points, axis=1)[:, None]
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=1), -1, 1)))
