// What `sear test DIR` runs: the scenarios found under a folder, the seeds each runs with, and the
// share of the (scenario, seed) cases one shard takes, all in an order every machine agrees on.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scene/urdf_overrides.hpp"

namespace sear {

// One scenario under the suite's folder: a *.xml file whose root is <scenario>, or a folder whose
// project.xml has an <expect> (then `path` names the folder; "." for the suite's folder itself).
struct FoundScenario {
  std::string path;  // relative to the suite's folder, '/'-separated
  bool project_folder = false;
};

// A file under the suite's folder that does not load: a *.xml that is not well-formed XML (it may
// have been meant for a scenario or a project), or a <project> that is no scenario and whose
// loader reports errors. Each is a failed case of the suite: a green suite beside a project that
// cannot even be read would be a silent mistake.
struct UnloadableFile {
  std::string path;    // relative to the suite's folder, '/'-separated
  std::string errors;  // the loader's diagnostics, "FILE:LINE: error: ..." one a line
};

// Every scenario under `dir`, sorted by path (byte order), so every machine lists the same suite;
// the files that do not load in `unloadable`, sorted the same way. Hidden folders and `skip` (the
// output folder, when it lies inside) are not searched. Projects load with `overrides` (--package, --arg).
std::vector<FoundScenario> find_scenarios(const std::filesystem::path& dir, const std::filesystem::path& skip,
                                          std::vector<UnloadableFile>& unloadable, const UrdfOverrides& overrides = {});

struct SeedRange {
  std::uint64_t first = 0;
  std::uint64_t last = 0;
};
// "A..B" (A <= B) or "A": whole decimal numbers. Empty and an error message when it is neither.
std::optional<SeedRange> parse_seed_range(const std::string& text, std::string& error);

struct Shard {
  std::size_t index = 1;  // K, 1-based
  std::size_t count = 1;  // N
};
// "K/N" with 1 <= K <= N.
std::optional<Shard> parse_shard(const std::string& text, std::string& error);

// One run: a scenario (index into the found list) with a seed from --seeds, or its own seed; or an
// unloadable file (index into that list), a case that fails without a run.
struct TestCase {
  std::size_t scenario = 0;
  std::optional<std::uint64_t> seed;
  bool unloadable = false;
};

// The cases of the whole suite, scenario by scenario and seed by seed, then each unloadable file
// once (with the first seed, if any), then the shard's share: every case i with i % N == K - 1.
std::vector<TestCase> plan_cases(std::size_t scenarios, std::size_t unloadable, const std::optional<SeedRange>& seeds,
                                 const Shard& shard);

}  // namespace sear
