#include "view/view_server.hpp"

#include <arpa/inet.h>
#include <civetweb.h>
#include <fmt/format.h>
#include <limits.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

namespace sear {
namespace {

// Worker threads: each open WebSocket keeps one, and so does each connection whose request is
// still being read. Well beyond the pages watching, so that connections that send half a request
// and wait (50 of them from loopback used to lock every page out for minutes) leave threads to
// serve a new page its files, or its refusal.
constexpr const char* kWorkerThreads = "64";
// Pages watching at once: so that the page's files are still served to a ninth page, which is
// told why it is refused.
constexpr std::size_t kMaxPages = 8;
// How long a connection may take to send its request, and the longest a single read or write of
// the page's files may wait: a request is a few hundred bytes, on loopback or a LAN a few ms. A
// connection that holds a worker thread without finishing its request lets it go after this.
constexpr int kRequestTimeoutMs = 3000;
// WebSocket close code 1013, "try again later" (RFC 6455, 7.4.1 / IANA registry).
constexpr unsigned kCloseTryLater = 1013;
// A command is a few dozen bytes; anything much longer is not one. civetweb (1.15) has no option
// bounding a WebSocket message's size: a longer one is read whole, then ignored here.
constexpr std::size_t kMaxCommandBytes = 4096;
// Commands waiting for the run: a page sends a few a second; more than this while the run is
// not taking them (a long step, the end of a run) are dropped and counted as ignored.
constexpr std::size_t kMaxQueuedCommands = 1024;
// The senders' nice value (0: the run's own, 19: the lowest).
constexpr int kSenderNice = 10;
// The speeds a page may ask for besides 0 (as fast as possible): at 0.001x a 1 ms step takes a
// second of wall time; a million times real time is beyond any host.
constexpr double kMinSpeed = 0.001, kMaxSpeed = 1e6;
// The most steps one "step" command may ask for: a day of 1 ms steps.
constexpr std::int64_t kMaxSteps = 86'400'000;

// One connected page: what is still to be sent to it, and the thread that sends it, so that a
// page that reads slowly holds up no one but itself.
struct Client {
  mg_connection* conn = nullptr;
  std::atomic<int>* watching = nullptr;  // the server's count of pages watching
  std::mutex m;
  std::condition_variable cv;
  std::deque<std::string> queue;  // hello, scenes: each sent, in order
  std::string frame, status;      // only the newest of each
  bool has_frame = false, has_status = false;
  std::uint64_t skipped = 0;  // frames replaced before they were sent, since the last status sent
  // No frame sent yet. The first is kept until it is sent, a newer one dropped instead: it holds
  // the log's whole ring, what was said before the page came, and it shows where a run held for
  // its first page starts. Replaced by a frame some steps on, both were lost under load.
  bool first_frame = true;
  bool closed = false;        // the connection is going: send nothing more
  bool counted = true;        // in *watching
  std::atomic<bool> dead{false};  // a write failed: nothing more is queued, civetweb closes it
  int fd = -1;                    // its socket (-1: not found), shut down when a write is stuck
  bool writing = false;           // since writing_since
  std::chrono::steady_clock::time_point writing_since;
  std::thread sender;
};

// With c->m held: the page no longer counts as watching (once, whoever sees it go first).
void uncount(Client* c) {
  if (!c->counted) return;
  c->counted = false;
  c->watching->fetch_sub(1, std::memory_order_relaxed);
}

// The status with "frames_skipped": n added (PROTOCOL.md), so that the page can say that log
// entries of frames it never got are missing.
std::string with_skipped(std::string status, std::uint64_t skipped) {
  const auto close = status.rfind('}');
  if (close == std::string::npos) return status;
  const auto last = status.find_last_not_of(" \t\r\n", close == 0 ? std::string::npos : close - 1);
  const bool empty = last == std::string::npos || status[last] == '{';
  status.insert(close, fmt::format("{}\"frames_skipped\":{}", empty ? "" : ",", skipped));
  return status;
}

void send_loop(Client* c) {
  // Below the run's threads: on a machine with as many cores as the simulator and its firmware
  // keep busy, a page's writes should wait for a free moment rather than preempt them.
  ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), kSenderNice);
  std::unique_lock<std::mutex> lock(c->m);
  for (;;) {
    c->cv.wait(lock, [c] { return c->closed || !c->queue.empty() || c->has_frame || c->has_status; });
    if (c->closed) return;
    std::string text;
    if (!c->queue.empty()) {
      text = std::move(c->queue.front());
      c->queue.pop_front();
    } else if (c->has_frame) {
      text = std::move(c->frame);
      c->has_frame = false;
      c->first_frame = false;
    } else {
      text = with_skipped(std::move(c->status), c->skipped);
      c->skipped = 0;
      c->has_status = false;
    }
    c->writing = true;
    c->writing_since = std::chrono::steady_clock::now();
    lock.unlock();
    const int n = mg_websocket_write(c->conn, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
    lock.lock();
    c->writing = false;
    // Gone, or shut down by the watchdog for not reading (a frame may be half written): nothing
    // more is built or queued for it, and civetweb, its socket shut down, closes it.
    if (n <= 0) {
      c->dead.store(true, std::memory_order_relaxed);
      c->queue.clear();
      c->frame.clear();
      c->status.clear();
      c->has_frame = c->has_status = false;
      uncount(c);
      return;
    }
  }
}

std::string listen_spec(const std::string& bind, int port) {
  return bind.find(':') != std::string::npos ? fmt::format("[{}]:{}", bind, port) : fmt::format("{}:{}", bind, port);
}

std::string real_path(const std::string& path) {
  char buffer[PATH_MAX];
  return ::realpath(path.c_str(), buffer) ? std::string(buffer) : std::string();
}

// A TCP socket for a numeric address and port, handed to `use` with the address; false when the
// address is not numeric. For the two times the server talks to its own port.
template <class F>
bool with_socket(const std::string& address, int port, F use) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICHOST | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  if (::getaddrinfo(address.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || !found) return false;
  const int fd = ::socket(found->ai_family, found->ai_socktype, found->ai_protocol);
  if (fd >= 0) {
    use(fd, *found);
    ::close(fd);
  }
  ::freeaddrinfo(found);
  return true;
}

// civetweb says only that it failed to set up its ports; binding the address here once more
// says why (most often: another server has it).
std::string bind_failure(const std::string& bind, int port, const std::string& civetweb_says) {
  std::string why = civetweb_says;
  const bool numeric = with_socket(bind, port, [&](int fd, const addrinfo& a) {
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd, a.ai_addr, a.ai_addrlen) != 0) why = ::strerror(errno);
  });
  return numeric ? why : "not a numeric IPv4 or IPv6 address";
}

