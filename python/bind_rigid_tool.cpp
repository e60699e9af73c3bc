// SPDX-License-Identifier: MIT
// The Python module's rigid tool: the point shell (burr_shell, ToolShell), the god-object's
// parameters and state, and rigid_tool_step over a trajectory of tool poses.
#include <hdm/haptics/rigid_tool.h>

#include "py_model.h"

#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hdm::python {
namespace {

std::vector<Vec3> vectors(const Points& a, const char* what) {
  require_rows_of_3(a, what);
  std::vector<Vec3> v(size_t(a.shape(0)));
  for (size_t i = 0; i < v.size(); ++i) v[i] = Vec3(a.data()[3 * i], a.data()[3 * i + 1], a.data()[3 * i + 2]);
  return v;
}

// One row of an optional (N, 3) array, or zero.
Vec3 row_or_zero(const std::optional<Points>& a, py::ssize_t i) {
  if (!a) return Vec3::Zero();
  const double* d = a->data() + 3 * i;
  return Vec3(d[0], d[1], d[2]);
}

void require_rows(const std::optional<Points>& a, py::ssize_t n, const char* what) {
  if (!a) return;
  require_rows_of_3(*a, what);
  if (a->shape(0) != n) throw InvalidInput(std::string(what) + ": expected as many rows as positions");
}

py::dict tool_trajectory(Model& m, const ToolShell& shell, const Points& positions, const Points& orientations,
                         RigidToolState& state, const std::optional<Workspace>& ws_in, const RigidToolParams& params,
                         const std::optional<Points>& velocities, const std::optional<Points>& angular_velocities) {
  require_rows_of_3(positions, "positions");
  const py::ssize_t n = positions.shape(0);
  if (orientations.ndim() != 2 || orientations.shape(1) != 4 || orientations.shape(0) != n)
    throw InvalidInput("orientations: expected an (N, 4) float64 array (w, x, y, z), one row per position");
  require_rows(velocities, n, "velocities");
  require_rows(angular_velocities, n, "angular_velocities");
  const Workspace ws = ws_in ? *ws_in : fit_workspace(m.box, 0.16);
  std::vector<Vec3> force, torque, tip;
  std::vector<int32_t> contacts;
  std::vector<int8_t> status;
  {
    py::gil_scoped_release release;
    const std::shared_lock lock(m.mutex);
    for (py::ssize_t i = 0; i < n; ++i) {
      const double* p = positions.data() + 3 * i;
      const double* q = orientations.data() + 4 * i;
      const ToolPose pose{Vec3(p[0], p[1], p[2]), Eigen::Quaterniond(q[0], q[1], q[2], q[3])};
      const ToolTwist twist{row_or_zero(velocities, i), row_or_zero(angular_velocities, i)};
      const ToolWrench w = rigid_tool_step(m.model, *m.locator, ws, shell, pose, twist, params, state);
      force.push_back(w.force), torque.push_back(w.torque), tip.push_back(state.position);
      contacts.push_back(w.contacts), status.push_back(int8_t(w.status));
    }
  }
  py::dict d;
  d["force"] = rows(force);
  d["torque"] = rows(torque);
  d["tip"] = rows(tip);
  d["contacts"] = py::array_t<int32_t>(py::ssize_t(contacts.size()), contacts.data());
  d["status"] = py::array_t<int8_t>(py::ssize_t(status.size()), status.data());
  return d;
}

}  // namespace

