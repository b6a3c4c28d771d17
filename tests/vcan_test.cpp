// SocketCAN against a real Linux kernel and can-utils: the guest harness itself, SocketCanPort's
// frames as candump records them and as cansend injects them, and `sear run --can` end to end. On a
// host with vcan0 the commands run there; otherwise in a qemu guest booted with Debian's kernel
// (scripts/vcan-guest/run-in-guest.sh). With neither, the tests skip saying what is missing, or
// fail when CI is set, so that CI never passes without having run them.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "can/socketcan_port.hpp"
#include "firmware_run.hpp"

#ifndef AF_CAN
#define AF_CAN 29
#endif

namespace sear::test {
namespace {

namespace fs = std::filesystem;

// Where the kernel side runs: natively (the host has vcan0 and AF_CAN), in the guest, or nowhere.
struct Place {
  enum Kind { kNative, kGuest, kNone } kind = kNone;
  std::string missing;  // for kNone: what is missing, in words a user can act on
};

bool on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / program).c_str(), X_OK) == 0) return true;
  return false;
}

int run_shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const Place& place() {
  static const Place found = [] {
    Place p;
    std::string native_why;
    if (!fs::exists("/sys/class/net/vcan0")) {
      native_why = "the host has no vcan0";
    } else {
      try {
        SocketCanPort probe("vcan0");
        p.kind = Place::kNative;
        return p;
      } catch (const SocketCanError& e) {
        native_why = std::string("the host's vcan0 is unusable: ") + e.what();
      }
    }
    std::vector<std::string> lacking;
    if (!on_path("qemu-system-x86_64")) lacking.push_back("qemu-system-x86_64 (Debian package qemu-system-x86)");
    if (::access("/bin/busybox", X_OK) != 0) lacking.push_back("/bin/busybox (Debian package busybox-static)");
    if (!on_path("candump") || !on_path("cansend")) lacking.push_back("candump and cansend (Debian package can-utils)");
    if (lacking.empty()) {
      // Fetches Debian's kernel into the cache the first time (a 70 MB download).
      const std::string fetch = std::string(VCAN_GUEST_DIR) + "/fetch-kernel.sh >/dev/null";
      if (run_shell(fetch) != 0)
        lacking.push_back("Debian's kernel for the guest (scripts/vcan-guest/fetch-kernel.sh failed, see above)");
    }
    if (lacking.empty()) {
      p.kind = Place::kGuest;
      return p;
    }
    p.missing = "no SocketCAN to test against: " + native_why + ", and the qemu guest lacks ";
    for (std::size_t i = 0; i < lacking.size(); ++i) p.missing += (i ? ", " : "") + lacking[i];
    return p;
  }();
  return found;
}

// Skips with what is missing, but fails under CI: there the suite must have run.
#define REQUIRE_SOCKETCAN()                                                                     \
  do {                                                                                          \
    if (place().kind == Place::kNone) {                                                         \
      if (std::getenv("CI")) FAIL() << place().missing << " (CI is set, so this fails)";        \
      GTEST_SKIP() << place().missing;                                                          \
    }                                                                                           \
  } while (0)

// Shell functions the scripts share: start candump and wait until its socket is bound (its
// receiver is listed by the kernel), and wait for a condition with a bound.
constexpr const char* kPrelude = R"sh(set -u
O=$1
receivers() { grep -c ' vcan0 ' /proc/net/can/rcvlist_all 2>/dev/null || true; }
wait_until() { for _ in $(seq 1000); do eval "$1" && return 0; sleep 0.01; done; echo "timed out: $1" >&2; return 1; }
lines() { grep -c . "$1" 2>/dev/null || true; }
start_candump() {
  local before; before=$(receivers)
  candump -L vcan0 >"$1" & CANDUMP=$!
  wait_until '[ "$(receivers)" -gt "$before" ]'
}
)sh";

