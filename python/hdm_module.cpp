// SPDX-License-Identifier: MIT
// The Python module `hdm` (pybind11, NumPy arrays): bake, load and save slab models, vectorised
// haptic queries, export. Docstrings give shapes, dtypes and units. Errors are Python exceptions
// carrying the C++ message: ValueError for InvalidInput, OSError for IoError, RuntimeError
// otherwise.
#include <hdm/analysis/fidelity.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/slab/shell_check.h>
#include <hdm/core/error.h>
#include <hdm/io/export_mesh.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>
#include <hdm/pipeline/bake_input.h>
#include <hdm/query/slab_locator.h>
#include <hdm/query/slab_query.h>
#include <hdm/slab/bake.h>

#include "py_model.h"

#include <pybind11/stl.h>

#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <utility>
#include <variant>
#include <vector>

namespace hdm::python {

Vec3 vec3_from(const py::handle& h, const char* what) {
  const Points a = py::cast<Points>(h);
  if (a.size() != 3) throw InvalidInput(std::string(what) + ": expected three numbers");
  return Vec3(a.data()[0], a.data()[1], a.data()[2]);
}

Model::Model(SlabModel m, std::string file)
    : model(std::move(m)), locator(std::make_unique<SlabLocator>(model)), path(std::move(file)) {
  for (size_t v = 0; v < model.inner.size(); ++v) box.extend(model.inner[v]), box.extend(model.outer[v]);
  open = analyze_topology(TriangleMesh{model.inner, model.slabs}).boundary_edges > 0;
}

const ExactMeshQuery& Model::displaced_side() {
  const std::lock_guard lock(side_mutex);
  if (!side || side_edits != edits) {
    TriangleMesh surface;
    displaced_surface(model, surface.vertices, surface.faces);
    side = std::make_unique<ExactMeshQuery>(surface);
    side_edits = edits;
  }
  return *side;
}

}  // namespace hdm::python

using namespace hdm;
using namespace hdm::python;

