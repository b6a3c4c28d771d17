#include "runtime/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "physics/scenery.hpp"

namespace sear {
namespace {

// Beyond these a body is broken rather than fast or far: no terrain a robot drives on spans
// 1000 km, nothing in a robot's world moves at 100 km/s, and a wheel's spin is capped by the
// vehicle at ten times its fastest motor (20 000 rpm motors: 2e4 rad/s), far under 1e6 rad/s.
constexpr double kAbsurdDistance_m = 1e6;
constexpr double kAbsurdSpeed_mps = 1e5;
constexpr double kAbsurdSpin_radps = 1e6;

// Tilt of the chassis' up axis from world up: past 100 degrees it rests on its back or side
// beyond recovery on its own; it must come back under 80 degrees before a new episode counts,
// so a robot rocking on its side is reported once.
const double kUpsideDownCos = std::cos(100.0 * kDegToRad);
const double kUprightAgainCos = std::cos(80.0 * kDegToRad);

// An ODE internal error or failed assertion, thrown out of ODE's handler so the run can stop
// with a report instead of ODE's abort().
struct OdeFault : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void throw_ode_fault(const char* what, int number, const char* message, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, message, args);
  throw OdeFault(fmt::format("ODE {} {}: {}", what, number, text));
}
void ode_error(int number, const char* message, va_list args) { throw_ode_fault("error", number, message, args); }
void ode_debug(int number, const char* message, va_list args) {
  throw_ode_fault("internal error", number, message, args);
}

// ODE's handlers are process-wide and, once set, the same for every simulation.
void install_ode_handlers() {
  static const bool installed = [] {
    dSetErrorHandler(ode_error);
    dSetDebugHandler(ode_debug);
    return true;
  }();
  (void)installed;
}

Eigen::Vector3d vec(const dReal* v) { return {v[0], v[1], v[2]}; }

bool finite(const Eigen::Vector3d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

// Farthest point of the robot from its chassis origin: if that origin is deeper than this under
// the terrain's surface, no part of the robot is at or above it.
double reach_of(const RobotDesc& r) {
  double reach = 0.5 * r.chassis.size_m.norm();
  for (const auto& w : r.wheels) reach = std::max(reach, w.position_m.norm() + w.radius_m);
  for (const auto& c : r.casters) reach = std::max(reach, c.position_m.norm() + c.radius_m);
  return reach;
}

double terrain_floor(const TerrainDesc& t) {
  switch (t.kind) {
    case TerrainKind::Flat: return 0.0;
    case TerrainKind::Heightmap: return *std::min_element(t.heights_m.begin(), t.heights_m.end());
    case TerrainKind::Mesh: {
      double lowest = std::numeric_limits<double>::infinity();
      for (const auto& v : t.mesh.vertices) lowest = std::min(lowest, static_cast<double>(v.z()));
      return lowest;
    }
  }
  return 0.0;
}

}  // namespace

// A threading implementation an ODE fault left half used is never freed (freeing it asserts), but
// kept reachable here for the life of the process, so that a leak checker does not report what
// is abandoned on purpose.
static void abandon(dxThreadingImplementation* threading) {
  static auto* const abandoned = new std::vector<dxThreadingImplementation*>();
  abandoned->push_back(threading);
}

void Simulation::ThreadingRelease::operator()(dxThreadingImplementation* threading) const {
  dWorldSetStepThreadingImplementation(world, nullptr, nullptr);
  dThreadingFreeImplementation(threading);
}

const char* to_string(RobotEventKind kind) {
  switch (kind) {
    case RobotEventKind::LeftTerrain: return "left the terrain";
    case RobotEventKind::FellBelow: return "fell below the terrain";
    case RobotEventKind::UpsideDown: return "upside down";
  }
  return "?";
}

Simulation::Simulation(const ProjectDesc& project, std::uint64_t seed)
    : step_s_(project.world.step_s),
      physics_(std::make_unique<PhysicsWorld>(project.world, seed)),
      step_ns_(std::llround(project.world.step_s * 1e9)) {
  install_ode_handlers();
  threading_ = {dThreadingAllocateSelfThreadedImplementation(), ThreadingRelease{physics_->world()}};
  dWorldSetStepThreadingImplementation(physics_->world(), dThreadingImplementationGetFunctions(threading_.get()),
                                       threading_.get());
  build_terrain(*physics_, project.world.terrain);
  terrain_floor_m_ = terrain_floor(project.world.terrain);
  terrain_.kind = project.world.terrain.kind;
  if (terrain_.kind == TerrainKind::Heightmap) terrain_ = project.world.terrain;
  // Placement is known only once the terrain exists: gather every problem, as the loader does.
  std::vector<std::string> problems = build_obstacles(*physics_, project.world, project.file);
  for (int g = 0; g < dSpaceGetNumGeoms(physics_->dynamic_space()); ++g) {
    dGeomID geom = dSpaceGetGeom(physics_->dynamic_space(), g);
    dBodyID body = dGeomGetBody(geom);
    if (!body) continue;
    const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
    const std::string name = tag ? physics_->entity_names()[static_cast<std::size_t>(tag->entity)] : "?";
    loose_obstacles_.push_back(body);
    watched_.push_back({body, "obstacle '" + name + "'", "body"});
  }
  for (const auto& robot : project.robots) {
    try {
      vehicles_.push_back(std::make_unique<Vehicle>(*physics_, robot));
    } catch (const PlacementError& e) {
      problems.push_back(e.what());
      continue;
    }
    const Vehicle& v = *vehicles_.back();
    const auto p = v.state().position_m;
    last_xy_.emplace_back(p.x(), p.y());
    robot_reach_m_.push_back(reach_of(robot));
    const std::string owner = "robot '" + robot.name + "'";
    watched_.push_back({v.chassis_body(), owner, "chassis"});
    for (std::size_t w = 0; w < v.wheel_count(); ++w)
      watched_.push_back({v.wheel_body(w), owner, "wheel '" + robot.wheels[w].name + "'"});
    for (std::size_t j = 0; j < v.joint_count(); ++j)
      watched_.push_back({v.joint(j).body(), owner, "link '" + robot.joints[j].link + "'"});
  }
  if (!problems.empty()) {
    std::string all;
    for (const auto& p : problems) all += (all.empty() ? "" : "\n") + p;
    throw PlacementError(all);
  }
  script_cursor_.assign(vehicles_.size(), 0);
  tallies_.assign(vehicles_.size(), RobotTally{});
  upside_down_.assign(vehicles_.size(), false);
  for (const auto& v : vehicles_) last_good_.push_back(v->state());
}

double Simulation::ground_under(double x, double y) const {
  switch (terrain_.kind) {
    case TerrainKind::Flat: return 0.0;
    case TerrainKind::Mesh: return physics_->terrain_height(x, y, std::nan(""));
    case TerrainKind::Heightmap: break;
  }
  const double u = (x + 0.5 * terrain_.size_m.x()) / terrain_.size_m.x() * (terrain_.columns - 1);
  const double v = (0.5 * terrain_.size_m.y() - y) / terrain_.size_m.y() * (terrain_.rows - 1);  // row 0 north
  if (!(u >= 0 && v >= 0 && u <= terrain_.columns - 1 && v <= terrain_.rows - 1)) return std::nan("");
  const int c = std::min(static_cast<int>(u), terrain_.columns - 2);
  const int r = std::min(static_cast<int>(v), terrain_.rows - 2);
  const double fu = u - c, fv = v - r;
  const auto h = [&](int row, int col) {
    return terrain_.heights_m[static_cast<std::size_t>(row) * static_cast<std::size_t>(terrain_.columns) +
                              static_cast<std::size_t>(col)];
  };
  return (1 - fv) * ((1 - fu) * h(r, c) + fu * h(r, c + 1)) + fv * ((1 - fu) * h(r + 1, c) + fu * h(r + 1, c + 1));
}

VehicleState Simulation::robot_state(std::size_t i) const {
  return physics_failure_ ? last_good_[i] : vehicles_[i]->state();
}

void Simulation::run_scripts() {
  for (std::size_t r = 0; r < vehicles_.size(); ++r) {
    Vehicle& v = *vehicles_[r];
    const auto& script = v.desc().script;
    std::size_t& cursor = script_cursor_[r];
    // Commands are due when their time is reached: compared in integer nanoseconds so that a
    // command at t = 0.3 s applies at the 300th step whatever the rounding of 0.3.
    while (cursor < script.size() && std::llround(script[cursor].t_s * 1e9) <= time_ns_) {
      const ScriptCommand& cmd = script[cursor++];
      if (cmd.is_servo) v.command_servo(static_cast<std::size_t>(v.servo_index(cmd.actuator)), cmd.pulse_us);
      else v.command_motor(static_cast<std::size_t>(v.motor_index(cmd.actuator)), {cmd.duty, cmd.direction});
    }
  }
}

void Simulation::account_step() {
  for (std::size_t r = 0; r < vehicles_.size(); ++r) {
    const auto& p = last_good_[r].position_m;
    const Eigen::Vector2d xy(p.x(), p.y());
    tallies_[r].distance_m += (xy - last_xy_[r]).norm();
    last_xy_[r] = xy;
  }
  const auto& now = physics_->touches();
  const auto& names = physics_->entity_names();
  for (const Touch& t : now) {
    if (std::find(touching_.begin(), touching_.end(), t) != touching_.end()) continue;
    for (std::size_t r = 0; r < vehicles_.size(); ++r) {
      if (vehicles_[r]->entity() != t.robot_entity) continue;
      ++tallies_[r].collisions;
      collisions_.push_back({time_ns_, names[static_cast<std::size_t>(t.robot_entity)],
                             names[static_cast<std::size_t>(t.other_entity)]});
    }
  }
  touching_ = now;
}

void Simulation::fail(const std::string& what) {
  physics_failure_ = fmt::format("physics failed at sim time {:.6f} s: {}", time_s(), what);
  throw PhysicsError(*physics_failure_);
}

std::optional<std::string> Simulation::first_broken_body() const {
  for (const WatchedBody& b : watched_) {
    const Eigen::Vector3d p = vec(dBodyGetPosition(b.body));
    const Eigen::Vector3d v = vec(dBodyGetLinearVel(b.body));
    const Eigen::Vector3d w = vec(dBodyGetAngularVel(b.body));
    const char* problem = nullptr;
    if (!finite(p) || !finite(v) || !finite(w)) problem = "a non-finite state";
    else if (p.norm() > kAbsurdDistance_m) problem = "flown beyond 1000 km";
    else if (v.norm() > kAbsurdSpeed_mps) problem = "a speed beyond 100 km/s";
    else if (w.norm() > kAbsurdSpin_radps) problem = "a spin beyond 1e6 rad/s";
    if (problem)
      return fmt::format("{} {} has {}: position ({:.6g}, {:.6g}, {:.6g}) m, velocity ({:.6g}, {:.6g}, {:.6g}) m/s, "
                         "angular velocity ({:.6g}, {:.6g}, {:.6g}) rad/s",
                         b.owner, b.part, problem, p.x(), p.y(), p.z(), v.x(), v.y(), v.z(), w.x(), w.y(), w.z());
  }
  return std::nullopt;
}

void Simulation::check_finite() {
  if (const auto broken = first_broken_body()) fail(*broken);
  for (std::size_t r = 0; r < vehicles_.size(); ++r) last_good_[r] = vehicles_[r]->state();
}

void Simulation::watch_robots() {
  for (std::size_t r = 0; r < vehicles_.size(); ++r) {
    Vehicle& v = *vehicles_[r];
    if (v.frozen()) continue;
    const VehicleState& s = last_good_[r];
    const Eigen::Vector3d& p = s.position_m;
    const auto report = [&](RobotEventKind kind, bool stops) {
      robot_events_.push_back({time_ns_, r, v.desc().name, kind, p, stops});
      if (stops) v.freeze();
    };
    const dReal* rot = dBodyGetRotation(v.chassis_body());
    const double up_z = rot[10];  // world z of the chassis' z axis
    if (!upside_down_[r] && up_z < kUpsideDownCos) {
      upside_down_[r] = true;
      report(RobotEventKind::UpsideDown, false);
    } else if (upside_down_[r] && up_z > kUprightAgainCos) {
      upside_down_[r] = false;
    }
    const double ground = ground_under(p.x(), p.y());
    if (std::isnan(ground)) report(RobotEventKind::LeftTerrain, true);
    else if (p.z() < ground - robot_reach_m_[r]) report(RobotEventKind::FellBelow, true);
  }
  // A movable obstacle wholly below the lowest point of the terrain can never come back: it is
  // put to sleep rather than left to fall until its numbers are absurd.
  for (dBodyID b : loose_obstacles_) {
    if (!dBodyIsEnabled(b)) continue;
    dReal aabb[6];
    dGeomGetAABB(dBodyGetFirstGeom(b), aabb);
    if (aabb[5] >= terrain_floor_m_) continue;
    dBodySetLinearVel(b, 0, 0, 0);
    dBodySetAngularVel(b, 0, 0, 0);
    dBodyDisable(b);
    dGeomDisable(dBodyGetFirstGeom(b));
  }
}

void Simulation::step() {
  if (physics_failure_) throw PhysicsError(*physics_failure_);
  try {
    run_scripts();
    for (auto& v : vehicles_) v->apply_actuators(step_s_);
    physics_->step();
  } catch (const OdeFault& e) {
    // ODE gave up part-way through the step: name what it found and, if a body is already
    // broken, which one, since ODE's own message names none.
    time_ns_ += step_ns_;
    abandon(threading_.release());
    const auto broken = first_broken_body();
    fail(broken ? std::string(e.what()) + "; " + *broken : std::string(e.what()));
  }
  time_ns_ += step_ns_;
  check_finite();
  account_step();
  watch_robots();
}

}  // namespace sear
