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
  if (S == 0 || m.slab_samples.size() != m.samples.slot_count() ||
      m.texels.slot_count() != size_t(S) * m.texels.per_slab || m.colour.size() != size_t(m.texels.count) ||
      m.roughness.size() != size_t(m.texels.count) || m.layer_displacement.size() != size_t(m.samples.count) ||
      m.hardness.size() != size_t(m.samples.count) ||
      m.samples.corner_slot_offsets.size() != size_t(m.coarse_vertex_count()) + 1)
    throw InvalidInput("snapshots: the model's derived data are missing (call rebuild_derived first)");
  if (o.reader_slots < 1 || o.reader_slots > 1024)
    throw InvalidInput("snapshots: reader_slots = " + std::to_string(o.reader_slots) + " outside [1, 1024]");
  if (o.spare_versions < -1 || o.spare_versions == 0)
    throw InvalidInput("snapshots: spare_versions = " + std::to_string(o.spare_versions) +
                       ": must be at least 1, or -1 for the default");
  per_slab_ = m.samples.per_slab;
  texels_per_slab_ = m.texels.per_slab;
  // A SlabSample and five 16-bit fields per displacement sample, one 4-byte word (the stored
  // codes) per texel; whole cache lines (16 floats).
  const size_t bytes = (sizeof(SlabSample) + 5 * sizeof(Unorm16)) * size_t(per_slab_) + 4 * size_t(texels_per_slab_);
  stride_ = (bytes + 63) / 64 * 64;
  slab_total_ = size_t(S);
  version_total_ = o.spare_versions > 0 ? size_t(o.spare_versions)
                                        : std::min(slab_total_, std::max<size_t>(16, (slab_total_ + 19) / 20));
  // One write asks for every slab holding its sample at once (a corner sample: every slab around
  // a coarse vertex); a pool smaller than that could never grant it, whatever was committed.
  size_t most = 2;  // an edge sample's two slabs
  for (int32_t v = 0; v < m.coarse_vertex_count(); ++v) most = std::max(most, size_t(m.samples.vertex_slab_count(v)));
  version_total_ = std::max(version_total_, most + 1);
  slot_count_ = size_t(o.reader_slots);
  arena_.assign(version_total_ * stride_, 0);
  versions_ = std::make_unique<Version[]>(version_total_);
  head_ = std::make_unique<std::atomic<int32_t>[]>(slab_total_);
  guard_ = std::make_unique<std::atomic<int32_t>[]>(slab_total_);
  live_since_ = std::make_unique<std::atomic<uint64_t>[]>(slab_total_);
  slots_ = std::make_unique<std::atomic<uint64_t>[]>(slot_count_);
  for (size_t k = 0; k < slot_count_; ++k) slots_[k].store(kFree);
  for (size_t s = 0; s < slab_total_; ++s) {
    head_[s].store(-1, std::memory_order_relaxed);
    guard_[s].store(0, std::memory_order_relaxed);
    live_since_[s].store(0, std::memory_order_relaxed);
  }
  state_.assign(slab_total_, 0);
  free_.reserve(version_total_);
  retired_.reserve(version_total_);
  pending_.reserve(version_total_);
  for (size_t v = version_total_; v-- > 0;) free_.push_back(static_cast<int32_t>(v));
  published_.store(0, std::memory_order_seq_cst);
}

SlabSnapshots::~SlabSnapshots() = default;

size_t SlabSnapshots::memory_bytes() const noexcept {
  return arena_.size() + version_total_ * sizeof(Version) + slab_total_ * (2 * sizeof(int32_t) + sizeof(uint64_t) + 1) +
         slot_count_ * sizeof(uint64_t);
}

