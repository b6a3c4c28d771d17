// The world holds the robot: obstacles reach the terrain along their whole footprint, a robot
// that leaves the terrain, falls through it or turns over is reported when it happens, and a
// physics state that turns non-finite stops the run with a report instead of an abort.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>

#include "exporters/run_summary.hpp"
#include "physics/physics_world.hpp"
#include "temp_dir.hpp"
#include "test_world.hpp"

// An ODE fault thrown out of a step loses a job record inside ODE's threading implementation,
// which SEAR then abandons on purpose (see Simulation::step); LeakSanitizer, in sanitizer runs of
// the test that provokes the fault, is told so rather than failing on ODE's 80 bytes.
extern "C" const char* __lsan_default_suppressions() { return "leak:PreallocateJobInfos\n"; }

namespace sear {
namespace {

// A 16-bit PGM of h(x, y) over size x size metres, n x n samples, row 0 the north edge, levels
// spanning 0..1 m.
std::string write_heightmap(const test::TempDir& dir, double size, int n, const std::function<double(double, double)>& h) {
  std::string pgm = "P5\n" + std::to_string(n) + " " + std::to_string(n) + "\n65535\n";
  for (int row = 0; row < n; ++row)
    for (int col = 0; col < n; ++col) {
      const double x = -0.5 * size + size * col / (n - 1), y = 0.5 * size - size * row / (n - 1);
      const auto v = static_cast<unsigned>(std::lround(std::clamp(h(x, y), 0.0, 1.0) * 65535.0));
      pgm += {static_cast<char>(v >> 8), static_cast<char>(v & 0xff)};
    }
  return dir.write("terrain.pgm", pgm);
}

std::string heightmap_terrain(const std::string& file, double size) {
  return R"(<terrain type="heightmap" image=")" + file + R"(" size=")" + std::to_string(size) + " " +
         std::to_string(size) + R"(" min_height="0" max_height="1"/>)";
}

std::string rover_at(double x, double y, double yaw_deg) {
  return R"(<robot file="../robots/rover.xml"><pose x=")" + std::to_string(x) + R"(" y=")" + std::to_string(y) +
         R"(" yaw_deg=")" + std::to_string(yaw_deg) + R"("/></robot>)";
}

Eigen::Vector3d vec(const dReal* v) { return {v[0], v[1], v[2]}; }

Eigen::Matrix3d rotation(const dReal* r) {
  Eigen::Matrix3d m;
  m << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
  return m;
}

// Bumps 0.3 m high every metre or two, in both directions.
double bumpy(double x, double y) { return 0.3 + 0.15 * std::sin(2 * M_PI * x / 1.7) * std::cos(2 * M_PI * y / 2.3); }

