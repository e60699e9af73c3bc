// SPDX-License-Identifier: MIT
// Which faces of a triangle soup cross another: candidate pairs from Embree's BVH-against-BVH
// collision (`rtcCollide`, in parallel) over the faces' boxes, each decided with CGAL's exact
// predicates, on the faces as indexed triangles. No halfedge mesh is built: converting a 12.6 M-
// triangle input to a CGAL::Surface_mesh (soup orientation, then one Euler::add_face per face) took
// longer than the crossing test itself.

#include "self_intersecting_faces.h"

#include <hdm/core/error.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

namespace hdm {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Pairs = std::vector<std::pair<int32_t, int32_t>>;

// x rounded to a float two steps outwards: the face's box holds it, and boxes of faces that only
// touch overlap by more than a point, whatever Embree's overlap test does at equality.
float down(double x) {
  const float f = static_cast<float>(x);
  return std::nextafter(double(f) > x ? std::nextafter(f, -INFINITY) : f, -INFINITY);
}
float up(double x) {
  const float f = static_cast<float>(x);
  return std::nextafter(double(f) < x ? std::nextafter(f, INFINITY) : f, INFINITY);
}

// Whether faces @p a and @p b cross, sharing a vertex or an edge not counting (the rule of CGAL's
// `Polygon_mesh_processing::self_intersections`, with "shared" read as the same vertex index): two
// faces with an edge in common cross when they are coplanar and lie on the same side of it; two
// with a vertex in common, when the edge opposite it in either meets the other; others, when the
// triangles meet.
bool cross(const TriangleMesh& m, const Tri& a, const Tri& b) {
  const auto point = [&](int32_t v) {
    const Vec3& p = m.vertices[v];
    return Point(p.x(), p.y(), p.z());
  };
  int shared = 0, ia = -1, ib = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) ++shared, ia = i, ib = j;
  if (shared >= 3) return true;  // the same triangle twice
  const Point a0 = point(a[0]), a1 = point(a[1]), a2 = point(a[2]);
  const Point b0 = point(b[0]), b1 = point(b[1]), b2 = point(b[2]);
  if (shared == 2) {
    // The vertex of each face off the shared edge (u, v).
    int oa = 0, ob = 0;
    while (a[oa] == b[0] || a[oa] == b[1] || a[oa] == b[2]) ++oa;
    while (b[ob] == a[0] || b[ob] == a[1] || b[ob] == a[2]) ++ob;
    const Point u = point(a[(oa + 1) % 3]), v = point(a[(oa + 2) % 3]), pa = point(a[oa]), pb = point(b[ob]);
    return CGAL::coplanar(u, v, pa, pb) && CGAL::coplanar_orientation(u, v, pa, pb) == CGAL::POSITIVE;
  }
  const Kernel::Triangle_3 ta(a0, a1, a2), tb(b0, b1, b2);
  if (shared == 1) {
    const Point sa0 = point(a[(ia + 1) % 3]), sa1 = point(a[(ia + 2) % 3]);
    const Point sb0 = point(b[(ib + 1) % 3]), sb1 = point(b[(ib + 2) % 3]);
    // Neighbours on a surface: each face's far edge lies strictly on one side of the other's plane
    // (two orientation tests each, where do_intersect() costs several times more).
    const auto off_plane = [](const Point& p, const Point& q, const Point& r, const Point& s, const Point& t) {
      const CGAL::Orientation o = CGAL::orientation(p, q, r, s);
      return o != CGAL::COPLANAR && o == CGAL::orientation(p, q, r, t);
    };
    if (off_plane(a0, a1, a2, sb0, sb1) && off_plane(b0, b1, b2, sa0, sa1)) return false;
    return CGAL::do_intersect(ta, Kernel::Segment_3(sb0, sb1)) || CGAL::do_intersect(tb, Kernel::Segment_3(sa0, sa1));
  }
  return CGAL::do_intersect(ta, tb);
}

}  // namespace

