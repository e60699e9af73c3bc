// SPDX-License-Identifier: MIT
#include <hdm/query/slab_locator.h>

#include <algorithm>
#include <cmath>

namespace hdm {

SlabLocator::SlabLocator(const SlabModel& model)
    : geometry_(&model.geometry), inner_(&model.inner), inner_faces_(&model.slabs) {
  const int S = model.slab_count();
  std::vector<Box> boxes(S);
  std::vector<Sides> sides(S);
  for (int s = 0; s < S; ++s) {
    const Aabb b = slab_bounds(model, s);
    for (int a = 0; a < 3; ++a) {  // round outward so the float box contains the double box
      boxes[s].lo[a] = std::nextafter(static_cast<float>(b.min[a]), -INFINITY);
      boxes[s].hi[a] = std::nextafter(static_cast<float>(b.max[a]), INFINITY);
    }
  }
  for (int s = 0; s < S; ++s) {
    const Tri& t = model.slabs[s];
    Vec3 corner[6];
    double M = 0;
    for (int k = 0; k < 3; ++k) {
      corner[k] = model.inner[t[k]], corner[k + 3] = model.outer[t[k]];
      M = std::max({M, corner[k].cwiseAbs().maxCoeff(), corner[k + 3].cwiseAbs().maxCoeff()});
    }
    Vec3 centroid = Vec3::Zero();
    for (const Vec3& c : corner) centroid += c / 6;
    M += slab_bounds(model, s).diagonal();
    for (int e = 0; e < 3; ++e) {  // edge RS, ST, TR: the plane through the edge and the mean ray
      const int v = e, w = (e + 1) % 3;
      const Vec3 along = 0.5 * (corner[w] - corner[v] + corner[w + 3] - corner[v + 3]);
      const Vec3 up = 0.5 * (corner[v + 3] - corner[v] + corner[w + 3] - corner[w]);
      Vec3 n = along.cross(up);
      const double len = n.norm();
      Sides& sd = sides[s];
      if (!(len > 0)) {  // degenerate: a plane that rejects nothing
        sd.n[e][0] = sd.n[e][1] = sd.n[e][2] = 0, sd.d[e] = INFINITY;
        continue;
      }
      n /= len;
      if (n.dot(centroid - 0.5 * (corner[v] + corner[w])) > 0) n = -n;  // outward
      const Vec3f nf = n.cast<float>();
      double d = -INFINITY;
      for (const Vec3& c : corner) d = std::max(d, nf.cast<double>().dot(c));
      // Margin: float rounding of n·x (|x| <= M) and the inside test's 1e-9 barycentric tolerance.
      for (int a = 0; a < 3; ++a) sd.n[e][a] = nf[a];
      sd.d[e] = std::nextafter(static_cast<float>(d + 1e-5 * M), INFINITY);
    }
  }
  filters_.resize(S);
  for (int s = 0; s < S; ++s) filters_[s] = {boxes[s], sides[s]};
  build_grid();
  build_occupancy(model);
  classify_cells();
  edge_ = model.edge_neighbour;

  // Neighbourhood: edge neighbours first (most likely next slab), then the rest of the corner rings.
  ring_offsets_.assign(S + 1, 0);
  std::vector<int32_t> tmp;
  for (int s = 0; s < S; ++s) {
    tmp.clear();
    for (int32_t nb : model.edge_neighbour[s])
      if (nb >= 0) tmp.push_back(nb);
    for (int32_t v : model.slabs[s])
      model.samples.for_each_vertex_slab(v, [&](int32_t t) {
        if (t != s && std::find(tmp.begin(), tmp.end(), t) == tmp.end()) tmp.push_back(t);
      });
    ring_.insert(ring_.end(), tmp.begin(), tmp.end());
    ring_offsets_[s + 1] = static_cast<int32_t>(ring_.size());
  }
  ring_blocks_ = pack_lists(ring_offsets_, ring_);
}

SlabLocator::BoxLists SlabLocator::pack_lists(const std::vector<int32_t>& offsets,
                                              const std::vector<int32_t>& slabs) const {
  BoxLists out;
  const size_t lists = offsets.size() - 1;
  out.offsets.assign(lists + 1, 0);
  for (size_t k = 0; k < lists; ++k) out.offsets[k + 1] = out.offsets[k] + (offsets[k + 1] - offsets[k] + 3) / 4;
  BoxBlock empty;
  for (int a = 0; a < 3; ++a)
    for (int i = 0; i < 4; ++i) empty.lo[a][i] = INFINITY, empty.hi[a][i] = -INFINITY;
  for (int i = 0; i < 4; ++i) empty.slab[i] = -1;
  out.blocks.assign(out.offsets[lists], empty);
  for (size_t k = 0; k < lists; ++k)
    for (int32_t e = offsets[k]; e < offsets[k + 1]; ++e) {
      const int j = e - offsets[k];
      BoxBlock& b = out.blocks[out.offsets[k] + j / 4];
      const Box& box = filters_[slabs[e]].box;
      for (int a = 0; a < 3; ++a) b.lo[a][j % 4] = box.lo[a], b.hi[a][j % 4] = box.hi[a];
      b.slab[j % 4] = slabs[e];
    }
  return out;
}

int SlabLocator::scan(const BoxBlock* b, const BoxBlock* e, const Vec3& p, float x, float y, float z, int32_t skip,
                      AlphaSolver solver, double guess, SlabCoordinates& c) const noexcept {
  const auto& g = *geometry_;
  int edge;
  for (; b != e; ++b)
    for (unsigned m = b->contains(x, y, z); m != 0; m &= m - 1) {
      const int32_t s = b->slab[__builtin_ctz(m)];
      if (s != skip && filters_[s].sides.may_contain(x, y, z) && locate_in_slab(g[s], p, solver, guess, c, edge))
        return s;
    }
  return -1;
}

void SlabLocator::build_grid() {
  const int S = static_cast<int>(filters_.size());
  if (S == 0) return;
  // Extent of all boxes and the median largest box side h: cells h/2 wide, capped at 32 cells per
  // slab. At 10^5 slabs (bunny, n = 16) a cell then lists ~14 boxes where the query looks, against
  // ~37 for cells h wide (global query ~650 vs ~900 ns), for ~930 instead of ~450 bytes per slab.
  std::vector<float> side(S);
  for (int a = 0; a < 3; ++a) grid_lo_[a] = INFINITY, grid_hi_[a] = -INFINITY;
  for (int s = 0; s < S; ++s) {
    const Box& b = filters_[s].box;
    float m = 0;
    for (int a = 0; a < 3; ++a) {
      grid_lo_[a] = std::min(grid_lo_[a], b.lo[a]), grid_hi_[a] = std::max(grid_hi_[a], b.hi[a]);
      m = std::max(m, b.hi[a] - b.lo[a]);
    }
    side[s] = m;
  }
  std::nth_element(side.begin(), side.begin() + S / 2, side.end());
  double h = std::max(static_cast<double>(side[S / 2]), 1e-30) * 0.5;
  auto cells_for = [&](double width) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil((grid_hi_[a] - grid_lo_[a]) / width));
    return cells;
  };
  const double cells = cells_for(h);
  if (cells > 32.0 * S) h *= std::cbrt(cells / (32.0 * S));
  // A flat or needle-like extent keeps too many cells after the cube-root step (one long slab
  // beside small ones asked for 10^8 cells and 2.7 GB): widen until there are at most 64 per slab.
  while (cells_for(h) > 64.0 * S) h *= 2;
  size_t total = 1;
  for (int a = 0; a < 3; ++a) {
    grid_dim_[a] = std::max(1, static_cast<int>(std::ceil((grid_hi_[a] - grid_lo_[a]) / h)));
    grid_inv_[a] = static_cast<float>(grid_dim_[a] / std::max(double(grid_hi_[a] - grid_lo_[a]), 1e-30));
    total *= static_cast<size_t>(grid_dim_[a]);
  }
  // Two passes over every slab's cell range: count, then fill.
  std::vector<int32_t> offsets(total + 1, 0);
  auto for_cells = [&](int s, auto&& f) {
    const Box& b = filters_[s].box;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = cell_coord(b.lo[a], a), hi[a] = cell_coord(b.hi[a], a);
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) f((static_cast<size_t>(z) * grid_dim_[1] + y) * grid_dim_[0] + x);
  };
  for (int s = 0; s < S; ++s) for_cells(s, [&](size_t k) { ++offsets[k + 1]; });
  for (size_t k = 0; k < total; ++k) offsets[k + 1] += offsets[k];
  std::vector<int32_t> listed(offsets[total]);
  std::vector<int32_t> fill(offsets.begin(), offsets.end() - 1);
  for (int s = 0; s < S; ++s) for_cells(s, [&](size_t k) { listed[fill[k]++] = s; });
  grid_ = pack_lists(offsets, listed);
}