void wake_listener(const std::string& address, int port) {
  with_socket(address, port, [](int fd, const addrinfo& a) { (void)::connect(fd, a.ai_addr, a.ai_addrlen); });
}

bool is_regular_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

// The socket civetweb accepted `conn` on, which its API does not give: the one of this process
// whose peer is the request's remote address and port and whose own port is `port`. -1: none.
int connection_socket(const mg_connection* conn, int port) {
  const mg_request_info* ri = mg_get_request_info(conn);
  if (!ri) return -1;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd", error)) {
    const int fd = std::atoi(entry.path().filename().c_str());
    sockaddr_storage peer{}, local{};
    socklen_t peer_len = sizeof peer, local_len = sizeof local;
    if (::getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &peer_len) != 0 ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&local), &local_len) != 0 || peer.ss_family != local.ss_family)
      continue;
    char address[INET6_ADDRSTRLEN] = "";
    int peer_port = 0, local_port = 0;
    if (peer.ss_family == AF_INET) {
      const auto& p4 = reinterpret_cast<const sockaddr_in&>(peer);
      ::inet_ntop(AF_INET, &p4.sin_addr, address, sizeof address);
      peer_port = ntohs(p4.sin_port);
      local_port = ntohs(reinterpret_cast<const sockaddr_in&>(local).sin_port);
    } else if (peer.ss_family == AF_INET6) {
      const auto& p6 = reinterpret_cast<const sockaddr_in6&>(peer);
      ::inet_ntop(AF_INET6, &p6.sin6_addr, address, sizeof address);
      peer_port = ntohs(p6.sin6_port);
      local_port = ntohs(reinterpret_cast<const sockaddr_in6&>(local).sin6_port);
    }
    if (peer_port == ri->remote_port && local_port == port && std::strcmp(address, ri->remote_addr) == 0) return fd;
  }
  return -1;
}

