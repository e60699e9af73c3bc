// SPDX-License-Identifier: MIT
#include <hdm/bridge/bridge_secret.h>
#include <hdm/bridge/wire_format.h>
#include <hdm/core/error.h>

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace hdm::bridge {
namespace {

std::string checked(std::string s, const std::string& where) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
  if (s.size() < kMinSecretBytes || s.size() > kMaxSecretBytes)
    throw InvalidInput(where + ": the bridge secret has " + std::to_string(s.size()) + " bytes; it needs " +
                       std::to_string(kMinSecretBytes) + " to " + std::to_string(kMaxSecretBytes));
  return s;
}

// A fresh file of 32 random hex digits, created exclusively (never through a planted link).
void create(const std::string& file) {
  unsigned char bytes[16];
  if (::getrandom(bytes, sizeof bytes, 0) != ssize_t(sizeof bytes))
    throw IoError(file + ": cannot draw a random secret: " + std::strerror(errno));
  char text[40];
  for (size_t i = 0; i < sizeof bytes; ++i) std::snprintf(text + 2 * i, 3, "%02x", bytes[i]);
  text[32] = '\n';
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) {
    if (errno == EEXIST) return;  // made meanwhile (a driver or another hdm): read that one
    throw IoError(file + ": cannot create the bridge secret: " + std::strerror(errno));
  }
  const bool ok = ::write(fd, text, 33) == 33 && ::fsync(fd) == 0;
  const int e = errno;
  ::close(fd);
  if (!ok) {
    ::unlink(file.c_str());
    throw IoError(file + ": cannot write the bridge secret: " + std::strerror(e));
  }
}

}  // namespace

std::string load_bridge_secret(const std::string& file) {
  if (file.empty()) {
    const char* v = std::getenv(kSecretVariable);
    if (!v)
      throw InvalidInput(std::string("the device bridge needs a shared secret: give --secret-file FILE (created "
                                     "with mode 0600 when missing) or set ") +
                         kSecretVariable);
    return checked(v, kSecretVariable);
  }
  if (::access(file.c_str(), F_OK) != 0 && errno == ENOENT) create(file);
  const int fd = ::open(file.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0)
    throw (errno == ELOOP ? InvalidInput(file + ": the bridge secret file is a symbolic link; give the file itself")
                          : InvalidInput(file + ": cannot open the bridge secret: " + std::strerror(errno)));
  struct stat st{};
  char buf[kMaxSecretBytes + 8];
  ssize_t n = -1;
  if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == ::geteuid() && (st.st_mode & 077) == 0)
    n = ::read(fd, buf, sizeof buf);
  ::close(fd);
  if (!S_ISREG(st.st_mode) || st.st_uid != ::geteuid())
    throw InvalidInput(file + ": the bridge secret must be a regular file of this user");
  if ((st.st_mode & 077) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%03o", unsigned(st.st_mode & 0777));
    throw InvalidInput(file + ": the bridge secret is readable by others (mode " + mode + "); chmod 600 " + file);
  }
  if (n < 0) throw IoError(file + ": cannot read the bridge secret: " + std::strerror(errno));
  return checked(std::string(buf, size_t(n)), file);
}

}  // namespace hdm::bridge
