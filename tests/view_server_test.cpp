// The viewer's server alone: one listener per port, only the page's folder and three.js's two
// files served whatever the request's spelling, the messages in PROTOCOL.md's order, commands
// parsed, and pages that read slowly, stop reading or leave mid-frame harming no one.
#include <arpa/inet.h>
#include <civetweb.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.hpp"
#include "view/view_server.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;
constexpr const char* kThreeDir = "/usr/share/javascript/three";

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void write_file(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A page folder with an index and one more file, beside a secret a client must never read.
struct PageDir {
  test::TempDir root;
  fs::path page = root.path() / "page";
  PageDir() {
    fs::create_directory(page);
    write_file(page / "index.html", "<html>the viewer</html>");
    write_file(page / "main.js", "// the page's script");
    write_file(root.path() / "secret.txt", "SECRET-OUTSIDE");
    fs::create_symlink(root.path() / "secret.txt", page / "link_out.txt");
    fs::create_directory_symlink(root.path(), page / "up");
  }
  ViewServerOptions options(int port = 0) const {
    ViewServerOptions o;
    o.port = port;
    o.page_dir = page.string();
    o.three_dir = kThreeDir;
    return o;
  }
};

int connect_to(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

void send_all(int fd, const std::string& text) {
  for (std::size_t sent = 0; sent < text.size();) {
    const ssize_t n = ::send(fd, text.data() + sent, text.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;
    sent += static_cast<std::size_t>(n);
  }
}

std::string host_of(int port) { return "127.0.0.1:" + std::to_string(port); }

// A request exactly as written (no client library normalises its path), the whole response.
std::string raw_request(int port, const std::string& target, const std::string& host = "") {
  const int fd = connect_to(port);
  if (fd < 0) return {};
  send_all(fd, "GET " + target + " HTTP/1.1\r\nHost: " + (host.empty() ? host_of(port) : host) +
                   "\r\nConnection: close\r\n\r\n");
  std::string response;
  char buffer[65536];
  for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) response.append(buffer, static_cast<std::size_t>(n));
  ::close(fd);
  return response;
}

int status_of(const std::string& response) {
  return response.size() > 12 && response.compare(0, 5, "HTTP/") == 0 ? std::atoi(response.c_str() + 9) : -1;
}

std::string body_of(const std::string& response) {
  const auto at = response.find("\r\n\r\n");
  return at == std::string::npos ? std::string() : response.substr(at + 4);
}

// A WebSocket client (civetweb's own) that keeps every text message it got.
struct WsClient {
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> messages;
  bool closed = false;
  mg_connection* conn = nullptr;

  explicit WsClient(int port) {
    char error[256] = "";
    conn = mg_connect_websocket_client("127.0.0.1", port, 0, error, sizeof error, "/ws", nullptr, &WsClient::on_data,
                                       &WsClient::on_close, this);
    EXPECT_NE(conn, nullptr) << error;
  }
  ~WsClient() {
    if (!conn) return;
    // A close frame first: the server's answering close ends the client's read at once.
    const char going_away[] = {'\x03', '\xe9'};  // 1001
    mg_websocket_client_write(conn, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE, going_away, sizeof going_away);
    mg_close_connection(conn);
  }
  static int on_data(mg_connection* conn, int bits, char* data, std::size_t size, void* self) {
    auto* c = static_cast<WsClient*>(self);
    // As a browser does: the server closes pages that leave its pings unanswered.
    if ((bits & 0xf) == MG_WEBSOCKET_OPCODE_PING) mg_websocket_client_write(conn, MG_WEBSOCKET_OPCODE_PONG, data, size);
    if ((bits & 0xf) == MG_WEBSOCKET_OPCODE_TEXT) {
      std::lock_guard<std::mutex> lock(c->m);
      c->messages.emplace_back(data, size);
      c->cv.notify_all();
    }
    return 1;
  }
  static void on_close(const mg_connection*, void* self) {
    auto* c = static_cast<WsClient*>(self);
    std::lock_guard<std::mutex> lock(c->m);
    c->closed = true;
    c->cv.notify_all();
  }
  // Waits (at most 5 s, far beyond the milliseconds it takes) until `n` messages arrived.
  std::vector<std::string> wait_for(std::size_t n) {
    std::unique_lock<std::mutex> lock(m);
    cv.wait_for(lock, std::chrono::seconds(5), [&] { return messages.size() >= n; });
    return messages;
  }
  void send(const std::string& text) {
    mg_websocket_client_write(conn, MG_WEBSOCKET_OPCODE_TEXT, text.data(), text.size());
  }
};

// Until `done` holds, at most 5 s (the conditions awaited take milliseconds).
template <typename F>
bool eventually(F done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

// The opening handshake of RFC 6455 by hand, for clients that misbehave on purpose afterwards;
// `head` gets the response's head, `headers` go into the request (Host: the server's own).
int raw_websocket(int port, int receive_buffer_bytes = 0, const std::string& headers = "",
                  std::string* head_out = nullptr, int expect_status = 101) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (receive_buffer_bytes > 0)
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof receive_buffer_bytes);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  send_all(fd,
           "GET /ws HTTP/1.1\r\n" + (headers.find("Host:") == std::string::npos ? "Host: " + host_of(port) + "\r\n" : "") +
               headers + "Upgrade: websocket\r\nConnection: Upgrade\r\n"
               "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n");
  std::string head;
  char c;
  while (head.find("\r\n\r\n") == std::string::npos && ::recv(fd, &c, 1, 0) == 1) head += c;
  EXPECT_EQ(status_of(head), expect_status) << headers << head;
  if (head_out) *head_out = head;
  return fd;
}

// Exactly `n` bytes from `fd` (false: it closed or 10 s passed first).
bool recv_exactly(int fd, char* out, std::size_t n) {
  timeval tv{10, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  for (std::size_t got = 0; got < n;) {
    const ssize_t r = ::recv(fd, out + got, n - got, 0);
    if (r <= 0) return false;
    got += static_cast<std::size_t>(r);
  }
  return true;
}

// One server-to-client WebSocket frame (unmasked, RFC 6455 5.2): its opcode and payload.
bool read_ws_frame(int fd, int& opcode, std::string& payload) {
  unsigned char h[2];
  if (!recv_exactly(fd, reinterpret_cast<char*>(h), 2)) return false;
  opcode = h[0] & 0xf;
  std::uint64_t len = h[1] & 0x7f;
  if (len >= 126) {
    unsigned char ext[8];
    const std::size_t k = len == 126 ? 2 : 8;
    if (!recv_exactly(fd, reinterpret_cast<char*>(ext), k)) return false;
    len = 0;
    for (std::size_t i = 0; i < k; ++i) len = len << 8 | ext[i];
  }
  payload.resize(len);
  return len == 0 || recv_exactly(fd, payload.data(), len);
}

// Another site's page in the same browser (Origin) or a DNS-rebound name (Host) gets nothing: a
// 403 before any handshake; the page's own origin, by either local name, is accepted.
TEST(ViewServer, AnotherSitesOriginOrHostIsRefusedThePagesOwnIsNot) {
  PageDir dir;
  ViewServer server(dir.options());
  const std::string port = std::to_string(server.port());
  std::string head;
  for (const std::string& origin : {std::string("http://evil.example"), "http://evil.example:" + port,
                                    std::string("http://127.0.0.1:1"), "https://127.0.0.1:" + port, std::string("null")}) {
    ::close(raw_websocket(server.port(), 0, "Origin: " + origin + "\r\n", &head, 403));
    EXPECT_NE(head.find("403"), std::string::npos) << origin;
  }
  ::close(raw_websocket(server.port(), 0, "Host: attacker.example:" + port + "\r\nOrigin: http://attacker.example:" +
                                              port + "\r\n", &head, 403));
  EXPECT_EQ(status_of(raw_request(server.port(), "/", "attacker.example:" + port)), 403);
  EXPECT_EQ(status_of(raw_request(server.port(), "/", "attacker.example")), 403);
  EXPECT_EQ(status_of(raw_request(server.port(), "/", "127.0.0.1.attacker.example:" + port)), 403);
  EXPECT_EQ(server.clients(), 0);
  EXPECT_EQ(status_of(raw_request(server.port(), "/", "localhost:" + port)), 200);
  EXPECT_EQ(status_of(raw_request(server.port(), "/", "LocalHost")), 200);  // civetweb's client sends no port
  const int own = raw_websocket(server.port(), 0, "Origin: http://127.0.0.1:" + port + "\r\n");
  const int by_name = raw_websocket(server.port(), 0, "Host: localhost:" + port + "\r\nOrigin: http://localhost:" + port + "\r\n");
  const int no_origin = raw_websocket(server.port());  // not a browser: no Origin
  EXPECT_TRUE(eventually([&] { return server.clients() == 3; }));
  for (int fd : {own, by_name, no_origin}) ::close(fd);
}

// Bound to every interface the Host is whatever name reached it; the Origin must be that one.
TEST(ViewServer, OnEveryInterfaceTheOriginMustBeTheHostsOwn) {
  PageDir dir;
  ViewServerOptions options = dir.options();
  options.bind = "0.0.0.0";
  ViewServer server(options);
  const std::string host = "192.0.2.7:" + std::to_string(server.port());
  EXPECT_EQ(status_of(raw_request(server.port(), "/", host)), 200);
  ::close(raw_websocket(server.port(), 0, "Host: " + host + "\r\nOrigin: http://evil.example\r\n", nullptr, 403));
  const int own = raw_websocket(server.port(), 0, "Host: " + host + "\r\nOrigin: http://" + host + "\r\n");
  EXPECT_TRUE(eventually([&] { return server.clients() == 1; }));
  ::close(own);
}

// A page beyond the eight is told why in a close frame: 1013, try again later, and the cap.
void expect_refused_with_1013(int fd) {
  int opcode = 0;
  std::string payload;
  ASSERT_TRUE(read_ws_frame(fd, opcode, payload));
  EXPECT_EQ(opcode, MG_WEBSOCKET_OPCODE_CONNECTION_CLOSE);
  ASSERT_GE(payload.size(), 2u);
  EXPECT_EQ((static_cast<unsigned char>(payload[0]) << 8) | static_cast<unsigned char>(payload[1]), 1013);
  EXPECT_NE(payload.find("at most 8 pages"), std::string::npos) << payload;
}

// Each page keeps a worker thread: a ninth is told why in a close frame (1013, try again later)
// and the page's files are still served meanwhile.
TEST(ViewServer, TheNinthPageIsRefusedWithAClearClose) {
  PageDir dir;
  ViewServer server(dir.options());
  server.set_hello(R"({"type":"hello"})");
  std::vector<std::unique_ptr<WsClient>> pages;
  for (int i = 0; i < 8; ++i) pages.push_back(std::make_unique<WsClient>(server.port()));
  ASSERT_TRUE(eventually([&] { return server.clients() == 8; }));
  const int ninth = raw_websocket(server.port());
  expect_refused_with_1013(ninth);
  EXPECT_EQ(server.clients(), 8);
  EXPECT_EQ(status_of(raw_request(server.port(), "/")), 200);
  ::close(ninth);
  pages.pop_back();  // one leaves: a new one is let in
  ASSERT_TRUE(eventually([&] { return server.clients() == 7; }));
  WsClient again(server.port());
  EXPECT_TRUE(eventually([&] { return server.clients() == 8; }));
  EXPECT_EQ(again.wait_for(1).size(), 1u);
}

// Connections held open lock no one out: 15 WebSockets (8 pages and 7 refused ones that never
// read their close) and 50 connections that sent half a request and wait. A new page still gets
// its files and a ninth WebSocket its 1013 close, within the 3 s a half-sent request may hold a
// worker thread (the server's request timeout), where they used to wait for minutes.
TEST(ViewServer, HeldConnectionsLeaveRoomForANewPage) {
  PageDir dir;
  ViewServer server(dir.options());
  server.set_hello(R"({"type":"hello"})");
  std::vector<int> held;
  for (int i = 0; i < 15; ++i) held.push_back(raw_websocket(server.port()));
  ASSERT_TRUE(eventually([&] { return server.clients() == 8; }));
  for (int i = 0; i < 50; ++i) {
    const int fd = connect_to(server.port());
    ASSERT_GE(fd, 0);
    send_all(fd, "GET / HTTP/1.1\r\nHost: " + host_of(server.port()) + "\r\n");
    held.push_back(fd);
  }
  const int page = connect_to(server.port());
  ASSERT_GE(page, 0);
  send_all(page, "GET / HTTP/1.1\r\nHost: " + host_of(server.port()) + "\r\nConnection: close\r\n\r\n");
  char head[12] = {};
  EXPECT_TRUE(recv_exactly(page, head, sizeof head - 1)) << "no answer within 10 s";  // 3 s, and room
  EXPECT_EQ(std::string(head), "HTTP/1.1 20");
  ::close(page);
  const int ninth = raw_websocket(server.port());
  expect_refused_with_1013(ninth);
  ::close(ninth);
  for (int fd : held) ::close(fd);
}

// A page, three.js or a replay is never an old copy from the browser's cache.
TEST(ViewServer, NothingServedIsCached) {
  PageDir dir;
  ViewServerOptions options = dir.options();
  options.replay_file = (dir.root.path() / "r.gz").string();
  write_file(options.replay_file, "not really gzip");
  ViewServer server(options);
  for (const char* target : {"/", "/main.js", "/three/three.min.js", "/replay"}) {
    const std::string response = raw_request(server.port(), target);
    const std::string head = response.substr(0, response.find("\r\n\r\n"));
    EXPECT_EQ(status_of(response), 200) << target;
    EXPECT_NE(head.find("max-age=0"), std::string::npos) << target << "\n" << head;
    EXPECT_NE(head.find("no-cache"), std::string::npos) << target << "\n" << head;
    EXPECT_EQ(head.find("max-age=3600"), std::string::npos) << target << "\n" << head;
  }
}

// A page that reads slowly gets only the newest frame, and each status says how many frames it
// missed since the last: what it got and what it was told it missed add up to every frame sent.
TEST(ViewServer, FramesASlowPageMissedAreCountedInTheNextStatus) {
  PageDir dir;
  ViewServer server(dir.options());
  const int slow = raw_websocket(server.port(), 4096);
  ASSERT_TRUE(eventually([&] { return server.clients() == 1; }));
  // 20 frames of 1 MiB, sent at once: far more than the socket buffers hold while it is not read.
  const std::string padding(1 << 20, 'x');
  constexpr int kFrames = 20;
  for (int i = 0; i < kFrames; ++i)
    server.send_frame(R"({"type":"frame","i":)" + std::to_string(i) + R"(,"pad":")" + padding + "\"}",
                      R"({"type":"status","i":)" + std::to_string(i) + "}");
  int frames = 0, skipped = 0, last_status = -1;
  while (last_status != kFrames - 1) {
    int opcode = 0;
    std::string payload;
    ASSERT_TRUE(read_ws_frame(slow, opcode, payload)) << frames << " frames, " << skipped << " skipped";
    if (payload.compare(0, 16, R"({"type":"frame",)") == 0) ++frames;
    if (payload.compare(0, 17, R"({"type":"status",)") == 0) {
      const auto at = payload.find(R"("frames_skipped":)");
      ASSERT_NE(at, std::string::npos) << payload;
      skipped += std::atoi(payload.c_str() + at + 17);
      last_status = std::atoi(payload.c_str() + payload.find(R"("i":)") + 4);
    }
  }
  EXPECT_EQ(frames + skipped, kFrames);
  EXPECT_GT(skipped, 0);
  ::close(slow);
}

// The only page stops reading: after the write timeout it no longer counts, so that the run
// builds no frames for nobody.
TEST(ViewServer, APageAloneThatStopsReadingNoLongerCountsAfterTheTimeout) {
  PageDir dir;
  ViewServerOptions options = dir.options();
  options.write_timeout_ms = 300;
  ViewServer server(options);
  const int stuck = raw_websocket(server.port(), 4096);
  ASSERT_TRUE(eventually([&] { return server.has_clients(); }));
  const std::string padding(1 << 20, 'x');  // 8 MiB in all: more than the socket buffers hold
  for (int i = 0; i < 8; ++i) server.send_frame(R"({"type":"frame","pad":")" + padding + "\"}", "{}");
  // Given up after the 0.3 s timeout; eventually() waits 5 s, so a page never given up fails
  // here (no wall-clock bound beyond that: a loaded host may be slow to schedule the watchdog).
  ASSERT_TRUE(eventually([&] { return !server.has_clients(); }));
  ::close(stuck);
}

