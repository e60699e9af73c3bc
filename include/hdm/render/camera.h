// SPDX-License-Identifier: MIT
#pragma once
/// @file
/// The orbit camera that frames a slab model for rendering (paper §6 says nothing about cameras;
/// this is hdm's convention, fixed so tests can predict where the model lands in the image).

#include <hdm/core/types.h>

#include <Eigen/Core>
#include <vector>

namespace hdm {

struct SlabModel;

/// A perspective camera looking at a model, with the matrices OpenGL needs.
///
/// Frames: world = model units; view = right-handed, camera at the origin looking down −Z, Y up;
/// clip = OpenGL clip space (NDC depth in [−1, 1]).
struct RenderCamera {
  Vec3 target = Vec3::Zero();  ///< point looked at: centre of the surface's bounding box [model units]
  Vec3 eye = Vec3::UnitZ();    ///< camera position [model units]
  double fov_y_deg = 30;       ///< vertical field of view [degrees]
  double radius = 1;           ///< radius of the framed sphere about `target` [model units]
  /// @{ Clip distances along the view axis [model units].
  double near_plane = 0.1, far_plane = 10;
  /// @}
  /// @{ Image size [pixels].
  int width = 1, height = 1;
  /// @}
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();        ///< world -> view (rigid)
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();  ///< view -> clip

  /// @brief Pixel position of world point @p p: x right from the left edge, y down from the top
  /// row (PNG row order), pixel centres at half-integers [pixels].
  /// @pre @p p lies in front of the camera.
  Eigen::Vector2d project(const Vec3& p) const;
};

/// Vertical field of view used by fit_camera [degrees].
inline constexpr double kRenderFovYDeg = 30.0;
/// Fraction of the half of the smaller image side that the framed sphere's silhouette fills.
inline constexpr double kRenderFill = 0.9;

/// @brief Camera looking at the centre c of the bounding box of @p points from direction
/// (azimuth, elevation), at the distance where the sphere about c through the farthest point
/// fills kRenderFill of the smaller half-side of the image.
///
/// The eye is c + D·(sin az·cos el, sin el, cos az·cos el): azimuth 0 looks from +Z towards −Z,
/// positive azimuth swings the eye towards +X, positive elevation raises it (Y up). With
/// half-angle h of the smaller field of view and sphere radius R, D = R / sin(atan(kRenderFill·tan h)),
/// so a concentric sphere of radius r has a centred circular silhouette of radius
/// (height/2)·tan(asin(r/D)) / tan(kRenderFovYDeg/2) pixels.
/// @param points     #P world points [model units]; an empty set frames the unit sphere at 0.
/// @param width,height image size [pixels], > 0.
/// @param azimuth_deg,elevation_deg view direction [degrees]; elevation in [−90, 90]. The image's
///        up direction is d(eye direction)/d(elevation): +Y when level, the continuous limit
///        (−(sin az, 0, cos az) from straight above) at ±90.
/// @throws InvalidInput on a non-positive size, non-finite angles or |elevation| > 90.
/// @note O(#P); no GL calls.
RenderCamera fit_camera(const std::vector<Vec3f>& points, int width, int height, double azimuth_deg,
                        double elevation_deg);

/// @brief fit_camera() over the displaced surface of @p model (sample_position of every sample).
/// @pre rebuild_derived(model) has run.
/// @throws InvalidInput if the model has no slabs or stale derived data.
/// @note O(#samples); allocates one temporary array.
RenderCamera fit_camera(const SlabModel& model, int width, int height, double azimuth_deg, double elevation_deg);

/// @brief The camera @p fitted moved to look at @p target from @p zoom times closer, along the
/// same view direction with the same up vector; the clip planes still hold everything @p fitted
/// framed.
/// @param fitted  a camera from fit_camera().
/// @param target  the new point looked at [model units].
/// @param zoom    > 0 (1: the fitted distance).
/// @throws InvalidInput when @p zoom is not positive or @p target is not finite.
RenderCamera zoom_camera(const RenderCamera& fitted, const Vec3& target, double zoom);

}  // namespace hdm
