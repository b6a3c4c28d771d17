// Simulated UART devices as host pseudo-terminals: PtyPort against a client on the slave (bytes
// both ways, the host's termios rate, closing and reopening as on a serial port), then whole runs
// with `sear run --pty`: gpsd reading the simulated GPS, and pty_client switching the simulated
// LMS200 to 38400 baud and reading a scan.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "devices/gnss_error.h"
#include "command_output.hpp"
#include "firmware_run.hpp"
#include "loopback_port.hpp"
#include "pty/line_speed.hpp"
#include "pty/pty_port.hpp"
#include "sensors/gnss_truth.hpp"
#include "temp_dir.hpp"

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;
using sear::PtyPort;
using sear::test::TempDir;

// Bytes cross a pty through the kernel's flip-buffer work queue, not within the write() call:
// every wait below polls until the expected bytes are in or 5 s have passed (only a broken port
// takes that long).
constexpr auto kPatience = std::chrono::seconds(5);

std::vector<serial_byte> line_of(const std::vector<std::uint8_t>& values) {
  std::vector<serial_byte> out;
  for (std::uint8_t v : values) out.push_back(serial_byte{0, 9600, v, {0, 0, 0}});
  return out;
}

std::vector<std::uint8_t> every_byte_value() {
  std::vector<std::uint8_t> v;
  for (int i = 0; i < 256; ++i) v.push_back(static_cast<std::uint8_t>(i));
  return v;
}

// What the port hands over from the host, until `want` bytes or the patience runs out.
std::vector<std::uint8_t> port_read(PtyPort& port, std::size_t want) {
  std::vector<std::uint8_t> got;
  std::uint8_t buf[4096];
  for (const auto end = Clock::now() + kPatience; got.size() < want && Clock::now() < end;) {
    const std::size_t n = port.read(buf, sizeof buf);
    got.insert(got.end(), buf, buf + n);
    if (n == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return got;
}

// What the client reads, until `want` bytes, or until nothing has come for `quiet`.
std::vector<std::uint8_t> client_read(int fd, std::size_t want,
                                      std::chrono::milliseconds quiet = std::chrono::milliseconds(200)) {
  std::vector<std::uint8_t> got;
  std::uint8_t buf[4096];
  while (got.size() < want) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(quiet.count())) <= 0) break;
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n <= 0) break;
    got.insert(got.end(), buf, buf + n);
  }
  return got;
}

// A host program's open of the port: raw 8N1 at `baud` (0: leave the settings as found).
int client_open(const std::string& path, speed_t baud) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0 || baud == 0) return fd;
  termios t{};
  ::tcgetattr(fd, &t);
  ::cfmakeraw(&t);
  ::cfsetospeed(&t, baud);
  ::cfsetispeed(&t, baud);
  ::tcsetattr(fd, TCSANOW, &t);
  return fd;
}

void client_write(int fd, const std::vector<std::uint8_t>& bytes) {
  ASSERT_EQ(::write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
}

}  // namespace

