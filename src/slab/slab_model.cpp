// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/slab/slab_model.h>
#include <hdm/slab/triangle_grid.h>

#include "../core/parallel_for.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace hdm {

SlabGeometry make_slab_geometry(const Vec3& R0, const Vec3& S0, const Vec3& T0, const Vec3& R1, const Vec3& S1,
                                const Vec3& T1) {
  SlabGeometry g;
  g.R0 = R0;
  g.dR = R1 - R0;
  g.e1 = S0 - R0;
  g.e2 = T0 - R0;
  g.d1 = (S1 - S0) - g.dR;
  g.d2 = (T1 - T0) - g.dR;
  g.N0 = g.e1.cross(g.e2);
  g.N1 = g.e1.cross(g.d2) + g.d1.cross(g.e2);
  g.N2 = g.d1.cross(g.d2);
  return g;
}

Aabb slab_bounds(const SlabModel& model, int slab) noexcept {
  Aabb box;
  for (const int32_t v : model.slabs[static_cast<size_t>(slab)]) box.extend(model.inner[v]), box.extend(model.outer[v]);
  return box;
}

double slab_min_jacobian(const SlabGeometry& g, const Vec3& dS, const Vec3& dT) noexcept {
  // gV(α) = N(α)·dV is quadratic; the Jacobian N(α)·D(w) is linear in w, so its minimum over the
  // slab is the minimum of the three quadratics over α in [0,1] (docs/design.md#slab-validity).
  const double scale = std::max(g.N0.norm(), 1e-300);
  double lowest = 1e300;
  for (const Vec3* d : {&g.dR, &dS, &dT}) {
    const double c = g.N0.dot(*d), b = g.N1.dot(*d), a = g.N2.dot(*d);
    double m = std::min(c, a + b + c);
    if (a > 0) {
      const double t = -b / (2 * a);
      if (t > 0 && t < 1) m = std::min(m, c - b * b / (4 * a));
    }
    lowest = std::min(lowest, m / (scale * std::max(d->norm(), 1e-300)));
  }
  return lowest;
}

void projection_line(const SlabModel& model, int slab, int index, Vec3& p0, Vec3& p1) noexcept {
  const SampleLayout& L = model.samples;
  const double n = L.n;
  const double wT = L.point_i[index] / n, wS = L.point_j[index] / n, wR = 1.0 - wT - wS;
  const Tri& t = model.slabs[slab];
  p0 = wR * model.inner[t[0]] + wS * model.inner[t[1]] + wT * model.inner[t[2]];
  p1 = wR * model.outer[t[0]] + wS * model.outer[t[1]] + wT * model.outer[t[2]];
}

Vec3 sample_position(const SlabModel& model, int sample) noexcept {
  Vec3 p0, p1;
  projection_line(model, model.samples.home(sample).slab, model.samples.home(sample).index, p0, p1);
  return p0 + static_cast<double>(model.displacement[sample]) * (p1 - p0);
}

void update_displacements(SlabModel& model, const int32_t* samples, size_t count) noexcept {
  if (model.slab_samples.size() != model.samples.slot_count()) return;
  for (size_t k = 0; k < count; ++k) {
    const float d = model.displacement[samples[k]];
    model.samples.for_each_slot(samples[k], [&](int32_t slot) { model.slab_samples[slot].delta = d; });
  }
}

Aabb surface_box(const SlabModel& model) noexcept {
  Aabb box;
  if (model.displacement.size() != size_t(model.samples.count)) return box;
  for (int s = 0; s < model.samples.count; ++s) box.extend(sample_position(model, s));
  return box;
}

double displacement_quantisation(const SlabModel& model) noexcept {
  double longest = 0;
  for (size_t v = 0; v < model.inner.size() && v < model.outer.size(); ++v)
    longest = std::max(longest, (model.outer[v] - model.inner[v]).norm());
  return 0.5 / 65535.0 * longest;
}

