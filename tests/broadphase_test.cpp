// Broadphase: the pairs ODE's own space collisions (dSpaceCollide on the moving geoms, then
// dSpaceCollide2 against the scenery) hand on, the same and in the same order, step after step,
// as bodies move and ODE reorders its lists; the order is the solver's row order.
#include <gtest/gtest.h>

#include <ode/ode.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "physics/broadphase.hpp"

namespace sear {
namespace {

using Pairs = std::vector<std::pair<dGeomID, dGeomID>>;

void record(void* data, dGeomID a, dGeomID b) { static_cast<Pairs*>(data)->emplace_back(a, b); }

struct Ode {
  Ode() { dInitODE2(0); }
  ~Ode() { dCloseODE(); }
};

class World {
 public:
  explicit World(unsigned seed) : random_(seed) {
    world_ = dWorldCreate();
    static_ = dHashSpaceCreate(nullptr);
    dynamic_ = dSimpleSpaceCreate(nullptr);
  }
  ~World() {
    dSpaceDestroy(dynamic_);
    dSpaceDestroy(static_);
    dWorldDestroy(world_);
  }

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(random_); }

  // Scenery of every kind the loader makes: a ground plane (unbounded), boxes, tree trunks and
  // crowns, walls tens of metres long, and one box wider than the grid takes.
  void scenery(int boxes) {
    dCreatePlane(static_, 0, 0, 1, 0);
    for (int i = 0; i < boxes; ++i) {
      dGeomID g;
      switch (i % 3) {
        case 0: g = dCreateBox(static_, uniform(0.1, 1.5), uniform(0.1, 1.5), uniform(0.1, 1)); break;
        case 1: g = dCreateCylinder(static_, uniform(0.05, 0.3), uniform(0.5, 3)); break;
        default: g = dCreateSphere(static_, uniform(0.2, 1.2)); break;
      }
      dGeomSetPosition(g, uniform(-6, 6), uniform(-6, 6), uniform(0, 1));
    }
    dGeomSetPosition(dCreateBox(static_, 30, 0.15, 0.6), 0, 6.5, 0.3);
    dGeomSetPosition(dCreateBox(static_, 0.15, 30, 0.6), -6.5, 0, 0.3);
    dGeomSetPosition(dCreateBox(static_, 40, 40, 0.05), 0, 0, -0.5);
  }

  // Bodies of one to three geoms (a robot's parts share a body, which ODE never pairs).
  void movers(int bodies) {
    for (int i = 0; i < bodies; ++i) {
      dBodyID b = dBodyCreate(world_);
      for (int k = 0; k <= i % 3; ++k) {
        dGeomID g = k == 1 ? dCreateSphere(dynamic_, uniform(0.05, 0.3))
                           : dCreateBox(dynamic_, uniform(0.1, 0.5), uniform(0.1, 0.5), uniform(0.1, 0.3));
        dGeomSetBody(g, b);
        if (k == 2) dGeomSetOffsetPosition(g, uniform(-0.3, 0.3), uniform(-0.3, 0.3), 0);
      }
      bodies_.push_back(b);
    }
  }

  // Moves about half the bodies, so that ODE puts their geoms at the front of its list.
  void shuffle(double spread) {
    for (dBodyID b : bodies_) {
      if (uniform(0, 1) < 0.5) continue;
      dBodySetPosition(b, uniform(-spread, spread), uniform(-spread, spread), uniform(-0.2, 1.5));
      dMatrix3 r;
      dRFromEulerAngles(r, uniform(-3, 3), uniform(-3, 3), uniform(-3, 3));
      dBodySetRotation(b, r);
    }
  }

  Pairs ode_pairs() {
    Pairs p;
    dSpaceCollide(dynamic_, &p, record);
    dSpaceCollide2(reinterpret_cast<dGeomID>(dynamic_), reinterpret_cast<dGeomID>(static_), &p, record);
    return p;
  }

  dSpaceID static_space() const { return static_; }
  dSpaceID dynamic_space() const { return dynamic_; }
  const std::vector<dBodyID>& bodies() const { return bodies_; }

