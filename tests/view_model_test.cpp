// The viewer's content (tools/view/view_model.hpp, PROTOCOL.md sections 2-3): the scene against
// the project; frames against the simulation in a short lockstep run of the wall follower facing a
// wall (a GP2D12, a MaxBotix, an LMS200 and a NEO-6M on its MCU, no motors wired, so the rover
// stands still and every distance is known from the geometry); and the log's decoding, cursors and
// panels fed by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <ode/ode.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <regex>
#include <zlib.h>

#include "runtime/can_bus.hpp"
#include "runtime/lockstep.hpp"
#include "scene/geodetic.hpp"
#include "scene/project_loader.hpp"
#include "temp_dir.hpp"
#include "view/replay_file.hpp"
#include "view/uart_decode.hpp"
#include "view/view_model.hpp"

extern "C" {
#include "devices/sharp_gp2d12.h"
#include "devices/sick_lms2xx.h"
}

namespace sear::test {
namespace {

using Json = nlohmann::json;

// The wall's face is at x = 1.20 - 0.05 = 1.15; the rover stands at the origin facing east.
constexpr double kWallFaceX = 1.15;
constexpr double kRunS = 3.0;
const GeoPoint kOrigin{52.2053, 0.1218, 12};

std::string project_text() {
  const std::string assets = SEAR_ASSET_DIR;
  return R"(<project name="view">
  <run duration="3" seed="1" trace_rate="10"/>
  <world step="0.001">
    <gps_origin latitude="52.2053" longitude="0.1218" altitude="12"/>
    <terrain type="flat"/>
    <box name="crate" pos="2 1" size="0.4 0.6 0.3" yaw_deg="30"/>
    <box name="parcel" pos="-2 1" size="0.2 0.2 0.2" mass="0.5"/>
    <tree name="oak" pos="-3 -3" trunk_radius="0.15" trunk_height="2.5" crown_radius="1.2"/>
    <wall name="target" from="1.2 -2" to="1.2 2" height="0.5" thickness="0.1"/>
    <mesh name="rock" file=")" + assets + R"(/meshes/rock.obj" pos="-2 2.5" yaw_deg="35"/>
  </world>
  <robot name="rover" file=")" + assets + R"(/robots/rover.xml">
    <pose x="0" y="0"/>
    <mcu name="main">
      <firmware executable=")" + WALL_FOLLOWER + R"("/>
      <gp2d12 name="ir" adc="0" pos="0.15 0 0.1"/>
      <maxbotix_lv_ez name="sonar" serial_uart="2" pos="0.15 0.05 0.12"/>
      <lms2xx name="lidar" uart="1" pos="0.12 0 0.12" power_up="0.2" noise_mm_mode="0" noise_cm_mode="0"/>
      <ublox_neo6m name="gps" uart="3" rate_hz="5" ttff="0.5" cep="0.001" pos="-0.05 0 0.15"/>
    </mcu>
  </robot>
  <robot name="pushed" file=")" + assets + R"(/robots/rover.xml">
    <pose x="-1" y="-1.5"/>
  </robot>
</project>
)";
}

ProjectDesc load() {
  Diagnostics diagnostics;
  auto project = load_project_text(project_text(), "view.xml", diagnostics);
  EXPECT_TRUE(project) << diagnostics.joined();
  return project ? *project : ProjectDesc{};
}

const Json* named(const Json& list, const std::string& name) {
  for (const Json& j : list)
    if (j.value("name", "") == name) return &j;
  return nullptr;
}

TEST(ViewScene, ListsEveryObstacleAndRobotWithTheProjectsSizes) {
  const ProjectDesc project = load();
  ViewModel view(project);
  const Json scene = Json::parse(view.scene_json());
  EXPECT_EQ(scene["type"], "scene");
  EXPECT_EQ(scene["world"]["terrain"]["kind"], "plane");
  EXPECT_DOUBLE_EQ(scene["world"]["gps_origin"]["latitude"].get<double>(), kOrigin.latitude_deg);

  const Json& obstacles = scene["world"]["obstacles"];
  const Json* crate = named(obstacles, "crate");
  ASSERT_TRUE(crate);
  EXPECT_EQ((*crate)["shape"], "box");
  EXPECT_EQ((*crate)["size"], Json::array({0.4, 0.6, 0.3}));
  EXPECT_NEAR((*crate)["pos"][2].get<double>(), 0.15, 1e-3);  // resting on z = 0
  // Yawed 30 degrees about z: q = (cos 15, 0, 0, sin 15).
  EXPECT_NEAR((*crate)["quat"][0].get<double>(), std::cos(15 * kDegToRad), 1e-4);
  EXPECT_NEAR((*crate)["quat"][3].get<double>(), std::sin(15 * kDegToRad), 1e-4);
  const Json* parcel = named(obstacles, "parcel");
  ASSERT_TRUE(parcel);
  EXPECT_TRUE((*parcel)["movable"].get<bool>());
  const Json* wall = named(obstacles, "target");
  ASSERT_TRUE(wall);
  EXPECT_NEAR((*wall)["size"][0].get<double>(), 4.0, 1e-3);
  EXPECT_NEAR((*wall)["size"][1].get<double>(), 0.1, 1e-3);
  EXPECT_NEAR((*wall)["pos"][0].get<double>(), 1.2, 1e-3);
  int trunks = 0, crowns = 0;
  for (const Json& o : obstacles) {
    if (o["name"] != "oak") continue;
    if (o["shape"] == "cylinder") {
      ++trunks;
      EXPECT_NEAR(o["radius"].get<double>(), 0.15, 1e-3);
    }
    if (o["shape"] == "sphere") {
      ++crowns;
      EXPECT_NEAR(o["radius"].get<double>(), 1.2, 1e-3);
    }
  }
  EXPECT_EQ(trunks, 1);
  EXPECT_EQ(crowns, 1);
  const Json* rock = named(obstacles, "rock");
  ASSERT_TRUE(rock);
  EXPECT_EQ((*rock)["shape"], "mesh");
  EXPECT_EQ((*rock)["vertices"].size(), 3 * project.world.meshes[0].mesh.vertices.size());
  EXPECT_EQ((*rock)["indices"].size(), project.world.meshes[0].mesh.indices.size());  // under the cap
  EXPECT_EQ(obstacles.size(), 6u);  // crate, parcel, wall, trunk, crown, rock

  const Json& robots = scene["robots"];
  ASSERT_EQ(robots.size(), 2u);
  const Json& rover = robots[0];
  const RobotDesc& desc = project.robots[0];
  EXPECT_EQ(rover["name"], "rover");
  EXPECT_FALSE(rover["keyboard"].get<bool>());
  EXPECT_TRUE(robots[1]["keyboard"].get<bool>());  // no MCU: the keys drive it
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rover["body"]["size"][k].get<double>(), desc.chassis.size_m[k], 5e-4);
  ASSERT_EQ(rover["wheels"].size(), desc.wheels.size());
  EXPECT_NEAR(rover["wheels"][0]["radius"].get<double>(), desc.wheels[0].radius_m, 5e-4);
  // The chassis, two shapes per wheel (tyre and tread), one per caster.
  EXPECT_EQ(rover["geoms"].size(), 1 + 2 * desc.wheels.size() + desc.casters.size());

