// SPDX-License-Identifier: MIT
// Edits: carve never raises, add never lowers, seams stay closed, normals stay consistent, paint
// follows the paper's blend, and the edited model round-trips through save and load.
#include "edit/stroke_fixture.h"
#include "support/test_models.h"

#include <hdm/edit/edit_tools.h>
#include <hdm/io/hdm_file.h>
#include <hdm/slab/triangle_grid.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <random>

using namespace hdm;

namespace {

struct Fixture {
  SlabModel model = test::baked_bunny(0, 16);  // a private copy to edit
  SlabLocator locator{model};
  EditScratch scratch{model};
  double diag = model.source_diagonal;

  // A contact a little below the surface point of a random sample.
  bool contact_at(int sample, double depth_frac, Contact& c, Vec3& hip) {
    const Vec3 p = sample_position(model, sample) - depth_frac * diag * sample_normal(model, sample).cast<double>();
    QueryCache cache;
    c = query(model, locator, p, cache);
    hip = p;
    return c.penetrating();
  }

  // 20 attempts at random samples, alternately adding (even) and carving (odd) with a tool of
  // radius_frac·diag; add raises by height_frac·diag.
  void carve_and_add(unsigned seed, double radius_frac, double height_frac) {
    std::mt19937 rng(seed);
    for (int k = 0; k < 20; ++k) {
      Contact c;
      Vec3 hip;
      if (!contact_at(int(rng() % model.samples.count), 0.004, c, hip)) continue;
      if (k % 2)
        carve(model, scratch, c, hip, radius_frac * diag, 0.0);
      else
        add_material(model, scratch, c, radius_frac * diag, height_frac * diag);
    }
  }
};

void expect_seams_closed(const SlabModel& m) {
  // The surface evaluated on a shared edge from either slab is the same point.
  for (int s = 0; s < m.slab_count(); ++s)
    for (int e = 0; e < 3; ++e) {
      const int nb = m.edge_neighbour[s][e];
      if (nb < 0) continue;
      const int a = m.slabs[s][e], b = m.slabs[s][(e + 1) % 3];
      for (double t : {0.13, 0.5, 0.77}) {
        Vec3 wa = Vec3::Zero(), wb = Vec3::Zero();
        wa[e] = 1 - t, wa[(e + 1) % 3] = t;
        for (int k = 0; k < 3; ++k) {
          if (m.slabs[nb][k] == a) wb[k] = 1 - t;
          if (m.slabs[nb][k] == b) wb[k] = t;
        }
        Contact ca, cb;
        evaluate_surface(m, s, SlabCoordinates{0.5, wa}, ca);
        evaluate_surface(m, nb, SlabCoordinates{0.5, wb}, cb);
        ASSERT_LT((ca.surface_point - cb.surface_point).norm(), 1e-9 * m.source_diagonal) << s << " / " << nb;
      }
    }
}

}  // namespace

TEST(EditToolsTest, CarveNeverRaisesAndAddNeverLowers) {
  Fixture f;
  std::mt19937 rng(9);
  int carved = 0, added = 0;
  for (int k = 0; k < 60; ++k) {
    Contact c;
    Vec3 hip;
    if (!f.contact_at(int(rng() % f.model.samples.count), 0.004, c, hip)) continue;
    const std::vector<float> before = test::values(f.model.displacement);
    if (k % 2 == 0) {
      carved += carve(f.model, f.scratch, c, hip, 0.01 * f.diag, 0.0005 * f.diag).changed;
      for (size_t s = 0; s < before.size(); ++s) ASSERT_LE(f.model.displacement[s], before[s]);
    } else {
      added += add_material(f.model, f.scratch, c, 0.01 * f.diag, 0.002 * f.diag).changed;
      for (size_t s = 0; s < before.size(); ++s) ASSERT_GE(f.model.displacement[s], before[s]);
    }
    for (float d : f.model.displacement) ASSERT_TRUE(d >= 0 && d <= 1);
  }
  EXPECT_GT(carved, 100);
  EXPECT_GT(added, 100);
  expect_seams_closed(f.model);
}