namespace {

// Stores the unit normal of sample s from its area-weighted sum in every slab copy of the sample:
// `slab_samples` is the only store of the normals. The copies' displacement is not written here
// (update_displacements() did): the face normals of other samples, computed in parallel by
// rebuild_derived(), read it from these slots.
inline void store_normal(SlabModel& m, int32_t s, const Vec3f& sum) noexcept {
  const float len = sum.norm();
  const Vec3f n = len > 0 ? Vec3f(sum * (1.0f / len)) : Vec3f(0, 0, 1);  // one division, not three
  const int16_t c[3] = {encode_snorm16(n[0]), encode_snorm16(n[1]), encode_snorm16(n[2])};
  m.samples.for_each_slot(s, [&](int32_t slot) {
    int16_t* v = m.slab_samples[slot].n;  // the displacement and force-shading normal are kept
    v[0] = c[0], v[1] = c[1], v[2] = c[2];
  });
}

// The power of two that brings the model's size to about 1: edges scaled by it before the cross
// product keep an area-weighted float normal inside float's range at any model size (unscaled,
// the squared norm of a 1e12-unit model's sum overflows and a 1e-12-unit model's underflows).
inline float normal_scale(const SlabModel& m) noexcept {
  const double d = m.source_diagonal;
  return d > 0 && std::isfinite(d) ? std::ldexp(1.0f, -std::ilogb(d)) : 1.0f;
}

// Area-weighted normal of grid triangle f (times scale²), from its slab's constants and its
// slab-major displacements: grid point (i, j) at displacement δ lies at R0 + q, with
// q = wS·e1 + wT·e2 + δ·(dR + wS·d1 + wT·d2), wS = j/n, wT = i/n (projection_line()). The edges
// are differences of q in double: exact to rounding at any distance from the origin, with no
// cache of surface points (12 B per sample) to keep in sync.
inline Vec3f face_normal(const SlabModel& m, int32_t f, float scale) noexcept {
  const SampleLayout& L = m.samples;
  const GridCellRef c = L.grid_cell(f);
  const SlabGeometry& g = m.geometry[c.slab];
  const SlabSample* slots = m.slab_samples.data() + static_cast<size_t>(c.slab) * L.per_slab;
  const double inv_n = 1.0 / L.n;
  auto q = [&](int i, int j) noexcept {
    const double wS = j * inv_n, wT = i * inv_n, d = slots[grid::index(L.n, i, j)].delta;
    return Vec3(wS * g.e1 + wT * g.e2 + d * (g.dR + wS * g.d1 + wT * g.d2));
  };
  const int i = c.i, j = c.j;
  const Vec3 a = c.down ? q(i + 1, j) : q(i, j), b = q(i, j + 1), e = c.down ? q(i + 1, j + 1) : q(i + 1, j);
  const double s2 = double(scale) * scale;
  return ((b - a).cross(e - a) * s2).cast<float>();
}

}  // namespace

ForceShadingCode force_shading_code(const SlabModel& m, int32_t s) noexcept {
  const Vec3f own = sample_normal(m, s);
  Vec3f sum = own;
  m.samples.for_each_neighbour(s, [&](int32_t t) noexcept { sum += sample_normal(m, t); });
  const float len = sum.norm();
  return encode_oct8(len > 0 ? Vec3f(sum * (1.0f / len)) : own);
}

void store_force_shading_code(SlabModel& m, int32_t s, const ForceShadingCode& c) noexcept {
  m.samples.for_each_slot(s, [&](int32_t slot) {
    int8_t* h = m.slab_samples[slot].h;
    h[0] = c[0], h[1] = c[1];
  });
}

namespace {

inline void store_force_shading_normal(SlabModel& m, int32_t s) noexcept {
  store_force_shading_code(m, s, force_shading_code(m, s));
}

}  // namespace