  const Json& sensors = rover["sensors"];
  ASSERT_EQ(sensors.size(), 4u);
  const Json* ir = named(sensors, "ir");
  ASSERT_TRUE(ir);
  EXPECT_EQ((*ir)["view"], "cone");
  EXPECT_EQ((*ir)["mcu"], "rover.main");
  EXPECT_NEAR((*ir)["beam_deg"].get<double>(), 4.0, 1e-4);  // the GP2D12 row's half-angle is 2 degrees
  EXPECT_NEAR((*ir)["max_m"].get<double>(), 1.5, 1e-9);
  EXPECT_NEAR((*ir)["min_m"].get<double>(), 0.10, 1e-9);
  EXPECT_EQ((*ir)["pos"], Json::array({0.15, 0.0, 0.1}));
  const Json* lidar = named(sensors, "lidar");
  ASSERT_TRUE(lidar);
  EXPECT_EQ((*lidar)["view"], "fan");
  EXPECT_EQ((*lidar)["count"], 361);
  EXPECT_EQ(named(sensors, "gps")->at("view"), "gps");
  const Json& mcu = rover["mcus"][0];
  EXPECT_EQ(mcu["id"], "rover.main");
  EXPECT_EQ(mcu["console_uart"], 0);
  EXPECT_EQ(named(mcu["devices"], "lidar")->at("wiring"), "uart 1");
  EXPECT_EQ(named(mcu["devices"], "ir")->at("wiring"), "adc 0");
  // The panel labels each quantity with its unit: the GP2D12's truth is a distance in metres, its
  // reading the volts on its output (reading_meaning.hpp's row for the part).
  EXPECT_EQ(named(mcu["devices"], "ir")->at("units"), Json({{"distance", "m"}, {"output_voltage", "V"}}));
}

// A heightmap's grid comes as world.json has it, to the millimetre; a mesh of more triangles than
// the cap is thinned to every k-th one, and only the kept triangles' vertices are sent.
TEST(ViewScene, HeightmapGridAndBigMeshesAreBounded) {
  const std::string assets = SEAR_ASSET_DIR;
  Diagnostics diagnostics;
  auto project = load_project_text(R"(<project name="hills">
  <world step="0.001">
    <terrain type="heightmap" image=")" + assets + R"(/heightmaps/hills.png" size="40 40" min_height="0" max_height="1.2"/>
  </world>
</project>
)", "hills.xml", diagnostics);
  ASSERT_TRUE(project) << diagnostics.joined();
  // A soup of 50000 triangles, each with its own three vertices; triangle i stands at x = i mm.
  MeshObstacleDesc big;
  big.name = "strip";
  big.xy_m = {5, 5};
  for (std::uint32_t i = 0; i < 50000; ++i) {
    const float x = 0.001f * static_cast<float>(i);
    big.mesh.vertices.emplace_back(x, 0.f, 0.f);
    big.mesh.vertices.emplace_back(x, 0.1f, 0.1f);
    big.mesh.vertices.emplace_back(x, 0.2f, 0.f);
    for (std::uint32_t k = 0; k < 3; ++k) big.mesh.indices.push_back(3 * i + k);
  }
  project->world.meshes.push_back(big);
  const Json scene = Json::parse(ViewModel(*project).scene_json());
  const Json& terrain = scene["world"]["terrain"];
  EXPECT_EQ(terrain["kind"], "heightmap");
  EXPECT_EQ(terrain["grid"], Json::array({129, 129}));  // under world.json's 256 cap: whole
  EXPECT_EQ(terrain["size_m"], Json::array({40.0, 40.0}));
  double highest = 0;
  for (const Json& row : terrain["heights_m"])
    for (const Json& h : row) {
      EXPECT_DOUBLE_EQ(h.get<double>(), std::round(h.get<double>() * 1000) / 1000);
      highest = std::max(highest, h.get<double>());
    }
  EXPECT_GT(highest, 0.5);
  EXPECT_LE(highest, 1.2);
  const Json* strip = named(scene["world"]["obstacles"], "strip");
  ASSERT_TRUE(strip);
  // 50000 triangles over a cap of 20000: every 3rd, 16667 of them, and their 3 vertices each
  // (not all 150000 of the mesh).
  const Json& indices = (*strip)["indices"];
  const Json& vertices = (*strip)["vertices"];
  ASSERT_EQ(indices.size(), 3u * 16667u);
  ASSERT_EQ(vertices.size(), 3u * 3u * 16667u);
  // Kept triangle k is the mesh's triangle 3k, at x = 3k mm, its vertices in their order.
  for (std::size_t k : {std::size_t{0}, std::size_t{1}, std::size_t{5000}, std::size_t{16666}})
    for (std::size_t j = 0; j < 3; ++j) {
      const std::size_t v = indices[3 * k + j].get<std::size_t>();
      ASSERT_LT(3 * v + 2, vertices.size());
      EXPECT_NEAR(vertices[3 * v].get<double>(), 0.003 * static_cast<double>(k), 1e-9) << k;
      EXPECT_NEAR(vertices[3 * v + 1].get<double>(), 0.1 * static_cast<double>(j), 1e-9) << k;
    }
}

class NoListener : public McuListener {
 public:
  void on_events(std::size_t, const sear_event*, std::size_t) override {}
  void on_stop(std::size_t, std::int64_t) override {}
};