// A client at 38400 raw: all 256 byte values cross unchanged both ways (no CR/LF mapping, no
// ^C signal, no XON/XOFF, no echo: the slave starts raw); baud() follows the client's termios
// through standard rates, the LMS's 500 kbaud, a BOTHER rate and B0; the link names the slave.
TEST(PtyPort, CarriesEveryByteValueBothWaysAtTheHostsRate) {
  TempDir dir;
  const std::string link = (dir.path() / "rover.main.gps.pty").string();
  std::string slave;
  {
    PtyPort port(link, 9600);
    slave = port.slave_path();
    EXPECT_EQ(slave.rfind("/dev/pts/", 0), 0u) << slave;
    EXPECT_EQ(std::filesystem::read_symlink(link).string(), slave);
    EXPECT_EQ(port.baud(), 9600u);  // the device's power-up rate, before any program sets one
    EXPECT_FALSE(port.host_attached());

    const int fd = client_open(link, B38400);
    ASSERT_GE(fd, 0) << link;
    EXPECT_EQ(port.baud(), 38400u);
    const auto values = every_byte_value();
    client_write(fd, values);
    EXPECT_EQ(port_read(port, 256), values);
    EXPECT_TRUE(port.host_attached());
    EXPECT_EQ(port.host_opens(), 1u);

    port.write(line_of(values).data(), values.size());
    EXPECT_EQ(client_read(fd, 256), values);
    EXPECT_EQ(port.dropped_unread() + port.dropped_closed(), 0u);

    termios t{};
    ::tcgetattr(fd, &t);
    for (const auto& [code, rate] :
         {std::pair<speed_t, std::uint32_t>{B9600, 9600}, {B38400, 38400}, {B500000, 500000}, {B115200, 115200}}) {
      ::cfsetospeed(&t, code);
      ::cfsetispeed(&t, code);
      ASSERT_EQ(::tcsetattr(fd, TCSANOW, &t), 0);
      EXPECT_EQ(port.baud(), rate);
    }
    // MIDI's 31250 has no Bxxx constant: a program sets it with termios2's BOTHER.
    ASSERT_TRUE(sear::set_line_baud_other(fd, 31250));
    EXPECT_EQ(port.baud(), 31250u);
    ::cfsetospeed(&t, B0);  // "hang up": no rate at all
    ASSERT_EQ(::tcsetattr(fd, TCSANOW, &t), 0);
    EXPECT_EQ(port.baud(), 0u);
    ::close(fd);

    // A port may start at a rate without a constant too.
    PtyPort odd("", 31250);
    EXPECT_EQ(odd.baud(), 31250u);
    EXPECT_TRUE(odd.link_path().empty());

    // The link is not taken over by a second port while it is a file.
    const std::string file = dir.write("taken.pty", "user data");
    EXPECT_THROW(PtyPort(file, 9600), std::runtime_error);
    EXPECT_EQ(sear::test::read_file(file), "user data");
  }
  EXPECT_FALSE(std::filesystem::is_symlink(link)) << "the link outlived its port";
}

// Nobody on the port: nothing blocks, the device's bytes are dropped and counted. A program's
// last bytes before close() arrive; bytes it left unread are gone for the next one, which reads
// only what the device sent after it opened, at the rate the last program set.
TEST(PtyPort, ClosingAndReopeningBehavesAsASerialPort) {
  // A blocking call here would hang the test: SIGALRM ends it as a failure instead.
  ::alarm(20);
  TempDir dir;
  const std::string link = (dir.path() / "rover.main.lidar.pty").string();
  PtyPort port(link, 9600);
  std::uint8_t buf[64];
  EXPECT_EQ(port.read(buf, sizeof buf), 0u);
  port.write(line_of({1, 2, 3, 4, 5}).data(), 5);
  EXPECT_EQ(port.dropped_closed(), 5u);

  int fd = client_open(link, B38400);
  ASSERT_GE(fd, 0);
  EXPECT_TRUE(client_read(fd, 1).empty()) << "bytes sent before anyone opened the port were kept";
  port.write(line_of({'o', 'n', 'e'}).data(), 3);
  EXPECT_EQ(client_read(fd, 3), (std::vector<std::uint8_t>{'o', 'n', 'e'}));
  EXPECT_EQ(port.host_opens(), 1u);

  // Unread by the client when it closes: 1000 bytes. Its own "bye" goes out before the close.
  port.write(line_of(std::vector<std::uint8_t>(1000, 0xAA)).data(), 1000);
  client_write(fd, {'b', 'y', 'e'});
  ::close(fd);
  EXPECT_EQ(port_read(port, 3), (std::vector<std::uint8_t>{'b', 'y', 'e'}));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(port.read(buf, sizeof buf), 0u);  // EIO, taken as "closed"
  EXPECT_FALSE(port.host_attached());
  port.write(line_of({6, 7, 8}).data(), 3);
  EXPECT_EQ(port.dropped_closed(), 5u + 3u);

  fd = client_open(link, 0);
  ASSERT_GE(fd, 0);
  EXPECT_EQ(port.baud(), 38400u) << "a serial port keeps its settings across opens";
  EXPECT_TRUE(client_read(fd, 1).empty()) << "the last program's unread bytes reached the next one";
  port.write(line_of({'t', 'w', 'o'}).data(), 3);
  EXPECT_EQ(client_read(fd, 3), (std::vector<std::uint8_t>{'t', 'w', 'o'}));
  client_write(fd, {'h', 'i'});
  EXPECT_EQ(port_read(port, 2), (std::vector<std::uint8_t>{'h', 'i'}));
  EXPECT_EQ(port.host_opens(), 2u);
  EXPECT_EQ(port.dropped_unread(), 0u);
  ::close(fd);
  ::alarm(0);
}

