# SPDX-License-Identifier: MIT
"""Proxy, devices and the closed loop against an analytic sphere (force along the radius, k times
the penetration), Newton's third law at rest, and the hdm program's own trace of a scenario."""
import csv
import subprocess

import numpy as np
import pytest

import hdm

from conftest import radial_angle_deg


def sphere_workspace(model):
    ws = hdm.fit_workspace(model)
    assert np.allclose(ws.origin, 0, atol=0.05) and ws.scale > 0
    return ws


def radial_path(direction, radii):
    d = np.asarray(direction, float)
    return np.asarray(radii)[:, None] * (d / np.linalg.norm(d))


def test_press_into_the_sphere_gives_the_spring_force_along_the_radius(sphere_files):
    model = sphere_files[2]
    ws = sphere_workspace(model)
    params = hdm.ProxyParams(damping=0.0, friction_scale=0.0, max_force=1.5)
    radii = np.linspace(1.06, 0.95, 2000)
    hip = radial_path([0.3, 0.2, 1.0], radii)
    run = hdm.proxy_step(model, ws.to_device(hip), hdm.ProxyState(), params=params)
    for key in ("force", "proxy", "normal", "device"):
        assert run[key].shape == (2000, 3) and run[key].dtype == np.float64
    assert run["status"].dtype == np.int8 and run["slab"].dtype == np.int32 and run["time"].shape == (2000,)
    free = radii > 1.01
    assert np.all(run["force"][free] == 0) and np.all(run["status"][free] == int(hdm.ProxyStatus.FREE))
    deep = radii < 0.99
    f = run["force"][deep]
    # The spring k·(proxy - HIP)/scale with the proxy on the unit sphere (the bake's error bound,
    # 0.2 % of the diagonal, is about 0.007), clamped at max_force.
    expected = np.minimum(params.stiffness * (1.0 - radii[deep]) / ws.scale, params.max_force)
    tol = params.stiffness * 0.008 / ws.scale
    assert np.allclose(np.linalg.norm(f, axis=1), expected, atol=tol)
    assert np.all(radial_angle_deg(f, hip[deep]) < 5)
    assert np.allclose(np.linalg.norm(run["proxy"][deep], axis=1), 1.0, atol=0.008)
    assert np.all(run["slab"][deep] >= 0) and np.all(run["depth"][deep] > 0)
    assert np.any(run["status"] == int(hdm.ProxyStatus.CLAMPED))


def test_frictionless_slide_keeps_the_force_radial_and_the_proxy_on_the_sphere(sphere_files):
    model = sphere_files[2]
    ws = sphere_workspace(model)
    params = hdm.ProxyParams(friction_scale=0.0)
    t = np.linspace(0, 1.2, 3000)
    hip = 0.98 * np.stack([np.sin(t) * 0.8, np.sin(t) * 0.6, np.cos(t)], axis=1)  # a great circle, 2 % deep
    run = hdm.proxy_step(model, ws.to_device(hip), hdm.ProxyState(), params=params)
    f = run["force"][10:]
    assert np.percentile(radial_angle_deg(f, run["proxy"][10:]), 95) < 5
    assert np.allclose(np.linalg.norm(run["proxy"][10:], axis=1), 1.0, atol=0.008)
    assert np.allclose(np.linalg.norm(f, axis=1), params.stiffness * 0.02 / ws.scale, rtol=0.4)


def test_a_trajectory_split_in_two_calls_continues_the_same_state(sphere_files):
    model = sphere_files[2]
    ws = sphere_workspace(model)
    t = np.linspace(0, 0.5, 1000)
    hip = ws.to_device(0.97 * np.stack([np.sin(t), 0 * t, np.cos(t)], axis=1))
    whole = hdm.proxy_step(model, hip, hdm.ProxyState())
    state = hdm.ProxyState()
    first = hdm.proxy_step(model, hip[:400], state)
    assert state.contact and state.slab >= 0
    second = hdm.proxy_step(model, hip[400:], state)
    np.testing.assert_array_equal(np.concatenate([first["force"], second["force"]]), whole["force"])
    np.testing.assert_array_equal(np.concatenate([first["proxy"], second["proxy"]]), whole["proxy"])


def test_penalty_mode_is_the_papers_spring_along_the_normal(sphere_files):
    model = sphere_files[2]
    ws = sphere_workspace(model)
    params = hdm.ProxyParams(damping=0.0)
    radii = np.linspace(1.0, 0.97, 500)
    hip = radial_path([-0.5, 0.4, -0.3], radii)
    run = hdm.proxy_step(model, ws.to_device(hip), hdm.ProxyState(), params=params, mode="penalty")
    deep = radii < 0.99
    expected = params.stiffness * (1.0 - radii[deep]) / ws.scale
    assert np.allclose(np.linalg.norm(run["force"][deep], axis=1), expected, atol=params.stiffness * 0.008 / ws.scale)
    assert np.all(radial_angle_deg(run["force"][deep], hip[deep]) < 5)