TEST(ViewServer, SecondServerOnTheSamePortIsRefusedNamingAddressAndPort) {
  PageDir dir;
  ViewServer first(dir.options(0));
  ASSERT_GT(first.port(), 0);
  try {
    ViewServer second(dir.options(first.port()));
    FAIL() << "a second server listened on port " << first.port();
  } catch (const ViewServerError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("127.0.0.1 port " + std::to_string(first.port())), std::string::npos) << what;
    EXPECT_NE(what.find("Address already in use"), std::string::npos) << what;
    EXPECT_NE(what.find("--port"), std::string::npos) << what;
  }
  // The first one still serves.
  EXPECT_EQ(status_of(raw_request(first.port(), "/")), 200);
}

TEST(ViewServer, ServesThePageFolderAndNothingOutsideIt) {
  PageDir dir;
  ViewServer server(dir.options());
  const std::string index = raw_request(server.port(), "/");
  EXPECT_EQ(status_of(index), 200);
  EXPECT_EQ(body_of(index), "<html>the viewer</html>");
  EXPECT_EQ(body_of(raw_request(server.port(), "/main.js")), "// the page's script");
  const std::string secret_path = (dir.root.path() / "secret.txt").string();
  for (const std::string& target :
       {std::string("/../secret.txt"), std::string("/%2e%2e/secret.txt"), std::string("/%2E%2E%2Fsecret.txt"),
        std::string("/..%2fsecret.txt"), std::string("/main.js/../../secret.txt"), std::string("/./../secret.txt"),
        std::string("/%2e%2e%2f%2e%2e%2f%2e%2e%2f%2e%2e%2fetc/passwd"), std::string("//etc/passwd"),
        std::string("/etc/passwd"), secret_path, "/" + secret_path, std::string("/link_out.txt"),
        std::string("/up/secret.txt"), std::string("/up/page/../secret.txt"), std::string("/three/../../secret.txt"),
        std::string("/three/..%2f..%2fsecret.txt"), std::string("http://127.0.0.1/../secret.txt"),
        std::string("/up/"), std::string("/secret.txt%00.html")}) {
    const std::string response = raw_request(server.port(), target);
    EXPECT_NE(status_of(response), 200) << target;
    EXPECT_EQ(response.find("SECRET-OUTSIDE"), std::string::npos) << target;
    EXPECT_EQ(response.find("root:"), std::string::npos) << target;
  }
}

