// SPDX-License-Identifier: MIT
#include <hdm/query/alpha_plane.h>

#include <cmath>

namespace hdm {
namespace {

struct Cubic {
  double c0, c1, c2, c3;  // f(α) = c3 α³ + c2 α² + c1 α + c0
  double operator()(double a) const noexcept { return ((c3 * a + c2) * a + c1) * a + c0; }
  double slope(double a) const noexcept { return (3 * c3 * a + 2 * c2) * a + c1; }
  double curvature(double a) const noexcept { return 6 * c3 * a + 2 * c2; }
};

// Halley steps stop once a step is below this: the error after the step is then about
// C·step³ with C = O((f''/f')²), far below the documented 1e-12 (checked on the shipped models,
// docs/performance.md).
constexpr double kStepTol = 1e-6;

// Root of f in [lo, hi] where f(lo) = flo, f(hi) = fhi have opposite signs.
double solve(const Cubic& f, double lo, double hi, double flo, double fhi, double guess, AlphaSolver solver) noexcept {
  if (solver == AlphaSolver::Bisection) {  // the paper's reference: exactly 15 steps
    for (int k = 0; k < 15; ++k) {
      const double mid = 0.5 * (lo + hi), fm = f(mid);
      if ((fm > 0) == (flo > 0))
        lo = mid, flo = fm;
      else
        hi = mid;
    }
    return 0.5 * (lo + hi);
  }
  // Warm start (previous tick's α) or the secant of the bracket: slabs are thin, so f is nearly
  // linear in α and either start is close; Halley's step (third order, one division) then needs
  // 2-3 iterations where Newton to 1e-13 needed 4-6.
  double a = guess;
  if (!(a > lo && a < hi)) {
    a = lo - flo * (hi - lo) / (fhi - flo);
    if (!(a > lo && a < hi)) a = 0.5 * (lo + hi);
  }
  for (int k = 0; k < 40; ++k) {
    const double fa = f(a);
    if (fa == 0) return a;
    if ((fa > 0) == (flo > 0))
      lo = a, flo = fa;
    else
      hi = a;
    const double d1 = f.slope(a), d2 = f.curvature(a);
    const double step = 2 * fa * d1 / (2 * d1 * d1 - fa * d2);
    const double next = a - step;
    if (std::abs(step) < kStepTol) return next < lo ? lo : next > hi ? hi : next;
    if (!(next > lo && next < hi)) {  // safeguard: bisect
      a = 0.5 * (lo + hi);
      if (hi - lo < 1e-13) return a;
    } else {
      a = next;
    }
  }
  return a;
}

// Barycentrics of p on the alpha-triangle at α (docs/design.md#barycentrics). Returns the edge beyond which
// p lies (0 RS, 1 ST, 2 TR) or -1 when every barycentric is >= -eps.
int barycentrics(const SlabGeometry& g, const Vec3& p, double alpha, Vec3& bary) noexcept {
  const Vec3 E1 = g.e1 + alpha * g.d1, E2 = g.e2 + alpha * g.d2;
  const Vec3 N = g.N0 + alpha * (g.N1 + alpha * g.N2);
  const Vec3 r = p - (g.R0 + alpha * g.dR);
  const double inv = 1.0 / N.squaredNorm();
  const double wS = r.cross(E2).dot(N) * inv, wT = E1.cross(r).dot(N) * inv;
  bary = Vec3(1.0 - wS - wT, wS, wT);
  constexpr double eps = 1e-9;
  if (bary[0] >= -eps && wS >= -eps && wT >= -eps) return -1;
  // Most negative barycentric: its opposite edge (R -> ST, S -> TR, T -> RS).
  if (bary[0] <= wS && bary[0] <= wT) return 1;
  return wS <= wT ? 2 : 0;
}

}  // namespace

bool locate_in_slab(const SlabGeometry& g, const Vec3& p, AlphaSolver solver, double alpha_guess, SlabCoordinates& c,
                    int& exit_edge) noexcept {
  exit_edge = -1;
  if (!p.allFinite()) return false;
  const Vec3 q = p - g.R0;
  const Cubic f{g.N0.dot(q), g.N1.dot(q) - g.N0.dot(g.dR), g.N2.dot(q) - g.N1.dot(g.dR), -g.N2.dot(g.dR)};
  const double f0 = f.c0, f1 = f.c0 + f.c1 + f.c2 + f.c3;
  if ((f0 > 0 && f1 > 0) || (f0 < 0 && f1 < 0)) return false;  // paper §3.1: no root in [0,1]
  double alpha = f0 == 0 ? 0.0 : f1 == 0 ? 1.0 : solve(f, 0.0, 1.0, f0, f1, alpha_guess, solver);
  Vec3 bary;
  const int edge = barycentrics(g, p, alpha, bary);
  if (edge < 0) {
    c.alpha = alpha;
    c.bary = bary;
    return true;
  }
  // Several roots in [0,1]: split at the critical points of f and try each monotone piece.
  const double A = 3 * f.c3, B = 2 * f.c2, C = f.c1;
  double cuts[4] = {0, 0, 0, 1};
  int n = 1;
  if (A != 0) {
    const double disc = B * B - 4 * A * C;
    if (disc > 0) {
      const double s = std::sqrt(disc), r1 = (-B - s) / (2 * A), r2 = (-B + s) / (2 * A);
      for (double r : {std::min(r1, r2), std::max(r1, r2)})
        if (r > 0 && r < 1) cuts[n++] = r;
    }
  } else if (B != 0) {
    const double r = -C / B;
    if (r > 0 && r < 1) cuts[n++] = r;
  }
  if (n == 1) {
    exit_edge = edge;
    return false;
  }
  cuts[n] = 1;
  for (int k = 0; k < n; ++k) {
    const double lo = cuts[k], hi = cuts[k + 1], flo = f(lo), fhi = f(hi);
    if ((flo > 0 && fhi > 0) || (flo < 0 && fhi < 0)) continue;
    alpha = flo == 0 ? lo : fhi == 0 ? hi : solve(f, lo, hi, flo, fhi, -1.0, solver);
    if (barycentrics(g, p, alpha, bary) < 0) {
      c.alpha = alpha;
      c.bary = bary;
      return true;
    }
  }
  exit_edge = edge;
  return false;
}

bool locate_in_slab(const SlabGeometry& g, const Vec3& p, AlphaSolver solver, SlabCoordinates& c) noexcept {
  int edge;
  return locate_in_slab(g, p, solver, -1.0, c, edge);
}

Vec3 slab_point(const SlabGeometry& g, const Vec3& w, double alpha) noexcept {
  return g.R0 + alpha * g.dR + w[1] * (g.e1 + alpha * g.d1) + w[2] * (g.e2 + alpha * g.d2);
}

}  // namespace hdm
