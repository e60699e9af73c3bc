// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The slab model: coarse slabs around a detailed surface, each holding a triangular displacement
/// map (paper §2), plus colour texels and per-sample surface fields.

#include <hdm/core/field16.h>
#include <hdm/core/sample_field.h>
#include <hdm/core/srgb.h>
#include <hdm/core/types.h>
#include <hdm/slab/sample_layout.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hdm {

/// Precomputed constants of one slab (paper §3.1; docs/design.md#alpha-plane), model units.
///
/// Corner V in {R, S, T} has inner point V0 and ray dV = V1 - V0. The alpha-triangle is
/// Rα = R0 + α·dR, Eα1 = e1 + α·d1 (Sα - Rα), Eα2 = e2 + α·d2 (Tα - Rα); its plane normal is
/// N(α) = N0 + N1·α + N2·α² (outward for a valid slab).
///
/// 216 bytes: what the query reads after the locator's filters, and nothing it can derive at no
/// cost on its chain (the box of the six corners is the locator's float filter and slab_bounds();
/// the products N·dR are three dot products beside the cubic's own).
struct SlabGeometry {
  /// @{ Inner R corner and R's ray.
  Vec3 R0, dR;
  /// @}
  /// @{ S0-R0, T0-R0, dS-dR, dT-dR.
  Vec3 e1, e2, d1, d2;
  /// @}
  /// @{ Alpha-plane normal coefficients.
  Vec3 N0, N1, N2;
  /// @}
};
static_assert(sizeof(SlabGeometry) == 216, "nine Vec3 of doubles, no padding");

/// @brief snorm16 code of a coordinate @p x in [-1, 1]: round(x·32767), clamped to ±32767 (a NaN
/// gives 0), so -32768 never occurs.
/// @note noexcept, O(1); decode_snorm16() returns it within 1/65534 (half a step).
inline int16_t encode_snorm16(float x) noexcept {
  const float c = std::clamp(x, -1.0f, 1.0f) * 32767.0f;  // std::clamp passes a NaN through
  return c == c ? static_cast<int16_t>(round_to_int(double(c))) : int16_t(0);
}

/// @brief The coordinate a snorm16 code of encode_snorm16() stands for: @p c / 32767, in [-1, 1].
/// @note noexcept, O(1).
inline float decode_snorm16(int16_t c) noexcept { return float(c) * (1.0f / 32767.0f); }

/// @brief The direction an encode_oct8() code stands for, not normalised: (x, y, 127 - |x| - |y|)
/// with the lower half unfolded, of length 127/√3 to 127 [code units]; zero for {-128, -128}.
/// @note noexcept, O(1).
inline Vec3f decode_oct8(const int8_t c[2]) noexcept {
  if (c[0] == -128 && c[1] == -128) return Vec3f::Zero();
  float x = c[0], y = c[1];
  const float z = 127.0f - std::abs(x) - std::abs(y), t = std::max(-z, 0.0f);
  x -= std::copysign(t, x), y -= std::copysign(t, y);
  return {x, y, z};
}