TEST(ViewServer, ThreeJsIsServedOnlyForItsTwoFiles) {
  PageDir dir;
  ViewServer server(dir.options());
  const std::string three = raw_request(server.port(), "/three/three.min.js");
  EXPECT_EQ(status_of(three), 200);
  EXPECT_EQ(body_of(three), read_file(std::string(kThreeDir) + "/build/three.min.js"));
  const std::string orbit = raw_request(server.port(), "/three/OrbitControls.js");
  EXPECT_EQ(body_of(orbit), read_file(std::string(kThreeDir) + "/examples/js/controls/OrbitControls.js"));
  for (const char* target : {"/three/", "/three/three.js", "/three/build/three.min.js", "/three/three.module.js",
                             "/three/examples/js/controls/OrbitControls.js", "/replay"})
    EXPECT_EQ(status_of(raw_request(server.port(), target)), 404) << target;
}

TEST(ViewServer, MissingThreeJsIsAClearErrorNamingTheDebianPackage) {
  PageDir dir;
  ViewServerOptions options = dir.options();
  options.three_dir = (dir.root.path() / "no-three").string();
  try {
    ViewServer server(options);
    FAIL();
  } catch (const ViewServerError& e) {
    EXPECT_NE(std::string(e.what()).find("libjs-three"), std::string::npos) << e.what();
  }
}

