#include "sear/run_folder.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace sear {
namespace {

namespace fs = std::filesystem;

// Names are printable UTF-8 of any kind (a project's name may hold spaces or a slash); a folder
// name keeps letters, digits, '-', '_' and '.', and may not start with '.' (hidden, or "..").
std::string folder_name(const std::string& name) {
  std::string safe;
  for (const char c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
                       c == '_' || c == '.';
    safe += plain ? c : '_';
  }
  if (safe.empty()) safe = "run";
  if (safe[0] == '.') safe[0] = '_';
  if (safe == "latest") safe = "latest_";  // the link's own name
  return safe;
}

}  // namespace

std::string default_run_folder(const std::string& name, bool view) {
  return (fs::path(kOutputRoot) / (folder_name(name) + (view ? ".view" : ""))).string();
}

void prepare_run_folder(const std::string& dir) {
  const fs::path folder(dir);
  std::error_code error;
  // Runs of SEAR before the mark left world.json first and summary.json last: such a folder is a
  // run's too (as `sear test`'s case folders from an earlier version are).
  const bool earlier_run = fs::exists(folder / kRunFolderMark, error) ||
                           (fs::exists(folder / "world.json", error) && fs::exists(folder / "summary.json", error));
  if (earlier_run) {
    // An earlier run's folder: all of it was that run's (cross-checks hold two runs' folders).
    for (const auto& entry : fs::directory_iterator(folder)) fs::remove_all(entry.path());
  } else if (fs::is_directory(folder, error)) {
    for (const auto& entry : fs::directory_iterator(folder))
      throw std::runtime_error(fmt::format(
          "{}: error: the output folder holds files that are not a SEAR run's (such as {}); a run writes into a new "
          "or empty folder, or one an earlier run wrote (which it empties first): name another with --out",
          dir, entry.path().filename().string()));
  }
  fs::create_directories(folder, error);
  if (error) throw std::runtime_error(fmt::format("{}: error: cannot create the output folder ({})", dir, error.message()));
  std::ofstream mark(folder / kRunFolderMark);
  mark << "A SEAR run's output folder: the next run into it empties it first.\n";
  if (!mark) throw std::runtime_error(fmt::format("{}: error: cannot write into the output folder", dir));
}

void point_latest_at(const std::string& dir) {
  const fs::path root = fs::path(dir).parent_path();
  const fs::path link = root / "latest";
  const fs::path scratch = root / fmt::format(".latest-{}", getpid());
  std::error_code error;
  fs::remove(scratch, error);
  fs::create_directory_symlink(fs::path(dir).filename(), scratch, error);
  // rename() replaces the old link in one step: a reader sees the old run or the new, never none.
  if (!error) fs::rename(scratch, link, error);
  if (error) {
    const std::string why = error.message();
    fs::remove(scratch, error);
    fmt::print(stderr, "sear: warning: cannot point {} at {} ({})\n", link.string(), dir, why);
  }
}

}  // namespace sear
