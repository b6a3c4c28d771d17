// `sear test DIR`: every scenario under a folder, over a range of seeds, a shard of the suite or all
// of it, each (scenario, seed) a `sear run` of its own, several at once; one JUnit report; and
// `sear test --merge`, which joins the reports of shards into the one a single run writes.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <system_error>

#include "expect/junit_report.hpp"
#include "expect/scenario_loader.hpp"
#include "runtime/stop_request.hpp"
#include "scene/project_loader.hpp"
#include "sear/commands.hpp"
#include "sear/test_plan.hpp"
#include "sear/test_report.hpp"
#include "sear/test_runner.hpp"
#include "sear/urdf_options.hpp"

namespace sear {
namespace fs = std::filesystem;
namespace {

// Every run already takes a process per MCU besides the simulator's, so a run per core would
// have the hand-offs waiting for each other: half the cores by default.
std::size_t default_jobs() {
  cpu_set_t set;
  CPU_ZERO(&set);
  const int cores = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 1;
  return static_cast<std::size_t>(std::max(1, cores / 2));
}

// The scenario's name, project and own seed, as far as they can be read; a scenario that cannot be
// read still runs (and fails there with the loader's errors), under its file's name.
struct ScenarioInfo {
  std::string file;  // the file `sear run` reads, relative to the suite's folder
  std::string name;
  std::string project_file;
  std::uint64_t seed = RunDesc{}.seed;
};

ScenarioInfo scenario_info(const fs::path& dir, const FoundScenario& found, bool own_seed,
                           const UrdfOverrides& overrides) {
  ScenarioInfo info;
  const fs::path rel = found.project_folder ? fs::path(found.path) / "project.xml" : fs::path(found.path);
  info.file = rel.lexically_normal().generic_string();
  info.name = (found.project_folder ? (dir / found.path).lexically_normal().filename() : rel.stem()).string();
  if (info.name.empty() || info.name == ".") info.name = dir.filename().string();
  Diagnostics diagnostics;
  const auto scenario = load_scenario((dir / rel).string(), diagnostics);
  if (!scenario) return info;
  info.name = scenario->name;
  info.project_file = scenario->project_file;
  if (scenario->seed) {
    info.seed = *scenario->seed;
  } else if (own_seed) {
    if (const auto project = load_project(scenario->project_file, diagnostics, overrides)) info.seed = project->run.seed;
  }
  return info;
}

// A path as a POSIX shell reads it back: quoted only when it needs to be.
std::string shell_word(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_./-+=:,@%") ==
                           std::string::npos)
    return word;
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string plural(std::size_t n, const char* noun) { return fmt::format("{} {}{}", n, noun, n == 1 ? "" : "s"); }

std::string self_executable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error(fmt::format("cannot find the sear program itself: {}", ec.message()));
  return self.string();
}

// A fresh private folder for the runs' reports and logs, removed with them at the end.
struct ScratchFolder {
  fs::path path;
  ScratchFolder() {
    std::string pattern = (fs::temp_directory_path() / "sear-test-XXXXXX").string();
    if (!mkdtemp(pattern.data()))
      throw std::runtime_error(fmt::format("cannot create a temporary folder: {}", std::strerror(errno)));
    path = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
};

int merge_command(const std::vector<std::string>& merge) {
  const std::vector<std::string> inputs(merge.begin() + 1, merge.end());
  merge_junit(inputs, merge.front());
  const auto suites = read_junit(merge.front());
  const auto failed = std::count_if(suites.begin(), suites.end(), suite_failed);
  fmt::print("sear test: {} from {} in {}: {} passed, {} failed\n", plural(suites.size(), "case"),
             plural(inputs.size(), "report"), merge.front(), suites.size() - static_cast<std::size_t>(failed), failed);
  return failed ? kExpectationFailedExitCode : 0;
}

int suite_command(const TestOptions& options) {
  std::string error;
  std::optional<SeedRange> seeds;
  if (!options.seeds.empty() && !(seeds = parse_seed_range(options.seeds, error)))
    throw std::invalid_argument("--seeds: " + error);
  Shard shard;
  if (!options.shard.empty()) {
    const auto parsed = parse_shard(options.shard, error);
    if (!parsed) throw std::invalid_argument("--shard: " + error);
    shard = *parsed;
  }
  if (!fs::is_directory(options.dir))
    throw std::invalid_argument(fmt::format("{}: not a folder of scenarios", options.dir));
  // Canonical: every run's files name it so, and the report's paths are made relative to it.
  const fs::path dir = fs::canonical(options.dir);
  const fs::path out = fs::absolute(options.out_dir).lexically_normal();
  // The runs work in the suite's folder: the overrides' folders are absolute.
  const UrdfOverrides overrides = urdf_overrides(options.urdf_packages, options.urdf_args);
  std::vector<std::string> override_args;
  for (const auto& [name, folder] : overrides.packages) override_args.insert(override_args.end(), {"--package", name + "=" + folder});
  for (const auto& [name, value] : overrides.args) override_args.insert(override_args.end(), {"--arg", name + "=" + value});
  std::vector<UnloadableFile> unloadable;
  const auto found = find_scenarios(dir, out, unloadable, overrides);
  if (found.empty() && unloadable.empty())
    throw std::invalid_argument(fmt::format(
        "{}: no scenario found (a *.xml with a <scenario> root, or a folder whose project.xml has an <expect>)",
        options.dir));
  const auto cases = plan_cases(found.size(), unloadable.size(), seeds, shard);

  const std::string self = self_executable();
  const ScratchFolder scratch;
  std::vector<ScenarioInfo> infos(found.size());
  std::vector<bool> known(found.size(), false);
  std::vector<FinishedCase> finished(cases.size());
  std::vector<ChildRun> children;
  std::vector<std::size_t> child_case;  // the case each child runs
  std::vector<std::size_t> broken;  // the cases of unloadable files: no run
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const TestCase& c = cases[i];
    if (c.unloadable) {
      broken.push_back(i);
      continue;
    }
    if (!known[c.scenario]) infos[c.scenario] = scenario_info(dir, found[c.scenario], !seeds, overrides);
    known[c.scenario] = true;
    const ScenarioInfo& info = infos[c.scenario];
    FinishedCase& f = finished[i];
    f.scenario_path = found[c.scenario].path;
    f.scenario_file = info.file;
    f.name = info.name;
    f.project_file = info.project_file;
    f.seed = c.seed.value_or(info.seed);
    f.junit = (scratch.path / fmt::format("{}.xml", i)).string();
    f.log = (scratch.path / fmt::format("{}.log", i)).string();
    ChildRun run;
    // No plots for a suite's runs: each costs seconds of drawing; `sear run` of the reproduce line
    // draws them for the case a person looks at.
    run.argv = {self, "run", f.scenario_path, "--seed", std::to_string(f.seed), "--junit", f.junit, "-q", "--no-plots", "-o",
                (out / f.scenario_path / fmt::format("seed-{}", f.seed)).lexically_normal().string()};
    run.argv.insert(run.argv.end(), override_args.begin(), override_args.end());
    if (options.timeout_s) {
      run.argv.push_back("--timeout");
      run.argv.push_back(fmt::format("{}", *options.timeout_s));
    }
    // From the suite's folder, so that what the run writes names the scenario relative to it.
    run.cwd = dir.string();
    run.log = f.log;
    children.push_back(std::move(run));
    child_case.push_back(i);
  }