/// @brief Octahedral code of the direction @p v: two int8 codes for the point p where @p v meets
/// the octahedron |x| + |y| + |z| = 1, the lower half (z < 0) folded over the upper, scaled by 127;
/// of the four codes around 127·p, the one whose direction is nearest @p v (Cigolle, Donow,
/// Evangelakos, Mara, McGuire & Meyer, "A Survey of Efficient Representations for Independent Unit
/// Vectors", JCGT 3(2), 2014, §3.3, 16-bit "oct" with the "precise" encoding).
/// decode_oct8() of the code is within 0.65° of @p v (measured over two million random directions
/// by `Oct8.UnitVectorsComeBackWithinTheStatedAngle`; 0.96° with plain rounding). A zero or
/// non-finite @p v gives the code {-128, -128}, which the encoding never makes otherwise and which
/// decodes to the zero vector (a grid point with no normal adds nothing to an interpolated one).
/// @note noexcept, O(1): four decodes.
inline std::array<int8_t, 2> encode_oct8(const Vec3f& v) noexcept {
  const float s = std::abs(v[0]) + std::abs(v[1]) + std::abs(v[2]);
  if (!(s > 0) || !(s < std::numeric_limits<float>::infinity())) return {-128, -128};
  float px = v[0] / s, py = v[1] / s;
  if (v[2] < 0) {
    const float fx = (1 - std::abs(py)) * (px >= 0 ? 1.0f : -1.0f), fy = (1 - std::abs(px)) * (py >= 0 ? 1.0f : -1.0f);
    px = fx, py = fy;
  }
  const float fx = std::floor(std::clamp(px, -1.0f, 1.0f) * 127.0f),
              fy = std::floor(std::clamp(py, -1.0f, 1.0f) * 127.0f);
  std::array<int8_t, 2> best{};
  float best_cos = -2;
  for (int k = 0; k < 4; ++k) {
    const int8_t c[2] = {static_cast<int8_t>(std::min(fx + float(k & 1), 127.0f)),
                         static_cast<int8_t>(std::min(fy + float(k >> 1), 127.0f))};
    const Vec3f d = decode_oct8(c);
    const float cos = d.dot(v) / d.norm();  // times |v|, the same for every candidate
    if (cos > best_cos) best_cos = cos, best = {c[0], c[1]};
  }
  return best;
}

/// One grid point of a slab as the haptic query and the proxy read it: the unit normal, the
/// displacement of its sample and the force-shading normal, side by side in 10 bytes, so a grid
/// cell's three points are one or two cache lines of one slab's block. The normal is snorm16 per
/// coordinate (encode_snorm16(); at most 2.7e-5 rad from the float normal): the query's depth
/// depends on it. The displacement is the unorm16 code of SlabModel::displacement. The
/// force-shading normal, which only directs the proxy's force, is an 8-bit octahedral code
/// (encode_oct8(); at most 0.65° from the float normal, against the 10° the force direction is
/// allowed: docs/haptics.md). The query interpolates the normal's codes and normalises the sum,
/// with no decode at all.
struct SlabSample {
  int16_t n[3];   ///< unit normal of the displaced surface, snorm16 (normal(); sample_normal() reads it)
  Unorm16 delta;  ///< displacement δ in [0,1] (copy of SlabModel::displacement's code)
  int8_t h[2];    ///< force-shading normal (one-ring sum of unit normals, normalised), octahedral (shading())

  /// The unit normal (to 2.7e-5 rad), decoded.
  Vec3f normal() const noexcept { return {decode_snorm16(n[0]), decode_snorm16(n[1]), decode_snorm16(n[2])}; }
  /// The force-shading normal (to 0.65°), decoded and normalised.
  Vec3f shading() const noexcept { return decode_oct8(h).normalized(); }  // Eigen: zero stays zero
};
static_assert(sizeof(SlabSample) == 10, "five 16-bit codes, no padding");

/// The material under the surface layer (paper §2: "the depth of various materials underneath or
/// above the visible surface — materials that may be exposed or added by an edit operation").
/// Where the surface lies below SlabModel::layer_displacement it is this material: the renderer
/// shows its colour and roughness, the proxy renders its stiffness and friction (design: docs/editing.md).
struct UnderLayer {
  Vec3f colour{0.85f, 0.62f, 0.3f};  ///< linear RGB shown where the under-layer is exposed
  float stiffness_scale = 0.5f;      ///< factor on the rendered stiffness where exposed, in [0,1]
  float friction_static = 0.3f;      ///< μs where exposed
  float friction_dynamic = 0.2f;     ///< μd where exposed
  float roughness = 1.0f;            ///< rendering roughness where exposed, in [0,1] (1: matte)
  /// Vickers hardness where the surface lies in the under-layer [HV], > 0 (what the drill brush
  /// reads there; 55 HV: dentin-like). 1 HV = 9.80665 MPa (hdm::vickers_to_pa).
  float hardness_hv = 55.0f;
};

/// Default Vickers hardness of the surface material [HV]: 300 HV, enamel-like (SlabModel::hardness).
inline constexpr float default_hardness_hv = 300.0f;