int SlabLocator::find_grid(const Vec3& p, AlphaSolver solver, double guess, SlabCoordinates& c) const noexcept {
  const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
  size_t k;
  uint64_t bit;
  // Outside the union of the (float) boxes, or in a sub-cell no slab reaches: no slab holds p.
  if (!cell_of(x, y, z, k, bit) || !(occupied_[k] & bit)) return -1;
  return scan_cell(k, p, x, y, z, solver, guess, c);
}

namespace {

// Bounding planes n·x <= d of the slab: the support planes of its six corners along the normals
// of its inner and outer faces, both ways (any direction gives a valid bound; these four are the
// tight ones for a thin slab), with the margin of the side planes.
void face_planes(const SlabModel& model, int s, Vec3 n[4], double d[4]) noexcept {
  const Tri& t = model.slabs[s];
  Vec3 corner[6];
  double M = slab_bounds(model, s).diagonal();
  for (int k = 0; k < 3; ++k) {
    corner[k] = model.inner[t[k]], corner[k + 3] = model.outer[t[k]];
    M = std::max({M, corner[k].cwiseAbs().maxCoeff(), corner[k + 3].cwiseAbs().maxCoeff()});
  }
  for (int f = 0; f < 2; ++f) {
    const Vec3* v = corner + 3 * f;
    Vec3 fn = (v[1] - v[0]).cross(v[2] - v[0]);
    const double len = fn.norm();
    fn = len > 0 ? Vec3(fn / len) : Vec3::Zero();
    for (int sign = 0; sign < 2; ++sign) {
      Vec3& nn = n[2 * f + sign];
      nn = sign ? Vec3(-fn) : fn;
      double m = -INFINITY;
      for (const Vec3& c : corner) m = std::max(m, nn.dot(c));
      d[2 * f + sign] = len > 0 ? m + 1e-5 * M : INFINITY;
    }
  }
}

}  // namespace

