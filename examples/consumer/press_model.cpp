// SPDX-License-Identifier: MIT
// press_model MODEL.hdm: loads a baked model and runs a simulated 1 kHz servo loop in which the
// haptic interaction point (HIP) moves straight down through the top of the model's bounding box
// at 2 cm/s (device frame, a 16 cm desktop workspace). The proxy (god-object) renders the force at
// every tick; every 20th tick is printed. Exits with 1 when the HIP never touches the surface, a
// force is not finite, or the contact force does not push the HIP back up.
#include <hdm/hdm.h>  // the runtime: model, query, proxy, forces, .hdm files

#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

static const char* const kStatus[] = {"free", "stuck", "sliding", "clamped", "bad input"};

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: press_model MODEL.hdm\n");
    return 2;
  }
  try {
    const hdm::SlabModel model = hdm::load_model(argv[1]);  // derived data built
    const hdm::SlabLocator locator(model);
    const hdm::Aabb box = hdm::surface_box(model);  // the displaced surface's box
    const hdm::Workspace ws = hdm::fit_workspace(box, 0.16);  // the box's diagonal spans 16 cm

    // Start 1 cm above the top of the box, over its centre; move down 2 cm/s for 1 s (1 cm into the model).
    const double rate_hz = 1000, speed_m_s = 0.02;
    const hdm::Vec3 centre = ws.to_device(0.5 * (box.min + box.max));
    const hdm::Vec3 start(centre.x(), ws.to_device(box.max).y() + 0.01, centre.z());
    const hdm::Vec3 velocity(0, -speed_m_s, 0);
    hdm::ProxyParams params;  // 1000 N/m, damping, friction from the model's fields
    hdm::ProxyState state;
    int contact_ticks = 0, upward_ticks = 0;
    double max_force = 0;
    std::printf("%s: %d slabs; tick, HIP y [mm], force [N] (device frame), proxy status\n", argv[1],
                model.slab_count());
    for (int tick = 0; tick < 1000; ++tick) {
      const hdm::Vec3 hip = start + velocity * (tick / rate_hz);
      const hdm::ProxyOutput out = hdm::proxy_step(model, locator, ws, hip, velocity, params, state);
      if (!out.force.allFinite()) throw hdm::NumericalError("force not finite at tick " + std::to_string(tick));
      const bool contact = out.status == hdm::ProxyStatus::Stuck || out.status == hdm::ProxyStatus::Sliding ||
                           out.status == hdm::ProxyStatus::Clamped;
      if (contact) {
        ++contact_ticks;
        if (out.force.y() > 0) ++upward_ticks;
        max_force = std::max(max_force, out.force.norm());
      }
      if (tick % 20 == 0 || (contact && contact_ticks == 1))
        std::printf("%4d  %8.2f  (%7.3f, %7.3f, %7.3f)  %s\n", tick, 1000 * hip.y(), out.force.x(), out.force.y(),
                    out.force.z(), kStatus[static_cast<int>(out.status)]);
    }
    std::printf("contact ticks %d, pushing up %d, max |F| %.3f N\n", contact_ticks, upward_ticks, max_force);
    if (contact_ticks == 0 || upward_ticks < contact_ticks * 9 / 10) {
      std::fprintf(stderr, "press_model: the probe %s\n",
                   contact_ticks == 0 ? "never touched the surface" : "was not pushed back up");
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "press_model: %s\n", e.what());
    return 1;
  }
}