/// @brief Pascals of a Vickers hardness @p hv [HV]: hv × 9.80665 MPa (1 kgf/mm²).
/// @note noexcept, O(1).
constexpr double vickers_to_pa(double hv) noexcept { return hv * 9.80665e6; }

/// A baked slab model.
///
/// Stored data (what a `.hdm` file holds) and derived data (rebuilt by rebuild_derived()).
/// Threading: readers may share a const model; edits (hdm/edit) mutate the stored per-sample and
/// per-texel fields and `slab_samples` and must not run
/// concurrently with readers of the same samples (hdm::SlabSnapshots gives other threads
/// consistent copies while one thread edits; docs/editing.md). Code that changes `displacement` outside the edit tools
/// must call update_displacements() on the changed samples and update_normals() on them and their one-ring (or
/// rebuild_derived()), or the query and the proxy will read stale values from `slab_samples`.
/// Surface points are not cached: sample_position() evaluates one in O(1) (docs/performance.md#model-memory-by-part).
struct SlabModel {
  // ---- stored ----
  int grid_n = 16;          ///< displacement intervals per slab edge (n)
  int texel_density = 2;    ///< colour texels per displacement interval (m); texel grid n·m
  std::vector<Vec3> inner;  ///< #C inner coarse vertex positions V0 [model units]
  std::vector<Vec3> outer;  ///< #C outer coarse vertex positions V1 [model units]
  std::vector<Tri> slabs;   ///< #S slabs as coarse-vertex triples R, S, T (CCW from outside)
  /// #samples δ in [0,1] along each projection line (0 inner, 1 outer), unorm16: within 7.7e-6
  /// of the shell's thickness along the line (displacement_quantisation() bounds it in model units)
  std::vector<Unorm16> displacement;
  /// #texels colour as 8-bit sRGB (decode_srgb8() gives the linear RGB it stands for; writers
  /// encode linear RGB with encode_srgb8(), rounding once). One value until painted (SampleField).
  SampleField<Srgb8> colour;
  /// @{ Surface material per sample, each one value until painted (SampleField: no array while
  /// uniform): static and dynamic friction coefficients μs, μd (binary16) and the factor on the
  /// rendered stiffness in [0,1] (unorm16).
  SampleField<Half16> friction_static;
  SampleField<Half16> friction_dynamic;
  SampleField<Unorm16> stiffness_scale;
  /// @}
  /// #texels rendering roughness as unorm8 (code/255 in [0,1]; 0 glossy, 255 matte, the default;
  /// unorm8_to_unit(), unit_to_unorm8()). One value until painted (SampleField).
  SampleField<uint8_t> roughness;
  /// #samples: displacement of the top of the under-layer on each projection line, in [0,1]
  /// (default 0: no under-layer above the inner face). The surface is the under-layer where
  /// δ < this value (exposed by carving); see UnderLayer and layer_exposure(). unorm16: within
  /// 7.7e-6 of the shell's thickness. One value until painted or drilled (SampleField).
  SampleField<Unorm16> layer_displacement;
  /// #samples Vickers hardness of the surface material [HV], > 0 and at most 65,504 (binary16; default
  /// default_hardness_hv). Where δ < layer_displacement the under-layer's UnderLayer::hardness_hv
  /// applies instead (sample_hardness_hv()). Read by the drill brush (BrushTool::Drill). One value
  /// until painted (SampleField).
  SampleField<Half16> hardness;
  UnderLayer under_layer;        ///< the under-layer's material
  std::string source;            ///< name of the input mesh the model was baked from
  int64_t source_triangles = 0;  ///< triangles of that input
  double source_diagonal = 0;    ///< bounding-box diagonal of that input [model units]