// A host that does not read: the pty's buffers fill and the rest is lost and counted, the first
// bytes kept in order (a full buffer refuses new bytes, as a UART's overrun loses the newest).
// Linux raw mode holds at least N_TTY_BUF_SIZE - 1 = 4095 bytes in the line discipline, and the
// pty's flip buffers at most the tty layer's 64 KiB limit (drivers/tty/tty_buffer.c) besides.
TEST(PtyPort, AHostThatDoesNotReadLosesTheNewestBytes) {
  TempDir dir;
  PtyPort port((dir.path() / "slow.pty").string(), 9600);
  const int fd = client_open(port.slave_path(), B9600);
  ASSERT_GE(fd, 0);
  std::vector<std::uint8_t> sent(200000);
  for (std::size_t i = 0; i < sent.size(); ++i) sent[i] = static_cast<std::uint8_t>(i * 7 + i / 256);
  port.write(line_of(sent).data(), sent.size());
  const std::uint64_t lost = port.dropped_unread();
  const auto got = client_read(fd, sent.size());
  EXPECT_EQ(got.size() + lost, sent.size());
  EXPECT_GE(got.size(), 4095u);
  EXPECT_LE(got.size(), 65536u + 4096u);
  EXPECT_TRUE(std::equal(got.begin(), got.end(), sent.begin())) << "the kept bytes are not the first ones";
  // Once read, the port takes bytes again.
  port.write(line_of({'o', 'k'}).data(), 2);
  EXPECT_EQ(client_read(fd, 2), (std::vector<std::uint8_t>{'o', 'k'}));
  EXPECT_EQ(port.dropped_unread(), lost);
  ::close(fd);
}