std::string lower(const char* text) {
  std::string s = text ? text : "";
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

bool is_loopback(const std::string& bind) { return bind.rfind("127.", 0) == 0 || bind == "::1"; }

// Refuses the request with 403 and `why`; for the callbacks, which return nonzero then. Written
// by hand: before a WebSocket handshake civetweb's mg_send_http_error sends only the body.
int refuse(const mg_connection* conn, const char* why) {
  mg_printf(const_cast<mg_connection*>(conn),
            "HTTP/1.1 403 Forbidden\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: %zu\r\n"
            "Connection: close\r\n\r\n%s",
            std::strlen(why), why);
  return 403;
}

}  // namespace

struct ViewServer::State {
  ViewServer* server = nullptr;
  ViewServerOptions options;
  std::string page_root;  // the page's folder, symlinks resolved
  // Bound to a loopback address: the Host headers (lower case) a request may carry, and the
  // Origins a WebSocket may come from; other names are another site's (DNS rebinding).
  bool loopback = true;
  std::vector<std::string> hosts, origins;
  std::map<std::string, std::string> three_files;  // URI -> file: the only ones served from three_dir
  mg_context* ctx = nullptr;
  std::mutex m;  // guards what follows
  std::vector<std::shared_ptr<Client>> clients;
  std::string hello, scene;
  std::vector<ViewCommand> commands;
  // civetweb (1.15) waits for ever on a write a page does not read (its issue #847): a watchdog
  // shuts down the socket of a page whose write has waited longer than the write timeout.
  std::chrono::milliseconds write_timeout{2000};
  std::mutex watch_m;
  std::condition_variable watch_cv;
  bool watch_stop = false;
  std::thread watchdog;
  void watch();

  // 0 when the request may be served; else the HTTP status it was refused with.
  int check_origin(const mg_connection* conn, bool websocket) const;
  static int on_request(mg_connection* conn, void* data);
  static int on_ws_connect(const mg_connection* conn, void* data);
  static void on_ws_ready(mg_connection* conn, void* data);
  static int on_ws_data(mg_connection* conn, int bits, char* text, std::size_t size, void* data);
  static void on_ws_close(const mg_connection* conn, void* data);
};

bool parse_view_command(const std::string& text, ViewCommand& command) {
  if (text.size() > kMaxCommandBytes) return false;
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (!j.is_object() || !j.contains("cmd") || !j["cmd"].is_string()) return false;
  const std::string cmd = j["cmd"].get<std::string>();
  ViewCommand c;
  if (cmd == "pause") {
    c.kind = ViewCommand::Kind::Pause;
  } else if (cmd == "resume") {
    c.kind = ViewCommand::Kind::Resume;
  } else if (cmd == "reset") {
    c.kind = ViewCommand::Kind::Reset;
  } else if (cmd == "start") {
    c.kind = ViewCommand::Kind::Start;
  } else if (cmd == "step") {
    c.kind = ViewCommand::Kind::Step;
    if (j.contains("n")) {
      if (!j["n"].is_number_integer()) return false;
      c.steps = j["n"].get<std::int64_t>();
    }
    if (c.steps < 1 || c.steps > kMaxSteps) return false;
  } else if (cmd == "speed") {
    c.kind = ViewCommand::Kind::Speed;
    if (!j.contains("factor") || !j["factor"].is_number()) return false;
    c.factor = j["factor"].get<double>();
    // 0: as fast as possible. Slower than kMinSpeed a step of the run would take minutes.
    if (!(c.factor == 0 || (c.factor >= kMinSpeed && c.factor <= kMaxSpeed))) return false;
  } else if (cmd == "key") {
    c.kind = ViewCommand::Kind::Key;
    static const char* const keys[] = {"h", "k", "u", "j", "ArrowUp", "ArrowDown", "ArrowLeft", "ArrowRight", "Enter"};
    if (!j.contains("key") || !j["key"].is_string()) return false;
    c.key = j["key"].get<std::string>();
    if (c.key.size() == 1) c.key[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(c.key[0])));
    if (std::find(std::begin(keys), std::end(keys), c.key) == std::end(keys)) return false;
    if (j.contains("down")) {
      if (!j["down"].is_boolean()) return false;
      c.down = j["down"].get<bool>();
    }
    if (j.contains("robot")) {
      if (!j["robot"].is_string()) return false;
      c.robot = j["robot"].get<std::string>();
    }
  } else {
    return false;
  }
  command = std::move(c);
  return true;
}

