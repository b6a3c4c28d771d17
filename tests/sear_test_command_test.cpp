// `sear test DIR` as CI runs it: a folder with a passing and a failing scenario, seeds, a run that
// cannot be done, and shards run by GNU parallel whose merged report is the single run's, byte for byte.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <tinyxml2.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;

const std::string kSuite = std::string(SEAR_TEST_DATA) + "/scenarios";

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  int exit_code;
  std::string out;
};

// Runs a shell command line in `dir` and collects its exit code and output.
Result shell(const fs::path& dir, const std::string& command) {
  const std::string log = (dir / "shell.log").string();
  const int status = std::system(("cd '" + dir.string() + "' && " + command + " >'" + log + "' 2>&1").c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read(log)};
}

Result sear_test(const fs::path& dir, const std::string& args) {
  return shell(dir, std::string(SEAR_BINARY) + " test " + args);
}

struct Suite {
  std::string name;
  std::string scenario_file;
  std::string seed;
  int tests = 0, failures = 0, errors = 0;
  std::vector<std::pair<std::string, std::string>> failed;  // test case name, failure message
  std::string error;
};

struct Report {
  int tests = 0, failures = 0, errors = 0;
  std::vector<Suite> suites;
};

Report parse(const fs::path& file) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.LoadFile(file.c_str()), tinyxml2::XML_SUCCESS) << file;
  Report r;
  const auto* root = doc.RootElement();
  if (!root) return r;
  EXPECT_STREQ(root->Name(), "testsuites");
  r.tests = root->IntAttribute("tests", -1);
  r.failures = root->IntAttribute("failures", -1);
  r.errors = root->IntAttribute("errors", -1);
  for (auto* e = root->FirstChildElement("testsuite"); e; e = e->NextSiblingElement("testsuite")) {
    Suite s;
    s.name = e->Attribute("name");
    s.tests = e->IntAttribute("tests", -1);
    s.failures = e->IntAttribute("failures", -1);
    s.errors = e->IntAttribute("errors", -1);
    for (auto* p = e->FirstChildElement("properties")->FirstChildElement("property"); p;
         p = p->NextSiblingElement("property")) {
      if (std::string(p->Attribute("name")) == "scenario") s.scenario_file = p->Attribute("value");
      if (std::string(p->Attribute("name")) == "seed") s.seed = p->Attribute("value");
    }
    for (auto* c = e->FirstChildElement("testcase"); c; c = c->NextSiblingElement("testcase")) {
      if (auto* f = c->FirstChildElement("failure")) s.failed.emplace_back(c->Attribute("name"), f->Attribute("message"));
      if (auto* f = c->FirstChildElement("error")) s.error = f->Attribute("message");
    }
    r.suites.push_back(std::move(s));
  }
  return r;
}

// The suite in tests/data/scenarios: the greeter's project folder (its own <expect>, 2 expectations,
// both met, seed 3 from its <run>) and goodbye.xml on the same project (2 expectations, "says goodbye"
// never met).
constexpr int kScenarios = 2;
constexpr int kExpectationsEach = 2;

