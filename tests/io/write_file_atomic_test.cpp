// SPDX-License-Identifier: MIT
// write_file_atomic / write_files_atomic (docs/reliability.md): a planted link or file at any
// temporary name is never followed or replaced; concurrent writers of one file each succeed or fail
// cleanly and leave a whole file; a dead writer's named temporary is removed by the next write and
// nothing else is; a write that runs out of space (a file size limit standing in for a full file
// system) or meets a directory it may not write leaves the old files and nothing new.
#include <hdm/core/error.h>
#include <hdm/core/write_file_atomic.h>

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace hdm {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// A fresh directory per test.
fs::path scratch(const char* name) {
  const fs::path d = fs::temp_directory_path() / ("hdm-atomic-" + std::string(name) + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// Every entry of @p dir but the ones named in @p expected.
std::vector<std::string> others(const fs::path& dir, const std::vector<std::string>& expected) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (std::find(expected.begin(), expected.end(), n) == expected.end()) out.push_back(n);
  }
  return out;
}

TEST(WriteFileAtomic, PlantedLinksAndFilesAtTemporaryNamesAreNeverFollowedOrReplaced) {
  const fs::path d = scratch("planted");
  const fs::path out = d / "model.hdm", victim = d / "victim.txt";
  put(victim, "victim");
  put(out, "old");
  // Links (to the victim) and files at the first 400 names of this process: every name the next
  // writes can take, wherever the process's counter stands (it counts up from 0 per process).
  for (unsigned k = 0; k < 400; ++k) {
    const fs::path t = temporary_name(out.string(), ::getpid(), k);
    if (k % 2) fs::create_symlink(victim, t);
    else put(t, "planted");
  }
  // Whether a write finds a free name (past the planted ones) or gives up after 100 taken names,
  // nothing planted changes, the victim keeps its bytes, and the output is old or new.
  int written = 0;
  for (int i = 0; i < 6; ++i) {
    try {
      write_file_atomic(out.string(), "new", 3);
      ++written;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find("names taken"), std::string::npos) << e.what();
    }
    EXPECT_EQ(slurp(victim), "victim");
    const std::string now = slurp(out);
    EXPECT_TRUE(now == "old" || now == "new") << now;
  }
  for (unsigned k = 0; k < 400; ++k) {
    const fs::path t = temporary_name(out.string(), ::getpid(), k);
    if (k % 2) {
      EXPECT_TRUE(fs::is_symlink(t)) << t;
    } else {
      EXPECT_EQ(slurp(t), "planted") << t;
    }
  }
  EXPECT_EQ(others(d, {}).size(), 402u);  // the planted names, the victim and the output: nothing new
  fs::remove_all(d);
}

TEST(WriteFileAtomic, ConcurrentWritersOfOneFileLeaveOneWholeFileAndNoTemporary) {
  const fs::path d = scratch("concurrent");
  const fs::path out = d / "out.bin";
  std::vector<std::string> contents;
  for (int i = 0; i < 20; ++i) contents.push_back(std::string(100000 + 1000 * i, char('a' + i)));
  std::vector<std::thread> writers;
  std::vector<int> ok(contents.size(), 0);
  for (size_t i = 0; i < contents.size(); ++i)
    writers.emplace_back([&, i] {
      try {
        write_file_atomic(out.string(), contents[i].data(), contents[i].size());
        ok[i] = 1;
      } catch (const IoError&) {
        ok[i] = -1;  // a clean failure is allowed; none is expected here
      }
    });
  for (auto& t : writers) t.join();
  for (int v : ok) EXPECT_EQ(v, 1);
  const std::string now = slurp(out);
  EXPECT_NE(std::find(contents.begin(), contents.end(), now), contents.end()) << "a torn or mixed file";
  EXPECT_TRUE(others(d, {"out.bin"}).empty());
  fs::remove_all(d);
}

// A process id that is not running: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t p = ::fork();
  if (p == 0) ::_exit(0);
  ::waitpid(p, nullptr, 0);
  return p;
}

