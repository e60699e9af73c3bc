// SPDX-License-Identifier: MIT
#include "glyphs.h"

#include <imgui.h>

#include <array>
#include <cmath>
#include <numbers>

namespace hdm::studio {
namespace {

constexpr int kSegments = 48;

bool in_front(const RenderCamera& cam, const Vec3& p) {
  const Eigen::Vector4f v = cam.view * Eigen::Vector4f(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  return v.z() < -cam.near_plane;
}

ImVec2 to_screen(const RenderCamera& cam, const Vec3& p) {
  const Eigen::Vector2d q = cam.project(p);
  return ImVec2(static_cast<float>(q.x()), static_cast<float>(q.y()));
}

// A circle of radius r about c in the plane spanned by unit vectors u, v.
void circle(ImDrawList* list, const RenderCamera& cam, const Vec3& c, const Vec3& u, const Vec3& v, double r,
            ImU32 colour, float thickness) {
  std::array<ImVec2, kSegments> pts;
  for (int k = 0; k < kSegments; ++k) {
    const double a = 2 * std::numbers::pi * k / kSegments;
    const Vec3 p = c + r * (std::cos(a) * u + std::sin(a) * v);
    if (!in_front(cam, p)) return;
    pts[k] = to_screen(cam, p);
  }
  list->AddPolyline(pts.data(), kSegments, colour, ImDrawFlags_Closed, thickness);
}

// The force as an arrow from @p from, o.newton_length model units per newton.
void force_arrow(ImDrawList* list, const RenderCamera& cam, const Vec3& from, const Vec3& force,
                 const GlyphOptions& o) {
  const double f = force.norm();
  if (!(f > 1e-6) || !std::isfinite(f)) return;
  const Vec3 tip = from + o.newton_length * force;
  if (!in_front(cam, tip) || !in_front(cam, from)) return;
  const ImVec2 a = to_screen(cam, from), b = to_screen(cam, tip);
  list->AddLine(a, b, IM_COL32(255, 60, 60, 255), 3.0f);
  const float dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
  if (len > 1) {
    const float ux = dx / len, uy = dy / len, h = std::min(10.0f, 0.4f * len);
    list->AddTriangleFilled(b, ImVec2(b.x - h * ux - 0.5f * h * uy, b.y - h * uy + 0.5f * h * ux),
                            ImVec2(b.x - h * ux + 0.5f * h * uy, b.y - h * uy - 0.5f * h * ux),
                            IM_COL32(255, 60, 60, 255));
  }
}

// A rigid tool: its point shell at the god-object's pose, a dot per point (the points facing the
// camera brighter), and the force from the tip.
void rigid_tool(ImDrawList* list, const RenderCamera& cam, const ToolState& t, const GlyphOptions& o, ImU32 colour) {
  if (!o.shell || !t.ball_centre.allFinite()) return;
  const Eigen::Matrix3d r = t.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3f eye = cam.view.inverse().col(3).head<3>();
  const ImU32 faint = (colour & 0x00FFFFFFu) | (90u << 24);
  for (size_t k = 0; k < o.shell->points.size(); ++k) {
    const Vec3 p = t.ball_centre + r * o.shell->points[k];
    if (!in_front(cam, p)) continue;
    // Inward normals: a point faces the camera when its inward normal points away from the eye.
    const bool facing = (r * o.shell->normals[k]).dot(p - eye.cast<double>()) > 0;
    const ImVec2 q = to_screen(cam, p);
    list->AddRectFilled(ImVec2(q.x - 1, q.y - 1), ImVec2(q.x + 1, q.y + 1), facing ? colour : faint);
  }
  force_arrow(list, cam, t.ball_centre, t.force, o);
}

}  // namespace

void draw_tool_glyphs(ImDrawList* list, const RenderCamera& cam, const ToolState& t, const GlyphOptions& o) {
  if (!t.hip.allFinite()) return;
  const ImU32 tool_colour = t.tool_on ? IM_COL32(255, 140, 0, 230) : IM_COL32(40, 120, 255, 210);
  if (t.rigid) return rigid_tool(list, cam, t, o, tool_colour);
  // The tool sphere: three great circles about the HIP, or about the ball held outside the surface
  // (a sphere proxy) with the HIP's own sphere faint where the hand pushed in.
  const Vec3 axes[3] = {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  const Vec3 centre = t.ball && t.ball_centre.allFinite() ? t.ball_centre : t.hip;
  for (int k = 0; k < 3; ++k) circle(list, cam, centre, axes[k], axes[(k + 1) % 3], o.brush_radius, tool_colour, 1.0f);
  if (t.ball && (centre - t.hip).norm() > 1e-3 * o.brush_radius)
    circle(list, cam, t.hip, axes[0], axes[1], o.brush_radius, IM_COL32(180, 180, 180, 90), 1.0f);
  if (!t.contact || !t.proxy.allFinite()) return;
  // The proxy, the HIP–proxy link and the force (the brush's footprint is drawn on the surface by
  // the slab renderer: SlabRenderer::set_footprint).
  if (!in_front(cam, t.proxy) || !in_front(cam, t.hip)) return;
  const ImVec2 proxy = to_screen(cam, t.proxy);
  list->AddCircleFilled(proxy, 4.0f, IM_COL32(255, 230, 0, 255));
  list->AddLine(proxy, to_screen(cam, t.hip), IM_COL32(255, 230, 0, 160), 1.0f);
  force_arrow(list, cam, t.proxy, t.force, o);
}

}  // namespace hdm::studio
