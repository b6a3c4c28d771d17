// A host program on a serial port, scripted from its command line, for the pty tests (and for a
// person poking at a simulated device): it opens the port as PC drivers do and prints, one line
// each, what it read. Wall-clock timeouts, as a real driver has; or, after trace=FILE, timeouts
// in the run's own sim time as its trace file says, so that a test waits for what the model
// does however slowly a busy host runs it.
//
//   pty_client PORT STEP...
//   trace=FILE every time from here on is sim time: the first column of FILE's last row (a run's
//              trace_ROBOT.csv, flushed row by row); a wait still ends after 60 s of wall time
//   baud=N     raw 8N1 at N baud (a standard rate), input flushed as a driver does on start
//   send=HEX   write these bytes
//   lms=S      read one SICK LMS2xx item within S seconds: prints "ack 06", "nak 15" or
//              "telegram 02 80 ..." (bytes before one: "junk ..."), or "timeout ..." with what came;
//              a power-on telegram on the way is printed as "power-on 02 80 ..." and skipped
//   read=S     read for S seconds; prints "bytes N HEX"
//   reopen     close the port, wait 0.1 s (a program restarting) and open it again; the
//              settings stay, as a serial port's do
//   sleep=S    wait
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

int port = -1;

std::string hex(const std::vector<std::uint8_t>& bytes) {
  std::string s;
  char b[4];
  for (std::uint8_t v : bytes) {
    std::snprintf(b, sizeof b, "%s%02x", s.empty() ? "" : " ", v);
    s += b;
  }
  return s;
}

std::string trace_path;  // empty: wall-clock timeouts

// The run's sim time: its trace's last complete row, 0 before there is one.
double sim_now() {
  std::FILE* f = std::fopen(trace_path.c_str(), "rb");
  if (!f) return 0;
  char tail[4096];
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  const long from = size > static_cast<long>(sizeof tail) ? size - static_cast<long>(sizeof tail) : 0;
  std::fseek(f, from, SEEK_SET);
  const std::size_t n = std::fread(tail, 1, sizeof tail, f);
  std::fclose(f);
  const std::string text(tail, n);
  const std::size_t end = text.rfind('\n');
  if (end == std::string::npos || end == 0) return 0;
  const std::size_t start = text.rfind('\n', end - 1);
  const std::string row = text.substr(start == std::string::npos ? 0 : start + 1, end);
  return row.empty() || row[0] < '0' || row[0] > '9' ? 0 : std::atof(row.c_str());  // the header: 0
}

struct Deadline {
  Clock::time_point wall;
  double sim_s;  // < 0: wall clock only
};

Deadline after(const std::string& seconds) {
  const double s = std::atof(seconds.c_str());
  if (trace_path.empty()) return {Clock::now() + std::chrono::microseconds(static_cast<long long>(s * 1e6)), -1};
  return {Clock::now() + std::chrono::seconds(60), sim_now() + s};
}

bool passed(const Deadline& d) { return Clock::now() >= d.wall || (d.sim_s >= 0 && sim_now() >= d.sim_s); }

// One byte, or -1 once the deadline has passed.
int next_byte(const Deadline& deadline) {
  for (;;) {
    if (passed(deadline)) return -1;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline.wall - Clock::now()).count();
    pollfd p{port, POLLIN, 0};
    // A sim-time deadline is looked at again every 10 ms (the trace's rows are 100 ms apart).
    if (::poll(&p, 1, static_cast<int>(deadline.sim_s >= 0 ? std::min<long long>(left, 10) : left)) <= 0) continue;
    std::uint8_t v;
    if (::read(port, &v, 1) == 1) return v;
  }
}

bool open_port(const char* path) {
  port = ::open(path, O_RDWR | O_NOCTTY);
  if (port < 0) std::fprintf(stderr, "pty_client: cannot open %s: %s\n", path, std::strerror(errno));
  return port >= 0;
}

