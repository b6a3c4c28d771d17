// Firmware built from C sources with the system C compiler: it runs, the cache rebuilds exactly when an
// input changed, and compiler errors reach the user with file and line.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "scoped_env.hpp"
#include "sear/firmware_builder.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

using test::ScopedEnv;

namespace fs = std::filesystem;

struct RunResult {
  int exit_code = -1;
  std::string output;
};

RunResult run_executable(const std::string& path) {
  RunResult result;
  FILE* pipe = popen(("'" + path + "'").c_str(), "r");  // test paths hold spaces but no quotes
  if (!pipe) return result;
  char buffer[256];
  while (std::fgets(buffer, sizeof buffer, pipe)) result.output += buffer;
  const int status = pclose(pipe);
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  return result;
}

struct FileIdentity {
  ino_t inode = 0;
  long long mtime_ns = 0;
  bool operator==(const FileIdentity& other) const { return inode == other.inode && mtime_ns == other.mtime_ns; }
};

FileIdentity identity(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) return {};
  return {info.st_ino, static_cast<long long>(info.st_mtim.tv_sec) * 1000000000LL + info.st_mtim.tv_nsec};
}

std::string twice_library_source(int factor) {
  return "int twice(int x) { return " + std::to_string(factor) + " * x; }\n";
}

// A fake HAL include folder, a tiny static library and a firmware folder whose name holds a space, so
// the compiler is seen to run without a shell.
class FirmwareBuilderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    toolchain_ = default_toolchain((dir_.path() / "hal include").string(), {});
    toolchain_.cache_dir = (dir_.path() / "cache dir").string();
    // The compiler is a wrapper that logs each compile or link, so a test can tell a cache hit from a
    // rebuild that happened to land on the same file.
    log_ = (dir_.path() / "compiler log.txt").string();
    toolchain_.compiler = dir_.write("tool dir/logging cc",
                                     "#!/bin/sh\n"
                                     "case \"$1\" in --version) ;; *) echo run >> '" + log_ + "' ;; esac\n"
                                     "exec " + toolchain_.compiler + " \"$@\"\n");
    fs::permissions(toolchain_.compiler, fs::perms::owner_all);
    write_answer(42);
    write_library(2);
    toolchain_.libraries = {library_};
    main_c_ = dir_.write("my firmware/main.c", main_source("answer"));
    dir_.write("my firmware/local.h", "#define LABEL \"answer\"\n");
  }

  static std::string main_source(const std::string& label) {
    return "#include <stdio.h>\n"
           "#include <hal/answer.h>\n"
           "#include \"local.h\"\n"
           "int twice(int x);\n"
           "int main(void) {\n"
           "  printf(\"%s \" LABEL \"=%d twice=%d\\n\", \"" + label + "\", ANSWER, twice(ANSWER));\n"
           "  return twice(ANSWER) - 80;\n"
           "}\n";
  }

  void write_answer(int answer) {
    dir_.write("hal include/hal/answer.h", "#define ANSWER " + std::to_string(answer) + "\n");
  }

  void write_library(int factor) {
    const std::string source = dir_.write("lib/twice.c", twice_library_source(factor));
    const std::string object = (dir_.path() / "lib" / "twice.o").string();
    library_ = (dir_.path() / "lib" / "libtwice.a").string();
    fs::remove(library_);
    ASSERT_EQ(std::system(("cc -c '" + source + "' -o '" + object + "'").c_str()), 0);
    ASSERT_EQ(std::system(("ar rcs '" + library_ + "' '" + object + "'").c_str()), 0);
  }

  // Compiler runs other than `--version`: one per source compiled plus one per link.
  int compiler_runs() const {
    std::ifstream in(log_);
    int lines = 0;
    for (std::string line; std::getline(in, line);) ++lines;
    return lines;
  }

  std::vector<std::string> leftover_scratch() const {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(toolchain_.cache_dir)) {
      if (entry.path().filename().string().rfind(".tmp-", 0) == 0) found.push_back(entry.path().string());
    }
    return found;
  }

  test::TempDir dir_;
  FirmwareToolchain toolchain_;
  std::string library_;
  std::string main_c_;
  std::string log_;
};

