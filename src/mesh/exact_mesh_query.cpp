// SPDX-License-Identifier: MIT
#include <hdm/mesh/exact_mesh_query.h>
#include <hdm/core/error.h>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <unordered_map>
#include <utility>

namespace hdm {

struct ExactMeshQuery::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  double diagonal = 0;
  // Computed on the first inside(), behind() or closed(): a BVH used for distances only (the
  // reconstructed surface of measure_fidelity(), 25 M triangles at 10^5 slabs) never pays for the
  // edge sort (8 B per face corner) or, when open, the pseudonormals.
  std::once_flag sides_once;
  bool closed = true;
  // Open meshes only: angle-weighted vertex normals and edge normals (sum of the faces' unit
  // normals), the pseudonormals of Bærentzen & Aanæs 2005 that give the side of a point.
  std::vector<Vec3> vertex_normal;
  std::unordered_map<uint64_t, Vec3> edge_normal;
};

ExactMeshQuery::ExactMeshQuery(TriangleMesh mesh_in, BvhQuality quality, const char* device_config)
    : impl_(std::make_unique<Impl>()), mesh_(std::move(mesh_in)) {
  const TriangleMesh& mesh = mesh_;
  impl_->device = rtcNewDevice(device_config);
  if (!impl_->device) throw NumericalError("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene,
                          quality == BvhQuality::high ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
  // Robust (watertight) triangle tests: a bake ray through an input vertex or edge, which a coarse
  // mesh at the input's own resolution casts on purpose, must hit one of its faces.
  // The context filter lets segment_hits() collect every hit of a segment in one traversal.
  // Compact leaves (indices, not vertex copies) for BVHs of distance queries: a third less memory.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION |
                                     (quality == BvhQuality::compact ? RTC_SCENE_FLAG_COMPACT : RTC_SCENE_FLAG_NONE));
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), mesh.vertices.size()));
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) vb[3 * v + a] = static_cast<float>(mesh.vertices[v][a]);
  // Embree reads the faces in place (three int32 per face: the bits of UINT3 for valid ids), as
  // a copy would cost 12 B per face; mesh_ is never modified, and the object never moves.
  static_assert(sizeof(Tri) == 3 * sizeof(unsigned), "Tri must be three packed 32-bit ids");
  rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh_.faces.data(), 0, sizeof(Tri),
                             mesh_.faces.size());
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
  impl_->diagonal = bounds(mesh).diagonal();
}