namespace {

using Faces = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

TriangleMesh mesh_from_arrays(const Points& v, const Faces& f) {
  if (v.ndim() != 2 || v.shape(1) != 3) throw InvalidInput("vertices: expected an (N, 3) array");
  if (f.ndim() != 2 || f.shape(1) != 3) throw InvalidInput("faces: expected an (M, 3) array of vertex indices");
  TriangleMesh m;
  const auto V = v.unchecked<2>();
  const auto F = f.unchecked<2>();
  m.vertices.resize(V.shape(0));
  for (py::ssize_t i = 0; i < V.shape(0); ++i) m.vertices[i] = Vec3(V(i, 0), V(i, 1), V(i, 2));
  m.faces.resize(F.shape(0));
  for (py::ssize_t i = 0; i < F.shape(0); ++i) {
    for (int k = 0; k < 3; ++k) {
      const int64_t id = F(i, k);
      if (id < 0 || id >= V.shape(0))
        throw InvalidInput("faces: row " + std::to_string(i) + " names vertex " + std::to_string(id) +
                           ", outside [0, " + std::to_string(V.shape(0)) + ")");
    }
    m.faces[i] = Tri{int32_t(F(i, 0)), int32_t(F(i, 1)), int32_t(F(i, 2))};
  }
  return m;
}

py::dict fidelity_dict(const Fidelity& f) {
  py::dict d;
  d["rms_pct"] = f.rms_pct;
  d["max_pct"] = f.max_pct;
  d["rms_back_pct"] = f.rms_back_pct;
  d["max_back_pct"] = f.max_back_pct;
  return d;
}

// hdm.bake(): bake_input(), the bake `hdm bake` and the studio run, so a mesh baked here with the
// same options gives the same model byte for byte.
py::tuple bake_mesh(const std::variant<std::string, std::pair<Points, Faces>>& input, int slabs, int grid,
                    double density, int texels, double max_error, double rms_error, bool error_bound, bool repair) {
  std::string name = "arrays";
  TriangleMesh mesh;
  if (const auto* path = std::get_if<std::string>(&input)) {
    name = *path;
    mesh = read_mesh(*path);
  } else {
    const auto& arrays = std::get<std::pair<Points, Faces>>(input);
    mesh = mesh_from_arrays(arrays.first, arrays.second);
  }
  BakeInputOptions o;
  o.bake.slabs = slabs;
  o.bake.grid_n = grid;
  o.bake.density = density;
  o.bake.texel_density = texels;
  o.prepare.repair = repair;
  o.tolerance.max_pct = max_error;
  o.tolerance.rms_pct = rms_error;
  o.bounded = error_bound;
  BakeInputReport rep;
  SlabModel model;
  {
    py::gil_scoped_release release;
    model = bake_input(std::move(mesh), name, o, &rep);
  }
  const BakeReport& r = rep.bake;
  py::dict report;
  if (error_bound) {
    report["bound_met"] = rep.rounds.back().met;
    report["rounds"] = rep.rounds.size();
    report["stopped_because"] = describe_stop(rep.rounds.back(), o.tolerance, r.input_triangles);
  }
  report["slabs"] = r.slabs;
  report["grid"] = r.grid_n;
  report["samples"] = r.samples;
  report["input_triangles"] = r.input_triangles;
  report["invalid_slabs"] = r.invalid_slabs;
  report["overlapping_pairs"] = r.overlapping_pairs;
  report["ray_misses"] = r.ray_misses;
  report["bake_seconds"] = r.seconds;
  report["self_intersections"] = rep.input.self_intersections;
  report["fidelity"] = fidelity_dict(rep.fidelity);
  return py::make_tuple(std::make_shared<Model>(std::move(model)), report);
}

py::dict query_points(Model& m, const Points& points) {
  require_rows_of_3(points, "points");
  const py::ssize_t n = points.shape(0);
  if (n > py::ssize_t(std::numeric_limits<uint32_t>::max())) throw InvalidInput("points: more than 2^32 rows");
  py::array_t<bool> inside(n);
  py::array_t<double> depth(n), surface({n, py::ssize_t(3)}), normal({n, py::ssize_t(3)});
  py::array_t<int32_t> slab(n);
  const double* p = points.data();
  bool* in = inside.mutable_data();
  double *d = depth.mutable_data(), *sp = surface.mutable_data(), *nm = normal.mutable_data();
  int32_t* sl = slab.mutable_data();
  {
    py::gil_scoped_release release;
    const std::shared_lock lock(m.mutex);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    // Points in Morton order of a grid over the model's box, about two cells per point up to 128³
    // (a counting sort: O(N + cells), no comparisons): neighbours in a chunk share slabs, so the
    // query's coherence cache (previous slab, its neighbours) answers most of them, as it does
    // along a servo path. Points in random order would each need the global lookup.
    int bits = 1;
    while (bits < 7 && (int64_t(1) << (3 * bits)) < 2 * int64_t(n)) ++bits;
    const uint32_t cells = uint32_t(1) << (3 * bits), top = (uint32_t(1) << bits) - 1;
    const ExactMeshQuery* side = m.open ? &m.displaced_side() : nullptr;
    const Aabb box = m.box;
    const Vec3 scale = (box.max - box.min).cwiseMax(1e-300).cwiseInverse() * double(top);
    std::vector<uint32_t> code(static_cast<size_t>(n)), order(static_cast<size_t>(n));
    auto spread = [](uint32_t v) {  // 10 bits -> every third bit
      v &= 0x3ff;
      v = (v | (v << 16)) & 0x030000ff;
      v = (v | (v << 8)) & 0x0300f00f;
      v = (v | (v << 4)) & 0x030c30c3;
      return (v | (v << 2)) & 0x09249249;
    };
    tbb::parallel_for(tbb::blocked_range<py::ssize_t>(0, n, 65536), [&](const tbb::blocked_range<py::ssize_t>& r) {
      for (py::ssize_t i = r.begin(); i < r.end(); ++i) {
        uint32_t c[3];
        for (int k = 0; k < 3; ++k) {
          const double u = (p[3 * i + k] - box.min[k]) * scale[k];
          c[k] = u >= 0 ? uint32_t(std::min(u, double(top))) : 0;  // NaN -> 0
        }
        code[i] = spread(c[0]) | (spread(c[1]) << 1) | (spread(c[2]) << 2);
      }
    });
    std::vector<uint32_t> start(size_t(cells) + 1, 0);
    for (py::ssize_t i = 0; i < n; ++i) ++start[code[i] + 1];
    for (uint32_t k = 0; k < cells; ++k) start[k + 1] += start[k];
    for (py::ssize_t i = 0; i < n; ++i) order[start[code[i]]++] = uint32_t(i);
    tbb::parallel_for(tbb::blocked_range<py::ssize_t>(0, n, 4096), [&](const tbb::blocked_range<py::ssize_t>& r) {
      QueryCache cache;  // coherence within a chunk, as the servo loop has along a path
      for (py::ssize_t j = r.begin(); j < r.end(); ++j) {
        // The points are visited out of their memory order: fetch the input and output rows of the
        // point 16 visits ahead, so that their cache misses overlap with this query.
        if (j + 16 < r.end()) {
          const py::ssize_t a = order[j + 16];
          __builtin_prefetch(p + 3 * a);
          __builtin_prefetch(sp + 3 * a, 1), __builtin_prefetch(nm + 3 * a, 1), __builtin_prefetch(d + a, 1);
          __builtin_prefetch(sl + a, 1), __builtin_prefetch(in + a, 1);
        }
        const py::ssize_t i = order[j];
        const Vec3 x(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        const Contact c = query(m.model, *m.locator, x, cache);
        sl[i] = c.slab;
        if (c.in_shell()) {
          in[i] = c.penetrating();
          d[i] = c.depth;
          for (int k = 0; k < 3; ++k) sp[3 * i + k] = c.surface_point[k], nm[3 * i + k] = c.normal[k];
        } else {
          // One cell lookup for most points of a closed model; the displaced surface's side for an
          // open one (Model::open).
          in[i] = side ? x.allFinite() && side->inside(x) : m.locator->inside_inner_shell(x);
          d[i] = nan;
          for (int k = 0; k < 3; ++k) sp[3 * i + k] = nan, nm[3 * i + k] = nan;
        }
      }
    });
  }
  py::dict out;
  out["inside"] = inside;
  out["depth"] = depth;
  out["surface_point"] = surface;
  out["normal"] = normal;
  out["slab"] = slab;
  return out;
}

py::tuple surface_arrays(Model& m) {
  std::vector<Vec3> v;
  std::vector<Tri> f;
  {
    const std::shared_lock lock(m.mutex);
    displaced_surface(m.model, v, f);
  }
  py::array_t<double> V({py::ssize_t(v.size()), py::ssize_t(3)});
  py::array_t<int32_t> F({py::ssize_t(f.size()), py::ssize_t(3)});
  auto vv = V.mutable_unchecked<2>();
  auto ff = F.mutable_unchecked<2>();
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) vv(i, k) = v[i][k];
  for (size_t i = 0; i < f.size(); ++i)
    for (int k = 0; k < 3; ++k) ff(i, k) = f[i][k];
  return py::make_tuple(V, F);
}

}  // namespace

