// gpsd 3.22 in its default mode (no -b: it configures the receiver) on the simulated NEO-6M's
// pty, through `sear run --pty`, as a user would start it: gpsd recognises the u-blox, switches
// it to UBX with CFG-PRT and CFG-MSG, polls MON-VER, and reports 3D fixes from NAV-SOL within the
// configured error of the antenna's truth.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "command_output.hpp"
#include "devices/gnss_error.h"
#include "firmware_run.hpp"
#include "loopback_port.hpp"
#include "sensors/gnss_truth.hpp"
#include "temp_dir.hpp"

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

// A shell command started for the test and ended by its process id when the test is done.
class Spawned {
 public:
  explicit Spawned(const std::string& cmd) {
    const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    if (::posix_spawn(&pid_, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) pid_ = -1;
  }
  ~Spawned() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      wait();
    }
  }
  Spawned(const Spawned&) = delete;
  Spawned& operator=(const Spawned&) = delete;
  bool running() const { return pid_ > 0 && ::waitpid(pid_, nullptr, WNOHANG) == 0; }
  int wait() {
    int status = 0;
    if (pid_ > 0 && ::waitpid(pid_, &status, 0) == pid_) pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
};

// The path the run links to the device's pty, once it exists (30 s at most: the run's start).
std::string wait_for_pty(const std::filesystem::path& link, const Spawned& run) {
  for (const auto end = Clock::now() + std::chrono::seconds(30); Clock::now() < end;) {
    if (std::filesystem::exists(link)) return link.string();
    if (!run.running()) return "";
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return "";
}

}  // namespace

