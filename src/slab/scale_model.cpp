// SPDX-License-Identifier: MIT
#include <hdm/slab/scale_model.h>

#include <cmath>

namespace hdm {

void scale_model(SlabModel& model, int exponent) {
  if (exponent == 0) return;
  for (std::vector<Vec3>* corners : {&model.inner, &model.outer})
    for (Vec3& v : *corners)
      for (int i = 0; i < 3; ++i) v[i] = std::ldexp(v[i], exponent);
  model.source_diagonal = std::ldexp(model.source_diagonal, exponent);
  if (!model.geometry.empty()) rebuild_derived(model);
}

}  // namespace hdm
