// SPDX-License-Identifier: MIT
// Generalized winding number with a dipole far field (Jacobson et al. 2013; Barill et al. 2018).
#include <hdm/mesh/winding_number.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

namespace hdm {
namespace {

constexpr int kLeafFaces = 8;

// Signed solid angle of triangle abc seen from the origin (Van Oosterom & Strackee 1983).
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  if (num == 0 && den <= 0) return 0;  // p on the plane, outside or on the triangle
  return 2 * std::atan2(num, den);
}

}  // namespace

WindingNumber::WindingNumber(const TriangleMesh& mesh, double beta) : beta2_(beta * beta) {
  const size_t nf = mesh.faces.size();
  std::vector<int32_t> order(nf);
  std::iota(order.begin(), order.end(), 0);
  std::vector<Vec3> centroid(nf);
  for (size_t f = 0; f < nf; ++f) {
    const Tri& t = mesh.faces[f];
    centroid[f] = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.0;
  }
  if (nf == 0) return;
  nodes_.reserve(2 * nf / kLeafFaces + 2);
  // Median split on the longest axis of the centroids' box, depth first.
  struct Task {
    int32_t node, begin, end;
  };
  std::vector<Task> stack;
  nodes_.push_back(Node{});
  stack.push_back({0, 0, int32_t(nf)});
  while (!stack.empty()) {
    const Task t = stack.back();
    stack.pop_back();
    Node& n = nodes_[t.node];
    n.begin = t.begin, n.end = t.end, n.left = n.right = -1;
    if (t.end - t.begin <= kLeafFaces) continue;
    Vec3 lo = centroid[order[t.begin]], hi = lo;
    for (int32_t i = t.begin; i < t.end; ++i)
      lo = lo.cwiseMin(centroid[order[i]]), hi = hi.cwiseMax(centroid[order[i]]);
    int axis;
    (hi - lo).maxCoeff(&axis);
    const int32_t mid = (t.begin + t.end) / 2;
    std::nth_element(order.begin() + t.begin, order.begin() + mid, order.begin() + t.end,
                     [&](int32_t x, int32_t y) { return centroid[x][axis] < centroid[y][axis]; });
    const int32_t l = int32_t(nodes_.size());
    nodes_.push_back(Node{});
    nodes_.push_back(Node{});
    nodes_[t.node].left = l, nodes_[t.node].right = l + 1;
    stack.push_back({l, t.begin, mid});
    stack.push_back({l + 1, mid, t.end});
  }
  corners_.resize(3 * nf);
  for (size_t i = 0; i < nf; ++i)
    for (int k = 0; k < 3; ++k) corners_[3 * i + k] = mesh.vertices[mesh.faces[order[i]][k]];
  // Moments of every node from its faces (nodes hold contiguous ranges, so no bottom-up pass).
  for (Node& n : nodes_) {
    Vec3 an = Vec3::Zero(), c = Vec3::Zero(), mean = Vec3::Zero();
    double area = 0;
    for (int32_t i = n.begin; i < n.end; ++i) {
      const Vec3 &a = corners_[3 * i], &b = corners_[3 * i + 1], &d = corners_[3 * i + 2];
      const Vec3 v = 0.5 * (b - a).cross(d - a);
      const double s = v.norm();
      an += v, area += s, c += s * (a + b + d) / 3.0, mean += (a + b + d) / 3.0;
    }
    n.area_normal = an;
    n.center = area > 0 ? Vec3(c / area) : Vec3(mean / double(n.end - n.begin));
    double r2 = 0;
    for (int32_t i = 3 * n.begin; i < 3 * n.end; ++i) r2 = std::max(r2, (corners_[i] - n.center).squaredNorm());
    n.radius = std::sqrt(r2);
  }
}

double WindingNumber::operator()(const Vec3& p) const {
  if (!p.allFinite()) return std::nan("");
  if (nodes_.empty()) return 0;
  double sum = 0;
  int32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    const Vec3 d = n.center - p;
    const double d2 = d.squaredNorm();
    if (d2 > beta2_ * n.radius * n.radius) {
      sum += n.area_normal.dot(d) / (d2 * std::sqrt(d2));
      continue;
    }
    if (n.left < 0 || top + 2 > 128) {
      for (int32_t i = n.begin; i < n.end; ++i)
        sum += solid_angle(corners_[3 * i] - p, corners_[3 * i + 1] - p, corners_[3 * i + 2] - p);
      continue;
    }
    stack[top++] = n.left;
    stack[top++] = n.right;
  }
  return sum / (4 * std::numbers::pi);
}

}  // namespace hdm
