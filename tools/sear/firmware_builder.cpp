// Firmware builds with the system C compiler, run without a shell, cached under a content hash.
// Cache layout: <cache_dir>/<name>-<key>/{firmware, firmware.d, compiler.txt} and <cache_dir>/<name>-<base>.last.

#include "sear/firmware_builder.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <string_view>

#include "runtime/process_keeper.hpp"
#include "runtime/stop_request.hpp"

extern char** environ;

namespace sear {
namespace {

namespace fs = std::filesystem;

// Bumped whenever what goes into a build changes in a way the key would not otherwise see.
constexpr std::string_view kLayoutVersion = "sear firmware cache 2";  // 2: compiler.txt

// FNV-1a 64: a cache key needs a stable, well-spread hash rather than a cryptographic one, and no
// hashing library in Debian is worth a dependency for that.
class Fnv1a {
 public:
  void bytes(std::string_view data) {
    for (const char c : data) {
      hash_ ^= static_cast<unsigned char>(c);
      hash_ *= 0x100000001b3ULL;
    }
  }
  // Length first, so that ("ab", "c") and ("a", "bc") give different keys.
  void field(std::string_view data) {
    bytes(std::to_string(data.size()));
    bytes(":");
    bytes(data);
  }
  std::string hex() const { return fmt::format("{:016x}", hash_); }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

std::optional<std::string> read_file(const fs::path& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string data;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) data.append(buffer, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) return std::nullopt;
  return data;
}

struct ProcessResult {
  bool ok = false;     // exited with status 0
  std::string output;  // stdout and stderr interleaved, as a terminal would show them
};

// No shell in between, so paths with spaces or quotes reach the compiler as they are. The
// compiler runs in its own process group, so that a stop request (Ctrl-C, SIGTERM, SIGHUP) or the
// keeper, if the simulator is killed outright, ends it with every pass it started.
ProcessResult run_process(const std::vector<std::string>& args) {
  int fds[2];
  // Close-on-exec, so a compiler spawned by another thread does not hold our pipe open.
  if (pipe2(fds, O_CLOEXEC) != 0) throw FirmwareBuildError(fmt::format("cannot create a pipe: {}", std::strerror(errno)));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF);
  posix_spawnattr_setpgroup(&attributes, 0);
  sigset_t defaults;  // what the run ignores (SIGPIPE), the compiler must not
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  sigaddset(&defaults, SIGXFSZ);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  std::vector<char*> argv;
  for (const auto& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, argv[0], &actions, &attributes, argv.data(), environ);
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  if (spawn_error != 0) {
    close(fds[0]);
    throw FirmwareBuildError(fmt::format("cannot run the C compiler '{}': {} (set $CC to the compiler to use)",
                                         args[0], std::strerror(spawn_error)));
  }
  keeper_watch(pid);
  ProcessResult result;
  char buffer[4096];
  for (;;) {
    if (stop_requested()) break;
    // A stop signal landing between the look above and a blocking read would go unseen until the
    // compiler finished: the read waits only while poll() says there is something to read, and
    // poll() looks at the flag again every 50 ms.
    struct pollfd ready = {fds[0], POLLIN, 0};
    const int polled = poll(&ready, 1, 50);
    if (polled == 0 || (polled < 0 && errno == EINTR)) continue;
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n > 0) {
      result.output.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  close(fds[0]);
  if (stop_requested()) kill(-pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw FirmwareBuildError(fmt::format("cannot wait for '{}': {}", args[0], std::strerror(errno)));
  }
  kill(-pid, SIGKILL);  // any pass of the compiler's still running (none, normally)
  keeper_forget(pid);
  if (stop_requested()) throw FirmwareBuildInterrupted();
  if (WIFSIGNALED(status)) result.output += fmt::format("{}: killed by signal {}\n", args[0], WTERMSIG(status));
  result.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  return result;
}

// Names become directory names; anything but a plain name character could escape the cache.
std::string safe_name(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    out += plain ? c : '_';
  }
  return out.empty() ? "firmware" : out;
}

std::vector<std::string> compile_flags(const FirmwareToolchain& toolchain, const std::vector<fs::path>& sources) {
  std::vector<std::string> flags = toolchain.compile_flags;
  if (flags.empty()) flags = {"-O2", "-g", "-Wall", "-Wextra", "-fno-common"};
  flags.push_back("-I" + fs::absolute(toolchain.hal_include_dir).lexically_normal().string());
  std::set<std::string> seen;
  for (const auto& source : sources) {
    const std::string dir = source.parent_path().string();
    if (seen.insert(dir).second) flags.push_back("-I" + dir);
  }
  for (const auto& dir : toolchain.include_dirs) flags.push_back("-I" + dir);
  for (const auto& define : toolchain.defines) flags.push_back("-D" + define);
  flags.insert(flags.end(), toolchain.extra_flags.begin(), toolchain.extra_flags.end());
  return flags;
}

// The files listed in the compiler's make-syntax dependency output (-MMD with -MT firmware).
std::set<std::string> parse_dependencies(const std::string& text) {
  std::set<std::string> files;
  std::string token;
  const auto flush = [&] {
    if (!token.empty() && token != "firmware:") files.insert(token);
    token.clear();
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const char next = i + 1 < text.size() ? text[i + 1] : '\0';
    if (c == '\\' && next == '\n') {
      flush();
      ++i;
    } else if (c == '\\' && (next == ' ' || next == '\t' || next == '#' || next == '\\')) {
      token += next;  // make's escapes for characters that would otherwise split or end the rule
      ++i;
    } else if (c == '$' && next == '$') {
      token += '$';
      ++i;
    } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
      flush();
    } else {
      token += c;
    }
  }
  flush();
  return files;
}

