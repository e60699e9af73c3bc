// SPDX-License-Identifier: MIT
// bake_mesh INPUT OUTPUT.hdm: reads a triangle mesh (OBJ, PLY, OFF, STL), bakes it into slabs with
// the default options (one round, no error bound: `hdm bake` adds the error-bounded loop, repair
// and the fidelity report) and saves the model.
#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>
#include <hdm/mesh/orient_mesh.h>
#include <hdm/slab/bake.h>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bake_mesh INPUT OUTPUT.hdm\n");
    return 2;
  }
  try {
    hdm::TriangleMesh mesh = hdm::read_mesh(argv[1]);
    hdm::orient_outward(mesh);  // every closed part facing out, as the bake expects
    hdm::BakeReport report;
    const hdm::SlabModel model = hdm::bake_slabs(mesh, argv[1], hdm::BakeOptions{}, &report);
    hdm::save_model(model, argv[2]);
    std::printf("%s: %d slabs, n = %d, %lld invalid slabs, %.2f s -> %s\n", argv[1], model.slab_count(), model.grid_n,
                static_cast<long long>(report.invalid_slabs), report.seconds, argv[2]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bake_mesh: %s\n", e.what());
    return 1;
  }
}
