// SPDX-License-Identifier: MIT
#include <hdm/query/slab_locator.h>

#include <algorithm>
#include <cmath>

namespace hdm {

SlabLocator::SlabLocator(const SlabModel& model) : geometry_(&model.geometry) {
  const int S = model.slab_count();
  order_.resize(S);
  std::vector<Vec3> centres(S);
  for (int s = 0; s < S; ++s) {
    order_[s] = s;
    centres[s] = 0.5 * (model.geometry[s].box.min + model.geometry[s].box.max);
  }
  nodes_.reserve(2 * S / 2 + 2);
  build(0, S, centres);

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

int SlabLocator::find_bvh(const Vec3& p, AlphaSolver solver, SlabCoordinates& c) const noexcept {
  const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (!(x >= n.lo[0] && x <= n.hi[0] && y >= n.lo[1] && y <= n.hi[1] && z >= n.lo[2] && z <= n.hi[2]))
      continue;
    if (n.count > 0) {
      for (int32_t k = n.first; k < n.first + n.count; ++k)
        if (locate_in_slab((*geometry_)[order_[k]], p, solver, c)) return order_[k];
    } else if (top < 126) {
      stack[top++] = n.first;
      stack[top++] = static_cast<int32_t>(&n - nodes_.data()) + 1;
    }
  }
  return -1;
}

int SlabLocator::find(const Vec3& p, int hint, AlphaSolver solver, SlabCoordinates& c) const noexcept {
  if (!p.allFinite() || nodes_.empty()) return -1;
  const auto& g = *geometry_;
  if (hint >= 0 && hint < static_cast<int>(g.size())) {
    if (locate_in_slab(g[hint], p, solver, c)) return hint;
    int count;
    const int32_t* ring = neighbourhood(hint, count);
    for (int k = 0; k < count; ++k)
      if (locate_in_slab(g[ring[k]], p, solver, c)) return ring[k];
  }
  return find_bvh(p, solver, c);
}

}  // namespace hdm
