// One run, one folder: runs from one directory without --out each write sear-out/NAME/, emptied
// of the previous run's files, with sear-out/latest naming the last; --out never mixes two runs'
// files nor deletes what is not a run's; the summary's output line names the folder and the plots.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "firmware_run.hpp"

namespace sear::test {
namespace {

namespace fs = std::filesystem;

struct Shell {
  int exit_code;
  std::string out, err;
};

// `sear ARGS` run from `dir`, as a user in their project's folder would.
Shell sear_in(const fs::path& dir, const std::string& args, const std::string& env = "") {
  const std::string cmd = "cd " + dir.string() + " && " + env + " " + SEAR_BINARY + " " + args + " >stdout 2>stderr";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_file(dir / "stdout"), read_file(dir / "stderr")};
}

// A robot without an MCU: nothing to build, a run of a few hundred steps.
std::string named_project(const std::string& name) {
  std::string p = rover_project("", "", 0.2);
  p.replace(p.find("name=\"test\""), 11, "name=\"" + name + "\"");
  return p;
}

std::string output_line(const std::string& stdout_text) {
  const auto at = stdout_text.find("  output: ");
  return at == std::string::npos ? "" : stdout_text.substr(at, stdout_text.find('\n', at) - at);
}

TEST(RunFolder, EachProjectGetsItsOwnFolderEmptiedOfItsLastRunAndLatestNamesTheLastRun) {
  TempDir dir;
  dir.write("alpha.xml", named_project("alpha"));
  dir.write("beta.xml", named_project("my beta"));  // a name with a space: a folder name without one
  ASSERT_EQ(sear_in(dir.path(), "run alpha.xml -q").exit_code, 0);
  const fs::path alpha = dir.path() / "sear-out" / "alpha";
  ASSERT_TRUE(fs::exists(alpha / "summary.json"));
  // What an earlier run left: a plot of a robot this project no longer has.
  std::ofstream(alpha / "plot_trajectory_gone.png") << "old";
  const Shell beta = sear_in(dir.path(), "run beta.xml");
  ASSERT_EQ(beta.exit_code, 0) << beta.err;
  EXPECT_EQ(output_line(beta.out).rfind("  output: sear-out/my_beta/ (summary.txt, summary.json, trace_rover.csv", 0), 0u)
      << beta.out;
  EXPECT_TRUE(fs::exists(dir.path() / "sear-out" / "my_beta" / "trace_rover.csv"));
  EXPECT_EQ(fs::read_symlink(dir.path() / "sear-out" / "latest"), "my_beta");
  // beta's run left alpha's folder as it was.
  EXPECT_TRUE(fs::exists(alpha / "plot_trajectory_gone.png"));

  ASSERT_EQ(sear_in(dir.path(), "run alpha.xml -q").exit_code, 0);
  EXPECT_FALSE(fs::exists(alpha / "plot_trajectory_gone.png"));  // alpha's new run starts clean
  EXPECT_TRUE(fs::exists(alpha / "trace_rover.csv"));
  EXPECT_EQ(fs::read_symlink(dir.path() / "sear-out" / "latest"), "alpha");
}

TEST(RunFolder, OutputLineListsThePlotsThisRunDrew) {
  TempDir dir;
  dir.write("p.xml", named_project("plotted"));
  // A plotter standing in for tools/plots/plot_run.py (its own tests draw real plots): it writes
  // two plots into the folder it is given, as the real one does.
  dir.write("plotter.sh", "touch \"$1/plot_b.png\" \"$1/plot_a.png\" \"$1/plot.log.txt\"\n");
  const std::string env = "SEAR_NO_PLOTS=0 SEAR_PYTHON=/bin/sh SEAR_PLOT_SCRIPT=" + (dir.path() / "plotter.sh").string();
  // --wait-plots: the run exits once they are drawn, and its summary's last line lists them in
  // name order after the files the run wrote.
  const Shell run = sear_in(dir.path(), "run p.xml --wait-plots", env);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string line = output_line(run.out);
  EXPECT_EQ(run.out.substr(run.out.size() - line.size() - 1), line + "\n");
  EXPECT_NE(line.find("(summary.txt, summary.json, trace_rover.csv, plot_a.png, plot_b.png)"), std::string::npos) << line;
  EXPECT_EQ(line.find("plot_c.txt"), std::string::npos) << line;
  // By default they are drawn in the background, and the last line says where and how to wait.
  const Shell background = sear_in(dir.path(), "run p.xml", env);
  ASSERT_EQ(background.exit_code, 0) << background.err;
  const std::string said = "  plots: drawn in the background into sear-out/plotted/ (`flock sear-out/plotted true` waits for them)\n";
  ASSERT_GE(background.out.size(), said.size());
  EXPECT_EQ(background.out.substr(background.out.size() - said.size()), said);
}

TEST(RunFolder, OutIntoAnEarlierRunsFolderEmptiesItAndIntoAnyOtherFolderIsRefused) {
  TempDir dir;
  dir.write("p.xml", named_project("p"));
  ASSERT_EQ(sear_in(dir.path(), "run p.xml -q -o mine").exit_code, 0);
  std::ofstream(dir.path() / "mine" / "trace_other.csv") << "another run's trace";
  ASSERT_EQ(sear_in(dir.path(), "run p.xml -q -o mine").exit_code, 0);
  EXPECT_FALSE(fs::exists(dir.path() / "mine" / "trace_other.csv"));
  EXPECT_TRUE(fs::exists(dir.path() / "mine" / "summary.json"));
  EXPECT_FALSE(fs::exists(dir.path() / "sear-out"));  // --out given: no default folder, no latest link

  // A run's folder from before the mark: its first and last files say what it is.
  dir.write("old/world.json", "{}");
  dir.write("old/summary.json", "{}");
  dir.write("old/trace_gone.csv", "t");
  ASSERT_EQ(sear_in(dir.path(), "run p.xml -q -o old").exit_code, 0);
  EXPECT_FALSE(fs::exists(dir.path() / "old" / "trace_gone.csv"));
  EXPECT_TRUE(fs::exists(dir.path() / "old" / ".sear-run"));

  // A folder of the user's: nothing written, nothing deleted, and the message says why.
  dir.write("notes/ideas.txt", "mine");
  const Shell refused = sear_in(dir.path(), "run p.xml -q -o notes");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("notes: error: the output folder holds files that are not a SEAR run's (such as ideas.txt)"),
            std::string::npos)
      << refused.err;
  EXPECT_EQ(read_file(dir.path() / "notes" / "ideas.txt"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path() / "notes"), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace sear::test
