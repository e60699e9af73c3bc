// SPDX-License-Identifier: MIT
#include "model_check.h"

#include <hdm/core/error.h>
#include <hdm/slab/slab_model.h>

namespace hdm::render_detail {

void check_renderable(const SlabModel& m) {
  const size_t S = m.slabs.size();
  if (S == 0) throw InvalidInput("render: the model has no slabs");
  const auto samples = static_cast<size_t>(m.samples.count), texels = static_cast<size_t>(m.texels.count);
  const bool fresh = m.samples.n == m.grid_n && m.samples.slot_count() == S * m.samples.per_slab &&
                     m.samples.point_i.size() == static_cast<size_t>(m.samples.per_slab) &&
                     m.samples.homes.size() == static_cast<size_t>(m.samples.first_interior) && m.slab_samples.size() == m.samples.slot_count() &&
                     m.displacement.size() == samples && m.texels.n == m.grid_n * m.texel_density &&
                     m.texels.slot_count() == S * m.texels.per_slab && m.colour.size() == texels &&
                     m.roughness.size() == texels && m.layer_displacement.size() == samples;
  if (!fresh)
    throw InvalidInput("render: the model's derived data are missing or stale (call rebuild_derived(model) first)");
}

}  // namespace hdm::render_detail
