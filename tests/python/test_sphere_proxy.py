# SPDX-License-Identifier: MIT
"""The sphere proxy from Python against the unit sphere: the ball rests r from the sphere's
surface (its centre 1 + r from the origin), the force is along the radius, arguments are checked."""
import numpy as np
import pytest

import hdm

from conftest import radial_angle_deg


def test_the_ball_rests_on_the_sphere_with_a_radial_force(sphere_files):
    model = sphere_files[2]
    ws = hdm.fit_workspace(model)
    params = hdm.SphereProxyParams()
    params.radius = 0.1
    params.proxy = hdm.ProxyParams(damping=0.0, friction_scale=0.0, max_force=3.0)
    d = np.array([0.3, 0.2, 1.0]) / np.linalg.norm([0.3, 0.2, 1.0])
    radii = np.linspace(1.3, 1.05, 500)  # the ball's centre, pressed 0.05 into the sphere at the end
    run = hdm.sphere_proxy_step(model, ws.to_device(radii[:, None] * d), hdm.SphereProxyState(), params=params)
    assert run["centre"].shape == (500, 3) and run["force"].shape == (500, 3)
    free = radii > 1.12
    assert np.all(run["force"][free] == 0) and np.all(run["planes"][free] == 0)
    held = radii < 1.08
    centre = run["centre"][held]
    # The bake reproduces radius 1 to within 0.2 % of the diagonal (2·sqrt(3)).
    assert np.all(np.abs(np.linalg.norm(centre, axis=1) - 1.1) < 0.007)
    assert np.max(radial_angle_deg(run["force"][held], centre)) < 3.0
    assert np.all(run["status"][held] != int(hdm.ProxyStatus.FREE))


def test_bad_parameters_are_refused(sphere_files):
    model = sphere_files[2]
    params = hdm.SphereProxyParams()
    params.radius = -1.0
    with pytest.raises(ValueError, match="radius"):
        hdm.sphere_proxy_step(model, np.zeros((3, 3)), hdm.SphereProxyState(), params=params)
    params.radius = 0.0
    params.samples = 500
    with pytest.raises(ValueError, match="samples"):
        hdm.sphere_proxy_step(model, np.zeros((3, 3)), hdm.SphereProxyState(), params=params)
