// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// Exact queries on a triangle mesh with Embree: closest point, inside test and all hits along a
/// segment. This is the independent reference hdm is measured against
/// (docs/design.md#how-we-measure), and the ray caster of the bake. It never uses slab code.

#include <hdm/mesh/triangle_mesh.h>

#include <memory>
#include <utility>
#include <vector>

namespace hdm {

/// Closest point on a mesh.
struct ClosestPoint {
  Vec3 point = Vec3::Zero();  ///< closest point on the mesh [model units]
  double distance = 0;        ///< Euclidean distance to it [model units]
  int32_t face = -1;          ///< face that holds it
};

/// A ray hit.
struct SegmentHit {
  double t;      ///< parameter along the segment, 0 at its origin and 1 at its end
  int32_t face;  ///< face hit
};

/// How much time Embree spends on building the BVH (RTC_BUILD_QUALITY_*): `high` (spatial splits)
/// builds 2-3× slower than `medium` for 10-20% faster queries. `compact` builds as `medium`, with
/// Embree's compact leaves (`RTC_SCENE_FLAG_COMPACT`: vertex indices instead of vertex copies),
/// for a BVH of distance queries over a large mesh: the 25.6 M reconstructed triangles of a
/// 10^5-slab model take 0.9 GB less. Closest points are exact either way (recomputed in double);
/// where two triangles tie within rounding, the traversal order may pick the other one, so a
/// distance can differ in its tenth digit from `medium`'s. Segment hits may differ at grazing
/// angles, so the shell's overlap test keeps `medium`.
enum class BvhQuality { high, medium, compact };

/// Embree BVH over a triangle mesh (single precision inside Embree; the closest-point distance is
/// recomputed in double on the winning triangle).
///
/// Threading: all const queries may run concurrently from any number of threads.
class ExactMeshQuery {
 public:
  /// @brief Builds the BVH over @p mesh, which this object keeps (Embree shares its face array and
  /// holds a float copy of its vertices).
  /// @param mesh     the triangle mesh [model units]; taken by value: pass an rvalue (std::move) to
  ///                 hand a mesh over without a copy (a 25 M-triangle mesh is 0.6 GB); need not
  ///                 outlive this object.
  /// @param quality  `high` (the default) for many queries; `medium` when the build dominates (a
  ///                 BVH used for about one query per triangle: 5.1 M triangles build in ~2 s
  ///                 instead of ~6 s); `compact` for such a BVH of distance queries only (the
  ///                 reconstructed surface in measure_fidelity()).
  /// @param device_config  Embree's device configuration (rtcNewDevice()), for example
  ///                 "threads=1" or "isa=sse4.2"; null for Embree's own choices (every hardware
  ///                 thread, the widest instruction set the CPU has). Results do not depend on it.
  /// @throws NumericalError if Embree cannot create a device (or rejects @p device_config).
  /// @note O(#F log #F), parallel (Embree's TBB builder). The first inside(), behind() or closed()
  ///       call adds the mesh's topology (a sort of 3·#F edge keys) and, for an open mesh, its
  ///       pseudonormals, once (later calls, from any thread, wait for it); a BVH queried for
  ///       distances only never builds them.
  explicit ExactMeshQuery(TriangleMesh mesh, BvhQuality quality = BvhQuality::high,
                          const char* device_config = nullptr);
  ~ExactMeshQuery();
  ExactMeshQuery(const ExactMeshQuery&) = delete;
  ExactMeshQuery& operator=(const ExactMeshQuery&) = delete;

  /// @brief Exact closest point on the mesh to @p p (Embree point query with a shrinking radius
  /// and the point-triangle closest point of Ericson, Real-Time Collision Detection §5.1.5).
  /// Faces at equal distance (a point nearest a shared edge or vertex) give the lowest face id,
  /// whatever order the BVH's traversal meets them in: the result is the same with each of
  /// Embree's instruction sets.
  ClosestPoint closest_point(const Vec3& p) const;

