#include "physics/physics_world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sear {
namespace {

// ODE keeps global state (collider tables, its random generator): initialise it once per process.
struct OdeLibrary {
  OdeLibrary() { dInitODE2(0); }
  ~OdeLibrary() { dCloseODE(); }
};

void ensure_ode() { static OdeLibrary library; }

constexpr int kMaxContacts = 8;  // per geom pair; a wheel on a heightfield or mesh may need several

// Contacts are slightly soft: stiff enough that a 2 kg rover sinks well under a millimetre,
// soft enough that the iterative solver converges in its fixed iteration count.
constexpr double kContactErp = 0.4;
constexpr double kContactCfm = 1e-5;

// A loose obstacle (a box with a mass) that has rested this long sleeps: ODE leaves it out of the
// solver and collide_pair() out of collision detection until a contact with something awake, a
// robot or another obstacle that moves, wakes it. At rest on the terrain it would otherwise cost
// every step what the rover does (its contact rows in the solver, its box against the heightfield).
// Resting means slower than ODE's default thresholds, 1 cm/s and 0.01 rad/s (a millimetre, or a
// milliradian, in the 0.1 s the test lasts), averaged over kRestSamples steps so that a box rocking
// through a turning point does not look still; and for kRestTime_s, long against the time a box
// dropped onto uneven ground takes to settle, short against a run. A sleeping box's velocity is
// set to zero, so it stays where it settled, within what it crept in that time. Robots never
// sleep: a firmware may start their motors at any moment, which wakes nothing in ODE.
constexpr double kRestSpeed_mps = 0.01;
constexpr double kRestSpin_radps = 0.01;
constexpr int kRestSamples = 10;
constexpr double kRestTime_s = 0.1;

bool awake(dBodyID body) { return body && dBodyIsEnabled(body); }

}  // namespace

PhysicsWorld::PhysicsWorld(const WorldDesc& desc, std::uint64_t seed)
    : materials_(desc.materials), step_s_(desc.step_s), solver_(desc.solver == WorldDesc::Solver::Direct) {
  ensure_ode();
  // The iterative solver shuffles its constraints with ODE's own generator: seeding it makes runs
  // repeat. The direct one draws nothing.
  dRandSetSeed(static_cast<unsigned long>(seed));
  world_ = dWorldCreate();
  dWorldSetGravity(world_, desc.gravity.x(), desc.gravity.y(), desc.gravity.z());
  dWorldSetERP(world_, 0.2);
  dWorldSetCFM(world_, 1e-6);
  dWorldSetQuickStepNumIterations(world_, desc.solver_iterations);
  dWorldSetContactSurfaceLayer(world_, 0.0005);
  dWorldSetContactMaxCorrectingVel(world_, 1.0);
  static_space_ = dHashSpaceCreate(nullptr);
  dynamic_space_ = dSimpleSpaceCreate(nullptr);
  broadphase_ = std::make_unique<Broadphase>(static_space_, dynamic_space_);
  contacts_ = dJointGroupCreate(0);
}

PhysicsWorld::~PhysicsWorld() {
  ray_scene_.reset();  // it refers to the geoms destroyed below
  dJointGroupDestroy(contacts_);
  dSpaceDestroy(dynamic_space_);
  dSpaceDestroy(static_space_);
  dWorldDestroy(world_);
  for (dTriMeshDataID data : mesh_data_) dGeomTriMeshDataDestroy(data);
  for (dHeightfieldDataID data : heightfield_data_) dGeomHeightfieldDataDestroy(data);
}

void PhysicsWorld::set_terrain_samples(const TerrainDesc& terrain) {
  terrain_kind_ = terrain.kind;
  terrain_columns_ = terrain.columns;
  terrain_rows_ = terrain.rows;
  terrain_size_m_ = terrain.size_m;
  terrain_heights_m_ = terrain.kind == TerrainKind::Heightmap ? terrain.heights_m : std::vector<double>{};
}