void SlabLocator::build_occupancy(const SlabModel& model) {
  occupied_.assign(grid_.offsets.empty() ? 0 : grid_.offsets.size() - 1, 0);
  double w[3], margin[3];
  for (int a = 0; a < 3; ++a) {
    w[a] = 0.25 / grid_inv_[a];  // sub-cell width
    margin[a] = 0.01 * w[a];     // far above the float rounding of the point's cell coordinate
  }
  for (int s = 0; s < static_cast<int>(filters_.size()); ++s) {
    const Filter& f = filters_[s];
    Vec3 n[7];
    double d[7];
    face_planes(model, s, n, d);
    for (int e = 0; e < 3; ++e) n[4 + e] = Vec3f(f.sides.n[e]).cast<double>(), d[4 + e] = f.sides.d[e];
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = cell_coord(f.box.lo[a], a), hi[a] = cell_coord(f.box.hi[a], a);
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          const int cell[3] = {x, y, z};
          // Per axis, the sub-cells (grown by the margin) that meet the slab's box, and their bounds.
          int j0[3], j1[3];
          double s0[3][4], s1[3][4];
          for (int a = 0; a < 3; ++a) {
            j0[a] = 4, j1[a] = -1;
            for (int j = 0; j < 4; ++j) {
              s0[a][j] = grid_lo_[a] + (4 * cell[a] + j) * w[a] - margin[a];
              s1[a][j] = grid_lo_[a] + (4 * cell[a] + j + 1) * w[a] + margin[a];
              if (s1[a][j] >= f.box.lo[a] && s0[a][j] <= f.box.hi[a]) j0[a] = std::min(j0[a], j), j1[a] = j;
            }
          }
          uint64_t bits = 0;
          for (int sz = j0[2]; sz <= j1[2]; ++sz)
            for (int sy = j0[1]; sy <= j1[1]; ++sy)
              for (int sx = j0[0]; sx <= j1[0]; ++sx) {
                const Vec3 lo3(s0[0][sx], s0[1][sy], s0[2][sz]), hi3(s1[0][sx], s1[1][sy], s1[2][sz]);
                const Vec3 centre = 0.5 * (lo3 + hi3), half = 0.5 * (hi3 - lo3);
                bool meets = true;  // separated when the sub-cell's lowest n·x is above d
                for (int k = 0; k < 7 && meets; ++k) meets = n[k].dot(centre) - n[k].cwiseAbs().dot(half) <= d[k];
                if (meets) bits |= uint64_t{1} << ((sz * 4 + sy) * 4 + sx);
              }
          occupied_[(static_cast<size_t>(z) * grid_dim_[1] + y) * grid_dim_[0] + x] |= bits;
        }
  }
}

