// SPDX-License-Identifier: MIT
#include <hdm/core/error.h>
#include <hdm/render/camera.h>
#include <hdm/slab/slab_model.h>

#include "model_check.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace hdm {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// gluLookAt-style rigid transform with explicit orthonormal axes.
Eigen::Matrix4f look_at(const Vec3& eye, const Vec3& forward, const Vec3& up) {
  const Vec3 z = -forward.normalized();
  const Vec3 x = up.cross(z).normalized();
  const Vec3 y = z.cross(x);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = x.transpose();
  m.block<1, 3>(1, 0) = y.transpose();
  m.block<1, 3>(2, 0) = z.transpose();
  m(0, 3) = -x.dot(eye);
  m(1, 3) = -y.dot(eye);
  m(2, 3) = -z.dot(eye);
  return m.cast<float>();
}

// gluPerspective.
Eigen::Matrix4f perspective(double fov_y, double aspect, double near_plane, double far_plane) {
  const double f = 1.0 / std::tan(fov_y / 2);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far_plane + near_plane) / (near_plane - far_plane);
  m(2, 3) = 2 * far_plane * near_plane / (near_plane - far_plane);
  m(3, 2) = -1;
  return m.cast<float>();
}

}  // namespace

Eigen::Vector2d RenderCamera::project(const Vec3& p) const {
  const Eigen::Vector4d clip = (projection.cast<double>() * view.cast<double>()) * p.homogeneous();
  const double x = clip.x() / clip.w(), y = clip.y() / clip.w();
  return {(x + 1) / 2 * width, (1 - y) / 2 * height};
}

RenderCamera fit_camera(const std::vector<Vec3f>& points, int width, int height, double azimuth_deg,
                        double elevation_deg) {
  if (width < 1 || height < 1)
    throw InvalidInput("image size " + std::to_string(width) + "x" + std::to_string(height) + " must be positive");
  if (!std::isfinite(azimuth_deg) || !std::isfinite(elevation_deg) || std::abs(elevation_deg) > 90)
    throw InvalidInput("view direction (azimuth " + std::to_string(azimuth_deg) + ", elevation " +
                       std::to_string(elevation_deg) + ") must be finite with elevation in [-90, 90] degrees");
  RenderCamera cam;
  cam.width = width;
  cam.height = height;
  cam.fov_y_deg = kRenderFovYDeg;

  Aabb box;
  for (const Vec3f& p : points) box.extend(p.cast<double>());
  cam.target = points.empty() ? Vec3::Zero() : Vec3((box.min + box.max) / 2);
  double r2 = 0;
  for (const Vec3f& p : points) r2 = std::max(r2, (p.cast<double>() - cam.target).squaredNorm());
  // A single point (or an empty model) still gets a finite, non-degenerate frustum.
  cam.radius = r2 > 0 ? std::sqrt(r2) : 1.0;

  const double aspect = static_cast<double>(width) / height;
  const double half_y = cam.fov_y_deg * kDegree / 2;
  const double half_x = std::atan(std::tan(half_y) * aspect);
  const double half_min = std::min(half_y, half_x);
  const double distance = cam.radius / std::sin(std::atan(kRenderFill * std::tan(half_min)));

  const double az = azimuth_deg * kDegree, el = elevation_deg * kDegree;
  const Vec3 towards_eye(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  // d(towards_eye)/d(el): orthogonal to the view axis and continuous through the poles.
  const Vec3 up(-std::sin(el) * std::sin(az), std::cos(el), -std::sin(el) * std::cos(az));
  cam.eye = cam.target + distance * towards_eye;
  // The framed sphere lies within [distance - radius, distance + radius] along the view axis.
  cam.near_plane = std::max((distance - cam.radius) * 0.9, distance * 1e-3);
  cam.far_plane = (distance + cam.radius) * 1.1;
  cam.view = look_at(cam.eye, -towards_eye, up);
  cam.projection = perspective(2 * half_y, aspect, cam.near_plane, cam.far_plane);
  return cam;
}

RenderCamera zoom_camera(const RenderCamera& f, const Vec3& target, double zoom) {
  if (!(zoom > 0) || !std::isfinite(zoom) || !target.allFinite())
    throw InvalidInput("zoom " + std::to_string(zoom) + " must be positive and the focus point finite");
  RenderCamera cam = f;
  const Vec3 towards_eye = (f.eye - f.target).normalized();
  const double distance = (f.eye - f.target).norm() / zoom;
  const Eigen::Matrix3d rotation = f.view.block<3, 3>(0, 0).cast<double>();
  const Vec3 up = rotation.row(1).transpose();
  cam.target = target;
  cam.eye = target + distance * towards_eye;
  cam.radius = f.radius / zoom;
  const double reach = f.radius + (target - f.target).norm();  // everything fitted lies within it
  cam.near_plane = std::max((distance - reach) * 0.9, distance * 1e-3);
  cam.far_plane = (distance + reach) * 1.1;
  cam.view = look_at(cam.eye, -towards_eye, up);
  const double aspect = static_cast<double>(f.width) / f.height;
  cam.projection = perspective(f.fov_y_deg * kDegree, aspect, cam.near_plane, cam.far_plane);
  return cam;
}

RenderCamera fit_camera(const SlabModel& model, int width, int height, double azimuth_deg, double elevation_deg) {
  render_detail::check_renderable(model);
  // The points drawn (sample_position()).
  std::vector<Vec3f> points(model.samples.count);
  for (int s = 0; s < model.samples.count; ++s) points[s] = sample_position(model, s).cast<float>();
  return fit_camera(points, width, height, azimuth_deg, elevation_deg);
}

}  // namespace hdm
