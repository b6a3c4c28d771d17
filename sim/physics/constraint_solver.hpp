// Steps an ODE world with the solver its <world> asks for. The direct solver (dWorldStep) solves
// each group of touching bodies' constraint rows exactly, but its cost grows with the cube of a
// group's rows and its pivoting gives up on some degenerate sets; so a step whose largest group
// is large, or in which the exact solve gave up, is taken by the iterative solver instead.
#pragma once

#include <ode/ode.h>

#include <cstdint>
#include <unordered_set>
#include <vector>

namespace sear {

class ConstraintSolver {
 public:
  // Estimated rows (three a contact point, six any other joint: each at most what it holds)
  // above which a group goes to the iterative solver. bench/physics_bench's piles: a rover's
  // group, about 40, costs the direct solver three quarters of 20 sweeps; 4 crates in contact,
  // about 90, three times as much.
  static constexpr int kDirectRowsAtMost = 64;

  explicit ConstraintSolver(bool direct);

  // One step of `h` seconds; `moving` is the space of every geom with a body (what the world's
  // bodies are found from: a body without one is reached through its joints).
  void step(dWorldID world, dSpaceID moving, double h);

  // Steps taken by each solver, and those the direct one gave up on and the iterative one took
  // again from the same state, over the world's life.
  struct Counts {
    std::uint64_t direct = 0, iterative = 0, retaken = 0;
  };
  const Counts& counts() const { return counts_; }

 private:
  // The rows of the largest group of bodies that move together this step; gathers bodies_.
  int largest_group_rows(dSpaceID moving);
  struct Saved {
    dBodyID body;
    dReal pos[3], quat[4], vel[3], spin[3], force[3], torque[3];
    bool enabled;
  };

  bool direct_;
  Counts counts_;
  std::vector<dBodyID> bodies_;  // in the step, in the order found
  std::unordered_set<dBodyID> seen_;
  std::vector<dBodyID> stack_;
  std::vector<Saved> saved_;
};

}  // namespace sear
