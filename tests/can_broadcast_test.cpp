// SEAR's broadcast frames: tools/can/sear.dbc is what the encoder's table generates, and Debian's
// python3-canmatrix, reading that file, decodes the frames back to the robots' values; the
// broadcast's schedule and its behaviour on a bus where nobody acks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "runtime/can_bus.hpp"
#include "runtime/can_state_broadcast.hpp"
#include "command_output.hpp"
#include "temp_dir.hpp"

namespace sear {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(CanBroadcast, DbcFileIsTheEncodersTable) {
  const std::string generated = broadcast_dbc();
  // After changing the table: SEAR_WRITE_DBC=1 build/tests/can_bus_tests --gtest_filter='*DbcFile*'
  if (std::getenv("SEAR_WRITE_DBC")) {
    std::ofstream(SEAR_DBC_FILE, std::ios::binary) << generated;
    GTEST_SKIP() << "wrote " << SEAR_DBC_FILE;
  }
  const std::string file = read_file(SEAR_DBC_FILE);
  if (file != generated) {
    std::size_t i = 0;
    while (i < file.size() && i < generated.size() && file[i] == generated[i]) ++i;
    FAIL() << SEAR_DBC_FILE << " differs from broadcast_dbc() at byte " << i << ":\nfile:      " << file.substr(i, 80)
           << "\ngenerated: " << generated.substr(i, 80);
  }
}

// Each frame decoded by canmatrix through sear.dbc: id -> signal -> physical value.
std::map<std::uint32_t, std::map<std::string, double>> decode_with_canmatrix(const std::vector<CanFrame>& frames) {
  test::TempDir dir;
  std::string input;
  for (const CanFrame& f : frames) {
    input += std::to_string(f.id) + " ";
    for (int i = 0; i < f.dlc; ++i) {
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02x", f.data[static_cast<std::size_t>(i)]);
      input += hex;
    }
    input += "\n";
  }
  const std::string frames_path = dir.write("frames.txt", input);
  const std::string script = dir.write("decode.py", R"(import sys
import canmatrix, canmatrix.formats
db = canmatrix.formats.loadp_flat(sys.argv[1])
for line in open(sys.argv[2]):
    ident, data = line.split()
    frame = db.frame_by_id(canmatrix.ArbitrationId(int(ident)))
    assert frame.size == len(data) // 2, (ident, frame.size)
    for name, value in frame.decode(bytes.fromhex(data)).items():
        print("SIG", ident, name, repr(float(value.phys_value)))
)");
  // Debian's interpreter, where python3-canmatrix is installed (not a pyenv shim on PATH).
  const std::string out = test::command_output("/usr/bin/python3 '" + script + "' '" SEAR_DBC_FILE "' '" + frames_path + "' 2>&1").out;
  std::map<std::uint32_t, std::map<std::string, double>> decoded;
  std::istringstream lines(out);
  std::string tag, name;
  std::uint32_t id;
  double value;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream l(line);
    if (l >> tag >> id >> name >> value && tag == "SIG") decoded[id][name] = value;
  }
  EXPECT_FALSE(decoded.empty()) << out;
  return decoded;
}

double wrap_deg(double rad) { return std::atan2(std::sin(rad), std::cos(rad)) * 180 / kPi; }