// The final key: the inputs known before compiling plus every file the compiler read, by path and content.
// A header created later earlier on the include path is not seen until something listed changes; ccache
// and make share that blind spot.
std::string full_key(const std::string& base, const std::set<std::string>& dependencies) {
  Fnv1a hash;
  hash.field(base);
  hash.field(std::to_string(dependencies.size()));
  for (const auto& file : dependencies) {
    hash.field(file);
    const auto content = read_file(file);
    hash.field(content ? "present" : "missing");
    if (content) hash.field(*content);
  }
  return hash.hex();
}

// Removes a build's scratch directory however the build ends.
class ScratchDir {
 public:
  explicit ScratchDir(fs::path path) : path_(std::move(path)) {}
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// Unique per process and per call, so concurrent builds in one cache never share scratch space.
fs::path make_scratch_dir(const fs::path& cache, const std::string& name) {
  static std::atomic<unsigned> counter{0};
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const fs::path candidate = cache / fmt::format(".tmp-{}-{}-{}", name, getpid(), counter++);
    std::error_code error;
    if (fs::create_directory(candidate, error)) return candidate;
    if (error) {
      throw FirmwareBuildError(
          fmt::format("{}: error: cannot create a build directory: {}", candidate.string(), error.message()));
    }
  }
  throw FirmwareBuildError(fmt::format("{}: error: cannot create a build directory", cache.string()));
}

// Readers only ever see the old pointer or the new one.
void write_atomically(const fs::path& path, const std::string& text, const fs::path& scratch) {
  const fs::path temp = scratch / "pointer";
  {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    if (!out) return;  // the pointer only saves a rebuild; missing it is not an error
  }
  std::error_code ignored;
  fs::rename(temp, path, ignored);
}