  fmt::print("sear test: {}{} from {}{} under {}, {} at once\n", plural(cases.size(), "case"),
             options.shard.empty() ? "" : fmt::format(" (shard {}/{})", shard.index, shard.count),
             plural(found.size(), "scenario"),
             unloadable.empty() ? "" : fmt::format(" and {} that do{} not load", plural(unloadable.size(), "file"),
                                                   unloadable.size() == 1 ? "es" : ""),
             options.dir, std::max<std::size_t>(options.jobs, 1));
  std::fflush(stdout);
  std::vector<JunitSuite> report;
  std::size_t done = 0, failed = 0;
  for (const std::size_t i : broken) {
    const UnloadableFile& u = unloadable[cases[i].scenario];
    JunitSuite s = unloadable_file_suite(u.path, u.errors, cases[i].seed.value_or(RunDesc{}.seed), dir);
    ++failed;
    fmt::print("[{}/{}] ERROR {}\n{}", ++done, cases.size(), u.path, failure_lines(s, "    "));
    report.push_back(std::move(s));
  }
  std::fflush(stdout);
  run_children(children, options.jobs, [&](std::size_t child, int code) {
    FinishedCase& f = finished[child_case[child]];
    f.exit_code = code;
    auto suites = finished_case_suites(f, dir);
    const bool bad = std::any_of(suites.begin(), suites.end(), suite_failed);
    failed += bad ? 1 : 0;
    std::size_t expectations = 0, unmet = 0;
    for (const auto& s : suites)
      for (const auto& k : s.cases) {
        ++expectations;
        unmet += k.failed ? 1 : 0;
      }
    const bool errored = std::any_of(suites.begin(), suites.end(), [](const JunitSuite& s) { return !s.error.empty(); });
    fmt::print("[{}/{}] {} {} seed {}: {}\n", ++done, cases.size(), !bad ? "PASS " : errored ? "ERROR" : "FAIL ",
               f.scenario_path, f.seed,
               errored ? std::string("the run could not be done")
               : bad   ? fmt::format("{} of {} expectations failed", unmet, expectations)
                       : fmt::format("{} expectations met", expectations));
    if (bad) {
      for (const auto& s : suites) fmt::print("{}", failure_lines(s, "    "));
      std::string repro = fmt::format("sear run {} --seed {}", shell_word((fs::path(options.dir) / f.scenario_path)
                                                                               .lexically_normal()
                                                                               .generic_string()),
                                      f.seed);
      if (options.timeout_s) repro += fmt::format(" --timeout {}", *options.timeout_s);
      for (std::size_t k = 0; k + 1 < override_args.size(); k += 2)
        repro += fmt::format(" {} {}", override_args[k], shell_word(override_args[k + 1]));
      fmt::print("    reproduce: {}\n", repro);
    }
    std::fflush(stdout);
    std::move(suites.begin(), suites.end(), std::back_inserter(report));
  });