int ViewServer::State::check_origin(const mg_connection* conn, bool websocket) const {
  const std::string host = lower(mg_get_header(conn, "Host"));
  const char* origin = mg_get_header(conn, "Origin");
  if (loopback) {
    if (std::find(hosts.begin(), hosts.end(), host) == hosts.end())
      return refuse(conn, "The viewer answers only to its own address (Host: 127.0.0.1:PORT or localhost:PORT)");
    if (websocket && origin && std::find(origins.begin(), origins.end(), lower(origin)) == origins.end())
      return refuse(conn, "The viewer's WebSocket is for the viewer's own page only");
  } else if (websocket && origin && (host.empty() || lower(origin) != "http://" + host)) {
    return refuse(conn, "The viewer's WebSocket is for the viewer's own page only");
  }
  return 0;
}

int ViewServer::State::on_request(mg_connection* conn, void* data) {
  State& s = *static_cast<State*>(data);
  if (const int refused = s.check_origin(conn, false)) return refused;
  const mg_request_info* ri = mg_get_request_info(conn);
  const std::string method = ri->request_method ? ri->request_method : "";
  if (method != "GET" && method != "HEAD") {
    mg_send_http_error(conn, 405, "%s", "Only GET and HEAD");
    return 405;
  }
  // local_uri is percent-decoded, its dot segments resolved by civetweb; the checks below do
  // not rely on that.
  const std::string uri = ri->local_uri ? ri->local_uri : "";
  if (uri == "/replay" && !s.options.replay_file.empty()) {
    mg_send_mime_file2(conn, s.options.replay_file.c_str(), "application/x-ndjson", "Content-Encoding: gzip\r\n");
    return 200;
  }
  if (const auto three = s.three_files.find(uri); three != s.three_files.end()) {
    mg_send_mime_file(conn, three->second.c_str(), "application/javascript");
    return 200;
  }
  // Any other path names a file of the page's folder, or nothing: it must resolve, symlinks
  // followed, to a regular file inside that folder.
  std::string relative = uri.empty() || uri.back() == '/' ? uri + "index.html" : uri;
  const std::string file = relative.find('\0') == std::string::npos && relative.front() == '/'
                               ? real_path(s.page_root + relative)
                               : std::string();
  if (file.empty() || file.compare(0, s.page_root.size() + 1, s.page_root + "/") != 0 || !is_regular_file(file)) {
    mg_send_http_error(conn, 404, "%s", "Not found");
    return 404;
  }
  mg_send_file(conn, file.c_str());
  return 200;
}

// Another site's page (its Origin) or a name that is not this server's (its Host) is refused
// with 403 before the handshake.
int ViewServer::State::on_ws_connect(const mg_connection* conn, void* data) {
  return static_cast<State*>(data)->check_origin(conn, true);
}

