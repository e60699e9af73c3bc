// SPDX-License-Identifier: MIT
// The Python module's sphere proxy: its parameters and state, and sphere_proxy_step over a
// trajectory of the ball's centre.
#include <hdm/haptics/sphere_proxy.h>

#include "py_model.h"

#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

namespace hdm::python {
namespace {

py::dict sphere_trajectory(Model& m, const Points& trajectory, SphereProxyState& state,
                           const std::optional<Workspace>& ws_in, const SphereProxyParams& params, double rate_hz) {
  require_rows_of_3(trajectory, "trajectory");
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) throw InvalidInput("rate_hz: must be positive and finite");
  if (!(params.radius >= 0) || !std::isfinite(params.radius))
    throw InvalidInput("radius: must be >= 0 and finite (0: 1 % of the model's diagonal)");
  if (params.samples < 6 || params.samples > kMaxBallSamples)
    throw InvalidInput("samples: must be in [6, " + std::to_string(kMaxBallSamples) + "]");
  const Workspace ws = ws_in ? *ws_in : fit_workspace(m.box, 0.16);
  const py::ssize_t n = trajectory.shape(0);
  const double* p = trajectory.data();
  std::vector<Vec3> device, force, centre;
  std::vector<int32_t> planes;
  std::vector<int8_t> status;
  {
    py::gil_scoped_release release;
    const std::shared_lock lock(m.mutex);
    for (py::ssize_t i = 0; i < n; ++i) {
      const Vec3 hip(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
      Vec3 vel = i > 0 ? Vec3((hip - Vec3(p[3 * i - 3], p[3 * i - 2], p[3 * i - 1])) * rate_hz) : Vec3::Zero();
      if (!vel.allFinite()) vel = Vec3::Zero();  // after a NaN row: the HIP itself is checked
      const ProxyOutput out = sphere_proxy_step(m.model, *m.locator, ws, hip, vel, params, state);
      device.push_back(hip), force.push_back(out.force), centre.push_back(state.center);
      planes.push_back(state.contact ? state.planes : 0), status.push_back(int8_t(out.status));
    }
  }
  py::dict d;
  d["device"] = rows(device);
  d["force"] = rows(force);
  d["centre"] = rows(centre);
  d["planes"] = py::array_t<int32_t>(py::ssize_t(planes.size()), planes.data());
  d["status"] = py::array_t<int8_t>(py::ssize_t(status.size()), status.data());
  return d;
}

}  // namespace

void bind_sphere_proxy(py::module_& m) {
  py::class_<SphereProxyParams>(m, "SphereProxyParams",
                                "Parameters of the sphere proxy: a ball of radius r held outside the displaced "
                                "surface (hdm::SphereProxyParams).")
      .def(py::init<>())
      .def_readwrite("proxy", &SphereProxyParams::proxy,
                     "hdm.ProxyParams: stiffness, damping, friction scale, solver; iterations = solve rounds")
      .def_readwrite("radius", &SphereProxyParams::radius, "ball radius [model units]; 0: 1 % of the diagonal")
      .def_readwrite("samples", &SphereProxyParams::samples, "points of the ball queried to find touched regions");
  py::class_<SphereProxyState, std::unique_ptr<SphereProxyState>>(
      m, "SphereProxyState", "The ball's state carried from tick to tick; pass the same object to continue a motion.")
      .def(py::init<>())
      .def_readonly("contact", &SphereProxyState::contact, "the ball is held by the surface")
      .def_readonly("stuck", &SphereProxyState::stuck, "static friction holds it")
      .def_readonly("planes", &SphereProxyState::planes, "constraint planes active at the last solve")
      .def_property_readonly(
          "centre", [](const SphereProxyState& s) { return py::make_tuple(s.center.x(), s.center.y(), s.center.z()); },
          "the ball's centre (god-object) [model units, model frame]");
  m.def("sphere_proxy_step", &sphere_trajectory, py::arg("model"), py::arg("trajectory"), py::arg("state"),
        py::kw_only(), py::arg("workspace") = std::nullopt, py::arg("params") = SphereProxyParams(),
        py::arg("rate_hz") = 1000.0,
        "Runs the sphere proxy (a ball god-object held outside the displaced surface; Ruspini et al. 1997 with "
        "several constraint planes) over a trajectory of the ball's centre on the device, one servo tick per row, "
        "open loop.\n\nmodel: hdm.Model. trajectory: (N, 3) float64 [m, device frame]. state: "
        "hdm.SphereProxyState, updated. workspace: hdm.Workspace (default fit_workspace(model)). params: "
        "hdm.SphereProxyParams. rate_hz: servo rate [Hz] (velocity = backward difference × rate).\nReturns a dict "
        "of arrays, one row per tick: device (N, 3) [m]; force (N, 3) [N, device frame], never NaN; centre (N, 3), "
        "the ball's centre [model units, model frame]; planes (N,) int32, constraints holding it (0 when free); "
        "status (N,) int8, hdm.ProxyStatus values. Raises ValueError for a negative radius or samples outside "
        "[6, 128].");
}

}  // namespace hdm::python