struct RunResult {
  std::vector<Json> frames;     // one every 50 ms, as a replay takes them
  std::vector<Json> entries;    // every log entry of rover.main, in order
  Json last;
  Eigen::Vector3d position_m;   // the rover's, at the end
  Eigen::Vector4d quat;         // ODE's [w x y z]
  double yaw_rad = 0;
  std::uint64_t dropped = 0;
};

const RunResult& run_once() {
  static const RunResult result = [] {
    RunResult r;
    const ProjectDesc project = load();
    TempDir dir;
    ViewModel view(project);
    Simulation sim(project, project.run.seed);
    LockstepOptions options;
    options.out_dir = dir.path().string();
    options.mcu.tap = &view;
    NoListener listener;
    Lockstep lockstep(sim, project, options, listener);
    FrameCursor cursor;
    const std::int64_t end_ns = std::llround(kRunS * 1e9);
    for (std::int64_t step = 1; sim.time_ns() < end_ns; ++step) {
      EXPECT_TRUE(lockstep.step());
      if (step % 50) continue;
      Json frame = Json::parse(view.frame_json(sim, cursor));
      r.dropped += frame["dropped"].get<std::uint64_t>();
      for (const Json& e : frame["mcus"][0]["log"]) r.entries.push_back(e);
      r.frames.push_back(std::move(frame));
    }
    r.last = r.frames.back();
    const VehicleState state = sim.robot_state(0);
    r.position_m = state.position_m;
    r.yaw_rad = state.roll_pitch_yaw.z();
    const dReal* q = dBodyGetQuaternion(sim.robot(0).chassis_body());
    r.quat = {q[0], q[1], q[2], q[3]};
    return r;
  }();
  return result;
}

TEST(ViewFrame, RobotPoseIsTheSimulations) {
  const RunResult& r = run_once();
  const Json& rover = r.last["robots"][0];
  EXPECT_EQ(rover["name"], "rover");
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rover["pos"][k].get<double>(), r.position_m[k], 5e-4 + 1e-9);  // 1 mm rounding
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(rover["quat"][k].get<double>(), r.quat[k], 5e-5 + 1e-9);       // 1e-4 rounding
  EXPECT_EQ(rover["wheels"].size(), load().robots[0].wheels.size());
  EXPECT_NEAR(r.last["t"].get<double>(), kRunS, 1e-9);
  EXPECT_EQ(r.dropped, 0u);  // 20 frames a second keep up with this run's log
  const Json* parcel = named(r.last["obstacles"], "parcel");
  ASSERT_TRUE(parcel);
  EXPECT_NEAR((*parcel)["pos"][2].get<double>(), 0.1, 2e-3);  // resting on the floor
}

TEST(ViewFrame, ConesSeeTheWallAtItsDistance) {
  const RunResult& r = run_once();
  const Json& sensors = r.last["robots"][0]["sensors"];
  // Both sit 0.15 m ahead of the chassis origin on a still rover facing the wall square on: the
  // axis ray is the closest, 1.15 - 0.15 - x = 1.00 m; 1.5 mm covers the frame's 1 mm rounding.
  const double expected = kWallFaceX - 0.15 - r.position_m.x();
  EXPECT_NEAR(named(sensors, "ir")->at("range_m").get<double>(), expected, 1.5e-3);    // the model's truth sample
  EXPECT_NEAR(named(sensors, "sonar")->at("range_m").get<double>(), expected, 1.5e-3);  // cast for the view
  // The MCU panel: the truth the GP2D12's model was fed, and the volts it gave the firmware for it,
  // the datasheet curve plus the row's 0.01 V noise (4 sigma).
  const Json& mcu = r.last["mcus"][0];
  EXPECT_NEAR(mcu["truth"]["ir"]["distance"].get<double>(), expected, 1.5e-3);
  ASSERT_TRUE(mcu["readings"].contains("ir")) << mcu["readings"].dump();
  EXPECT_NEAR(mcu["readings"]["ir"]["output_voltage"].get<double>(), gp2d12_output_v(expected), 0.04);
}

TEST(ViewFrame, LidarFanHitsTheWall) {
  const RunResult& r = run_once();
  const Json* lidar = named(r.last["robots"][0]["sensors"], "lidar");
  ASSERT_TRUE(lidar);
  ASSERT_FALSE((*lidar)["ranges_m"].is_null()) << "no scan decoded in " << kRunS << " s";
  const Json& ranges = (*lidar)["ranges_m"];
  ASSERT_EQ(ranges.size(), 361u);
  EXPECT_DOUBLE_EQ((*lidar)["start_deg"].get<double>(), -90.0);
  EXPECT_DOUBLE_EQ((*lidar)["step_deg"].get<double>(), 0.5);
  // The units the scans came in: the model's resolution (1 cm or 1 mm) plus 1 mm of rounding.
  bool mm = false;
  for (const Json& e : r.entries)
    if (e["kind"] == "lms" && e["text"].get<std::string>().rfind("B0 scan", 0) == 0)
      mm = e["text"].get<std::string>().find(", mm") != std::string::npos;
  const double tolerance = (mm ? 0.001 : 0.01) + 0.001;
  const double ahead = kWallFaceX - (r.position_m.x() + 0.12);
  int checked = 0;
  for (int i = 90; i <= 270; ++i) {  // -45 .. +45 degrees: all on the wall
    const double angle = (-90.0 + 0.5 * i) * kDegToRad + r.yaw_rad;
    ASSERT_FALSE(ranges[i].is_null()) << i;
    EXPECT_NEAR(ranges[i].get<double>(), ahead / std::cos(angle), tolerance) << "value " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 181);
}

TEST(ViewFrame, GpsFixIsDecodedAndNearTheTruth) {
  const RunResult& r = run_once();
  const Json* gps = named(r.last["robots"][0]["sensors"], "gps");
  ASSERT_TRUE(gps);
  ASSERT_FALSE((*gps)["fix"].is_null());
  // CEP 1 mm, and NMEA's 1e-5 minute steps are 1.9 cm of latitude: within 3 cm horizontally.
  const double de = (*gps)["fix"][0].get<double>() - (*gps)["truth"][0].get<double>();
  const double dn = (*gps)["fix"][1].get<double>() - (*gps)["truth"][1].get<double>();
  EXPECT_LT(std::hypot(de, dn), 0.03);
  // The antenna is 5 cm behind the chassis origin.
  EXPECT_NEAR((*gps)["truth"][0].get<double>(), r.position_m.x() - 0.05, 2e-3);
}

