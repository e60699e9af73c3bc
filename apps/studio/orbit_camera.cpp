// SPDX-License-Identifier: MIT
#include "orbit_camera.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace hdm::studio {

void OrbitCamera::orbit(double dx, double dy) noexcept {
  azimuth_deg = std::fmod(azimuth_deg - 0.3 * dx, 360.0);
  elevation_deg = std::clamp(elevation_deg + 0.3 * dy, -89.0, 89.0);
}

void OrbitCamera::pan(double dx, double dy, int height) noexcept {
  const RenderCamera cam = camera(std::max(height, 1), std::max(height, 1));
  // Model units per pixel at the target's distance.
  const double distance = (cam.eye - cam.target).norm();
  const double per_pixel = 2 * distance * std::tan(cam.fov_y_deg * std::numbers::pi / 360) / std::max(height, 1);
  const Eigen::Matrix3d r = cam.view.block<3, 3>(0, 0).cast<double>();
  target += per_pixel * (-dx * r.row(0).transpose() + dy * r.row(1).transpose());
}

void OrbitCamera::dolly(double steps) noexcept { zoom = std::clamp(zoom * std::pow(1.15, steps), 0.2, 200.0); }

RenderCamera OrbitCamera::camera(int width, int height) const {
  // Two points whose box centre is `centre` and farthest distance `radius`: fit_camera() frames
  // the model's bounding sphere without visiting the model.
  const Vec3f c = centre.cast<float>(), e = Vec3f(static_cast<float>(radius), 0, 0);
  const std::vector<Vec3f> sphere = {c - e, c + e};
  return zoom_camera(fit_camera(sphere, width, height, azimuth_deg, elevation_deg), target, zoom);
}

Vec3 unproject(const RenderCamera& cam, double x, double y, double depth) {
  const Eigen::Vector4d ndc(2 * x / cam.width - 1, 1 - 2 * y / cam.height, 2 * depth - 1, 1);
  const Eigen::Matrix4d inv = (cam.projection.cast<double>() * cam.view.cast<double>()).inverse();
  const Eigen::Vector4d p = inv * ndc;
  return p.head<3>() / p.w();
}

}  // namespace hdm::studio