// Runs `body` (after kPrelude, with $O = dir) where SocketCAN is; returns its exit status.
int run_script(const fs::path& dir, const std::string& body) {
  std::ofstream(dir / "script.sh") << kPrelude << body;
  const std::string redirect = " >" + (dir / "script.out").string() + " 2>" + (dir / "script.err").string();
  const std::string script = "bash " + (dir / "script.sh").string() + " " + dir.string();
  if (place().kind == Place::kNative) return run_shell(script + redirect);
  return run_shell(std::string(VCAN_GUEST_DIR) + "/run-in-guest.sh --out " + dir.string() + " -- " + script + redirect);
}

std::string diagnostics(const fs::path& dir) {
  return "script stdout:\n" + read_file(dir / "script.out") + "\nscript stderr:\n" + read_file(dir / "script.err");
}

// The frame fields of a candump -L log ("(sec.usec) iface ID#DATA"), in order.
std::vector<std::string> candump_frames(const fs::path& log, std::vector<double>* times = nullptr) {
  std::vector<std::string> frames;
  static const std::regex line(R"(^\((\d+\.\d{6})\) (\S+) (\S+)$)");
  for (const auto& text : lines_of(read_file(log))) {
    std::smatch m;
    if (!std::regex_match(text, m, line)) continue;
    frames.push_back(m[3]);
    if (times) times->push_back(std::stod(m[1]));
  }
  return frames;
}

// One guest boot for the harness and SocketCanPort checks, shared by the tests below.
class Kernel : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (place().kind == Place::kNone) return;
    dir_ = new TempDir;
    status_ = run_script(dir_->path(), "PROBE='" SOCKETCAN_PROBE "'\n" R"sh(
# 1. The harness: cansend's frame seen by candump.
start_candump "$O/harness.log"
cansend vcan0 123#DEADBEEF
wait_until '[ "$(lines "$O/harness.log")" -ge 1 ]'
kill $CANDUMP; wait $CANDUMP 2>/dev/null

# 2a. SocketCanPort writes; candump records.
start_candump "$O/sent.log"
"$PROBE" send vcan0 || echo "probe send failed" >&2
wait_until '[ "$(lines "$O/sent.log")" -ge 16 ]'
sleep 0.2  # anything beyond the 16 frames would show up now
kill $CANDUMP; wait $CANDUMP 2>/dev/null

# 2b. cansend writes; SocketCanPort reads.
"$PROBE" recv vcan0 6 "$O/ready" >"$O/received.txt" & RECV=$!
wait_until '[ -f "$O/ready" ]'
for f in 123#DEADBEEF 7FF# 1ABCDEF0#0011223344556677 00000080#AA 321#R 18DAF110#R3; do cansend vcan0 $f; done
wait $RECV || echo "probe recv failed" >&2

# 2c. Batching and the drop count; 2d. the errors.
"$PROBE" burst vcan0 >"$O/burst.txt"
"$PROBE" errors >"$O/errors.txt"

# 2e. A transmit queue that stays full: the plug qdisc holds back 160 bytes, 10 CAN frames of 16
# (a controller's default txqueuelen), and drops what comes after, as a controller's queue does.
# On a host's own vcan0 this needs root and the module sch_plug; without them the test says so.
if tc qdisc add dev vcan0 root plug limit 160 2>"$O/tc.err"; then
  "$PROBE" fill vcan0 11 >"$O/stuck.txt"
  tc qdisc del dev vcan0 root
  # 2f. One that drains: released 0.3 s after the writes begin.
  start_candump "$O/drained.log"
  tc qdisc add dev vcan0 root plug limit 160
  (sleep 0.3; tc qdisc change dev vcan0 root plug release_indefinite) & RELEASE=$!
  "$PROBE" fill vcan0 40 >"$O/drained.txt"
  wait $RELEASE
  wait_until '[ "$(lines "$O/drained.log")" -ge 40 ]'
  kill $CANDUMP; wait $CANDUMP 2>/dev/null
  tc qdisc del dev vcan0 root
fi
true
)sh");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    REQUIRE_SOCKETCAN();
    ASSERT_EQ(status_, 0) << diagnostics(dir_->path());
  }
  static fs::path out(const std::string& name) { return dir_->path() / name; }

  static TempDir* dir_;
  static int status_;
};
TempDir* Kernel::dir_ = nullptr;
int Kernel::status_ = -1;