TEST(EditToolsTest, CarveCutsToTheSphere) {
  Fixture f;
  Contact c;
  Vec3 hip;
  ASSERT_TRUE(f.contact_at(1234, 0.006, c, hip));
  const double r = 0.01 * f.diag, k = 0.001 * f.diag;
  carve(f.model, f.scratch, c, hip, r, k);
  const Vec3 centre = hip + c.normal * (r + k);
  // No changed sample lies inside the tool sphere any more (up to rounding: δ is stored to half a
  // unorm16 step along its projection line), and the samples it moved now lie on its boundary or
  // on the inner face.
  for (int s = 0; s < f.model.samples.count; ++s) {
    const double d = (sample_position(f.model, s) - centre).norm();
    const GridSlot h = f.model.samples.home(s);
    Vec3 p0, p1;
    projection_line(f.model, h.slab, h.index, p0, p1);
    const double half_step = 0.5 / 65535 * (p1 - p0).norm();
    if (f.model.displacement[s] > 0) {
      EXPECT_GT(d, r * (1 - 1e-5) - half_step) << "sample " << s;
    }
  }
}

TEST(EditToolsTest, IncrementalNormalsMatchAFullRecompute) {
  Fixture f;
  std::mt19937 rng(4);
  for (int k = 0; k < 20; ++k) {
    Contact c;
    Vec3 hip;
    if (f.contact_at(int(rng() % f.model.samples.count), 0.004, c, hip))
      carve(f.model, f.scratch, c, hip, 0.012 * f.diag, 0.0);
  }
  SlabModel fresh = f.model;
  rebuild_derived(fresh);
  for (int s = 0; s < f.model.samples.count; ++s)
    ASSERT_LT((sample_normal(fresh, s) - sample_normal(f.model, s)).norm(), 1e-5) << "sample " << s;
  ASSERT_EQ(fresh.slab_samples.size(), f.model.slab_samples.size());
  for (size_t slot = 0; slot < fresh.slab_samples.size(); ++slot)  // every slab's copy of the edited δ
    ASSERT_EQ(fresh.slab_samples[slot].delta, f.model.slab_samples[slot].delta) << "slot " << slot;
}

// Independent reference for the normals: area-weighted vertex normals of the displaced surface
// in double precision, from sample_position() and grid triangles enumerated here from the slabs
// and grid::index (not from the layout's triangle list or its incidence CSR).
static std::vector<Vec3> brute_force_normals(const SlabModel& m) {
  const SampleLayout& L = m.samples;
  const int n = L.n;
  std::vector<Vec3> sum(L.count, Vec3::Zero());
  auto add = [&](const SlabIds& g, int a, int b, int c) {
    const Vec3 pa = sample_position(m, g[a]), pb = sample_position(m, g[b]), pc = sample_position(m, g[c]);
    const Vec3 f = (pb - pa).cross(pc - pa);
    sum[g[a]] += f, sum[g[b]] += f, sum[g[c]] += f;
  };
  for (int slab = 0; slab < m.slab_count(); ++slab) {
    const SlabIds g = L.slab_ids(slab);
    for (int j = 0; j < n; ++j)
      for (int i = 0; i + j < n; ++i) {
        add(g, grid::index(n, i, j), grid::index(n, i, j + 1), grid::index(n, i + 1, j));
        if (i + j <= n - 2) add(g, grid::index(n, i + 1, j), grid::index(n, i, j + 1), grid::index(n, i + 1, j + 1));
      }
  }
  for (Vec3& v : sum) v.normalize();
  return sum;
}

TEST(EditToolsTest, EditedNormalsMatchABruteForceRecompute) {
  Fixture f;
  const std::vector<Vec3f> before = test::sample_normals(f.model);
  std::mt19937 rng(9);
  for (int k = 0; k < 30; ++k) {
    Contact c;
    Vec3 hip;
    if (!f.contact_at(int(rng() % f.model.samples.count), 0.004, c, hip)) continue;
    if (k % 2)
      carve(f.model, f.scratch, c, hip, 0.015 * f.diag, 0.0);
    else
      add_material(f.model, f.scratch, c, 0.015 * f.diag, 0.004 * f.diag);
  }
  const std::vector<Vec3> ref = brute_force_normals(f.model);
  int moved = 0;
  for (int s = 0; s < f.model.samples.count; ++s) {
    // Float positions against double ones: agreement to ~1e-4 rad on grid triangles this small.
    ASSERT_LT((sample_normal(f.model, s).cast<double>() - ref[s]).norm(), 2e-3) << "sample " << s;
    moved += (before[s] - sample_normal(f.model, s)).norm() > 1e-3;
  }
  EXPECT_GT(moved, 200);  // the edits did turn normals
}

