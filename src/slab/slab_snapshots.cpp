// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/slab/slab_snapshots.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <thread>

namespace hdm {
namespace {

constexpr uint64_t kFree = UINT64_MAX;  // reader slot unused
constexpr uint64_t kClaiming = 0;       // reader slot being claimed: pins every epoch for a moment

}  // namespace

SlabSnapshots::SlabSnapshots(const SlabModel& m, const SnapshotOptions& o) : model_(m), options_(o) {
  const int S = m.slab_count();
  if (S == 0 || m.slab_samples.size() != m.samples.slot_count() || m.texels.slot_count() != size_t(S) * m.texels.per_slab ||
      m.colour.size() != size_t(m.texels.count) || m.roughness.size() != size_t(m.texels.count) ||
      m.layer_displacement.size() != size_t(m.samples.count) || m.hardness.size() != size_t(m.samples.count))
    throw InvalidInput("snapshots: the model's derived data are missing (call rebuild_derived first)");
  if (o.reader_slots < 1 || o.reader_slots > 1024)
    throw InvalidInput("snapshots: reader_slots = " + std::to_string(o.reader_slots) + " outside [1, 1024]");
  per_slab_ = m.samples.per_slab;
  texels_per_slab_ = m.texels.per_slab;
  // A SlabSample and five 16-bit fields per displacement sample, one 4-byte word (the stored
  // codes) per texel; whole cache lines (16 floats).
  const size_t bytes = (sizeof(SlabSample) + 5 * sizeof(Unorm16)) * size_t(per_slab_) + 4 * size_t(texels_per_slab_);
  stride_ = (bytes + 63) / 64 * 64;
  const size_t spare = o.spare_versions < 0 ? size_t(S) : size_t(o.spare_versions);
  version_total_ = size_t(S) + spare;
  slot_count_ = size_t(o.reader_slots);
  arena_.assign(version_total_ * stride_, 0);
  versions_ = std::make_unique<Version[]>(version_total_);
  current_ = std::make_unique<std::atomic<int32_t>[]>(size_t(S));
  slots_ = std::make_unique<std::atomic<uint64_t>[]>(slot_count_);
  for (size_t k = 0; k < slot_count_; ++k) slots_[k].store(kFree);
  free_.reserve(version_total_);
  retired_.reserve(version_total_);
  pending_.reserve(size_t(S));
  for (int s = 0; s < S; ++s) {
    fill(s, s);
    versions_[s].slab = s;
    versions_[s].epoch = 0;
    if (options_.checksums) versions_[s].checksum = checksum(s);
    current_[s].store(s, std::memory_order_relaxed);
  }
  for (size_t v = version_total_; v-- > size_t(S);) free_.push_back(static_cast<int32_t>(v));
  published_.store(0, std::memory_order_seq_cst);
}

SlabSnapshots::~SlabSnapshots() = default;

void SlabSnapshots::fill(int32_t v, int slab) noexcept {
  const SlabModel& m = model_;
  unsigned char* d = data(v);
  const size_t P = size_t(per_slab_), T = size_t(texels_per_slab_);
  std::memcpy(d, m.slab_samples.data() + size_t(slab) * P, P * sizeof(SlabSample));
  auto* fs = reinterpret_cast<Half16*>(d + P * sizeof(SlabSample));
  Half16* fd = fs + P;
  auto* st = reinterpret_cast<Unorm16*>(fd + P);
  Unorm16* ly = st + P;
  auto* hv = reinterpret_cast<Half16*>(ly + P);
  const SlabIds ids = m.samples.slab_ids(slab);
  for (size_t k = 0; k < P; ++k) {
    const int32_t id = ids[k];
    fs[k] = m.friction_static[id];
    fd[k] = m.friction_dynamic[id];
    st[k] = m.stiffness_scale[id];
    ly[k] = m.layer_displacement[id];
    hv[k] = m.hardness[id];
  }
  uint8_t* tx = reinterpret_cast<uint8_t*>(hv + P);
  const SlabIds tids = m.texels.slab_ids(slab);
  for (size_t k = 0; k < T; ++k) {
    const int32_t id = tids[k];
    const Srgb8 c = m.colour[id];
    tx[4 * k] = c.r, tx[4 * k + 1] = c.g, tx[4 * k + 2] = c.b, tx[4 * k + 3] = m.roughness[id];
  }
}

uint64_t SlabSnapshots::checksum(int32_t v) const noexcept {
  const unsigned char* d = data(v);
  uint64_t h = 14695981039346656037ull;
  for (size_t k = 0; k < stride_; k += 4) {
    uint32_t w;
    std::memcpy(&w, d + k, 4);
    h = (h ^ w) * 1099511628211ull;
  }
  return h;
}

SlabView SlabSnapshots::view(int32_t v) const noexcept {
  const unsigned char* d = data(v);
  const size_t P = size_t(per_slab_);
  SlabView s;
  s.epoch = versions_[v].epoch;
  s.per_slab = per_slab_;
  s.texels_per_slab = texels_per_slab_;
  s.points = reinterpret_cast<const SlabSample*>(d);
  s.friction_static = reinterpret_cast<const Half16*>(d + P * sizeof(SlabSample));
  s.friction_dynamic = s.friction_static + P;
  s.stiffness_scale = reinterpret_cast<const Unorm16*>(s.friction_dynamic + P);
  s.layer_displacement = s.stiffness_scale + P;
  s.hardness = reinterpret_cast<const Half16*>(s.layer_displacement + P);
  s.texels = reinterpret_cast<const uint8_t*>(s.hardness + P);
  return s;
}

int32_t SlabSnapshots::version_at(int slab, uint64_t e) const noexcept {
  int32_t v = current_[slab].load(std::memory_order_acquire);
  // The reader's pinned epoch keeps every version it may need from being recycled, and the chain
  // from the newest version back to it intact (reclaim() cuts it only below every reader's epoch).
  while (versions_[v].epoch > e) v = versions_[v].prev.load(std::memory_order_acquire);
  return v;
}

bool SlabSnapshots::publish_reserve(int n) noexcept {
  // Epoch-based reclamation: a retired version is needed by readers pinned at an epoch in
  // [its epoch, superseded); recycle it once every reader is pinned at or after `superseded`.
  uint64_t oldest = kFree;
  for (size_t k = 0; k < slot_count_; ++k) oldest = std::min(oldest, slots_[k].load(std::memory_order_seq_cst));
  size_t keep = 0;
  for (int32_t r : retired_) {
    Version& v = versions_[r];
    if (v.superseded <= oldest) {
      if (v.next >= 0) versions_[v.next].prev.store(-1, std::memory_order_release);
      v.next = -1;
      v.superseded = kFree;
      v.prev.store(-1, std::memory_order_relaxed);
      free_.push_back(r);
    } else {
      retired_[keep++] = r;
    }
  }
  retired_.resize(keep);
  return free_.size() >= size_t(std::max(n, 0));
}

void SlabSnapshots::publish_slab(int slab) noexcept {
  if (free_.empty() || slab < 0 || slab >= model_.slab_count()) return;
  const int32_t v = free_.back();
  free_.pop_back();
  fill(v, slab);
  versions_[v].slab = slab;
  if (options_.checksums) versions_[v].checksum = checksum(v);
  pending_.push_back(v);
}

uint64_t SlabSnapshots::publish_commit() noexcept {
  const uint64_t now = published_.load(std::memory_order_relaxed);
  if (pending_.empty()) return now;
  const uint64_t next = now + 1;
  for (int32_t v : pending_) {
    Version& nv = versions_[v];
    const int32_t old = current_[nv.slab].load(std::memory_order_relaxed);
    nv.epoch = next;
    nv.prev.store(old, std::memory_order_relaxed);
    versions_[old].superseded = next;
    versions_[old].next = v;
    retired_.push_back(old);
    current_[nv.slab].store(v, std::memory_order_release);  // readers pinned before `next` walk to old
  }
  pending_.clear();
  published_.store(next, std::memory_order_seq_cst);
  return next;
}

int SlabSnapshots::pending() const noexcept { return static_cast<int>(pending_.size()); }

SnapshotReader::SnapshotReader(const SlabSnapshots& s) : s_(s) {
  for (;;) {
    for (size_t k = 0; k < s.slot_count_; ++k) {
      uint64_t expected = kFree;
      if (s.slots_[k].compare_exchange_strong(expected, kClaiming, std::memory_order_seq_cst)) {
        slot_ = k;
        // Claimed (pinning everything); now pin the newest epoch. The writer either saw this slot
        // claimed, or recycled only versions superseded by an epoch this load returns or precedes.
        epoch_ = s.published_.load(std::memory_order_seq_cst);
        s.slots_[k].store(epoch_, std::memory_order_seq_cst);
        return;
      }
    }
    std::this_thread::yield();  // every slot taken: wait for another reader, never for the writer
  }
}

SnapshotReader::~SnapshotReader() { s_.slots_[slot_].store(kFree, std::memory_order_seq_cst); }

SlabView SnapshotReader::slab(int slab) const noexcept { return s_.view(s_.version_at(slab, epoch_)); }

bool SnapshotReader::verify(int slab) const noexcept {
  if (!s_.options_.checksums) return true;
  const int32_t v = s_.version_at(slab, epoch_);
  return s_.checksum(v) == s_.versions_[v].checksum;
}

SlabModel SnapshotReader::stored_model() const {
  const SlabModel& live = s_.model_;
  SlabModel m;
  m.grid_n = live.grid_n;
  m.texel_density = live.texel_density;
  m.inner = live.inner;
  m.outer = live.outer;
  m.slabs = live.slabs;
  m.source = live.source;
  m.source_triangles = live.source_triangles;
  m.source_diagonal = live.source_diagonal;
  m.under_layer = live.under_layer;
  const int S = live.slab_count();
  std::vector<SlabView> views(static_cast<size_t>(S));
  for (int s = 0; s < S; ++s) views[size_t(s)] = slab(s);
  const SampleLayout& L = live.samples;
  m.displacement.resize(size_t(L.count));
  m.friction_static.resize(size_t(L.count));
  m.friction_dynamic.resize(size_t(L.count));
  m.stiffness_scale.resize(size_t(L.count));
  m.layer_displacement.resize(size_t(L.count));
  m.hardness.resize(size_t(L.count));
  for (int32_t id = 0; id < L.count; ++id) {
    const SlabView& v = views[size_t(L.home(id).slab)];
    const int32_t k = L.home(id).index;
    m.displacement[id] = v.points[k].delta;
    m.friction_static[id] = v.friction_static[k];
    m.friction_dynamic[id] = v.friction_dynamic[k];
    m.stiffness_scale[id] = v.stiffness_scale[k];
    m.layer_displacement[id] = v.layer_displacement[k];
    m.hardness[id] = v.hardness[k];
  }
  const SampleLayout& T = live.texels;
  m.colour.resize(size_t(T.count));
  m.roughness.resize(size_t(T.count));
  for (int32_t id = 0; id < T.count; ++id) {
    const uint8_t* t = views[size_t(T.home(id).slab)].texels + 4 * size_t(T.home(id).index);
    m.colour[id] = Srgb8{t[0], t[1], t[2]};
    m.roughness[id] = t[3];
  }
  return m;
}

}  // namespace hdm