void ViewServer::State::watch() {
  std::unique_lock<std::mutex> watch_lock(watch_m);
  while (!watch_stop) {
    watch_cv.wait_for(watch_lock, std::max(std::chrono::milliseconds(10), write_timeout / 4));
    const auto now = std::chrono::steady_clock::now();
    // While a page is in `clients` civetweb has not closed its socket (on_ws_close removes it
    // first), and while it is writing, the socket is its own: shutting it down is safe.
    std::lock_guard<std::mutex> lock(m);
    for (auto& c : clients) {
      std::lock_guard<std::mutex> client_lock(c->m);
      if (!c->writing || c->dead.load(std::memory_order_relaxed) || now - c->writing_since < write_timeout) continue;
      c->dead.store(true, std::memory_order_relaxed);
      uncount(c.get());
      if (c->fd >= 0) ::shutdown(c->fd, SHUT_RDWR);  // the write fails, civetweb's read ends
    }
  }
}

void ViewServer::State::on_ws_ready(mg_connection* conn, void* data) {
  State& s = *static_cast<State*>(data);
  auto c = std::make_shared<Client>();
  c->conn = conn;
  c->fd = connection_socket(conn, s.server->port_);
  c->watching = &s.server->clients_;
  std::unique_lock<std::mutex> lock(s.m);
  // Pages given up for not reading count too until civetweb has closed them: each keeps a thread.
  if (s.clients.size() >= kMaxPages) {
    lock.unlock();
    // A close frame whose reason the page can show; its answering close ends the connection.
    const std::string reason = fmt::format("sear: at most {} pages may watch a run; close one", kMaxPages);
    std::string payload{static_cast<char>(kCloseTryLater >> 8), static_cast<char>(kCloseTryLater & 0xff)};
    payload += reason;
    mg_websocket_write(conn, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, payload.data(), payload.size());
    return;
  }
  if (!s.hello.empty()) c->queue.push_back(s.hello);
  if (!s.scene.empty()) c->queue.push_back(s.scene);
  c->sender = std::thread(send_loop, c.get());
  mg_set_user_connection_data(conn, c.get());
  s.clients.push_back(c);
  s.server->clients_.fetch_add(1, std::memory_order_relaxed);
  s.server->connections_.fetch_add(1, std::memory_order_relaxed);
}

int ViewServer::State::on_ws_data(mg_connection* conn, int bits, char* text, std::size_t size, void* data) {
  State& s = *static_cast<State*>(data);
  const int opcode = bits & 0xf;
  if (opcode == MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE) return 0;
  // Refused (too many pages) or given up: returning 0 has civetweb close it.
  const auto* c = static_cast<const Client*>(mg_get_user_connection_data(conn));
  if (!c || c->dead.load(std::memory_order_relaxed)) return 0;
  if (opcode != MG_WEBSOCKET_OPCODE_TEXT) return 1;  // pings are answered by civetweb
  ViewCommand command;
  if (!parse_view_command(std::string(text, size), command)) {
    s.server->ignored_.fetch_add(1, std::memory_order_relaxed);
    return 1;
  }
  std::lock_guard<std::mutex> lock(s.m);
  if (s.commands.size() >= kMaxQueuedCommands) {
    s.server->ignored_.fetch_add(1, std::memory_order_relaxed);
    return 1;
  }
  s.commands.push_back(std::move(command));
  s.server->pending_.store(true, std::memory_order_relaxed);
  return 1;
}

void ViewServer::State::on_ws_close(const mg_connection* conn, void* data) {
  State& s = *static_cast<State*>(data);
  auto* c = static_cast<Client*>(mg_get_user_connection_data(conn));
  if (!c) return;  // the handshake never completed
  {
    std::lock_guard<std::mutex> lock(c->m);
    c->closed = true;
  }
  c->cv.notify_one();
  // The connection is freed once this returns: its sender must be done with it.
  if (c->sender.joinable()) c->sender.join();
  std::lock_guard<std::mutex> lock(s.m);
  for (auto it = s.clients.begin(); it != s.clients.end(); ++it)
    if (it->get() == c) {
      {
        std::lock_guard<std::mutex> client_lock(c->m);
        uncount(c);
      }
      s.clients.erase(it);
      break;
    }
}

