// SPDX-License-Identifier: MIT
#include <hdm/analysis/fidelity.h>
#include <hdm/core/error.h>
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/mesh/scale_mesh.h>
#include <hdm/pipeline/prepare_input.h>

#include <utility>

namespace hdm {
namespace {

// Whether @p mesh is what the bake takes (validate_for_bake()): each step of the preparation must
// hand on such a mesh, and one that does not is undone.
bool bakeable(const TriangleMesh& mesh) {
  try {
    validate_for_bake(mesh, "");
  } catch (const InvalidInput&) {
    return false;
  }
  return true;
}

// Steps 4 and 5 of prepare_input(): an open mesh that crosses itself is joined at its seams, and
// a nearly closed one that still crosses is closed; @p open is set to what is left.
void close_self_intersecting_parts(PreparedInput& in, bool& open) {
  PrepareReport& r = in.report;
  TriangleMesh joined = stitch_seams(in.mesh, &r.seams);
  if (r.seams.inserted + r.seams.snapped > 0) {
    orient_outward(joined);  // r.orient keeps the report of the input's own parts
    in.mesh = std::move(joined);
    open = r.seams.boundary_edges_after != 0;
  }
  // A nearly closed input that crosses itself is the solid it nearly bounds: its holes are filled
  // for the bake and the check alike, so the check measures the caps the model has, and the
  // interior faces are those inside that solid.
  if (open) {
    TriangleMesh filled = fill_nearly_closed(in.mesh);
    if (!filled.faces.empty()) {  // only returned closed
      r.filled_faces = static_cast<int64_t>(filled.faces.size() - in.mesh.faces.size());
      in.mesh = std::move(filled);
      open = false;
    }
  }
}

}  // namespace

PreparedInput prepare_input(TriangleMesh mesh, const std::string& name, const PrepareOptions& options) {
  PreparedInput in;
  PrepareReport& r = in.report;
  in.mesh = std::move(mesh);
  validate_mesh_data(in.mesh, name);
  r.scale_exponent = scale_exponent(bounds(in.mesh).diagonal(), name);
  scale_mesh(in.mesh, r.scale_exponent);
  bool repaired = false;
  if (!options.repair) {
    validate_for_bake(in.mesh, name);
  } else if (needs_repair(in.mesh)) {
    RepairOptions ro;
    ro.max_hole_edges = options.max_hole_edges;
    ro.max_hole_size = options.max_hole_size;
    in.mesh = repair_mesh(in.mesh, name, ro, &r.repair);
    repaired = true;
  }
  r.orient = orient_outward(in.mesh);
  r.self_intersections = count_self_intersections(in.mesh);
  bool open = r.orient.nearly_closed + r.orient.sheets > 0;  // some part has a boundary edge
  // A mesh that needed no repair, or passed validate_for_bake(), is bakeable: orient_outward()
  // flips whole edge-connected parts, which keeps every edge as it was (one topology pass less).
  const bool valid = !repaired || bakeable(in.mesh);

  TriangleMesh before;
  if (r.self_intersections > 0 && open) {
    if (valid) before = in.mesh;
    close_self_intersecting_parts(in, open);
    if (valid && !bakeable(in.mesh)) {  // the seams left edges the bake cannot take: undone
      in.mesh = before;
      open = true;
      r.seams = {};
      r.filled_faces = 0;
    }
  }
  if (open) {
    if (valid) before = in.mesh;
    const FoldReport folds = remove_folds(in.mesh);
    if (valid && !bakeable(in.mesh))
      in.mesh = std::move(before);
    else
      r.folds = folds;
  }
  if (!options.resolve || r.self_intersections == 0) return in;
  {
    const ExactMeshQuery unresolved(in.mesh);  // a copy: the faces as `hdm check` measures them
    const std::vector<uint8_t> interior = interior_faces(unresolved);
    in.surface_points = surface_points(unresolved, &interior);
  }
  {
    SelfIntersectionReport resolved;
    TriangleMesh out = resolve_self_intersections(in.mesh, &resolved);
    if (bakeable(out) || !bakeable(in.mesh)) {
      in.mesh = std::move(out);
      r.resolved = resolved;
    } else {  // a resolution the bake cannot take: the crossings stay as the input has them
      r.resolved.pairs_before = r.resolved.pairs_after = r.self_intersections;
      r.resolved.faces_before = r.resolved.faces_after = static_cast<int64_t>(in.mesh.faces.size());
    }
    r.resolved.filled_faces = r.filled_faces;
  }
  if (r.seams.inserted + r.seams.snapped > 0) r.resolved.seam_vertices = r.seams.inserted + r.seams.snapped;
  return in;
}

}  // namespace hdm