// Every static obstacle's bottom face lies nowhere above ODE's terrain surface, and its top
// stands at least `height` (by name) above it; returns how many obstacles were checked.
int check_footprints(const Simulation& sim, const std::map<std::string, double>& height) {
  const PhysicsWorld& physics = sim.physics();
  int checked = 0;
  for (int i = 0; i < dSpaceGetNumGeoms(physics.static_space()); ++i) {
    dGeomID geom = dSpaceGetGeom(physics.static_space(), i);
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
    if (tag->role != GeomRole::Obstacle) continue;
    const std::string name = physics.entity_names()[static_cast<std::size_t>(tag->entity)];
    const Eigen::Vector3d centre = vec(dGeomGetPosition(geom));
    const Eigen::Matrix3d r = rotation(dGeomGetRotation(geom));
    // Points of the bottom and top faces, every centimetre, in world coordinates.
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> columns;
    if (dGeomGetClass(geom) == dBoxClass) {
      dVector3 l;
      dGeomBoxGetLengths(geom, l);
      const int na = static_cast<int>(std::ceil(l[0] / 0.01)), nb = static_cast<int>(std::ceil(l[1] / 0.01));
      for (int a = 0; a <= na; ++a)
        for (int b = 0; b <= nb; ++b) {
          const Eigen::Vector2d local(-0.5 * l[0] + l[0] * a / na, -0.5 * l[1] + l[1] * b / nb);
          columns.push_back({centre + r * Eigen::Vector3d(local.x(), local.y(), -0.5 * l[2]),
                             centre + r * Eigen::Vector3d(local.x(), local.y(), 0.5 * l[2])});
        }
    } else if (dGeomGetClass(geom) == dCylinderClass) {
      dReal radius, length;
      dGeomCylinderGetParams(geom, &radius, &length);
      for (double rr : {0.0, 0.5 * radius, radius})
        for (int k = 0; k < 360; ++k) {
          const Eigen::Vector2d local = rr * Eigen::Vector2d(std::cos(k * M_PI / 180), std::sin(k * M_PI / 180));
          columns.push_back({centre + r * Eigen::Vector3d(local.x(), local.y(), -0.5 * length),
                             centre + r * Eigen::Vector3d(local.x(), local.y(), 0.5 * length)});
        }
    } else {
      continue;
    }
    SCOPED_TRACE(name);
    double worst_gap = -1e9, worst_shortfall = -1e9;
    for (const auto& [bottom, top] : columns) {
      const double ground = physics.terrain_height(bottom.x(), bottom.y());
      worst_gap = std::max(worst_gap, bottom.z() - ground);
      worst_shortfall = std::max(worst_shortfall, ground + height.at(name) - top.z());
    }
    // The builder sinks each footprint by the terrain's steepest gradient times the farthest any
    // point lies from one of its samples, so no point of the bottom is above ODE's surface; 1 um
    // is the rays' precision, which these heights are read with.
    EXPECT_LT(worst_gap, 1e-6);
    // And it stands at least its described height above the terrain everywhere.
    EXPECT_LT(worst_shortfall, 1e-6);
    ++checked;
  }
  return checked;
}

TEST(WorldBounds, ObstaclesReachTheTerrainUnderTheirWholeFootprint) {
  const test::TempDir dir;
  const std::string terrain = heightmap_terrain(write_heightmap(dir, 12, 121, bumpy), 12);
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", terrain + R"(
    <wall name="along_x" from="-5 -4" to="5 -4" height="0.6" thickness="0.15"/>
    <wall name="along_y" from="4.3 -5" to="4.3 5" height="0.6" thickness="0.3"/>
    <wall name="diagonal" from="-5 -2" to="3 4.5" height="0.4" thickness="0.1"/>
    <box name="crate" pos="-2 1.2" size="1.4 0.6 0.4" yaw_deg="33"/>
    <tree name="oak" pos="1.1 -1.3" trunk_radius="0.3" trunk_height="2" crown_radius="0"/>)",
                                                                       ""));
  Simulation sim(project, 1);
  const std::map<std::string, double> height = {{"along_x", 0.6}, {"along_y", 0.6}, {"diagonal", 0.4}, {"crate", 0.4}, {"oak", 2.0}};
  EXPECT_EQ(check_footprints(sim, height), 5);
}