void SlabSnapshots::fill(unsigned char* d, int slab) const noexcept {
  const SlabModel& m = model_;
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

uint64_t SlabSnapshots::checksum(const unsigned char* d) const noexcept {
  uint64_t h = 14695981039346656037ull;
  for (size_t k = 0; k < stride_; k += 4) {
    uint32_t w;
    std::memcpy(&w, d + k, 4);
    h = (h ^ w) * 1099511628211ull;
  }
  return h;
}

SlabView SlabSnapshots::view(const unsigned char* d, uint64_t epoch) const noexcept {
  const size_t P = size_t(per_slab_);
  SlabView s;
  s.epoch = epoch;
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

// Epoch-based reclamation: a retired version serves readers pinned in [from, to); recycle it once
// every reader is pinned at or after `to`. A slab's newest version is also reached from head_ by
// readers past `to` (to learn that the live slab is current), under the slab's guard: it is
// unlinked first and recycled once no reader holds that guard.
void SlabSnapshots::reclaim() noexcept {
  uint64_t oldest = kFree;
  for (size_t k = 0; k < slot_count_; ++k) oldest = std::min(oldest, slots_[k].load(std::memory_order_seq_cst));
  size_t keep = 0;
  for (int32_t r : retired_) {
    Version& x = versions_[r];
    bool recycle = false;
    if (x.to.load(std::memory_order_relaxed) <= oldest) {
      if (x.next >= 0) {  // readers past `to` stop at the newer version
        versions_[x.next].prev.store(-1, std::memory_order_release);
        recycle = true;
      } else {
        if (!x.unlinked) head_[x.slab].store(-1, std::memory_order_seq_cst);
        x.unlinked = true;
        recycle = guard_[x.slab].load(std::memory_order_seq_cst) == 0;
      }
    }
    if (recycle) {
      x.next = -1;
      x.unlinked = false;
      x.prev.store(-1, std::memory_order_relaxed);
      free_.push_back(r);
    } else {
      retired_[keep++] = r;
    }
  }
  retired_.resize(keep);
}

bool SlabSnapshots::before_write(int slab) noexcept {
  if (slab < 0 || size_t(slab) >= slab_total_) return false;
  uint8_t& st = state_[size_t(slab)];
  if (st == 0) {  // first write since the commit: preserve the committed state
    if (free_.empty()) reclaim();
    if (free_.empty()) {
      starved_ = true;
      return false;
    }
    const int32_t v = free_.back();
    free_.pop_back();
    Version& x = versions_[v];
    fill(data(v), slab);
    if (options_.checksums) x.checksum = checksum(data(v));
    x.slab = slab;
    x.next = -1;
    x.unlinked = false;
    x.from.store(live_since_[slab].load(std::memory_order_relaxed), std::memory_order_relaxed);
    x.to.store(kOpen, std::memory_order_relaxed);
    const int32_t old = head_[slab].load(std::memory_order_relaxed);
    x.prev.store(old, std::memory_order_relaxed);
    if (old >= 0) versions_[old].next = v;
    head_[slab].store(v, std::memory_order_seq_cst);  // readers from now on take the version
    pending_.push_back(v);
    st = 1;
  }
  if (st == 1) {
    // With the version visible (seq_cst store above), a reader that raises the guard after this
    // load sees it; one that raised it before may be copying the live slab: not yet.
    if (guard_[slab].load(std::memory_order_seq_cst) != 0) return false;
    st = 2;
  }
  return true;
}

uint64_t SlabSnapshots::publish_commit() noexcept {
  const uint64_t now = published_.load(std::memory_order_relaxed);
  starved_ = false;
  if (pending_.empty()) return now;
  const uint64_t next = now + 1;
  for (int32_t v : pending_) {
    Version& x = versions_[v];
    x.to.store(next, std::memory_order_release);
    // A slab preserved but never granted (a reader held its guard) is unchanged: its live content
    // stays current since the epoch it had, so readers see no new epoch for it.
    if (state_[size_t(x.slab)] == 2) live_since_[x.slab].store(next, std::memory_order_release);
    state_[size_t(x.slab)] = 0;
    retired_.push_back(v);
  }
  pending_.clear();
  published_.store(next, std::memory_order_seq_cst);
  return next;
}

int SlabSnapshots::pending() const noexcept { return static_cast<int>(pending_.size()); }

bool SlabSnapshots::readers_caught_up() noexcept {
  reclaim();
  return retired_.empty();
}

SnapshotReader::SnapshotReader(const SlabSnapshots& s) : s_(s), copy_(s.stride_, 0), check_(s.stride_, 0) {
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

int32_t SnapshotReader::find(int slab) const noexcept {
  const SlabSnapshots& s = s_;
  s.guard_[slab].fetch_add(1, std::memory_order_seq_cst);
  int32_t v = s.head_[slab].load(std::memory_order_seq_cst);
  // From the newest version back: the pinned epoch keeps every version it needs from being
  // recycled and the chain down to it intact (reclaim() cuts it only below every reader's epoch).
  while (v >= 0) {
    const SlabSnapshots::Version& x = s.versions_[v];
    const uint64_t to = x.to.load(std::memory_order_acquire);
    if (to != SlabSnapshots::kOpen && epoch_ >= to) {  // committed before the pin: the live slab is current
      v = -1;
      break;
    }
    if (epoch_ >= x.from.load(std::memory_order_acquire)) break;
    v = x.prev.load(std::memory_order_acquire);
  }
  if (v >= 0) s.guard_[slab].fetch_sub(1, std::memory_order_release);
  return v;
}

SlabView SnapshotReader::slab(int slab) const noexcept {
  const int32_t v = find(slab);
  if (v >= 0) return s_.view(s_.data(v), s_.versions_[v].from.load(std::memory_order_relaxed));
  s_.fill(copy_.data(), slab);
  const uint64_t since = s_.live_since_[slab].load(std::memory_order_acquire);
  s_.guard_[slab].fetch_sub(1, std::memory_order_release);
  return s_.view(copy_.data(), since);
}

uint64_t SnapshotReader::slab_epoch(int slab) const noexcept {
  const int32_t v = find(slab);
  if (v >= 0) return s_.versions_[v].from.load(std::memory_order_relaxed);
  const uint64_t since = s_.live_since_[slab].load(std::memory_order_acquire);
  s_.guard_[slab].fetch_sub(1, std::memory_order_release);
  return since;
}

bool SnapshotReader::verify(int slab) const noexcept {
  const int32_t v = find(slab);
  if (v >= 0) return !s_.options_.checksums || s_.checksum(s_.data(v)) == s_.versions_[v].checksum;
  s_.fill(copy_.data(), slab);
  s_.fill(check_.data(), slab);
  s_.guard_[slab].fetch_sub(1, std::memory_order_release);
  return std::memcmp(copy_.data(), check_.data(), s_.stride_) == 0;
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
  const SampleLayout& L = live.samples;
  const SampleLayout& T = live.texels;
  m.displacement.resize(size_t(L.count));
  std::vector<Half16> fs(size_t(L.count)), fd(size_t(L.count)), hv(size_t(L.count));
  std::vector<Unorm16> st(size_t(L.count)), ly(size_t(L.count));
  std::vector<Srgb8> colour(size_t(T.count));
  std::vector<uint8_t> roughness(size_t(T.count));
  // Slab by slab (a view lasts until the next slab() call), each sample and texel from its home.
  for (int s = 0; s < live.slab_count(); ++s) {
    const SlabView v = slab(s);
    const SlabIds ids = L.slab_ids(s);
    for (int k = 0; k < L.per_slab; ++k) {
      const int32_t id = ids[k];
      if (L.home(id).slab != s) continue;
      m.displacement[id] = v.points[k].delta;
      fs[id] = v.friction_static[k];
      fd[id] = v.friction_dynamic[k];
      st[id] = v.stiffness_scale[k];
      ly[id] = v.layer_displacement[k];
      hv[id] = v.hardness[k];
    }
    const SlabIds tids = T.slab_ids(s);
    for (int k = 0; k < T.per_slab; ++k) {
      const int32_t id = tids[k];
      if (T.home(id).slab != s) continue;
      const uint8_t* t = v.texels + 4 * size_t(k);
      colour[id] = Srgb8{t[0], t[1], t[2]};
      roughness[id] = t[3];
    }
  }
  // Fields the same everywhere come back uniform, as the live model may hold them.
  m.friction_static.assign(std::move(fs));
  m.friction_dynamic.assign(std::move(fd));
  m.stiffness_scale.assign(std::move(st));
  m.layer_displacement.assign(std::move(ly));
  m.hardness.assign(std::move(hv));
  m.colour.assign(std::move(colour));
  m.roughness.assign(std::move(roughness));
  return m;
}

}  // namespace hdm