TEST_F(FirmwareBuilderTest, BuildsAgainstTheHalHeadersAndLibrariesAndRuns) {
  std::string warnings = "stale";
  const std::string exe = build_firmware("rover", {main_c_}, toolchain_, &warnings);
  EXPECT_EQ(warnings, "");
  EXPECT_EQ(compiler_runs(), 2);
  const RunResult run = run_executable(exe);
  EXPECT_EQ(run.output, "answer answer=42 twice=84\n");
  EXPECT_EQ(run.exit_code, 4);

  // <cache_dir>/<name>-<16 hex digits>/firmware, with the compiler's dependency list beside it.
  const fs::path key_dir = fs::path(exe).parent_path();
  EXPECT_EQ(fs::path(exe).filename(), "firmware");
  EXPECT_EQ(fs::canonical(key_dir.parent_path()), fs::canonical(toolchain_.cache_dir));
  const std::string key = key_dir.filename().string();
  ASSERT_EQ(key.size(), std::string("rover-").size() + 16);
  EXPECT_EQ(key.rfind("rover-", 0), 0U);
  EXPECT_EQ(key.find_first_not_of("0123456789abcdef", 6), std::string::npos);
  std::ifstream deps(key_dir / "firmware.d");
  const std::string dep_text((std::istreambuf_iterator<char>(deps)), {});
  EXPECT_NE(dep_text.find("answer.h"), std::string::npos);
  EXPECT_NE(dep_text.find("local.h"), std::string::npos);
  EXPECT_TRUE(leftover_scratch().empty());
}

TEST_F(FirmwareBuilderTest, SecondCallReturnsTheSameExecutableWithoutCompiling) {
  const std::string first = build_firmware("rover", {main_c_}, toolchain_);
  const FileIdentity before = identity(first);
  ASSERT_NE(before.inode, 0U);
  const int runs = compiler_runs();
  EXPECT_EQ(runs, 2);
  const std::string second = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_EQ(second, first);
  EXPECT_TRUE(identity(second) == before);
  EXPECT_EQ(compiler_runs(), runs);
  EXPECT_TRUE(leftover_scratch().empty());
}

TEST_F(FirmwareBuilderTest, EditingTheSourceRebuilds) {
  const std::string first = build_firmware("rover", {main_c_}, toolchain_);
  const int runs = compiler_runs();
  dir_.write("my firmware/main.c", main_source("edited"));
  const std::string second = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_NE(second, first);
  EXPECT_EQ(compiler_runs(), runs + 2);
  EXPECT_EQ(run_executable(second).output, "edited answer=42 twice=84\n");
  // A firmware still running from the old build keeps its executable.
  EXPECT_EQ(run_executable(first).output, "answer answer=42 twice=84\n");
}

TEST_F(FirmwareBuilderTest, EditingAnIncludedHeaderRebuildsAndRevertingReusesTheFirstBuild) {
  const std::string first = build_firmware("rover", {main_c_}, toolchain_);
  const FileIdentity first_identity = identity(first);

  write_answer(43);
  const std::string hal_edited = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_NE(hal_edited, first);
  const RunResult run = run_executable(hal_edited);
  EXPECT_EQ(run.output, "answer answer=43 twice=86\n");
  EXPECT_EQ(run.exit_code, 6);

  dir_.write("my firmware/local.h", "#define LABEL \"value\"\n");
  const std::string local_edited = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_NE(local_edited, hal_edited);
  EXPECT_EQ(run_executable(local_edited).output, "answer value=43 twice=86\n");

  write_answer(42);
  dir_.write("my firmware/local.h", "#define LABEL \"answer\"\n");
  const int runs = compiler_runs();
  const std::string reverted = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_EQ(reverted, first);
  EXPECT_TRUE(identity(reverted) == first_identity);
  EXPECT_EQ(compiler_runs(), runs);
}

TEST_F(FirmwareBuilderTest, ChangingALibraryRebuilds) {
  const std::string first = build_firmware("rover", {main_c_}, toolchain_);
  write_library(3);
  const std::string second = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_NE(second, first);
  const RunResult run = run_executable(second);
  EXPECT_EQ(run.output, "answer answer=42 twice=126\n");
  EXPECT_EQ(run.exit_code, 46);
}