TEST(SearTestCommand, FolderWithPassingAndFailingScenario) {
  const sear::test::TempDir tmp;
  const Result r = sear_test(tmp.path(), kSuite + " -o out --junit report.xml");
  EXPECT_EQ(r.exit_code, 5) << r.out;
  const Report report = parse(tmp.path() / "report.xml");
  EXPECT_EQ(report.tests, kScenarios * kExpectationsEach);
  EXPECT_EQ(report.failures, 1);
  EXPECT_EQ(report.errors, 0);
  ASSERT_EQ(report.suites.size(), 2u) << r.out;
  // Sorted by scenario name; paths relative to the suite's folder; each run with its own seed.
  EXPECT_EQ(report.suites[0].name, "greeter (seed 3)");
  EXPECT_EQ(report.suites[0].scenario_file, "greeter/project.xml");
  EXPECT_EQ(report.suites[0].failures, 0);
  EXPECT_EQ(report.suites[1].name, "greeter says goodbye (seed 3)");
  EXPECT_EQ(report.suites[1].scenario_file, "goodbye.xml");
  EXPECT_EQ(report.suites[1].tests, kExpectationsEach);
  ASSERT_EQ(report.suites[1].failed.size(), 1u);
  EXPECT_EQ(report.suites[1].failed[0].first, "says goodbye");
  // The greeter said hello at 0.1 s and "tick" at 1.1 s; the deadline is 1.2 s.
  EXPECT_EQ(report.suites[1].failed[0].second, "no line matched among 2 by 1.200 s; the last: 'tick' at 1.100 s");
  // The failure, what was seen, and the command that does that run again.
  EXPECT_NE(r.out.find("FAIL  goodbye.xml seed 3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("says goodbye: no line matched among 2 by 1.200 s"), std::string::npos) << r.out;
  const std::string reproduce = "sear run " + kSuite + "/goodbye.xml --seed 3";
  EXPECT_NE(r.out.find("reproduce: " + reproduce + "\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("PASS  greeter seed 3"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(tmp.path() / "out/goodbye.xml/seed-3/summary.json"));
  EXPECT_TRUE(fs::exists(tmp.path() / "out/greeter/seed-3/summary.json"));
  // The line reproduces it: the same verdict, the same exit code.
  const Result again = shell(tmp.path(), std::string(SEAR_BINARY) + reproduce.substr(4) + " -q -o again");
  EXPECT_EQ(again.exit_code, 5);
  EXPECT_NE(again.out.find("says goodbye: no line matched among 2 by 1.200 s"), std::string::npos) << again.out;
}

TEST(SearTestCommand, SeedsRepeatEveryScenario) {
  const sear::test::TempDir tmp;
  const Result r = sear_test(tmp.path(), kSuite + " --seeds 1..3 -j 2 -o out --junit report.xml");
  EXPECT_EQ(r.exit_code, 5) << r.out;
  const Report report = parse(tmp.path() / "report.xml");
  constexpr int kSeeds = 3;
  EXPECT_EQ(report.tests, kScenarios * kSeeds * kExpectationsEach);
  EXPECT_EQ(report.failures, kSeeds);  // goodbye's one failure, once per seed
  std::map<std::string, std::set<std::string>> seeds;
  for (const Suite& s : report.suites) seeds[s.scenario_file].insert(s.seed);
  const std::set<std::string> expected{"1", "2", "3"};
  EXPECT_EQ(seeds["goodbye.xml"], expected);
  EXPECT_EQ(seeds["greeter/project.xml"], expected);
  EXPECT_EQ(seeds.size(), 2u);
  EXPECT_NE(r.out.find("reproduce: sear run " + kSuite + "/goodbye.xml --seed 2\n"), std::string::npos) << r.out;
}

TEST(SearTestCommand, RunThatCannotBeDoneFailsWithItsError) {
  const sear::test::TempDir tmp;
  tmp.write("suite/lost.xml", R"(<scenario name="lost" project="nowhere/project.xml">
  <expect><mcu_running mcu="rover.main"/></expect>
</scenario>
)");
  tmp.write("suite/notes/readme.xml", "<notes/>");  // XML that is no scenario: not a case
  const Result r = sear_test(tmp.path(), "suite --junit report.xml -o out");
  EXPECT_EQ(r.exit_code, 5) << r.out;
  const Report report = parse(tmp.path() / "report.xml");
  EXPECT_EQ(report.tests, 1);
  EXPECT_EQ(report.errors, 1);
  ASSERT_EQ(report.suites.size(), 1u);
  EXPECT_EQ(report.suites[0].name, "lost (seed 1)");  // the default seed: the project could not be read
  EXPECT_NE(report.suites[0].error.find("sear run exited with code 1"), std::string::npos) << report.suites[0].error;
  EXPECT_NE(report.suites[0].error.find("lost.xml:1: error: <scenario> project file 'nowhere/project.xml' not found"),
            std::string::npos)
      << report.suites[0].error;
  EXPECT_NE(r.out.find("reproduce: sear run suite/lost.xml --seed 1"), std::string::npos) << r.out;
}

// Issue 22: a project beside the suite's scenarios that does not load is a failed case, not a
// warning above a green suite. The greeter's folder (which passes) sits in tests/data/ beside a
// link to the assets, as its project reaches the robot at ../../../../assets.
TEST(SearTestCommand, FileThatDoesNotLoadIsAFailedCase) {
  const sear::test::TempDir tmp;
  fs::create_directories(tmp.path() / "tests/data/scenarios");
  fs::copy(kSuite + "/greeter", tmp.path() / "tests/data/scenarios/greeter", fs::copy_options::recursive);
  fs::create_directory_symlink(fs::path(SEAR_TEST_DATA).parent_path().parent_path() / "assets", tmp.path() / "assets");
  // <world> (line 3) is never closed: </project> on line 6 comes where </world> belongs.
  tmp.write("tests/data/scenarios/broken/project.xml", R"(<project name="broken">
  <run duration="2"/>
  <world step="0.001">
    <terrain type="flat"/>
  <robot file="../../../../assets/robots/rover.xml"/>
</project>
)");
  // Well-formed, no scenario of its own, and a misspelt attribute the loader refuses.
  tmp.write("tests/data/scenarios/lib/arena.xml", R"(<project name="arena">
  <world><terrain type="flat" colour="red"/></world>
</project>
)");
  const Result r = sear_test(tmp.path(), "tests/data/scenarios --seeds 1..2 -o out --junit report.xml");
  EXPECT_EQ(r.exit_code, 5) << r.out;
  EXPECT_NE(r.out.find("4 cases from 1 scenario and 2 files that do not load"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ERROR broken/project.xml\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ERROR lib/arena.xml\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 of 4 cases passed, 2 failed"), std::string::npos) << r.out;
  const Report report = parse(tmp.path() / "report.xml");
  // The greeter's 2 expectations with each of 2 seeds, and one error case per file, whatever the seeds.
  EXPECT_EQ(report.tests, 2 * 2 + 2);
  EXPECT_EQ(report.failures, 0);
  EXPECT_EQ(report.errors, 2);
  ASSERT_EQ(report.suites.size(), 4u) << r.out;
  const Suite& broken = report.suites[0];  // sorted by name: "broken/..." < "greeter" < "lib/..."
  EXPECT_EQ(broken.scenario_file, "broken/project.xml");
  EXPECT_EQ(broken.errors, 1);
  EXPECT_NE(broken.error.find("broken/project.xml:3: error: malformed XML: <world> is never closed: </project> on "
                              "line 6 comes before its </world>"),
            std::string::npos)
      << broken.error;
  const Suite& arena = report.suites[3];
  EXPECT_EQ(arena.scenario_file, "lib/arena.xml");
  EXPECT_NE(arena.error.find("lib/arena.xml:2: error: unknown attribute 'colour' on <terrain>"), std::string::npos)
      << arena.error;
  // One shard of two takes the first and third of the 4 cases: a greeter run and a file's error.
  const Result shard = sear_test(tmp.path(), "tests/data/scenarios --seeds 1..2 --shard 1/2 -o out1");
  EXPECT_EQ(shard.exit_code, 5) << shard.out;
  EXPECT_NE(shard.out.find("1 of 2 cases passed, 1 failed"), std::string::npos) << shard.out;
}

TEST(SearTestCommand, BadArgumentsAreRefused) {
  const sear::test::TempDir tmp;
  for (const std::string& args : {kSuite + " --shard 0/3", kSuite + " --shard 4/3", kSuite + " --seeds 5..2",
                                 kSuite + " --seeds 1..x", tmp.path().string() + "/missing"}) {
    const Result r = sear_test(tmp.path(), args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.out;
  }
  tmp.write("empty/world.xml", "<world/>");
  const Result empty = sear_test(tmp.path(), "empty");
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.out.find("no scenario found"), std::string::npos) << empty.out;
}

// Copies of the suite at three places, as on three machines: the greeter's project reaches the
// robot at ../../../../assets, so each copy sits in tests/data/ beside a link to the assets.
fs::path machine(const fs::path& root, int k) {
  const fs::path base = root / ("machine" + std::to_string(k));
  fs::create_directories(base / "tests/data");
  fs::copy(kSuite, base / "tests/data/scenarios", fs::copy_options::recursive);
  fs::create_directory_symlink(fs::path(SEAR_TEST_DATA).parent_path().parent_path() / "assets", base / "assets");
  return base / "tests/data/scenarios";
}

TEST(SearTestCommand, ShardsByGnuParallelMergeIntoTheSingleRunsReport) {
  if (shell(fs::temp_directory_path(), "command -v parallel").exit_code != 0)
    GTEST_SKIP() << "GNU parallel is not installed (Debian package parallel)";
  const sear::test::TempDir tmp;
  for (int k = 1; k <= 3; ++k) machine(tmp.path(), k);
  const std::string seeds = " --seeds 1..4";
  const Result single = sear_test(tmp.path(), kSuite + seeds + " -o single --junit single.xml");
  EXPECT_EQ(single.exit_code, 5) << single.out;
  const Result shards = shell(tmp.path(), "parallel " + std::string(SEAR_BINARY) + " test machine{}/tests/data/scenarios" +
                                              seeds + " --shard {}/3 -o out{} --junit shard{}.xml ::: 1 2 3");
  // parallel's exit code: how many jobs failed. Every shard holds a failing goodbye case.
  EXPECT_EQ(shards.exit_code, 3) << shards.out;
  // Every case exactly once over the shards, in shares of 8 cases dealt round-robin: 3, 3, 2.
  std::multiset<std::pair<std::string, std::string>> cases;
  const std::size_t shares[] = {3, 3, 2};
  for (int k = 1; k <= 3; ++k) {
    const Report shard = parse(tmp.path() / ("shard" + std::to_string(k) + ".xml"));
    EXPECT_EQ(shard.suites.size(), shares[k - 1]) << k;
    for (const Suite& s : shard.suites) cases.emplace(s.scenario_file, s.seed);
  }
  std::multiset<std::pair<std::string, std::string>> all;
  for (const Suite& s : parse(tmp.path() / "single.xml").suites) all.emplace(s.scenario_file, s.seed);
  EXPECT_EQ(all.size(), static_cast<std::size_t>(kScenarios * 4));
  EXPECT_EQ(cases, all);
  const Result merge = sear_test(tmp.path(), "--merge merged.xml shard1.xml shard2.xml shard3.xml");
  EXPECT_EQ(merge.exit_code, 5) << merge.out;
  const std::string merged = read(tmp.path() / "merged.xml");
  EXPECT_FALSE(merged.empty());
  EXPECT_TRUE(merged == read(tmp.path() / "single.xml")) << "merged and single reports differ";
  // No report names where its suite lay.
  EXPECT_EQ(merged.find(tmp.path().string()), std::string::npos);
  EXPECT_EQ(merged.find(kSuite), std::string::npos);
}

// docs/expectations.md's Slurm array job, where a Slurm controller with an idle node answers here:
// scripts/test.sh starts one (scripts/slurm-local.sh) when run as root, as in CI, where a missing
// node is a failure rather than a skip.
TEST(SearTestCommand, SlurmArrayJobShardsMergeIntoTheSingleRunsReport) {
  const Result nodes = shell(fs::temp_directory_path(), "sinfo -h -t idle,mix -o %n");
  if (nodes.exit_code != 0 || nodes.out.empty()) {
    if (std::getenv("CI")) FAIL() << "no Slurm node to run on (scripts/slurm-local.sh start): " << nodes.out;
    GTEST_SKIP() << "no Slurm node to run on (scripts/slurm-local.sh start, as root): " << nodes.out;
  }
  const sear::test::TempDir tmp;
  tmp.write("job.sh", "#!/bin/sh\n#SBATCH --array=1-3\n#SBATCH --output=shard-%a.log\nexec " + std::string(SEAR_BINARY) +
                          " test " + kSuite +
                          " --seeds 1..2 -j 1 -o out --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT"
                          " --junit shard-$SLURM_ARRAY_TASK_ID.xml\n");
  // --wait: sbatch returns when every task has ended, with the highest exit code among them.
  const Result job = shell(tmp.path(), "timeout 300 sbatch --wait job.sh");
  EXPECT_EQ(job.exit_code, 5) << job.out;
  const Result merge = sear_test(tmp.path(), "--merge merged.xml shard-1.xml shard-2.xml shard-3.xml");
  EXPECT_EQ(merge.exit_code, 5) << merge.out;
  const Result single = sear_test(tmp.path(), kSuite + " --seeds 1..2 -o single --junit single.xml");
  EXPECT_EQ(single.exit_code, 5) << single.out;
  EXPECT_EQ(parse(tmp.path() / "merged.xml").suites.size(), static_cast<std::size_t>(kScenarios * 2));
  EXPECT_TRUE(read(tmp.path() / "merged.xml") == read(tmp.path() / "single.xml")) << "merged and single reports differ";
}

}  // namespace
