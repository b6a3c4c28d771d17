// Terrain: heightmap orientation and a rover riding it, mesh terrain, and Coulomb friction on a slope.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/physics_world.hpp"
#include "physics/scenery.hpp"
#include "temp_dir.hpp"
#include "test_world.hpp"

namespace sear {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The plane h = 1 + 0.1 y + 0.05 x: rising to the north twice as fast as to the east, so a
// heightmap read upside down or transposed gives different heights.
double plane_height(double x, double y) { return 1.0 + 0.1 * y + 0.05 * x; }

// A 16-bit binary PGM of that plane over 20 x 20 m, row 0 the north edge; heights -0.5..2.5 m.
std::string write_plane_pgm(const test::TempDir& dir) {
  constexpr int n = 65;
  std::string pgm = "P5\n" + std::to_string(n) + " " + std::to_string(n) + "\n65535\n";
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const double x = -10.0 + 20.0 * col / (n - 1), y = 10.0 - 20.0 * row / (n - 1);
      const auto v = static_cast<unsigned>(std::lround((plane_height(x, y) + 0.5) / 3.0 * 65535.0));
      pgm += {static_cast<char>(v >> 8), static_cast<char>(v & 0xff)};
    }
  }
  return dir.write("plane.pgm", pgm);
}

std::string heightmap_world(const test::TempDir& dir, const std::string& robots) {
  return test::project_xml(R"(step="0.001")",
                           R"(<terrain type="heightmap" image=")" + write_plane_pgm(dir) +
                               R"(" size="20 20" min_height="-0.5" max_height="2.5"/>)",
                           robots);
}

TEST(Terrain, HeightmapIsNorthUpAndEastRight) {
  const test::TempDir dir;
  const ProjectDesc project = test::project_from_xml(heightmap_world(dir, ""));
  PhysicsWorld physics(project.world, 1);
  build_terrain(physics, project.world.terrain);
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0, 0}, {5, 0}, {0, 5}, {-7, 3}, {8.5, -9}, {-9.9, 9.9}}) {
    // 16-bit levels over 3 m quantise to 0.05 mm; the plane is exact on ODE's triangles.
    EXPECT_NEAR(physics.terrain_height(x, y), plane_height(x, y), 1e-4) << "at " << x << ", " << y;
  }
  EXPECT_EQ(physics.terrain_height(15, 0, -99), -99);  // off the map
}

TEST(Terrain, RoverHeightFollowsTheHeightmap) {
  const test::TempDir dir;
  const ProjectDesc project = test::project_from_xml(
      heightmap_world(dir, R"(<robot file="../robots/rover.xml"><pose x="0" y="-5" yaw_deg="90"/></robot>)"));
  Simulation sim(project, 1);
  test::drive(sim, "left", 0.8, MotorDirection::Forward);
  test::drive(sim, "right", 0.8, MotorDirection::Forward);
  test::run_for(sim, 1.0);  // settle onto the slope and get going
  const auto start = sim.robot(0).state().position_m;
  const double clearance = start.z() - plane_height(start.x(), start.y());
  EXPECT_GT(clearance, 0.0);
  EXPECT_LT(clearance, 0.1);
  test::run_for(sim, 8.0, [&] {
    const auto p = sim.robot(0).state().position_m;
    ASSERT_NEAR(p.z() - plane_height(p.x(), p.y()), clearance, 0.005) << "t = " << sim.time_s();
  });
  const auto end = sim.robot(0).state().position_m;
  EXPECT_GT(end.y() - start.y(), 3.0);  // it really climbed: 0.3 m up over these 3 m
  EXPECT_NEAR(sim.robot(0).state().roll_pitch_yaw.y(), -std::atan(0.1), 1.0 * kDeg);  // nose up is negative pitch
}