  /// @brief The closest point on the mesh to @p p if it lies within @p radius of @p p (the same
  /// point as closest_point(p)), else face -1 and distance @p radius.
  ///
  /// The query starts with a sphere of that radius instead of an unbounded one, so Embree culls
  /// every BVH node farther away from the start: for points known to lie near the mesh (fidelity
  /// samples) this is several times faster than closest_point(p), which the caller uses as the
  /// fallback when face is -1.
  /// @param p       query point [model units].
  /// @param radius  query radius [model units], > 0.
  /// @note Thread-safe (const); O(log #F) for a radius of the order of the local triangle size.
  ClosestPoint closest_point(const Vec3& p, double radius) const;

  /// @brief Whether @p p is inside the material the mesh bounds.
  ///
  /// Closed mesh: the winding number along a ray (faces left through their front count +1,
  /// through their back -1) is not zero, the majority over three fixed skew directions (a ray
  /// grazing an edge cannot flip the answer). Faces met at one point of the ray count once, by the
  /// sign of their sum: an edge of one surface crosses once, and coincident faces of opposite
  /// orientation (parts stacked on a shared face plane) cancel. This is ray parity for a mesh that does not cross
  /// itself, and the union of the parts for one that does (a leg pushed into a body is inside
  /// once, not twice). Open mesh: behind() (the side of the surface; rays can leave through the
  /// openings, so parity means nothing there).
  /// @return false for a non-finite point.
  /// @note Thread-safe (const); three ray traversals, or one closest-point query.
  bool inside(const Vec3& p) const;

  /// @brief Whether @p p lies behind the surface: (p − c)·n < 0 for the closest point c and the
  /// angle-weighted pseudonormal n there (the face normal inside a face, the sum of the two face
  /// normals on an edge, the angle-weighted vertex normal at a vertex; Bærentzen & Aanæs, "Signed
  /// distance computation using the angle weighted pseudonormal", IEEE TVCG 2005). Exact for
  /// a closed mesh that does not cross itself, where it answers as inside() (no pseudonormals are
  /// kept for closed meshes); for an open one it is the side of the surface the point is on, as a
  /// one-sided surface (a sheet, a scan with a cut) is touched from its front.
  /// @pre the mesh is oriented as orient_outward() orients it (faces counter-clockwise from the front).
  bool behind(const Vec3& p) const;

  /// True when every edge is used by two faces (no boundary).
  bool closed() const;

  /// @brief The faces with a point within @p radius of @p p (exact point-triangle distance), in
  /// increasing id, each once; @p faces is cleared first. Sorted so that no caller depends on the
  /// BVH's traversal order, which differs between Embree's instruction sets.
  /// @note Thread-safe (const); O(log #F + found · log found).
  void faces_within(const Vec3& p, double radius, std::vector<int32_t>& faces) const;

  /// @brief Every hit of the segment a→b, sorted by t in [0,1]; @p hits is cleared first. Each
  /// t is computed in double from the face's plane (Embree only finds the faces, whose float t
  /// rounds differently between its instruction sets), so the hits are the same with each. Hits
  /// within 10⁻⁷ (in t) after the last one kept are skipped (adjacent faces met at an edge count
  /// once), and a face met again right after itself is listed once; at most 1024 steps.
  /// @note Thread-safe (const); one BVH traversal that collects every candidate (Embree's
  ///       context filter function), O(log #F + hits · log hits); allocates only when a thread
  ///       meets more hits than before.
  void segment_hits(const Vec3& a, const Vec3& b, std::vector<SegmentHit>& hits) const;

  /// @brief First hit of the segment a→b, t in [0,1], or face -1 when none.
  SegmentHit first_hit(const Vec3& a, const Vec3& b) const;

  /// Outward unit normal of face @p f (counter-clockwise from outside).
  Vec3 face_normal(int32_t f) const;

  /// The mesh queried.
  const TriangleMesh& mesh() const { return mesh_; }

 private:
  struct Impl;
  const Impl& sides() const;  // closedness and pseudonormals, computed once on first use
  const std::vector<std::pair<float, int32_t>>& sorted_hits(const Vec3& a, const Vec3& b) const;
  int winding_along(const Vec3& a, const Vec3& b) const;  // closed mesh: crossings of a -> b, signed
  std::unique_ptr<Impl> impl_;
  TriangleMesh mesh_;
};

/// @brief Closest point to @p p on triangle (@p a, @p b, @p c) (Ericson 2005, §5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) noexcept;

}  // namespace hdm
