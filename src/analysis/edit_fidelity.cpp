// SPDX-License-Identifier: MIT
#include <hdm/analysis/edit_fidelity.h>
#include <hdm/core/error.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace hdm {
namespace {

struct Sum {
  double sq = 0, max = 0;
  int64_t n = 0;
  Sum operator+(const Sum& o) const { return {sq + o.sq, std::max(max, o.max), n + o.n}; }
};

double segment_distance(const Vec3& p, const ToolCapsule& t, Vec3* closest = nullptr) {
  const Vec3 u = t.b - t.a;
  const double uu = u.squaredNorm();
  const double s = uu > 0 ? std::clamp((p - t.a).dot(u) / uu, 0.0, 1.0) : 0.0;
  const Vec3 c = t.a + s * u;
  if (closest) *closest = c;
  return (p - c).norm();
}

// The tools in a uniform grid of cells `cell` wide; a cell lists (in application order) every tool
// whose segment comes within radius + margin of it.
class ToolGrid {
 public:
  ToolGrid(const std::vector<ToolCapsule>& tools, double margin) : tools_(tools) {
    double reach = 0;
    for (const ToolCapsule& t : tools) reach = std::max(reach, t.radius + margin);
    cell_ = std::max(reach, 1e-12);
    for (size_t i = 0; i < tools.size(); ++i) {
      const ToolCapsule& t = tools[i];
      const Vec3 lo = t.a.cwiseMin(t.b).array() - (t.radius + margin),
                 hi = t.a.cwiseMax(t.b).array() + (t.radius + margin);
      const Eigen::Vector3i c0 = key(lo), c1 = key(hi);
      for (int x = c0.x(); x <= c1.x(); ++x)
        for (int y = c0.y(); y <= c1.y(); ++y)
          for (int z = c0.z(); z <= c1.z(); ++z) cells_[pack({x, y, z})].push_back(static_cast<int32_t>(i));
    }
  }
  const std::vector<int32_t>* near(const Vec3& p) const {
    const auto it = cells_.find(pack(key(p)));
    return it == cells_.end() ? nullptr : &it->second;
  }
  const std::vector<ToolCapsule>& tools() const { return tools_; }

 private:
  Eigen::Vector3i key(const Vec3& p) const {
    return {static_cast<int>(std::floor(p.x() / cell_)), static_cast<int>(std::floor(p.y() / cell_)),
            static_cast<int>(std::floor(p.z() / cell_))};
  }
  static uint64_t pack(const Eigen::Vector3i& k) {
    return (uint64_t(uint32_t(k.x()) & 0x1fffff) << 42) | (uint64_t(uint32_t(k.y()) & 0x1fffff) << 21) |
           uint64_t(uint32_t(k.z()) & 0x1fffff);
  }
  const std::vector<ToolCapsule>& tools_;
  double cell_ = 1;
  std::unordered_map<uint64_t, std::vector<int32_t>> cells_;
};

// The band and the composed signed distance of B (the input edited by the tools), at one point.
class BandField {
 public:
  BandField(const ExactMeshQuery& input, const std::vector<ToolCapsule>& tools, const ToolGrid& grid, double margin,
            double near_radius)
      : input_(input), tools_(tools), grid_(grid), margin_(margin), near_radius_(near_radius) {}

  const std::vector<int32_t>* near(const Vec3& p) const { return grid_.near(p); }
  const std::vector<ToolCapsule>& tools() const { return tools_; }
  // Within the measured band: some measured tool's segment is within radius + margin.
  bool in_band(const Vec3& p, const std::vector<int32_t>* list) const {
    if (!list) return false;
    for (int32_t i : *list)
      if (tools_[i].measured && segment_distance(p, tools_[i]) <= tools_[i].radius + margin_) return true;
    return false;
  }
  // Signed distance of B: the input's (negative inside), then the tools in order.
  double compose(double sd, const Vec3& p, const std::vector<int32_t>* list) const {
    if (list)
      for (int32_t i : *list) {
        const double c = segment_distance(p, tools_[i]) - tools_[i].radius;
        sd = tools_[i].add ? std::min(sd, c) : std::max(sd, -c);
      }
    return sd;
  }
  double input_sd(const Vec3& p) const {
    ClosestPoint c = input_.closest_point(p, near_radius_);
    if (c.face < 0) c = input_.closest_point(p);
    return input_.inside(p) ? -c.distance : c.distance;
  }

