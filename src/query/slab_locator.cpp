// SPDX-License-Identifier: MIT
#include <hdm/query/slab_locator.h>

#include <algorithm>
#include <cmath>

namespace hdm {

SlabLocator::SlabLocator(const SlabModel& model) : geometry_(&model.geometry) {
  const int S = model.slab_count();
  order_.resize(S);
  std::vector<Box> boxes(S);
  std::vector<Sides> sides(S);
  std::vector<Vec3> centres(S);
  for (int s = 0; s < S; ++s) {
    order_[s] = s;
    const Aabb& b = model.geometry[s].box;
    centres[s] = 0.5 * (b.min + b.max);
    for (int a = 0; a < 3; ++a) {  // round outward so the float box contains the double box
      boxes[s].lo[a] = std::nextafter(static_cast<float>(b.min[a]), -INFINITY);
      boxes[s].hi[a] = std::nextafter(static_cast<float>(b.max[a]), INFINITY);
    }
  }
  for (int s = 0; s < S; ++s) {
    const Tri& t = model.slabs[s];
    Vec3 corner[6];
    double M = 0;
    for (int k = 0; k < 3; ++k) {
      corner[k] = model.inner[t[k]], corner[k + 3] = model.outer[t[k]];
      M = std::max({M, corner[k].cwiseAbs().maxCoeff(), corner[k + 3].cwiseAbs().maxCoeff()});
    }
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& c : corner) centroid += c / 6;
    M += (model.geometry[s].box.max - model.geometry[s].box.min).norm();
    for (int e = 0; e < 3; ++e) {  // edge RS, ST, TR: the plane through the edge and the mean ray
      const int v = e, w = (e + 1) % 3;
      const Vec3 along = 0.5 * (corner[w] - corner[v] + corner[w + 3] - corner[v + 3]);
      const Vec3 up = 0.5 * (corner[v + 3] - corner[v] + corner[w + 3] - corner[w]);
      Vec3 n = along.cross(up);
      const double len = n.norm();
      Sides& sd = sides[s];
      if (!(len > 0)) {  // degenerate: a plane that rejects nothing
        sd.n[e][0] = sd.n[e][1] = sd.n[e][2] = 0, sd.d[e] = INFINITY;
        continue;
      }
      n /= len;
      if (n.dot(centroid - 0.5 * (corner[v] + corner[w])) > 0) n = -n;  // outward
      const Vec3f nf = n.cast<float>();
      double d = -INFINITY;
      for (const Vec3& c : corner) d = std::max(d, nf.cast<double>().dot(c));
      // Margin: float rounding of n·x (|x| <= M) and the inside test's 1e-9 barycentric tolerance.
      for (int a = 0; a < 3; ++a) sd.n[e][a] = nf[a];
      sd.d[e] = std::nextafter(static_cast<float>(d + 1e-5 * M), INFINITY);
    }
  }
  nodes_.reserve(2 * S / 2 + 2);
  build(0, S, centres);
  filters_.resize(S);
  for (int s = 0; s < S; ++s) filters_[s] = {boxes[s], sides[s]};
  leaf_.resize(S);
  for (int k = 0; k < S; ++k) leaf_[k] = {filters_[order_[k]], order_[k]};
  std::vector<int32_t>().swap(order_);  // only the build needs it; leaf_ holds the slab ids
  edge_ = model.edge_neighbour;

  // Neighbourhood: edge neighbours first (most likely next slab), then the rest of the corner rings.
  ring_offsets_.assign(S + 1, 0);
  std::vector<int32_t> tmp;
  for (int s = 0; s < S; ++s) {
    tmp.clear();
    for (int32_t nb : model.edge_neighbour[s])
      if (nb >= 0) tmp.push_back(nb);
    for (int32_t v : model.slabs[s])
      for (int32_t k = model.vertex_slab_offsets[v]; k < model.vertex_slab_offsets[v + 1]; ++k) {
        const int32_t t = model.vertex_slabs[k];
        if (t != s && std::find(tmp.begin(), tmp.end(), t) == tmp.end()) tmp.push_back(t);
      }
    ring_.insert(ring_.end(), tmp.begin(), tmp.end());
    ring_offsets_[s + 1] = static_cast<int32_t>(ring_.size());
  }
}

