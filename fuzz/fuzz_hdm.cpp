// SPDX-License-Identifier: MIT
// libFuzzer target for the .hdm reader (load_model_from_memory). The input's last 8 bytes are
// replaced by the FNV-1a checksum of the rest, so mutations reach the sections and the layout
// checks instead of stopping at the checksum (a file with a valid checksum can still be corrupt).
#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>
#include <hdm/query/slab_query.h>
#include <hdm/query/slab_locator.h>

#include <cstddef>
#include <cstdint>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  if (bytes.size() >= 16) {
    uint64_t h = 14695981039346656037ull;  // FNV-1a, as hdm_file.h specifies
    for (size_t k = 0; k + 8 < bytes.size(); ++k) h = (h ^ bytes[k]) * 1099511628211ull;
    for (int k = 0; k < 8; ++k) bytes[bytes.size() - 8 + k] = static_cast<uint8_t>(h >> (8 * k));
  }
  hdm::SlabModel m;
  try {
    m = hdm::load_model_from_memory(bytes, "fuzz.hdm");
  } catch (const hdm::IoError&) {
    return 0;
  } catch (const hdm::InvalidInput&) {
    return 0;
  }
  // What load_model() promises: the derived arrays are rebuilt to the stored sizes.
  if (m.samples.count != static_cast<int>(m.displacement.size()) || m.slab_samples.size() != m.samples.slot_count() ||
      m.texels.count != static_cast<int>(m.colour.size()) || m.geometry.size() != m.slabs.size())
    __builtin_trap();
  const hdm::SlabLocator locator(m);
  hdm::QueryCache cache;
  for (size_t s = 0; s < m.slabs.size() && s < 4; ++s) {
    const hdm::Vec3 c = (m.inner[m.slabs[s][0]] + m.outer[m.slabs[s][1]] + m.inner[m.slabs[s][2]]) / 3;
    (void)hdm::query(m, locator, c, cache);
  }
  return 0;
}