void update_force_shading_normals(SlabModel& model, const int32_t* samples, size_t count, bool with_ring) noexcept {
  const SampleLayout& L = model.samples;
  if (model.slab_samples.size() != L.slot_count()) return;
  for (size_t k = 0; k < count; ++k) {
    const int32_t s = samples[k];
    store_force_shading_normal(model, s);
    if (!with_ring) continue;
    // A neighbour shared with another listed sample is recomputed once per listing: the same value.
    L.for_each_neighbour(s, [&](int32_t t) noexcept { store_force_shading_normal(model, t); });
  }
}

void update_normals(SlabModel& model, const int32_t* samples, size_t count) noexcept {
  const SampleLayout& L = model.samples;
  if (model.slab_samples.size() != L.slot_count()) return;
  const float scale = normal_scale(model);
  for (size_t k = 0; k < count; ++k) {
    const int32_t s = samples[k];
    Vec3f sum = Vec3f::Zero();
    L.for_each_incident_triangle(s, [&](int32_t f, const Tri&) { sum += face_normal(model, f, scale); });
    store_normal(model, s, sum);
  }
  update_force_shading_normals(model, samples, count, true);
}

FaceNormalCache::FaceNormalCache() : memo(kSlots), pending(2 * kSlots) {}

namespace {

// Evaluates the listed triangles whose slot still names them (a later triangle may have taken the
// slot; its own entry in the list comes after and is evaluated then).
void flush_faces(const SlabModel& m, FaceNormalCache& cache, size_t& pending, float scale) noexcept {
  constexpr int32_t mask = FaceNormalCache::kSlots - 1;
  for (size_t k = 0; k < pending; ++k) {
    const int32_t f = cache.pending[k];
    FaceNormalCache::Entry& e = cache.memo[f & mask];
    if (e.tri == f) e.face = face_normal(m, f, scale);
  }
  pending = 0;
}

}  // namespace

void update_normals(SlabModel& model, const int32_t* samples, size_t count, FaceNormalCache& cache,
                    bool force_shading_ring) noexcept {
  const SampleLayout& L = model.samples;
  if (model.slab_samples.size() != L.slot_count()) return;
  constexpr int32_t mask = FaceNormalCache::kSlots - 1;
  if (++cache.current == 0) {  // wrapped: forget every memo once every 2³² calls
    for (FaceNormalCache::Entry& e : cache.memo) e.tri = -1, e.stamp = 0;
    cache.current = 1;
  }
  const uint32_t now = cache.current;
  const float scale = normal_scale(model);
  // Branch-free passes (whether a triangle was already seen is unpredictable, and a mispredicted
  // branch costs about as much as a cross product): list the triangles not yet in the memo, evaluate
  // them, then sum per sample in incidence order.
  size_t pending = 0;
  const size_t room = cache.pending.size();
  for (size_t k = 0; k < count; ++k) {
    const int32_t s = samples[k];
    L.for_each_incident_triangle(s, [&](int32_t f, const Tri&) {
      if (pending == room) flush_faces(model, cache, pending, scale);  // rare: a long listing
      FaceNormalCache::Entry& m = cache.memo[f & mask];
      const bool fresh = m.tri != f || m.stamp != now;
      m.tri = f, m.stamp = now;
      cache.pending[pending] = f;
      pending += fresh;
    });
  }
  flush_faces(model, cache, pending, scale);
  for (size_t k = 0; k < count; ++k) {
    const int32_t s = samples[k];
    Vec3f sum = Vec3f::Zero();
    // Same triangles in the same order as the overload above: the same sum, bit for bit.
    L.for_each_incident_triangle(s, [&](int32_t f, const Tri&) {
      const FaceNormalCache::Entry& m = cache.memo[f & mask];
      sum += m.tri == f ? m.face : face_normal(model, f, scale);  // recompute if evicted
    });
    store_normal(model, s, sum);
  }
  if (force_shading_ring) update_force_shading_normals(model, samples, count, true);
}