def test_bad_rows_give_zero_force_and_bad_arguments_raise(sphere_files):
    model = sphere_files[2]
    hip = np.zeros((4, 3))
    hip[1] = np.nan
    hip[2] = [5.0, 0, 0]  # 5 m from the workspace centre: beyond position_limit_m
    run = hdm.proxy_step(model, hip, hdm.ProxyState())
    assert np.all(run["force"][1:3] == 0)
    assert list(run["status"][1:3]) == [int(hdm.ProxyStatus.BAD_INPUT)] * 2
    assert not np.isnan(run["force"]).any()
    with pytest.raises(ValueError, match="trajectory"):
        hdm.proxy_step(model, np.zeros((3, 2)), hdm.ProxyState())
    with pytest.raises(ValueError, match="velocity"):
        hdm.proxy_step(model, np.zeros((3, 3)), hdm.ProxyState(), velocity=np.zeros((2, 3)))
    with pytest.raises(ValueError, match="sideways"):
        hdm.proxy_step(model, np.zeros((3, 3)), hdm.ProxyState(), mode="sideways")
    with pytest.raises(ValueError, match="rigid_tool_step"):
        hdm.proxy_step(model, np.zeros((3, 3)), hdm.ProxyState(), mode="rigid")
    with pytest.raises(ValueError, match="no parameter 'stifness'"):
        hdm.ProxyParams(stifness=10)
    with pytest.raises(ValueError, match="mass"):
        hdm.SimulatedDevice(np.zeros((3, 3)), mass_kg=0)


def test_simulated_hand_comes_to_rest_where_the_hand_balances_the_surface(sphere_files):
    model = sphere_files[2]
    ws = sphere_workspace(model)
    target = ws.to_device(radial_path([0.1, -0.2, 1.0], [0.95]))  # the hand aims 5 % below the surface
    start = ws.to_device(radial_path([0.1, -0.2, 1.0], [1.05]))[0]
    device = hdm.SimulatedDevice(np.repeat(target, 3000, axis=0), start=start)
    run = hdm.run_device(model, device, 3000)
    assert run["force"].shape == (3000, 3) and device.tick == 3000
    # At rest the handle is in equilibrium: the hand's force balances the rendered one.
    f, hand = run["force"][-1], np.array(device.hand_force)
    assert np.linalg.norm(f) > 0.2
    assert np.allclose(f, -hand, atol=0.02 * np.linalg.norm(f))
    assert radial_angle_deg(f[None], run["proxy"][-1:])[0] < 5


def test_replaying_the_programs_trace_gives_its_forces(sphere_files, hdm_program, tmp_path):
    off, path, model = sphere_files
    trace = str(tmp_path / "slide.csv")
    subprocess.run([hdm_program, "feel", path, "--scenario", "slide", "--trace", trace, "--json"], check=True,
                   capture_output=True)
    with open(trace) as f:
        rows = list(csv.DictReader(f))
    want = np.array([[float(r[f"force_{a}_n"]) for a in "xyz"] for r in rows])
    # The scenario's workspace: the input's box fitted into 0.16 m (hdm::fit_workspace).
    with open(off) as f:
        f.readline()
        nv = int(f.readline().split()[0])
        v = np.array([[float(x) for x in f.readline().split()] for _ in range(nv)])
    lo, hi = v.min(0), v.max(0)
    ws = hdm.Workspace((lo + hi) / 2, np.linalg.norm(hi - lo) / 0.16)
    device = hdm.ReplayDevice(trace)
    assert len(device) == len(rows) and device.rate_hz == pytest.approx(1000, rel=1e-3)
    run = hdm.run_device(model, device, len(rows), workspace=ws, params=hdm.ProxyParams(friction_scale=0.0))
    assert run["force"].shape == want.shape
    # The trace holds positions to 1 µm and forces to 10 µN: k·1 µm = 1 mN.
    err = np.linalg.norm(run["force"] - want, axis=1)
    assert np.median(err) < 0.005 and np.percentile(err, 99) < 0.05
    assert np.linalg.norm(want, axis=1).max() > 0.5


def test_device_frames_by_hand():
    device = hdm.ReplayDevice.from_csv("time_s,device_x_m,device_y_m,device_z_m\n0,0,0,0\n0.001,0.002,0,0\n",
                                       "two rows")
    assert len(device) == 2
    first = device.begin_frame()
    device.end_frame((0.0, 0.0, 1.0))
    second = device.begin_frame()
    device.end_frame((0.0, 0.5, 0.0))
    assert first["position"] == (0, 0, 0) and second["position"] == (0.002, 0, 0)
    assert second["velocity"] == pytest.approx((2.0, 0, 0))  # backward difference [m/s]
    assert device.begin_frame() is None and device.last_force == (0.0, 0.5, 0.0)
    with pytest.raises(ValueError, match="bad rows"):
        hdm.ReplayDevice.from_csv("time_s,device_x_m,device_y_m,device_z_m\n0,0,0\n", "bad rows")
    # A free handle (no rendered force) pulled by the hand spring towards a held target settles there.
    hand = hdm.SimulatedDevice(np.array([[0.01, 0.0, 0.0]]), start=(0.0, 0.0, 0.0))
    for _ in range(3000):
        state = hand.begin_frame()
        hand.end_frame((0.0, 0.0, 0.0))
    assert state["position"] == pytest.approx((0.01, 0, 0), abs=1e-5)