// LMS2xx framing (telegram listing 8007954 section 2): STX, address, length (2 bytes, LSB
// first, counting command through status), that many bytes, CRC (2 bytes).
void read_lms(const std::string& seconds) {
  const auto deadline = after(seconds);
  std::vector<std::uint8_t> junk, t;
  int v;
  while ((v = next_byte(deadline)) >= 0) {
    if (v == 0x06 || v == 0x15) {
      if (!junk.empty()) std::printf("junk %s\n", hex(junk).c_str());
      std::printf("%s %02x\n", v == 0x06 ? "ack" : "nak", v);
      return;
    }
    if (v != 0x02) {
      junk.push_back(static_cast<std::uint8_t>(v));
      continue;
    }
    t.push_back(static_cast<std::uint8_t>(v));
    while (t.size() < 4 && (v = next_byte(deadline)) >= 0) t.push_back(static_cast<std::uint8_t>(v));
    if (t.size() < 4) break;
    const std::size_t total = 4 + (t[2] | t[3] << 8) + 2;
    if (total > 812) {  // longer than the longest telegram: not a telegram start
      junk.insert(junk.end(), t.begin(), t.end());
      t.clear();
      continue;
    }
    while (t.size() < total && (v = next_byte(deadline)) >= 0) t.push_back(static_cast<std::uint8_t>(v));
    if (t.size() < total) break;
    if (!junk.empty()) std::printf("junk %s\n", hex(junk).c_str());
    junk.clear();
    // The power-on message (0x90) comes unasked whenever the scanner boots; drivers skip it.
    const bool power_on = t[4] == 0x90;
    std::printf("%s %s\n", power_on ? "power-on" : "telegram", hex(t).c_str());
    t.clear();
    if (!power_on) return;
    continue;
  }
  junk.insert(junk.end(), t.begin(), t.end());
  std::printf("timeout %s\n", hex(junk).c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: pty_client PORT [trace=FILE|baud=N|send=HEX|lms=S|read=S|reopen|sleep=S]...\n");
    return 2;
  }
  if (!open_port(argv[1])) return 1;
  for (int i = 2; i < argc; ++i) {
    const std::string step = argv[i];
    const std::string key = step.substr(0, step.find('='));
    const std::string value = step.find('=') == std::string::npos ? "" : step.substr(step.find('=') + 1);
    if (key == "trace") {
      trace_path = value;
    } else if (key == "baud") {
      termios t{};
      ::tcgetattr(port, &t);
      ::cfmakeraw(&t);
      // glibc takes a standard rate as a plain number.
      if (::cfsetspeed(&t, static_cast<speed_t>(std::atol(value.c_str()))) != 0 ||
          ::tcsetattr(port, TCSANOW, &t) != 0) {
        std::fprintf(stderr, "pty_client: cannot set %s baud\n", value.c_str());
        return 1;
      }
      ::tcflush(port, TCIFLUSH);
    } else if (key == "send") {
      std::vector<std::uint8_t> bytes;
      for (std::size_t at = 0; at + 1 < value.size(); at += 2)
        bytes.push_back(static_cast<std::uint8_t>(std::stoul(value.substr(at, 2), nullptr, 16)));
      if (::write(port, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) return 1;
      ::tcdrain(port);
    } else if (key == "lms") {
      read_lms(value);
    } else if (key == "read") {
      const auto deadline = after(value);
      std::vector<std::uint8_t> got;
      for (int v; (v = next_byte(deadline)) >= 0;) got.push_back(static_cast<std::uint8_t>(v));
      std::printf("bytes %zu %s\n", got.size(), hex(got).c_str());
    } else if (key == "reopen") {
      ::close(port);
      ::usleep(100000);
      if (!open_port(argv[1])) return 1;
    } else if (key == "sleep") {
      const Deadline d = after(value);
      while (!passed(d)) ::usleep(5000);
    } else {
      std::fprintf(stderr, "pty_client: unknown step '%s'\n", step.c_str());
      return 2;
    }
    std::fflush(stdout);
  }
  ::close(port);
  return 0;
}