  // ---- derived (rebuild_derived) ----
  SampleLayout samples;                ///< displacement samples (grid n)
  SampleLayout texels;                 ///< colour texels (grid n·m), without grid triangles
  std::vector<SlabGeometry> geometry;  ///< #S slab constants
  /// #S: slab across edge RS, ST, TR or -1. The slabs around a coarse vertex are its corner
  /// sample's (samples.for_each_vertex_slab()).
  std::vector<std::array<int32_t, 3>> edge_neighbour;
  /// #S·samples.per_slab: slab-major copy of `displacement` with each sample's unit normal and
  /// force-shading normal (SlabSample), in grid::index order within a slab (slot slab·per_slab +
  /// index holds sample samples.id(slab, index)). What the query and the proxy interpolate, and the only
  /// store of the normals: every slot of a shared sample holds the same values (sample_normal()
  /// reads the home slot). The force-shading normal (hdm::proxy_step) is the sample's normal summed
  /// with those of its grid neighbours (one ring, across seams) and normalised: the proxy's fixed
  /// point (the surface point whose interpolated normal points at the hand) folds, and the force
  /// jumps, wherever penetration depth × the normal field's rate of turn exceeds 1 rad; the grid
  /// normals of a scanned surface turn that fast at about 1 mm of depth (docs/haptics.md).
  /// update_displacements() and update_normals() keep them in sync with `displacement`.
  std::vector<SlabSample> slab_samples;

  /// Number of slabs.
  int slab_count() const noexcept { return static_cast<int>(slabs.size()); }
  /// Number of coarse vertices.
  int coarse_vertex_count() const noexcept { return static_cast<int>(inner.size()); }
};

/// @brief How far the under-layer shows at a point whose surface lies @p depth_below_layer below
/// the top of the under-layer [model units] (negative above it): clamp(depth / band, 0, 1).
/// @param depth_below_layer  depth of the surface below the under-layer's top [model units].
/// @param band  depth over which the exposure ramps from 0 to 1 [model units], > 0; a narrow ramp
///              instead of a step keeps the force continuous when the proxy crosses the boundary.
/// @note noexcept, O(1); NaN gives 0.
inline double layer_exposure(double depth_below_layer, double band) noexcept {
  const double e = depth_below_layer / band;
  return e > 0 ? (e < 1 ? e : 1.0) : 0.0;
}

/// @brief Hardness of the material at sample @p sample's surface [HV]: the under-layer's
/// (UnderLayer::hardness_hv) where its displacement is below the layer's top, else its own
/// SlabModel::hardness.
/// @note noexcept, O(1); @p sample in [0, #samples) and `hardness` sized (rebuild_derived()).
inline float sample_hardness_hv(const SlabModel& model, int32_t sample) noexcept {
  return model.displacement[sample] < model.layer_displacement[sample] ? model.under_layer.hardness_hv
                                                                       : float(model.hardness[sample]);
}

/// @brief Recomputes every derived member of @p model from its stored data: sample and texel
/// layouts, slab constants, adjacency and normals.
/// Optional stored arrays that are empty (colour, friction, stiffness, roughness,
/// layer_displacement, hardness) are filled with their defaults (the per-sample ones as one
/// uniform value, SampleField).
/// @throws InvalidInput when the stored data are inconsistent (sizes, ids, non-finite values,
///         displacements or layer displacements outside [0,1], the under-layer's roughness outside [0,1],
///         a hardness (per sample or the under-layer's) not > 0,
///         grid_n < 1 or texel_density < 1), naming the member.
/// @note O(#S·n²·m²); allocates; normals and the layouts' CSR rows in parallel (std::thread).
void rebuild_derived(SlabModel& model);

/// @brief Gives each per-sample and per-texel field of @p model that is one value everywhere
/// (SampleField) its array, kept from then on, so that no later write allocates: what the edits do
/// before they run (EditScratch and StrokeEditor call it), since the servo thread that edits never
/// allocates. Costs 2 bytes per sample for each per-sample field that was uniform (at most 10),
/// and 3 and 1 bytes per texel for colour and roughness.
/// @throws std::bad_alloc. @note O(#samples).
void materialise_fields(SlabModel& model);

/// @brief Slab constants of the slab with corners (R0,S0,T0) and (R1,S1,T1) [model units].
/// @see docs/design.md#alpha-plane (the cubic's constants, paper eq. 1-2 expanded).
SlabGeometry make_slab_geometry(const Vec3& R0, const Vec3& S0, const Vec3& T0, const Vec3& R1, const Vec3& S1,
                                const Vec3& T1);

