// SPDX-License-Identifier: MIT
#pragma once
// Internal, for the CGAL translation units only: CGAL 5.5's experimental autorefine run in a child
// process, so that an input it cannot take costs the step and not the process.
//
// Why a process: autorefine assumes that no input vertex becomes two different intersection
// points. Rounding breaks that on some inputs (three thin parts whose faces cross nearly in one
// plane at a shared corner); CGAL checks it only in debug builds, and a release build then either
// goes on and gives a usable refinement (most real scans where it happens, diplodocus.off among
// them) or dereferences a null face in its 2D constrained triangulation and crashes. Which of the
// two follows cannot be told beforehand, and turning CGAL's checks on refuses the good cases too.

#include <CGAL/Polygon_mesh_processing/corefinement.h>

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <cstdint>
#include <vector>

namespace hdm::mesh::detail {

// Writes @p size bytes to @p fd, retrying short writes; false on an error.
inline bool write_all(int fd, const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t k = ::write(fd, p, size);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k, size -= size_t(k);
  }
  return true;
}

// Reads @p fd to its end into @p out; false on an error.
inline bool read_all(int fd, std::vector<char>& out) {
  char buffer[1 << 16];
  for (;;) {
    const ssize_t k = ::read(fd, buffer, sizeof buffer);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) return false;
    if (k == 0) return true;
    out.insert(out.end(), buffer, buffer + k);
  }
}

// The child's side: refines @p sm and writes its vertices (x, y, z doubles) and triangles (three
// uint32 ids) to @p fd, with the two counts first. Never returns.
template <class SurfaceMesh>
[[noreturn]] void autorefine_child(SurfaceMesh& sm, int fd) {
  int status = 2;
  try {
    CGAL::Polygon_mesh_processing::experimental::autorefine(sm);
    sm.collect_garbage();
    const uint64_t counts[2] = {sm.number_of_vertices(), sm.number_of_faces()};
    bool ok = write_all(fd, counts, sizeof counts);
    for (auto v : sm.vertices()) {
      const double xyz[3] = {sm.point(v).x(), sm.point(v).y(), sm.point(v).z()};
      ok = ok && write_all(fd, xyz, sizeof xyz);
    }
    for (auto f : sm.faces()) {
      uint32_t t[3] = {0, 0, 0};
      int k = 0;
      for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[k < 3 ? k++ : 2] = uint32_t(v.idx());
      ok = ok && k == 3 && write_all(fd, t, sizeof t);
    }
    status = ok ? 0 : 3;
  } catch (...) {  // CGAL's refinement throws on inputs it recognises it cannot take
  }
  ::_exit(status);  // no atexit handlers, no stdio flush: the parent owns those
}

// Rebuilds @p sm from what autorefine_child() wrote; false when the data are incomplete or a
// face cannot be added.
template <class SurfaceMesh>
bool rebuild_from(const std::vector<char>& data, SurfaceMesh& sm) {
  uint64_t counts[2];
  if (data.size() < sizeof counts) return false;
  std::memcpy(counts, data.data(), sizeof counts);
  const uint64_t nv = counts[0], nf = counts[1];
  if (data.size() != sizeof counts + nv * 3 * sizeof(double) + nf * 3 * sizeof(uint32_t)) return false;
  sm.clear();
  const char* p = data.data() + sizeof counts;
  for (uint64_t i = 0; i < nv; ++i, p += 3 * sizeof(double)) {
    double xyz[3];
    std::memcpy(xyz, p, sizeof xyz);
    sm.add_vertex(typename SurfaceMesh::Point(xyz[0], xyz[1], xyz[2]));
  }
  using Vertex = typename SurfaceMesh::Vertex_index;
  for (uint64_t i = 0; i < nf; ++i, p += 3 * sizeof(uint32_t)) {
    uint32_t t[3];
    std::memcpy(t, p, sizeof t);
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv) return false;
    if (sm.add_face(Vertex(t[0]), Vertex(t[1]), Vertex(t[2])) == SurfaceMesh::null_face()) return false;
  }
  return true;
}

// Autorefines @p sm (CGAL::Polygon_mesh_processing::experimental::autorefine()) in a forked child
// process and takes its result back through a pipe. Returns false, @p sm unchanged or cleared,
// when the refinement throws, the child crashes, or no child can be started. O(the refinement +
// a copy of the result); the child shares the parent's memory copy-on-write and runs no thread.
template <class SurfaceMesh>
bool autorefine_apart(SurfaceMesh& sm) {
  int fd[2];
  if (::pipe(fd) != 0) return false;
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fd[0]), ::close(fd[1]);
    return false;
  }
  if (pid == 0) {
    ::close(fd[0]);
    autorefine_child(sm, fd[1]);
  }
  ::close(fd[1]);
  std::vector<char> data;
  const bool read = read_all(fd[0], data);  // before waiting: the child blocks on a full pipe
  ::close(fd[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!read || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return false;
  return rebuild_from(data, sm);
}

}  // namespace hdm::mesh::detail
