// SPDX-License-Identifier: MIT
#include "snapshot_uploader.h"

#include <algorithm>
#include <cstring>

namespace hdm::studio {
namespace {

// The arrays of a slab view, as (pointer, byte count) pairs: what a slab is made of.
template <class Fn>
void for_each_array(const SlabView& v, Fn&& fn) {
  const size_t P = static_cast<size_t>(v.per_slab), T = static_cast<size_t>(v.texels_per_slab);
  fn(static_cast<const void*>(v.points), P * sizeof(SlabSample));
  fn(v.friction_static, P * sizeof(Half16));
  fn(v.friction_dynamic, P * sizeof(Half16));
  fn(v.stiffness_scale, P * sizeof(Unorm16));
  fn(v.layer_displacement, P * sizeof(Unorm16));
  fn(v.hardness, P * sizeof(Half16));
  fn(v.texels, 4 * T);
}

}  // namespace

SnapshotUploader::SnapshotUploader(const SlabSnapshots& snapshots, SlabRenderer& renderer, bool verify)
    : snapshots_(snapshots), renderer_(renderer), verify_(verify) {
  const SlabModel& model = snapshots.model();
  const int S = model.slab_count();
  renderer_.upload_all(model);  // buffers and atlas layout; the slabs' data come from the snapshot
  drawn_epoch_.assign(static_cast<size_t>(S), 0);
  SnapshotReader reader(snapshots_);
  if (verify_) {
    stride_ = (sizeof(SlabSample) + 5 * sizeof(Unorm16)) * static_cast<size_t>(model.samples.per_slab) +
              4 * static_cast<size_t>(model.texels.per_slab);
    mirror_.assign(stride_ * static_cast<size_t>(S), 0);
  }
  for (int s = 0; s < S; ++s) {
    const SlabView v = reader.slab(s);
    renderer_.upload_slab(model, v, s);
    drawn_epoch_[static_cast<size_t>(s)] = v.epoch;
    if (verify_) remember(v, s);
  }
}

bool SnapshotUploader::differs(const SlabView& view, int slab) const {
  const uint8_t* m = &mirror_[static_cast<size_t>(slab) * stride_];
  bool diff = false;
  for_each_array(view, [&](const void* a, size_t bytes) {
    diff = diff || std::memcmp(a, m, bytes) != 0;
    m += bytes;
  });
  return diff;
}

void SnapshotUploader::remember(const SlabView& view, int slab) {
  uint8_t* m = &mirror_[static_cast<size_t>(slab) * stride_];
  for_each_array(view, [&](const void* a, size_t bytes) {
    std::memcpy(m, a, bytes);
    m += bytes;
  });
}

UploadFrame SnapshotUploader::update() {
  UploadFrame f;
  SnapshotReader reader(snapshots_);  // held for this update only
  f.epoch = reader.epoch();
  if (verify_) f.dirty = 0;
  const SlabModel& model = snapshots_.model();
  for (int s = 0; s < static_cast<int>(drawn_epoch_.size()); ++s) {
    // The epoch alone decides (a slab's copy is made only to upload it, or to verify it).
    const bool newer = reader.slab_epoch(s) > drawn_epoch_[static_cast<size_t>(s)];
    if (!newer && !verify_) continue;
    const SlabView v = reader.slab(s);
    if (verify_) {
      const bool changed = differs(v, s);
      f.dirty += changed;
      f.mismatched += changed != newer;
      if (changed) remember(v, s);
    }
    if (!newer) continue;
    renderer_.upload_slab(model, v, s);
    drawn_epoch_[static_cast<size_t>(s)] = v.epoch;
    ++f.uploaded;
  }
  total_ += f.uploaded;
  return f;
}

}  // namespace hdm::studio
