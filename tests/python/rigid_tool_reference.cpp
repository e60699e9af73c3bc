// SPDX-License-Identifier: MIT
// The C++ side of tests/python/test_rigid_tool.py: loads a .hdm model, builds the burr shell and
// runs rigid_tool_step over the poses read from stdin, one tick per line, printing each wrench.
// usage: rigid_tool_reference MODEL.hdm ORIGIN_X ORIGIN_Y ORIGIN_Z SCALE RADIUS COUNT < poses
//   stdin: one pose per line, "px py pz qw qx qy qz" (tip [m], orientation tool → device)
//   stdout: one line per pose, "fx fy fz tx ty tz status contacts" (%.17g: exact doubles)
#include <hdm/haptics/rigid_tool.h>
#include <hdm/io/hdm_file.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>

int main(int argc, char** argv) {
  if (argc != 8) {
    std::fprintf(stderr, "usage: %s MODEL.hdm ORIGIN_X ORIGIN_Y ORIGIN_Z SCALE RADIUS COUNT < poses\n", argv[0]);
    return 2;
  }
  try {
    const hdm::SlabModel model = hdm::load_model(argv[1]);
    const hdm::SlabLocator locator(model);
    hdm::Workspace ws;
    ws.origin = hdm::Vec3(std::strtod(argv[2], nullptr), std::strtod(argv[3], nullptr), std::strtod(argv[4], nullptr));
    ws.scale = std::strtod(argv[5], nullptr);
    const hdm::ToolShell shell = hdm::burr_shell(std::strtod(argv[6], nullptr), std::atoi(argv[7]));
    auto state = std::make_unique<hdm::RigidToolState>();
    const hdm::RigidToolParams params;
    double p[3], q[4];
    while (std::scanf("%lf %lf %lf %lf %lf %lf %lf", &p[0], &p[1], &p[2], &q[0], &q[1], &q[2], &q[3]) == 7) {
      const hdm::ToolPose pose{hdm::Vec3(p[0], p[1], p[2]), Eigen::Quaterniond(q[0], q[1], q[2], q[3])};
      const hdm::ToolWrench w = hdm::rigid_tool_step(model, locator, ws, shell, pose, {}, params, *state);
      std::printf("%.17g %.17g %.17g %.17g %.17g %.17g %d %d\n", w.force.x(), w.force.y(), w.force.z(), w.torque.x(),
                  w.torque.y(), w.torque.z(), int(w.status), w.contacts);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rigid_tool_reference: %s\n", e.what());
    return 1;
  }
  return 0;
}
