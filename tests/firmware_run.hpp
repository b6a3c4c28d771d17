// Runs the `sear` program on a project written by a test, as a user would, and reads back what the
// run wrote: the helpers the firmware tests share.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace sear::test {

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct SearRun {
  int exit_code;
  std::string out;
  std::string err;
  std::filesystem::path dir;  // the output folder
  std::string file(const std::string& name) const { return read_file(dir / name); }
};

// A flat world with the bundled rover at the origin facing east, carrying `mcus` (XML), and any
// extra obstacles in `world_extra`.
inline std::string rover_project(const std::string& mcus, const std::string& world_extra = "",
                                 double duration_s = 1.05) {
  std::ostringstream p;
  p << "<project name=\"test\">\n"
    << "  <run duration=\"" << duration_s << "\" seed=\"1\" trace_rate=\"10\"/>\n"
    << "  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n" << world_extra << "  </world>\n"
    << "  <robot file=\"" << SEAR_ASSET_DIR << "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n"
    << mcus << "  </robot>\n</project>\n";
  return p.str();
}

// Writes `project` into `dir` and runs `sear run` on it with `args`; output goes to dir/out.
inline SearRun run_sear(const TempDir& dir, const std::string& project, const std::string& args = "") {
  const auto project_file = dir.path() / "project.xml";
  std::ofstream(project_file) << project;
  const auto out = dir.path() / "out";
  const std::string cmd = std::string(SEAR_BINARY) + " run " + project_file.string() + " -o " + out.string() + " " +
                          args + " >" + (dir.path() / "stdout").string() + " 2>" + (dir.path() / "stderr").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(dir.path() / "stdout"),
          read_file(dir.path() / "stderr"), out};
}

// Names a parameterised test's cases by their number, for ctest.
template <class T>
std::string case_name(const ::testing::TestParamInfo<T>& param) {
  return "Case" + std::to_string(param.index);
}

inline std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace sear::test
