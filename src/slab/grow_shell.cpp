// SPDX-License-Identifier: MIT
// The bake's shell: grown while valid, thinned where slabs overlap (docs/design.md#growing-the-shell).
#include "grow_shell.h"

#include <hdm/slab/shell_check.h>

#include <algorithm>

namespace hdm::slab::detail {

Shell::Shell(SlabModel& model, const CoarseMesh& coarse, const VertexFrame& fr, ShellTargets& targets)
    : model_(model),
      coarse_(coarse),
      fr_(fr),
      t_(targets),
      tgt_in0_(targets.tgt_in),
      tgt_out0_(targets.tgt_out),
      off_in_(targets.min_off),
      off_out_(targets.min_off),
      moved_(model.slabs.size()) {
  const size_t nv = coarse.vertices.size();
  model.inner.resize(nv);
  model.outer.resize(nv);
  for (size_t v = 0; v < nv; ++v) place(v);
  // The Jacobian each slab must keep while the shell grows: 0.02, or half of what the thinnest
  // shell gives where that is less (a barely seen star), never letting a valid slab turn invalid.
  // Slabs that are invalid even in the thinnest shell (a direction that cannot see all its faces)
  // are left out of the growth test and reported.
  required_.resize(model.slabs.size());
  hopeless_.resize(model.slabs.size());
  for (size_t f = 0; f < model.slabs.size(); ++f) {
    const double j = jacobian(static_cast<int32_t>(f));
    hopeless_[f] = !(j > 0);
    required_[f] = j > 0.04 ? 0.02 : 0.5 * j;
  }
}

void Shell::restart() {
  t_.tgt_in = tgt_in0_, t_.tgt_out = tgt_out0_;
  for (size_t v = 0; v < coarse_.vertices.size(); ++v) off_in_[v] = off_out_[v] = t_.min_off[v], place(v);
}

void Shell::place(size_t v) {
  model_.inner[v] = coarse_.vertices[v] - off_in_[v] * fr_.direction[v];
  model_.outer[v] = coarse_.vertices[v] + off_out_[v] * fr_.direction[v];
}

double Shell::jacobian(int32_t f) const {
  const Tri& t = model_.slabs[f];
  const SlabGeometry g = make_slab_geometry(model_.inner[t[0]], model_.inner[t[1]], model_.inner[t[2]],
                                            model_.outer[t[0]], model_.outer[t[1]], model_.outer[t[2]]);
  return slab_min_jacobian(g, model_.outer[t[1]] - model_.inner[t[1]], model_.outer[t[2]] - model_.inner[t[2]]);
}

bool Shell::ring_ok(size_t v) const {
  for (int32_t k = fr_.offsets[v]; k < fr_.offsets[v + 1]; ++k)
    if (!hopeless_[fr_.faces[k]] && !slab_ok(fr_.faces[k])) return false;
  return true;
}

// Grow while valid (thin-to-thick, as in the shell literature): from a thin valid shell, raise each
// vertex's offset towards its target, keeping the largest value found by bisection.
void Shell::grow() {
  // Every vertex grows by a bounded step per sweep (at most doubling, or a sixth of its
  // target), so neighbours rise together and the alpha-planes stay parallel; a vertex that
  // jumped to its target alone would tilt its slabs and block its neighbours' growth.
  for (int sweep = 0; sweep < 32; ++sweep) {
    bool changed = false;
    for (size_t v = 0; v < coarse_.vertices.size(); ++v)
      for (int side = 0; side < 2; ++side) {
        double& off = side ? off_out_[v] : off_in_[v];
        const double target = side ? t_.tgt_out[v] : t_.tgt_in[v];
        if (off >= target * 0.999) continue;
        const double start = off;
        double lo = off, hi = std::min(target, std::max(2 * off, off + target / 6));
        off = hi;
        place(v);
        if (!ring_ok(v)) {
          for (int it = 0; it < 6; ++it) {
            off = 0.5 * (lo + hi);
            place(v);
            (ring_ok(v) ? lo : hi) = off;
          }
          off = lo;
          place(v);
        }
        changed |= off > start * 1.001;
      }
    if (!changed) break;
  }
}

void Shell::shrink(size_t v, double f) {
  off_in_[v] = std::max(t_.min_off[v], off_in_[v] * f), off_out_[v] = std::max(t_.min_off[v], off_out_[v] * f);
  t_.tgt_in[v] = std::min(t_.tgt_in[v], off_in_[v]), t_.tgt_out[v] = std::min(t_.tgt_out[v], off_out_[v]);
  place(v);
}

// Overlapping pairs are kept from one check to the next and recomputed only around slabs
// whose corners moved since (most of the shell is settled after the first iterations).
const std::vector<std::pair<int32_t, int32_t>>& Shell::current_pairs() {
  if (checked_inner_.empty()) {
    known_pairs_ = overlapping_pairs(model_);
  } else {
    for (size_t f = 0; f < model_.slabs.size(); ++f) {
      moved_[f] = 0;
      for (int32_t v : model_.slabs[f])
        moved_[f] |= model_.inner[v] != checked_inner_[v] || model_.outer[v] != checked_outer_[v];
    }
    update_overlapping_pairs(model_, moved_, known_pairs_);
  }
  checked_inner_ = model_.inner;
  checked_outer_ = model_.outer;
  return known_pairs_;
}

void Shell::separate() {
  for (int it = 0; it < 12; ++it) {
    auto pairs = current_pairs();
    if (pairs.empty()) {
      checked_inner_.clear();
      pairs = current_pairs();
    }
    if (pairs.empty()) break;
    for (const auto& [a, b] : pairs)
      for (int32_t f : {a, b})
        for (int32_t v : model_.slabs[f]) shrink(v, 0.9);
    for (int fix = 0; fix < 40; ++fix) {
      bool bad = false;
      for (size_t f = 0; f < model_.slabs.size(); ++f)
        if (!hopeless_[f] && !slab_ok(static_cast<int32_t>(f))) {
          bad = true;
          for (int32_t v : model_.slabs[f]) shrink(v, 0.8);
        }
      if (!bad) break;
    }
  }
}

bool Shell::widen(const std::vector<uint8_t>& grow_in, const std::vector<uint8_t>& grow_out) {
  bool grew = false;
  for (size_t v = 0; v < coarse_.vertices.size(); ++v) {
    if (grow_in[v] && t_.tgt_in[v] < t_.cap_in[v])
      t_.tgt_in[v] = std::min(t_.cap_in[v], std::max(t_.tgt_in[v], off_in_[v]) * 1.5), grew = true;
    if (grow_out[v] && t_.tgt_out[v] < t_.cap_out[v])
      t_.tgt_out[v] = std::min(t_.cap_out[v], std::max(t_.tgt_out[v], off_out_[v]) * 1.5), grew = true;
  }
  return grew;
}

}  // namespace hdm::slab::detail