ViewServer::ViewServer(const ViewServerOptions& options) : s_(std::make_unique<State>()), bind_(options.bind) {
  State& s = *s_;
  s.server = this;
  s.options = options;
  s.page_root = real_path(options.page_dir);
  if (s.page_root.empty() || !is_regular_file(s.page_root + "/index.html"))
    throw ViewServerError(fmt::format("sear: the viewer's page is missing: no {}/index.html", options.page_dir));
  const std::string three_min = options.three_dir + "/build/three.min.js";
  const std::string orbit = options.three_dir + "/examples/js/controls/OrbitControls.js";
  if (!is_regular_file(three_min) || !is_regular_file(orbit))
    throw ViewServerError(fmt::format(
        "sear: three.js is missing ({} and {}): install Debian's libjs-three (scripts/install-deps.sh)", three_min,
        orbit));
  s.three_files = {{"/three/three.min.js", three_min}, {"/three/OrbitControls.js", orbit}};
  if (!options.replay_file.empty() && !is_regular_file(options.replay_file))
    throw ViewServerError(fmt::format("sear: {}: no such file", options.replay_file));

  static std::once_flag library;
  std::call_once(library, [] { mg_init_library(MG_FEATURES_WEBSOCKET); });
  if (options.bind.find(':') != std::string::npos && !mg_check_feature(MG_FEATURES_IPV6))
    throw ViewServerError(fmt::format(
        "sear: the viewer cannot listen on {}: this system's civetweb has no IPv6; --bind takes an IPv4 address "
        "(127.0.0.1, or 0.0.0.0 for every interface)",
        options.bind));
  const std::string ports = listen_spec(options.bind, options.port);
  const std::string timeout_ms = std::to_string(std::max(1, options.write_timeout_ms));
  const std::string request_timeout_ms = std::to_string(std::min(kRequestTimeoutMs, std::max(1, options.write_timeout_ms)));
  // static_file_max_age 0: a page edited, or a new replay, is never an hour-old copy. Pings after
  // a silent timeout: a page that stopped reading is closed when they fail or go unanswered.
  const char* config[] = {"listening_ports", ports.c_str(),
                          "document_root", s.page_root.c_str(),
                          "enable_directory_listing", "no",
                          "num_threads", kWorkerThreads,
                          "request_timeout_ms", request_timeout_ms.c_str(),
                          "websocket_timeout_ms", timeout_ms.c_str(),
                          "enable_websocket_ping_pong", "yes",
                          "static_file_max_age", "0",
                          nullptr};
  mg_callbacks callbacks{};
  // civetweb's own messages (a client gone mid-request) are no concern of the run's output.
  callbacks.log_message = [](const mg_connection*, const char*) { return 1; };
  mg_init_data init{&callbacks, &s, config};
  char error_text[256] = "";
  unsigned error_code = 0;
  mg_error_data error{&error_code, error_text, sizeof error_text};
  s.ctx = mg_start2(&init, &error);
  if (!s.ctx) {
    const std::string why = bind_failure(options.bind, options.port, error_text);
    throw ViewServerError(fmt::format(
        "sear: the viewer cannot listen on {} port {} ({}){}", options.bind, options.port, why,
        why == std::strerror(EADDRINUSE)
            ? ": is another sear view running there? Choose another port with --port N (--port 0: any free one)"
            : ""));
  }
  mg_server_port listening[4] = {};
  const int n = mg_get_server_ports(s.ctx, 4, listening);
  port_ = n > 0 ? listening[0].port : options.port;
  s.loopback = is_loopback(options.bind);
  const std::string bind_name = options.bind.find(':') != std::string::npos ? "[" + options.bind + "]" : options.bind;
  for (const std::string& name : {bind_name, std::string("127.0.0.1"), std::string("localhost")}) {
    s.hosts.push_back(lower(name.c_str()) + ":" + std::to_string(port_));
    s.origins.push_back("http://" + s.hosts.back());
    // Without the port: browsers leave out only the default one (80), civetweb's own WebSocket
    // client always; the name is what tells a rebound one (attacker.example) apart.
    s.hosts.push_back(lower(name.c_str()));
    if (port_ == 80) s.origins.push_back("http://" + s.hosts.back());
  }
  s.write_timeout = std::chrono::milliseconds(std::max(1, options.write_timeout_ms));
  s.watchdog = std::thread([&s] { s.watch(); });
  mg_set_request_handler(s.ctx, "/", &State::on_request, &s);
  mg_set_websocket_handler(s.ctx, "/ws", &State::on_ws_connect, &State::on_ws_ready, &State::on_ws_data,
                           &State::on_ws_close, &s);
}