namespace {

// `sear run` in the background, so that host programs can talk to its ptys while it runs.
class BackgroundRun {
 public:
  BackgroundRun(const TempDir& dir, const std::string& project, const std::string& args) : dir_(dir.path()) {
    std::ofstream(dir_ / "project.xml") << project;
    const std::string cmd = "exec " + std::string(SEAR_BINARY) + " run " + (dir_ / "project.xml").string() + " -o " +
                            (dir_ / "out").string() + " " + args + " >" + (dir_ / "stdout").string() + " 2>" +
                            (dir_ / "stderr").string();
    const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    if (::posix_spawn(&pid_, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) pid_ = -1;
  }
  ~BackgroundRun() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      wait();
    }
  }
  // The pty of robot.mcu.device, by the link the run makes in its output folder; "" if none
  // appears within 30 s or the run ends first.
  std::string pty(const std::string& device) const {
    const auto link = dir_ / "out" / (device + ".pty");
    for (const auto end = Clock::now() + std::chrono::seconds(30); Clock::now() < end;) {
      if (std::filesystem::exists(link)) return link.string();
      if (pid_ <= 0 || ::waitpid(pid_, nullptr, WNOHANG) != 0) return "";
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return "";
  }
  int wait() {
    int status = 0;
    if (pid_ > 0 && ::waitpid(pid_, &status, 0) == pid_) pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string file(const std::string& name) const { return sear::test::read_file(dir_ / name); }

 private:
  std::filesystem::path dir_;
  pid_t pid_ = -1;
};

std::string run_output(const std::string& cmd) { return sear::test::command_output(cmd).out; }

// A rover at rest at the origin of a flat world, its ATmega running a firmware that does not
// use the device under test; `devices` are wired to its MCU "main".
std::string pty_project(const std::string& devices, const std::string& world_extra, double duration_s) {
  return sear::test::rover_project(std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + TIMER_PROBE +
                                       "\"/>\n" + devices + "    </mcu>\n",
                                   world_extra, duration_s);
}

// SICK's CRC-16 as the telegram listing prints it (generator 0x8005, each step folding in the
// current and the previous byte); written here apart from the model's, to check it.
std::uint16_t sick_crc(const std::vector<std::uint8_t>& d, std::size_t n) {
  std::uint16_t crc = 0;
  std::uint8_t previous = 0;
  for (std::size_t i = 0; i < n; ++i) {
    crc = (crc & 0x8000) ? static_cast<std::uint16_t>(((crc & 0x7FFF) << 1) ^ 0x8005)
                         : static_cast<std::uint16_t>(crc << 1);
    crc ^= static_cast<std::uint16_t>(d[i] | previous << 8);
    previous = d[i];
  }
  return crc;
}

std::string request_hex(const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> t = {0x02, 0x00, static_cast<std::uint8_t>(payload.size()), 0x00};
  t.insert(t.end(), payload.begin(), payload.end());
  const std::uint16_t crc = sick_crc(t, t.size());
  t.push_back(static_cast<std::uint8_t>(crc & 0xFF));
  t.push_back(static_cast<std::uint8_t>(crc >> 8));
  std::string s;
  char b[3];
  for (std::uint8_t v : t) {
    std::snprintf(b, sizeof b, "%02x", v);
    s += b;
  }
  return s;
}

std::vector<std::uint8_t> hex_bytes(const std::string& text) {
  std::vector<std::uint8_t> out;
  std::istringstream in(text);
  for (std::string h; in >> h;) out.push_back(static_cast<std::uint8_t>(std::stoul(h, nullptr, 16)));
  return out;
}

}  // namespace

// SICK's own example (telegram listing: mode change request 02 00 02 00 20 24 has CRC 08 34)
// checks the test's CRC before it judges the run's telegrams with it.
TEST(PtyRun, SickCrcMatchesThePublishedExample) {
  EXPECT_EQ(sick_crc({0x02, 0x00, 0x02, 0x00, 0x20, 0x24}, 6), 0x0834);
  EXPECT_EQ(request_hex({0x20, 0x24}), "0200020020243408");
}

// A process started for a test, ended by its id when the test is done with it.
class Spawned {
 public:
  explicit Spawned(const std::string& cmd) {
    const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    if (::posix_spawn(&pid_, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) pid_ = -1;
  }
  ~Spawned() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    ::waitpid(pid_, nullptr, 0);
  }
  Spawned(const Spawned&) = delete;
  Spawned& operator=(const Spawned&) = delete;

