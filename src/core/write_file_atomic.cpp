// SPDX-License-Identifier: MIT
// Unnamed temporaries (O_TMPFILE) so that a kill during the write, the long part, leaves nothing;
// a name carrying the process id only for the microseconds between linkat and rename, so that the
// next write of the same file can tell a dead writer's leftover from a live one's.
#include <hdm/core/error.h>
#include <hdm/core/write_file_atomic.h>

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <vector>

namespace hdm {
namespace {

constexpr unsigned kMaxNames = 100;
std::atomic<unsigned> next_name{0};  // per process, so threads of one process never share a name

struct Temp {
  std::string dir, base, name;  // name: the temporary's file name once it has one
  int fd = -1;
  bool named = false;
};

std::string reason() { return std::strerror(errno); }

std::string dir_of(const std::string& path) {
  const std::string d = std::filesystem::path(path).parent_path().string();
  return d.empty() ? "." : d;
}

// Removes `.<base>.<pid>-<k>.tmp` files of this user whose process is gone (a writer killed
// between naming its temporary and renaming it). Anything else, links included, is left alone.
void remove_stale(int dirfd, const std::string& base) {
  const int fd = ::openat(dirfd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  DIR* d = ::fdopendir(fd);
  if (!d) return (void)::close(fd);
  const std::string prefix = "." + base + ".";
  while (const dirent* e = ::readdir(d)) {
    const std::string_view n = e->d_name;
    if (n.size() <= prefix.size() + 4 || n.substr(0, prefix.size()) != prefix || !n.ends_with(".tmp")) continue;
    const std::string id(n.substr(prefix.size(), n.size() - prefix.size() - 4));
    char* end = nullptr;
    const long pid = std::strtol(id.c_str(), &end, 10);
    if (pid <= 0 || *end != '-' || end[1] == '\0' || std::strspn(end + 1, "0123456789") != std::strlen(end + 1))
      continue;
    if (pid == ::getpid() || ::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    struct stat st{};
    if (::fstatat(dirfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISREG(st.st_mode) && st.st_uid == ::geteuid())
      ::unlinkat(dirfd, e->d_name, 0);
  }
  ::closedir(d);
}

void write_all(int fd, const void* data, size_t size, const std::string& path) {
  const auto* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw IoError(path + ": cannot write: " + (n < 0 ? reason() : "no progress"));
    p += n;
    size -= static_cast<size_t>(n);
  }
}

// The streaming form's sink: each piece goes to the temporary as it comes.
class FdSink final : public FileSink {
 public:
  FdSink(int fd, const std::string& path) : fd_(fd), path_(path) {}
  void write(const void* data, size_t size) override { write_all(fd_, data, size, path_); }

 private:
  int fd_;
  const std::string& path_;
};

// Creates the temporary: unnamed where the file system allows, else under a fresh name.
void create(Temp& t, int dirfd, const std::string& path) {
  t.fd = ::openat(dirfd, ".", O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
  if (t.fd >= 0) return;
  if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL)
    throw IoError(path + ": cannot create a temporary file in " + t.dir + ": " + reason());
  for (unsigned tries = 0; tries < kMaxNames; ++tries) {
    t.name = std::filesystem::path(temporary_name(path, ::getpid(), next_name++)).filename().string();
    t.fd = ::openat(dirfd, t.name.c_str(), O_CREAT | O_EXCL | O_NOFOLLOW | O_WRONLY | O_CLOEXEC, 0666);
    if (t.fd >= 0) return void(t.named = true);
    if (errno != EEXIST) throw IoError(path + ": cannot create " + t.dir + "/" + t.name + ": " + reason());
  }
  throw IoError(path + ": cannot create a temporary file: " + std::to_string(kMaxNames) + " names taken in " + t.dir);
}

// Gives an unnamed temporary its name (never replacing anything that exists).
void name(Temp& t, int dirfd, const std::string& path) {
  if (t.named) return;
  const std::string self = "/proc/self/fd/" + std::to_string(t.fd);
  for (unsigned tries = 0; tries < kMaxNames; ++tries) {
    t.name = std::filesystem::path(temporary_name(path, ::getpid(), next_name++)).filename().string();
    if (::linkat(AT_FDCWD, self.c_str(), dirfd, t.name.c_str(), AT_SYMLINK_FOLLOW) == 0) return void(t.named = true);
    // Without /proc, the descriptor itself (allowed to privileged processes only).
    if (errno == ENOENT && ::linkat(t.fd, "", dirfd, t.name.c_str(), AT_EMPTY_PATH) == 0) return void(t.named = true);
    if (errno != EEXIST) throw IoError(path + ": cannot name the temporary file in " + t.dir + ": " + reason());
  }
  throw IoError(path + ": cannot name the temporary file: " + std::to_string(kMaxNames) + " names taken in " + t.dir);
}

struct Dirs {
  std::vector<std::string> names;
  std::vector<int> fds;
  int open(const std::string& dir, const std::string& path) {
    for (size_t k = 0; k < names.size(); ++k)
      if (names[k] == dir) return fds[k];
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) throw IoError(path + ": cannot open its directory " + dir + ": " + reason());
    names.push_back(dir);
    fds.push_back(fd);
    return fd;
  }
  ~Dirs() {
    for (int fd : fds) ::close(fd);
  }
};

}  // namespace

std::string temporary_name(const std::string& path, long pid, unsigned k) {
  const std::filesystem::path p(path);
  const std::string file = "." + p.filename().string() + "." + std::to_string(pid) + "-" + std::to_string(k) + ".tmp";
  return p.has_parent_path() ? (p.parent_path() / file).string() : file;
}

void write_file_atomic(const std::string& path, const void* data, size_t size) {
  const FileBytes one{path, data, size};
  write_files_atomic({&one, 1});
}

namespace {

// write_files_atomic() with each file's bytes written by @p fill(k, fd) into its temporary.
void write_atomic(size_t count, const std::function<const std::string&(size_t)>& path_of,
                  const std::function<void(size_t, int)>& fill) {
  Dirs dirs;
  std::vector<Temp> temps(count);
  std::vector<int> dirfd(count);
  auto cleanup = [&] {
    for (size_t k = 0; k < temps.size(); ++k) {
      if (temps[k].named) ::unlinkat(dirfd[k], temps[k].name.c_str(), 0);
      if (temps[k].fd >= 0) ::close(temps[k].fd);
      temps[k] = Temp{};
    }
  };
  try {
    for (size_t k = 0; k < count; ++k) {
      const std::string& path = path_of(k);
      if (path.empty() || std::filesystem::path(path).filename().empty())
        throw IoError("'" + path + "': not a file name");
      temps[k].dir = dir_of(path);
      temps[k].base = std::filesystem::path(path).filename().string();
      dirfd[k] = dirs.open(temps[k].dir, path);
      remove_stale(dirfd[k], temps[k].base);
      create(temps[k], dirfd[k], path);
      fill(k, temps[k].fd);
      if (::fsync(temps[k].fd) != 0) throw IoError(path + ": cannot flush to disk: " + reason());
    }
    for (size_t k = 0; k < count; ++k) name(temps[k], dirfd[k], path_of(k));
  } catch (...) {
    cleanup();
    throw;
  }
  // Side files first, the main file last: a reader that sees the new main file sees its side files.
  for (size_t j = count; j-- > 0;) {
    if (::renameat(dirfd[j], temps[j].name.c_str(), dirfd[j], temps[j].base.c_str()) != 0) {
      const std::string why = reason();
      cleanup();
      throw IoError(path_of(j) + ": cannot rename " + temps[j].dir + "/" + temps[j].name + " over it: " + why);
    }
    temps[j].named = false;
  }
  for (Temp& t : temps) ::close(t.fd), t.fd = -1;
  for (size_t k = 0; k < dirs.fds.size(); ++k)
    if (::fsync(dirs.fds[k]) != 0 && errno != EINVAL)  // the rename must reach the disk too
      throw IoError(path_of(0) + ": cannot flush its directory " + dirs.names[k] + ": " + reason());
}

}  // namespace

void write_files_atomic(std::span<const FileBytes> files) {
  write_atomic(
      files.size(), [&](size_t k) -> const std::string& { return files[k].path; },
      [&](size_t k, int fd) { write_all(fd, files[k].data, files[k].size, files[k].path); });
}

void write_file_atomic(const std::string& path, const std::function<void(FileSink&)>& produce) {
  write_atomic(
      1, [&](size_t) -> const std::string& { return path; },
      [&](size_t, int fd) {
        FdSink sink(fd, path);
        produce(sink);
      });
}

}  // namespace hdm