TEST(CanBroadcast, CanmatrixDecodesTheFramesToTheInputs) {
  std::vector<RobotBroadcastState> robots(3);
  robots[0].position_m = {1.2345, -2.5, 0.0125};
  robots[0].roll_pitch_yaw_rad = {0.1, -0.2, 3.0};
  robots[0].forward_speed_mps = 0.75;
  robots[0].angular_velocity_rps = {0.3, 0.0, -0.5};
  robots[1].position_m = {-1000.0005, 2000000.25, -12.3456};
  robots[1].roll_pitch_yaw_rad = {-3.0, 1.4, -3.1};
  robots[1].forward_speed_mps = -1.234;
  robots[1].angular_velocity_rps = {0, 0, 2.0};
  robots[2].roll_pitch_yaw_rad = {0, 0, 4.0};    // past half a turn: -130.8 degrees
  robots[2].forward_speed_mps = 40;              // beyond int16 mm/s: saturates at 32.767
  robots[2].angular_velocity_rps = {0, 0, -10};  // -573 deg/s: saturates at -327.68
  const std::int64_t time_ns = 123'456'789'012;
  const std::vector<CanFrame> frames = encode_broadcast(time_ns, robots);
  ASSERT_EQ(frames.size(), 1u + 3 * robots.size());
  auto decoded = decode_with_canmatrix(frames);

  // Within one LSB of each signal: rounding leaves half an LSB, the decimal factor a few ulps.
  EXPECT_NEAR(decoded[0x700]["SimTime"], 123.456789012, 1e-9);
  for (std::uint32_t r = 0; r < 3; ++r) {
    const RobotBroadcastState& s = robots[r];
    auto& pos = decoded[0x710 + r];
    auto& hh = decoded[0x720 + r];
    auto& att = decoded[0x730 + r];
    EXPECT_NEAR(pos["X"], s.position_m[0], 0.001) << r;
    EXPECT_NEAR(pos["Y"], s.position_m[1], 0.001) << r;
    EXPECT_NEAR(hh["Z"], s.position_m[2], 0.001) << r;
    EXPECT_NEAR(hh["Yaw"], wrap_deg(s.roll_pitch_yaw_rad[2]), 0.01) << r;
    EXPECT_NEAR(att["Roll"], wrap_deg(s.roll_pitch_yaw_rad[0]), 0.01) << r;
    EXPECT_NEAR(att["Pitch"], s.roll_pitch_yaw_rad[1] * 180 / kPi, 0.01) << r;
    if (r < 2) {
      EXPECT_NEAR(hh["Speed"], s.forward_speed_mps, 0.001) << r;
      EXPECT_NEAR(att["YawRate"], s.angular_velocity_rps[2] * 180 / kPi, 0.01) << r;
    }
  }
  EXPECT_NEAR(decoded[0x722]["Speed"], 32.767, 1e-9);     // int16 max * 0.001
  EXPECT_NEAR(decoded[0x732]["YawRate"], -327.68, 1e-9);  // int16 min * 0.01
  EXPECT_NEAR(decoded[0x722]["Yaw"], -130.82, 0.01);      // 4 rad = 229.18 deg, one turn less
}

TEST(CanBroadcast, SendsOnScheduleInTableOrder) {
  CanBus bus(500'000);
  CanStateBroadcast broadcast(bus, 3.0);  // 1/3 s is no whole number of ns: due times round
  const std::size_t mcu = bus.add_node("robot.mcu");
  bus.set_listening(mcu, true);
  const std::vector<RobotBroadcastState> robots(2);
  std::vector<std::int64_t> due;
  std::vector<CanTransfer> done;
  for (int k = 0; k < 4; ++k) {
    due.push_back(broadcast.next_due_ns());
    broadcast.publish(broadcast.next_due_ns(), robots);
    bus.run_until(broadcast.next_due_ns(), done);
  }
  EXPECT_EQ(due, (std::vector<std::int64_t>{0, 333'333'333, 666'666'667, 1'000'000'000}));
  ASSERT_EQ(done.size(), 4u * 7u);
  const std::uint32_t order[] = {0x700, 0x710, 0x720, 0x730, 0x711, 0x721, 0x731};
  for (std::size_t i = 0; i < done.size(); ++i) {
    EXPECT_EQ(done[i].frame.id, order[i % 7]) << i;
    EXPECT_TRUE(done[i].acked);
    EXPECT_EQ(done[i].node, broadcast.node());
  }
  EXPECT_EQ(done[7].start_ns, 333'333'333);
  // The broadcast node acks the MCU's frames.
  bus.request(mcu, bus.horizon_ns(), CanFrame{}, 0);
  bus.run_until(bus.horizon_ns() + 1'000'000, done);
  EXPECT_TRUE(done.back().acked);
  EXPECT_EQ(done.back().node, mcu);
  // A publish after a long step catches up to the next due time after it.
  broadcast.publish(5'100'000'000, robots);
  EXPECT_EQ(broadcast.next_due_ns(), 5'333'333'333);
  EXPECT_THROW(encode_broadcast(0, std::vector<RobotBroadcastState>(kBroadcastMaxRobots + 1)), std::invalid_argument);
}

TEST(CanBroadcast, SkipsWhileItsLastBroadcastFindsNoReceiver) {
  CanBus bus(1'000'000);
  CanStateBroadcast broadcast(bus, 10.0);
  const std::vector<RobotBroadcastState> robots(1);
  std::vector<CanTransfer> done;
  for (int k = 0; k < 5; ++k) {
    broadcast.publish(broadcast.next_due_ns(), robots);
    bus.run_until(broadcast.next_due_ns(), done);
  }
  // Nobody acks the clock frame: it repeats, and the queue never grows past one broadcast.
  EXPECT_EQ(broadcast.sent(), 1u);
  EXPECT_EQ(broadcast.skipped(), 4u);
  EXPECT_EQ(bus.pending(broadcast.node()), 4u);
  EXPECT_EQ(bus.counters(broadcast.node()).state, CanErrorState::passive);
}

}  // namespace
}  // namespace sear