namespace {

void check(bool ok, const std::string& what) {
  if (!ok) throw InvalidInput("slab model: " + what);
}

// A field no writer set takes its default everywhere, as one uniform value (no array).
template <class T>
void fill_default(SampleField<T>& f, size_t n, T value, const char* name) {
  if (f.empty()) f.assign(n, value);
  check(f.size() == n,
        std::string(name) + " has " + std::to_string(f.size()) + " entries, expected " + std::to_string(n));
}

void build_adjacency(SlabModel& m) {
  const int S = m.slab_count();
  m.edge_neighbour.assign(S, {-1, -1, -1});
  std::unordered_map<uint64_t, int32_t> first;  // undirected edge -> slab*3 + edge
  first.reserve(S * 2);
  for (int s = 0; s < S; ++s)
    for (int k = 0; k < 3; ++k) {
      const auto [lo, hi] = std::minmax(m.slabs[s][k], m.slabs[s][(k + 1) % 3]);
      const uint64_t key = (static_cast<uint64_t>(lo) << 32) | static_cast<uint32_t>(hi);
      auto [it, fresh] = first.try_emplace(key, s * 3 + k);
      if (!fresh) {
        m.edge_neighbour[s][k] = it->second / 3;
        m.edge_neighbour[it->second / 3][it->second % 3] = s;
      }
    }
}

// Calls f(ids, count) on the consecutive sample ids [b, e), a chunk at a time: the update
// functions take id lists, and one list of every sample would hold 4 B per sample (51 MB at
// 10^5 slabs) through the rebuild. The updates give the same values however the ids are split.
template <class F>
void for_id_chunks(size_t b, size_t e, F f) {
  constexpr size_t chunk = 4096;
  int32_t ids[chunk];
  for (size_t c = b; c < e; c += chunk) {
    const size_t k = std::min(chunk, e - c);
    for (size_t i = 0; i < k; ++i) ids[i] = static_cast<int32_t>(c + i);
    f(ids, k);
  }
}

}  // namespace

void materialise_fields(SlabModel& m) {
  m.friction_static.materialise();
  m.friction_dynamic.materialise();
  m.stiffness_scale.materialise();
  m.layer_displacement.materialise();
  m.hardness.materialise();
  m.colour.materialise();
  m.roughness.materialise();
}