TEST(ViewLog, NmeaLmsAndConsoleEntriesAreWhole) {
  const RunResult& r = run_once();
  int nmea = 0, scans = 0, mode_requests = 0, ready = 0, scan_lines = 0;
  std::uint64_t last_seq = 0;
  bool first = true;
  const std::regex scan_line(R"(scan \d+: right (--|[0-9.]+) m, ahead [0-9.]+ m, steer [LR+-]?\d+\.\d\d, crc errors \d+)");
  for (const Json& e : r.entries) {
    const std::uint64_t seq = e["seq"];
    EXPECT_TRUE(first || seq > last_seq);
    first = false;
    last_seq = seq;
    const std::string text = e.value("text", "");
    if (e["kind"] == "nmea") {
      ++nmea;
      EXPECT_EQ(e["device"], "gps");
      EXPECT_EQ(e["dir"], "tx");
      EXPECT_TRUE(e["crc_ok"].get<bool>()) << text;
      EXPECT_EQ(text[0], '$');
      EXPECT_EQ(text.find('\r'), std::string::npos);
    }
    if (e["kind"] == "lms" && text.rfind("B0 scan, 361 values", 0) == 0) {
      ++scans;
      EXPECT_EQ(e["dir"], "tx");
      EXPECT_TRUE(e["crc_ok"].get<bool>());
      EXPECT_EQ(e["hex"].get<std::string>().substr(0, 5), "02 80");
    }
    if (e["kind"] == "lms" && text.rfind("20 mode", 0) == 0 && e["dir"] == "rx" && e["crc_ok"].get<bool>()) ++mode_requests;
    if (e["kind"] == "console") {
      EXPECT_EQ(text.find('\n'), std::string::npos);
      if (text == "wall_follower: ready") ++ready;
      if (text.rfind("scan ", 0) == 0) {
        ++scan_lines;
        EXPECT_TRUE(std::regex_match(text, scan_line)) << text;  // never cut where a quantum ended
      }
    }
  }
  EXPECT_GE(nmea, 5);  // 5 fixes a second from 0.5 s on, several sentences each
  EXPECT_GE(scans, 3);
  EXPECT_GE(mode_requests, 1);
  EXPECT_EQ(ready, 1);
  EXPECT_GE(scan_lines, 3);
}

// ---- Fed by hand: a simulation that is not stepped, its hooks called directly. ----

class FedView : public ::testing::Test {
 protected:
  FedView() : project_(load()), sim_(project_, 1), view_(project_) {}
  Json frame(FrameCursor& c) { return Json::parse(view_.frame_json(sim_, c)); }
  void tx(int port, const std::string& text, std::int64_t t_ns = 1000) {
    for (char c : text) view_.on_mcu_event(0, {t_ns, static_cast<std::uint8_t>(c), SEAR_EVENT_UART_TX, static_cast<std::uint8_t>(port), {}});
  }
  void wire(std::size_t device, bool from_device, const std::vector<std::uint8_t>& bytes, std::int64_t t_ns = 1000,
            std::uint32_t baud = 9600) {
    std::vector<serial_byte> b;
    for (std::uint8_t v : bytes) b.push_back({t_ns += serial_frame_ns(baud), baud, v, {}});
    view_.on_wire_bytes(0, device, from_device, b.data(), b.size());
  }
  static std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }
  static constexpr std::size_t kLidar = 2, kGps = 3;  // their places among the MCU's devices

  ProjectDesc project_;
  Simulation sim_;
  ViewModel view_;
};

TEST_F(FedView, ConsoleLinesSplitAcrossQuantaAreWhole) {
  FrameCursor c;
  tx(0, "hel");
  EXPECT_TRUE(frame(c)["mcus"][0]["log"].empty());  // no line yet
  tx(0, "lo\r\nwor");
  tx(1, "not the console\n");
  Json log = frame(c)["mcus"][0]["log"];
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0]["text"], "hello");
  EXPECT_DOUBLE_EQ(log[0]["t"].get<double>(), 1e-6);
  tx(0, "ld", 2000);
  EXPECT_TRUE(frame(c)["mcus"][0]["log"].empty());
  tx(0, "!\n", 3000);
  log = frame(c)["mcus"][0]["log"];
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(log[0]["text"], "world!");
  // A line is stamped with its last byte's time; its seq follows the line before.
  EXPECT_DOUBLE_EQ(log[0]["t"].get<double>(), 3e-6);
}

TEST_F(FedView, NmeaIsDecodedAndItsChecksumChecked) {
  // A GGA at a known place 30 m east and 40 m north of the origin, with its checksum computed here.
  const LocalTangentPlane plane(kOrigin);
  const GeoPoint p = plane.to_geo({30, 40, 0});
  const auto dm = [](double deg) { return std::floor(deg) * 100 + (deg - std::floor(deg)) * 60; };
  char body[128];
  std::snprintf(body, sizeof body, "GPGGA,120000.00,%010.5f,N,%011.5f,E,1,08,0.9,%.1f,M,0.0,M,,", dm(p.latitude_deg),
                dm(p.longitude_deg), p.altitude_m);
  unsigned sum = 0;
  for (const char* c = body; *c; ++c) sum ^= static_cast<unsigned char>(*c);
  char good[160], bad[160];
  std::snprintf(good, sizeof good, "$%s*%02X", body, sum);
  std::snprintf(bad, sizeof bad, "$%s*%02X", body, sum ^ 0x10u);
  FrameCursor c;
  wire(kGps, true, bytes_of(std::string(good) + "\r\n$GPG"));
  wire(kGps, true, bytes_of("SA,A,3*00\r\n"));  // split over two calls, wrong checksum
  Json f = frame(c);
  const Json& log = f["mcus"][0]["log"];
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0]["kind"], "nmea");
  EXPECT_EQ(log[0]["text"], good);
  EXPECT_TRUE(log[0]["crc_ok"].get<bool>());
  EXPECT_EQ(log[1]["text"], "$GPGSA,A,3*00");
  EXPECT_FALSE(log[1]["crc_ok"].get<bool>());
  const Json* gps = named(f["robots"][0]["sensors"], "gps");
  // 1e-5 minute of latitude is 1.9 mm... of arc 1.85 cm: the fix is within 1 cm of (30, 40).
  EXPECT_NEAR((*gps)["fix"][0].get<double>(), 30, 0.01);
  EXPECT_NEAR((*gps)["fix"][1].get<double>(), 40, 0.01);

  // A corrupted sentence is flagged and does not move the fix.
  wire(kGps, true, bytes_of(std::string(bad) + "\r\n"));
  f = frame(c);
  ASSERT_EQ(f["mcus"][0]["log"].size(), 1u);
  EXPECT_FALSE(f["mcus"][0]["log"][0]["crc_ok"].get<bool>());
  EXPECT_NEAR(named(f["robots"][0]["sensors"], "gps")->at("fix")[0].get<double>(), 30, 0.01);
  EXPECT_TRUE(nmea_checksum_ok(good));
  EXPECT_FALSE(nmea_checksum_ok(bad));
}