TEST(EditToolsTest, ForceShadingNormalsFollowTheEdits) {
  // The proxy's force-shading field: each sample's normal plus its grid neighbours', normalised.
  // Reference: the neighbours found from the grid triangles of every slab (not the layout's
  // adjacency), after edits, against the brute-force normals.
  Fixture f;
  f.carve_and_add(13, 0.015, 0.004);
  const SampleLayout& L = f.model.samples;
  const std::vector<Vec3> n = brute_force_normals(f.model);
  std::vector<std::vector<int32_t>> nb(L.count);
  L.for_each_triangle([&](const Tri& t) {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (a != b) nb[t[a]].push_back(t[b]);
  });
  std::vector<Vec3> ref(L.count);
  for (int s = 0; s < L.count; ++s) {
    std::sort(nb[s].begin(), nb[s].end());
    nb[s].erase(std::unique(nb[s].begin(), nb[s].end()), nb[s].end());
    Vec3 sum = n[s];
    for (int32_t u : nb[s]) sum += n[u];
    ref[s] = sum.normalized();
  }
  // Slab-major: every slot of a shared sample (edges, corners) holds its sample's value.
  ASSERT_EQ(f.model.slab_samples.size(), L.slot_count());
  std::vector<int64_t> first_slot(L.count, -1);
  for (size_t slot = 0; slot < L.slot_count(); ++slot) {
    const int32_t s = L.id(int32_t(slot / L.per_slab), int32_t(slot % L.per_slab));
    // 3e-3 for the normals' float sums, plus the stored code's 0.65° (encode_oct8()) as a chord.
    const double stored = 2 * std::sin(0.65 / 2 * std::numbers::pi / 180);
    ASSERT_LT((f.model.slab_samples[slot].shading().cast<double>() - ref[s]).norm(), 3e-3 + stored) << "slot " << slot;
    // Bit for bit the same in every slab that holds the sample, so the interpolated field is the
    // same on a shared edge or corner from either side.
    if (first_slot[s] < 0)
      first_slot[s] = int64_t(slot);
    else
      ASSERT_EQ(f.model.slab_samples[slot].shading(), f.model.slab_samples[first_slot[s]].shading()) << "sample " << s;
  }
}

TEST(EditToolsTest, SlabMajorCopyFollowsTheEdits) {
  // The query reads slab_samples; after edits every grid point must hold its sample's current
  // displacement and normal exactly.
  Fixture f;
  f.carve_and_add(5, 0.012, 0.003);
  const SampleLayout& L = f.model.samples;
  ASSERT_EQ(f.model.slab_samples.size(), L.slot_count());
  for (size_t slot = 0; slot < L.slot_count(); ++slot) {
    const SlabSample& v = f.model.slab_samples[slot];
    const int32_t s = L.id(int32_t(slot / L.per_slab), int32_t(slot % L.per_slab));
    ASSERT_EQ(v.delta, f.model.displacement[s]) << "slot " << slot;
    ASSERT_EQ(v.normal(), sample_normal(f.model, s)) << "slot " << slot << ": every slot of a sample holds its normal";
  }
}