PYBIND11_MODULE(hdm, mod) {
  mod.doc() =
      "hdm: haptic displacement maps (Jagnow & Dorsey, Graphics Interface 2002). Bake a triangle mesh into "
      "slabs, query it, save and export it. Lengths are in the input's model units.";
  py::register_exception<InvalidInput>(mod, "InvalidInput", PyExc_ValueError);
  py::register_exception<IoError>(mod, "IoError", PyExc_OSError);

  py::class_<Model, std::shared_ptr<Model>>(mod, "Model",
                                            "A slab model: coarse slabs holding the fine surface as "
                                            "displacement maps.")
      .def_property_readonly(
          "slab_count", [](const Model& m) { return m.model.slab_count(); }, "number of slabs")
      .def_property_readonly(
          "grid_n", [](const Model& m) { return m.model.grid_n; }, "displacement intervals per slab edge")
      .def_property_readonly(
          "source", [](const Model& m) { return m.model.source; }, "name of the baked input")
      .def_property_readonly(
          "path", [](const Model& m) { return m.path; },
          "the .hdm file it was loaded from or last saved to ('' for none)")
      .def_property_readonly(
          "box",
          [](const Model& m) {
            auto b = rows_of_3(2);
            for (int k = 0; k < 3; ++k) b.mutable_at(0, k) = m.box.min[k], b.mutable_at(1, k) = m.box.max[k];
            return b;
          },
          "bounding box of the slabs, (2, 3) float64 [model units]: min row, max row")
      .def_property_readonly(
          "invalid_slabs", [](const Model& m) { return count_invalid_slabs(m.model); },
          "slabs whose Jacobian is not positive everywhere (0 for a valid model)")
      .def("query", &query_points, py::arg("points"),
           "Haptic query of many points at once (parallel, the GIL released).\n\n"
           "points: (N, 3) float64 array [model units].\n"
           "Returns a dict of arrays: inside (N,) bool (below the displaced surface in a slab; in no slab, enclosed by "
           "the inner shell for a closed model, behind the nearest face of the displaced surface for an open one, "
           "as hdm check judges it: that surface's Embree BVH is built on the first such query after an edit); depth "
           "(N,) float64 [model units], > 0 inside, the distance to the "
           "surface's tangent plane, NaN in no slab; surface_point (N, 3) float64, the surface point on the point's "
           "projection line, NaN in no slab; normal (N, 3) float64, unit outward normal there, NaN in no slab; slab "
           "(N,) int32, the slab holding the point or -1 (also for non-finite points).")
      .def("surface", &surface_arrays,
           "The displaced surface as arrays (vertices (V, 3) float64 [model units], faces (F, 3) int32): every "
           "slab's grid triangles.")
      .def(
          "save",
          [](Model& m, const std::string& path) {
            const std::shared_lock lock(m.mutex);
            save_model(m.model, path);
            m.path = path;
          },
          py::arg("path"), "Writes the model to an .hdm file (atomically: a failure keeps the previous file).")
      .def(
          "export",
          [](Model& m, const std::string& path) {
            const std::shared_lock lock(m.mutex);
            export_mesh(m.model, path);
          },
          py::arg("path"),
          "Writes the reconstructed surface with its colours: .obj (with .mtl and .png), .ply or .glb.");

  mod.def(
      "load", [](const std::string& path) { return std::make_shared<Model>(load_model(path), path); }, py::arg("path"),
      "Reads an .hdm file written by hdm bake or Model.save.");
  mod.def("bake", &bake_mesh, py::arg("mesh"), py::kw_only(), py::arg("slabs") = 0, py::arg("grid") = 16,
          py::arg("density") = 4.0, py::arg("texels") = 2, py::arg("max_error") = 0.2, py::arg("rms_error") = 0.02,
          py::arg("error_bound") = true, py::arg("repair") = true,
          "Bakes a triangle mesh into a slab model. The mesh is validated (at least one face, finite coordinates, "
          "vertex ids in range), scaled by a power of two to a bounding-box diagonal in [1, 2) (exact), repaired when "
          "needed, oriented outward, open patches that cross joined at their seams, the folds of open sheets removed "
          "and, where it still crosses itself, resolved to the surface of the solid it bounds; the model is scaled "
          "back to the input's units. This is the bake `hdm bake` runs: the same mesh and options give the same model "
          "byte for byte.\n\n"
          "mesh: a file path (OBJ, PLY, OFF, STL) or a (vertices, faces) pair of arrays: (N, 3) float64 [model units] "
          "and (M, 3) integer vertex indices, counter-clockwise seen from outside.\n"
          "slabs: target slab count (0: input triangles * density / grid^2); grid: intervals per slab edge; "
          "texels: colour texels per interval; max_error and rms_error: the fidelity bound, % of the bounding-box "
          "diagonal, both ways; error_bound=False bakes once at the given count; repair=False refuses a dirty mesh.\n"
          "Returns (Model, report dict: slabs, grid, samples, input_triangles, invalid_slabs, overlapping_pairs, "
          "ray_misses, bake_seconds, self_intersections, fidelity {rms_pct, max_pct, rms_back_pct, max_back_pct}, "
          "and with the bound: bound_met, rounds, stopped_because: why an unmet bound stopped, or '').\n"
          "Raises ValueError (hdm.InvalidInput) for a mesh it cannot bake and OSError (hdm.IoError) for a file it "
          "cannot read, with hdm's message.");
  bind_haptics(mod);
  bind_sphere_proxy(mod);
  bind_rigid_tool(mod);
  bind_edit(mod);
  bind_feel(mod);
}