// Links the compiled objects (`link`: the C driver, then one object per source, the extra sources'
// last) into staged/firmware, adding what the tools say to `output`.
void link_firmware(const std::string& name, const FirmwareToolchain& toolchain, std::vector<std::string> link,
                   const std::vector<std::string>& libraries, bool any_cxx, const fs::path& scratch,
                   const fs::path& staged, std::string& output) {
  if (!toolchain.archiver.empty() && !toolchain.extra_sources.empty()) {
    // The extra sources (a HAL) become an archive, so that only the parts a firmware uses are
    // linked: a register-level firmware's own ISR() must not meet the HAL's for the same vector.
    const std::size_t first = link.size() - toolchain.extra_sources.size();
    const std::string archive = (scratch / "hal.a").string();
    std::vector<std::string> ar{toolchain.archiver, "rcs", archive};
    ar.insert(ar.end(), link.begin() + static_cast<std::ptrdiff_t>(first), link.end());
    const ProcessResult archived = run_process(ar);
    output += archived.output;
    if (!archived.ok) throw FirmwareBuildError(fmt::format("firmware '{}' failed to build:\n{}", name, output));
    link.resize(first);
    link.push_back(archive);
  }
  if (any_cxx) link[0] = toolchain.cxx_compiler;
  link.insert(link.end(), libraries.begin(), libraries.end());
  link.insert(link.end(), toolchain.link_flags.begin(), toolchain.link_flags.end());
  link.insert(link.end(), {"-o", (staged / "firmware").string()});
  const ProcessResult linked = run_process(link);
  output += linked.output;
  if (!linked.ok) throw FirmwareBuildError(fmt::format("firmware '{}' failed to build:\n{}", name, output));
}

std::string getenv_or_empty(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

}  // namespace

FirmwareToolchain default_toolchain(std::string hal_include_dir, std::vector<std::string> libraries,
                                    std::vector<std::string> link_flags) {
  FirmwareToolchain toolchain;
  toolchain.compiler = getenv_or_empty("CC");
  if (toolchain.compiler.empty()) toolchain.compiler = "cc";
  toolchain.cxx_compiler = getenv_or_empty("CXX");
  if (toolchain.cxx_compiler.empty()) toolchain.cxx_compiler = "c++";
  toolchain.c_std = toolchain.hal_c_std = "c99";
  toolchain.cxx_std = "c++17";
  toolchain.hal_include_dir = std::move(hal_include_dir);
  toolchain.libraries = std::move(libraries);
  toolchain.link_flags = std::move(link_flags);
  const std::string sear_cache = getenv_or_empty("SEAR_CACHE_DIR");
  const std::string xdg_cache = getenv_or_empty("XDG_CACHE_HOME");
  const std::string home = getenv_or_empty("HOME");
  if (!sear_cache.empty()) {
    toolchain.cache_dir = sear_cache;
  } else if (!xdg_cache.empty() && fs::path(xdg_cache).is_absolute()) {  // the XDG spec says to ignore relative ones
    toolchain.cache_dir = (fs::path(xdg_cache) / "sear" / "firmware").string();
  } else if (!home.empty()) {
    toolchain.cache_dir = (fs::path(home) / ".cache" / "sear" / "firmware").string();
  } else {
    toolchain.cache_dir = (fs::temp_directory_path() / fmt::format("sear-firmware-{}", getuid())).string();
  }
  return toolchain;
}

FirmwareToolchain avr_toolchain(std::string hal_include_dir, const std::string& hal_avr_dir, double clock_hz) {
  FirmwareToolchain toolchain = default_toolchain(std::move(hal_include_dir), {}, {"-mmcu=atmega2560", "-Wl,--gc-sections", "-lm"});
  toolchain.compiler = getenv_or_empty("AVR_CC");
  if (toolchain.compiler.empty()) toolchain.compiler = "avr-gcc";
  // As cmake/avr-gcc.cmake builds the examples: for size, each function in its own section so
  // that --gc-sections drops what the firmware never calls. GNU C for the HAL's ISR() and
  // ATOMIC_BLOCK.
  toolchain.cxx_compiler = getenv_or_empty("AVR_CXX");
  if (toolchain.cxx_compiler.empty()) toolchain.cxx_compiler = "avr-g++";
  toolchain.c_std = toolchain.hal_c_std = "gnu99";
  toolchain.cxx_std = "gnu++17";
  toolchain.compile_flags = {"-mmcu=atmega2560", fmt::format("-DF_CPU={}UL", std::llround(clock_hz)),
                             "-Os", "-g", "-Wall", "-Wextra", "-ffunction-sections", "-fdata-sections"};
  std::vector<std::string> hal;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(hal_avr_dir, error))
    if (entry.path().extension() == ".c") hal.push_back(entry.path().string());
  if (hal.empty()) throw FirmwareBuildError(fmt::format("{}: error: no AVR HAL sources here", hal_avr_dir));
  std::sort(hal.begin(), hal.end());  // the same order, the same image
  toolchain.extra_sources = hal;
  toolchain.archiver = getenv_or_empty("AVR_AR");
  if (toolchain.archiver.empty()) toolchain.archiver = "avr-ar";
  return toolchain;
}