TEST_F(Kernel, CandumpSeesWhatCansendSent) {
  std::vector<double> times;
  const auto frames = candump_frames(out("harness.log"), &times);
  ASSERT_EQ(frames, std::vector<std::string>{"123#DEADBEEF"}) << read_file(out("harness.log"));
  // The guest's clock starts from the host's RTC: a stamp of this century, not 0.
  EXPECT_GT(times[0], 1.6e9);
}

// The frames socketcan_probe writes (its sent_frames()), written out here by hand in candump's
// syntax (can-utils lib.c: 3 hex digits for a standard id, 8 for an extended one, R and the dlc
// for a remote frame), identical and in order.
TEST_F(Kernel, FramesThePortWritesReachCandumpIdenticallyAndInOrder) {
  const std::vector<std::string> expected = {
      "123#DEADBEEF", "000#", "7FF#0102030405060708", "1FFFFFFF#FFFFFFFFFFFFFFFF", "00000001#00", "321#R",
      "18DAF110#R3", "200#", "201#10", "202#2021", "203#303132", "204#40414243", "205#5051525354",
      "206#606162636465", "207#70717273747576", "208#8081828384858687"};
  EXPECT_EQ(candump_frames(out("sent.log")), expected) << read_file(out("sent.log"));
}

TEST_F(Kernel, ThePortReadsWhatCansendSentInOrder) {
  const std::vector<std::string> expected = {"123#DEADBEEF", "7FF#",  "1ABCDEF0#0011223344556677",
                                             "00000080#AA",  "321#R", "18DAF110#R3",
                                             "dropped 0"};
  EXPECT_EQ(lines_of(read_file(out("received.txt"))), expected);
}

// 150 frames fit a socket's default receive queue (net.core.rmem_default, 212992 bytes, holds
// a few hundred CAN skbs) and come through one read_available(), beyond one recvmmsg batch of 64;
// 5000 do not, and every frame not read is in the kernel's drop count, the ones read being the
// first ones, in order.
TEST_F(Kernel, ABurstComesInOneCallAndAnOverflowIsCounted) {
  const std::string text = read_file(out("burst.txt"));
  int total[2], first[2], in_order[2], second[2];
  unsigned dropped[2];
  std::istringstream in(text);
  for (int i = 0; i < 2; ++i) {
    std::string line;
    std::getline(in, line);
    ASSERT_EQ(std::sscanf(line.c_str(), "burst %d: first_call %d in_order %d second_call %d dropped %u", &total[i],
                          &first[i], &in_order[i], &second[i], &dropped[i]),
              5)
        << text;
  }
  EXPECT_EQ(total[0], 150);
  EXPECT_EQ(first[0], 150);
  EXPECT_EQ(in_order[0], 150);
  EXPECT_EQ(second[0], 0);
  EXPECT_EQ(dropped[0], 0U);
  EXPECT_EQ(total[1], 5000);
  EXPECT_GT(first[1], 150) << "the queue held fewer frames than the small burst";
  EXPECT_LT(first[1], 5000) << "the queue never overflowed";
  EXPECT_EQ(in_order[1], first[1]);
  EXPECT_EQ(second[1], 0);
  EXPECT_EQ(static_cast<int>(dropped[1]) + first[1], 5000);
}