// The scanner model of hal/devices answers a request for values with a scan of a wall 2.345 m
// away in every direction; its bytes both ways go through the view.
void at_two_metres(void*, std::int64_t, double, double, std::uint32_t count, double* out_m) {
  for (std::uint32_t i = 0; i < count; ++i) out_m[i] = 2.345;
}

TEST_F(FedView, LmsTelegramsRoundTripThroughTheModel) {
  lms2xx_config config;
  lms2xx_default_config(&config);
  config.power_up_ns = 1'000'000;
  config.noise_sd_cm_mode_m = config.noise_sd_mm_mode_m = 0;
  lms2xx lms{};
  lms2xx_init(&lms, &config, {at_two_metres, nullptr}, 0);
  std::vector<serial_byte> sent(4096);
  std::int64_t now = 0;
  const auto pass = [&](std::int64_t until) {  // what the model sends up to `until`, into the view
    const std::size_t n = lms2xx_transmit(&lms, now, until, sent.data(), sent.size());
    if (n) view_.on_wire_bytes(0, kLidar, true, sent.data(), n);
    now = until;
  };
  pass(100'000'000);  // its power-on telegram
  const std::uint8_t payload[] = {LMS2XX_CMD_VALUES, 0x01};
  std::uint8_t request[16];
  const std::size_t len = lms2xx_encode_request(payload, sizeof payload, request, sizeof request);
  std::vector<serial_byte> req;
  for (std::size_t i = 0; i < len; ++i) req.push_back({now + static_cast<std::int64_t>(i + 1) * serial_frame_ns(9600), 9600, request[i], {}});
  for (const serial_byte& b : req) lms2xx_receive(&lms, &b);
  view_.on_wire_bytes(0, kLidar, false, req.data(), req.size());
  for (int k = 0; k < 20; ++k) pass(now + 100'000'000);  // 361 values at 9600 baud take 0.76 s

  FrameCursor c;
  const Json f = frame(c);
  std::vector<std::string> texts;
  for (const Json& e : f["mcus"][0]["log"]) {
    texts.push_back(e["dir"].get<std::string>() + " " + e["text"].get<std::string>());
    if (e.contains("crc_ok")) {
      EXPECT_TRUE(e["crc_ok"].get<bool>()) << e.dump();
    }
  }
  EXPECT_EQ(texts, (std::vector<std::string>{"tx 90 power-on", "rx 30 values request", "tx ACK",
                                             "tx B0 scan, 361 values, cm"}));
  const Json* lidar = named(f["robots"][0]["sensors"], "lidar");
  ASSERT_EQ((*lidar)["ranges_m"].size(), 361u);
  // cm mode: 2.345 m is sent as 234 or 235 cm.
  for (const Json& v : (*lidar)["ranges_m"]) EXPECT_NEAR(v.get<double>(), 2.345, 0.0051);

  // The same scan with one value's byte flipped on the line: its CRC no longer holds.
  std::vector<std::uint8_t> telegram;
  const std::string hex = f["mcus"][0]["log"][3]["hex"];
  EXPECT_NE(hex.find("(732 bytes)"), std::string::npos);  // 4 + 1 + 2 + 722 + 1 + 2, shown cut short
  pass(now + 1);
  const std::uint8_t p2[] = {LMS2XX_CMD_VALUES, 0x01};
  const std::size_t len2 = lms2xx_encode_request(p2, sizeof p2, request, sizeof request);
  for (std::size_t i = 0; i < len2; ++i) {
    const serial_byte b{now + static_cast<std::int64_t>(i + 1) * serial_frame_ns(9600), 9600, request[i], {}};
    lms2xx_receive(&lms, &b);
  }
  std::vector<serial_byte> reply;
  for (int k = 0; k < 20; ++k) {
    const std::size_t n = lms2xx_transmit(&lms, now, now + 100'000'000, sent.data(), sent.size());
    reply.insert(reply.end(), sent.begin(), sent.begin() + static_cast<std::ptrdiff_t>(n));
    now += 100'000'000;
  }
  ASSERT_GT(reply.size(), 100u);
  reply[50].value ^= 0x40;
  view_.on_wire_bytes(0, kLidar, true, reply.data(), reply.size());
  const Json g = frame(c);
  const Json& log = g["mcus"][0]["log"];
  ASSERT_EQ(log.size(), 2u);
  EXPECT_EQ(log[0]["text"], "ACK");
  EXPECT_EQ(log[1]["text"], "B0 scan, 361 values, cm");
  EXPECT_FALSE(log[1]["crc_ok"].get<bool>());
}