TEST(ViewServer, APageGetsHelloSceneThenTheNewestFramesAndItsCommandsAreQueued) {
  PageDir dir;
  ViewServer server(dir.options());
  server.set_hello(R"({"type":"hello"})");
  server.set_scene(R"({"type":"scene"})");
  EXPECT_FALSE(server.has_clients());
  WsClient page(server.port());
  ASSERT_TRUE(eventually([&] { return server.has_clients(); }));
  auto got = page.wait_for(2);
  ASSERT_GE(got.size(), 2u);
  EXPECT_EQ(got[0], R"({"type":"hello"})");
  EXPECT_EQ(got[1], R"({"type":"scene"})");
  server.send_frame(R"({"type":"frame","t":1})", R"({"type":"status","t":1})");
  got = page.wait_for(4);
  ASSERT_GE(got.size(), 4u);
  EXPECT_EQ(got[2], R"({"type":"frame","t":1})");
  EXPECT_EQ(got[3], R"({"type":"status","t":1,"frames_skipped":0})");

  page.send(R"({"cmd":"step","n":3})");
  page.send("not json");
  page.send(R"({"cmd":"step","n":-2})");
  page.send(R"({"cmd":"fly"})");
  page.send(R"({"cmd":"key","key":"U","down":true,"robot":"rover"})");
  std::vector<ViewCommand> commands;
  ASSERT_TRUE(eventually([&] {
    for (auto& c : server.take_commands()) commands.push_back(c);
    return commands.size() >= 2 && server.ignored_commands() >= 3;
  }));
  ASSERT_EQ(commands.size(), 2u);
  EXPECT_EQ(commands[0].kind, ViewCommand::Kind::Step);
  EXPECT_EQ(commands[0].steps, 3);
  EXPECT_EQ(commands[1].kind, ViewCommand::Kind::Key);
  EXPECT_EQ(commands[1].key, "u");
  EXPECT_EQ(commands[1].robot, "rover");
  EXPECT_EQ(server.ignored_commands(), 3u);
  EXPECT_FALSE(server.has_commands());
}

