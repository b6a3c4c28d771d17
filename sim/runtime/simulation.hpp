// One run of a project: the physics world, its robots, their scripted commands, and the running
// tallies a summary reports (distance driven, collisions), advanced one fixed step at a time.
#pragma once

#include <cstdint>
#include <memory>
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

class Simulation {
 public:
  // Throws PlacementError naming every robot and obstacle with no terrain under it.
  Simulation(const ProjectDesc& project, std::uint64_t seed);

  void step();
  std::int64_t time_ns() const { return time_ns_; }
  std::int64_t step_ns() const { return step_ns_; }
  double time_s() const { return static_cast<double>(time_ns_) * 1e-9; }

  std::size_t robot_count() const { return vehicles_.size(); }
  Vehicle& robot(std::size_t i) { return *vehicles_[i]; }
  const Vehicle& robot(std::size_t i) const { return *vehicles_[i]; }
  const RobotTally& tally(std::size_t i) const { return tallies_[i]; }
  const std::vector<CollisionEvent>& collisions() const { return collisions_; }
  const PhysicsWorld& physics() const { return *physics_; }

 private:
  void run_scripts();
  void account_step();

  double step_s_;
  std::unique_ptr<PhysicsWorld> physics_;
  std::vector<std::unique_ptr<Vehicle>> vehicles_;
  std::vector<std::size_t> script_cursor_;
  std::vector<RobotTally> tallies_;
  std::vector<Eigen::Vector2d> last_xy_;
  std::vector<Touch> touching_;  // at the end of the previous step
  std::vector<CollisionEvent> collisions_;
  std::int64_t step_ns_;
  std::int64_t time_ns_ = 0;
};

}  // namespace sear