TEST_F(FirmwareBuilderTest, ChangingTheFlagsOrNameUsesAnotherEntry) {
  const std::string first = build_firmware("rover", {main_c_}, toolchain_);
  toolchain_.link_flags = {"-lm"};
  const std::string with_libm = build_firmware("rover", {main_c_}, toolchain_);
  EXPECT_NE(with_libm, first);
  const std::string other_name = build_firmware("rover two/../x", {main_c_}, toolchain_);
  EXPECT_EQ(fs::canonical(fs::path(other_name).parent_path().parent_path()), fs::canonical(toolchain_.cache_dir));
  EXPECT_EQ(fs::path(other_name).parent_path().filename().string().rfind("rover_two____x-", 0), 0U);
}

TEST_F(FirmwareBuilderTest, CompilerErrorsCarryFileAndLineOfEverySource) {
  const std::string bad = dir_.write("my firmware/bad.c",
                                     "#include <hal/answer.h>\n"
                                     "int twice(int x);\n"
                                     "int main(void) {\n"
                                     "  return twice(ANSWER)\n"
                                     "}\n");
  const std::string worse = dir_.write("my firmware/worse.c", "int helper(void) {\n  return undeclared_thing;\n}\n");
  try {
    build_firmware("broken", {bad, worse}, toolchain_);
    FAIL() << "a syntax error should stop the build";
  } catch (const FirmwareBuildError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("firmware 'broken' failed to build:\n", 0), 0U) << message;
    EXPECT_NE(message.find(bad + ":4:"), std::string::npos) << message;
    EXPECT_NE(message.find(worse + ":2:"), std::string::npos) << message;
    EXPECT_NE(message.find("undeclared_thing"), std::string::npos) << message;
  }
  EXPECT_TRUE(leftover_scratch().empty());

  // Fixing it builds; the failure was not cached.
  dir_.write("my firmware/bad.c",
             "#include <hal/answer.h>\nint twice(int x);\nint main(void) {\n  return twice(ANSWER) - 80;\n}\n");
  EXPECT_EQ(run_executable(build_firmware("broken", {bad}, toolchain_)).exit_code, 4);
}

TEST_F(FirmwareBuilderTest, LinkErrorsNameTheMissingSymbol) {
  const std::string source = dir_.write("my firmware/unlinked.c",
                                        "void motor_enable(void);\nint main(void) {\n  motor_enable();\n  return 0;\n}\n");
  try {
    build_firmware("unlinked", {source}, toolchain_);
    FAIL() << "an undefined function should stop the build";
  } catch (const FirmwareBuildError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("firmware 'unlinked' failed to build:\n", 0), 0U) << message;
    EXPECT_NE(message.find("motor_enable"), std::string::npos) << message;
  }
}

TEST_F(FirmwareBuilderTest, MissingSourceIsNamed) {
  const std::string missing = (dir_.path() / "my firmware" / "nowhere.c").string();
  try {
    build_firmware("rover", {main_c_, missing}, toolchain_);
    FAIL() << "a missing source should stop the build";
  } catch (const FirmwareBuildError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(missing), std::string::npos) << message;
    EXPECT_NE(message.find("'rover'"), std::string::npos) << message;
  }
}

TEST_F(FirmwareBuilderTest, MissingCompilerIsNamed) {
  toolchain_.compiler = (dir_.path() / "no such cc").string();
  try {
    build_firmware("rover", {main_c_}, toolchain_);
    FAIL() << "a missing compiler should stop the build";
  } catch (const FirmwareBuildError& e) {
    EXPECT_NE(std::string(e.what()).find(toolchain_.compiler), std::string::npos) << e.what();
  }
}