TEST(ViewServer, CommandsAreParsedAsProtocolSays) {
  ViewCommand c;
  ASSERT_TRUE(parse_view_command(R"({"cmd":"speed","factor":0})", c));
  EXPECT_EQ(c.kind, ViewCommand::Kind::Speed);
  EXPECT_EQ(c.factor, 0);
  EXPECT_FALSE(parse_view_command(R"({"cmd":"speed","factor":-1})", c));
  // Slower than 0.001x would hold a step for minutes: refused, as is the overflowing 1e-300.
  for (const char* factor : {"1e-6", "1e-300", "0.0009", "1e7", "1e400"})
    EXPECT_FALSE(parse_view_command(std::string(R"({"cmd":"speed","factor":)") + factor + "}", c)) << factor;
  for (double factor : {0.001, 1.0, 1e6}) {
    ASSERT_TRUE(parse_view_command(R"({"cmd":"speed","factor":)" + std::to_string(factor) + "}", c));
    EXPECT_EQ(c.factor, factor);
  }
  EXPECT_FALSE(parse_view_command(R"({"cmd":"speed"})", c));
  ASSERT_TRUE(parse_view_command(R"({"cmd":"key","key":"ArrowLeft","down":false})", c));
  EXPECT_FALSE(c.down);
  EXPECT_FALSE(parse_view_command(R"({"cmd":"key","key":"x"})", c));
  EXPECT_FALSE(parse_view_command(R"({"cmd":"step","n":1.5})", c));
  EXPECT_FALSE(parse_view_command(R"(["pause"])", c));
  ASSERT_TRUE(parse_view_command(R"({"cmd":"start"})", c));
  EXPECT_EQ(c.kind, ViewCommand::Kind::Start);
}