 private:
  pid_t pid_ = -1;
};

// gpsd 3.22 on the simulated NEO-6M's pty, read-only (-b: it sends the receiver nothing) at the
// power-up 9600 baud: its 3D fixes lie within 4.5 sigma of the antenna's truth from the run's
// trace (Rayleigh tail exp(-4.5^2/2) = 4e-5 per fix horizontally). Paced at --realtime 2: gpsd
// only needs the bytes in order, and fewer wall seconds keep the test short.
TEST(PtyRun, GpsdReadsAThreeDFixWithinTheConfiguredError) {
  if (std::system("command -v gpsd >/dev/null && command -v gpspipe >/dev/null") != 0)
    GTEST_SKIP() << "gpsd or gpspipe not installed";
  TempDir dir;
  // A made-up origin (Cambridge), the geoid separation left at 0 so gpsd's altHAE is the MSL truth.
  const sear::GeoPoint origin{52.2053, 0.1218, 12.0};
  const double cep_m = 2.5;
  BackgroundRun run(dir,
                    pty_project("      <ublox_neo6m name=\"gps\" uart=\"3\" rate_hz=\"5\" ttff=\"0\" cep=\"2.5\" "
                                "utc_start=\"2026-11-24T07:00:00Z\"/>\n",
                                "    <gps_origin latitude=\"52.2053\" longitude=\"0.1218\" altitude=\"12\"/>\n", 8.0),
                    "--pty rover.main.gps --realtime 2 -q");
  const std::string pty = run.pty("rover.main.gps");
  ASSERT_FALSE(pty.empty()) << run.file("stderr");
  const int port = sear::test::free_loopback_port();  // gpsd without -G listens on loopback only
  ASSERT_GT(port, 0);
  std::string json;
  {
    Spawned gpsd("exec timeout 30 gpsd -N -n -b -s 9600 -S " + std::to_string(port) + " " + pty + " >/dev/null 2>&1");
    ASSERT_TRUE(sear::test::wait_for_listener(port)) << "gpsd did not start";
    json = run_output("timeout 15 gpspipe -w -n 40 127.0.0.1:" + std::to_string(port) + " 2>/dev/null");
  }
  EXPECT_EQ(run.wait(), 0) << run.file("stderr");

  // Truth: the chassis centre from the trace (the GPS is mounted there).
  struct Row {
    double t, x, y, z;
  };
  std::vector<Row> rows;
  for (const auto& line : sear::test::lines_of(run.file("out/trace_rover.csv"))) {
    Row r{};
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf", &r.t, &r.x, &r.y, &r.z) == 4) rows.push_back(r);
  }
  ASSERT_FALSE(rows.empty());
  gnss_error_config ec;
  gnss_error_defaults(&ec);
  ec.cep_m = cep_m;
  gnss_error error;
  gnss_error_init(&error, &ec);
  const double sh = cep_m / GNSS_CEP_PER_SIGMA;
  EXPECT_NEAR(error.sigma_horizontal_m, sh, 1e-9);
  const sear::GnssTruth geo(origin, 0.0);
  int checked = 0;
  for (const auto& line : sear::test::lines_of(json)) {
    if (line.rfind("{\"class\":\"TPV\"", 0) != 0) continue;
    const auto tpv = nlohmann::json::parse(line);
    if (tpv.value("mode", 0) != 3 || !tpv.contains("time") || !tpv.contains("lat") || !tpv.contains("altHAE")) continue;
    const std::string iso = tpv["time"];
    ASSERT_EQ(iso.substr(0, 11), "2026-11-24T") << line;
    const double s =
        std::stod(iso.substr(11, 2)) * 3600 + std::stod(iso.substr(14, 2)) * 60 + std::stod(iso.substr(17)) - 7 * 3600;
    const Row* truth = &rows.front();
    for (const Row& r : rows)
      if (std::fabs(r.t - s) < std::fabs(truth->t - s)) truth = &r;
    const sear::Enu got =
        geo.plane().to_enu({tpv["lat"].get<double>(), tpv["lon"].get<double>(), tpv["altHAE"].get<double>()});
    EXPECT_LT(std::hypot(got.east_m - truth->x, got.north_m - truth->y), 4.5 * sh) << line;
    // + 0.05 m: the GGA altitude is printed to 0.1 m.
    EXPECT_NEAR(got.up_m, truth->z, 4.5 * error.sigma_vertical_m + 0.05) << line;
    ++checked;
  }
  // 5 Hz for about 3 wall seconds of gpsd at twice real time: well over 10 epochs.
  EXPECT_GE(checked, 10) << json;
  std::printf("gpsd: %d 3D fixes checked, horizontal sigma %.2f m, vertical sigma %.2f m\n", checked, sh,
              error.sigma_vertical_m);
}

// pty_client as a PC-side LMS driver: at the power-up 9600 it sends the baud-change request
// 0x20 0x40 (38400) and gets the ACK and the 0xA0 reply at 9600; a request still sent at 9600
// then goes unanswered (the scanner listens at 38400); at 38400 the scan request 0x30 0x01 gets
// its ACK and a CRC-correct 0xB0 telegram of 361 values with the wall 2.00 m ahead; and again
// after the client closed and reopened the port. Paced at --realtime 1, as a user runs a PC
// driver against it. The client's waits are in the run's sim time (trace=), read from its trace,
// so that a host too busy to keep up with real time delays the exchange but cannot reorder it:
// the scanner answers within 1 ms plus the telegram's bytes (a few ms at 9600 baud), the client
// gives each answer 3 s and a request at the old rate 0.5 s to go unanswered (the scanner hears
// it at 38400 as garbage, which it ignores), and the run lasts 8 s to outlive the exchange.
TEST(PtyRun, ClientSwitchesTheLms200To38400AndReadsAScan) {
  TempDir dir;
  // The wall's near face at x = 2.12 m: 2.00 m from the scanner mounted 0.12 m ahead of the centre.
  BackgroundRun run(
      dir,
      pty_project("      <lms2xx name=\"lidar\" uart=\"1\" pos=\"0.12 0 0.12\" power_up=\"0.2\"/>\n",
                  "    <wall name=\"ahead\" from=\"2.17 -5\" to=\"2.17 5\" height=\"0.4\" thickness=\"0.1\"/>\n", 8.0),
      "--pty rover.main.lidar --realtime 1 -q");
  const std::string pty = run.pty("rover.main.lidar");
  ASSERT_FALSE(pty.empty()) << run.file("stderr");
  const std::string scan = request_hex({0x30, 0x01});
  const std::string out =
      run_output(std::string(PTY_CLIENT) + " " + pty + " trace=" + (dir.path() / "out/trace_rover.csv").string() +
                 " sleep=0.5 baud=9600 send=" + request_hex({0x20, 0x40}) +
                 " lms=3 lms=3 send=" + scan + " lms=0.5 baud=38400 send=" + scan + " lms=3 lms=3 reopen send=" + scan +
                 " lms=3 lms=3");
  EXPECT_EQ(run.wait(), 0) << run.file("stderr");
  std::vector<std::string> lines;
  for (const auto& line : sear::test::lines_of(out))
    if (line.rfind("power-on", 0) != 0) lines.push_back(line);  // if the run started late
  ASSERT_EQ(lines.size(), 7u) << out << run.file("stderr");
  EXPECT_EQ(lines[0], "ack 06");
  // Mode change reply: A0, status 00 (accepted), status byte 10; SICK CRC 0A16 (the listing's).
  EXPECT_EQ(lines[1], "telegram 02 80 03 00 a0 00 10 16 0a");
  EXPECT_TRUE(lines[2].rfind("timeout", 0) == 0) << lines[2] << ": a request at the old rate was understood";
  for (const std::size_t at : {3u, 5u}) {
    EXPECT_EQ(lines[at], "ack 06");
    ASSERT_EQ(lines[at + 1].rfind("telegram ", 0), 0u) << lines[at + 1];
    const auto t = hex_bytes(lines[at + 1].substr(9));
    ASSERT_GE(t.size(), 10u);
    const std::size_t len = t[2] | t[3] << 8;
    ASSERT_EQ(t.size(), 4 + len + 2);
    EXPECT_EQ(t[1], 0x80);
    EXPECT_EQ(t[4], 0xB0);
    EXPECT_EQ(sick_crc(t, t.size() - 2), t[t.size() - 2] | t[t.size() - 1] << 8) << "CRC";
    // 180 degrees at 0.5: 361 values of 2 bytes, in cm (unit bits 00) at power-up.
    const unsigned count_word = t[5] | t[6] << 8;
    ASSERT_EQ(count_word & 0x3FF, 361u);
    EXPECT_EQ(count_word >> 14, 0u);
    ASSERT_EQ(len, 1u + 2u + 722u + 1u);
    // Straight ahead is value 180 (scanner angle 90 degrees); 13-bit distance in cm. Noise 1 cm
    // (1 sigma) in cm mode: 4.5 sigma plus half a count of rounding.
    const unsigned ahead = (t[7 + 2 * 180] | t[8 + 2 * 180] << 8) & 0x1FFF;
    EXPECT_NEAR(ahead, 200.0, 4.5 + 0.5);
  }
}