TEST_F(FedView, PinsPwmAndServosFollowEvents) {
  FrameCursor c;
  view_.on_mcu_event(0, {10, 1, SEAR_EVENT_PIN_MODE, 13, {}});
  view_.on_mcu_event(0, {10, 1, SEAR_EVENT_PIN, 13, {}});
  view_.on_mcu_event(0, {20, 128, SEAR_EVENT_PWM, 3, {}});
  view_.on_mcu_event(0, {30, 1500, SEAR_EVENT_SERVO, 9, {}});
  Json m = frame(c)["mcus"][0];
  EXPECT_EQ(m["pins"], Json({{"13", 1}}));
  EXPECT_EQ(m["pwm"], Json({{"3", 128}}));
  EXPECT_EQ(m["servo"], Json({{"9", 1500}}));
  EXPECT_TRUE(m["running"].get<bool>());
  view_.on_mcu_event(0, {40, 0, SEAR_EVENT_PIN, 13, {}});
  view_.on_mcu_event(0, {50, 1, SEAR_EVENT_PIN, 3, {}});  // a PWM pin driven as a level
  view_.on_mcu_event(0, {60, 0, SEAR_EVENT_SERVO, 9, {}});  // pulses off
  m = frame(c)["mcus"][0];
  EXPECT_EQ(m["pins"], Json({{"13", 0}, {"3", 1}}));
  EXPECT_TRUE(m["pwm"].empty());
  EXPECT_TRUE(m["servo"].empty());
  view_.mcu_stopped("rover.main", "crashed");
  m = frame(c)["mcus"][0];
  EXPECT_FALSE(m["running"].get<bool>());
  EXPECT_EQ(m["stopped"], "crashed");
  view_.restart();
  m = frame(c)["mcus"][0];
  EXPECT_TRUE(m["pins"].empty());
  EXPECT_TRUE(m["running"].get<bool>());
}

TEST_F(FedView, ReadingsAndTruthAreNamed) {
  FrameCursor c;
  sear_link_sample s{};
  s.value[0] = 0.4567;
  view_.on_sample(0, 0, s);  // the GP2D12
  const double volts = 1.234;
  view_.on_reading(0, 0, 1000, &volts, 1);
  const Json m = frame(c)["mcus"][0];
  EXPECT_DOUBLE_EQ(m["truth"]["ir"]["distance"].get<double>(), 0.4567);
  EXPECT_DOUBLE_EQ(m["readings"]["ir"]["output_voltage"].get<double>(), 1.234);
}

TEST_F(FedView, CursorDropsAndCountsBeyondTheFrameLimit) {
  FrameCursor a;
  const std::size_t lines = ViewModel::kMaxEntriesPerFrame + 100;
  for (std::size_t i = 0; i < lines; ++i) tx(0, std::to_string(i) + "\n");
  Json f = frame(a);
  const Json& log = f["mcus"][0]["log"];
  ASSERT_EQ(log.size(), ViewModel::kMaxEntriesPerFrame);
  EXPECT_EQ(f["mcus"][0]["dropped"], 100);
  EXPECT_EQ(f["dropped"], 100);
  EXPECT_EQ(log[0]["text"], "100");  // the newest are kept
  EXPECT_EQ(log.back()["text"], std::to_string(lines - 1));

  // The ring keeps kLogCapacity entries: a stream that falls further behind loses the rest.
  FrameCursor late;
  frame(late);
  for (std::size_t i = 0; i < kLogCapacity + 10; ++i) tx(0, "x\n");
  f = frame(late);
  // All it missed, 10 of them no longer in the ring; the MCU's own count is of those still there.
  EXPECT_EQ(f["dropped"].get<std::uint64_t>() + f["mcus"][0]["log"].size(), kLogCapacity + 10);
  EXPECT_EQ(f["mcus"][0]["dropped"].get<std::uint64_t>() + 10, f["dropped"].get<std::uint64_t>());
}

// A live frame keeps the newest `stream_cap` entries of each binary stream and every text line;
// a replay's (no cap) keeps them all.
TEST_F(FedView, LiveFramesKeepTheNewestOfEachBinaryStreamAndEveryLine) {
  constexpr std::size_t kCap = 8, kBlocks = 20, kLines = 3;
  FrameCursor live, replay;
  std::int64_t t = 1000;
  for (std::size_t i = 0; i < kBlocks; ++i) {
    // Not an LMS2xx telegram (no STX): each block ends as one "bytes" entry after a pause.
    wire(kGps, true, {0xB5, 0x62, static_cast<std::uint8_t>(i)}, t += 50'000'000);
    if (i < kLines) tx(0, "line " + std::to_string(i) + "\n", t);
  }
  const auto count = [](const Json& log, const char* kind) {
    return std::count_if(log.begin(), log.end(), [&](const Json& e) { return e["kind"] == kind; });
  };
  const Json l = Json::parse(view_.frame_json(sim_, live, kCap));
  const Json r = Json::parse(view_.frame_json(sim_, replay));
  const long bytes = count(r["mcus"][0]["log"], "bytes");
  ASSERT_GT(bytes, static_cast<long>(kCap)) << r.dump();
  EXPECT_EQ(count(l["mcus"][0]["log"], "bytes"), static_cast<long>(kCap));
  EXPECT_EQ(count(l["mcus"][0]["log"], "console"), static_cast<long>(kLines));
  EXPECT_EQ(count(r["mcus"][0]["log"], "console"), static_cast<long>(kLines));
  EXPECT_EQ(l["dropped"].get<long>(), bytes - static_cast<long>(kCap));
  EXPECT_EQ(r["dropped"], 0);
}

// A firmware's non-ASCII bytes (a degree sign in Latin-1, 0xFF, UBX binary after a '$') never
// reach the JSON raw: nlohmann would throw type_error.316 and end the run.
TEST_F(FedView, NonAsciiBytesShowAsHexAndFramesStayJson) {
  FrameCursor c;
  tx(0, "temp 21\xb0" "C\n");
  tx(0, "\xff\n");
  wire(kGps, true, {'$', 'G', 'P', 'G', 'G', 'A', ',', 0xB5, 0x62, 0x01, 0x07, '\r', '\n'});
  std::string text;
  ASSERT_NO_THROW(text = view_.frame_json(sim_, c));
  const Json log = Json::parse(text)["mcus"][0]["log"];
  ASSERT_EQ(log.size(), 3u) << log.dump();
  EXPECT_EQ(log[0]["text"], "temp 21\\xB0C");
  EXPECT_EQ(log[1]["text"], "\\xFF");
  // A high byte ends the would-be sentence: its bytes show as hex, not as an NMEA entry.
  EXPECT_EQ(log[2]["kind"], "bytes");
  EXPECT_EQ(log[2]["hex"], "24 47 50 47 47 41 2C B5 62 01 07");
}