def test_an_exposed_under_layer_renders_its_stiffness(fresh_sphere):
    model = fresh_sphere
    model.set_under_layer(0.01, stiffness_scale=0.5)
    assert len(model.field("layer_displacement")) == len(model.field("displacement"))
    d = np.array([0.0, 0.3, 1.0]) / np.linalg.norm([0.0, 0.3, 1.0])
    model.carve((0.97 * d)[None], 0.1)  # a pit 3 % deep: through the 1 % layer
    ws = sphere_workspace(model)
    params = hdm.ProxyParams(damping=0.0, friction_scale=0.0)
    other = np.array([0.0, -0.3, 1.0]) / np.linalg.norm([0.0, -0.3, 1.0])
    forces = []  # stiffness felt [N/m]
    for direction, surface in ((d, 0.97), (other, 1.0)):  # the pit's floor, and the bare surface
        hip = radial_path(direction, np.linspace(surface + 0.01, surface - 0.01, 400))
        run = hdm.proxy_step(model, ws.to_device(hip), hdm.ProxyState(), params=params)
        # The stiffness felt: |F| over the spring's stretch (proxy - HIP)·n [m at the device].
        forces.append(np.linalg.norm(run["force"][-1]) / (run["depth"][-1] / ws.scale))
    assert forces[1] == pytest.approx(params.stiffness, rel=0.02)
    assert forces[0] == pytest.approx(0.5 * params.stiffness, rel=0.05)


def test_bake_gives_the_programs_report(hdm_program, tmp_path):
    import json
    import os

    path = os.path.join(os.environ.get("HDM_DATA_DIR", "data/meshes"), "sphere.off")
    out = subprocess.run([hdm_program, "bake", path, "-o", str(tmp_path / "s.hdm"), "--json"], check=True,
                         capture_output=True, text=True).stdout
    theirs = json.loads(out)
    model, mine = hdm.bake(path)
    for key in ("slabs", "grid", "samples", "input_triangles", "invalid_slabs", "overlapping_pairs", "ray_misses"):
        assert mine[key] == theirs[key], key
    for key in ("max_pct", "rms_pct", "max_back_pct", "rms_back_pct"):
        assert mine["fidelity"][key] == pytest.approx(theirs["fidelity"][key], rel=1e-9), key
    assert model.slab_count == hdm.load(str(tmp_path / "s.hdm")).slab_count


def test_simulated_handle_turns_by_the_torque_as_a_free_rigid_body():
    # A free handle (no wrist spring or damper) under a constant torque τ from rest turns by
    # θ = τ·t²/(2I) (constant angular acceleration), about the torque's axis.
    tau, inertia, ticks = 0.002, 1e-4, 100
    device = hdm.SimulatedDevice(np.zeros((1, 3)), inertia_kgm2=inertia, wrist_stiffness=0.0, wrist_damping=0.0,
                                 max_torque_nm=1.0)
    for _ in range(ticks):
        device.begin_frame()
        device.end_frame((0.0, 0.0, 0.0), torque=(0.0, 0.0, tau))
    w, x, y, z = device.begin_frame()["orientation"]
    t = ticks / 1000.0
    assert abs(x) < 1e-12 and abs(y) < 1e-12
    assert 2 * np.arctan2(z, w) == pytest.approx(tau * t * t / (2 * inertia), rel=0.02)


def test_simulated_wrist_settles_the_torque_over_its_stiffness():
    # With the wrist spring k the handle comes to rest where k·θ balances τ.
    tau, k = 0.01, 1.0
    device = hdm.SimulatedDevice(np.zeros((1, 3)), wrist_stiffness=k, max_torque_nm=1.0)
    for _ in range(3000):
        device.begin_frame()
        device.end_frame((0.0, 0.0, 0.0), torque=(tau, 0.0, 0.0))
    frame = device.begin_frame()
    w, x = frame["orientation"][:2]
    assert 2 * np.arctan2(x, w) == pytest.approx(tau / k, rel=0.01)
    assert np.linalg.norm(frame["angular_velocity"]) < 1e-6
    assert np.allclose(device.wrist_torque, (-tau, 0.0, 0.0), atol=1e-4 * tau)
    with pytest.raises(ValueError, match="orientation"):
        hdm.SimulatedDevice(np.zeros((1, 3)), orientation=(0.0, 0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="4 numbers"):
        hdm.SimulatedDevice(np.zeros((1, 3)), orientation=(1.0, 0.0, 0.0))