std::vector<std::pair<int32_t, int32_t>> mesh::detail::self_intersecting_pairs(const TriangleMesh& mesh) {
  Pairs out;
  // The faces with a box: all but those whose corners are collinear, which are reported paired with
  // themselves, as CGAL does.
  struct Scan {
    const TriangleMesh* mesh;
    std::vector<int32_t> faces;
    std::vector<RTCBounds> boxes;
    tbb::enumerable_thread_specific<Pairs> found;
  } scan{&mesh, {}, {}, {}};
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    const auto point = [&](int k) {
      const Vec3& p = mesh.vertices[t[k]];
      return Point(p.x(), p.y(), p.z());
    };
    if (CGAL::collinear(point(0), point(1), point(2)))
      out.emplace_back(static_cast<int32_t>(f), static_cast<int32_t>(f));
    else
      scan.faces.push_back(static_cast<int32_t>(f));
  }
  if (!scan.faces.empty()) {
    const std::unique_ptr<RTCDeviceTy, decltype(&rtcReleaseDevice)> device(rtcNewDevice(nullptr), rtcReleaseDevice);
    if (!device) throw NumericalError("self-intersection test: Embree could not start");
    const std::unique_ptr<RTCSceneTy, decltype(&rtcReleaseScene)> scene(rtcNewScene(device.get()), rtcReleaseScene);
    // Embree's Morton builder: 1.9 s less than its default build over 12.6 M boxes, for about the
    // same collision pass.
    rtcSetSceneBuildQuality(scene.get(), RTC_BUILD_QUALITY_LOW);
    RTCGeometry boxes = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryBuildQuality(boxes, RTC_BUILD_QUALITY_LOW);
    rtcSetGeometryUserPrimitiveCount(boxes, static_cast<unsigned>(scan.faces.size()));
    // The boxes first, in parallel: Embree's builder calls the bounds function per primitive and
    // per build pass.
    scan.boxes.resize(scan.faces.size());
    tbb::parallel_for(size_t(0), scan.faces.size(), [&](size_t i) {
      const Tri& t = mesh.faces[scan.faces[i]];
      const Vec3 &p = mesh.vertices[t[0]], &q = mesh.vertices[t[1]], &r = mesh.vertices[t[2]];
      const Vec3 lo = p.cwiseMin(q).cwiseMin(r), hi = p.cwiseMax(q).cwiseMax(r);
      scan.boxes[i] = {down(lo.x()), down(lo.y()), down(lo.z()), 0, up(hi.x()), up(hi.y()), up(hi.z()), 0};
    });
    rtcSetGeometryBoundsFunction(
        boxes,
        [](const RTCBoundsFunctionArguments* a) {
          *a->bounds_o = static_cast<const Scan*>(a->geometryUserPtr)->boxes[a->primID];
        },
        nullptr);
    rtcSetGeometryUserData(boxes, &scan);
    rtcCommitGeometry(boxes);
    rtcAttachGeometry(scene.get(), boxes);
    rtcReleaseGeometry(boxes);
    rtcCommitScene(scene.get());
    // Each overlapping pair comes twice, (a, b) and (b, a), from the threads Embree runs on (TBB).
    rtcCollide(
        scene.get(), scene.get(),
        [](void* user, RTCCollision* c, unsigned n) {
          Scan& s = *static_cast<Scan*>(user);
          Pairs& found = s.found.local();
          for (unsigned i = 0; i < n; ++i) {
            if (c[i].primID0 >= c[i].primID1) continue;
            const int32_t a = s.faces[c[i].primID0], b = s.faces[c[i].primID1];
            if (cross(*s.mesh, s.mesh->faces[a], s.mesh->faces[b])) found.emplace_back(a, b);
          }
        },
        &scan);
  }
  for (const Pairs& p : scan.found) out.insert(out.end(), p.begin(), p.end());
  for (auto& [a, b] : out)
    if (a > b) std::swap(a, b);
  std::sort(out.begin(), out.end());  // the same list whatever the threads did
  return out;
}

std::vector<char> mesh::detail::self_intersecting_faces(const TriangleMesh& mesh, int64_t* pairs_out) {
  const Pairs pairs = self_intersecting_pairs(mesh);
  std::vector<char> crossing(mesh.faces.size(), 0);
  for (const auto& [a, b] : pairs) crossing[a] = crossing[b] = 1;
  if (pairs_out) *pairs_out = static_cast<int64_t>(pairs.size());
  return crossing;
}

}  // namespace hdm
