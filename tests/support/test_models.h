// SPDX-License-Identifier: MIT
#pragma once
// Shared fixtures: the real models extracted at set-up (data/meshes), baked once per test process,
// and analytic shapes.

#include <hdm/mesh/triangle_mesh.h>
#include <hdm/slab/slab_model.h>

#include <string>
#include <utility>
#include <vector>

namespace hdm::test {

/// The values the codes of a 16-bit field (Unorm16, Half16) stand for: two such arrays compare
/// equal exactly when their codes do (each code reads back as one float).
template <class Field>
std::vector<float> values(const std::vector<Field>& field) {
  return {field.begin(), field.end()};
}
/// values() of a SampleField: one value per sample, however the field stores them.
template <class Code>
std::vector<float> values(const SampleField<Code>& field) {
  return {field.begin(), field.end()};
}

/// Path of a model extracted by scripts/setup.sh (fails the test if missing).
std::string data_path(const std::string& name);

/// bunny00.off from Debian's libcgal-demo, read once.
const TriangleMesh& bunny();

/// The bunny baked once per process with @p slabs and @p grid (cached per pair).
const SlabModel& baked_bunny(int slabs, int grid);

/// Icosphere of radius @p radius centred at @p centre with @p subdivisions 1-to-4 splits,
/// counter-clockwise from outside.
TriangleMesh icosphere(int subdivisions, double radius, const Vec3& centre = Vec3::Zero());

/// Appends @p part to @p to as a component of its own (its vertex indices shifted); returns the
/// range of its faces in @p to, [first, last).
std::pair<size_t, size_t> append(TriangleMesh& to, const TriangleMesh& part);

/// The volume @p m encloses, by the divergence theorem (positive when it faces outward).
double signed_volume(const TriangleMesh& m);

/// A disk of radius 1 and height 0.1 as a CAD exporter writes it: the rim a ring of @p n quads,
/// each cap a fan of needles from one rim vertex; closed, counter-clockwise from outside.
TriangleMesh fan_capped_disk(int n);

/// icosphere(subdivisions, 1) with a crumple at vertex 0: its ring shrunk to @p size around it and
/// turned by @p twist_deg about its normal, so the faces from the ring to the next ring twist over
/// each other (as where a scanned surface crumples) and the ring's vertices have empty dual cones.
TriangleMesh crumpled_icosphere(int subdivisions, double size, double twist_deg);

/// Vertices whose incident face normals no direction sees all with a dot product above
/// @p margin, by brute force over 40,000 directions (a Fibonacci sphere, about 1 degree apart),
/// then a local refinement around the best. Degenerate faces are left out.
int count_empty_cones(const TriangleMesh& mesh, double margin = 0.0);

/// X(w, α) = Σ wV·(V0 + α·(V1 − V0)) from the stored corners of slab @p slab (an independent
/// evaluation of the slab map, not through SlabGeometry). @p w = (wR, wS, wT).
Vec3 point_from_corners(const SlabModel& m, int slab, const Vec3& w, double alpha);

}  // namespace hdm::test