// The bundled world's walls run 30 m over its hills; seated on their ends and middle, the south
// wall floated over dips up to 23 cm deep and the rover drove under it.
TEST(WorldBounds, DefaultWorldWallsReachTheGround) {
  std::ifstream file(std::string(SEAR_ASSET_DIR) + "/projects/default.xml");
  const std::string xml((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  const ProjectDesc project = test::project_from_xml(xml);
  Simulation sim(project, 1);
  std::map<std::string, double> height;
  for (const auto& w : project.world.walls) height[w.name] = w.height_m;
  for (const auto& b : project.world.boxes) height[b.name] = b.size_m.z();
  for (const auto& t : project.world.trees) height[t.name] = t.trunk_height_m;
  EXPECT_EQ(check_footprints(sim, height), 4 + 2 + 2);  // walls, fixed boxes, trunks
  // That means something here: along their centre lines alone the old three-point seats stood
  // 6 to 23 cm (west wall) over the lowest ground.
  double worst_old_gap = 0;
  for (const auto& w : project.world.walls) {
    const Eigen::Vector2d mid = 0.5 * (w.from_m + w.to_m);
    double seat = 1e9, lowest = 1e9;
    for (const Eigen::Vector2d& p : {w.from_m, mid, w.to_m}) seat = std::min(seat, sim.physics().terrain_height(p.x(), p.y()));
    for (int i = 0; i <= 3000; ++i) {
      const Eigen::Vector2d p = w.from_m + (w.to_m - w.from_m) * (i / 3000.0);
      lowest = std::min(lowest, sim.physics().terrain_height(p.x(), p.y()));
    }
    worst_old_gap = std::max(worst_old_gap, seat - lowest);
  }
  EXPECT_GT(worst_old_gap, 0.2);
}

// A trench 25 cm deep runs east under a wall whose ends and middle stand on the high ground:
// seated on those three points, the wall floated 25 cm over the trench, above the rover's
// 9 cm high chassis top.
TEST(WorldBounds, RoverDrivingAlongATrenchHitsTheWallAcrossIt) {
  const test::TempDir dir;
  // Flat-bottomed, 60 cm wide at the bottom (the rover is 25 cm wide), its sides rising over 30 cm.
  const auto trench = [](double, double y) {
    const double s = std::clamp((std::abs(y - 1) - 0.3) / 0.3, 0.0, 1.0);
    return 0.25 * s * s * (3 - 2 * s);
  };
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(step="0.001")",
      heightmap_terrain(write_heightmap(dir, 12, 121, trench), 12) +
          R"(<wall name="barrier" from="3 -2" to="3 2" height="0.5" thickness="0.1"/>)",
      rover_at(0, 1, 0)));
  Simulation sim(project, 1);
  test::drive(sim, "left", 1.0, MotorDirection::Forward);
  test::drive(sim, "right", 1.0, MotorDirection::Forward);
  double furthest = -1e9;
  test::run_for(sim, 8.0, [&] { furthest = std::max(furthest, sim.robot(0).state().position_m.x()); });
  ASSERT_FALSE(sim.collisions().empty());
  EXPECT_EQ(sim.collisions()[0].other, "barrier");
  // The chassis front (15 cm ahead of its origin) stops at the wall's face, 5 cm before x = 3,
  // give or take the contacts' softness.
  EXPECT_LT(furthest, 3.0 - 0.05 - 0.15 + 0.01);
  EXPECT_GT(furthest, 3.0 - 0.05 - 0.15 - 0.05);
}

// A flat 8 x 8 m heightmap: the rover drives east off its edge at x = 4.
TEST(WorldBounds, DrivingOffTheTerrainIsReportedAndStopsTheRobot) {
  const test::TempDir dir;
  const ProjectDesc project = test::project_from_xml(test::project_xml(
      R"(step="0.001")", heightmap_terrain(write_heightmap(dir, 8, 33, [](double, double) { return 0.2; }), 8),
      rover_at(2, 0, 0)));
  Simulation sim(project, 1);
  test::drive(sim, "left", 1.0, MotorDirection::Forward);
  test::drive(sim, "right", 1.0, MotorDirection::Forward);
  while (!sim.robot_stopped(0) && sim.time_s() < 10) sim.step();
  ASSERT_TRUE(sim.robot_stopped(0));
  ASSERT_EQ(sim.robot_events().size(), 1u);
  const RobotEvent e = sim.robot_events()[0];
  EXPECT_EQ(e.kind, RobotEventKind::LeftTerrain);
  EXPECT_EQ(e.robot, 0u);
  EXPECT_EQ(e.robot_name, "rover");
  EXPECT_TRUE(e.stops_robot);
  EXPECT_EQ(e.time_ns, sim.time_ns());  // reported in the step it happened
  // Reported the step its origin passed the edge: past it by at most one step's travel at the
  // rover's top speed, 0.73 mm.
  EXPECT_GT(e.position_m.x(), 4.0);
  EXPECT_LT(e.position_m.x(), 4.0 + 0.00075);
  // It had not fallen yet: the terrain is 0.2 m high, the origin rides 5.5 cm above it.
  EXPECT_NEAR(e.position_m.z(), 0.2 + 0.055, 0.01);
  // Stopped: it stays where it left, whatever its motors were told, and is reported once.
  test::run_for(sim, 2.0);
  EXPECT_LT((sim.robot(0).state().position_m - e.position_m).norm(), 1e-9);
  EXPECT_EQ(sim.robot_events().size(), 1u);

  RunOutcome outcome;
  const auto j = nlohmann::json::parse(summary_json(sim, outcome));
  ASSERT_EQ(j["robot_events"].size(), 1u);
  EXPECT_EQ(j["robot_events"][0]["kind"], "left the terrain");
  EXPECT_EQ(j["robot_events"][0]["robot"], "rover");
  EXPECT_NEAR(j["robot_events"][0]["time_s"].get<double>(), static_cast<double>(e.time_ns) * 1e-9, 1e-12);
  EXPECT_NEAR(j["robot_events"][0]["position_m"][0].get<double>(), e.position_m.x(), 1e-12);
  EXPECT_EQ(j["robot_events"][0]["stopped"], true);
  EXPECT_EQ(j["robots"][0]["status"], "stopped");
  EXPECT_TRUE(j["physics_failure"].is_null());
  EXPECT_NE(summary_text(sim, outcome).find("robot rover left the terrain at sim time"), std::string::npos);
}