  if (!options.junit.empty()) write_junit(options.junit, report);
  fmt::print("sear test: {} of {} passed, {} failed{}\n", done - failed, plural(cases.size(), "case"), failed,
             options.junit.empty() ? "" : "; JUnit report: " + options.junit);
  if (stop_requested()) {
    fmt::print(stderr, "sear test: interrupted; {} cases not run\n", cases.size() - done);
    return 128 + stop_signal();
  }
  return failed ? kExpectationFailedExitCode : 0;
}

}  // namespace

CLI::App* add_test_subcommand(CLI::App& app, TestOptions& options) {
  CLI::App* cmd = app.add_subcommand(
      "test", "Run every scenario under a folder (over seeds, in parallel, or a shard of them) and report as JUnit");
  cmd->add_option("dir", options.dir,
                  "Folder searched for scenarios: *.xml files with a <scenario> root, and folders whose project.xml "
                  "has an <expect>");
  options.jobs = default_jobs();
  cmd->add_option("-j,--jobs", options.jobs,
                  "Runs at once; each takes a process per MCU besides its own, hence half the cores by default")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}));
  cmd->add_option("--seeds", options.seeds, "Run each scenario once per seed A..B (default: once, with its own seed)")
      ->type_name("A..B");
  cmd->add_option("--shard", options.shard,
                  "Run only the share K of N of the sorted (scenario, seed) cases: case i when i % N == K - 1")
      ->type_name("K/N");
  cmd->add_option("--junit", options.junit, "Write the JUnit report of every case run here")->type_name("FILE");
  cmd->add_option("-o,--out", options.out_dir, "Output folder: each run's files in OUT/SCENARIO/seed-S")
      ->capture_default_str();
  cmd->add_option("--timeout", options.timeout_s, "Simulated seconds after which a pending expectation fails")
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            errno = 0;
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (!text.empty() && end && *end == '\0' && errno != ERANGE && std::isfinite(v) && v > 0 && v <= 1e7)
              return {};
            return fmt::format("expected a number of seconds > 0 and <= 1e7, got '{}'", text);
          },
          "SECONDS", "SECONDS"));
  CLI::Option* merge = cmd->add_option("--merge", options.merge,
                                       "Join the JUnit reports of shards (IN...) into OUT, as one run of them all "
                                       "writes it; exit code 5 when it holds a failure")
                           ->type_name("OUT IN")
                           ->expected(2, 1 << 20);
  add_urdf_options(cmd, options.urdf_packages, options.urdf_args);
  for (const char* other : {"dir", "--seeds", "--shard", "--junit", "--timeout", "--package", "--arg"})
    merge->excludes(other);
  cmd->footer("Exit code 0 when every case passed, 5 when one failed or could not be run, 1 on bad input.");
  return cmd;
}

int test_command(const TestOptions& options) {
  install_stop_signals();
  try {
    if (!options.merge.empty()) return merge_command(options.merge);
    if (options.dir.empty()) throw std::invalid_argument("a folder of scenarios is needed (or --merge)");
    return suite_command(options);
  } catch (const std::exception& e) {
    fmt::print(stderr, "sear test: error: {}\n", e.what());
    return 1;
  }
}

}  // namespace sear