void rebuild_derived(SlabModel& m) {
  check(m.grid_n >= 1 && m.grid_n <= 1024, "grid_n = " + std::to_string(m.grid_n) + " outside [1, 1024]");
  check(m.texel_density >= 1 && m.grid_n * m.texel_density <= 4096,
        "texel_density = " + std::to_string(m.texel_density) + " must be >= 1 with grid_n·texel_density <= 4096");
  check(m.inner.size() == m.outer.size(), "inner and outer vertex counts differ");
  check(!m.slabs.empty(), "no slabs");
  // Per-element checks build their message only on failure (millions of elements per model).
  for (size_t v = 0; v < m.inner.size(); ++v)
    if (!(m.inner[v].allFinite() && m.outer[v].allFinite()))
      check(false, "coarse vertex " + std::to_string(v) + " is not finite");
  m.samples = build_sample_layout(m.slabs, m.coarse_vertex_count(), m.grid_n);
  m.texels = build_sample_layout(m.slabs, m.coarse_vertex_count(), m.grid_n * m.texel_density);
  const size_t ns = m.samples.count, nt = m.texels.count;
  check(m.displacement.size() == ns,
        "displacement has " + std::to_string(m.displacement.size()) + " samples, the layout has " + std::to_string(ns));
  for (size_t s = 0; s < ns; ++s)
    if (!(m.displacement[s] >= 0.0f && m.displacement[s] <= 1.0f))
      check(false, "displacement of sample " + std::to_string(s) + " is outside [0, 1] or not finite");
  fill_default(m.colour, nt, encode_srgb8(Vec3f(0.8f, 0.8f, 0.8f)), "colour");
  fill_default(m.friction_static, ns, Half16(0.3f), "friction_static");
  fill_default(m.friction_dynamic, ns, Half16(0.2f), "friction_dynamic");
  fill_default(m.stiffness_scale, ns, Unorm16(1.0f), "stiffness_scale");
  fill_default(m.roughness, nt, uint8_t{255}, "roughness");
  fill_default(m.layer_displacement, ns, Unorm16(0.0f), "layer_displacement");
  fill_default(m.hardness, ns, Half16(default_hardness_hv), "hardness");
  for (size_t s = 0; s < ns; ++s)
    if (!(m.hardness[s] > 0.0f && std::isfinite(m.hardness[s])))
      check(false, "hardness of sample " + std::to_string(s) + " is not > 0 and finite");
  for (size_t s = 0; s < ns; ++s)
    if (!(std::isfinite(m.friction_static[s]) && std::isfinite(m.friction_dynamic[s]) &&
          std::isfinite(m.stiffness_scale[s])))
      check(false, "surface field of sample " + std::to_string(s) + " is not finite");
  for (size_t s = 0; s < ns; ++s)
    if (!(m.layer_displacement[s] >= 0.0f && m.layer_displacement[s] <= 1.0f))
      check(false, "layer displacement of sample " + std::to_string(s) + " is outside [0, 1] or not finite");
  // Every 8-bit colour and roughness code is a valid value: the texels need no check.
  {
    const UnderLayer& u = m.under_layer;
    if (!(u.colour.allFinite() && std::isfinite(u.stiffness_scale) && std::isfinite(u.friction_static) &&
          std::isfinite(u.friction_dynamic) && u.roughness >= 0.0f && u.roughness <= 1.0f && u.hardness_hv > 0.0f &&
          std::isfinite(u.hardness_hv)))
      check(false, "under-layer material has a non-finite value, a roughness outside [0, 1] or a hardness not > 0");
  }

  m.geometry.resize(m.slabs.size());
  for (size_t s = 0; s < m.slabs.size(); ++s) {
    const Tri& t = m.slabs[s];
    m.geometry[s] =
        make_slab_geometry(m.inner[t[0]], m.inner[t[1]], m.inner[t[2]], m.outer[t[0]], m.outer[t[1]], m.outer[t[2]]);
  }
  build_adjacency(m);

  m.slab_samples.resize(m.samples.slot_count());
  // In blocks of samples, in parallel: each call writes only its own samples' slab copies, and a
  // normal is the same sum in the same order whatever the block. The displacements first: the
  // face normals read them from every slot.
  constexpr size_t block = 16384;
  core::detail::parallel_blocks(ns, block, [&](size_t b, size_t e, size_t) {
    for_id_chunks(b, e, [&](const int32_t* ids, size_t k) { update_displacements(m, ids, k); });
  });
  std::vector<FaceNormalCache> caches(core::detail::parallel_workers(ns, block));
  core::detail::parallel_blocks(ns, block, [&](size_t b, size_t e, size_t w) {
    // Also fills slab_samples; the force-shading normals once below, not per ring.
    for_id_chunks(b, e, [&](const int32_t* ids, size_t k) { update_normals(m, ids, k, caches[w], false); });
  });
  core::detail::parallel_blocks(ns, block, [&](size_t b, size_t e, size_t) {
    // Reads the finished normals.
    for_id_chunks(b, e, [&](const int32_t* ids, size_t k) { update_force_shading_normals(m, ids, k, false); });
  });
}

void displaced_surface(const SlabModel& model, std::vector<Vec3>& vertices, std::vector<Tri>& faces) {
  vertices.resize(model.samples.count);
  for (int s = 0; s < model.samples.count; ++s) vertices[s] = sample_position(model, s);
  faces.clear();
  faces.reserve(static_cast<size_t>(model.samples.triangle_count()));
  model.samples.for_each_triangle([&](const Tri& t) { faces.push_back(t); });
}

}  // namespace hdm
