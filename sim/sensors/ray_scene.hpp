// The static scenery of one PhysicsWorld (terrain, fixed boxes and walls, trees, meshes) built once
// into an Embree 3 BVH, so that rays cost a tree walk instead of ODE's cell-by-cell heightfield
// test. Embree answers in float; a hit that decides a reading is re-asked of ODE's collider for the
// one geom it struck (the terrain's: its triangle's plane, in double, as ODE computes it), so that
// readings agree with ODE's to rounding. Bodies that move stay with ODE (sensors/range_sensor).
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <memory>
#include <unordered_map>
#include <vector>

#include "physics/box_grid.hpp"
#include "physics/physics_world.hpp"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace sear {

// Where one ray first meets a surface.
struct RayHit {
  bool hit = false;
  double distance_m = 0;              // along the (unit) ray; meaningless without a hit
  Eigen::Vector3d point_m{0, 0, 0};   // world frame
  Eigen::Vector3d normal_m{0, 0, 0};  // world frame, unit, turned to face the ray's origin
  int entity = -1;                    // PhysicsWorld::entity_names(); -1 the terrain
};

// Embree's answer for one ray: how far (float) and what it struck, to be refined.
struct BvhHit {
  float t = 0;  // INFINITY: nothing within the ray's reach
  unsigned item = 0;
  unsigned prim = 0;
};

// Agreement with ODE (tests/ray_scene_test.cpp): refined hits equal ODE's to 1e-9 m; Embree's
// raw float distances are within float_slack_m(). Where they can differ: a ray grazing an edge
// to within float rounding (Embree may pass where ODE hits, or the reverse), and a ray that
// starts under the terrain's surface, for which ODE's heightfield invents a contact that depends
// on the ray's length (sensors start above ground). Like ODE's geoms it is used from the thread
// that steps the world, one call at a time: refine() reuses one ODE ray.
class RayScene {
 public:
  // The scene of `physics`: built on first call and kept by the world (ray_scene_slot), so that
  // every sensor shares one and none keeps its own copy; built again when geoms have been added to
  // the static space since (static geoms are never moved: they would be bodies otherwise).
  static const RayScene& of(const PhysicsWorld& physics);

  explicit RayScene(const PhysicsWorld& physics);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Rays per Embree packet (rtcIntersect16).
  static constexpr std::size_t kPacket = 16;

  // Embree's nearest hit along each ray i, from origins[shared_origin ? 0 : i] along the unit
  // dirs[i], within [0, reach_m], skipping `ignore_entity`'s geoms; cast kPacket at a time.
  void cast(const Eigen::Vector3d* origins, bool shared_origin, const Eigen::Vector3d* dirs, std::size_t count,
            double reach_m, int ignore_entity, BvhHit* out) const;
  // The same for a planar fan: ray i leaves `origin` along cos_i * a + sin_i * b (a, b unit and
  // orthogonal); distances go to out_m[i], INFINITY where nothing lies within reach_m.
  void cast_fan(const Eigen::Vector3d& origin, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                const float* cos_table, const float* sin_table, std::size_t count, double reach_m, int ignore_entity,
                float* out_m) const;

  // ODE's answer for the geom `hit` struck, along the ray from `origin` along the unit `dir` cut at
  // limit_m: the heightfield's triangle planes about Embree's point met in double exactly as ODE's
  // heightfield collider meets them, any other geom through dCollide. Then every other static geom
  // whose box the last float_slack_m() before that point meets is asked the same way, so that
  // where two surfaces meet (a wall's foot in the ground) the nearer in double wins, as in ODE.
  // False when, so asked, the ray misses what Embree struck.
  bool refine(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double limit_m, const BvhHit& hit,
              int ignore_entity, RayHit& out) const;
  // The nearest static hit of one ray through ODE alone, every geom whose box the ray meets: the
  // reference, and the way out where Embree and ODE disagree on an edge.
  RayHit ode_nearest(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double limit_m,
                     int ignore_entity) const;
  // The exact nearest static hit of one ray: Embree's, refined, with ode_nearest() behind it.
  RayHit nearest(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double limit_m, int ignore_entity) const;

  // Whether no static geom can meet a ray that lies wholly inside `box` (ODE's order): every
  // geom's box, but the terrain's, lies more than `slack_m` clear of it, and it lies more than
  // that above `terrain_ceiling_m`, the highest the terrain reaches under it
  // (PhysicsWorld::terrain_ceiling). `ignore_entity`'s geoms do not count. Then casting is known
  // to find nothing, and is spared. `slack_m`: the rays' float_slack_m().
  bool clear_of(const double box[6], double terrain_ceiling_m, double slack_m, int ignore_entity) const;

  // The terrain as a sonar meets it: no surface of it (a heightmap's triangles, or its plane) is
  // tilted further from terrain_up() than its steepest triangle, so a ray whose line lies further
  // than that plus max_incidence_rad from terrain_up() strikes all of them too obliquely to echo:
  // |terrain_up() . dir| is then below grazing_cos(max_incidence_rad). That is -1 (no ray) where
  // the terrain is left to ODE, or the bound leaves no ray.
  const Eigen::Vector3d& terrain_up() const { return terrain_up_; }
  double grazing_cos(double max_incidence_rad) const;
  // The boxes of the static geoms other than the terrain that meet `box` (ODE's order), each grown
  // by the margin clear_of() keeps: all that a ray inside `box` can strike besides the terrain.
  void others_near(const double box[6], double slack_m, int ignore_entity, std::vector<std::array<double, 6>>& out) const;

  // Embree's float distance may differ from ODE's double one by this much at distance t_m from
  // an origin |o| from the world's origin (see ray_scene.cpp); readings refine every ray within
  // it of the nearest.
  static double float_slack_m(double t_m, double origin_norm_m);

  // Static geoms that are in no BVH (a kind the scene does not model): asked through ODE with
  // the moving bodies.
  const std::vector<dGeomID>& ode_only() const { return ode_only_; }
  std::size_t triangle_count() const { return triangles_; }
  int static_geom_count() const { return static_count_; }

  struct Item;  // one Embree geometry: the geom(s) it stands for

 private:
  std::shared_ptr<RTCDeviceTy> device_;
  RTCSceneTy* scene_ = nullptr;
  std::vector<std::unique_ptr<Item>> items_;  // by Embree geometry id
  std::vector<dGeomID> ode_only_;
  struct StaticGeom {
    dGeomID geom;
    int entity;
    double aabb[6];
    const Item* heightfield;  // the terrain's item, or nullptr
  };
  // The nearest hit on one static geom within [from_m, limit_m], exactly; false for none.
  bool exact(const StaticGeom& g, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double from_m,
             double limit_m, RayHit& out) const;
  std::vector<StaticGeom> all_;  // every tagged static geom, for ode_nearest()
  // all_ filed by where its boxes lie, and by geom: a world of many obstacles costs a ray what
  // the few near it do.
  BoxGrid grid_;
  std::unordered_map<dGeomID, std::uint32_t> index_of_;
  std::size_t triangles_ = 0;
  int static_count_ = 0;
  dGeomID ray_ = nullptr;  // a ray in no space, for refine() and ode_nearest()
  dGeomID terrain_ = nullptr;
  Eigen::Vector3d terrain_up_{0, 0, 1};
  double terrain_tilt_rad_ = -1;  // unknown: see grazing_cos()
};

}  // namespace sear