/// @brief Box of the six corners of slab @p slab (inner and outer points of R, S, T) [model units]:
/// it contains the whole slab, since every slab point is a convex combination of its corners.
/// @param model  slab model (`inner`, `outer`, `slabs`); @param slab  slab id in [0, #S).
/// @note noexcept, O(1); reads only the stored corners (derived data may be stale).
Aabb slab_bounds(const SlabModel& model, int slab) noexcept;

/// @brief Ends of the projection line of grid point @p index of slab @p slab.
/// @param model  slab model with derived data.
/// @param slab   slab id in [0, #S).
/// @param index  packed grid index in the slab (grid::index).
/// @param[out] p0  inner end Σ wV·V0 [model units]
/// @param[out] p1  outer end Σ wV·V1 [model units]
/// @note O(1), noexcept; the sample's surface point is p0 + δ·(p1 - p0) (paper §2, §3.2).
void projection_line(const SlabModel& model, int slab, int index, Vec3& p0, Vec3& p1) noexcept;

/// @brief Surface point of global sample @p sample at its current displacement [model units].
/// @note O(1), noexcept; evaluated in the sample's home slab, so shared samples agree exactly.
Vec3 sample_position(const SlabModel& model, int sample) noexcept;

/// @brief The slab-major record of sample @p s in its home slot (SampleLayout::home()); every
/// slot of a shared sample holds the same normal and force-shading normal.
/// Precondition: 0 <= s < samples.count, `slab_samples` sized to the slots. @note O(1), noexcept.
inline const SlabSample& home_slab_sample(const SlabModel& model, int32_t s) noexcept {
  const GridSlot h = model.samples.home(s);
  return model.slab_samples[static_cast<size_t>(h.slab) * model.samples.per_slab + h.index];
}

/// @brief Unit normal of sample @p s of the displaced surface (paper §3.4), read from its home
/// slot of `slab_samples` (every slot of the sample holds the same value), as decoded from its
/// snorm16 codes: unit to 2.7e-5, not renormalised (SlabSample).
/// @pre rebuild_derived(model) has run; 0 <= s < model.samples.count.
/// @note O(1) (a shift, a mask, one load), noexcept.
inline Vec3f sample_normal(const SlabModel& model, int32_t s) noexcept { return home_slab_sample(model, s).normal(); }

/// @brief Copies the stored `displacement` of @p samples into every slot of theirs in
/// `slab_samples` (the copy the query, the proxy and the normals read).
/// @note O(count × the slabs holding each sample); no allocation; noexcept. Call it after changing
///       `displacement` outside the edit tools, before update_normals() on the samples and their
///       one-ring. Does nothing when `slab_samples` is not sized to the slots.
void update_displacements(SlabModel& model, const int32_t* samples, size_t count) noexcept;

/// @brief Bounding box of the displaced surface: every sample's surface point (sample_position())
/// [model units, model frame].
/// @note O(#samples), noexcept; empty for a model without derived data.
Aabb surface_box(const SlabModel& model) noexcept;

/// @brief The most a stored surface point can lie from the one its displacement was written for:
/// half a unorm16 step of δ (0.5/65535) times the longest projection line [model units].
/// @note O(#C), noexcept. The line at barycentrics w is Σ wV·(V1 − V0), never longer than the longest
///       corner's |V1 − V0|, so the bound holds at every sample. 0 for a model without coarse vertices.
double displacement_quantisation(const SlabModel& model) noexcept;

/// @brief Recomputes the unit normals of @p samples (area-weighted average of the incident grid
/// triangles of every slab, across seams) (paper §3.4; docs/design.md#normals), and refreshes their
/// normal in `slab_samples`, and the force-shading normals of them and their grid neighbours. The
/// triangles' corners are read from the displacements in `slab_samples`: after changing
/// `displacement`, call update_displacements() on the changed samples first. Does nothing when
/// `slab_samples` is not sized to the slots.
/// @note O(k·valence); no allocation. Evaluates each incident triangle once per sample; for many
///       samples sharing triangles use the FaceNormalCache overload.
void update_normals(SlabModel& model, const int32_t* samples, size_t count) noexcept;