size_t SlabLocator::memory_bytes() const noexcept {
  return nodes_.capacity() * sizeof(Node) + order_.capacity() * sizeof(int32_t) +
         filters_.capacity() * sizeof(Filter) + leaf_.capacity() * sizeof(LeafEntry) +
         edge_.capacity() * sizeof(edge_[0]) +
         ring_offsets_.capacity() * sizeof(int32_t) + ring_.capacity() * sizeof(int32_t);
}

int SlabLocator::build(int32_t begin, int32_t end, std::vector<Vec3>& centres) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Aabb box, cbox;
  for (int32_t k = begin; k < end; ++k) {
    const Aabb& b = (*geometry_)[order_[k]].box;
    box.extend(b.min);
    box.extend(b.max);
    cbox.extend(centres[order_[k]]);
  }
  Node& node = nodes_[index];
  for (int a = 0; a < 3; ++a) {  // round outward so float boxes still contain the double boxes
    node.lo[a] = std::nextafter(static_cast<float>(box.min[a]), -INFINITY);
    node.hi[a] = std::nextafter(static_cast<float>(box.max[a]), INFINITY);
  }
  if (end - begin <= 4) {
    node.first = begin;
    node.count = end - begin;
    return index;
  }
  int axis;
  (cbox.max - cbox.min).maxCoeff(&axis);
  const int32_t mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int32_t a, int32_t b) { return centres[a][axis] < centres[b][axis]; });
  build(begin, mid, centres);
  const int right = build(mid, end, centres);
  nodes_[index].first = right;
  nodes_[index].count = 0;
  return index;
}

int SlabLocator::find_bvh(const Vec3& p, AlphaSolver solver, double guess, SlabCoordinates& c) const noexcept {
  const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
  const auto& g = *geometry_;
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  int edge;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!(x >= n.lo[0] && x <= n.hi[0] && y >= n.lo[1] && y <= n.hi[1] && z >= n.lo[2] && z <= n.hi[2]))
      continue;
    if (n.count > 0) {
      for (int32_t k = n.first; k < n.first + n.count; ++k)
        if (leaf_[k].filter.may_contain(x, y, z) && locate_in_slab(g[leaf_[k].slab], p, solver, guess, c, edge))
          return leaf_[k].slab;
    } else if (top < 126) {
      stack[top++] = n.first;
      stack[top++] = static_cast<int32_t>(&n - nodes_.data()) + 1;
    }
  }
  return -1;
}

int SlabLocator::find(const Vec3& p, int hint, AlphaSolver solver, double guess, SlabCoordinates& c) const noexcept {
  if (!p.allFinite() || nodes_.empty()) return -1;
  const auto& g = *geometry_;
  if (hint >= 0 && hint < static_cast<int>(g.size())) {
    const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
    int edge = -1;
    if (locate_in_slab(g[hint], p, solver, guess, c, edge)) return hint;
    // The point left through `edge`: the slab across it is the likely one (design notes §3.6).
    const int32_t across = edge >= 0 ? edge_[hint][edge] : -1;
    if (across >= 0 && candidate(across, x, y, z) && locate_in_slab(g[across], p, solver, guess, c, edge))
      return across;
    int count;
    const int32_t* ring = neighbourhood(hint, count);
    for (int k = 0; k < count; ++k) {
      const int32_t s = ring[k];
      if (s != across && candidate(s, x, y, z) && locate_in_slab(g[s], p, solver, guess, c, edge)) return s;
    }
  }
  return find_bvh(p, solver, guess, c);
}

}  // namespace hdm