// One page stops reading (its socket buffers fill), another leaves halfway through a frame: the
// run's sends never wait for them, and a third page that reads goes on getting every new frame.
// The one that stopped reading is given up after the write timeout and closed by the server.
TEST(ViewServer, PagesThatStopReadingOrLeaveMidFrameHoldUpNoOne) {
  PageDir dir;
  ViewServerOptions options = dir.options();
  options.write_timeout_ms = 300;  // the stuck page is given up within the test's time
  ViewServer server(options);
  server.set_hello(R"({"type":"hello"})");
  const int stuck = raw_websocket(server.port(), 4096);
  const int leaving = raw_websocket(server.port());
  WsClient reader(server.port());
  ASSERT_TRUE(eventually([&] { return server.connections() == 3; }));
  // Frames of 256 KiB: a few fill the stuck page's socket buffers on both ends.
  const std::string padding(256 * 1024, 'x');
  char half[1000];
  ASSERT_GT(::recv(leaving, half, sizeof half, 0), 0);
  for (int i = 0; i < 200; ++i) {
    server.send_frame(R"({"type":"frame","i":)" + std::to_string(i) + R"(,"pad":")" + padding + "\"}", "{}");
    if (i == 20) {
      ASSERT_GT(::recv(leaving, half, sizeof half, 0), 0);  // the middle of some frame
      ::close(leaving);
    }
    // The reader has this frame before the next is sent: no page waits on another's writes.
    const std::string wanted = R"({"type":"frame","i":)" + std::to_string(i) + ",";
    ASSERT_TRUE(eventually([&] {
      std::lock_guard<std::mutex> lock(reader.m);
      for (const auto& m : reader.messages)
        if (m.compare(0, wanted.size(), wanted) == 0) return true;
      return false;
    })) << "frame " << i;
  }
  // The page that left is gone, the stuck one given up (a write waited 300 ms): only the reader
  // counts, and frames are still sent to it.
  EXPECT_TRUE(eventually([&] { return server.clients() == 1; })) << server.clients() << " pages counted";
  EXPECT_TRUE(server.has_clients());
  server.send_frame(R"({"type":"frame","i":"after"})", "{}");
  EXPECT_TRUE(eventually([&] {
    std::lock_guard<std::mutex> lock(reader.m);
    return std::find(reader.messages.begin(), reader.messages.end(), R"({"type":"frame","i":"after"})") !=
           reader.messages.end();
  }));
  // The server closes the stuck page's connection (a ping after 300 ms of silence cannot be
  // written): reading what it was sent ends in the end of the stream, within seconds.
  char buffer[65536];
  timeval tv{5, 0};
  ::setsockopt(stuck, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  ssize_t n = 0;
  while ((n = ::recv(stuck, buffer, sizeof buffer, 0)) > 0) {
  }
  EXPECT_TRUE(n == 0 || errno == ECONNRESET) << "recv: " << n << " errno " << errno;
  ::close(stuck);
  EXPECT_EQ(server.clients(), 1);
}

}  // namespace
}  // namespace sear