// Nobody watching: UART traffic and CAN frames cost nothing and log nothing; levels and console
// lines are still kept (a page that comes late gets them). Watching again, the log starts at the
// next whole sentence.
TEST_F(FedView, UnwatchedTrafficIsSkippedAndResumesAtABoundaryAndConsoleLinesAreKept) {
  const std::string gga = "$GPGGA,120000.00,5212.31800,N,00007.30800,E,1,08,0.9,12.0,M,0.0,M,,*";
  unsigned sum = 0;
  for (std::size_t i = 1; i + 1 < gga.size(); ++i) sum ^= static_cast<unsigned char>(gga[i]);
  char tail[4];
  std::snprintf(tail, sizeof tail, "%02X", sum);
  const std::string good = gga + tail;
  ASSERT_TRUE(nmea_checksum_ok(good));

  FrameCursor c;
  view_.set_watching(false);
  std::size_t bytes = 0, lines = 0;
  while (bytes < 1000) {
    ++lines;
    wire(kGps, true, bytes_of(good + "\r\n"));
    tx(0, "unseen\n");
    bytes += good.size() + 2 + 7;
  }
  wire(kGps, true, bytes_of(good.substr(0, 30)));  // torn: its start goes by unwatched
  tx(0, "half a li");
  view_.on_mcu_event(0, {10, 1, SEAR_EVENT_PIN_MODE, 13, {}});
  view_.on_mcu_event(0, {10, 1, SEAR_EVENT_PIN, 13, {}});
  Json f = frame(c);
  ASSERT_EQ(f["mcus"][0]["log"].size(), lines) << f["mcus"][0]["log"].dump();
  for (const Json& e : f["mcus"][0]["log"]) EXPECT_EQ(e["text"], "unseen");
  EXPECT_EQ(f["dropped"], 0);
  EXPECT_EQ(f["mcus"][0]["pins"]["13"], 1);

  view_.set_watching(true);
  wire(kGps, true, bytes_of(good.substr(30) + "\r\n" + good + "\r\n"));
  tx(0, "ne\nwhole\n");
  f = frame(c);
  const Json& log = f["mcus"][0]["log"];
  ASSERT_EQ(log.size(), 3u) << log.dump();
  EXPECT_EQ(log[0]["kind"], "nmea");
  EXPECT_EQ(log[0]["text"], good);
  EXPECT_TRUE(log[0]["crc_ok"].get<bool>());
  EXPECT_EQ(log[1]["text"], "half a line");
  EXPECT_EQ(log[2]["text"], "whole");
}

// The same for an LMS2xx: a telegram under way when watching starts is skipped, ACK-looking data
// bytes in it included; logging resumes at the next telegram whose CRC holds (the ACK before it
// cannot be told from data, so it goes unlogged too).
TEST_F(FedView, UnwatchedLmsResumesAtTheNextWholeTelegram) {
  lms2xx_config config;
  lms2xx_default_config(&config);
  config.power_up_ns = 1'000'000;
  config.noise_sd_cm_mode_m = config.noise_sd_mm_mode_m = 0;
  lms2xx lms{};
  lms2xx_init(&lms, &config, {at_two_metres, nullptr}, 0);
  std::vector<serial_byte> sent(4096), reply;
  std::int64_t now = 0;
  lms2xx_transmit(&lms, now, now + 100'000'000, sent.data(), sent.size());  // power-on, unseen
  now += 100'000'000;
  std::uint8_t request[16];
  for (int scan = 0; scan < 2; ++scan) {
    const std::uint8_t payload[] = {LMS2XX_CMD_VALUES, 0x01};
    const std::size_t len = lms2xx_encode_request(payload, sizeof payload, request, sizeof request);
    for (std::size_t i = 0; i < len; ++i) {
      const serial_byte b{now + static_cast<std::int64_t>(i + 1) * serial_frame_ns(9600), 9600, request[i], {}};
      lms2xx_receive(&lms, &b);
    }
    for (int k = 0; k < 10; ++k) {  // 732 bytes at 9600 baud: 0.76 s
      const std::size_t n = lms2xx_transmit(&lms, now, now + 100'000'000, sent.data(), sent.size());
      reply.insert(reply.end(), sent.begin(), sent.begin() + static_cast<std::ptrdiff_t>(n));
      now += 100'000'000;
    }
  }
  // ACK, scan (732 bytes), ACK, scan: watching starts 300 bytes into the first scan.
  ASSERT_EQ(reply.size(), 2u * (1 + 732)) << reply.size();
  reply[400].value = LMS2XX_ACK;  // a data byte that looks like an ACK (the CRC no longer holds)
  FrameCursor c;
  view_.set_watching(false);
  view_.on_wire_bytes(0, kLidar, true, reply.data(), 300);
  view_.set_watching(true);
  view_.on_wire_bytes(0, kLidar, true, reply.data() + 300, reply.size() - 300);
  const Json f = frame(c);
  std::vector<std::string> texts;
  for (const Json& e : f["mcus"][0]["log"]) texts.push_back(e["text"].get<std::string>());
  ASSERT_EQ(texts, (std::vector<std::string>{"B0 scan, 361 values, cm"}));
  EXPECT_TRUE(f["mcus"][0]["log"][0]["crc_ok"].get<bool>());
}

// The replay's frames: gunzipped, one JSON a line.
std::vector<Json> replay_lines(const std::filesystem::path& path) {
  gzFile gz = gzopen(path.c_str(), "rb");
  EXPECT_TRUE(gz);
  std::string text;
  char buffer[65536];
  int n;
  while (gz && (n = gzread(gz, buffer, sizeof buffer)) > 0) text.append(buffer, static_cast<std::size_t>(n));
  if (gz) gzclose(gz);
  std::vector<Json> lines;
  std::size_t from = 0;
  for (std::size_t end; (end = text.find('\n', from)) != std::string::npos; from = end + 1)
    lines.push_back(Json::parse(text.substr(from, end - from)));
  EXPECT_EQ(from, text.size());  // ends with a whole line
  return lines;
}

std::vector<std::string> console_texts(const std::vector<Json>& lines) {
  std::vector<std::string> texts;
  for (const Json& l : lines)
    if (l["type"] == "frame")
      for (const Json& e : l["mcus"][0]["log"])
        if (e["kind"] == "console") texts.push_back(e["text"]);
  return texts;
}

