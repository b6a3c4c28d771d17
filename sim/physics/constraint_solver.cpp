#include "physics/constraint_solver.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

#include "physics/physics_world.hpp"

namespace sear {
namespace {

// ODE's Dantzig solver reports a pivot it cannot take (d_ERR_LCP, "s <= 0") as a message and
// leaves the rows it had not reached without force for the step; it is told here, not printed.
constexpr int kLcpMessage = 3;  // d_ERR_LCP in ODE's error.h
thread_local bool lcp_gave_up = false;

void ode_message(int number, const char* message, va_list args) {
  if (number == kLcpMessage) {
    lcp_gave_up = true;
    return;
  }
  // Any other message as ODE's own handler prints it.
  std::fprintf(stderr, "\nODE Message %d: ", number);
  std::vfprintf(stderr, message, args);
  std::fprintf(stderr, "\n");
}

void install_message_handler() {
  static const bool installed = [] {
    dSetMessageHandler(ode_message);
    return true;
  }();
  (void)installed;
}

}  // namespace

ConstraintSolver::ConstraintSolver(bool direct) : direct_(direct) { install_message_handler(); }

int ConstraintSolver::largest_group_rows(dSpaceID moving) {
  bodies_.clear();
  seen_.clear();
  int largest = 0;
  for_each_geom(moving, [&](dGeomID geom) {
    dBodyID seed = dGeomGetBody(geom);
    // Asleep with nothing joined to it: ODE leaves it out of the step.
    if (!seed || (!dBodyIsEnabled(seed) && dBodyGetNumJoints(seed) == 0)) return;
    if (!seen_.insert(seed).second) return;
    int twice_rows = 0;  // a joint between two bodies is met from each
    bodies_.push_back(seed);
    stack_.assign(1, seed);
    while (!stack_.empty()) {
      dBodyID body = stack_.back();
      stack_.pop_back();
      for (int i = 0, n = dBodyGetNumJoints(body); i < n; ++i) {
        dJointID joint = dBodyGetJoint(body, i);
        if (!dJointIsEnabled(joint)) continue;
        const int rows = dJointGetType(joint) == dJointTypeContact ? 3 : 6;
        dBodyID other = dJointGetBody(joint, 0) == body ? dJointGetBody(joint, 1) : dJointGetBody(joint, 0);
        twice_rows += other ? rows : 2 * rows;
        if (other && seen_.insert(other).second) {
          bodies_.push_back(other);
          stack_.push_back(other);
        }
      }
    }
    largest = std::max(largest, twice_rows / 2);
  });
  return largest;
}

void ConstraintSolver::step(dWorldID world, dSpaceID moving, double h) {
  if (!direct_ || largest_group_rows(moving) > kDirectRowsAtMost) {
    ++counts_.iterative;
    dWorldQuickStep(world, h);
    return;
  }
  // What the step changes of each body it moves, to take it again if the direct solver gives up.
  saved_.resize(bodies_.size());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Saved& s = saved_[i];
    s.body = bodies_[i];
    std::copy_n(dBodyGetPosition(s.body), 3, s.pos);
    std::copy_n(dBodyGetQuaternion(s.body), 4, s.quat);
    std::copy_n(dBodyGetLinearVel(s.body), 3, s.vel);
    std::copy_n(dBodyGetAngularVel(s.body), 3, s.spin);
    std::copy_n(dBodyGetForce(s.body), 3, s.force);
    std::copy_n(dBodyGetTorque(s.body), 3, s.torque);
    s.enabled = dBodyIsEnabled(s.body) != 0;
  }
  lcp_gave_up = false;
  dWorldStep(world, h);
  if (!lcp_gave_up) {
    ++counts_.direct;
    return;
  }
  for (const Saved& s : saved_) {
    dBodySetPosition(s.body, s.pos[0], s.pos[1], s.pos[2]);
    dBodySetQuaternion(s.body, s.quat);
    dBodySetLinearVel(s.body, s.vel[0], s.vel[1], s.vel[2]);
    dBodySetAngularVel(s.body, s.spin[0], s.spin[1], s.spin[2]);
    dBodySetForce(s.body, s.force[0], s.force[1], s.force[2]);
    dBodySetTorque(s.body, s.torque[0], s.torque[1], s.torque[2]);
    if (s.enabled) dBodyEnable(s.body);
    else dBodyDisable(s.body);
  }
  ++counts_.retaken;
  ++counts_.iterative;
  dWorldQuickStep(world, h);
}

}  // namespace sear