TEST_F(Kernel, OpeningErrorsSayWhatIsWrong) {
  const auto lines = lines_of(read_file(out("errors.txt")));
  ASSERT_EQ(lines.size(), 2U);
  EXPECT_EQ(lines[0].rfind("nocan0: no CAN interface 'nocan0' (", 0), 0U) << lines[0];
  // lo's link type is ARPHRD_LOOPBACK, 772 (linux/if_arp.h); CAN's is ARPHRD_CAN, 280.
  EXPECT_EQ(lines[1], "lo: 'lo' is not a CAN interface (its link type is 772, CAN's is 280)");
}

// A full transmit queue (the kernel's ENOBUFS) makes write() wait and retry: ten frames fill the
// plugged queue, the eleventh gives up after kFullQueueWait with the error naming the interface;
// when the queue drains, all 40 frames written into a queue of 10 arrive, in order.
TEST_F(Kernel, WritesWaitForAFullQueueAndSayWhenItStaysFull) {
  if (!fs::exists(out("stuck.txt"))) {
    const std::string why = "cannot plug vcan0's queue (`tc qdisc add dev vcan0 root plug`): " + read_file(out("tc.err"));
    // The guest has root and the module; only a host's own vcan0 may lack them.
    if (place().kind == Place::kGuest || std::getenv("CI")) FAIL() << why;
    GTEST_SKIP() << why;
  }
  const auto stuck = lines_of(read_file(out("stuck.txt")));
  ASSERT_EQ(stuck.size(), 2U) << read_file(out("stuck.txt"));
  EXPECT_EQ(stuck[0], "wrote 10");
  EXPECT_EQ(stuck[1].rfind("error: CAN interface 'vcan0' stayed full for 1000 ms", 0), 0U) << stuck[1];

  EXPECT_EQ(read_file(out("drained.txt")), "wrote 40\n");
  std::vector<std::string> expected;
  for (int i = 0; i < 40; ++i) {
    char frame[32];
    std::snprintf(frame, sizeof frame, "%08X#%02X%02X", i, i >> 8, i & 0xFF);
    expected.push_back(frame);
  }
  EXPECT_EQ(candump_frames(out("drained.log")), expected);
}

// On the host itself, whatever its kernel has: the first thing missing is named.
TEST(SocketCanPortHost, SaysWhatTheHostLacks) {
  const int fd = ::socket(AF_CAN, SOCK_RAW, 1 /* CAN_RAW */);
  const bool has_can = fd >= 0;
  if (fd >= 0) ::close(fd);
  try {
    SocketCanPort port("nocan0");
    FAIL() << "opened an interface that does not exist";
  } catch (const SocketCanError& e) {
    const std::string what = e.what();
    if (has_can)
      EXPECT_EQ(what.rfind("no CAN interface 'nocan0' (", 0), 0U) << what;
    else
      EXPECT_EQ(what.rfind("this kernel has no SocketCAN (socket(AF_CAN) failed: ", 0), 0U) << what;
  }
}