TEST(WriteFileAtomic, ADeadWritersTemporaryIsRemovedAndNothingElse) {
  const fs::path d = scratch("stale");
  const fs::path out = d / "out.hdm";
  const pid_t dead = dead_pid();
  const fs::path stale = temporary_name(out.string(), dead, 3);
  const fs::path live = temporary_name(out.string(), 1, 0);  // pid 1 is running
  const fs::path link = temporary_name(out.string(), dead, 4);
  const fs::path other = temporary_name((d / "other.hdm").string(), dead, 0);
  put(stale, "half a model");
  put(live, "another writer's");
  put(d / "victim", "victim");
  fs::create_symlink(d / "victim", link);
  put(other, "another file's");
  write_file_atomic(out.string(), "model", 5);
  EXPECT_EQ(slurp(out), "model");
  EXPECT_FALSE(fs::exists(fs::symlink_status(stale))) << "the dead writer's temporary was left";
  EXPECT_EQ(slurp(live), "another writer's");
  EXPECT_TRUE(fs::is_symlink(link));  // not a regular file: left alone
  EXPECT_EQ(slurp(d / "victim"), "victim");
  EXPECT_EQ(slurp(other), "another file's");  // another destination's: left to its own writes
  fs::remove_all(d);
}

// Runs @p body in a child process; the child's exit status (0: the checks held).
template <class F>
int in_child(F body) {
  const pid_t p = ::fork();
  if (p == 0) ::_exit(body());
  int status = 0;
  ::waitpid(p, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 100 + WTERMSIG(status);
}

TEST(WriteFilesAtomic, ASetThatRunsOutOfSpaceLeavesTheOldFilesAndNothingNew) {
  const fs::path d = scratch("full");
  put(d / "a.obj", "old obj");
  const std::string big(1 << 20, 'x'), small = "mtl";
  // A file size limit of 64 KiB: the big file's write fails with EFBIG as on a full file system
  // (SIGXFSZ ignored, so the write returns the error instead of killing the process).
  const int rc = in_child([&] {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{64 << 10, 64 << 10};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const FileBytes set[] = {{(d / "a.obj").string(), big.data(), big.size()},
                             {(d / "a.mtl").string(), small.data(), small.size()}};
    try {
      write_files_atomic(set);
    } catch (const IoError& e) {
      return std::string(e.what()).find("a.obj") != std::string::npos ? 0 : 2;
    }
    return 1;
  });
  EXPECT_EQ(rc, 0) << "1: the write succeeded; 2: the error does not name the file";
  EXPECT_EQ(slurp(d / "a.obj"), "old obj");
  EXPECT_TRUE(others(d, {"a.obj"}).empty()) << "a side file or a temporary was left";
  fs::remove_all(d);
}

TEST(WriteFilesAtomic, ADirectoryItMayNotWriteLeavesNothingNew) {
  const fs::path d = scratch("readonly");
  put(d / "a.png", "old");
  // As root permissions do not apply: the child drops to an unprivileged user first.
  fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                         fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  const int rc = in_child([&] {
    if (::geteuid() == 0 && (::setgid(65534) != 0 || ::setuid(65534) != 0)) return 3;
    try {
      write_file_atomic((d / "a.png").string(), "new", 3);
    } catch (const IoError& e) {
      return std::string(e.what()).find("a.png") != std::string::npos ? 0 : 2;
    }
    return 1;
  });
  fs::permissions(d, fs::perms::owner_all);
  EXPECT_EQ(rc, 0) << "1: the write succeeded; 2: the error does not name the file; 3: no user to drop to";
  EXPECT_EQ(slurp(d / "a.png"), "old");
  EXPECT_TRUE(others(d, {"a.png"}).empty());
  fs::remove_all(d);
}

TEST(WriteFileAtomic, StreamedPiecesMakeTheFileAndAThrowingProducerLeavesTheOldOne) {
  // The streaming form: pieces of any size, in order, give the same file as one buffer; a
  // producer that throws half way leaves the old file and no temporary, and its exception comes out.
  const fs::path d = scratch("stream");
  const fs::path f = d / "m.hdm";
  put(f, "old");
  std::string expected;
  for (int k = 0; k < 5000; ++k) expected += std::to_string(k * 7919) + (k % 3 ? "," : "\n");
  write_file_atomic(f.string(), [&](FileSink& sink) {
    for (size_t at = 0, len = 1; at < expected.size(); at += len, len = len * 2 + 1)
      sink.write(expected.data() + at, std::min(len, expected.size() - at));
  });
  EXPECT_EQ(slurp(f), expected);
  EXPECT_THROW(write_file_atomic(f.string(),
                                 [&](FileSink& sink) {
                                   sink.write("partial", 7);
                                   throw IoError("producer failed");
                                 }),
               IoError);
  EXPECT_EQ(slurp(f), expected);
  EXPECT_TRUE(others(d, {"m.hdm"}).empty());
  fs::remove_all(d);
}

}  // namespace
}  // namespace hdm