double PhysicsWorld::terrain_ceiling(const double box[6]) const {
  switch (terrain_kind_) {
    case TerrainKind::Flat: return 0.0;
    case TerrainKind::Mesh: return std::numeric_limits<double>::infinity();
    case TerrainKind::Heightmap: break;
  }
  if (terrain_columns_ < 2 || terrain_rows_ < 2) return std::numeric_limits<double>::infinity();
  // Sample (c, r) lies at x = -size_x/2 + c dx, y = size_y/2 - r dy (row 0 the north edge, as
  // build_terrain lays it out); the cells the box touches span these index ranges.
  const double dx = terrain_size_m_.x() / (terrain_columns_ - 1), dy = terrain_size_m_.y() / (terrain_rows_ - 1);
  const auto index = [](double v, int last) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(last))); };
  const int c0 = index(std::floor((box[0] + 0.5 * terrain_size_m_.x()) / dx), terrain_columns_ - 1);
  const int c1 = index(std::ceil((box[1] + 0.5 * terrain_size_m_.x()) / dx), terrain_columns_ - 1);
  const int r0 = index(std::floor((0.5 * terrain_size_m_.y() - box[3]) / dy), terrain_rows_ - 1);
  const int r1 = index(std::ceil((0.5 * terrain_size_m_.y() - box[2]) / dy), terrain_rows_ - 1);
  double top = -std::numeric_limits<double>::infinity();
  for (int r = r0; r <= r1; ++r)
    for (int c = c0; c <= c1; ++c)
      top = std::max(top, terrain_heights_m_[static_cast<std::size_t>(r) * static_cast<std::size_t>(terrain_columns_) +
                                             static_cast<std::size_t>(c)]);
  return top;
}

dHeightfieldDataID PhysicsWorld::add_heightfield_data() {
  heightfield_data_.push_back(dGeomHeightfieldDataCreate());
  return heightfield_data_.back();
}

int PhysicsWorld::material_index(const std::string& name) const {
  for (std::size_t i = 0; i < materials_.size(); ++i)
    if (materials_[i].name == name) return static_cast<int>(i);
  throw std::logic_error("material '" + name + "' was not validated by the loader");
}

int PhysicsWorld::add_entity(const std::string& name) {
  entity_names_.push_back(name);
  return static_cast<int>(entity_names_.size() - 1);
}

void PhysicsWorld::tag(dGeomID geom, GeomRole role, int entity, int material) {
  tags_.push_back({role, entity, material});
  dGeomSetData(geom, &tags_.back());
  dBodyID body = dGeomGetBody(geom);
  if (role == GeomRole::Obstacle && body) {
    dBodySetAutoDisableFlag(body, 1);
    dBodySetAutoDisableLinearThreshold(body, kRestSpeed_mps);
    dBodySetAutoDisableAngularThreshold(body, kRestSpin_radps);
    dBodySetAutoDisableAverageSamplesCount(body, kRestSamples);
    dBodySetAutoDisableSteps(body, 1);  // the time below decides, whatever the step size
    dBodySetAutoDisableTime(body, kRestTime_s);
  }
}

dTriMeshDataID PhysicsWorld::add_mesh_data(const TriangleMesh& mesh) {
  meshes_.push_back(mesh);
  const TriangleMesh& kept = meshes_.back();
  dTriMeshDataID data = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildSingle(data, kept.vertices.data(), sizeof(Eigen::Vector3f),
                              static_cast<int>(kept.vertices.size()), kept.indices.data(),
                              static_cast<int>(kept.indices.size()), 3 * sizeof(std::uint32_t));
  mesh_data_.push_back(data);
  return data;
}

double PhysicsWorld::terrain_height(double x, double y, double fallback) const {
  if (!terrain_geom_) return fallback;
  constexpr double kTop = 1e4;
  dGeomID ray = dCreateRay(nullptr, 2 * kTop);
  dGeomRaySet(ray, x, y, kTop, 0, 0, -1);
  dGeomRaySetClosestHit(ray, 1);  // a mesh may have several faces above each other: take the top one
  dContactGeom hit;
  const int n = dCollide(ray, terrain_geom_, 1, &hit, sizeof(dContactGeom));
  dGeomDestroy(ray);
  return n > 0 ? hit.pos[2] : fallback;
}

bool PhysicsWorld::only_woken_or_asleep(dBodyID a, dBodyID b) const {
  const auto woken = [&](dBodyID body) { return std::find(woken_.begin(), woken_.end(), body) != woken_.end(); };
  // A pair with a body that was already awake was met in an earlier pass.
  const auto new_here = [&](dBodyID body) { return !awake(body) || woken(body); };
  return (woken(a) || woken(b)) && new_here(a) && new_here(b);
}

void PhysicsWorld::near_callback(void* self, dGeomID a, dGeomID b) {
  static_cast<PhysicsWorld*>(self)->collide_pair(a, b);
}