// PROTOCOL.md: a replay drops nothing. 10000 lines between two of its frames (the sim not stepped,
// so no frame is due) outrun both the live page's 400 a frame and the 4096-entry ring; the file
// has every one, and a non-ASCII one as hex.
TEST_F(FedView, ReplayKeepsEveryEntryBetweenFrames) {
  TempDir dir;
  const auto path = dir.path() / "run.replay.gz";
  constexpr int kLines = 10000;
  {
    ReplayFile replay(path.string(), project_, view_, ReplayFile::kDefaultRateHz);
    view_.set_watching(false);  // no page: the replay still watches
    replay.start_run(sim_);
    for (int i = 0; i < kLines; ++i) {
      tx(0, std::to_string(i) + "\n");
      if (i % 100 == 99) replay.after_step(sim_);  // a step logs 100 lines
    }
    tx(0, "21\xb0" "C\n");
    replay.finish(sim_);
  }
  const std::vector<Json> lines = replay_lines(path);
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0]["type"], "hello");
  EXPECT_EQ(lines[1]["type"], "scene");
  const std::vector<std::string> texts = console_texts(lines);
  ASSERT_EQ(texts.size(), static_cast<std::size_t>(kLines + 1));
  for (int i = 0; i < kLines; ++i) ASSERT_EQ(texts[static_cast<std::size_t>(i)], std::to_string(i));
  EXPECT_EQ(texts.back(), "21\\xB0C");
  for (const Json& l : lines)
    if (l["type"] == "frame") {
      EXPECT_EQ(l["dropped"], 0);
    }
}

// A reset mid-run: end_segment() writes what was logged since the last frame before the model
// forgets it; the new run starts with its scene and a frame of t = 0.
TEST_F(FedView, ReplayEndSegmentKeepsTheLinesBeforeAReset) {
  TempDir dir;
  const auto path = dir.path() / "run.replay.gz";
  {
    ReplayFile replay(path.string(), project_, view_, ReplayFile::kDefaultRateHz);
    replay.start_run(sim_);
    tx(0, "before reset\n");
    replay.end_segment(sim_);
    view_.restart();
    replay.start_run(sim_);
    tx(0, "after reset\n");
    replay.finish(sim_);
  }
  const std::vector<Json> lines = replay_lines(path);
  std::vector<std::string> types;
  for (const Json& l : lines) types.push_back(l["type"]);
  EXPECT_EQ(types, (std::vector<std::string>{"hello", "scene", "frame", "frame", "scene", "frame", "frame"}));
  EXPECT_EQ(console_texts(lines), (std::vector<std::string>{"before reset", "after reset"}));
}

TEST_F(FedView, TwoCursorsEachGetEveryEntry) {
  FrameCursor a, b;
  for (int i = 0; i < 100; ++i) tx(0, "a" + std::to_string(i) + "\n");
  const Json fa = frame(a);
  for (int i = 0; i < 50; ++i) tx(0, "b" + std::to_string(i) + "\n");
  const Json fb = frame(b);
  const Json fa2 = frame(a);
  EXPECT_EQ(fa["mcus"][0]["log"].size(), 100u);
  EXPECT_EQ(fb["mcus"][0]["log"].size(), 150u);
  EXPECT_EQ(fa2["mcus"][0]["log"].size(), 50u);
  EXPECT_EQ(fa2["mcus"][0]["log"][0]["text"], "b0");
  EXPECT_EQ(fb["mcus"][0]["log"][100]["seq"], fa2["mcus"][0]["log"][0]["seq"]);
  for (const Json* f : {&fa, &fb, &fa2}) EXPECT_EQ((*f)["dropped"], 0);
}

// Two MCUs on one <can_bus>, one off it: a frame shows in the log of each MCU on its bus.
TEST(ViewCan, FramesShowOnTheirBusAsCandumpText) {
  const std::string mcus = std::string("    <mcu name=\"a\">\n      <firmware executable=\"") + WALL_FOLLOWER +
                           "\"/>\n      <can bus=\"body\"/>\n    </mcu>\n    <mcu name=\"b\">\n      <firmware executable=\"" +
                           WALL_FOLLOWER + "\"/>\n      <can bus=\"body\"/>\n    </mcu>\n    <mcu name=\"c\">\n      <firmware executable=\"" +
                           WALL_FOLLOWER + "\"/>\n    </mcu>\n";
  const std::string text = "<project name=\"can\">\n  <run duration=\"0.3\" seed=\"1\" trace_rate=\"10\"/>\n"
                           "<can_bus name=\"body\" bitrate=\"500000\"/>\n  <world step=\"0.001\">\n    <terrain type=\"flat\"/>\n"
                           "  </world>\n  <robot file=\"" SEAR_ASSET_DIR "/robots/rover.xml\">\n    <pose x=\"0\" y=\"0\"/>\n" +
                           mcus + "  </robot>\n</project>\n";
  Diagnostics diagnostics;
  const auto project = load_project_text(text, "can.xml", diagnostics);
  ASSERT_TRUE(project) << diagnostics.joined();
  const Simulation sim(*project, 1);
  ViewModel view(*project);
  CanTransfer t;
  t.end_ns = 5'000'000;
  t.acked = true;
  t.frame.id = 0x123;
  t.frame.dlc = 2;
  t.frame.data[0] = 0xDE;
  t.frame.data[1] = 0xAD;
  view.on_can_frame(0, t);
  t.frame.extended = true;
  t.frame.id = 0x1ABCDEF;
  t.frame.remote = true;
  view.on_can_frame(0, t);
  FrameCursor c;
  const Json f = Json::parse(view.frame_json(sim, c));
  for (int m = 0; m < 2; ++m) {
    const Json& log = f["mcus"][m]["log"];
    ASSERT_EQ(log.size(), 2u);
    EXPECT_EQ(log[0]["kind"], "can");
    EXPECT_EQ(log[0]["bus"], "body");
    EXPECT_EQ(log[0]["text"], "123#DEAD");
    EXPECT_EQ(log[1]["text"], "01ABCDEF#R");
    EXPECT_DOUBLE_EQ(log[0]["t"].get<double>(), 0.005);
  }
  EXPECT_TRUE(f["mcus"][2]["log"].empty());
}

}  // namespace
}  // namespace sear::test