ViewServer::~ViewServer() {
  State& s = *s_;
  {
    std::lock_guard<std::mutex> lock(s.watch_m);
    s.watch_stop = true;
  }
  s.watch_cv.notify_one();
  s.watchdog.join();
  {
    std::lock_guard<std::mutex> lock(s.m);
    for (auto& c : s.clients) {
      std::lock_guard<std::mutex> client_lock(c->m);
      c->closed = true;
      c->cv.notify_one();
      // civetweb's read of a silent page would go on until its timeout (seconds): the page
      // sees its connection end now, as it does when the run ends.
      if (c->fd >= 0) ::shutdown(c->fd, SHUT_RDWR);
    }
  }
  // civetweb's listening thread looks at its stop flag between polls of up to 2 s; a connection
  // made once the flag is up wakes it at once, so that stopping takes milliseconds.
  std::thread wake([this] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    wake_listener(bind_ == "0.0.0.0" ? "127.0.0.1" : bind_, port_);
  });
  // Every open WebSocket's close handler runs (joining its sender) before mg_stop returns.
  mg_stop(s.ctx);
  wake.join();
  for (auto& c : s.clients)
    if (c->sender.joinable()) c->sender.join();
}

std::string ViewServer::url() const {
  return bind_.find(':') != std::string::npos ? fmt::format("http://[{}]:{}/", bind_, port_)
                                              : fmt::format("http://{}:{}/", bind_, port_);
}

void ViewServer::set_hello(const std::string& hello) {
  std::lock_guard<std::mutex> lock(s_->m);
  s_->hello = hello;
}

void ViewServer::set_scene(const std::string& scene) {
  std::lock_guard<std::mutex> lock(s_->m);
  s_->scene = scene;
  for (auto& c : s_->clients) {
    if (c->dead.load(std::memory_order_relaxed)) continue;
    std::lock_guard<std::mutex> client_lock(c->m);
    c->has_frame = false;  // a frame of the run before the scene
    c->queue.push_back(scene);
    c->cv.notify_one();
  }
}

void ViewServer::send_frame(const std::string& frame, const std::string& status) {
  std::lock_guard<std::mutex> lock(s_->m);
  for (auto& c : s_->clients) {
    if (c->dead.load(std::memory_order_relaxed)) continue;
    std::lock_guard<std::mutex> client_lock(c->m);
    if (c->has_frame) ++c->skipped;  // its log entries never reach this page
    if (!c->has_frame || !c->first_frame) c->frame = frame;
    c->has_frame = c->has_status = true;
    c->status = status;
    c->cv.notify_one();
  }
}

void ViewServer::send_status(const std::string& status) {
  std::lock_guard<std::mutex> lock(s_->m);
  for (auto& c : s_->clients) {
    if (c->dead.load(std::memory_order_relaxed)) continue;
    std::lock_guard<std::mutex> client_lock(c->m);
    c->status = status;
    c->has_status = true;
    c->cv.notify_one();
  }
}

std::vector<ViewCommand> ViewServer::take_commands() {
  std::lock_guard<std::mutex> lock(s_->m);
  std::vector<ViewCommand> taken;
  taken.swap(s_->commands);
  pending_.store(false, std::memory_order_relaxed);
  return taken;
}

}  // namespace sear
