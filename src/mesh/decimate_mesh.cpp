// SPDX-License-Identifier: MIT
// Decimation by checked edge collapses: Garland–Heckbert quadrics with feature planes, a lazy
// priority queue, and the link condition, so the coarse mesh keeps the input's topology.
#include <hdm/core/error.h>
#include <hdm/mesh/decimate_mesh.h>

#include "max_min_direction.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <string>
#include <tuple>
#include <vector>

#include "decimate_parts.h"
#include "disjoint_sets.h"
#include "simplifier.h"

namespace hdm {
namespace {

using mesh::detail::Simplifier;

// One vertex per fan: a vertex whose faces form several edge-connected fans (a pinch) is split,
// since the link condition is defined on manifold vertices. Faces keep their orientation.
TriangleMesh split_pinched_vertices(const TriangleMesh& mesh, std::vector<int32_t>& origin) {
  const size_t nv = mesh.vertices.size(), nf = mesh.faces.size();
  std::vector<int32_t> offset(nv + 1, 0);
  for (const Tri& t : mesh.faces)
    for (int32_t v : t) ++offset[v + 1];
  for (size_t v = 0; v < nv; ++v) offset[v + 1] += offset[v];
  // Per vertex: (neighbour, face) for both edges of each incident face; faces that list the same
  // neighbour share the edge (v, neighbour) and belong to one fan.
  std::vector<std::pair<int32_t, int32_t>> spokes(2 * 3 * nf);
  std::vector<int32_t> fill(offset.begin(), offset.end() - 1);
  for (size_t f = 0; f < nf; ++f)
    for (int a = 0; a < 3; ++a) {
      const int32_t v = mesh.faces[f][a];
      spokes[2 * fill[v]] = {mesh.faces[f][(a + 1) % 3], static_cast<int32_t>(f)};
      spokes[2 * fill[v] + 1] = {mesh.faces[f][(a + 2) % 3], static_cast<int32_t>(f)};
      ++fill[v];
    }
  TriangleMesh out = mesh;
  std::vector<int32_t> faces;
  mesh::detail::DisjointSets<> sets;
  std::vector<std::pair<int32_t, int32_t>> root_copy;
  for (size_t v = 0; v < nv; ++v) {
    auto* b = spokes.data() + 2 * offset[v];
    auto* e = spokes.data() + 2 * offset[v + 1];
    if (e - b < 4) continue;  // one face
    std::sort(b, e);
    faces.clear();
    for (auto* s = b; s != e; ++s) faces.push_back(s->second);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    auto slot = [&](int32_t f) { return int32_t(std::lower_bound(faces.begin(), faces.end(), f) - faces.begin()); };
    sets.reset(faces.size());
    for (auto* s = b; s + 1 != e; ++s)
      if (s[0].first == s[1].first) sets.unite(slot(s[0].second), slot(s[1].second));
    // The fan of the first face keeps v; every other fan gets a copy.
    const int32_t keep = sets.find(0);
    root_copy.clear();
    for (size_t i = 0; i < faces.size(); ++i) {
      const int32_t r = sets.find(static_cast<int32_t>(i));
      if (r == keep) continue;
      auto it = std::find_if(root_copy.begin(), root_copy.end(), [&](const auto& rc) { return rc.first == r; });
      if (it == root_copy.end()) {
        root_copy.emplace_back(r, static_cast<int32_t>(out.vertices.size()));
        out.vertices.push_back(mesh.vertices[v]);
        origin.push_back(static_cast<int32_t>(v));
        it = root_copy.end() - 1;
      }
      for (int32_t& x : out.faces[faces[i]])
        if (x == static_cast<int32_t>(v)) x = it->second;
    }
  }
  return out;
}

}  // namespace

TriangleMesh mesh::detail::decimate_pinch_free(const TriangleMesh& input, const DecimateOptions& options, bool clean,
                                               DecimateReport* report, std::vector<int32_t>* kept,
                                               std::vector<uint8_t> frozen, std::vector<double>* max_edge) {
  std::vector<int32_t> origin;  // input vertex of each copy split_pinched_vertices() appended
  DecimateOptions o = options;
  const TriangleMesh split = split_pinched_vertices(input, origin);
  for (int32_t v : origin)
    if (!o.max_edge.empty()) o.max_edge.push_back(options.max_edge[v]);
  Simplifier s(split, o);
  if (!frozen.empty()) {
    for (int32_t v : origin) frozen.push_back(frozen[v]);
    s.freeze(std::move(frozen));
  }
  s.run(options.target_faces, options.max_cost);
  if (clean) s.clean_folds();
  std::vector<int32_t> ids;
  TriangleMesh out = s.result(kept || max_edge ? &ids : nullptr);
  if (max_edge) {
    max_edge->clear();
    if (!o.max_edge.empty())
      for (int32_t v : ids) max_edge->push_back(s.max_edge(v));
  }
  if (kept) {  // a split copy is the vertex it was split from
    for (int32_t& v : ids)
      if (v >= static_cast<int32_t>(input.vertices.size())) v = origin[v - input.vertices.size()];
    *kept = std::move(ids);
  }
  if (report) {
    report->faces = static_cast<int64_t>(out.faces.size());
    report->vertices = static_cast<int64_t>(out.vertices.size());
    report->feature_edges = s.feature_edges();
    report->collapses = s.collapses();
    report->last_cost = s.last_cost();
  }
  return out;
}

TriangleMesh decimate_mesh(const TriangleMesh& input, const DecimateOptions& options, DecimateReport* report) {
  validate_mesh_data(input, "decimate_mesh input");
  if (options.target_faces < 1)
    throw InvalidInput("decimate_mesh: target_faces " + std::to_string(options.target_faces) + " must be at least 1");
  const MeshTopology topo = analyze_topology(input);
  if (topo.non_manifold_edges || topo.inconsistent_edges)
    throw InvalidInput("decimate_mesh input: " + std::to_string(topo.non_manifold_edges) + " non-manifold and " +
                       std::to_string(topo.inconsistent_edges) +
                       " inconsistently oriented edges (repair the mesh first)");
  if (!options.max_edge.empty() && options.max_edge.size() != input.vertices.size())
    throw InvalidInput("decimate_mesh: max_edge has " + std::to_string(options.max_edge.size()) + " values for " +
                       std::to_string(input.vertices.size()) + " vertices");
  if (!mesh::detail::decimate_in_parts_first(input, options))
    return mesh::detail::decimate_pinch_free(input, options, true, report, nullptr);
  DecimateOptions next = options;  // each pass keeps to the edge caps the one before it leaves
  TriangleMesh coarser;
  const TriangleMesh* from = &input;  // the input, then each pass's result
  int64_t collapses = 0;
  double last_cost = 0;
  for (const mesh::detail::PartsPass& pass : mesh::detail::kPartsPasses) {
    DecimateReport parts;
    std::vector<double> caps;
    coarser = mesh::detail::decimate_in_parts(*from, next, pass, &parts, &caps);
    from = &coarser;
    next.max_edge = std::move(caps);
    collapses += parts.collapses;
    last_cost = std::max(last_cost, parts.last_cost);
  }
  TriangleMesh out = mesh::detail::decimate_pinch_free(coarser, next, true, report, nullptr);
  if (report) {
    report->collapses += collapses;
    report->last_cost = std::max(report->last_cost, last_cost);
  }
  return out;
}

}  // namespace hdm