 private:
  std::mt19937 random_;
  dWorldID world_;
  dSpaceID static_, dynamic_;
  std::vector<dBodyID> bodies_;
};

std::size_t pairs_between(const Pairs& pairs, dSpaceID a, dSpaceID b) {
  std::size_t n = 0;
  for (const auto& [g1, g2] : pairs) n += dGeomGetSpace(g1) == a && dGeomGetSpace(g2) == b;
  return n;
}

// Steps of random motion among scenery over a 12 m square, the bodies within `spread` of its
// centre; every step's pairs equal ODE's. With fewer moving geoms than scenery ODE walks the
// moving ones, with more the scenery: both are run.
void expect_ode_order(int boxes, int bodies, double spread, unsigned seed) {
  static Ode ode;
  World w(seed);
  w.scenery(boxes);
  w.movers(bodies);
  Broadphase broadphase(w.static_space(), w.dynamic_space());
  std::size_t moving_pairs = 0, scenery_pairs = 0;
  for (int step = 0; step < 40; ++step) {
    w.shuffle(spread);
    const Pairs expected = w.ode_pairs();
    Pairs got;
    broadphase.collide(&got, record);
    ASSERT_EQ(got, expected) << "step " << step;
    moving_pairs += pairs_between(expected, w.dynamic_space(), w.dynamic_space());
    scenery_pairs += pairs_between(expected, w.dynamic_space(), w.static_space());
  }
  // Crowded enough that both kinds of pair occur many times: the order is really tested.
  std::printf("%zu pairs of moving geoms, %zu with scenery\n", moving_pairs, scenery_pairs);
  EXPECT_GT(moving_pairs, 40u);
  EXPECT_GT(scenery_pairs, 200u);
}

TEST(Broadphase, FewMoversAmongMuchScenery) { expect_ode_order(60, 8, 1.5, 1); }

TEST(Broadphase, MoreMoversThanScenery) { expect_ode_order(6, 40, 6.5, 2); }

// Scenery enough for the grid, and more moving geoms still: the pairs are gathered, then ordered.
TEST(Broadphase, MoreMoversThanGriddedScenery) { expect_ode_order(24, 20, 6.5, 5); }

TEST(Broadphase, DisabledAndZeroSizedGeomsAsOdeSkipsThem) {
  static Ode ode;
  for (const int boxes : {40, 3}) {  // both walks: a disabled geom is skipped on one side only
    World w(3);
    w.scenery(boxes);
    w.movers(12);
    dGeomDisable(dBodyGetFirstGeom(w.bodies()[1]));
    dGeomDisable(dBodyGetFirstGeom(w.bodies()[4]));
    dGeomSetPosition(dCreateBox(w.static_space(), 0, 1, 1), 0, 0, 0.5);  // zero width: ODE ignores it
    dGeomSetBody(dCreateSphere(w.dynamic_space(), 0), w.bodies()[2]);
    Broadphase broadphase(w.static_space(), w.dynamic_space());
    for (int step = 0; step < 20; ++step) {
      w.shuffle(3);
      const Pairs expected = w.ode_pairs();
      Pairs got;
      broadphase.collide(&got, record);
      ASSERT_EQ(got, expected) << boxes << " boxes, step " << step;
    }
  }
}

// Boxes that only touch (a row of crates placed side by side, a crate against a wall) meet for
// ODE; here their faces lie on the grid's cell edges too.
TEST(Broadphase, BoxesThatOnlyTouchMeet) {
  static Ode ode;
  World w(6);
  for (int i = 0; i < 30; ++i) dGeomSetPosition(dCreateBox(w.static_space(), 1, 1, 1), i % 6 + 0.5, i / 6 * 2 + 0.5, 0.5);
  w.movers(0);
  dWorldID world = dWorldCreate();
  for (int i = 0; i < 24; ++i) {
    dBodyID b = dBodyCreate(world);
    dGeomSetBody(dCreateBox(w.dynamic_space(), 1, 1, 1), b);
    dBodySetPosition(b, i % 6 + 0.5, i / 6 * 2 + 1.5, 0.5);  // rows between the scenery's, touching it
  }
  Broadphase broadphase(w.static_space(), w.dynamic_space());
  const Pairs expected = w.ode_pairs();
  Pairs got;
  broadphase.collide(&got, record);
  // Each row of 6 holds 5 touching pairs. Each moving box touches, in each scenery row beside
  // its own, the box over against it and those diagonal to it, corners meeting: 2 + 4 * 3 + 2 = 16
  // a row, twice for each of the 4 moving rows.
  EXPECT_EQ(pairs_between(expected, w.dynamic_space(), w.dynamic_space()), 4u * 5u);
  EXPECT_EQ(pairs_between(expected, w.dynamic_space(), w.static_space()), 4u * 2u * 16u);
  EXPECT_EQ(got, expected);
  dWorldDestroy(world);
}

// A body flung kilometres away or to NaN (a blown-up simulation, before the run reports it)
// is still paired as ODE pairs it; scenery added after the first step is found.
TEST(Broadphase, FarAwayNaNAndLateScenery) {
  static Ode ode;
  World w(4);
  w.scenery(30);
  w.movers(10);
  Broadphase broadphase(w.static_space(), w.dynamic_space());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int step = 0; step < 12; ++step) {
    w.shuffle(6);
    if (step == 3) dBodySetPosition(w.bodies()[0], 5e9, 0, 0);
    if (step == 5) dBodySetPosition(w.bodies()[3], nan, 1, 0.5);
    if (step == 7) dGeomSetPosition(dCreateBox(w.static_space(), 2, 2, 2), 1, 1, 0.5);
    const Pairs expected = w.ode_pairs();
    Pairs got;
    broadphase.collide(&got, record);
    ASSERT_EQ(got, expected) << "step " << step;
  }
}

}  // namespace
}  // namespace sear