// The slabs an edit flags dirty (what a renderer re-uploads, what snapshots copy before the
// write) are, by a scan of every slab's grid, every slab holding a sample or texel the edit changed
// (its displacement, normal or force-shading normal, colour), and no other.
TEST(EditToolsTest, DirtySlabsAreTheSlabsHoldingWhatChanged) {
  Fixture f;
  const test::ModelState before(f.model);
  const std::vector<SlabSample> slots_before = f.model.slab_samples;
  clear_dirty(f.scratch);
  f.carve_and_add(29, 0.012, 0.003);
  Contact c;
  Vec3 hip;
  ASSERT_TRUE(f.contact_at(5000, 0.003, c, hip));
  ASSERT_GT(paint(f.model, f.scratch, c, 0.02 * f.diag, Vec3f(0, 1, 0), 1.0).changed, 10);
  std::vector<uint8_t> flagged(f.model.slab_count(), 0);
  for (int32_t k = 0; k < f.scratch.dirty_count; ++k) flagged[f.scratch.dirty_list[k]] = 1;
  const test::ModelState after(f.model);
  const SampleLayout &S = f.model.samples, &T = f.model.texels;
  int changed_slabs = 0;
  for (int slab = 0; slab < f.model.slab_count(); ++slab) {
    bool changed = false;
    for (int k = 0; k < S.per_slab && !changed; ++k) {
      const int32_t id = S.id(slab, k);
      const size_t slot = size_t(slab) * S.per_slab + k;
      changed = before.displacement[id] != after.displacement[id] || before.normals[id] != after.normals[id] ||
                std::memcmp(slots_before[slot].h, f.model.slab_samples[slot].h, sizeof(SlabSample::h)) != 0;
    }
    for (int k = 0; k < T.per_slab && !changed; ++k) {
      const int32_t id = T.id(slab, k);
      changed = before.colour[id] != after.colour[id];
    }
    changed_slabs += changed;
    ASSERT_EQ(bool(flagged[slab]), changed)
        << "slab " << slab << (changed ? " changed but is not" : " is") << " flagged dirty";
  }
  EXPECT_GT(changed_slabs, 20);
}

TEST(EditToolsTest, PaintBlendsWithThePapersIntensity) {
  Fixture f;
  Contact c;
  Vec3 hip;
  ASSERT_TRUE(f.contact_at(2000, 0.003, c, hip));
  const std::vector<Srgb8> before = f.model.colour.codes();
  const double r = 0.02 * f.diag, pressure = 0.7;
  const Vec3f brush(1, 0, 0);
  const EditResult res = paint(f.model, f.scratch, c, r, brush, pressure);
  EXPECT_GT(res.changed, 10);
  // Texels on displacement samples (every m-th texel) sit at the sample's surface point, an
  // independent position: check c_new = k·brush + (1-k)·c_old with k = p·(1 - d/r).
  int checked = 0;
  test::for_each_sample_texel(f.model, [&](int sample, int texel) {
    const double d = (sample_position(f.model, sample) - c.surface_point).norm();
    const float k = d < r ? float(pressure * (1 - d / r)) : 0.0f;
    // Rounded once to 8-bit sRGB: within half a code step, plus the float error of k.
    const Vec3f expected = k * brush + (1 - k) * decode_srgb8(before[texel]);
    const Srgb8 got = f.model.colour[texel];
    const int code[3] = {got.r, got.g, got.b};
    for (int q = 0; q < 3; ++q)
      ASSERT_LE(std::abs(code[q] - test::srgb_code(expected[q])), 0.55) << "texel " << texel << " channel " << q;
    checked += k > 0;
  });
  EXPECT_GT(checked, 5);
  EXPECT_DOUBLE_EQ(paint_pressure(0.5, 1.0, 2.0), 0.0);  // dead zone
  EXPECT_DOUBLE_EQ(paint_pressure(1.5, 1.0, 2.0), 0.5);
  EXPECT_DOUBLE_EQ(paint_pressure(9.0, 1.0, 2.0), 1.0);
}

TEST(EditToolsTest, EditedModelRoundTripsBitForBit) {
  Fixture f;
  Contact c;
  Vec3 hip;
  ASSERT_TRUE(f.contact_at(3000, 0.005, c, hip));
  carve(f.model, f.scratch, c, hip, 0.01 * f.diag, 0.0);
  paint(f.model, f.scratch, c, 0.02 * f.diag, Vec3f(0, 0, 1), 1.0);
  const std::string path = (std::filesystem::temp_directory_path() / "hdm_edit_roundtrip.hdm").string();
  save_model(f.model, path);
  const SlabModel back = load_model(path);
  std::filesystem::remove(path);
  ASSERT_EQ(back.displacement.size(), f.model.displacement.size());
  EXPECT_EQ(0, std::memcmp(back.displacement.data(), f.model.displacement.data(),
                           back.displacement.size() * sizeof(Unorm16)));
  EXPECT_TRUE(back.colour == f.model.colour);
  EXPECT_EQ(back.inner, f.model.inner);
  EXPECT_EQ(back.outer, f.model.outer);
  EXPECT_EQ(back.slabs, f.model.slabs);
}
