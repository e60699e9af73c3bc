// SPDX-License-Identifier: MIT
// The Python module's edits: brushes, strokes along a path of tool positions (one method per
// registered brush, through hdm::StrokeEditor), undo and redo, the under-layer, and the per-sample
// and per-texel fields as arrays.
#include <hdm/edit/brush.h>
#include <hdm/edit/brush_registry.h>
#include <hdm/edit/edit_tools.h>
#include <hdm/edit/stroke_editor.h>
#include <hdm/query/slab_query.h>

#include "py_model.h"

#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>

namespace hdm::python {
namespace {

StrokeEditor& editor_of(Model& m) {
  if (!m.editor) m.editor = std::make_unique<StrokeEditor>(m.model);
  return *m.editor;
}

// Runs the editor's queue to the end (no deadline: Python is not a servo thread).
void drain(Model& m, EditWork* total = nullptr) {
  StrokeEditor& e = editor_of(m);
  e.flush();
  for (;;) {
    const EditWork w = e.work(m.model, std::numeric_limits<int64_t>::max());
    if (total) total->sweeps += w.sweeps, total->visited += w.visited, total->changed += w.changed;
    if (e.idle()) break;
  }
  clear_dirty(e.scratch());
}

// One stroke: a tool position per row of `path` [model units], one servo tick each.
py::dict stroke(Model& m, const Points& path, const Brush& brush, double rate_hz, std::optional<double> force_n) {
  require_rows_of_3(path, "path");
  check_brush(brush);
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) throw InvalidInput("rate_hz: must be positive and finite");
  const double force = force_n.value_or(brush.pressure_force_n);
  if (!(force >= 0) || !std::isfinite(force)) throw InvalidInput("force_n: must be >= 0 and finite");
  const py::ssize_t n = path.shape(0);
  const double* p = path.data();
  EditWork total;
  int64_t in_slab = 0;
  {
    py::gil_scoped_release release;
    const std::unique_lock lock(m.mutex);
    ++m.edits;
    StrokeEditor& e = editor_of(m);
    e.begin_stroke(brush);
    QueryCache cache;
    for (py::ssize_t i = 0; i < n; ++i) {
      ToolSample s;
      s.hip = Vec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
      s.contact = query(m.model, *m.locator, s.hip, cache);
      if (!s.contact.in_shell()) continue;
      ++in_slab;
      s.normal_force_n = force;
      s.time_s = double(i) / rate_hz;
      e.add_sample(m.model, s);
      // Sweep as the servo loop would: the tool's axis reads the surface the stroke started from.
      const EditWork w = e.work(m.model, std::numeric_limits<int64_t>::max());
      total.sweeps += w.sweeps, total.visited += w.visited, total.changed += w.changed;
    }
    e.end_stroke();
    drain(m, &total);
  }
  py::dict d;
  d["tool_positions"] = in_slab;  // rows whose position lies in a slab (the others are skipped)
  d["sweeps"] = total.sweeps;
  d["visited"] = total.visited;
  d["changed"] = total.changed;
  return d;
}

bool undo_redo(Model& m, bool undo) {
  py::gil_scoped_release release;
  const std::unique_lock lock(m.mutex);
  ++m.edits;
  StrokeEditor& e = editor_of(m);
  drain(m);
  if (undo ? !e.history().can_undo() : !e.history().can_redo()) return false;
  if (undo ? !e.undo() : !e.redo()) return false;
  drain(m);
  return true;
}

constexpr const char* kStrokeReturns =
    "Returns a dict: tool_positions (rows in a slab; rows outside the shell are skipped), sweeps, visited and "
    "changed (samples, or texels for colour and roughness).";

Brush make_brush(const std::string& tool, double radius, double strength, const std::string& falloff, double resilience,
                 double height, const std::string& field, py::object colour, double value, double pressure_force_n,
                 double wear_coefficient, double rpm) {
  Brush b;
  b.tool = parse_brush_tool(tool);
  b.radius = radius;
  b.strength = strength;
  b.falloff = falloff.empty() ? find_brush(b.tool)->falloff : parse_falloff(falloff);
  b.resilience = resilience;
  b.height = height;
  b.field = parse_brush_field(field);
  if (!colour.is_none()) b.colour = vec3_from(colour, "colour").cast<float>();
  b.value = float(value);
  b.pressure_force_n = pressure_force_n;
  b.wear_coefficient = wear_coefficient;
  b.rpm = rpm;
  check_brush(b);
  return b;
}

// A 16-bit field (Half16, Unorm16; an array or a SampleField) decoded to float32: the values the
// model uses, one per sample.
template <class Field>
py::array_t<float> decoded(const Field& v) {
  py::array_t<float> a(py::ssize_t(v.size()));
  for (size_t i = 0; i < v.size(); ++i) a.mutable_data()[i] = float(v[i]);
  return a;
}

const char* falloff_name(Falloff f) {
  return f == Falloff::Constant ? "constant" : f == Falloff::Linear ? "linear" : "smooth";
}

// The Brush class (hdm::Brush), its docstring from the brush registry.
void bind_brush(py::module_& m) {
  std::string doc = "A sculpting or painting brush. Lengths in model units. tool:";
  for (const BrushInfo& i : brush_registry())
    doc += std::string(" '") + i.name + "' (" + i.summary + "; default falloff " + falloff_name(i.falloff) + ");";
  doc +=
      " falloff: 'constant', 'linear' or 'smooth'. field (paint): 'colour', 'roughness', 'friction_static', "
      "'friction_dynamic', 'stiffness', 'layer_thickness', 'hardness'.";
  py::class_<Brush>(m, "Brush", doc.c_str())
      .def(py::init(&make_brush), py::arg("tool"), py::arg("radius"), py::kw_only(), py::arg("strength") = 1.0,
           py::arg("falloff") = "", py::arg("resilience") = 0.0, py::arg("height") = 0.0, py::arg("field") = "colour",
           py::arg("colour") = py::none(), py::arg("value") = 0.0, py::arg("pressure_force_n") = 1.0,
           py::arg("wear_coefficient") = Brush{}.wear_coefficient, py::arg("rpm") = Brush{}.rpm,
           "radius [model units] > 0; strength in [0, 1]; resilience: carve's resilient band [model units]; "
           "height: add's ridge height [model units]; colour: (3,) linear RGB in [0, 1]; value: the painted value "
           "of a scalar field (model units for layer_thickness); pressure_force_n: normal force [N] of full "
           "pressure; wear_coefficient: drill's Archard K in (0, 1]; rpm: drill's burr speed [rev/min] in (0, 1e6]. "
           "Raises ValueError for an unknown name or a value out of range.")
      .def_property_readonly("tool", [](const Brush& b) { return std::string(brush_tool_name(b.tool)); })
      .def_readonly("radius", &Brush::radius)
      .def_readonly("strength", &Brush::strength)
      .def_readonly("height", &Brush::height)
      .def_readonly("resilience", &Brush::resilience)
      .def_readonly("wear_coefficient", &Brush::wear_coefficient)
      .def_readonly("rpm", &Brush::rpm);
  m.def(
      "brushes",
      [] {
        py::list out;
        for (const BrushInfo& i : brush_registry()) {
          py::dict d;
          d["name"] = i.name, d["label"] = i.label, d["summary"] = i.summary, d["falloff"] = falloff_name(i.falloff);
          py::dict params;
          for (int p = 0; p < brush_param_count; ++p) {
            if (!i.uses(BrushParam(p))) continue;
            const BrushParamRange& r = brush_param_range(BrushParam(p));
            params[r.name] = py::make_tuple(r.lo, r.hi, r.lo_open);
          }
          d["params"] = params;
          out.append(d);
        }
        return out;
      },
      "The registered brushes, in order: a list of dicts with name (Brush's tool), label (the studio's), summary, "
      "falloff (the default) and params ({keyword: (lo, hi, lo_open)}: the parameters the brush reads and their "
      "valid range; lo = hi = 0 for the enumerations falloff and field).");
}

// Model.stroke and one method per registered brush (carve, add, smooth, flatten, paint, drill).
void bind_strokes(py::module_& m) {
  auto model = py::reinterpret_borrow<py::class_<Model, ModelPtr>>(m.attr("Model"));
  model.def("stroke", &stroke, py::arg("path"), py::arg("brush"), py::kw_only(), py::arg("rate_hz") = 1000.0,
            py::arg("force_n") = std::nullopt,
            (std::string("Applies one stroke of `brush` along `path` as a sculpting session does (hdm::StrokeEditor: "
                         "the brush swept between consecutive positions, once per stroke whatever the rate).\n\n"
                         "path: (N, 3) float64 tool positions [model units, model frame], one per servo tick at "
                         "rate_hz [Hz]: the haptic interaction point (carve cuts down to it; add, smooth, flatten "
                         "and paint act around the surface point on its projection line). force_n: the normal "
                         "force [N] giving the pressure of paint, smooth and flatten and drill's F_n (default: the "
                         "brush's full pressure). Drill reads model units as millimetres (1000 per metre). One undo "
                         "step. ") +
             kStrokeReturns)
                .c_str());
  // pybind11 copies the name and the doc; the captured tool name is the registry's (static).
  auto tool = [&](const char* name, const char* tool_name, const char* doc) {
    model.def(
        name,
        [tool_name](Model& self, const Points& path, double radius, double strength, const std::string& falloff,
                    double resilience, double height, const std::string& field, py::object colour, double value,
                    double wear_coefficient, double rpm, double rate_hz, std::optional<double> force_n) {
          return stroke(self, path,
                        make_brush(tool_name, radius, strength, falloff, resilience, height, field, colour, value, 1.0,
                                   wear_coefficient, rpm),
                        rate_hz, force_n);
        },
        py::arg("path"), py::arg("radius"), py::kw_only(), py::arg("strength") = 1.0, py::arg("falloff") = "",
        py::arg("resilience") = 0.0, py::arg("height") = 0.0, py::arg("field") = "colour",
        py::arg("colour") = py::none(), py::arg("value") = 0.0, py::arg("wear_coefficient") = Brush{}.wear_coefficient,
        py::arg("rpm") = Brush{}.rpm, py::arg("rate_hz") = 1000.0, py::arg("force_n") = std::nullopt, doc);
  };
  for (const BrushInfo& i : brush_registry()) {
    const std::string doc =
        std::string("Model.stroke with Brush('") + i.name + "', radius, ...) along path ((N, 3) or " +
        "(1, 3) float64 tool positions [model units]; a single row is a single stamp): " + i.summary +
        ". Returns Model.stroke's dict.";
    tool(i.name, i.name, doc.c_str());
  }
}

// Model.undo, redo, set_under_layer and field.
void bind_model_edits(py::module_& m) {
  auto model = py::reinterpret_borrow<py::class_<Model, ModelPtr>>(m.attr("Model"));
  model
      .def(
          "undo", [](Model& self) { return undo_redo(self, true); },
          "Undoes the last stroke. Returns False when there is none to undo.")
      .def(
          "redo", [](Model& self) { return undo_redo(self, false); },
          "Redoes the last undone stroke. Returns False when there is none (a new stroke discards the redo steps).")
      .def(
          "set_under_layer",
          [](Model& self, double thickness, py::object colour, double stiffness_scale, double friction_static,
             double friction_dynamic, double hardness_hv) {
            if (!(thickness >= 0) || !std::isfinite(thickness)) throw InvalidInput("thickness: must be >= 0");
            UnderLayer u;
            if (!colour.is_none()) u.colour = vec3_from(colour, "colour").cast<float>();
            u.stiffness_scale = float(stiffness_scale);
            u.friction_static = float(friction_static), u.friction_dynamic = float(friction_dynamic);
            if (!(hardness_hv > 0) || !std::isfinite(hardness_hv))
              throw InvalidInput("hardness_hv: must be > 0 and finite");
            u.hardness_hv = float(hardness_hv);
            py::gil_scoped_release release;
            const std::unique_lock lock(self.mutex);
            ++self.edits;
            set_under_layer(self.model, thickness, u);
          },
          py::arg("thickness"), py::kw_only(), py::arg("colour") = py::none(), py::arg("stiffness_scale") = 0.5,
          py::arg("friction_static") = 0.3, py::arg("friction_dynamic") = 0.2,
          py::arg("hardness_hv") = double(UnderLayer{}.hardness_hv),
          "Puts a second material `thickness` [model units] below the current surface (paper §2, e.g. enamel "
          "over dentin): where carving exposes it, the renderer shows its colour (3,) linear RGB and the proxy "
          "renders its stiffness scale in [0, 1] and friction, and the drill reads its Vickers hardness [HV].")
      .def(
          "field",
          [](Model& self, const std::string& name) -> py::array {
            const std::shared_lock lock(self.mutex);
            const SlabModel& s = self.model;
            if (name == "displacement") return decoded(s.displacement);
            if (name == "friction_static") return decoded(s.friction_static);
            if (name == "friction_dynamic") return decoded(s.friction_dynamic);
            if (name == "stiffness") return decoded(s.stiffness_scale);
            if (name == "roughness") {  // decoded, like colour: the values a brush's `value` is compared with
              py::array_t<float> a(py::ssize_t(s.roughness.size()));
              for (size_t i = 0; i < s.roughness.size(); ++i) a.mutable_data()[i] = unorm8_to_unit(s.roughness[i]);
              return a;
            }
            if (name == "layer_displacement") return decoded(s.layer_displacement);
            if (name == "hardness") return decoded(s.hardness);
            if (name == "colour" || name == "positions" || name == "normals") {
              const bool colour = name == "colour", normals = name == "normals";
              const size_t n = colour ? s.colour.size() : size_t(s.samples.count);
              py::array_t<float> a({py::ssize_t(n), py::ssize_t(3)});
              float* d = a.mutable_data();
              for (size_t i = 0; i < n; ++i) {
                const Vec3f c = colour    ? decode_srgb8(s.colour[i])
                                : normals ? sample_normal(s, static_cast<int32_t>(i))
                                          : Vec3f(sample_position(s, static_cast<int>(i)).cast<float>());
                for (int k = 0; k < 3; ++k) d[3 * i + k] = c[k];
              }
              return a;
            }
            throw InvalidInput("field: '" + name +
                               "' is not one of displacement, positions, normals, friction_static, friction_dynamic, "
                               "stiffness, layer_displacement, hardness (per sample), colour, roughness (per texel)");
          },
          py::arg("name"),
          "A copy of a stored field as a float32 array: per displacement sample (#samples,): displacement δ in [0, "
          "1], friction_static, friction_dynamic, stiffness (scale in [0, 1]), layer_displacement (empty without "
          "an under-layer), hardness [HV] (the last five decoded from the model's 16-bit codes: binary16 for the "
          "frictions and hardness, unorm16 for stiffness and layer_displacement); per sample (#samples, 3): "
          "positions [model units], normals (unit to 2.7e-5, decoded from snorm16); per "
          "texel: colour "
          "(#texels, 3) linear RGB decoded from the stored 8-bit sRGB, roughness (#texels,) decoded from unorm8 (code "
          "/ "
          "255).");
}

}  // namespace

void bind_edit(py::module_& m) {
  bind_brush(m);
  bind_strokes(m);
  bind_model_edits(m);
}

}  // namespace hdm::python