// The rover rests at the origin of a flat world (Cambridge; geoid separation 0, so gpsd's altHAE
// is the MSL truth); its NEO-6M at the power-up 9600 baud, 5 Hz, fix from the start. gpsd must
// report the u-blox driver with the MON-VER it read, and TPVs in 3D mode carrying ECEF fields
// (which only the UBX NAV-SOL gives; the NMEA sentences it turned off have none), within 4.5 sigma
// of the trace's truth (Rayleigh tail exp(-4.5^2/2) = 4e-5 per fix horizontally), with the GPS-UTC
// leap seconds from NAV-TIMEGPS. Paced at --realtime 2: gpsd's own waits are wall-clock ones far
// longer than a 9600-baud answer takes, and fewer wall seconds keep the test short.
TEST(GpsdDefaultMode, SwitchesTheNeo6mToUbxAndReportsA3dFixWithinTheConfiguredError) {
  if (std::system("command -v gpsd >/dev/null && command -v gpspipe >/dev/null") != 0)
    GTEST_SKIP() << "gpsd or gpspipe not installed";
  sear::test::TempDir dir;
  const double cep_m = 2.5;
  const std::string project = sear::test::rover_project(
      std::string("    <mcu name=\"main\">\n      <firmware executable=\"") + TIMER_PROBE +
          "\"/>\n      <ublox_neo6m name=\"gps\" uart=\"3\" rate_hz=\"5\" ttff=\"0\" cep=\"2.5\" "
          "utc_start=\"2026-11-24T07:00:00Z\"/>\n    </mcu>\n",
      "    <gps_origin latitude=\"52.2053\" longitude=\"0.1218\" altitude=\"12\"/>\n", 14.0);
  std::ofstream(dir.path() / "project.xml") << project;
  const auto out = dir.path() / "out";
  Spawned run("exec " + std::string(SEAR_BINARY) + " run " + (dir.path() / "project.xml").string() + " -o " +
              out.string() + " --pty rover.main.gps --realtime 2 -q >" + (dir.path() / "stdout").string() + " 2>" +
              (dir.path() / "stderr").string());
  const std::string pty = wait_for_pty(out / "rover.main.gps.pty", run);
  ASSERT_FALSE(pty.empty()) << sear::test::read_file(dir.path() / "stderr");
  const int port = sear::test::free_loopback_port();  // gpsd without -G listens on loopback only
  ASSERT_GT(port, 0);
  // Everything gpsd reports until the run has ended: how long that takes in wall time is the
  // host's business (twice real time, or much less beside busy processes), so nothing here is
  // bounded by a wall-clock window; `timeout 300` only keeps a hung tool from outliving the test.
  // A count of messages would not do either: how many NMEA reports come before gpsd has switched
  // the receiver to UBX depends on how fast the host answers gpsd's probes.
  const auto json_path = dir.path() / "gpspipe.json";
  std::unique_ptr<Spawned> gpspipe;
  {
    // The command line: default mode (no -b), no fixed rate (-s): gpsd starts at the
    // pty's power-up 9600 and recognises the stream there.
    Spawned gpsd("exec timeout 300 gpsd -N -n -S " + std::to_string(port) + " " + pty + " >/dev/null 2>&1");
    ASSERT_TRUE(sear::test::wait_for_listener(port)) << "gpsd did not start";
    gpspipe = std::make_unique<Spawned>("exec timeout 300 gpspipe -w 127.0.0.1:" + std::to_string(port) + " >" +
                                        json_path.string() + " 2>/dev/null");
    EXPECT_EQ(run.wait(), 0) << sear::test::read_file(dir.path() / "stderr");
  }  // gpsd stops here; gpspipe then reads the end of its socket and exits
  gpspipe->wait();
  const std::string json = sear::test::read_file(json_path);

  // Truth: the chassis centre from the trace (the GPS is mounted there).
  struct Row {
    double t, x, y, z;
  };
  std::vector<Row> rows;
  for (const auto& line : sear::test::lines_of(sear::test::read_file(out / "trace_rover.csv"))) {
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
  const sear::GnssTruth geo({52.2053, 0.1218, 12.0}, 0.0);

  bool ublox = false;
  int checked = 0, with_leap = 0;
  for (const auto& line : sear::test::lines_of(json)) {
    const auto msg = nlohmann::json::parse(line, nullptr, false);
    if (msg.is_discarded() || !msg.contains("class")) continue;
    if (msg["class"] == "DEVICE" && msg.value("driver", "") == "u-blox") {
      ublox = true;
      EXPECT_NE(msg.value("subtype", "").find("SW 7.03 (45969),HW 00040007"), std::string::npos) << line;
    }
    if (msg["class"] != "TPV" || msg.value("mode", 0) != 3 || !msg.contains("ecefx")) continue;
    EXPECT_TRUE(ublox) << "a UBX fix before gpsd named the driver: " << line;
    // GPS - UTC, once NAV-TIMEGPS has told it (gpsd enables that message after NAV-SOL).
    if (msg.contains("leapseconds")) {
      EXPECT_EQ(msg["leapseconds"].get<int>(), 18) << line;
      ++with_leap;
    }
    const std::string iso = msg["time"];
    ASSERT_EQ(iso.substr(0, 11), "2026-11-24T") << line;
    const double s =
        std::stod(iso.substr(11, 2)) * 3600 + std::stod(iso.substr(14, 2)) * 60 + std::stod(iso.substr(17)) - 7 * 3600;
    EXPECT_GT(s, 0.0) << line;
    EXPECT_LT(s, 14.0) << line;
    const Row* truth = &rows.front();
    for (const Row& r : rows)
      if (std::fabs(r.t - s) < std::fabs(truth->t - s)) truth = &r;
    const sear::Enu got =
        geo.plane().to_enu({msg["lat"].get<double>(), msg["lon"].get<double>(), msg["altHAE"].get<double>()});
    EXPECT_LT(std::hypot(got.east_m - truth->x, got.north_m - truth->y), 4.5 * sh) << line;
    // NAV-SOL's ECEF is to 1 cm; far below the error.
    EXPECT_NEAR(got.up_m, truth->z, 4.5 * error.sigma_vertical_m) << line;
    // At rest: the speed is the size of two velocity errors of 0.1 m/s each (Rayleigh, 4.5 sigma).
    EXPECT_LT(msg.value("speed", 99.0), 4.5 * GNSS_DEFAULT_VELOCITY_SD_MPS + 0.01) << line;
    ++checked;
  }
  EXPECT_TRUE(ublox) << json;
  EXPECT_GT(with_leap, 0) << json;
  // 5 Hz for the 14 simulated seconds, less gpsd's probing (a few seconds): well over 10 epochs.
  EXPECT_GE(checked, 10) << json;
  std::printf("gpsd default mode: %d UBX 3D fixes checked, horizontal sigma %.2f m, vertical sigma %.2f m\n",
              checked, sh, error.sigma_vertical_m);
}
