// The viewer's HTTP and WebSocket server (civetweb): serves the page's folder and three.js, sends
// each connected page the messages of tools/view/PROTOCOL.md and queues the commands pages send.
// The run thread only hands it strings; writing to a page is done by a thread of that page's own.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sear {

struct ViewServerOptions {
  std::string bind = "127.0.0.1";  // the address to listen on
  int port = 8080;                 // 0: a free port the system chooses
  std::string page_dir;            // the page's files, the only folder served
  std::string three_dir;           // libjs-three's folder (/usr/share/javascript/three)
  std::string replay_file;         // served as /replay when not empty (a gzip file)
  // How long a write to a page may wait for it to read before the page is given up; also how
  // long a page may stay silent before it is pinged (browsers answer pings by themselves). Long:
  // a browser starved of CPU (rendering in software beside a busy run) can go seconds without
  // reading, and a page that lags costs the run nothing (it only gets the newest frame).
  int write_timeout_ms = 15000;
};

// The server could not start: its address was taken, or a folder it serves is missing.
struct ViewServerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A page's command (PROTOCOL.md, "Page to server"), parsed.
struct ViewCommand {
  enum class Kind { Pause, Resume, Step, Reset, Speed, Start, Key } kind = Kind::Pause;
  std::int64_t steps = 1;  // Step
  double factor = 1;       // Speed
  std::string key;         // Key: "h", "k", "u", "j", "ArrowUp", ... "Enter"
  bool down = true;        // Key: pressed (true) or released
  std::string robot;       // Key: the robot it drives; empty: the first driven by keys
};
// The command in `text`, or nothing when it is not one PROTOCOL.md describes.
bool parse_view_command(const std::string& text, ViewCommand& command);

class ViewServer {
 public:
  // Listens at once. Throws ViewServerError naming the address and port when it cannot.
  explicit ViewServer(const ViewServerOptions& options);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  int port() const { return port_; }
  std::string url() const;  // http://ADDR:PORT/

  // What every page gets first on connecting: the hello, then the scene. set_scene also sends
  // the new scene to the pages already connected (after a reset).
  void set_hello(const std::string& hello);
  void set_scene(const std::string& scene);
  // The newest frame and status for every connected page. Never waits for a page: one that is
  // still writing the last ones gets only the newest when it is done.
  void send_frame(const std::string& frame, const std::string& status);
  void send_status(const std::string& status);

  // One atomic load: whether any page is connected (a page given up for not reading is not).
  bool has_clients() const { return clients_.load(std::memory_order_relaxed) > 0; }
  int clients() const { return clients_.load(std::memory_order_relaxed); }
  // How many pages connected since the start; a change says a new one wants the state now.
  std::uint64_t connections() const { return connections_.load(std::memory_order_relaxed); }
  // Whether commands are waiting (one atomic load), and taking them, oldest first.
  bool has_commands() const { return pending_.load(std::memory_order_relaxed); }
  std::vector<ViewCommand> take_commands();
  // Messages from pages that were not commands PROTOCOL.md describes, and commands that found
  // the queue full (the run not taking them).
  std::uint64_t ignored_commands() const { return ignored_.load(std::memory_order_relaxed); }

  struct State;  // the civetweb callbacks' view of the server

 private:
  std::unique_ptr<State> s_;
  std::string bind_;
  int port_ = 0;
  std::atomic<int> clients_{0};
  std::atomic<std::uint64_t> connections_{0};
  std::atomic<bool> pending_{false};
  std::atomic<std::uint64_t> ignored_{0};
};

}  // namespace sear
