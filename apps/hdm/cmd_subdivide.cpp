// SPDX-License-Identifier: MIT
// hdm subdivide INPUT -o OUT.off --min-triangles N: √3 subdivision (CGAL) of a mesh, to make large
// test and benchmark inputs from the real models.
#include "commands.h"
#include "output_guard.h"

#include <hdm/core/error.h>
#include <hdm/io/hdm_file.h>
#include <hdm/io/read_mesh.h>
#include <hdm/mesh/repair_mesh.h>
#include <hdm/mesh/subdivide_mesh.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace hdm::app {
namespace {

struct SubdivideArgs {
  std::string input, output;
  int64_t min_triangles = 1000000;
  bool json = false, no_repair = false;
  InputLimit limit;
};

// OFF text with shortest round-trip decimals (std::to_chars), so reading it back gives the same
// doubles.
std::string off_text(const TriangleMesh& m) {
  std::string s = "OFF\n" + std::to_string(m.vertices.size()) + " " + std::to_string(m.faces.size()) + " 0\n";
  s.reserve(s.size() + 64 * m.vertices.size() + 32 * m.faces.size());
  char buf[32];
  for (const Vec3& p : m.vertices) {
    for (int a = 0; a < 3; ++a) {
      const auto r = std::to_chars(buf, buf + sizeof buf, p[a]);
      s.append(buf, r.ptr);
      s.push_back(a < 2 ? ' ' : '\n');
    }
  }
  for (const Tri& t : m.faces) {
    s += "3";
    for (int32_t v : t) {
      s.push_back(' ');
      const auto r = std::to_chars(buf, buf + sizeof buf, v);
      s.append(buf, r.ptr);
    }
    s.push_back('\n');
  }
  return s;
}

void run_subdivide(const SubdivideArgs& a) {
  std::string ext = std::filesystem::path(a.output).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".off") throw InvalidInput(a.output + ": hdm subdivide writes OFF files (.off)");
  check_outputs({a.output}, {a.input});
  const auto start = std::chrono::steady_clock::now();
  TriangleMesh mesh = read_mesh(a.input, {a.limit.bytes()});
  const auto input_triangles = static_cast<int64_t>(mesh.faces.size());
  bool repaired = false;
  if (!a.no_repair && needs_repair(mesh)) {
    mesh = repair_mesh(mesh, a.input);
    repaired = true;
  }
  int steps = 0;
  const TriangleMesh out = subdivide_mesh(mesh, a.min_triangles, &steps);
  const std::string text = off_text(out);
  write_file_atomic(a.output, text.data(), text.size());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (a.json) {
    const nlohmann::json j = {{"input", a.input},
                              {"output", a.output},
                              {"input_triangles", input_triangles},
                              {"repaired", repaired},
                              {"steps", steps},
                              {"triangles", out.faces.size()},
                              {"vertices", out.vertices.size()},
                              {"seconds", seconds}};
    std::printf("%s\n", j.dump(2).c_str());
    return;
  }
  std::printf("subdivided %s -> %s\n", a.input.c_str(), a.output.c_str());
  std::printf("  triangles   %lld -> %zu (%d sqrt(3) steps%s)\n", (long long)input_triangles, out.faces.size(), steps,
              repaired ? ", input repaired first" : "");
  std::printf("  vertices    %zu\n", out.vertices.size());
  std::printf("  time        %.2f s\n", seconds);
}

}  // namespace

void add_subdivide_command(CLI::App& app) {
  auto a = std::make_shared<SubdivideArgs>();
  CLI::App* cmd =
      app.add_subcommand("subdivide", "Refine a mesh with sqrt(3) subdivision (CGAL) to at least N triangles (.off)");
  cmd->add_option("input", a->input, "input mesh (OBJ, PLY, OFF, STL)")->required();
  cmd->add_option("-o,--output", a->output, "output mesh (.off)")->required();
  cmd->add_option("--min-triangles", a->min_triangles, "wanted triangle count (default 1000000)")
      ->check(CLI::Range(int64_t(0), int64_t(1) << 30));
  cmd->add_flag("--no-repair", a->no_repair, "refuse a dirty mesh instead of repairing it first");
  cmd->add_flag("--json", a->json, "print the report as one JSON object");
  add_input_limit(cmd, a->limit);
  cmd->callback([a] { run_subdivide(*a); });
}

}  // namespace hdm::app
