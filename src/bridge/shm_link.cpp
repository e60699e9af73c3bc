// SPDX-License-Identifier: MIT
// The shared-memory transport: the region "/NAME" (shm_open) holds a header and the two seqlocked
// blocks; the driver process writes the device block and reads the force block, the servo thread
// the other way round. No thread, no system call after the set-up.
#include <hdm/core/error.h>

#include "link.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace hdm::bridge {
namespace {

struct ShmLink final : BridgeDevice::Link {
  ShmLink(const std::string& name, const std::string& secret) : Link(secret), path("/" + name) {
    const int fd = ::shm_open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (fd < 0) throw IoError("bridge shm:" + name + ": cannot create the region: " + std::strerror(errno));
    // A region taken over keeps the owner it was made by: another user's is refused, this user's
    // is made private again (another process may have opened it while it was open to others).
    struct stat st{};
    if (::fstat(fd, &st) != 0 || st.st_uid != ::geteuid()) {
      ::close(fd);
      char mode[8];
      std::snprintf(mode, sizeof mode, "%03o", unsigned(st.st_mode & 0777));
      throw IoError("bridge shm:" + name + ": the existing region /dev/shm/" + name +
                    " belongs to another user (mode " + mode + "); remove it or choose another name");
    }
    ::fchmod(fd, 0600);
    if (::ftruncate(fd, static_cast<off_t>(kMapBytes)) != 0) {
      const int e = errno;
      ::close(fd);
      ::shm_unlink(path.c_str());
      throw IoError("bridge shm:" + name + ": cannot size the region: " + std::strerror(e));
    }
    void* p = ::mmap(nullptr, kMapBytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    const int e = errno;
    ::close(fd);
    if (p == MAP_FAILED) {
      ::shm_unlink(path.c_str());
      throw IoError("bridge shm:" + name + ": cannot map the region: " + std::strerror(e));
    }
    base = static_cast<std::byte*>(p);
    std::memset(base, 0, kMapBytes);
    device_block = reinterpret_cast<uint64_t*>(base + kRegionDeviceBlock);
    force_block = reinterpret_cast<uint64_t*>(base + kRegionForceBlock);
    const uint16_t reserved = 0;
    const uint32_t bytes = kRegionBytes;
    std::memcpy(base + 4, &kRegionVersion, 2);
    std::memcpy(base + 6, &reserved, 2);
    std::memcpy(base + 8, &bytes, 4);
    // The magic last: a driver that sees it sees a cleared, sized region.
    std::atomic_ref<uint32_t>(*reinterpret_cast<uint32_t*>(base)).store(kRegionMagic, std::memory_order_release);
  }

  ~ShmLink() override {
    ::munmap(base, kMapBytes);
    ::shm_unlink(path.c_str());
  }

  static constexpr size_t kMapBytes = 4096;  // one page; the layout uses kRegionBytes of it
  std::string path;
  std::byte* base = nullptr;
};

}  // namespace

std::unique_ptr<BridgeDevice::Link> open_shm_link(const std::string& name, const std::string& secret) {
  return std::make_unique<ShmLink>(name, secret);
}

}  // namespace hdm::bridge
