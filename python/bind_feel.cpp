// SPDX-License-Identifier: MIT
// The Python module's hdm.feel: the scripted haptic scenarios of `hdm feel` (hdm::harness), scored
// against the exact input mesh, returning the same dict as `hdm feel --json`.
#include <hdm/harness/scenarios.h>
#include <hdm/harness/tool_scenarios.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>

#include "py_model.h"

#include <filesystem>
#include <optional>

namespace hdm::python {
namespace {

// The input named in model.source: as written, else next to the model's file (as hdm feel finds it).
std::string find_input(const Model& m) {
  namespace fs = std::filesystem;
  const fs::path src(m.model.source);
  if (!m.model.source.empty() && fs::exists(src)) return src.string();
  if (!m.path.empty()) {
    const fs::path next = fs::path(m.path).parent_path() / src.filename();
    if (!src.filename().empty() && fs::exists(next)) return next.string();
  }
  throw InvalidInput("model: input mesh '" + m.model.source + "' not found; pass it as input=");
}

// The renderer's parameters of feel() and feel_tool(): solver, stiffness, damping and its ramp, force limit.
ProxyParams proxy_params(const std::string& solver, double stiffness, double damping, double damping_force,
                         double max_force) {
  ProxyParams p;
  p.solver = parse_alpha_solver(solver);
  p.force.stiffness = stiffness;
  p.force.damping = damping;
  p.damping_force_n = damping_force;
  p.force.max_force = max_force;
  return p;
}

py::dict feel(py::object model_arg, const std::string& scenario, const std::string& input_arg,
              const std::string& replay, const std::string& mode, double radius, const std::string& solver, double rate,
              double stiffness, double damping, double damping_force, double max_force, double speed, double press,
              bool friction, bool trace) {
  ModelPtr model =
      py::isinstance<py::str>(model_arg)
          ? std::make_shared<Model>(load_model(model_arg.cast<std::string>()), model_arg.cast<std::string>())
          : model_arg.cast<ModelPtr>();
  if (scenario.empty() == replay.empty()) throw InvalidInput("feel: give either scenario or replay= (exactly one)");
  if (!(rate >= 100 && rate <= 1e6)) throw InvalidInput("rate: must be in [100, 1e6] Hz");
  if (!(damping_force >= 0 && damping_force <= 100)) throw InvalidInput("damping_force: must be in [0, 100] N");
  ScenarioOptions o;
  if (!scenario.empty()) o.scenario = parse_scenario(scenario);
  o.mode = parse_render_mode(mode);
  o.ball_radius = radius;
  o.proxy = proxy_params(solver, stiffness, damping, damping_force, max_force);
  o.rate_hz = rate;
  o.friction = friction;
  o.speed_m_s = speed;
  o.press_force_n = press;
  o.keep_trace = trace;
  const std::string input = input_arg.empty() ? find_input(*model) : input_arg;
  ScenarioReport r;
  {
    py::gil_scoped_release release;
    const ExactMeshQuery reference(read_mesh(input));
    const std::shared_lock lock(model->mutex);
    if (!replay.empty()) {
      ReplayDevice device(replay);
      r = run_replay(model->model, *model->locator, reference, device, o);
    } else {
      r = run_scenario(model->model, *model->locator, reference, o);
    }
  }
  py::dict d;
  d["model"] = model->path;
  d["input"] = input;
  d["scenario"] = r.scenario;
  d["rate_hz"] = r.rate_hz;
  d["mode"] = r.mode;
  d["ball_radius"] = r.ball_radius;
  d["solver"] = solver;
  d["replay"] = replay;
  d["friction"] = friction;
  d["ticks"] = r.ticks;
  d["contact_ticks"] = r.contact_ticks;
  d["pop_throughs"] = r.pop_throughs;
  d["max_force_step_pct"] = r.max_force_step_pct;
  d["reference_force_step_pct"] = r.reference_force_step_pct;
  d["reference_facet_force_step_pct"] = r.reference_facet_force_step_pct;
  d["normal_error_p95_deg"] = r.normal_error_p95_deg;
  d["normal_error_smooth_p95_deg"] = r.normal_error_smooth_p95_deg;
  d["normal_floor_p95_deg"] = r.normal_floor_p95_deg;
  d["energy_ratio"] = r.energy_ratio;
  d["stable_stiffness_n_per_m"] = r.stable_stiffness_n_per_m;
  d["passive_stiffness_n_per_m"] = r.passive_stiffness_n_per_m;
  d["max_force_n"] = r.max_force_n;
  d["mean_contact_force_n"] = r.mean_contact_force_n;
  d["force_cv"] = r.force_cv;
  d["max_penetration_mm"] = r.max_penetration_mm;
  d["proxy_surface_error_max"] = r.proxy_surface_error_max;
  d["slab_crossings"] = r.slab_crossings;
  d["bad_input_ticks"] = r.bad_input_ticks;
  py::dict tick;
  tick["median"] = r.tick_ns_median;
  tick["p99"] = r.tick_ns_p99;
  tick["max"] = r.tick_ns_max;
  d["tick_ns"] = tick;
  d["note"] = r.note;
  d["trace"] = "";
  if (trace) {
    const py::ssize_t n = py::ssize_t(r.trace.size());
    py::array_t<double> t(n), depth(n);
    auto device = rows_of_3(n), force = rows_of_3(n), proxy = rows_of_3(n), normal = rows_of_3(n);
    py::array_t<int32_t> status(n), slab(n);
    for (py::ssize_t i = 0; i < n; ++i) {
      const ScenarioTraceRow& row = r.trace[i];
      t.mutable_at(i) = row.t, depth.mutable_at(i) = row.depth_mm;
      status.mutable_at(i) = row.status, slab.mutable_at(i) = row.slab;
      for (int k = 0; k < 3; ++k) {
        device.mutable_at(i, k) = row.device[k], force.mutable_at(i, k) = row.force[k];
        proxy.mutable_at(i, k) = row.proxy[k], normal.mutable_at(i, k) = row.normal[k];
      }
    }
    py::dict rows;
    rows["time"] = t, rows["device"] = device, rows["force"] = force, rows["depth_mm"] = depth;
    rows["status"] = status, rows["slab"] = slab, rows["proxy"] = proxy, rows["normal"] = normal;
    d["trace_rows"] = rows;
  }
  return d;
}

// A 3-vector as the list `hdm feel --json` writes.
py::list xyz(const Vec3& v) {
  py::list l;
  for (int k = 0; k < 3; ++k) l.append(v[k]);
  return l;
}

// A tool scenario (no model): the dict of `hdm feel --scenario NAME --json` for slot, roll_edge,
// shaft_edge and drill_layers.
py::dict feel_tool(const std::string& scenario, const std::string& solver, double rate, double stiffness,
                   double damping, double damping_force, double max_force, double speed, double press) {
  ToolScenarioOptions o;
  o.scenario = parse_tool_scenario(scenario);
  o.rate_hz = rate;
  o.proxy = proxy_params(solver, stiffness, damping, damping_force, max_force);
  o.speed_m_s = speed;
  o.press_force_n = press;
  ToolScenarioReport r;
  {
    py::gil_scoped_release release;
    r = run_tool_scenario(o);
  }
  const bool rigid = o.scenario == ToolScenario::ShaftEdge || o.scenario == ToolScenario::DrillLayers;
  py::dict d;
  d["scenario"] = r.scenario, d["rate_hz"] = r.rate_hz, d["mode"] = rigid ? "rigid" : "sphere";
  d["radius"] = r.radius, d["ticks"] = r.ticks, d["contact_ticks"] = r.contact_ticks;
  d["max_penetration_pct_r"] = r.max_penetration_pct_r, d["rest_height_error_pct_r"] = r.rest_height_error_pct_r;
  d["entered"] = r.entered, d["max_force_step_pct"] = r.max_force_step_pct;
  d["max_direction_step_deg"] = r.max_direction_step_deg, d["normal_error_p95_deg"] = r.normal_error_p95_deg;
  d["normal_error_max_deg"] = r.normal_error_max_deg, d["max_force_n"] = r.max_force_n;
  d["energy_ratio"] = r.energy_ratio;
  d["mean_contact_force_n"] = r.mean_contact_force_n, d["head_contacts"] = r.head_contacts;
  d["shaft_contacts"] = r.shaft_contacts, d["torque_error_pct"] = r.torque_error_pct;
  d["torque_sense_ok"] = r.torque_sense_ok, d["torque_nm"] = xyz(r.tool_torque), d["force_n"] = xyz(r.tool_force);
  d["tool_tip"] = xyz(r.tool_tip), d["tool_axis"] = xyz(r.tool_axis);
  d["enamel_rate_mm3_per_ns"] = r.enamel_rate, d["dentin_rate_mm3_per_ns"] = r.dentin_rate;
  d["enamel_archard_mm3_per_ns"] = r.enamel_archard, d["dentin_archard_mm3_per_ns"] = r.dentin_archard;
  d["ratio_error_pct"] = r.ratio_error_pct, d["note"] = r.note;
  return d;
}

}  // namespace

void bind_feel(py::module_& m) {
  m.def("feel_tool", &feel_tool, py::arg("scenario"), py::kw_only(), py::arg("solver") = "newton",
        py::arg("rate") = 1000.0, py::arg("stiffness") = 1000.0, py::arg("damping") = 1.0,
        py::arg("damping_force") = 0.2, py::arg("max_force") = 3.3, py::arg("speed") = 0.1, py::arg("press") = 1.0,
        "Runs a tool scenario of `hdm feel` (no model: each builds its block in code; hdm::run_tool_scenario): "
        "'slot' and 'roll_edge' (the sphere proxy), 'shaft_edge' and 'drill_layers' (the rigid burr). solver "
        "'newton' or 'bisection'; rate [Hz]; stiffness [N/m]; damping [N·s/m]; damping_force [N]; max_force [N]; "
        "speed [m/s]; press [N].\n"
        "Returns the dict of `hdm feel --scenario NAME --json` (same keys and values).\n"
        "Raises ValueError for an unknown scenario or solver, or an option out of range, naming it.");
  m.def("feel", &feel, py::arg("model"), py::arg("scenario") = "", py::kw_only(), py::arg("input") = "",
        py::arg("replay") = "", py::arg("mode") = "proxy", py::arg("radius") = 0.0, py::arg("solver") = "newton",
        py::arg("rate") = 1000.0, py::arg("stiffness") = 1000.0, py::arg("damping") = 1.0,
        py::arg("damping_force") = 0.2, py::arg("max_force") = 3.3, py::arg("speed") = 0.1, py::arg("press") = 1.0,
        py::arg("friction") = false, py::arg("trace") = false,
        "Runs a scripted haptic scenario with a simulated hand (or plays a recorded trajectory) and scores it "
        "against the exact input mesh, as `hdm feel --json` does (hdm::harness).\n\n"
        "model: hdm.Model or an .hdm path. scenario: 'slide', 'press', 'thin', 'edges' or 'stiff' (or replay=: a CSV "
        "with time_s,device_x_m,device_y_m,device_z_m). input: the input mesh (default: model.source, as written or "
        "next to the model's file). mode 'proxy', 'penalty' or 'sphere' (a ball of radius [model units], 0: 1 % of the "
        "model's diagonal); solver 'newton' or 'bisection'; rate [Hz]; stiffness "
        "[N/m]; damping [N·s/m]; damping_force [N]; max_force [N]; speed [m/s]; press [N]; friction: use the model's "
        "friction fields.\n"
        "Returns the dict of `hdm feel --json` (same keys; 'model' is the model's file or ''; 'trace' is ''); with "
        "trace=True also 'trace_rows': arrays time (N,) [s], device (N, 3) [m], force (N, 3) [N], depth_mm (N,), "
        "status (N,), slab (N,), proxy (N, 3) [m, device frame], normal (N, 3).\n"
        "Raises ValueError for an unknown scenario, mode or solver, or a scenario that cannot be placed on the model; "
        "OSError for a file that cannot be read.");
}

}  // namespace hdm::python
