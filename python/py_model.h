// SPDX-License-Identifier: MIT
#pragma once
// What the binding files of the Python module share: the Model object (a slab model with its
// locator, its stroke editor and a lock), the array types, and the binders of each part.
#include <hdm/core/error.h>
#include <hdm/edit/stroke_editor.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/query/slab_locator.h>
#include <hdm/slab/slab_model.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

namespace hdm::python {

namespace py = pybind11;

/// A loaded or baked model and what queries and edits need. Queries hold the lock shared, edits
/// exclusively (both with the GIL released), so Python threads may query and edit one model.
struct Model {
  SlabModel model;
  std::unique_ptr<SlabLocator> locator;  ///< slab boxes never change while editing: built once
  Aabb box;                              ///< of the slab vertices [model units]
  std::string path;                      ///< .hdm file it was loaded from or last saved to ("" for none)
  std::shared_mutex mutex;
  std::unique_ptr<StrokeEditor> editor;  ///< built on the first edit (about 60 bytes per sample)
  uint64_t edits = 0;                    ///< changes of the surface so far (under the exclusive lock)

  /// An open model (its inner shell has a boundary) encloses nothing: a point in no slab is inside
  /// when it lies behind the nearest face of the displaced surface, the rule `hdm check` and the
  /// fidelity measurement judge an open input by. That surface's query is built on the first such
  /// query after an edit.
  bool open = false;
  std::mutex side_mutex;
  std::unique_ptr<ExactMeshQuery> side;  ///< of the displaced surface, as it was after side_edits edits
  uint64_t side_edits = 0;

  explicit Model(SlabModel m, std::string file = {});
  /// The displaced surface's query for the current edits (builds it when stale: O(#S n^2 log)).
  /// Precondition: the caller holds #mutex (shared or exclusive).
  const ExactMeshQuery& displaced_side();
};
using ModelPtr = std::shared_ptr<Model>;

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// @brief Checks that @p a is an (N, 3) array; @throws InvalidInput naming @p what otherwise.
inline void require_rows_of_3(const Points& a, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw InvalidInput(std::string(what) + ": expected an (N, 3) float64 array, got " + std::to_string(a.ndim()) +
                       " dimension(s)" + (a.ndim() == 2 ? " with " + std::to_string(a.shape(1)) + " columns" : ""));
}

/// @brief A 3-vector from a sequence of three numbers; @throws InvalidInput naming @p what otherwise.
Vec3 vec3_from(const py::handle& h, const char* what);

/// An (N, 3) float64 array.
inline py::array_t<double> rows_of_3(py::ssize_t n) { return py::array_t<double>({n, py::ssize_t(3)}); }

/// @brief @p v as an (N, 3) float64 array (a copy).
inline py::array_t<double> rows(const std::vector<Vec3>& v) {
  auto a = rows_of_3(py::ssize_t(v.size()));
  double* d = a.mutable_data();
  for (size_t i = 0; i < v.size(); ++i)
    for (int k = 0; k < 3; ++k) d[3 * i + k] = v[i][k];
  return a;
}

void bind_haptics(py::module_& m);
void bind_sphere_proxy(py::module_& m);
void bind_rigid_tool(py::module_& m);
void bind_edit(py::module_& m);
void bind_feel(py::module_& m);

}  // namespace hdm::python