TEST_F(FirmwareBuilderTest, WarningsOfASuccessfulBuildAreHandedBack) {
  const std::string source =
      dir_.write("my firmware/warn.c", "int main(void) {\n  int unused_value = 3;\n  return 0;\n}\n");
  std::string warnings;
  const std::string exe = build_firmware("warn", {source}, toolchain_, &warnings);
  EXPECT_NE(warnings.find(source + ":2:"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("unused_value"), std::string::npos) << warnings;
  EXPECT_EQ(run_executable(exe).exit_code, 0);
  const int runs = compiler_runs();
  build_firmware("warn", {source}, toolchain_, &warnings);
  EXPECT_EQ(warnings, "");
  EXPECT_EQ(compiler_runs(), runs);
}

// What the compiler said is kept beside the cached build and read back on every run.
TEST_F(FirmwareBuilderTest, TheWarningsStayBesideTheCachedBuild) {
  const std::string source =
      dir_.write("my firmware/warn.c", "int main(void) {\n  int unused_value = 3;\n  return 0;\n}\n");
  std::string warnings;
  const std::string exe = build_firmware("warn", {source}, toolchain_, &warnings);
  EXPECT_EQ(cached_compiler_output(exe), warnings);
  const std::string again = build_firmware("warn", {source}, toolchain_, &warnings);
  EXPECT_EQ(warnings, "");  // nothing was built
  EXPECT_NE(cached_compiler_output(again).find(source + ":2:"), std::string::npos) << cached_compiler_output(again);
}

// A check of the sources (the chip's warnings): each of the firmware's own sources is compiled and
// nothing is linked (so a missing symbol is no error) nor are the extra sources compiled; cached alike.
TEST_F(FirmwareBuilderTest, CompileOnlyCompilesTheOwnSourcesAndLinksNothing) {
  const std::string source = dir_.write("my firmware/lonely.c", "int twice(int x);\nint main(void) {\n"
                                                               "  int unused_value = 3;\n  return twice(1);\n}\n");
  toolchain_.libraries = {};  // twice() is nowhere: a link would fail
  toolchain_.extra_sources = {dir_.write("extra/broken.c", "this is not C\n")};
  toolchain_.compile_only = true;
  const std::string stamp = build_firmware("check", {source}, toolchain_);
  EXPECT_EQ(compiler_runs(), 1);  // lonely.c alone
  EXPECT_EQ(fs::file_size(stamp), 0U);
  EXPECT_NE(cached_compiler_output(stamp).find(source + ":3:"), std::string::npos) << cached_compiler_output(stamp);
  EXPECT_EQ(build_firmware("check", {source}, toolchain_), stamp);
  EXPECT_EQ(compiler_runs(), 1);
  // The same sources linked are another entry, which fails on twice().
  toolchain_.compile_only = false;
  toolchain_.extra_sources = {};
  EXPECT_THROW(build_firmware("check", {source}, toolchain_), FirmwareBuildError);
}

TEST_F(FirmwareBuilderTest, ConcurrentBuildsOfTheSameFirmwareAgree) {
  std::string paths[2];
  std::string errors[2];
  std::thread builders[2];
  for (int i = 0; i < 2; ++i) {
    builders[i] = std::thread([&, i] {
      try {
        paths[i] = build_firmware("rover", {main_c_}, toolchain_);
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  }
  for (auto& builder : builders) builder.join();
  EXPECT_EQ(errors[0], "");
  EXPECT_EQ(errors[1], "");
  EXPECT_EQ(paths[0], paths[1]);
  EXPECT_EQ(run_executable(paths[0]).output, "answer answer=42 twice=84\n");
  EXPECT_TRUE(leftover_scratch().empty());
}


TEST(DefaultToolchain, FollowsTheEnvironment) {
  {
    const ScopedEnv cc("CC", nullptr);
    const ScopedEnv sear("SEAR_CACHE_DIR", nullptr);
    const ScopedEnv xdg("XDG_CACHE_HOME", nullptr);
    const ScopedEnv home("HOME", "/home/someone");
    const FirmwareToolchain toolchain = default_toolchain("/hal/include", {"/lib/libhal.a"}, {"-lm"});
    EXPECT_EQ(toolchain.compiler, "cc");
    EXPECT_EQ(toolchain.cache_dir, "/home/someone/.cache/sear/firmware");
    EXPECT_EQ(toolchain.hal_include_dir, "/hal/include");
    EXPECT_EQ(toolchain.libraries, std::vector<std::string>{"/lib/libhal.a"});
    EXPECT_EQ(toolchain.link_flags, std::vector<std::string>{"-lm"});
  }
  {
    const ScopedEnv cc("CC", "clang");
    const ScopedEnv sear("SEAR_CACHE_DIR", nullptr);
    const ScopedEnv xdg("XDG_CACHE_HOME", "/var/cache/me");
    const FirmwareToolchain toolchain = default_toolchain("/hal/include", {});
    EXPECT_EQ(toolchain.compiler, "clang");
    EXPECT_EQ(toolchain.cache_dir, "/var/cache/me/sear/firmware");
  }
  {
    const ScopedEnv sear("SEAR_CACHE_DIR", "/tmp/sear-cache");
    const ScopedEnv xdg("XDG_CACHE_HOME", "/var/cache/me");
    EXPECT_EQ(default_toolchain("/hal/include", {}).cache_dir, "/tmp/sear-cache");
  }
}

}  // namespace
}  // namespace sear
