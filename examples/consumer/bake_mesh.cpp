// SPDX-License-Identifier: MIT
// bake_mesh INPUT OUTPUT.hdm: reads a triangle mesh (OBJ, PLY, OFF, STL), bakes it as `hdm bake`
// does with its defaults (bake_input(): repair, orientation, crossings, then slabs until the
// fidelity bound of 0.2 % of the diagonal holds) and saves the model.
#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>
#include <hdm/pipeline/bake_input.h>

#include <algorithm>
#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bake_mesh INPUT OUTPUT.hdm\n");
    return 2;
  }
  try {
    hdm::BakeInputReport report;
    const hdm::SlabModel model = hdm::bake_input(hdm::read_mesh(argv[1]), argv[1], {}, &report);
    hdm::save_model(model, argv[2]);
    std::printf("%s: %d slabs, n = %d, max error %.3f%% of the diagonal, %.2f s -> %s\n", argv[1], model.slab_count(),
                model.grid_n, std::max(report.fidelity.max_pct, report.fidelity.max_back_pct), report.seconds, argv[2]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bake_mesh: %s\n", e.what());
    return 1;
  }
}