namespace {

// Sign of the 2D edge function of q against the edge u -> v in the (y, z) plane, with q perturbed
// by (ε, ε²) so that it is never zero for distinct u, v (simulation of simplicity): the edge is
// evaluated in one canonical vertex order, so two faces sharing it see exactly opposite signs and
// a ray through the edge or a vertex crosses one face of a closed shell, not zero or two.
int edge_sign(const Vec3& u, const Vec3& v, double qy, double qz, double& value) noexcept {
  const bool swap = u.y() > v.y() || (u.y() == v.y() && u.z() > v.z());
  const Vec3& a = swap ? v : u;
  const Vec3& b = swap ? u : v;
  double e = (b.y() - a.y()) * (qz - a.z()) - (b.z() - a.z()) * (qy - a.y());
  int s = e > 0 ? 1 : e < 0 ? -1 : 0;
  if (s == 0) s = (b.z() - a.z()) < 0 ? 1 : (b.z() - a.z()) > 0 ? -1 : (b.y() - a.y()) > 0 ? 1 : -1;
  if (swap) e = -e, s = -s;
  value = e;
  return s;
}

}  // namespace

int SlabLocator::winding_along_x(const Vec3& p, bool stop_at_classified) const noexcept {
  const float y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
  const size_t row = (static_cast<size_t>(cell_coord(z, 2)) * grid_dim_[1] + cell_coord(y, 1)) * grid_dim_[0];
  int winding = 0;
  for (int i = cell_coord(static_cast<float>(p.x()), 0); i < grid_dim_[0]; ++i) {
    const size_t k = row + i;
    if (stop_at_classified && cell_winding_[k] != kMixed) return winding + cell_winding_[k];
    for (int32_t e = grid_.offsets[k]; e < grid_.offsets[k + 1]; ++e)
      for (int l = 0; l < 4; ++l) {
        const BoxBlock& gb = grid_.blocks[e];
        if (!(y >= gb.lo[1][l] && y <= gb.hi[1][l] && z >= gb.lo[2][l] && z <= gb.hi[2][l])) continue;
        const Tri& t = (*inner_faces_)[gb.slab[l]];
        const Vec3 &a = (*inner_)[t[0]], &b = (*inner_)[t[1]], &c = (*inner_)[t[2]];
        double wa, wb, wc;  // edge functions opposite a, b, c: barycentric weights of the hit
        const int sa = edge_sign(b, c, p.y(), p.z(), wa), sb = edge_sign(c, a, p.y(), p.z(), wb),
                  sc = edge_sign(a, b, p.y(), p.z(), wc);
        if (sa != sb || sb != sc) continue;  // the ray misses the face
        const double sum = wa + wb + wc;     // twice the signed projected area: 0 for a face parallel to x
        if (sum == 0) continue;
        // Clamped to the face's x range: on a face almost parallel to x the quotient may round
        // outside it, and then outside the cells that list the face.
        const double hx = std::clamp((wa * a.x() + wb * b.x() + wc * c.x()) / sum, std::min({a.x(), b.x(), c.x()}),
                                     std::max({a.x(), b.x(), c.x()}));
        // Each crossing is counted in the one cell its x falls in (the function that listed the
        // face's box), so a face listed in several cells of the row counts once.
        if (!(hx > p.x()) || cell_coord(static_cast<float>(hx), 0) != i) continue;
        winding += sa;  // sa > 0: the face's normal has n.x > 0, the ray leaves through its front
      }
  }
  return winding;
}

