#include "sear/test_plan.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>

#include "scene/diagnostics.hpp"
#include "scene/loader_parts.hpp"
#include "scene/project_loader.hpp"

namespace sear {
namespace fs = std::filesystem;
namespace {

// The root element's name, "" when the file cannot be read as XML (`diagnostics` says why, in
// the words the project loader uses for it).
std::string root_name(const fs::path& file, const tinyxml2::XMLElement** root, tinyxml2::XMLDocument& doc,
                      Diagnostics& diagnostics) {
  std::string text;
  if (!read_text_file(file.string(), text)) {
    diagnostics.error(file.string(), 0, "cannot read the file");
    return "";
  }
  if (!parse_xml(text, file.string(), diagnostics, doc)) return "";
  *root = doc.RootElement();
  return *root ? (*root)->Name() : "";
}

std::string relative_to(const fs::path& dir, const fs::path& p) {
  const std::string rel = p.lexically_relative(dir).generic_string();
  return rel.empty() ? "." : rel;
}

// A whole decimal number 0..2^64-1; strtoull alone takes "-1" and saturates past the top.
std::optional<std::uint64_t> whole_number(const std::string& text) {
  if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) return std::nullopt;
  return static_cast<std::uint64_t>(v);
}

// More runs than a night holds even for the fastest scenario; a typo such as 1..10000000000 is caught.
constexpr std::uint64_t kMaxSeeds = 1000000;

}  // namespace

std::vector<FoundScenario> find_scenarios(const fs::path& dir, const fs::path& skip,
                                          std::vector<UnloadableFile>& unloadable, const UrdfOverrides& overrides) {
  std::vector<FoundScenario> found;
  std::error_code ec;
  const fs::path skip_canonical = fs::weakly_canonical(skip, ec);
  fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
  if (ec) throw fs::filesystem_error("cannot list the scenario folder", dir, ec);
  for (; it != end; it.increment(ec)) {
    if (ec) throw fs::filesystem_error("cannot list the scenario folder", dir, ec);
    const fs::path& p = it->path();
    const std::string filename = p.filename().string();
    if (it->is_directory(ec)) {
      if ((!filename.empty() && filename[0] == '.') || fs::weakly_canonical(p, ec) == skip_canonical)
        it.disable_recursion_pending();
      continue;
    }
    if (p.extension() != ".xml" || !it->is_regular_file(ec)) continue;
    tinyxml2::XMLDocument doc;
    const tinyxml2::XMLElement* root = nullptr;
    Diagnostics diagnostics;
    const std::string kind = root_name(p, &root, doc, diagnostics);
    if (!diagnostics.ok()) {
      unloadable.push_back({relative_to(dir, p), diagnostics.joined()});
    } else if (kind == "scenario") {
      found.push_back({relative_to(dir, p), false});
    } else if (kind == "project" && filename == "project.xml" && root->FirstChildElement("expect")) {
      found.push_back({relative_to(dir, p.parent_path()), true});
    } else if (kind == "project") {
      // No scenario of its own, so no run would read it: loaded here, so that its mistakes show.
      if (!load_project(p.string(), diagnostics, overrides)) unloadable.push_back({relative_to(dir, p), diagnostics.joined()});
    }
  }
  std::sort(found.begin(), found.end(),
            [](const FoundScenario& a, const FoundScenario& b) { return a.path < b.path; });
  std::sort(unloadable.begin(), unloadable.end(),
            [](const UnloadableFile& a, const UnloadableFile& b) { return a.path < b.path; });
  return found;
}

std::optional<SeedRange> parse_seed_range(const std::string& text, std::string& error) {
  const auto dots = text.find("..");
  const auto first = whole_number(text.substr(0, dots));
  const auto last = dots == std::string::npos ? first : whole_number(text.substr(dots + 2));
  if (first && last && *first <= *last && *last - *first < kMaxSeeds) return SeedRange{*first, *last};
  error = fmt::format("expected seeds A..B, whole numbers with A <= B and at most {} seeds (or one seed), got '{}'",
                      kMaxSeeds, text);
  return std::nullopt;
}

std::optional<Shard> parse_shard(const std::string& text, std::string& error) {
  const auto slash = text.find('/');
  const auto k = whole_number(text.substr(0, slash));
  const auto n = slash == std::string::npos ? std::nullopt : whole_number(text.substr(slash + 1));
  if (k && n && *k >= 1 && *k <= *n) return Shard{static_cast<std::size_t>(*k), static_cast<std::size_t>(*n)};
  error = fmt::format("expected a shard K/N with 1 <= K <= N, got '{}'", text);
  return std::nullopt;
}

std::vector<TestCase> plan_cases(std::size_t scenarios, std::size_t unloadable, const std::optional<SeedRange>& seeds,
                                 const Shard& shard) {
  std::vector<TestCase> cases;
  std::size_t i = 0;
  const auto add = [&](std::size_t scenario, std::optional<std::uint64_t> seed, bool broken = false) {
    if (i++ % shard.count == shard.index - 1) cases.push_back({scenario, seed, broken});
  };
  for (std::size_t s = 0; s < scenarios; ++s) {
    if (!seeds) {
      add(s, std::nullopt);
      continue;
    }
    for (std::uint64_t seed = seeds->first;; ++seed) {
      add(s, seed);
      if (seed == seeds->last) break;  // the range may end at 2^64-1
    }
  }
  // Once, whatever the seeds: a file that does not load fails the same way with every seed.
  for (std::size_t u = 0; u < unloadable; ++u)
    add(u, seeds ? std::optional<std::uint64_t>(seeds->first) : std::nullopt, true);
  return cases;
}

}  // namespace sear
