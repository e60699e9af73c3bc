// SPDX-License-Identifier: MIT
#include <hdm/slab/model_memory.h>

#include <vector>

namespace hdm {
namespace {

template <class T>
int64_t bytes(const std::vector<T>& v) noexcept {
  return static_cast<int64_t>(v.capacity() * sizeof(T));
}

template <class T>
int64_t bytes(const SampleField<T>& f) noexcept {
  return static_cast<int64_t>(f.heap_bytes());  // 0 while uniform
}

template <class... V>
int64_t sum_bytes(const V&... v) noexcept {
  return (bytes(v) + ...);
}

// The bytes a uniform field's array would take (0 for one already materialised).
template <class... T>
int64_t uniform_bytes(const SampleField<T>&... f) noexcept {
  return ((f.uniform() ? static_cast<int64_t>(f.size() * sizeof(T)) : 0) + ...);
}

int64_t layout_bytes(const SampleLayout& l) noexcept {
  return sum_bytes(l.local_rank, l.interior_index, l.boundary_ids, l.homes, l.point_i, l.point_j, l.edge_other_side,
                   l.side_points, l.corner_slot_offsets, l.corner_slots);
}

}  // namespace

ModelMemory model_memory(const SlabModel& m) noexcept {
  ModelMemory r;
  r.sample_fields = sum_bytes(m.displacement, m.friction_static, m.friction_dynamic, m.stiffness_scale,
                              m.layer_displacement, m.hardness);
  r.texel_fields = sum_bytes(m.colour, m.roughness);
  r.coarse = sum_bytes(m.inner, m.outer, m.slabs);
  r.sample_layout = layout_bytes(m.samples);
  r.texel_layout = layout_bytes(m.texels);
  r.caches = sum_bytes(m.slab_samples);
  r.slab_constants = sum_bytes(m.geometry, m.edge_neighbour);
  r.uniform_fields = uniform_bytes(m.friction_static, m.friction_dynamic, m.stiffness_scale, m.layer_displacement,
                                   m.hardness, m.colour, m.roughness);
  r.samples = m.samples.count;
  r.texels = m.texels.count;
  return r;
}

}  // namespace hdm
