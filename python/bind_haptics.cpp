// SPDX-License-Identifier: MIT
// The Python module's haptics: workspace, proxy parameters and state, proxy_step over a
// trajectory, the simulated and replay devices, and a closed loop of a device and the proxy.
#include <hdm/haptics/device.h>
#include <hdm/haptics/force.h>
#include <hdm/haptics/proxy.h>

#include "py_model.h"

#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <vector>

namespace hdm::python {
namespace {

// The point renderers' modes: the ball and the rigid tool have their own calls and states.
RenderMode point_render_mode(const std::string& name) {
  const RenderMode mode = parse_render_mode(name);
  if (mode == RenderMode::Sphere)
    throw InvalidInput("mode 'sphere': the ball carries its own state; call sphere_proxy_step with a SphereProxyState");
  if (mode == RenderMode::RigidTool)
    throw InvalidInput(
        "mode 'rigid': the rigid tool carries its own state; call rigid_tool_step with a RigidToolState");
  return mode;
}

// Per-tick results of a run, filled with the GIL released, handed to Python as arrays.
struct Run {
  std::vector<Vec3> device, force, proxy, normal;
  std::vector<double> time, depth;
  std::vector<int32_t> slab;
  std::vector<int8_t> status;
  void reserve(size_t n) {
    for (auto* v : {&device, &force, &proxy, &normal}) v->reserve(n);
    time.reserve(n), depth.reserve(n), slab.reserve(n), status.reserve(n);
  }
  void add(double t, const Vec3& hip_m, const ProxyOutput& out, const ProxyState& st) {
    time.push_back(t), device.push_back(hip_m), force.push_back(out.force), status.push_back(int8_t(out.status));
    const bool contact = out.contact.slab >= 0;
    proxy.push_back(contact ? out.contact.surface_point : st.position);
    normal.push_back(contact ? out.contact.normal : Vec3::Constant(std::nan("")));
    depth.push_back(contact ? out.contact.depth : 0.0);
    slab.push_back(out.contact.slab);
  }
  py::dict to_dict() const {
    auto rows = [](const std::vector<Vec3>& v) {
      auto a = rows_of_3(py::ssize_t(v.size()));
      double* d = a.mutable_data();
      for (size_t i = 0; i < v.size(); ++i)
        for (int k = 0; k < 3; ++k) d[3 * i + k] = v[i][k];
      return a;
    };
    py::dict d;
    d["time"] = py::array_t<double>(py::ssize_t(time.size()), time.data());
    d["device"] = rows(device);
    d["force"] = rows(force);
    d["proxy"] = rows(proxy);
    d["normal"] = rows(normal);
    d["depth"] = py::array_t<double>(py::ssize_t(depth.size()), depth.data());
    d["slab"] = py::array_t<int32_t>(py::ssize_t(slab.size()), slab.data());
    d["status"] = py::array_t<int8_t>(py::ssize_t(status.size()), status.data());
    return d;
  }
};

constexpr const char* kRunDoc =
    "a dict of arrays, one row per tick: time (N,) float64 [s]; device (N, 3) float64, the HIP [m, device frame]; "
    "force (N, 3) float64, the force on the handle [N, device frame], never NaN; proxy (N, 3) float64, the proxy "
    "(god-object) [model units, model frame], on the displaced surface in contact, else the HIP; normal (N, 3) "
    "float64, the unit contact normal (model frame), NaN when free; depth (N,) float64, (proxy - HIP)·n [model "
    "units], 0 when free; slab (N,) int32, the contact slab or -1; status (N,) int8, hdm.ProxyStatus values (0 free, "
    "1 stuck, 2 sliding, 3 clamped, 4 bad input)";

Workspace workspace_or_fit(const Model& m, const std::optional<Workspace>& ws) {
  return ws ? *ws : fit_workspace(m.box, 0.16);
}

py::dict proxy_trajectory(Model& m, const Points& trajectory, ProxyState& state, const std::optional<Workspace>& ws_in,
                          const ProxyParams& params, double rate_hz, const std::string& mode_name,
                          const std::optional<Points>& velocity) {
  require_rows_of_3(trajectory, "trajectory");
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) throw InvalidInput("rate_hz: must be positive and finite");
  if (velocity) {
    require_rows_of_3(*velocity, "velocity");
    if (velocity->shape(0) != trajectory.shape(0))
      throw InvalidInput("velocity: " + std::to_string(velocity->shape(0)) + " rows for a trajectory of " +
                         std::to_string(trajectory.shape(0)));
  }
  const RenderMode mode = point_render_mode(mode_name);
  const Workspace ws = workspace_or_fit(m, ws_in);
  const py::ssize_t n = trajectory.shape(0);
  const double* p = trajectory.data();
  const double* v = velocity ? velocity->data() : nullptr;
  Run run;
  {
    py::gil_scoped_release release;
    const std::shared_lock lock(m.mutex);
    run.reserve(size_t(n));
    for (py::ssize_t i = 0; i < n; ++i) {
      const Vec3 hip(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
      Vec3 vel = Vec3::Zero();
      if (v)
        vel = Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
      else if (i > 0)
        vel = (hip - Vec3(p[3 * i - 3], p[3 * i - 2], p[3 * i - 1])) * rate_hz;
      else if (state.has_last_hip)
        vel = (hip - ws.to_device(state.last_hip)) * rate_hz;
      if (!vel.allFinite()) vel = Vec3::Zero();  // after a NaN row: the HIP itself is checked
      const ProxyOutput out = render_step(mode, m.model, *m.locator, ws, hip, vel, params, state);
      run.add(double(i) / rate_hz, hip, out, state);
    }
  }
  return run.to_dict();
}

// Closed loop: device → proxy → device, as hdm's servo loop runs it, in simulated time.
py::dict run_device(Model& m, HapticDevice& device, int64_t ticks, const std::optional<Workspace>& ws_in,
                    const ProxyParams& params, const std::string& mode_name) {
  if (ticks < 0) throw InvalidInput("ticks: must be >= 0");
  const RenderMode mode = point_render_mode(mode_name);
  const Workspace ws = workspace_or_fit(m, ws_in);
  Run run;
  {
    py::gil_scoped_release release;
    const std::shared_lock lock(m.mutex);
    run.reserve(size_t(std::min<int64_t>(ticks, int64_t(1) << 24)));
    ProxyState state;
    DeviceState ds;
    for (int64_t i = 0; i < ticks && device.begin_frame(ds); ++i) {
      const ProxyOutput out = render_step(mode, m.model, *m.locator, ws, ds.position, ds.velocity, params, state);
      device.end_frame(out.force);
      run.add(ds.time_s, ds.position, out, state);
    }
  }
  return run.to_dict();
}

// Applies f to every row of an (N, 3) array.
template <class F>
py::array_t<double> map_rows(const Points& p, F&& f) {
  require_rows_of_3(p, "points");
  auto out = rows_of_3(p.shape(0));
  const double* in = p.data();
  double* o = out.mutable_data();
  for (py::ssize_t i = 0; i < p.shape(0); ++i) {
    const Vec3 y = f(Vec3(in[3 * i], in[3 * i + 1], in[3 * i + 2]));
    for (int k = 0; k < 3; ++k) o[3 * i + k] = y[k];
  }
  return out;
}

// A (w, x, y, z) quaternion from a sequence of 4 numbers. @throws InvalidInput naming @p what otherwise.
Eigen::Quaterniond quaternion_from(py::object o, const char* what) {
  const auto v = py::cast<std::vector<double>>(o);
  if (v.size() != 4) throw InvalidInput(std::string(what) + ": expected 4 numbers (w, x, y, z)");
  return Eigen::Quaterniond(v[0], v[1], v[2], v[3]);
}

py::tuple tuple3(const Vec3& v) { return py::make_tuple(v.x(), v.y(), v.z()); }

// Ends @p d's tick with the force @p f and, unless None, the torque @p t.
void end_frame_with(HapticDevice& d, py::object f, py::object t) {
  if (t.is_none())
    d.end_frame(vec3_from(f, "force"));
  else
    d.end_frame(vec3_from(f, "force"), vec3_from(t, "torque"));
}

// A SimulatedDevice with its own copy of the targets (the device keeps spans).
struct PySimulatedDevice {
  std::vector<Vec3> targets;
  std::unique_ptr<SimulatedDevice> device;
};

py::object frame_dict(bool ok, const DeviceState& s) {
  if (!ok) return py::none();
  py::dict d;
  d["position"] = py::make_tuple(s.position.x(), s.position.y(), s.position.z());
  d["velocity"] = py::make_tuple(s.velocity.x(), s.velocity.y(), s.velocity.z());
  d["buttons"] = s.buttons;
  d["time_s"] = s.time_s;
  const Eigen::Quaterniond& q = s.orientation;
  d["orientation"] = py::make_tuple(q.w(), q.x(), q.y(), q.z());
  d["angular_velocity"] = py::make_tuple(s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z());
  return d;
}

// Workspace and fit_workspace: the device frame [m] to the model frame.
void bind_workspace(py::module_& m) {
  py::class_<Workspace>(
      m, "Workspace", "Maps the device frame [m] to the model frame [model units]: x_model = origin + scale·x_device.")
      .def(py::init([](py::object origin, double scale) {
             if (!(scale > 0) || !std::isfinite(scale)) throw InvalidInput("scale: must be positive and finite");
             Workspace w;
             w.origin = vec3_from(origin, "origin");
             w.scale = scale;
             return w;
           }),
           py::arg("origin"), py::arg("scale"),
           "origin: (3,) model point at the device's workspace centre [model units]; scale: model units per metre")
      .def_property_readonly(
          "origin", [](const Workspace& w) { return py::make_tuple(w.origin.x(), w.origin.y(), w.origin.z()); })
      .def_readonly("scale", &Workspace::scale, "model units per metre of device motion")
      .def(
          "to_model",
          [](const Workspace& w, const Points& p) { return map_rows(p, [&](const Vec3& x) { return w.to_model(x); }); },
          py::arg("points"), "(N, 3) device points [m] to model points [model units]")
      .def(
          "to_device",
          [](const Workspace& w, const Points& p) {
            return map_rows(p, [&](const Vec3& x) { return w.to_device(x); });
          },
          py::arg("points"), "(N, 3) model points [model units] to device points [m]");
  m.def(
      "fit_workspace",
      [](const Model& model, double workspace_m) {
        if (!(workspace_m > 0)) throw InvalidInput("workspace_m: must be positive");
        return fit_workspace(model.box, workspace_m);
      },
      py::arg("model"), py::arg("workspace_m") = 0.16,
      "The Workspace that fits the model's slab box diagonal into a device workspace of workspace_m metres, centred "
      "on the box (what proxy_step uses by default).");
}

// The proxy (god-object): its status, parameters, state and the open-loop proxy_step.
void bind_proxy(py::module_& m) {
  py::enum_<ProxyStatus>(m, "ProxyStatus", "Status of one proxy tick (the status arrays hold these values).")
      .value("FREE", ProxyStatus::Free)
      .value("STUCK", ProxyStatus::Stuck)
      .value("SLIDING", ProxyStatus::Sliding)
      .value("CLAMPED", ProxyStatus::Clamped)
      .value("BAD_INPUT", ProxyStatus::BadInput);

  py::class_<ProxyParams>(m, "ProxyParams",
                          "Parameters of the proxy (god-object), SI at the device. Defaults suit a desktop device "
                          "(Phantom Omni / Touch class) at 1 kHz.")
      .def(py::init([](py::kwargs kw) {
             ProxyParams p;
             py::object self = py::cast(p);
             for (auto item : kw) {
               const std::string key = py::str(item.first);
               if (!py::hasattr(self, key.c_str())) throw InvalidInput("ProxyParams: no parameter '" + key + "'");
               self.attr(key.c_str()) = item.second;
             }
             return self.cast<ProxyParams>();
           }),
           "Keyword arguments set the attributes of the same names.")
      .def_property(
          "stiffness", [](const ProxyParams& p) { return p.force.stiffness; },
          [](ProxyParams& p, double v) { p.force.stiffness = v; }, "spring stiffness k [N/m] at the device")
      .def_property(
          "damping", [](const ProxyParams& p) { return p.force.damping; },
          [](ProxyParams& p, double v) { p.force.damping = v; }, "normal damping b [N·s/m]")
      .def_property(
          "max_force", [](const ProxyParams& p) { return p.force.max_force; },
          [](ProxyParams& p, double v) { p.force.max_force = v; }, "force clamp [N]")
      .def_readwrite("damping_force_n", &ProxyParams::damping_force_n,
                     "spring force [N] at which the damping reaches full (ramps in from contact)")
      .def_readwrite("friction_scale", &ProxyParams::friction_scale,
                     "factor on the model's per-sample friction (0: frictionless)")
      .def_readwrite("iterations", &ProxyParams::iterations, "projection rounds per tick (>= 1)")
      .def_readwrite("max_halvings", &ProxyParams::max_halvings, "step halvings per round")
      .def_readwrite("max_turn_deg", &ProxyParams::max_turn_deg, "largest normal turn per step [deg]")
      .def_readwrite("position_limit_m", &ProxyParams::position_limit_m,
                     "a HIP farther than this from the workspace centre [m] gives zero force")
      .def_readwrite("tunnel_step", &ProxyParams::tunnel_step, "free-space sub-step [model units] (0: automatic)")
      .def_readwrite("max_tunnel_steps", &ProxyParams::max_tunnel_steps, "cap on free-space sub-steps per tick")
      .def_readwrite("layer_band", &ProxyParams::layer_band, "under-layer blend band [model units] (0: automatic)")
      .def_property(
          "solver", [](const ProxyParams& p) { return p.solver == AlphaSolver::Newton ? "newton" : "bisection"; },
          [](ProxyParams& p, const std::string& s) { p.solver = parse_alpha_solver(s); },
          "alpha-plane root finder: 'newton' or 'bisection' (the paper's)");

  py::class_<ProxyState>(m, "ProxyState",
                         "The proxy's state carried from tick to tick; pass the same object to successive proxy_step "
                         "calls to continue a motion.")
      .def(py::init<>())
      .def_readonly("contact", &ProxyState::contact, "the proxy is on the surface")
      .def_readonly("stuck", &ProxyState::stuck, "static friction holds the proxy")
      .def_readonly("slab", &ProxyState::slab, "the proxy's slab (-1 when free)")
      .def_property_readonly(
          "position",
          [](const ProxyState& s) { return py::make_tuple(s.position.x(), s.position.y(), s.position.z()); },
          "the proxy [model units, model frame]: on the displaced surface in contact, else the HIP")
      .def_property_readonly(
          "normal", [](const ProxyState& s) { return py::make_tuple(s.normal.x(), s.normal.y(), s.normal.z()); },
          "the unit normal at the proxy (model frame; meaningful in contact)");

  m.def("proxy_step", &proxy_trajectory, py::arg("model"), py::arg("trajectory"), py::arg("state"), py::kw_only(),
        py::arg("workspace") = std::nullopt, py::arg("params") = ProxyParams(), py::arg("rate_hz") = 1000.0,
        py::arg("mode") = "proxy", py::arg("velocity") = std::nullopt,
        (std::string("Runs the proxy (god-object; Zilles & Salisbury 1995, Ruspini et al. 1997) over a trajectory "
                     "of the haptic interaction point, one servo tick per row, open loop (the HIP does not react "
                     "to the force).\n\n"
                     "model: hdm.Model. trajectory: (N, 3) float64 HIP positions [m, device frame], one per tick. "
                     "state: hdm.ProxyState, updated (pass a new one to start free). workspace: hdm.Workspace "
                     "(default fit_workspace(model)). params: hdm.ProxyParams. rate_hz: servo rate [Hz] (the "
                     "velocity is the backward difference times it unless velocity, (N, 3) [m/s], is given). "
                     "mode: 'proxy' or 'penalty' (the paper's memoryless force, §3.4).\n"
                     "Returns ") +
         kRunDoc + ". A non-finite or out-of-range HIP gives zero force and status BAD_INPUT.")
            .c_str());
}

// Devices read once per servo tick: the interface and the simulated device.
void bind_simulated_device(py::module_& m) {
  py::class_<HapticDevice>(m, "HapticDevice", "A haptic device read once per servo tick (begin_frame / end_frame).")
      .def(
          "begin_frame",
          [](HapticDevice& d) {
            DeviceState s;
            const bool ok = d.begin_frame(s);
            return frame_dict(ok, s);
          },
          "Reads the handle: a dict position (3,) [m], velocity (3,) [m/s], buttons (int), time_s [s], "
          "orientation (w, x, y, z) (tool → device frame), angular_velocity (3,) [rad/s], device frame; None when "
          "the device has nothing more to give.")
      .def(
          "end_frame", [](HapticDevice& d, py::object f, py::object t) { end_frame_with(d, f, t); }, py::arg("force"),
          py::arg("torque") = py::none(),
          "Commands the force (3,) [N, device frame] and, when given, the torque (3,) [N·m, device frame] until "
          "the next tick and ends the tick.");

  py::class_<PySimulatedDevice>(m, "SimulatedDevice",
                                "A simulated device: a handle of mass mass_kg pulled by a hand spring-damper towards "
                                "one target per tick and pushed by the rendered force, held over each servo period.")
      .def(py::init([](const Points& targets, py::object start, double mass_kg, double hand_stiffness,
                       double hand_damping, double rate_hz, int substeps, double max_force_n, py::object orientation,
                       double inertia_kgm2, double wrist_stiffness, double wrist_damping, double max_torque_nm) {
             require_rows_of_3(targets, "targets");
             if (targets.shape(0) == 0) throw InvalidInput("targets: no rows");
             auto d = std::make_unique<PySimulatedDevice>();
             d->targets.resize(targets.shape(0));
             for (py::ssize_t i = 0; i < targets.shape(0); ++i)
               d->targets[i] = Vec3(targets.at(i, 0), targets.at(i, 1), targets.at(i, 2));
             SimulatedDeviceOptions o;
             o.mass_kg = mass_kg, o.hand_stiffness = hand_stiffness, o.hand_damping = hand_damping;
             o.rate_hz = rate_hz, o.substeps = substeps, o.spec.max_force_n = max_force_n;
             o.inertia_kgm2 = inertia_kgm2, o.wrist_stiffness = wrist_stiffness, o.wrist_damping = wrist_damping;
             o.spec.max_torque_nm = max_torque_nm;
             if (!orientation.is_none()) o.orientation = quaternion_from(orientation, "orientation");
             const Vec3 x0 = start.is_none() ? d->targets[0] : vec3_from(start, "start");
             d->device = std::make_unique<SimulatedDevice>(o, d->targets, x0);
             return d;
           }),
           py::arg("targets"), py::kw_only(), py::arg("start") = py::none(), py::arg("mass_kg") = 0.05,
           py::arg("hand_stiffness") = 200.0, py::arg("hand_damping") = 2.0, py::arg("rate_hz") = 1000.0,
           py::arg("substeps") = 10, py::arg("max_force_n") = 3.3, py::arg("orientation") = py::none(),
           py::arg("inertia_kgm2") = 1e-4, py::arg("wrist_stiffness") = 1.0, py::arg("wrist_damping") = 0.006,
           py::arg("max_torque_nm") = 0.0,
           "targets: (N, 3) float64 hand targets [m, device frame], one per tick (the last is held); start: (3,) "
           "initial handle position [m] (default the first target); mass_kg [kg], hand_stiffness [N/m], "
           "hand_damping [N·s/m], rate_hz [Hz], substeps per period, max_force_n [N] (force clamp); orientation: "
           "(w, x, y, z) the handle's start and the wrist's target (tool → device frame, normalised; default "
           "identity); inertia_kgm2 [kg·m²] about the tip, wrist_stiffness [N·m/rad] (math.inf: held rigidly), "
           "wrist_damping [N·m·s/rad], max_torque_nm [N·m] (torque clamp; 0: renders no torque, as a 3-DOF "
           "device). Raises ValueError for a non-positive mass, inertia or rate, substeps < 1, a negative wrist "
           "setting or a zero or non-finite orientation.")
      .def(
          "begin_frame",
          [](PySimulatedDevice& d) {
            DeviceState s;
            const bool ok = d.device->begin_frame(s);
            return frame_dict(ok, s);
          },
          "Reads the handle: dict position (3,) [m], velocity (3,) [m/s], buttons, time_s [s], orientation "
          "(w, x, y, z), angular_velocity (3,) [rad/s].")
      .def(
          "end_frame", [](PySimulatedDevice& d, py::object f, py::object t) { end_frame_with(*d.device, f, t); },
          py::arg("force"), py::arg("torque") = py::none(),
          "Holds the force (3,) [N] and the torque (3,) [N·m, device frame, about the tip; default none] over one "
          "period and integrates the handle's position and orientation.")
      .def_property_readonly(
          "wrist_torque", [](const PySimulatedDevice& d) { return tuple3(d.device->wrist_torque()); },
          "the wrist's torque on the handle over the last period [N·m] (zero when held rigidly)")
      .def_property_readonly(
          "hand_force", [](const PySimulatedDevice& d) { return tuple3(d.device->hand_force()); },
          "the hand's force on the handle over the last period [N]")
      .def_property_readonly(
          "tick", [](const PySimulatedDevice& d) { return d.device->tick(); }, "ticks integrated");
}

// A recorded trajectory played as the device, and the closed servo loop in simulated time.
void bind_replay_and_run(py::module_& m) {
  py::class_<ReplayDevice, HapticDevice>(m, "ReplayDevice",
                                         "Plays back a recorded trajectory (CSV of hdm sculpt --forces or hdm feel "
                                         "--trace: time_s,device_x_m,device_y_m,device_z_m,...), one row per tick.")
      .def(py::init([](const std::string& path) { return std::make_unique<ReplayDevice>(path); }), py::arg("path"),
           "Reads the whole file. Raises OSError (hdm.IoError) when it cannot be read, ValueError (hdm.InvalidInput) "
           "naming the file and line for a malformed row.")
      .def_static(
          "from_csv",
          [](const std::string& text, const std::string& name) {
            return std::make_unique<ReplayDevice>(ReplayDevice::from_csv(text, name));
          },
          py::arg("text"), py::arg("name") = "csv", "Loads a recording from CSV text; name starts error messages.")
      .def("__len__", &ReplayDevice::size, "recorded ticks")
      .def_property_readonly("rate_hz", &ReplayDevice::rate_hz, "mean tick rate of the recording [Hz]")
      .def_property_readonly(
          "last_force",
          [](const ReplayDevice& d) {
            const Vec3& f = d.last_force();
            return py::make_tuple(f.x(), f.y(), f.z());
          },
          "the last commanded force [N]");

  const std::string run_doc =
      std::string(
          "Runs the closed servo loop in simulated time: each tick reads the device, runs the proxy (or penalty) "
          "renderer and commands the force (the simulated hand then reacts to it).\n\n"
          "model: hdm.Model; device: hdm.SimulatedDevice or hdm.ReplayDevice; ticks: at most this many (a replay "
          "ends with its rows); workspace: hdm.Workspace (default fit_workspace(model)); params: hdm.ProxyParams; "
          "mode: 'proxy' or 'penalty'.\nReturns ") +
      kRunDoc + ".";
  m.def(
      "run_device",
      [](Model& model, py::object device, int64_t ticks, const std::optional<Workspace>& ws, const ProxyParams& params,
         const std::string& mode) {
        if (py::isinstance<PySimulatedDevice>(device))
          return run_device(model, *device.cast<PySimulatedDevice&>().device, ticks, ws, params, mode);
        return run_device(model, device.cast<HapticDevice&>(), ticks, ws, params, mode);
      },
      py::arg("model"), py::arg("device"), py::arg("ticks"), py::kw_only(), py::arg("workspace") = std::nullopt,
      py::arg("params") = ProxyParams(), py::arg("mode") = "proxy", run_doc.c_str());
}

}  // namespace

void bind_haptics(py::module_& m) {
  bind_workspace(m);
  bind_proxy(m);
  bind_simulated_device(m);
  bind_replay_and_run(m);
}

}  // namespace hdm::python