// Moves every body of robot 0 by the rigid motion p -> c + R (p - c).
void move_robot(Simulation& sim, const Eigen::Vector3d& c, const Eigen::Matrix3d& rot) {
  Vehicle& v = sim.robot(0);
  std::vector<dBodyID> bodies{v.chassis_body()};
  for (std::size_t w = 0; w < v.wheel_count(); ++w) bodies.push_back(v.wheel_body(w));
  for (dBodyID b : bodies) {
    const Eigen::Vector3d p = c + rot * (vec(dBodyGetPosition(b)) - c);
    dBodySetPosition(b, p.x(), p.y(), p.z());
    const Eigen::Matrix3d m = rot * rotation(dBodyGetRotation(b));
    dMatrix3 r = {m(0, 0), m(0, 1), m(0, 2), 0, m(1, 0), m(1, 1), m(1, 2), 0, m(2, 0), m(2, 1), m(2, 2), 0};
    dBodySetRotation(b, r);
    dBodySetLinearVel(b, 0, 0, 0);
    dBodySetAngularVel(b, 0, 0, 0);
  }
}

TEST(WorldBounds, FallingThroughTheTerrainIsReportedAndStopsTheRobot) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", "", rover_at(0, 0, 0)));
  Simulation sim(project, 1);
  test::run_for(sim, 0.5);
  // As if it had tunnelled: moved under the ground plane in one go. With its origin 15 cm under
  // the surface the rover (its farthest part 17.8 cm from its origin, a chassis corner) still
  // pokes out; 25 cm under, none of it does. The ground pushes it back up at most 1 m/s (ODE's
  // correcting speed), 1 mm a step, which neither change of depth is close to.
  const Eigen::Vector3d start = sim.robot(0).state().position_m;
  move_robot(sim, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
  const auto sink_to = [&](double depth) {
    move_robot(sim, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
    Vehicle& v = sim.robot(0);
    const double dz = -depth - sim.robot(0).state().position_m.z();
    for (dBodyID b : {v.chassis_body(), v.wheel_body(0), v.wheel_body(1)}) {
      const dReal* p = dBodyGetPosition(b);
      dBodySetPosition(b, p[0], p[1], p[2] + dz);
    }
  };
  sink_to(0.15);
  sim.step();
  EXPECT_TRUE(sim.robot_events().empty());
  sink_to(0.25);
  sim.step();
  ASSERT_EQ(sim.robot_events().size(), 1u);
  EXPECT_EQ(sim.robot_events()[0].kind, RobotEventKind::FellBelow);
  EXPECT_NEAR(sim.robot_events()[0].position_m.z(), -0.25, 0.002);
  EXPECT_NEAR(sim.robot_events()[0].position_m.x(), start.x(), 0.002);
  EXPECT_TRUE(sim.robot_events()[0].stops_robot);
  EXPECT_TRUE(sim.robot_stopped(0));
}

TEST(WorldBounds, TurningOverIsReportedOncePerEpisode) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", "", rover_at(0, 0, 0)));
  Simulation sim(project, 1);
  test::run_for(sim, 0.5);
  EXPECT_TRUE(sim.robot_events().empty());
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const auto turn_over = [&] {
    const Eigen::Vector3d p = sim.robot(0).state().position_m;
    move_robot(sim, p + Eigen::Vector3d(0, 0, 0.15), flip);
  };
  turn_over();
  test::run_for(sim, 2.0);  // it lies on its back, wheels up
  ASSERT_EQ(sim.robot_events().size(), 1u);
  EXPECT_EQ(sim.robot_events()[0].kind, RobotEventKind::UpsideDown);
  EXPECT_EQ(sim.robot_events()[0].time_ns, 501'000'000);  // the first step after the flip
  EXPECT_FALSE(sim.robot_events()[0].stops_robot);
  EXPECT_FALSE(sim.robot_stopped(0));
  turn_over();  // back on its wheels: the episode ends
  test::run_for(sim, 1.0);
  EXPECT_EQ(sim.robot_events().size(), 1u);
  turn_over();
  test::run_for(sim, 1.0);
  ASSERT_EQ(sim.robot_events().size(), 2u);
  EXPECT_EQ(sim.robot_events()[1].kind, RobotEventKind::UpsideDown);
}