void PhysicsWorld::collide_pair(dGeomID a, dGeomID b) {
  const auto* ta = static_cast<const GeomTag*>(dGeomGetData(a));
  const auto* tb = static_cast<const GeomTag*>(dGeomGetData(b));
  if (!ta || !tb) return;
  if (ta->entity == tb->entity && ta->entity >= 0) return;  // a robot's own parts are held by its joints
  // The terrain meets a wheel's tread, everything else its tyre (see GeomRole).
  const auto wrong_half = [](const GeomTag* wheel, const GeomTag* other) {
    return (wheel->role == GeomRole::Wheel && other->role == GeomRole::Terrain) ||
           (wheel->role == GeomRole::Tread && other->role != GeomRole::Terrain);
  };
  if (wrong_half(ta, tb) || wrong_half(tb, ta)) return;
  dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
  // A sleeping obstacle against the scenery or another sleeper: ODE would not move either, and
  // its contacts would only cost time. Against something awake the contact is made, and ODE wakes
  // the sleeper when it gathers the bodies joined to the awake one; step() wakes it first, and meets
  // it again with what it sleeps against, so that it is pushed on the ground, not above it.
  if (!awake(ba) && !awake(bb)) return;
  if (rewaking_ && !only_woken_or_asleep(ba, bb)) return;
  if (ba && bb && dAreConnectedExcluding(ba, bb, dJointTypeContact)) return;

  dContactGeom geoms[kMaxContacts];
  const int n = dCollide(a, b, kMaxContacts, geoms, sizeof(dContactGeom));
  if (n == 0) return;

  const Material& ma = materials_[static_cast<std::size_t>(ta->material)];
  const Material& mb = materials_[static_cast<std::size_t>(tb->material)];
  const bool caster = ta->role == GeomRole::Caster || tb->role == GeomRole::Caster;
  dSurfaceParameters surface{};
  surface.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
  // The lower coefficient of the two materials, as Gazebo does: a slippery surface stays slippery.
  surface.mu = caster ? 0.0 : std::min(ma.friction, mb.friction);
  surface.soft_erp = kContactErp;
  surface.soft_cfm = kContactCfm;
  surface.bounce = std::max(ma.bounce, mb.bounce);
  if (surface.bounce > 0) {
    surface.mode |= dContactBounce;
    surface.bounce_vel = 0.1;
  }
  contact_count_ += static_cast<std::size_t>(n);
  for (dBodyID sleeper : {ba, bb})
    if (sleeper && !awake(sleeper) && std::find(waking_.begin(), waking_.end(), sleeper) == waking_.end())
      waking_.push_back(sleeper);
  for (int i = 0; i < n; ++i) {
    dContact contact{};
    contact.surface = surface;
    contact.geom = geoms[i];
    dJointID joint = dJointCreateContact(world_, contacts_, &contact);
    dJointAttach(joint, ba, bb);
  }

  const auto is_robot = [](const GeomTag* t) {
    return t->role == GeomRole::Chassis || t->role == GeomRole::Wheel || t->role == GeomRole::Caster ||
           t->role == GeomRole::Tread;
  };
  const auto note = [&](const GeomTag* robot, const GeomTag* other) {
    if (other->role == GeomRole::Terrain) return;
    const Touch touch{robot->entity, other->entity};
    if (std::find(touches_.begin(), touches_.end(), touch) == touches_.end()) touches_.push_back(touch);
  };
  if (is_robot(ta)) note(ta, tb);
  if (is_robot(tb)) note(tb, ta);
}

const std::vector<PhysicsWorld::GeomBox>* PhysicsWorld::moving_held_still() const {
  if (!holding_still_) return nullptr;
  if (!moving_listed_) {
    moving_.clear();
    for_each_geom(dynamic_space_, [&](dGeomID geom) {
      moving_.push_back({geom, {}});
      dGeomGetAABB(geom, moving_.back().aabb);  // brings a moved body's box up to date first
    });
    moving_listed_ = true;
  }
  return &moving_;
}

void PhysicsWorld::step() {
  touches_.clear();
  contact_count_ = 0;
  broadphase_->collide(this, &PhysicsWorld::near_callback);
  // Sleepers something awake touched: awake now, each met again with the scenery and the other
  // sleepers it lay against, and those it touches in turn (a pile wakes in one step).
  while (!waking_.empty()) {
    woken_.swap(waking_);
    waking_.clear();
    for (dBodyID body : woken_) dBodyEnable(body);
    rewaking_ = true;
    broadphase_->collide(this, &PhysicsWorld::near_callback);
    rewaking_ = false;
  }
  woken_.clear();
  solver_.step(world_, dynamic_space_, step_s_);
  dJointGroupEmpty(contacts_);
}

}  // namespace sear