void SlabLocator::classify_cells() {
  const size_t total = grid_.offsets.empty() ? 0 : grid_.offsets.size() - 1;
  cell_winding_.assign(total, kMixed);
  if (total == 0) return;
  constexpr int8_t kUnset = INT8_MIN + 1;
  for (size_t k = 0; k < total; ++k)
    if (grid_.offsets[k] == grid_.offsets[k + 1]) cell_winding_[k] = kUnset;
  const int X = grid_dim_[0], Y = grid_dim_[1], Z = grid_dim_[2];
  std::vector<size_t> queue;
  // Flood fill of one component of empty cells (face neighbours) with winding w.
  auto fill = [&](size_t seed, int8_t w) {
    queue.assign(1, seed);
    cell_winding_[seed] = w;
    while (!queue.empty()) {
      const size_t k = queue.back();
      queue.pop_back();
      const int x = int(k % X), y = int(k / X % Y), z = int(k / (size_t(X) * Y));
      const int nb[6][3] = {{x - 1, y, z}, {x + 1, y, z}, {x, y - 1, z}, {x, y + 1, z}, {x, y, z - 1}, {x, y, z + 1}};
      for (const auto& n : nb) {
        if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[0] >= X || n[1] >= Y || n[2] >= Z) continue;
        const size_t m = (size_t(n[2]) * Y + n[1]) * X + n[0];
        if (cell_winding_[m] == kUnset) cell_winding_[m] = w, queue.push_back(m);
      }
    }
  };
  // Empty cells on the grid's border touch the outside of every box, so no face separates them
  // from infinity: winding 0, and so is every empty cell connected to them.
  for (int z = 0; z < Z; ++z)
    for (int y = 0; y < Y; ++y)
      for (int x = 0; x < X; ++x) {
        if (x != 0 && y != 0 && z != 0 && x != X - 1 && y != Y - 1 && z != Z - 1) continue;
        const size_t k = (size_t(z) * Y + y) * X + x;
        if (cell_winding_[k] == kUnset) fill(k, 0);
      }
  // Enclosed components (the body under the inner shell, pockets between parts): the winding of
  // one cell centre, counted along the ray to the grid's end, holds for the whole component.
  const double w[3] = {1.0 / grid_inv_[0], 1.0 / grid_inv_[1], 1.0 / grid_inv_[2]};
  for (size_t k = 0; k < total; ++k) {
    if (cell_winding_[k] != kUnset) continue;
    const int x = int(k % X), y = int(k / X % Y), z = int(k / (size_t(X) * Y));
    const Vec3 centre(grid_lo_[0] + (x + 0.5) * w[0], grid_lo_[1] + (y + 0.5) * w[1], grid_lo_[2] + (z + 0.5) * w[2]);
    const int n = winding_along_x(centre, false);
    fill(k, static_cast<int8_t>(std::clamp(n, -100, 100)));
  }
}

bool SlabLocator::inside_inner_shell(const Vec3& p) const noexcept {
  if (!p.allFinite() || cell_winding_.empty()) return false;
  const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
  if (!(x >= grid_lo_[0] && x <= grid_hi_[0] && y >= grid_lo_[1] && y <= grid_hi_[1] && z >= grid_lo_[2] &&
        z <= grid_hi_[2]))
    return false;  // outside every slab box, so outside the inner shell
  return winding_along_x(p, true) != 0;
}

size_t SlabLocator::memory_bytes() const noexcept {
  return cell_winding_.capacity() + filters_.capacity() * sizeof(Filter) + edge_.capacity() * sizeof(edge_[0]) +
         ring_offsets_.capacity() * sizeof(int32_t) + ring_.capacity() * sizeof(int32_t) + grid_.memory_bytes() +
         ring_blocks_.memory_bytes();
}

int SlabLocator::find(const Vec3& p, int hint, AlphaSolver solver, double guess, SlabCoordinates& c) const noexcept {
  if (!p.allFinite() || filters_.empty()) return -1;
  const auto& g = *geometry_;
  if (hint >= 0 && hint < static_cast<int>(g.size())) {
    const float x = static_cast<float>(p.x()), y = static_cast<float>(p.y()), z = static_cast<float>(p.z());
    int edge = -1;
    // The hint's float filter first: a point that left the hint's box (most points of a batch in
    // no slab, see inside_inner_shell) skips its cubic; the ring below is filtered the same way.
    const bool near_hint = candidate(hint, x, y, z);
    if (near_hint && locate_in_slab(g[hint], p, solver, guess, c, edge)) return hint;
    // The point left through `edge`: the slab across it is the likely one (docs/design.md#slab-locator).
    const int32_t across = near_hint && edge >= 0 ? edge_[hint][edge] : -1;
    if (across >= 0 && candidate(across, x, y, z) && locate_in_slab(g[across], p, solver, guess, c, edge))
      return across;
    size_t k;
    uint64_t bit;
    // A point in a sub-cell no slab reaches is in none: answered before the neighbourhood and the cell.
    if (!cell_of(x, y, z, k, bit) || !(occupied_[k] & bit)) return -1;
    const BoxBlock* b = ring_blocks_.blocks.data();
    const int s =
        scan(b + ring_blocks_.offsets[hint], b + ring_blocks_.offsets[hint + 1], p, x, y, z, across, solver, guess, c);
    return s >= 0 ? s : scan_cell(k, p, x, y, z, solver, guess, c);
  }
  return find_grid(p, solver, guess, c);
}

}  // namespace hdm
