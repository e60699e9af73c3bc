#!/usr/bin/env python3
"""Draws the figure of docs/design.md: a slab cut through two of its corners, with the inner and
outer faces, the corner rays, one alpha-plane, one interpolated ray and the displaced surface.

Usage: python3 scripts/design_figures.py [OUT.svg]   (default: docs/img/design_slab.svg)
Plain SVG written by hand: no plotting library needed.
"""
import math
import os
import sys

# Two corners R and S of a slab, in the plane of the cut: inner point V0 and ray dV (model units).
R0, dR = (0.0, 0.0), (-1.2, 4.0)
S0, dS = (10.0, 0.6), (1.0, 3.8)
N = 8  # grid intervals along the cut
ALPHA = 0.35  # the alpha-plane drawn
W_RAY = 0.4  # barycentric weight of S on the interpolated ray drawn


def lerp(a, b, t):
    return (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))


def at(w, alpha):
    """X(w, α) restricted to the edge R-S: (1-w)(R0 + α dR) + w (S0 + α dS)."""
    r = (R0[0] + alpha * dR[0], R0[1] + alpha * dR[1])
    s = (S0[0] + alpha * dS[0], S0[1] + alpha * dS[1])
    return lerp(r, s, w)


def delta(w):
    """A displacement field along the cut, one value per grid point."""
    return 0.55 + 0.18 * math.sin(2.4 * math.pi * w) + 0.08 * math.cos(7.0 * w)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "docs", "img",
                                                            "design_slab.svg")
    scale, pad = 40.0, 60.0
    xs = [p[0] for p in (R0, S0, at(0, 1), at(1, 1))]
    ys = [p[1] for p in (R0, S0, at(0, 1), at(1, 1))]
    x_lo, y_hi = min(xs), max(ys)
    width = (max(xs) - x_lo) * scale + 2 * pad + 120
    height = (y_hi - min(ys)) * scale + 2 * pad

    def px(p):
        return (pad + (p[0] - x_lo) * scale, pad + (y_hi - p[1]) * scale)

    def line(a, b, style):
        (x0, y0), (x1, y1) = px(a), px(b)
        return f'<line x1="{x0:.1f}" y1="{y0:.1f}" x2="{x1:.1f}" y2="{y1:.1f}" {style}/>'

    def text(p, s, dx=6, dy=-4, colour="#222"):
        x, y = px(p)
        return f'<text x="{x + dx:.1f}" y="{y + dy:.1f}" fill="{colour}">{s}</text>'

    grey, blue, green, red = "#888", "#2b6cb0", "#2f855a", "#c53030"
    el = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height:.0f}" '
          f'font-family="sans-serif" font-size="14">',
          f'<rect width="100%" height="100%" fill="white"/>']
    # Corner rays, inner and outer faces.
    el.append(line(at(0, 0), at(0, 1), f'stroke="{grey}" stroke-width="1.5" stroke-dasharray="6,4"'))
    el.append(line(at(1, 0), at(1, 1), f'stroke="{grey}" stroke-width="1.5" stroke-dasharray="6,4"'))
    el.append(line(at(0, 0), at(1, 0), f'stroke="{grey}" stroke-width="2.5"'))
    el.append(line(at(0, 1), at(1, 1), f'stroke="{grey}" stroke-width="2.5"'))
    # Grid rays (thin) and the displaced surface through their displacements.
    pts = []
    for k in range(N + 1):
        w = k / N
        el.append(line(at(w, 0), at(w, 1), f'stroke="#ddd" stroke-width="1"'))
        pts.append(at(w, delta(w)))
    path = "M " + " L ".join(f"{px(p)[0]:.1f} {px(p)[1]:.1f}" for p in pts)
    el.append(f'<path d="{path}" fill="none" stroke="{red}" stroke-width="2.5"/>')
    for p in pts:
        x, y = px(p)
        el.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3.5" fill="{red}"/>')
    # One alpha-plane and one interpolated ray.
    el.append(line(at(0, ALPHA), at(1, ALPHA), f'stroke="{blue}" stroke-width="2"'))
    el.append(line(at(W_RAY, 0), at(W_RAY, 1), f'stroke="{green}" stroke-width="2"'))
    # δ on the interpolated ray: the surface is linear between grid points.
    k = int(W_RAY * N)
    f = W_RAY * N - k
    d = (1 - f) * delta(k / N) + f * delta((k + 1) / N)
    x, y = px(at(W_RAY, d))
    el.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="5" fill="none" stroke="{green}" stroke-width="2"/>')
    # Labels.
    def sub(name, index):
        return f'{name}<tspan baseline-shift="sub" font-size="10">{index}</tspan>'

    el += [text(at(0, 0), sub("R", 0), -26, 16), text(at(0, 1), sub("R", 1), -26, 0),
           text(at(1, 0), sub("S", 0), 8, 16), text(at(1, 1), sub("S", 1), 8, 0),
           text(at(0.75, 0), "inner face (α = 0)", -60, 22, grey),
           text(at(0.75, 1), "outer face (α = 1)", -60, -8, grey),
           text(at(1, ALPHA), "alpha-plane", 10, 5, blue),
           text(at(W_RAY, 0), sub("P", 0) + "(w)", -20, 20, green),
           text(at(W_RAY, 1), sub("P", 1) + "(w)", -20, -8, green),
           text(at(W_RAY, d), "δ(w)", 10, -6, green),
           text(at(1, delta(1)), "displaced surface", 10, 5, red)]
    el.append("</svg>")
    with open(out, "w") as fh:
        fh.write("\n".join(el) + "\n")
    print(out)


if __name__ == "__main__":
    main()
