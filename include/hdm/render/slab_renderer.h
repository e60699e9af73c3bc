// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// OpenGL drawing of a slab model's displaced surface with per-slab buffer ranges, so that an
/// editor re-uploads only the slabs it changed (paper §6: one display list per slab, rebuilt when
/// the haptic process flags the slab).

#include <hdm/core/types.h>

#include <memory>

namespace hdm {

struct SlabModel;
struct SlabView;
struct RenderCamera;

/// Draws the reconstructed surface of a SlabModel: one vertex per (slab, grid point) at
/// sample_position() with the sample's normal, the slab's n² grid triangles (triangle_grid.h
/// split), colour from a texture atlas (build_texture_atlas(), sRGB texels decoded to linear),
/// the under-layer's colour where the surface lies below its top (SlabModel::layer_displacement;
/// the boundary is the zero line of the interpolated depth, per fragment), two-light Lambert +
/// ambient shading and a Blinn-Phong highlight scaled by 1 − roughness (SlabModel::roughness);
/// output is sRGB-encoded.
///
/// GPU layout: one vertex buffer where slab s owns vertices [s·P, (s+1)·P) with
/// P = (n+1)(n+2)/2, one static index buffer, and one atlas texture where slab s owns its tile.
/// Edge and corner samples therefore exist once per slab that shares them: after an edit that
/// touches a shared sample, re-upload every slab holding it (SampleLayout::for_each_slot() gives
/// them).
///
/// Lights are fixed in view space (key light from the upper left, fill from the lower right), so
/// every view direction is lit alike.
/// @note Needs a current OpenGL 4.5 core context on the calling thread for its whole life:
///       construct, upload, draw and destroy with the same context current. Not copyable.
/// @see paper §6
class SlabRenderer {
 public:
  /// @brief Compiles the shaders and creates the (empty) GL objects.
  /// @throws RenderError if the shaders do not compile or OpenGL reports an error.
  SlabRenderer();
  /// Deletes the GL objects (the context that created them must be current).
  ~SlabRenderer();
  SlabRenderer(const SlabRenderer&) = delete;
  SlabRenderer& operator=(const SlabRenderer&) = delete;

  /// @brief (Re)creates the buffers and the atlas texture for @p model and uploads every slab.
  /// @pre rebuild_derived(model) has run since the last structural change.
  /// @throws InvalidInput if the model has no slabs or stale derived data; RenderError if the
  ///         atlas exceeds GL_MAX_TEXTURE_SIZE or OpenGL reports an error.
  /// @note O(#S·n² + #S·N²) with N = n·texel_density; allocates CPU staging memory of that size.
  void upload_all(const SlabModel& model);

  /// @brief Re-uploads the vertices (positions, normals) and the atlas tile (colours) of one slab
  /// with glBufferSubData / glTexSubImage2D; other slabs keep what they had.
  /// @param model  the model given to upload_all(), edited since.
  /// @param slab   slab id in [0, #S).
  /// @pre upload_all() ran with a model of the same slabs, grid_n and texel_density; positions
  ///      come from the model's displacements, normals from `model.slab_samples` (refresh them first
  ///      with update_displacements() / update_normals()).
  /// @throws InvalidInput if @p slab is out of range or the layout changed since upload_all().
  /// @note O(n² + N²); no allocation after the first call.
  void upload_slab(const SlabModel& model, int slab);

  /// @brief Re-uploads slab @p slab from a snapshot of it (SnapshotReader::slab()): the same
  /// vertices and atlas tile the model overload gives for the same data, while another thread
  /// edits the live model (the studio's render thread; paper §6, only flagged slabs re-sent).
  /// @param model  the model the snapshots were made of: only its static members are read
  ///               (layouts, coarse vertices), which edits never change.
  /// @param view   the slab's data (displacements, normals, under-layer top, texels).
  /// @param slab   slab id in [0, #S).
  /// @throws InvalidInput if @p slab is out of range, the layout changed since upload_all() or
  ///         @p view does not match the model's grids.
  /// @note O(n² + N²); no allocation after the first call.
  void upload_slab(const SlabModel& model, const SlabView& view, int slab);

  /// @brief Draws every uploaded slab into the currently bound framebuffer with depth testing.
  /// @param camera           view and projection; its size should match the viewport.
  /// @param show_slab_edges  darken a line about 2 pixels wide along every slab boundary.
  /// @pre the target framebuffer is bound with a depth buffer and cleared (Framebuffer::begin()).
  /// @param level            level of detail (paper §6): 0 draws every grid triangle (#S·n²), level
  ///                          k the grid of every 2^k-th point (#S·(n/2^k)² triangles, same
  ///                          vertices, normals and colours); clamped to [0, level_count()).
  /// @throws RenderError if OpenGL reports an error. Draws nothing before upload_all().
  void draw(const RenderCamera& camera, bool show_slab_edges = false, int level = 0) const;

  /// @brief The brush's footprint for the next draws: the surface inside the sphere of @p radius
  /// [model units] about @p centre [model units] is tinted and its rim (where the surface crosses the
  /// sphere) drawn as a line about 2 pixels wide, on the surface itself, so it follows every bump.
  /// A radius <= 0 or a non-finite argument turns it off (the default). noexcept, O(1): a uniform.
  void set_footprint(const Vec3& centre, double radius) noexcept;

  /// Levels of detail available: 1 + the number of times n halves evenly (n = 16: 5 levels,
  /// the coarsest one triangle per slab); 0 before upload_all().
  int level_count() const noexcept;

  /// Number of slabs uploaded (0 before upload_all()).
  int slab_count() const noexcept;
  /// Number of triangles drawn (#S·n²).
  long long triangle_count() const noexcept;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace hdm