std::string build_firmware(const std::string& name, const std::vector<std::string>& sources,
                           const FirmwareToolchain& toolchain, std::string* compiler_output) {
  if (compiler_output) compiler_output->clear();
  if (sources.empty()) throw FirmwareBuildError(fmt::format("firmware '{}' names no source files", name));

  // Absolute paths, so the compiler's messages and dependency lists do not depend on our working directory.
  std::vector<fs::path> source_paths;
  for (const auto& source : sources) source_paths.push_back(fs::absolute(source).lexically_normal());
  for (const auto& source : toolchain.extra_sources) source_paths.push_back(fs::absolute(source).lexically_normal());
  const std::vector<std::string> flags = compile_flags(toolchain, source_paths);

  // Everything known before compiling goes into the base key; the headers follow in full_key().
  Fnv1a base;
  base.field(kLayoutVersion);
  base.field(toolchain.compiler);
  base.field(toolchain.archiver);
  base.field(toolchain.cxx_compiler);
  base.field(toolchain.c_std);
  base.field(toolchain.cxx_std);
  base.field(toolchain.compile_only ? "compile only" : "link");
  const ProcessResult version = run_process({toolchain.compiler, "--version"});
  if (!version.ok) {
    throw FirmwareBuildError(fmt::format("cannot run the C compiler '{}' (set $CC to the compiler to use):\n{}",
                                         toolchain.compiler, version.output));
  }
  base.field(version.output);
  base.field(std::to_string(flags.size()));
  for (const auto& flag : flags) base.field(flag);
  base.field(std::to_string(toolchain.libraries.size()));
  std::vector<std::string> libraries;
  for (const auto& library : toolchain.libraries) {
    libraries.push_back(fs::absolute(library).lexically_normal().string());
    const auto content = read_file(libraries.back());
    if (!content) {
      throw FirmwareBuildError(
          fmt::format("{}: error: cannot read this library, needed by firmware '{}'", libraries.back(), name));
    }
    base.field(libraries.back());
    base.field(*content);
  }
  base.field(std::to_string(toolchain.link_flags.size()));
  for (const auto& flag : toolchain.link_flags) base.field(flag);
  base.field(std::to_string(source_paths.size()));
  for (const auto& source : source_paths) {
    const auto content = read_file(source);
    if (!content) {
      throw FirmwareBuildError(fmt::format("{}: error: no such source file for firmware '{}'", source.string(), name));
    }
    base.field(source.string());
    base.field(*content);
  }

  const std::string prefix = safe_name(name) + "-";
  const fs::path cache = fs::absolute(toolchain.cache_dir);
  std::error_code error;
  fs::create_directories(cache, error);
  if (error) {
    throw FirmwareBuildError(
        fmt::format("{}: error: cannot create the firmware cache: {}", cache.string(), error.message()));
  }

  // The header list lives with the last build from the same base; if those headers still hash to a
  // key that has a built executable, that executable was built from exactly these inputs.
  const fs::path pointer = cache / (prefix + base.hex() + ".last");
  if (const auto last = read_file(pointer)) {
    if (last->size() == prefix.size() + 16 && last->compare(0, prefix.size(), prefix) == 0) {
      if (const auto deps = read_file(cache / *last / "firmware.d")) {
        const fs::path executable = cache / (prefix + full_key(base.hex(), parse_dependencies(*deps))) / "firmware";
        if (fs::is_regular_file(executable, error)) return executable.string();
      }
    }
  }

  const ScratchDir scratch(make_scratch_dir(cache, safe_name(name)));
  std::string output;
  bool compiled = true;
  std::vector<std::string> link{toolchain.compiler};  // the C++ driver instead once a C++ source is seen
  std::string dependencies_text;
  bool any_cxx = false;
  const std::size_t own_sources = source_paths.size() - toolchain.extra_sources.size();
  for (std::size_t i = 0; i < (toolchain.compile_only ? own_sources : source_paths.size()); ++i) {
    const std::string object = (scratch.path() / fmt::format("{}.o", i)).string();
    const std::string dep_file = (scratch.path() / fmt::format("{}.d", i)).string();
    // .cpp, .cc and .cxx are C++; the extra sources (the AVR HAL) keep the toolchain's own C.
    const std::string ext = source_paths[i].extension().string();
    const bool cxx = ext == ".cpp" || ext == ".cc" || ext == ".cxx";
    any_cxx = any_cxx || cxx;
    std::vector<std::string> args{cxx ? toolchain.cxx_compiler : toolchain.compiler};
    args.push_back("-std=" + (cxx ? toolchain.cxx_std : i < own_sources ? toolchain.c_std : toolchain.hal_c_std));
    args.insert(args.end(), flags.begin(), flags.end());
    args.insert(args.end(), {"-MMD", "-MF", dep_file, "-MT", "firmware", "-c", source_paths[i].string(), "-o", object});
    // Every source is compiled even after one fails, so one attempt shows all the errors.
    const ProcessResult result = run_process(args);
    output += result.output;
    compiled = compiled && result.ok;
    link.push_back(object);
    if (result.ok) dependencies_text += read_file(dep_file).value_or("") + "\n";
  }
  if (!compiled) throw FirmwareBuildError(fmt::format("firmware '{}' failed to build:\n{}", name, output));
  const fs::path staged = scratch.path() / "staged";
  fs::create_directory(staged, error);
  if (toolchain.compile_only) {
    std::ofstream stamp(staged / "firmware", std::ios::binary);
    if (!stamp) throw FirmwareBuildError(fmt::format("{}: error: cannot write", (staged / "firmware").string()));
  } else {
    link_firmware(name, toolchain, link, libraries, any_cxx, scratch.path(), staged, output);
  }
  // What the compiler said stays with the executable, for cached_compiler_output().
  for (const auto& [file, text] : {std::pair{"firmware.d", &dependencies_text}, std::pair{"compiler.txt", &output}}) {
    std::ofstream out(staged / file, std::ios::binary);
    out << *text;
    if (!out) throw FirmwareBuildError(fmt::format("{}: error: cannot write", (staged / file).string()));
  }

  // The key directory appears whole, in one rename, or not at all.
  const std::string key = prefix + full_key(base.hex(), parse_dependencies(dependencies_text));
  const fs::path key_dir = cache / key;
  for (int attempt = 0;; ++attempt) {
    if (std::rename(staged.c_str(), key_dir.c_str()) == 0) break;
    const int rename_error = errno;
    if (fs::is_regular_file(key_dir / "firmware", error)) break;  // a concurrent build of the same inputs won
    if (attempt > 0 || (rename_error != ENOTEMPTY && rename_error != EEXIST)) {
      throw FirmwareBuildError(fmt::format("{}: error: cannot store the built firmware: {}", key_dir.string(),
                                           std::strerror(rename_error)));
    }
    fs::remove_all(key_dir, error);  // left half-deleted by hand; nothing can be running from it
  }
  write_atomically(pointer, key, scratch.path());
  if (compiler_output) *compiler_output = output;
  return (key_dir / "firmware").string();
}

std::string cached_compiler_output(const std::string& executable) {
  if (executable.empty()) return "";
  return read_file(fs::path(executable).parent_path() / "compiler.txt").value_or("");
}

}  // namespace sear
