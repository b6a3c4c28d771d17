#include "physics/physics_world.hpp"

#include <algorithm>
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
// soft enough that QuickStep converges in its fixed iteration count.
constexpr double kContactErp = 0.4;
constexpr double kContactCfm = 1e-5;

}  // namespace

PhysicsWorld::PhysicsWorld(const WorldDesc& desc, std::uint64_t seed)
    : materials_(desc.materials), step_s_(desc.step_s) {
  ensure_ode();
  // QuickStep shuffles its constraints with ODE's own generator: seeding it makes runs repeat.
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
  contacts_ = dJointGroupCreate(0);
}

PhysicsWorld::~PhysicsWorld() {
  dJointGroupDestroy(contacts_);
  dSpaceDestroy(dynamic_space_);
  dSpaceDestroy(static_space_);
  dWorldDestroy(world_);
  for (dTriMeshDataID data : mesh_data_) dGeomTriMeshDataDestroy(data);
  for (dHeightfieldDataID data : heightfield_data_) dGeomHeightfieldDataDestroy(data);
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

void PhysicsWorld::near_callback(void* self, dGeomID a, dGeomID b) {
  static_cast<PhysicsWorld*>(self)->collide_pair(a, b);
}

void PhysicsWorld::collide_pair(dGeomID a, dGeomID b) {
  const auto* ta = static_cast<const GeomTag*>(dGeomGetData(a));
  const auto* tb = static_cast<const GeomTag*>(dGeomGetData(b));
  if (!ta || !tb) return;
  if (ta->entity == tb->entity && ta->entity >= 0) return;  // a robot's own parts are held by its joints
  dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
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
  for (int i = 0; i < n; ++i) {
    dContact contact{};
    contact.surface = surface;
    contact.geom = geoms[i];
    dJointID joint = dJointCreateContact(world_, contacts_, &contact);
    dJointAttach(joint, ba, bb);
  }

  const auto is_robot = [](const GeomTag* t) {
    return t->role == GeomRole::Chassis || t->role == GeomRole::Wheel || t->role == GeomRole::Caster;
  };
  const auto note = [&](const GeomTag* robot, const GeomTag* other) {
    if (other->role == GeomRole::Terrain) return;
    const Touch touch{robot->entity, other->entity};
    if (std::find(touches_.begin(), touches_.end(), touch) == touches_.end()) touches_.push_back(touch);
  };
  if (is_robot(ta)) note(ta, tb);
  if (is_robot(tb)) note(tb, ta);
}

void PhysicsWorld::step() {
  touches_.clear();
  dSpaceCollide(dynamic_space_, this, &PhysicsWorld::near_callback);
  dSpaceCollide2(reinterpret_cast<dGeomID>(dynamic_space_), reinterpret_cast<dGeomID>(static_space_), this,
                 &PhysicsWorld::near_callback);
  dWorldQuickStep(world_, step_s_);
  dJointGroupEmpty(contacts_);
}

}  // namespace sear