 private:
  const ExactMeshQuery& input_;
  const std::vector<ToolCapsule>& tools_;
  const ToolGrid& grid_;
  double margin_, near_radius_;
};

// Model → exact: B's distance at the displaced surface's vertices and face centroids in the band.
Sum model_to_exact(const BandField& field, const TriangleMesh& surface) {
  const int64_t ns = static_cast<int64_t>(surface.vertices.size()), nt = static_cast<int64_t>(surface.faces.size());
  auto model_point = [&](int64_t k) {
    if (k < ns) return surface.vertices[k];
    const Tri& t = surface.faces[k - ns];
    return Vec3((surface.vertices[t[0]] + surface.vertices[t[1]] + surface.vertices[t[2]]) / 3.0);
  };
  return tbb::parallel_reduce(
      tbb::blocked_range<int64_t>(0, ns + nt, 4096), Sum{},
      [&](const tbb::blocked_range<int64_t>& r, Sum s) {
        for (int64_t k = r.begin(); k < r.end(); ++k) {
          const Vec3 p = model_point(k);
          const std::vector<int32_t>* list = field.near(p);
          if (!field.in_band(p, list)) continue;
          const double d = std::abs(field.compose(field.input_sd(p), p, list));
          s.sq += d * d, s.max = std::max(s.max, d), ++s.n;
        }
        return s;
      },
      [](const Sum& a, const Sum& b) { return a + b; });
}

// (a) the input's vertices and face centroids (kept if in the band and no tool moved them).
std::vector<Vec3> input_candidates(const TriangleMesh& in) {
  std::vector<Vec3> candidates;
  for (const Vec3& v : in.vertices) candidates.push_back(v);
  for (const Tri& t : in.faces) candidates.push_back((in.vertices[t[0]] + in.vertices[t[1]] + in.vertices[t[2]]) / 3.0);
  return candidates;
}

// Samples of a whole sphere about `spacing` apart (where a chain of tools starts or ends).
void add_sphere(std::vector<Vec3>& candidates, const Vec3& c, double r, double spacing) {
  const int n = std::max(8, static_cast<int>(4 * std::numbers::pi * r * r / (spacing * spacing)));
  for (int i = 0; i < n; ++i) {  // Fibonacci sphere
    const double z = 1 - 2 * (i + 0.5) / n, rho = std::sqrt(std::max(0.0, 1 - z * z)), phi = i * 2.399963229728653;
    candidates.push_back(c + r * Vec3(rho * std::cos(phi), rho * std::sin(phi), z));
  }
}

// (b) the swept envelope: circles normal to the path every `spacing` of path length, and whole
// spheres where a chain of consecutive tools starts or ends.
void add_envelope(std::vector<Vec3>& candidates, const std::vector<ToolCapsule>& tools, double spacing, double diag) {
  double since = 0;  // path length since the last circle
  for (size_t i = 0; i < tools.size(); ++i) {
    const ToolCapsule& t = tools[i];
    if (!t.measured) continue;
    const bool starts = i == 0 || (tools[i - 1].b - t.a).norm() > 1e-9 * diag || tools[i - 1].radius != t.radius;
    const bool ends =
        i + 1 == tools.size() || (tools[i + 1].a - t.b).norm() > 1e-9 * diag || tools[i + 1].radius != t.radius;
    if (starts) add_sphere(candidates, t.a, t.radius, spacing), since = 0;
    const Vec3 u = t.b - t.a;
    const double len = u.norm();
    if (len > 0) {
      const Vec3 dir = u / len;
      const Vec3 e1 = (std::abs(dir.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(dir).normalized(),
                 e2 = dir.cross(e1);
      const int around = std::max(8, static_cast<int>(2 * std::numbers::pi * t.radius / spacing));
      double last = -1;
      for (double s = spacing - since; s <= len; s += spacing) {
        for (int k = 0; k < around; ++k) {
          const double a = 2 * std::numbers::pi * k / around;
          candidates.push_back(t.a + s * dir + t.radius * (std::cos(a) * e1 + std::sin(a) * e2));
        }
        last = s;
      }
      since = last >= 0 ? len - last : since + len;
    }
    if (ends) add_sphere(candidates, t.b, t.radius, spacing);
  }
}

// B's signed distance at envelope sample @p y after moving it onto the nearest tool's surface (the
// envelope sample is within rounding of it); false if it has no such tool or left the band.
bool envelope_sd(const BandField& field, const std::vector<int32_t>& list, Vec3& y, double& sd) {
  const std::vector<ToolCapsule>& tools = field.tools();
  double best = 1e300;
  Vec3 axis = Vec3::Zero();
  int32_t nearest = -1;
  for (int32_t i : list) {
    Vec3 c;
    const double d = segment_distance(y, tools[i], &c) - tools[i].radius;
    if (d < best) best = d, axis = c, nearest = i;
  }
  if (nearest < 0 || (y - axis).norm() <= 0) return false;
  y = axis + tools[nearest].radius * (y - axis).normalized();
  const std::vector<int32_t>* moved = field.near(y);
  if (!field.in_band(y, moved)) return false;
  sd = field.compose(field.input_sd(y), y, moved);
  return true;
}

// Exact → model: the reconstruction's distance at the candidates that lie on B's surface in the band
// (the first @p n_input are the input's, the rest the tools' envelope).
Sum exact_to_model(const BandField& field, const std::vector<Vec3>& candidates, size_t n_input,
                   const ExactMeshQuery& recon, double near_radius, double on_surface) {
  const int64_t nc = static_cast<int64_t>(candidates.size());
  return tbb::parallel_reduce(
      tbb::blocked_range<int64_t>(0, nc, 1024), Sum{},
      [&](const tbb::blocked_range<int64_t>& r, Sum s) {
        for (int64_t k = r.begin(); k < r.end(); ++k) {
          Vec3 y = candidates[k];
          const std::vector<int32_t>* list = field.near(y);
          if (!list) continue;
          double sd;
          if (static_cast<size_t>(k) < n_input) {
            if (!field.in_band(y, list)) continue;
            sd = field.compose(0.0, y, list);  // on the input: stays on B's surface unless a tool moved it
          } else if (!envelope_sd(field, *list, y, sd)) {
            continue;
          }
          if (std::abs(sd) > on_surface) continue;  // not on B's surface (inside another tool, or in the air)
          ClosestPoint c = recon.closest_point(y, near_radius);
          if (c.face < 0) c = recon.closest_point(y);
          s.sq += c.distance * c.distance, s.max = std::max(s.max, c.distance), ++s.n;
        }
        return s;
      },
      [](const Sum& a, const Sum& b) { return a + b; });
}

}  // namespace

EditFidelity measure_edit_fidelity(const SlabModel& model, const ExactMeshQuery& input,
                                   const std::vector<ToolCapsule>& tools, double margin, double spacing) {
  if (tools.empty()) throw InvalidInput("measure_edit_fidelity: no tools");
  if (!(margin > 0) || !(spacing > 0)) throw InvalidInput("measure_edit_fidelity: margin and spacing must be > 0");
  const TriangleMesh& in = input.mesh();
  EditFidelity f;
  f.diagonal = bounds(in).diagonal();
  const double diag = f.diagonal, near_radius = 1e-2 * diag, on_surface = 1e-7 * diag;
  const ToolGrid grid(tools, margin);
  const BandField field(input, tools, grid, margin, near_radius);

  TriangleMesh surface;
  displaced_surface(model, surface.vertices, surface.faces);
  const Sum fwd = model_to_exact(field, surface);

  // Exact → model: points of B's surface in the band.
  std::vector<Vec3> candidates = input_candidates(in);
  const size_t n_input = candidates.size();
  add_envelope(candidates, tools, spacing, diag);
  const ExactMeshQuery recon(surface, BvhQuality::compact);
  const Sum back = exact_to_model(field, candidates, n_input, recon, near_radius, on_surface);

  f.points = fwd.n;
  f.back_points = back.n;
  f.rms_pct = fwd.n ? 100 * std::sqrt(fwd.sq / fwd.n) / diag : 0;
  f.max_pct = 100 * fwd.max / diag;
  f.rms_back_pct = back.n ? 100 * std::sqrt(back.sq / back.n) / diag : 0;
  f.max_back_pct = 100 * back.max / diag;
  return f;
}

}  // namespace hdm