TEST(WorldBounds, NonFiniteStateStopsWithAPhysicsReport) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", "", rover_at(1, 2, 0)));
  Simulation sim(project, 1);
  test::run_for(sim, 0.1);
  const VehicleState before = sim.robot(0).state();
  dBodySetLinearVel(sim.robot(0).wheel_body(1), std::nan(""), 0, 0);
  try {
    sim.step();
    FAIL() << "a NaN velocity went unnoticed";
  } catch (const PhysicsError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("physics failed at sim time 0.101000 s"), std::string::npos) << what;
    EXPECT_NE(what.find("robot 'rover'"), std::string::npos) << what;
  }
  ASSERT_TRUE(sim.physics_failure());
  EXPECT_THROW(sim.step(), PhysicsError);  // over for good
  // Reports give the last finite state.
  EXPECT_LT((sim.robot_state(0).position_m - before.position_m).norm(), 0.01);
  RunOutcome outcome;
  outcome.status = "physics failed";
  const auto j = nlohmann::json::parse(summary_json(sim, outcome));
  EXPECT_EQ(j["physics_failure"], *sim.physics_failure());
  EXPECT_NEAR(j["robots"][0]["final_position_m"][0].get<double>(), 1.0, 0.01);
}

TEST(WorldBounds, AbsurdPositionStopsWithAPhysicsReport) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", "", rover_at(0, 0, 0)));
  Simulation sim(project, 1);
  dBodySetPosition(sim.robot(0).chassis_body(), 2e6, 0, 0.1);
  try {
    sim.step();
    FAIL() << "a chassis 2000 km away went unnoticed";
  } catch (const PhysicsError& e) {
    EXPECT_NE(std::string(e.what()).find("robot 'rover' chassis has flown beyond 1000 km"), std::string::npos) << e.what();
  }
}

TEST(WorldBounds, OdeInternalErrorsBecomeExceptions) {
  const ProjectDesc project = test::project_from_xml(test::project_xml(R"(step="0.001")", "", rover_at(0, 0, 0)));
  Simulation sim(project, 1);  // installs ODE's handlers
  try {
    dDebug(3, "assertion \"%s\" failed", "bNormalizationResult");
    FAIL() << "ODE's debug handler returned";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "ODE internal error 3: assertion \"bNormalizationResult\" failed");
  }
  EXPECT_THROW(dError(2, "bad argument"), std::runtime_error);
}

}  // namespace
}  // namespace sear