const ExactMeshQuery::Impl& ExactMeshQuery::sides() const {
  std::call_once(impl_->sides_once, [this] {
    const TriangleMesh& mesh = mesh_;
    impl_->closed = analyze_topology(mesh).boundary_edges == 0;
    if (impl_->closed) return;
    const uint64_t nv = mesh.vertices.size();
    impl_->vertex_normal.assign(nv, Vec3::Zero());
    for (const Tri& t : mesh.faces) {
      const Vec3 n = (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
      if (!(n.norm() > 0)) continue;
      const Vec3 u = n.normalized();
      for (int k = 0; k < 3; ++k) {
        const Vec3 e1 = mesh.vertices[t[(k + 1) % 3]] - mesh.vertices[t[k]],
                   e2 = mesh.vertices[t[(k + 2) % 3]] - mesh.vertices[t[k]];
        impl_->vertex_normal[t[k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * u;
        const uint64_t a = uint64_t(t[k]), b = uint64_t(t[(k + 1) % 3]);
        // try_emplace with an explicit zero: operator[] would value-initialise an Eigen vector, which
        // leaves it uninitialised, and the side of a point would then change from run to run.
        impl_->edge_normal.try_emplace(std::min(a, b) * nv + std::max(a, b), Vec3::Zero()).first->second += u;
      }
    }
  });
  return *impl_;
}

bool ExactMeshQuery::closed() const { return sides().closed; }

namespace {
struct WithinState {
  const TriangleMesh* mesh;
  Vec3 p;
  double radius;
  std::vector<int32_t>* out;
};

bool within_callback(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<WithinState*>(args->userPtr);
  const Tri& f = st->mesh->faces[args->primID];
  const Vec3 q =
      closest_point_on_triangle(st->p, st->mesh->vertices[f[0]], st->mesh->vertices[f[1]], st->mesh->vertices[f[2]]);
  if ((q - st->p).norm() <= st->radius) st->out->push_back(static_cast<int32_t>(args->primID));
  return false;  // the query sphere never shrinks
}
}  // namespace

void ExactMeshQuery::faces_within(const Vec3& p, double radius, std::vector<int32_t>& faces) const {
  faces.clear();
  if (!p.allFinite() || !(radius >= 0)) return;
  WithinState st{&mesh_, p, radius, &faces};
  RTCPointQuery q;
  q.x = static_cast<float>(p.x());
  q.y = static_cast<float>(p.y());
  q.z = static_cast<float>(p.z());
  q.time = 0;
  q.radius = static_cast<float>(radius) * 1.0001f + 1e-30f;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(impl_->scene, &q, &ctx, within_callback, &st);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
}

ExactMeshQuery::~ExactMeshQuery() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) noexcept {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

namespace {

struct PointQueryState {
  const TriangleMesh* mesh;
  Vec3 p;
  ClosestPoint best;
};

bool point_query_callback(RTCPointQueryFunctionArguments* args) {
  auto* st = static_cast<PointQueryState*>(args->userPtr);
  const Tri& f = st->mesh->faces[args->primID];
  const Vec3 q =
      closest_point_on_triangle(st->p, st->mesh->vertices[f[0]], st->mesh->vertices[f[1]], st->mesh->vertices[f[2]]);
  const double d = (q - st->p).norm();
  // Equal distances (a point nearest a shared vertex or edge) go to the lower face id, whatever
  // order the traversal meets the faces in: the BVH, and with it that order, differ between
  // Embree's instruction sets and CPUs, and the bake follows the face it is given.
  const auto face = static_cast<int32_t>(args->primID);
  if (d < st->best.distance || (d == st->best.distance && face < st->best.face)) {
    st->best = {q, d, face};
    // Embree works in float: keep a small margin so the true closest triangle is not culled.
    args->query->radius = static_cast<float>(d) * 1.0001f + 1e-30f;
    return true;
  }
  return false;
}

RTCRayHit make_ray(const Vec3& o, const Vec3& d, float tnear, float tfar) {
  RTCRayHit rh{};
  rh.ray.org_x = static_cast<float>(o.x());
  rh.ray.org_y = static_cast<float>(o.y());
  rh.ray.org_z = static_cast<float>(o.z());
  rh.ray.dir_x = static_cast<float>(d.x());
  rh.ray.dir_y = static_cast<float>(d.y());
  rh.ray.dir_z = static_cast<float>(d.z());
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

}  // namespace

ClosestPoint ExactMeshQuery::closest_point(const Vec3& p) const {
  return closest_point(p, std::numeric_limits<double>::infinity());
}

ClosestPoint ExactMeshQuery::closest_point(const Vec3& p, double radius) const {
  // Only faces nearer than `radius` are accepted; the float sphere gets the callback's margin.
  PointQueryState st{&mesh_, p, {Vec3::Zero(), radius, -1}};
  RTCPointQuery q;
  q.x = static_cast<float>(p.x());
  q.y = static_cast<float>(p.y());
  q.z = static_cast<float>(p.z());
  q.time = 0;
  q.radius =
      std::isinf(radius) ? std::numeric_limits<float>::infinity() : static_cast<float>(radius) * 1.0001f + 1e-30f;
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(impl_->scene, &q, &ctx, point_query_callback, &st);
  return st.best;
}

namespace {

// Every candidate hit of one traversal, rejected so the traversal goes on (Embree's context filter).
struct AllHitsContext {
  RTCIntersectContext context;  // first member: Embree passes a pointer to it
  std::vector<std::pair<float, int32_t>>* hits;
};

// The parameter just past a hit at @p t: hits before it are at the same point of the segment
// (adjacent triangles met at their shared edge, coincident faces).
float past(float t) { return std::nextafter(t, 2.0f) + 1e-7f; }

void collect_hit(const RTCFilterFunctionNArguments* args) {
  if (!args->valid[0]) return;
  auto* c = reinterpret_cast<const AllHitsContext*>(args->context);
  c->hits->emplace_back(RTCRayN_tfar(args->ray, args->N, 0),
                        static_cast<int32_t>(RTCHitN_primID(args->hit, args->N, 0)));
  args->valid[0] = 0;
}

}  // namespace

// Every hit of the segment a -> b in one traversal, sorted by (t, face): a thread's own buffer,
// valid until its next call.
const std::vector<std::pair<float, int32_t>>& ExactMeshQuery::sorted_hits(const Vec3& a, const Vec3& b) const {
  thread_local std::vector<std::pair<float, int32_t>> raw;
  raw.clear();
  AllHitsContext c;
  rtcInitIntersectContext(&c.context);
  c.context.filter = collect_hit;
  c.hits = &raw;
  RTCRayHit rh = make_ray(a, b - a, 0.0f, 1.0f);
  rtcIntersect1(impl_->scene, &c.context, &rh);
  // Each hit's t again in double, from the face's plane: Embree's float t rounds differently
  // between its instruction sets, and the bake follows the last bits of t.
  const Vec3 d = b - a;
  for (auto& [t, face] : raw) {
    const Tri& f = mesh_.faces[face];
    const Vec3& v0 = mesh_.vertices[f[0]];
    const Vec3 n = (mesh_.vertices[f[1]] - v0).cross(mesh_.vertices[f[2]] - v0);
    const double along = n.dot(d);
    if (along != 0) t = static_cast<float>(std::clamp(n.dot(v0 - a) / along, 0.0, 1.0));
  }
  std::sort(raw.begin(), raw.end());
  return raw;
}

void ExactMeshQuery::segment_hits(const Vec3& a, const Vec3& b, std::vector<SegmentHit>& hits) const {
  hits.clear();
  // One traversal collects every hit; then the hits are read as successive nearest-hit queries
  // would, each from just past the last (a relative epsilon in t keeps adjacent triangles from
  // repeating), 1024 steps at most. A traversal per hit cost as many descents as hits: an edge of
  // a slab's boundary, cast against the shells of its neighbours, meets dozens of faces at its ends.
  float tnear = 0;
  int steps = 0;
  for (const auto& [t, face] : sorted_hits(a, b)) {
    if (!(t >= tnear)) continue;
    if (hits.empty() || hits.back().face != face) hits.push_back({t, face});
    tnear = past(t);
    if (++steps == 1024) break;
  }
}

SegmentHit ExactMeshQuery::first_hit(const Vec3& a, const Vec3& b) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = make_ray(a, b - a, 0.0f, 1.0f);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {1.0, -1};
  return {rh.ray.tfar, static_cast<int32_t>(rh.hit.primID)};
}

// The winding number along the segment a -> b of a closed mesh: the hits are read in order of t,
// and the faces met at one crossing (equal t within the same relative epsilon as segment_hits())
// count once, by the sign of their sum. A ray through an edge or a vertex of one surface meets
// every face there with the same sign (one crossing); coincident faces of opposite orientation
// (two parts stacked on a shared face plane, as CAD exports put them) add up to zero, as the
// winding number is zero just above both; a ray grazing a silhouette edge meets a front and a
// back face and does not cross. Reading one face per crossing, as successive nearest hits do,
// dropped one of two coincident faces and put the space above stacked parts inside them.
int ExactMeshQuery::winding_along(const Vec3& a, const Vec3& b) const {
  const std::vector<std::pair<float, int32_t>>& raw = sorted_hits(a, b);
  const Vec3 d = b - a;
  int winding = 0;
  for (size_t k = 0; k < raw.size();) {
    const float end = past(raw[k].first);
    int sum = 0;
    for (; k < raw.size() && raw[k].first < end; ++k) {
      const double s = face_normal(raw[k].second).dot(d);
      sum += s > 0 ? 1 : s < 0 ? -1 : 0;
    }
    winding += sum > 0 ? 1 : sum < 0 ? -1 : 0;
  }
  return winding;
}

bool ExactMeshQuery::inside(const Vec3& p) const {
  if (!p.allFinite()) return false;
  if (!sides().closed) return behind(p);
  static const Vec3 dirs[3] = {Vec3(0.5773, 0.5774, 0.5771).normalized(), Vec3(-0.3141, 0.8523, -0.4182).normalized(),
                               Vec3(0.7071, -0.1234, -0.6963).normalized()};
  const double far = 4.0 * std::max(impl_->diagonal, 1e-30) + (p - mesh_.vertices[0]).norm();
  int votes = 0;
  for (const Vec3& d : dirs) votes += winding_along(p, p + far * d) != 0;
  return votes >= 2;
}

bool ExactMeshQuery::behind(const Vec3& p) const {
  if (!p.allFinite()) return false;
  const Impl& sides = this->sides();
  if (sides.closed) return inside(p);  // the same answer for a closed mesh; no pseudonormals kept
  const ClosestPoint c = closest_point(p);
  if (c.face < 0) return false;
  const Tri& t = mesh_.faces[c.face];
  const Vec3* v[3] = {&mesh_.vertices[t[0]], &mesh_.vertices[t[1]], &mesh_.vertices[t[2]]};
  const double scale = std::max({(*v[1] - *v[0]).norm(), (*v[2] - *v[1]).norm(), (*v[0] - *v[2]).norm()});
  const double eps = 1e-9 * scale;
  Vec3 n = face_normal(c.face);
  {
    bool done = false;
    for (int k = 0; k < 3 && !done; ++k)
      if ((c.point - *v[k]).norm() <= eps) n = sides.vertex_normal[t[k]], done = true;
    for (int k = 0; k < 3 && !done; ++k) {
      const Vec3 e = *v[(k + 1) % 3] - *v[k];
      const double s = std::clamp((c.point - *v[k]).dot(e) / std::max(e.squaredNorm(), 1e-300), 0.0, 1.0);
      if ((c.point - (*v[k] + s * e)).norm() <= eps) {
        const uint64_t nv = mesh_.vertices.size(), a = uint64_t(t[k]), b = uint64_t(t[(k + 1) % 3]);
        n = sides.edge_normal.at(std::min(a, b) * nv + std::max(a, b));
        done = true;
      }
    }
  }
  return (p - c.point).dot(n) < 0;
}

Vec3 ExactMeshQuery::face_normal(int32_t f) const {
  const Tri& t = mesh_.faces[f];
  return (mesh_.vertices[t[1]] - mesh_.vertices[t[0]]).cross(mesh_.vertices[t[2]] - mesh_.vertices[t[0]]).normalized();
}

}  // namespace hdm
