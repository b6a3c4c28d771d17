// One run of a project: the physics world, its robots, their scripted commands, and the running
// tallies a summary reports (distance driven, collisions), advanced one fixed step at a time.
// It also watches that the world still holds each robot (on the terrain, above it, upright) and
// that the physics stays finite.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/physics_world.hpp"
#include "physics/vehicle.hpp"
#include "scene/description.hpp"

namespace sear {

// A robot starting to touch an obstacle or another robot.
struct CollisionEvent {
  std::int64_t time_ns;
  std::string robot;
  std::string other;
};

struct RobotTally {
  double distance_m = 0;  // path length of the chassis origin in the horizontal plane
  int collisions = 0;
};

enum class RobotEventKind {
  LeftTerrain,   // its chassis origin is past the terrain's edge: it stops there
  FellBelow,     // its chassis origin is deeper under the terrain surface than the robot is big: it stops
  UpsideDown,    // tilted past 100 degrees; reported again only after it was upright (< 80 degrees) again
};
const char* to_string(RobotEventKind kind);  // "left the terrain", "fell below the terrain", "upside down"

struct RobotEvent {
  std::int64_t time_ns;
  std::size_t robot;         // index, as robot(i)
  std::string robot_name;
  RobotEventKind kind;
  Eigen::Vector3d position_m;  // chassis origin, world frame
  bool stops_robot;            // the robot left the world and was stopped (robot_stopped() is true)
};

// The physics state turned non-finite or absurd, or ODE failed one of its internal checks.
// what() names the sim time, the robot or obstacle and the body when known.
struct PhysicsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Simulation {
 public:
  // Throws PlacementError naming every robot and obstacle with no terrain under it.
  Simulation(const ProjectDesc& project, std::uint64_t seed);

  // Throws PhysicsError when the step leaves a body non-finite or absurd, or ODE reports an
  // internal error; the simulation is then over: physics_failure() holds the report and every
  // later step() throws it again.
  void step();
  std::int64_t time_ns() const { return time_ns_; }
  std::int64_t step_ns() const { return step_ns_; }
  double time_s() const { return static_cast<double>(time_ns_) * 1e-9; }

  std::size_t robot_count() const { return vehicles_.size(); }
  Vehicle& robot(std::size_t i) { return *vehicles_[i]; }
  const Vehicle& robot(std::size_t i) const { return *vehicles_[i]; }
  // The robot's state, or after a physics failure the last finite one, for reports.
  VehicleState robot_state(std::size_t i) const;
  const RobotTally& tally(std::size_t i) const { return tallies_[i]; }
  const std::vector<CollisionEvent>& collisions() const { return collisions_; }
  const PhysicsWorld& physics() const { return *physics_; }

  // Robot events in the order they happened; a caller remembers how many it has seen.
  const std::vector<RobotEvent>& robot_events() const { return robot_events_; }
  // True once robot i left the world: its bodies are frozen and its actuators let go.
  bool robot_stopped(std::size_t i) const { return vehicles_[i]->frozen(); }
  const std::optional<std::string>& physics_failure() const { return physics_failure_; }

 private:
  void run_scripts();
  void account_step();
  void watch_robots();
  void check_finite();
  std::optional<std::string> first_broken_body() const;
  [[noreturn]] void fail(const std::string& what);

  struct WatchedBody {
    dBodyID body;
    std::string owner;  // "robot 'rover'" or "obstacle 'parcel'"
    std::string part;   // "chassis", "wheel 'left'", "body"
  };

  // The world steps on a threading implementation of its own rather than ODE's process-wide
  // one: an ODE error thrown out of a step leaves that implementation's job list half full, and
  // it is then leaked rather than freed (freeing asserts), so no other world, and not ODE's
  // clean-up at exit, ever meets it.
  struct ThreadingRelease {
    dWorldID world;
    void operator()(dxThreadingImplementation* threading) const;
  };

  double step_s_;
  std::unique_ptr<PhysicsWorld> physics_;
  std::unique_ptr<dxThreadingImplementation, ThreadingRelease> threading_;
  std::vector<std::unique_ptr<Vehicle>> vehicles_;
  std::vector<std::size_t> script_cursor_;
  std::vector<RobotTally> tallies_;
  std::vector<Eigen::Vector2d> last_xy_;
  std::vector<Touch> touching_;  // at the end of the previous step
  std::vector<CollisionEvent> collisions_;
  std::vector<RobotEvent> robot_events_;
  std::vector<bool> upside_down_;         // an upside-down episode is under way
  std::vector<double> robot_reach_m_;     // farthest point of each robot from its chassis origin
  std::vector<VehicleState> last_good_;   // each robot's state after the last finite step
  std::vector<WatchedBody> watched_;
  std::vector<dBodyID> loose_obstacles_;  // movable obstacles, put to sleep once they fall out of the world
  double terrain_floor_m_ = 0;            // lowest point of the terrain
  // Height under (x, y), NaN off the terrain: arithmetic on a heightmap's samples (bilinear,
  // within a few mm of ODE's triangles, far inside the margins it is compared with), a ray on a mesh.
  double ground_under(double x, double y) const;
  TerrainDesc terrain_;  // heightmap samples only; a mesh is asked through the physics world
  std::optional<std::string> physics_failure_;
  std::int64_t step_ns_;
  std::int64_t time_ns_ = 0;
};

}  // namespace sear