/// Caller-owned per-triangle memo for update_normals(): each grid triangle's (area-weighted)
/// normal is computed once per call however many of its corners are updated. A direct-mapped
/// table of kSlots entries keyed by triangle id (an edit's triangles have nearby ids, so they
/// rarely collide; a collision only costs a recomputation), small enough to stay in cache,
/// unlike a table over every triangle of the model. One per thread.
struct FaceNormalCache {
  static constexpr int32_t kSlots = 4096;  ///< table entries (power of two)
  /// @brief Allocates the table and the pending list (about 110 KB, independent of the model).
  FaceNormalCache();
  /// One memo entry.
  struct Entry {
    Vec3f face;          ///< cross product of the triangle's edges, each scaled by 2^-ilogb(source_diagonal)
    int32_t tri = -1;    ///< triangle whose normal `face` holds (-1: none)
    uint32_t stamp = 0;  ///< call number that set `tri`
  };
  std::vector<Entry> memo;       ///< kSlots entries, triangle f in slot f & (kSlots - 1)
  std::vector<int32_t> pending;  ///< triangles listed for evaluation (flushed when full)
  uint32_t current = 0;          ///< number of the current call
};

/// @brief A force-shading normal as stored: its octahedral code (SlabSample::h, encode_oct8()).
using ForceShadingCode = std::array<int8_t, 2>;

/// @brief The force-shading normal of sample @p sample as update_force_shading_normals() would
/// store it (the normalised sum of its normal and its grid neighbours' normals, encoded), without
/// storing it: an editor compares it with the stored code and writes only a change.
/// Precondition: 0 <= sample < samples.count, `slab_samples` sized to the slots.
/// @note O(valence), noexcept, no allocation.
ForceShadingCode force_shading_code(const SlabModel& model, int32_t sample) noexcept;

/// @brief Stores @p code as the force-shading normal of every slot of sample @p sample.
/// Preconditions as force_shading_code(). @note O(slabs holding the sample), noexcept.
void store_force_shading_code(SlabModel& model, int32_t sample, const ForceShadingCode& code) noexcept;

/// @brief Recomputes the force-shading normals (SlabSample::h) of @p samples from the normals (sample_normal()): the
/// normalised sum of the sample's normal and its grid neighbours' (SampleLayout::for_each_neighbour(),
/// across seams, so a sample shared by several slabs has one value). With @p with_ring, the grid
/// neighbours of @p samples are recomputed too (what a change of their normals affects). Every slot of a sample gets
/// the same value.
/// @note O(count·valence²) with the ring, O(count·valence) without; no allocation. Does nothing
///       when `slab_samples` is not sized to the slots (samples.slot_count()).
void update_force_shading_normals(SlabModel& model, const int32_t* samples, size_t count, bool with_ring) noexcept;

/// @brief update_normals() with each affected grid triangle's normal computed once: the same
/// result bit for bit (same products, same summation order), about a third of the cross products
/// when the samples form a patch (each triangle has three corners).
/// With @p force_shading_ring (the default) it then calls update_force_shading_normals(samples, with_ring);
/// without, the caller updates the force-shading normals itself (the edit tools list the ring's
/// neighbours once each with their visit stamps, instead of once per listing).
/// @note O(k·valence); no allocation, noexcept: used by the edit tools in the servo tick.
void update_normals(SlabModel& model, const int32_t* samples, size_t count, FaceNormalCache& cache,
                    bool force_shading_ring = true) noexcept;

/// @brief Exact per-slab validity: the Jacobian N(α)·D(w) is positive over the whole slab
/// (docs/design.md#slab-validity: three quadratics positive on [0,1]).
/// @return the minimum over the slab of the Jacobian, normalised by |N0|·|dV| scale; > 0 iff valid.
double slab_min_jacobian(const SlabGeometry& g, const Vec3& dS, const Vec3& dT) noexcept;

/// @brief The reconstructed (displaced) surface as a triangle mesh: one vertex per sample,
/// the grid triangles of every slab [model units].
void displaced_surface(const SlabModel& model, std::vector<Vec3>& vertices, std::vector<Tri>& faces);

}  // namespace hdm