void bind_rigid_tool(py::module_& m) {
  py::class_<ToolShell>(m, "ToolShell",
                        "A rigid tool's point shell: points on its surface with inward normals [model units, tool "
                        "frame, the tip point at the origin] (hdm::ToolShell).")
      .def(py::init([](const Points& points, const Points& normals) {
             ToolShell s{vectors(points, "points"), vectors(normals, "normals")};
             if (s.points.size() != s.normals.size()) throw InvalidInput("normals: expected one per point");
             return s;
           }),
           py::arg("points"), py::arg("normals"), "points, normals: (P, 3) float64 arrays")
      .def_property_readonly(
          "points", [](const ToolShell& s) { return rows(s.points); }, "(P, 3) [model units]")
      .def_property_readonly(
          "normals", [](const ToolShell& s) { return rows(s.normals); }, "(P, 3) unit, inward");
  m.def("burr_shell", &burr_shell, py::arg("radius"), py::arg("count") = 1000,
        "The point shell of a dental burr: a spherical head of radius `radius` [model units] centred at the tip "
        "point, on a shaft of radius 0.4·radius along +z, 8·radius long (hdm::burr_shell). count: points, in [16, "
        "2048]. Raises ValueError for a radius that is not positive and finite or a count out of range.");
  py::class_<RigidToolParams>(m, "RigidToolParams",
                              "Parameters of the rigid tool's god-object, SI at the device (hdm::RigidToolParams).")
      .def(py::init<>())
      .def_readwrite("stiffness", &RigidToolParams::stiffness, "translational coupling [N/m]")
      .def_readwrite("damping", &RigidToolParams::damping, "translational damping in contact [N·s/m]")
      .def_readwrite("rot_stiffness", &RigidToolParams::rot_stiffness, "rotational coupling [N·m/rad]")
      .def_readwrite("rot_damping", &RigidToolParams::rot_damping, "rotational damping in contact [N·m·s/rad]")
      .def_readwrite("max_force", &RigidToolParams::max_force, "force clamp [N]")
      .def_readwrite("max_torque", &RigidToolParams::max_torque, "torque clamp [N·m]")
      .def_readwrite("band", &RigidToolParams::band, "contact band and step bound [model units]; 0: 0.002 × diagonal")
      .def_readwrite("rounds", &RigidToolParams::rounds, "query + solve rounds per tick (>= 1)")
      .def_readwrite("sweeps", &RigidToolParams::sweeps, "Gauss–Seidel sweeps per solve (>= 1)");
  py::class_<RigidToolState, std::unique_ptr<RigidToolState>>(
      m, "RigidToolState",
      "The god-object carried from tick to tick (about 200 KB); pass the same object to continue a motion.")
      .def(py::init([] { return std::make_unique<RigidToolState>(); }))
      .def_readonly("contact", &RigidToolState::contact, "the last tick's god-object was pushed")
      .def_property_readonly(
          "position",
          [](const RigidToolState& s) { return py::make_tuple(s.position.x(), s.position.y(), s.position.z()); },
          "the god-object's tip [model units, model frame]")
      .def_property_readonly(
          "orientation",
          [](const RigidToolState& s) {
            return py::make_tuple(s.orientation.w(), s.orientation.x(), s.orientation.y(), s.orientation.z());
          },
          "the god-object's rotation, tool → model frame, (w, x, y, z)");
  m.def("rigid_tool_step", &tool_trajectory, py::arg("model"), py::arg("shell"), py::arg("positions"),
        py::arg("orientations"), py::arg("state"), py::kw_only(), py::arg("workspace") = std::nullopt,
        py::arg("params") = RigidToolParams(), py::arg("velocities") = std::nullopt,
        py::arg("angular_velocities") = std::nullopt,
        "Runs the rigid tool (a 6-DOF god-object of the shell held outside the displaced surface; "
        "hdm::rigid_tool_step) over a trajectory of device poses, one servo tick per row, open loop.\n\nmodel: "
        "hdm.Model. shell: hdm.ToolShell (hdm.burr_shell). positions: (N, 3) float64, the tip [m, device frame]. "
        "orientations: (N, 4) float64, (w, x, y, z) quaternions, tool → device frame. state: hdm.RigidToolState, "
        "updated. workspace: hdm.Workspace (default fit_workspace(model)). params: hdm.RigidToolParams. "
        "velocities, angular_velocities: optional (N, 3) [m/s], [rad/s] (default zero).\nReturns a dict of "
        "arrays, one row per tick: force (N, 3) [N] and torque (N, 3) [N·m, about the tip], device frame, never "
        "NaN; tip (N, 3), the god-object's tip [model units, model frame]; contacts (N,) int32, shell points "
        "pushing; status (N,) int8 (0 free, 1 contact, 2 clamped, 3 bad input). Raises ValueError for arrays of "
        "the wrong shape.");
}

}  // namespace hdm::python