// sear bridges the project's bus "body" to vcan0 while a firmware (can_echo_probe.c) echoes every
// frame under id + 1 and sends its own frame 0x0A0 every 10 ms: candump on the host sees the
// firmware's frames and the echoes of what cansend sent, and the run's own log has them at sim time.
TEST(SearBridge, FramesCrossBothWaysInOrder) {
  REQUIRE_SOCKETCAN();
  TempDir dir;
  const double duration_s = 2;
  std::ofstream(dir.path() / "project.xml")
      << "<project name=\"vcan\">\n  <run duration=\"" << duration_s << "\" seed=\"1\" trace_rate=\"10\"/>\n"
      << "  <can_bus name=\"body\" bitrate=\"500000\"/>\n"
      << "  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n  </world>\n"
      << "  <robot file=\"" << SEAR_ASSET_DIR << "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n"
      << "    <mcu name=\"main\">\n      <firmware executable=\"" << CAN_ECHO_PROBE << "\"/>\n"
      << "      <can bus=\"body\"/>\n    </mcu>\n  </robot>\n</project>\n";
  const std::vector<std::string> sent = {"123#DEADBEEF", "1ABCDEF0#0011223344556677", "7FE#", "321#R2"};
  const std::vector<std::string> echoed = {"124#DEADBEEF", "1ABCDEF1#0011223344556677", "7FF#", "322#R2"};
  std::string sends;
  for (const auto& f : sent) sends += "cansend vcan0 " + f + "; sleep 0.05\n";
  const int status = run_script(dir.path(), std::string(R"sh(
start_candump "$O/host.log"
")sh") + SEAR_BINARY + R"sh(" run "$O/project.xml" -o "$O/run" --can body=vcan0 --realtime 1 >"$O/sear.out" 2>"$O/sear.err" & SEAR=$!
# The firmware's first frame on the host says the bridge is up.
wait_until 'grep -q " 0A0#" "$O/host.log"'
)sh" + sends + R"sh(
wait $SEAR; echo "sear exit $?"
sleep 0.2
kill $CANDUMP; wait $CANDUMP 2>/dev/null
true
)sh");
  ASSERT_EQ(status, 0) << diagnostics(dir.path());
  ASSERT_NE(read_file(dir.path() / "script.out").find("sear exit 0"), std::string::npos)
      << diagnostics(dir.path()) << read_file(dir.path() / "sear.err");

  // On the host: the firmware's frames numbered 0, 1, 2, ... with none missing, and each frame sent
  // exactly once (the bridge does not send the host's frames back), followed by its echo.
  const auto host = candump_frames(dir.path() / "host.log");
  int own = 0;
  std::vector<std::string> others;
  for (const auto& f : host) {
    if (f.rfind("0A0#", 0) == 0) {
      char expected[32];
      std::snprintf(expected, sizeof expected, "0A0#%02X%02XC0DE", own & 0xFF, own >> 8);
      ASSERT_EQ(f, expected) << "own frame " << own;
      ++own;
    } else {
      others.push_back(f);
    }
  }
  // Queued at 10, 20, ... ms: 199 frames before 2 s (1990 ms), 200 if the run's last step sends the
  // one due at 2.000 s.
  EXPECT_GE(own, 199);
  EXPECT_LE(own, 200);
  std::vector<std::string> interleaved;
  for (std::size_t i = 0; i < sent.size(); ++i) {
    interleaved.push_back(sent[i]);
    interleaved.push_back(echoed[i]);
  }
  EXPECT_EQ(others, interleaved) << read_file(dir.path() / "host.log");

  // In the run's own log, stamped at each frame's end in sim time: each host frame, then its echo.
  // The bus hands a frame to the MCU at the first quantum boundary after its end (up to one 1 ms
  // step later); the firmware looks every 200 us; an own frame of 4 bytes may be on the wire
  // (76 bits + 3 of interframe space + at most 16 stuff bits: 190 us at 500 kbit/s); then the echo
  // itself, at most an extended frame of 8 bytes (131 bits + 29 stuff bits: 320 us); and the HAL
  // calls of one look, about five at 50 cycles of 16 MHz (16 us). Together 1.73 ms. At least, the
  // echo's own time on the wire: the shortest frame, 47 bits, 94 us.
  std::vector<double> times;
  const auto run_frames = candump_frames(dir.path() / "run" / "body.candump.log", &times);
  for (std::size_t i = 0; i < sent.size(); ++i) {
    const auto at = std::find(run_frames.begin(), run_frames.end(), sent[i]);
    const auto echo = std::find(run_frames.begin(), run_frames.end(), echoed[i]);
    ASSERT_NE(at, run_frames.end()) << sent[i] << " is not in the run's log";
    ASSERT_NE(echo, run_frames.end()) << echoed[i] << " is not in the run's log";
    const double gap = times[echo - run_frames.begin()] - times[at - run_frames.begin()];
    EXPECT_GE(gap, 94e-6) << sent[i];
    EXPECT_LE(gap, 1.73e-3) << sent[i];
  }
}

}  // namespace
}  // namespace sear::test
