// SPDX-License-Identifier: MIT
// One pass of a large input's decimation: spatial parts decimated at once, where they meet left as
// they are.
#include "decimate_parts.h"
#include "../core/morton.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace hdm::mesh::detail {
namespace {

// The faces of @p mesh in Morton order of their centroids in the bounding box.
std::vector<int32_t> morton_order(const TriangleMesh& mesh) {
  const Aabb box = bounds(mesh);
  std::vector<std::pair<uint64_t, int32_t>> keyed(mesh.faces.size());
  tbb::parallel_for(size_t(0), mesh.faces.size(), [&](size_t f) {
    const Tri& t = mesh.faces[f];
    const Vec3 c = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3;
    keyed[f] = {core::detail::morton_code(c, box), int32_t(f)};
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());
  std::vector<int32_t> order(keyed.size());
  for (size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

// One part: its faces with the part's own vertex ids, the mesh vertex of each, which of them other
// parts use too, and how many faces lie within one edge of those (what no collapse can remove).
struct Part {
  TriangleMesh mesh;
  std::vector<int32_t> global;
  std::vector<uint8_t> shared;
  int64_t band = 0;
};

int64_t band_faces(const Part& p) {
  std::vector<uint8_t> near = p.shared;
  for (const Tri& t : p.mesh.faces)
    if (p.shared[t[0]] || p.shared[t[1]] || p.shared[t[2]]) near[t[0]] = near[t[1]] = near[t[2]] = 1;
  int64_t band = 0;
  for (const Tri& t : p.mesh.faces) band += near[t[0]] || near[t[1]] || near[t[2]];
  return band;
}

// @p local: #V entries of -1, the scratch that maps mesh vertices to the part's (left as given).
Part make_part(const TriangleMesh& mesh, const int32_t* faces, size_t count, const std::vector<uint8_t>& shared,
               std::vector<int32_t>& local) {
  Part p;
  for (size_t i = 0; i < count; ++i)
    for (int32_t v : mesh.faces[faces[i]])
      if (local[v] < 0) local[v] = 0, p.global.push_back(v);
  std::sort(p.global.begin(), p.global.end());  // the part's vertices in the mesh's order
  for (size_t v = 0; v < p.global.size(); ++v) local[p.global[v]] = int32_t(v);
  p.mesh.faces.reserve(count);
  for (size_t i = 0; i < count; ++i) {
    const Tri& t = mesh.faces[faces[i]];
    p.mesh.faces.push_back({local[t[0]], local[t[1]], local[t[2]]});
  }
  for (int32_t v : p.global) local[v] = -1;
  p.mesh.vertices.reserve(p.global.size());
  p.shared.reserve(p.global.size());
  for (int32_t v : p.global) {
    p.mesh.vertices.push_back(mesh.vertices[v]);
    p.shared.push_back(shared[v]);
  }
  p.band = band_faces(p);
  return p;
}

}  // namespace

bool decimate_in_parts_first(const TriangleMesh& mesh, const DecimateOptions& options) {
  const auto faces = static_cast<int64_t>(mesh.faces.size());
  return faces >= kLargeFaces && faces >= 64 * options.target_faces;
}

TriangleMesh decimate_in_parts(const TriangleMesh& mesh, const DecimateOptions& options, const PartsPass& pass,
                               DecimateReport* report, std::vector<double>* max_edge) {
  const std::vector<int32_t> order = morton_order(mesh);
  const size_t nf = order.size(), parts = (nf + pass.part_faces - 1) / pass.part_faces;
  const auto begin = [&](size_t p) { return p * nf / parts; };
  // A vertex is shared when faces of two parts use it.
  std::vector<int32_t> owner(mesh.vertices.size(), -1);
  std::vector<uint8_t> shared(mesh.vertices.size(), 0);
  for (size_t p = 0; p < parts; ++p)
    for (size_t i = begin(p); i < begin(p + 1); ++i)
      for (int32_t v : mesh.faces[order[i]]) {
        if (owner[v] < 0) owner[v] = int32_t(p);
        shared[v] |= owner[v] != int32_t(p);
      }
  std::vector<TriangleMesh> results(parts);
  std::vector<std::vector<int32_t>> kept(parts);
  std::vector<std::vector<double>> caps(parts);  // per kept vertex, with options.max_edge
  std::vector<DecimateReport> reports(parts);
  const double keep = std::min(1.0, pass.keep * double(options.target_faces) / double(nf));
  tbb::enumerable_thread_specific<std::vector<int32_t>> scratch(std::vector<int32_t>(mesh.vertices.size(), -1));
  tbb::parallel_for(size_t(0), parts, [&](size_t p) {
    Part part = make_part(mesh, order.data() + begin(p), begin(p + 1) - begin(p), shared, scratch.local());
    DecimateOptions o = options;
    if (!options.max_edge.empty()) {
      o.max_edge.resize(part.global.size());
      for (size_t v = 0; v < part.global.size(); ++v) o.max_edge[v] = options.max_edge[part.global[v]];
    }
    // Its share of the faces to keep, beside the faces where it meets other parts (a target that
    // counted those would decimate the rest of the part too far).
    const auto faces = static_cast<int64_t>(part.mesh.faces.size());
    o.target_faces = std::max<int64_t>(1, part.band + int64_t(keep * double(faces - part.band)));
    results[p] = decimate_pinch_free(part.mesh, o, false, &reports[p], &kept[p], std::move(part.shared), &caps[p]);
    for (int32_t& v : kept[p]) v = part.global[v];  // to the mesh's vertex ids
  });
  // The parts joined: each vertex of the mesh a part kept, once (a shared one is kept by all its
  // parts, unmoved), in the mesh's order.
  std::vector<int32_t> id(mesh.vertices.size(), -1);
  for (size_t p = 0; p < parts; ++p)
    for (int32_t v : kept[p]) id[v] = 0;
  TriangleMesh out;
  for (size_t v = 0; v < id.size(); ++v)
    if (id[v] == 0) id[v] = int32_t(out.vertices.size()), out.vertices.push_back(mesh.vertices[v]);
  if (max_edge) max_edge->assign(options.max_edge.empty() ? 0 : out.vertices.size(), INFINITY);
  for (size_t p = 0; p < parts; ++p) {
    for (size_t v = 0; v < kept[p].size(); ++v) {
      out.vertices[id[kept[p][v]]] = results[p].vertices[v];
      // A shared vertex is kept by each of its parts, unmerged: every part gives its own value.
      if (max_edge && !caps[p].empty()) (*max_edge)[id[kept[p][v]]] = caps[p][v];
    }
    for (const Tri& t : results[p].faces)
      out.faces.push_back({id[kept[p][t[0]]], id[kept[p][t[1]]], id[kept[p][t[2]]]});
  }
  if (report) {
    *report = DecimateReport{};
    for (const DecimateReport& r : reports) {
      report->collapses += r.collapses;
      report->last_cost = std::max(report->last_cost, r.last_cost);
    }
    report->faces = static_cast<int64_t>(out.faces.size());
    report->vertices = static_cast<int64_t>(out.vertices.size());
  }
  return out;
}

}  // namespace hdm::mesh::detail
