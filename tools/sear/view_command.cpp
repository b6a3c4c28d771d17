#include "sear/view_command.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "runtime/stop_request.hpp"
#include "sear/commands.hpp"

namespace sear {

ViewServerOptions view_server_options(const std::string& bind, int port) {
  ViewServerOptions options;
  options.bind = bind;
  options.port = port;
  options.three_dir = SEAR_THREE_DIR;
  options.page_dir = SEAR_VIEW_PAGE_DIR;  // the source tree's: `sear` runs from its build tree
  return options;
}

int view_replay_command(const std::string& file, const std::string& bind, int port) {
  install_stop_signals();
  // The file's own first line is the hello the page gets: a replay file, gzip, starts with one.
  unsigned char magic[2] = {};
  std::ifstream probe(file, std::ios::binary);
  if (!probe) {
    fmt::print(stderr, "sear: {}: no such replay file\n", file);
    return 1;
  }
  probe.read(reinterpret_cast<char*>(magic), 2);
  if (probe.gcount() != 2 || magic[0] != 0x1f || magic[1] != 0x8b) {
    fmt::print(stderr, "sear: {}: not a replay file (not gzip; `sear run --replay FILE` writes one)\n", file);
    return 1;
  }
  std::string hello;
  if (gzFile gz = gzopen(file.c_str(), "rb")) {
    char line[4096];
    if (gzgets(gz, line, sizeof line)) hello = line;
    gzclose(gz);
  }
  const auto j = nlohmann::json::parse(hello, nullptr, false);
  if (!j.is_object() || j.value("type", "") != "hello" || j.value("mode", "") != "replay") {
    fmt::print(stderr, "sear: {}: not a replay file (its first line is not the viewer's hello)\n", file);
    return 1;
  }
  try {
    ViewServerOptions options = view_server_options(bind, port);
    options.replay_file = file;
    ViewServer server(options);
    server.set_hello(j.dump());
    fmt::print(stderr, "sear: viewer on {}\n", server.url());
    fmt::print(stderr, "sear: playing {} back; Ctrl-C ends\n", file);
    while (!stop_requested()) {
      (void)server.take_commands();  // a replay takes no commands: the page plays it itself
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  } catch (const ViewServerError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace sear
