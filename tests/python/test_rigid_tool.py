# SPDX-License-Identifier: MIT
"""The rigid tool from Python: the burr pressed onto the unit sphere's pole and rocked gives the same
force and torque, bit for bit, as the same rigid_tool_step calls in C++ (rigid_tool_reference, built
next to the hdm program); the force pushes the tool out and the shell and arguments are checked."""
import os
import subprocess

import numpy as np
import pytest

import hdm


def poses(ws, radius):
    """A press of the tip onto the pole (0.3 beyond contact), then a rocking of the shaft."""
    n = 400
    t = np.linspace(0.0, 1.0, n)
    z = 1.0 + radius + 0.02 - np.minimum(t / 0.5, 1.0) * (0.02 + 0.3 * radius)
    tip = ws.to_device(np.stack([0.02 * np.sin(6 * t), np.zeros(n), z], axis=1))
    angle = 0.4 * np.sin(4 * np.pi * t) * (t > 0.5)  # about x, once pressed
    q = np.stack([np.cos(angle / 2), np.sin(angle / 2), np.zeros(n), np.zeros(n)], axis=1)
    return tip, q


def test_the_wrench_equals_the_cpp_call(sphere_files):
    exe = os.path.join(os.environ.get("HDM_BIN_DIR", ""), "rigid_tool_reference")
    if not os.path.exists(exe):
        pytest.skip("rigid_tool_reference is not built (HDM_BIN_DIR)")
    path = sphere_files[1]
    model = hdm.load(path)
    ws = hdm.fit_workspace(model)
    radius, count = 0.05, 600
    tip, q = poses(ws, radius)
    shell = hdm.burr_shell(radius, count)
    assert shell.points.shape == (count, 3) and shell.normals.shape == (count, 3)
    run = hdm.rigid_tool_step(model, shell, tip, q, hdm.RigidToolState(), workspace=ws)

    lines = "".join(" ".join(f"{x!r}" for x in (*p, *r)) + "\n" for p, r in zip(tip, q))
    args = [exe, path, *(repr(float(x)) for x in ws.origin), repr(float(ws.scale)), repr(radius), str(count)]
    out = subprocess.run(args, input=lines, capture_output=True, text=True, check=True).stdout.split("\n")
    ref = np.array([[float(x) for x in line.split()] for line in out if line])
    assert ref.shape == (len(tip), 8)
    np.testing.assert_array_equal(run["force"], ref[:, 0:3])
    np.testing.assert_array_equal(run["torque"], ref[:, 3:6])
    np.testing.assert_array_equal(run["status"], ref[:, 6].astype(np.int8))
    np.testing.assert_array_equal(run["contacts"], ref[:, 7].astype(np.int32))

    # The run touches, pushes the tool out (upward at the pole) and is torqued while rocked.
    pressed = run["contacts"] > 0
    assert pressed.sum() > 100
    assert np.all(run["force"][pressed][:, 2] > 0)
    assert np.max(np.linalg.norm(run["torque"], axis=1)) > 0
    assert np.min(np.linalg.norm(run["tip"][pressed], axis=1)) > 1.0 + 0.8 * radius  # the head stays outside


def test_bad_arguments_are_refused(sphere_files):
    model = sphere_files[2]
    with pytest.raises(ValueError, match="radius"):
        hdm.burr_shell(-1.0)
    shell = hdm.burr_shell(0.05, 64)
    with pytest.raises(ValueError, match="orientations"):
        hdm.rigid_tool_step(model, shell, np.zeros((3, 3)), np.zeros((3, 3)), hdm.RigidToolState())
    with pytest.raises(ValueError, match="velocities"):
        hdm.rigid_tool_step(
            model, shell, np.zeros((3, 3)), np.ones((3, 4)), hdm.RigidToolState(), velocities=np.zeros((2, 3))
        )
