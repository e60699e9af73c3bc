// SPDX-License-Identifier: MIT
#pragma once
// Orbit, pan and zoom about a model, on hdm's render camera conventions (fit_camera, zoom_camera),
// so that the studio frames a model exactly as `hdm render` does at the same view and zoom.
#include <hdm/render/camera.h>

namespace hdm::studio {

/// An orbit camera: azimuth and elevation about a target, a zoom factor relative to the fitted
/// distance. Model units, degrees.
struct OrbitCamera {
  Vec3 centre = Vec3::Zero();                  ///< centre of the model's bounding sphere (fit) [model units]
  double radius = 1;                           ///< its radius [model units]
  double azimuth_deg = 0, elevation_deg = 15;  ///< view direction, as fit_camera()
  double zoom = 1;                             ///< 1: the whole model fits
  Vec3 target = Vec3::Zero();                  ///< point looked at [model units]

  /// Frames the sphere (centre, radius) from the current view direction, zoom 1.
  void fit() noexcept { target = centre, zoom = 1; }
  /// Turns about the target by pixel motion (dx, dy) (0.3 degree per pixel).
  void orbit(double dx, double dy) noexcept;
  /// Moves the target in the view plane by pixel motion (dx, dy) of a @p height pixel view.
  void pan(double dx, double dy, int height) noexcept;
  /// Zooms by 1.15^steps (positive: closer), within [0.2, 200].
  void dolly(double steps) noexcept;
  /// The camera for a @p width × @p height view. @throws InvalidInput on a zero size.
  RenderCamera camera(int width, int height) const;
};

/// @brief Pixel (x right, y down, pixel centres at +0.5) and window depth in [0,1] to a model point.
Vec3 unproject(const RenderCamera& camera, double x, double y, double depth);

}  // namespace hdm::studio