TEST(Terrain, MeshTerrainInEveryFormatKeepsItsShape) {
  for (const char* file : {"wedge.obj", "wedge.stl", "wedge.dae", "wedge.mesh.xml"}) {
    const ProjectDesc project = test::project_from_xml(test::project_xml(
        R"(step="0.001")", std::string(R"(<terrain type="mesh" file=")") + SEAR_TEST_DATA + "/meshes/" + file + R"("/>)",
        ""));
    PhysicsWorld physics(project.world, 1);
    build_terrain(physics, project.world.terrain);
    // The wedge rises from z = 0 at x = 0 to z = 1 at x = 4.
    EXPECT_NEAR(physics.terrain_height(2, 0), 0.5, 1e-6) << file;
    EXPECT_NEAR(physics.terrain_height(3, 0.5), 0.75, 1e-6) << file;
    EXPECT_EQ(physics.terrain_height(6, 0, -99), -99) << file;
  }
}

// On a 20 degree slope, an unpowered robot whose gearboxes hold its wheels stays put when
// mu > tan(20 deg) = 0.364 and slides with a = g (sin 20 - mu cos 20) when mu is lower. A
// slope of an infinite plane is the same as level ground under gravity tilted by 20 degrees.
// The direct solver (the default) holds it to 0.04 mm in the 3 s, what the gearboxes' rows give
// under the world's CFM; the iterative one at its default 20 sweeps lets static friction creep
// about 1 mm/s here (3 mm), so the bound of 0.5 mm sees friction itself and the solver's answer.
Simulation slope_sim(double mu, ProjectDesc& project, const std::string& solver = "") {
  const double g = 9.81, a = 20 * kDeg;
  project = test::project_from_xml(test::project_xml(
      "step=\"0.001\" " + solver + " gravity=\"" + std::to_string(-g * std::sin(a)) + " 0 " + std::to_string(-g * std::cos(a)) + "\"",
      "<material name=\"ground\" friction=\"" + std::to_string(mu) + "\"/><terrain type=\"flat\" material=\"ground\"/>",
      R"(<robot file="../robots/skid4.xml"><pose x="0" y="0"/></robot>)"));
  return Simulation(project, 1);
}

TEST(Terrain, UnpoweredRobotHoldsOnASlopeWhenMuExceedsTan20) {
  ProjectDesc project;
  Simulation sim = slope_sim(0.45, project);
  test::run_for(sim, 0.5);
  const double x0 = sim.robot(0).state().position_m.x();
  test::run_for(sim, 3.0);
  EXPECT_NEAR(sim.robot(0).state().position_m.x(), x0, 0.0005);
}

// The iterative solver, asked for, converges there too given the sweeps: 200 bring its creep to
// 0.01 mm/s (0.03 mm in the 3 s), where its default 20 would let the robot slide 3 mm.
TEST(Terrain, TheIterativeSolverHoldsItGivenTheSweeps) {
  ProjectDesc project;
  Simulation sim = slope_sim(0.45, project, R"(solver="iterative" solver_iterations="200")");
  ASSERT_EQ(project.world.solver, WorldDesc::Solver::Iterative);
  test::run_for(sim, 0.5);
  const double x0 = sim.robot(0).state().position_m.x();
  test::run_for(sim, 3.0);
  EXPECT_NEAR(sim.robot(0).state().position_m.x(), x0, 0.0005);
  // At 20 sweeps it does not: the bound above tells the solvers apart.
  ProjectDesc twenty;
  Simulation loose = slope_sim(0.45, twenty, R"(solver="iterative" solver_iterations="20")");
  test::run_for(loose, 0.5);
  const double x1 = loose.robot(0).state().position_m.x();
  test::run_for(loose, 3.0);
  EXPECT_GT(std::abs(loose.robot(0).state().position_m.x() - x1), 0.0005);
}

TEST(Terrain, UnpoweredRobotSlidesWithCoulombAccelerationBelowTan20) {
  ProjectDesc project;
  const double mu = 0.30;
  Simulation sim = slope_sim(mu, project);
  const double g = 9.81, a = 20 * kDeg;
  const double accel = g * (std::sin(a) - mu * std::cos(a));  // 0.59 m/s^2
  test::run_for(sim, 0.5);
  const double x1 = sim.robot(0).state().position_m.x();
  test::run_for(sim, 2.0);
  const double x2 = sim.robot(0).state().position_m.x();
  const double expected = 0.5 * accel * (2.5 * 2.5 - 0.5 * 0.5);
  EXPECT_NEAR(x1 - x2, expected, 0.1 * expected);
  EXPECT_NEAR(sim.robot(0).wheel_speed(0), 0.0, 0.05);  // the wheels stay locked: it slides, not rolls
}

// terrain_ceiling() is an upper bound for the surface in a box, and a tight one: on a rough 6 x 5
// heightmap, over a thousand random boxes, no point of ODE's own surface (probed by rays on a
// 1 cm grid) lies above it, and it is no higher than the highest sample of the cells the box
// touches. A range that skips a row or a column of cells is caught by the first; one that takes
// in too many by the second.
TEST(Terrain, TheCeilingBoundsTheSurfaceInAnyBoxTightly) {
  WorldDesc world;
  world.materials.push_back({"default", 0.8, 0.0});
  world.terrain.kind = TerrainKind::Heightmap;
  world.terrain.columns = 6;
  world.terrain.rows = 5;
  world.terrain.size_m = {5.0, 4.0};  // 1 m cells
  std::uint64_t state = 12345;
  const auto next = [&state] {  // a fixed sequence: the same boxes in every run
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < 30; ++i) world.terrain.heights_m.push_back(2.0 * next());
  PhysicsWorld physics(world, 1);
  build_terrain(physics, world.terrain);
  for (int trial = 0; trial < 1000; ++trial) {
    const double x0 = -2.5 + 5.0 * next(), y0 = -2.0 + 4.0 * next();
    const double box[6] = {x0, std::min(2.5, x0 + 0.3 * next()), y0, std::min(2.0, y0 + 0.3 * next()), 0, 0};
    const double ceiling = physics.terrain_ceiling(box);
    double highest_surface = -1e9, highest_sample = -1e9;
    for (double x = box[0]; x <= box[1]; x += 0.01)
      for (double y = box[2]; y <= box[3]; y += 0.01) highest_surface = std::max(highest_surface, physics.terrain_height(x, y, -1e9));
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c < 6; ++c) {
        const double x = -2.5 + c, y = 2.0 - r;  // sample (c, r); row 0 the north edge
        const bool touches = x >= std::floor(box[0] + 2.5) - 2.5 && x <= std::ceil(box[1] + 2.5) - 2.5 &&
                             y <= 2.0 - std::floor(2.0 - box[3]) && y >= 2.0 - std::ceil(2.0 - box[2]);
        if (touches) highest_sample = std::max(highest_sample, world.terrain.heights_m[static_cast<std::size_t>(r * 6 + c)]);
      }
    // ODE's rays meet its triangles to within rounding.
    ASSERT_GE(ceiling, highest_surface - 1e-9) << "box x " << box[0] << ".." << box[1] << ", y " << box[2] << ".." << box[3];
    ASSERT_LE(ceiling, highest_sample + 1e-12);
  }
}

}  // namespace
}  // namespace sear
