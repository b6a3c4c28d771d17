#include "sensors/ray_scene.hpp"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

#include "sensors/ray_geometry.hpp"

namespace sear {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr double kPi = 3.14159265358979323846;

// A shape beyond this from the origin has no bounds Embree can hold: an infinite plane is cut here.
constexpr double kWorldReach_m = 1e5;

// Contacts per dCollide: one per ray for every geom but a heightfield (unused by refine()).
constexpr int kMaxContacts = 32;

// Where a hit found in float may sit against its double counterpart, in cell fractions: a hit on a
// cell's edge is kept by the cell Embree named (ODE would report it from its neighbour, at the
// same point to rounding).
constexpr double kCellEdgeSlack = 1e-9;

// One process-wide Embree device on one thread: builds run on the caller's thread (several
// simulations share two cores here), and rays are cast one call at a time per world anyway.
std::shared_ptr<RTCDeviceTy> shared_device() {
  static std::mutex mutex;
  static std::weak_ptr<RTCDeviceTy> kept;
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto device = kept.lock()) return device;
  RTCDevice raw = rtcNewDevice("threads=1,set_affinity=0,verbose=0");
  if (!raw) throw std::runtime_error("ray scene: Embree device could not be created (" +
                                     std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  std::shared_ptr<RTCDeviceTy> device(raw, [](RTCDevice d) { rtcReleaseDevice(d); });
  kept = device;
  return device;
}

// Embree's context with the entity a cast ignores (a sensor never sees its own robot).
struct CastContext {
  RTCIntersectContext rtc;
  int ignore_entity;
};

Eigen::Matrix3d rotation_of(dGeomID geom) {
  const dReal* r = dGeomGetRotation(geom);  // 3x4, row-major
  Eigen::Matrix3d m;
  m << r[0], r[1], r[2], r[4], r[5], r[6], r[8], r[9], r[10];
  return m;
}

Eigen::Vector3d position_of(dGeomID geom) {
  const dReal* p = dGeomGetPosition(geom);
  return {p[0], p[1], p[2]};
}

}  // namespace

struct RayScene::Item {
  // A sphere, cylinder, capsule or plane: Embree user geometry met in double, for candidates
  // only (refine() asks ODE for the figure that counts).
  struct Shape {
    enum class Type { Sphere, Cylinder, Capsule, Plane } type;
    dGeomID geom;
    int entity;
    Eigen::Vector3d position;  // plane: its unit normal
    Eigen::Matrix3d rotation;  // cylinder, capsule: local z is the axis
    double radius = 0;
    double half_length = 0;  // cylinder, capsule: half the axis; plane: its offset along the normal
  };
  enum class Kind { Heightfield, Mesh, Shapes } kind;
  dGeomID geom = nullptr;  // heightfield, mesh (a trimesh or a box)
  int entity = -1;
  // Heightfield: ODE's frame (y up, samples at x = c w, z = r d from the corner) in the world.
  int columns = 0, rows = 0;
  double sample_width = 0, sample_depth = 0, half_width = 0, half_depth = 0;
  const std::vector<double>* heights = nullptr;  // the PhysicsWorld's, which outlives this
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d position{0, 0, 0};
  std::vector<Shape> shapes;
};

namespace {

using Shape = RayScene::Item::Shape;

// How far a hit a cast reports may lie outside its geom's box: in double for boxes, primitives
// and the terrain, but in float for a trimesh (OPCODE meets the ray in float, a few µm at tens
// of metres from the origin), which the rays' float slack covers with room to spare.
double hit_margin(double slack_m) { return std::max(2 * detail::kAabbSlack_m, slack_m); }

// A heightfield's sample (c, r) in ODE's frame of it.
Eigen::Vector3d cell_vertex(const RayScene::Item& item, int c, int r) {
  return Eigen::Vector3d(c * item.sample_width,
                         (*item.heights)[static_cast<std::size_t>(r) * static_cast<std::size_t>(item.columns) +
                                         static_cast<std::size_t>(c)],
                         r * item.sample_depth);
}

// The unit normal of cell (c, r)'s triangle ABC (`upper`) or DCB, with A (c, r), B (c + 1, r),
// C (c, r + 1), D (c + 1, r + 1): (C - A) x (B - A) or (B - D) x (C - D), as ODE forms them.
Eigen::Vector3d cell_normal(const RayScene::Item& item, int c, int r, bool upper) {
  if (upper) {
    const Eigen::Vector3d A = cell_vertex(item, c, r);
    return (cell_vertex(item, c, r + 1) - A).cross(cell_vertex(item, c + 1, r) - A).normalized();
  }
  const Eigen::Vector3d D = cell_vertex(item, c + 1, r + 1);
  return (cell_vertex(item, c + 1, r) - D).cross(cell_vertex(item, c, r + 1) - D).normalized();
}

// The largest angle between any of a heightfield's triangles' normals and its up axis (atan2, not
// acos, which loses the angle of a nearly flat cell to rounding).
double steepest_tilt(const RayScene::Item& item) {
  double steepest = 0;
  for (int row = 0; row + 1 < item.rows; ++row)
    for (int col = 0; col + 1 < item.columns; ++col)
      for (const bool upper : {true, false}) {
        const Eigen::Vector3d n = cell_normal(item, col, row, upper);
        steepest = std::max(steepest, std::atan2(std::hypot(n.x(), n.z()), std::abs(n.y())));
      }
  return steepest;
}

// The first t in [t_min, t_max] of `roots` (unsorted), with its normal; false for none.
struct Nearest {
  double t_min, t_max;
  double t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal{0, 0, 0};
  void offer(double candidate, const Eigen::Vector3d& n) {
    if (candidate >= t_min && candidate <= t_max && candidate < t) {
      t = candidate;
      normal = n;
    }
  }
  bool found() const { return t <= t_max; }
};

// Both roots of a t^2 + 2 b t + c = 0, or false.
bool roots(double a, double b, double c, double& t0, double& t1) {
  if (a == 0) return false;
  const double disc = b * b - a * c;
  if (disc < 0) return false;
  const double s = std::sqrt(disc);
  t0 = (-b - s) / a;
  t1 = (-b + s) / a;
  return true;
}

void meet_shape(const Shape& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Nearest& best) {
  double t0, t1;
  switch (s.type) {
    case Shape::Type::Sphere: {
      const Eigen::Vector3d oc = o - s.position;
      if (roots(d.dot(d), oc.dot(d), oc.dot(oc) - s.radius * s.radius, t0, t1)) {
        best.offer(t0, oc + t0 * d);
        best.offer(t1, oc + t1 * d);
      }
      return;
    }
    case Shape::Type::Plane: {
      const double k = s.position.dot(d);
      if (k != 0) best.offer((s.half_length - s.position.dot(o)) / k, s.position);
      return;
    }
    case Shape::Type::Cylinder:
    case Shape::Type::Capsule: {
      const Eigen::Vector3d lo = s.rotation.transpose() * (o - s.position), ld = s.rotation.transpose() * d;
      const double h = s.half_length, r2 = s.radius * s.radius;
      const auto local_offer = [&](double t, const Eigen::Vector3d& n) { best.offer(t, s.rotation * n); };
      if (roots(ld.x() * ld.x() + ld.y() * ld.y(), lo.x() * ld.x() + lo.y() * ld.y(),
                lo.x() * lo.x() + lo.y() * lo.y() - r2, t0, t1)) {
        for (double t : {t0, t1}) {
          const Eigen::Vector3d p = lo + t * ld;
          if (std::abs(p.z()) <= h) local_offer(t, {p.x(), p.y(), 0});
        }
      }
      if (s.type == Shape::Type::Cylinder) {
        if (ld.z() != 0) {
          for (double cap : {-h, h}) {
            const double t = (cap - lo.z()) / ld.z();
            const Eigen::Vector3d p = lo + t * ld;
            if (p.x() * p.x() + p.y() * p.y() <= r2) local_offer(t, {0, 0, cap});
          }
        }
      } else {
        for (double cap : {-h, h}) {
          const Eigen::Vector3d oc = lo - Eigen::Vector3d(0, 0, cap);
          if (roots(ld.dot(ld), oc.dot(ld), oc.dot(oc) - r2, t0, t1))
            for (double t : {t0, t1}) {
              const Eigen::Vector3d p = lo + t * ld;
              if (cap > 0 ? p.z() >= h : p.z() <= -h) local_offer(t, p - Eigen::Vector3d(0, 0, cap));
            }
        }
      }
      return;
    }
  }
}

void shape_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* item = static_cast<const RayScene::Item*>(args->geometryUserPtr);
  const Shape& s = item->shapes[args->primID];
  Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
  switch (s.type) {
    case Shape::Type::Sphere:
      lo = s.position.array() - s.radius;
      hi = s.position.array() + s.radius;
      break;
    case Shape::Type::Cylinder:
    case Shape::Type::Capsule: {
      const double cap = s.type == Shape::Type::Capsule ? s.radius : 0.0;
      const Eigen::Vector3d half(s.radius, s.radius, s.half_length + cap);
      const Eigen::Vector3d extent = s.rotation.cwiseAbs() * half;
      lo = s.position - extent;
      hi = s.position + extent;
      break;
    }
    case Shape::Type::Plane:
      lo.setConstant(-kWorldReach_m);
      hi.setConstant(kWorldReach_m);
      for (int axis = 0; axis < 3; ++axis) {  // an axis-aligned plane is flat along its axis
        if (std::abs(s.position[axis]) == 1.0) lo[axis] = hi[axis] = s.half_length * s.position[axis];
      }
      break;
  }
  // Widened by more than float rounding, so that no true hit falls outside its box.
  const Eigen::Vector3d pad = 1e-6 * (lo.cwiseAbs().cwiseMax(hi.cwiseAbs()).array() + 1.0);
  lo -= pad;
  hi += pad;
  RTCBounds* b = args->bounds_o;
  b->lower_x = static_cast<float>(lo.x());
  b->lower_y = static_cast<float>(lo.y());
  b->lower_z = static_cast<float>(lo.z());
  b->upper_x = static_cast<float>(hi.x());
  b->upper_y = static_cast<float>(hi.y());
  b->upper_z = static_cast<float>(hi.z());
}

void shape_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* item = static_cast<const RayScene::Item*>(args->geometryUserPtr);
  const Shape& s = item->shapes[args->primID];
  const auto* context = reinterpret_cast<const CastContext*>(args->context);
  if (s.entity >= 0 && s.entity == context->ignore_entity) return;
  const unsigned n = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, n);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, n);
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const Eigen::Vector3d o(RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i));
    const Eigen::Vector3d d(RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i));
    Nearest best{RTCRayN_tnear(ray, n, i), RTCRayN_tfar(ray, n, i)};
    meet_shape(s, o, d, best);
    if (!best.found()) continue;
    RTCRayN_tfar(ray, n, i) = static_cast<float>(best.t);
    RTCHitN_Ng_x(hit, n, i) = static_cast<float>(best.normal.x());
    RTCHitN_Ng_y(hit, n, i) = static_cast<float>(best.normal.y());
    RTCHitN_Ng_z(hit, n, i) = static_cast<float>(best.normal.z());
    RTCHitN_u(hit, n, i) = 0;
    RTCHitN_v(hit, n, i) = 0;
    RTCHitN_primID(hit, n, i) = args->primID;
    RTCHitN_geomID(hit, n, i) = args->geomID;
    RTCHitN_instID(hit, n, i, 0) = args->context->instID[0];
  }
}

// Rejects hits on a mesh or box of the entity the cast ignores.
void skip_ignored(const RTCFilterFunctionNArguments* args) {
  const auto* item = static_cast<const RayScene::Item*>(args->geometryUserPtr);
  const auto* context = reinterpret_cast<const CastContext*>(args->context);
  if (item->entity != context->ignore_entity) return;
  for (unsigned i = 0; i < args->N; ++i) args->valid[i] = 0;
}

// Casts rays 16 at a time through rtcIntersect16 (one or two alone): `fill(i, o, d)` gives ray i,
// `take(i, t, geom, prim)` its answer (t = INFINITY for none).
template <typename Fill, typename Take>
void cast_packets(RTCScene scene, std::size_t count, double reach_m, int ignore_entity, Fill&& fill, Take&& take) {
  CastContext context;
  rtcInitIntersectContext(&context.rtc);
  // A scan's or a beam's rays leave one point in neighbouring directions.
  context.rtc.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  context.ignore_entity = ignore_entity;
  const auto reach = static_cast<float>(reach_m);
  if (count <= 2) {
    // A lone ray (a lever's, a single-ray ranger's) costs less alone than in a packet of 16.
    context.rtc.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    for (std::size_t i = 0; i < count; ++i) {
      RTCRayHit single;
      float o[3], d[3];
      fill(i, o, d);
      single.ray.org_x = o[0];
      single.ray.org_y = o[1];
      single.ray.org_z = o[2];
      single.ray.dir_x = d[0];
      single.ray.dir_y = d[1];
      single.ray.dir_z = d[2];
      single.ray.tnear = 0;
      single.ray.tfar = reach;
      single.ray.time = 0;
      single.ray.mask = ~0u;
      single.ray.id = 0;
      single.ray.flags = 0;
      single.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      single.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context.rtc, &single);
      const bool hit = single.hit.geomID != RTC_INVALID_GEOMETRY_ID;
      take(i, hit ? single.ray.tfar : kInfF, single.hit.geomID, single.hit.primID);
    }
    return;
  }
  alignas(64) int valid[16];
  RTCRayHit16 packet;
  for (std::size_t first = 0; first < count; first += 16) {
    const std::size_t lanes = std::min<std::size_t>(16, count - first);
    for (std::size_t k = 0; k < 16; ++k) {
      valid[k] = k < lanes ? -1 : 0;
      float o[3] = {0, 0, 0}, d[3] = {1, 0, 0};
      if (k < lanes) fill(first + k, o, d);
      packet.ray.org_x[k] = o[0];
      packet.ray.org_y[k] = o[1];
      packet.ray.org_z[k] = o[2];
      packet.ray.dir_x[k] = d[0];
      packet.ray.dir_y[k] = d[1];
      packet.ray.dir_z[k] = d[2];
      packet.ray.tnear[k] = 0;
      packet.ray.tfar[k] = reach;
      packet.ray.time[k] = 0;
      packet.ray.mask[k] = ~0u;
      packet.ray.id[k] = static_cast<unsigned>(k);
      packet.ray.flags[k] = 0;
      packet.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      packet.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect16(valid, scene, &context.rtc, &packet);
    for (std::size_t k = 0; k < lanes; ++k) {
      const bool hit = packet.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
      take(first + k, hit ? packet.ray.tfar[k] : kInfF, packet.hit.geomID[k], packet.hit.primID[k]);
    }
  }
}

}  // namespace

const RayScene& RayScene::of(const PhysicsWorld& physics) {
  std::shared_ptr<const RayScene>& slot = physics.ray_scene_slot();
  if (!slot || slot->static_count_ != dSpaceGetNumGeoms(physics.static_space()))
    slot = std::make_shared<const RayScene>(physics);
  return *slot;
}

RayScene::RayScene(const PhysicsWorld& physics) : device_(shared_device()) {
  static_count_ = dSpaceGetNumGeoms(physics.static_space());
  terrain_ = physics.terrain_geom();
  ray_ = dCreateRay(nullptr, 1.0);
  // Every triangle a ray crosses is considered and the nearest kept; both faces count.
  dGeomRaySetFirstContact(ray_, 0);
  dGeomRaySetBackfaceCull(ray_, 0);
  dGeomRaySetClosestHit(ray_, 1);

  scene_ = rtcNewScene(device_.get());
  // Static and asked millions of times: worth the better tree.
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
  RTCDevice device = device_.get();

  // A geometry per heightfield, trimesh and box, and one of user shapes, each pointing at its item.
  const auto attach = [&](RTCGeometry geometry, std::unique_ptr<Item> item) {
    rtcSetGeometryUserData(geometry, item.get());
    // Shapes skip the ignored entity in shape_intersect(); a terrain (entity -1) is never ignored.
    if (item->entity >= 0 && item->kind != Item::Kind::Shapes)
      rtcSetGeometryIntersectFilterFunction(geometry, &skip_ignored);
    rtcCommitGeometry(geometry);
    const unsigned id = rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    if (items_.size() <= id) items_.resize(id + 1);
    items_[id] = std::move(item);
  };
  const auto add_triangles = [&](dGeomID geom, int entity, const std::vector<Eigen::Vector3d>& corners) {
    const std::size_t n = corners.size() / 3;
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n));
    auto* idx = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n));
    for (std::size_t i = 0; i < 3 * n; ++i) {
      for (int k = 0; k < 3; ++k) v[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(corners[i][k]);
      idx[i] = static_cast<unsigned>(i);
    }
    triangles_ += n;
    auto item = std::make_unique<Item>();
    item->kind = Item::Kind::Mesh;
    item->geom = geom;
    item->entity = entity;
    attach(geometry, std::move(item));
  };

  auto shapes = std::make_unique<Item>();
  shapes->kind = Item::Kind::Shapes;
  std::vector<dSpaceID> spaces{physics.static_space()};
  while (!spaces.empty()) {
    dSpaceID space = spaces.back();
    spaces.pop_back();
    for (int i = 0; i < dSpaceGetNumGeoms(space); ++i) {
      dGeomID geom = dSpaceGetGeom(space, i);
      if (dGeomIsSpace(geom)) {
        spaces.push_back(reinterpret_cast<dSpaceID>(geom));
        continue;
      }
      // Untagged geoms take part in no contact: not solid to a ray either; treads meet only the ground.
      const auto* tag = static_cast<const GeomTag*>(dGeomGetData(geom));
      if (!tag || tag->role == GeomRole::Tread) continue;
      StaticGeom kept{geom, tag->entity, {}, nullptr};
      dGeomGetAABB(geom, kept.aabb);
      all_.push_back(kept);

      const bool placeable = dGeomGetClass(geom) != dPlaneClass;
      const Eigen::Vector3d p = placeable ? position_of(geom) : Eigen::Vector3d::Zero();
      const Eigen::Matrix3d r = placeable ? rotation_of(geom) : Eigen::Matrix3d::Identity();
      switch (dGeomGetClass(geom)) {
        case dHeightfieldClass: {
          const std::vector<double>& h = physics.terrain_samples();
          const int columns = physics.terrain_columns(), rows = physics.terrain_rows();
          // Only the terrain's samples are known here (as build_terrain gave them to ODE, scale 1,
          // offset 0); any other heightfield is left to ODE.
          if (geom != physics.terrain_geom() || columns < 2 || rows < 2 ||
              h.size() != static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows)) {
            ode_only_.push_back(geom);
            break;
          }
          auto item = std::make_unique<Item>();
          item->kind = Item::Kind::Heightfield;
          item->geom = geom;
          item->entity = tag->entity;
          item->columns = columns;
          item->rows = rows;
          item->sample_width = physics.terrain_size_m().x() / (columns - 1);
          item->sample_depth = physics.terrain_size_m().y() / (rows - 1);
          item->half_width = 0.5 * physics.terrain_size_m().x();
          item->half_depth = 0.5 * physics.terrain_size_m().y();
          item->heights = &h;
          item->rotation = r;
          item->position = p;
          // ODE's cell (c, r) has corners A (c, r), B (c + 1, r), C (c, r + 1), D (c + 1, r + 1) and
          // splits along B-C into ABC and DCB; Embree's quad (v0 v1 v2 v3) splits into (v0 v1 v3)
          // and (v2 v3 v1), so the quad A B D C is exactly ODE's pair.
          RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
          const std::size_t nv = h.size(), cells = static_cast<std::size_t>(columns - 1) * static_cast<std::size_t>(rows - 1);
          auto* v = static_cast<float*>(
              rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
          auto* idx = static_cast<unsigned*>(
              rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(unsigned), cells));
          for (int row = 0; row < rows; ++row)
            for (int col = 0; col < columns; ++col) {
              const std::size_t k = static_cast<std::size_t>(row) * static_cast<std::size_t>(columns) + static_cast<std::size_t>(col);
              const Eigen::Vector3d local(col * item->sample_width - item->half_width, h[k],
                                          row * item->sample_depth - item->half_depth);
              const Eigen::Vector3d world = r * local + p;
              for (int a = 0; a < 3; ++a) v[3 * k + static_cast<std::size_t>(a)] = static_cast<float>(world[a]);
            }
          for (int row = 0; row + 1 < rows; ++row)
            for (int col = 0; col + 1 < columns; ++col) {
              const auto at = [&](int c, int rr) { return static_cast<unsigned>(rr * columns + c); };
              unsigned* q = idx + 4 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(columns - 1) +
                                       static_cast<std::size_t>(col));
              q[0] = at(col, row);
              q[1] = at(col + 1, row);
              q[2] = at(col + 1, row + 1);
              q[3] = at(col, row + 1);
            }
          triangles_ += 2 * cells;
          all_.back().heightfield = item.get();
          if (geom == terrain_) {
            terrain_up_ = r.col(1);  // ODE's heightfield frame has y up
            terrain_tilt_rad_ = steepest_tilt(*item);
          }
          attach(geometry, std::move(item));
          break;
        }
        case dTriMeshClass: {
          const int n = dGeomTriMeshGetTriangleCount(geom);
          std::vector<Eigen::Vector3d> corners;
          corners.reserve(3 * static_cast<std::size_t>(n));
          for (int t = 0; t < n; ++t) {
            dVector3 a, b, c;
            dGeomTriMeshGetTriangle(geom, t, &a, &b, &c);  // in the world
            corners.emplace_back(a[0], a[1], a[2]);
            corners.emplace_back(b[0], b[1], b[2]);
            corners.emplace_back(c[0], c[1], c[2]);
          }
          add_triangles(geom, tag->entity, corners);
          break;
        }
        case dBoxClass: {
          dVector3 lengths;
          dGeomBoxGetLengths(geom, lengths);
          const auto corner = [&](int bits) {
            const Eigen::Vector3d local((bits & 1 ? 0.5 : -0.5) * lengths[0], (bits & 2 ? 0.5 : -0.5) * lengths[1],
                                        (bits & 4 ? 0.5 : -0.5) * lengths[2]);
            return Eigen::Vector3d(r * local + p);
          };
          // Two triangles per face; corners indexed by bits x, y, z.
          static constexpr int kFaces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                               {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
          std::vector<Eigen::Vector3d> corners;
          for (const auto& f : kFaces)
            for (int k : {f[0], f[1], f[2], f[0], f[2], f[3]}) corners.push_back(corner(k));
          add_triangles(geom, tag->entity, corners);
          break;
        }
        case dSphereClass:
          shapes->shapes.push_back({Shape::Type::Sphere, geom, tag->entity, p, r, dGeomSphereGetRadius(geom), 0});
          break;
        case dCylinderClass:
        case dCapsuleClass: {
          dReal radius, length;
          const bool capsule = dGeomGetClass(geom) == dCapsuleClass;
          if (capsule)
            dGeomCapsuleGetParams(geom, &radius, &length);
          else
            dGeomCylinderGetParams(geom, &radius, &length);
          shapes->shapes.push_back({capsule ? Shape::Type::Capsule : Shape::Type::Cylinder, geom, tag->entity, p, r,
                                    radius, 0.5 * length});
          break;
        }
        case dPlaneClass: {
          dVector4 plane;
          dGeomPlaneGetParams(geom, plane);
          if (geom == terrain_) {
            terrain_up_ = Eigen::Vector3d(plane[0], plane[1], plane[2]);
            terrain_tilt_rad_ = 0;
          }
          shapes->shapes.push_back({Shape::Type::Plane, geom, tag->entity, Eigen::Vector3d(plane[0], plane[1], plane[2]),
                                    Eigen::Matrix3d::Identity(), 0, plane[3]});
          break;
        }
        default:
          ode_only_.push_back(geom);
          break;
      }
    }
  }
  if (!shapes->shapes.empty()) {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geometry, static_cast<unsigned>(shapes->shapes.size()));
    rtcSetGeometryBoundsFunction(geometry, &shape_bounds, nullptr);
    rtcSetGeometryIntersectFunction(geometry, &shape_intersect);
    attach(geometry, std::move(shapes));
  }
  std::vector<std::array<double, 6>> boxes;
  for (std::uint32_t i = 0; i < all_.size(); ++i) {
    const double* a = all_[i].aabb;
    boxes.push_back({a[0], a[1], a[2], a[3], a[4], a[5]});
    index_of_.emplace(all_[i].geom, i);
  }
  grid_ = BoxGrid(boxes);
  rtcCommitScene(scene_);
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error("ray scene: Embree failed to build the static world (error " +
                             std::to_string(static_cast<int>(error)) + ")");
}

double RayScene::grazing_cos(double max_incidence_rad) const {
  // A normal within tilt of up meets a ray at theta from up at no less than theta - tilt. The
  // margin is far beyond the rounding of the normals, computed in double as refine() does.
  const double widest = terrain_tilt_rad_ + max_incidence_rad + 1e-9;
  return terrain_tilt_rad_ < 0 || widest >= 0.5 * kPi ? -1.0 : std::cos(widest);
}

void RayScene::others_near(const double box[6], double slack_m, int ignore_entity,
                           std::vector<std::array<double, 6>>& out) const {
  out.clear();
  const double margin = hit_margin(slack_m);
  for (std::uint32_t i : grid_.near(box, margin)) {
    const StaticGeom& g = all_[i];
    if (g.geom == terrain_ || (ignore_entity >= 0 && g.entity == ignore_entity)) continue;
    if (!detail::boxes_meet(g.aabb, box, margin)) continue;
    out.push_back({g.aabb[0] - margin, g.aabb[1] + margin, g.aabb[2] - margin, g.aabb[3] + margin,
                   g.aabb[4] - margin, g.aabb[5] + margin});
  }
}

RayScene::~RayScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (ray_) dGeomDestroy(ray_);
}

double RayScene::float_slack_m(double t_m, double origin_norm_m) {
  // Embree holds the origin, the direction and the vertices in float: each place is off by up to
  // 2^-24 of its size, about 6e-8 (|o| + t) across the ray, and its intersection arithmetic adds a
  // few such roundings. Along the ray that lateral error grows as 1 / cos(incidence); 3e-5 covers
  // four roundings up to 89.2 degrees, where only a grazing ray's distance is then doubtful.
  return 1e-6 + 3e-5 * (t_m + origin_norm_m);
}

void RayScene::cast(const Eigen::Vector3d* origins, bool shared_origin, const Eigen::Vector3d* dirs,
                    std::size_t count, double reach_m, int ignore_entity, BvhHit* out) const {
  cast_packets(
      scene_, count, reach_m, ignore_entity,
      [&](std::size_t i, float* o, float* d) {
        const Eigen::Vector3d& origin = origins[shared_origin ? 0 : i];
        for (int a = 0; a < 3; ++a) {
          o[a] = static_cast<float>(origin[a]);
          d[a] = static_cast<float>(dirs[i][a]);
        }
      },
      [&](std::size_t i, float t, unsigned geom, unsigned prim) { out[i] = {t, geom, prim}; });
}

void RayScene::cast_fan(const Eigen::Vector3d& origin, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                        const float* cos_table, const float* sin_table, std::size_t count, double reach_m,
                        int ignore_entity, float* out_m) const {
  const Eigen::Vector3f of = origin.cast<float>(), af = a.cast<float>(), bf = b.cast<float>();
  cast_packets(
      scene_, count, reach_m, ignore_entity,
      [&](std::size_t i, float* o, float* d) {
        for (int k = 0; k < 3; ++k) {
          o[k] = of[k];
          d[k] = cos_table[i] * af[k] + sin_table[i] * bf[k];
        }
      },
      [&](std::size_t i, float t, unsigned, unsigned) { out_m[i] = t; });
}

namespace {

// ODE's triangles of heightfield cells crossed by the ray over [from, limit], met in double as
// dxHeightfield::dCollideHeightfieldZone meets them; the nearest kept in `out`.
bool heightfield_hit(const RayScene::Item& item, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                     double from, double limit, RayHit& out) {
  // In ODE's frame, as dCollideHeightfield turns the ray into it.
  const Eigen::Vector3d corner(item.half_width, 0, item.half_depth);
  const Eigen::Vector3d o = item.rotation.transpose() * (origin - item.position) + corner;
  const Eigen::Vector3d v = item.rotation.transpose() * dir;
  const Eigen::Vector3d a = o + from * v, b = o + limit * v;
  const auto cells = [](double p, double q, double size, int last) {
    const double lo = std::floor(std::min(p, q) / size - kCellEdgeSlack), hi = std::floor(std::max(p, q) / size + kCellEdgeSlack);
    return std::pair<int, int>(static_cast<int>(std::clamp(lo, 0.0, static_cast<double>(last))),
                               static_cast<int>(std::clamp(hi, 0.0, static_cast<double>(last))));
  };
  if (std::max(a.x(), b.x()) < 0 || std::max(a.z(), b.z()) < 0 ||
      std::min(a.x(), b.x()) > (item.columns - 1) * item.sample_width ||
      std::min(a.z(), b.z()) > (item.rows - 1) * item.sample_depth)
    return false;
  const auto [c0, c1] = cells(a.x(), b.x(), item.sample_width, item.columns - 2);
  const auto [r0, r1] = cells(a.z(), b.z(), item.sample_depth, item.rows - 2);
  // A long segment would walk many cells; refine() only asks about a few millimetres.
  bool found = false;
  for (int row = r0; row <= r1; ++row)
    for (int col = c0; col <= c1; ++col) {
      const Eigen::Vector3d A = cell_vertex(item, col, row), D = cell_vertex(item, col + 1, row + 1);
      for (const bool up : {true, false}) {
        // The triangle's plane through its first vertex, as dCollideRayPlane meets it.
        const Eigen::Vector3d& first = up ? A : D;
        const Eigen::Vector3d n = cell_normal(item, col, row, up);
        const double k = n.dot(v);
        if (k == 0) continue;
        const double alpha = (n.dot(first) - n.dot(o)) / k;
        if (!(alpha >= 0)) continue;
        const Eigen::Vector3d p = o + alpha * v;
        // IsOnHeightfield2: inside the cell, and on its triangle's side of the diagonal.
        const double fx = (p.x() - A.x()) / item.sample_width, fz = (p.z() - A.z()) / item.sample_depth;
        if (fx < -kCellEdgeSlack || fx > 1 + kCellEdgeSlack || fz < -kCellEdgeSlack || fz > 1 + kCellEdgeSlack) continue;
        if (up ? fx + fz > 1 + kCellEdgeSlack : fx + fz < 1 - kCellEdgeSlack) continue;
        const Eigen::Vector3d world = item.rotation * (p - corner) + item.position;
        const double t = (world - origin).dot(dir);
        if (!(t >= 0 && t <= limit) || ((found || out.hit) && t >= out.distance_m)) continue;
        detail::record_hit(out, t, world, item.rotation * n, dir, item.entity);
        found = true;
      }
    }
  return found;
}

}  // namespace

bool RayScene::exact(const StaticGeom& g, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double from_m,
                     double limit_m, RayHit& out) const {
  if (g.heightfield) return heightfield_hit(*g.heightfield, origin, dir, from_m, limit_m, out);
  // A little longer than asked: a trimesh's collider (OPCODE) culls in float against the ray's
  // end, and would drop a hit just inside the limit. The limit is applied in double below.
  dGeomRaySetLength(ray_, limit_m + float_slack_m(limit_m, origin.norm()));
  dGeomRaySet(ray_, origin.x(), origin.y(), origin.z(), dir.x(), dir.y(), dir.z());
  dContactGeom contacts[kMaxContacts];
  const int n = dCollide(ray_, g.geom, kMaxContacts, contacts, sizeof(dContactGeom));
  return detail::take_nearest_contact(contacts, n, origin, dir, limit_m, g.entity, false, out);
}

bool RayScene::refine(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double limit_m, const BvhHit& hit,
                      int ignore_entity, RayHit& out) const {
  if (!std::isfinite(hit.t) || hit.item >= items_.size() || !items_[hit.item]) return false;
  const Item& item = *items_[hit.item];
  const dGeomID struck = item.kind == Item::Kind::Shapes ? item.shapes.at(hit.prim).geom : item.geom;
  const double slack = float_slack_m(hit.t, origin.norm());
  RayHit best;
  const auto kept = index_of_.find(struck);
  if (kept == index_of_.end() ||
      !exact(all_[kept->second], origin, dir, std::max(0.0, hit.t - slack), std::min(limit_m, hit.t + slack), best))
    return false;
  // Anything else within rounding before it: the foot of a wall in the ground, a box on a box.
  // The stretch is a fraction of a millimetre, so most boxes lie clear of its own box: that test
  // first, with room to spare, spares the slab test's three divisions for every geom of the
  // world on every ray (most of refine()'s own time on a sonar cone's rays).
  const double from = std::max(0.0, best.distance_m - slack);
  const Eigen::Vector3d start = origin + from * dir;
  const Eigen::Vector3d end = origin + best.distance_m * dir;
  const double stretch[6] = {std::min(start.x(), end.x()), std::max(start.x(), end.x()),
                             std::min(start.y(), end.y()), std::max(start.y(), end.y()),
                             std::min(start.z(), end.z()), std::max(start.z(), end.z())};
  for (std::uint32_t i : grid_.near(stretch, 2 * detail::kAabbSlack_m)) {
    const StaticGeom& g = all_[i];
    if (g.geom == struck || (ignore_entity >= 0 && g.entity == ignore_entity)) continue;
    if (!detail::boxes_meet(g.aabb, stretch, 2 * detail::kAabbSlack_m)) continue;
    if (!detail::segment_meets_box(start, dir, best.distance_m - from, g.aabb)) continue;
    exact(g, origin, dir, from, best.distance_m, best);
  }
  out = best;
  return true;
}

bool RayScene::clear_of(const double box[6], double terrain_ceiling_m, double slack_m, int ignore_entity) const {
  const double margin = hit_margin(slack_m);
  // The terrain is judged by its samples under the box, not by its own box.
  const auto terrain = index_of_.find(terrain_);
  if (terrain != index_of_.end() && !(ignore_entity >= 0 && all_[terrain->second].entity == ignore_entity) &&
      !(box[4] - margin > terrain_ceiling_m))
    return false;
  for (std::uint32_t i : grid_.near(box, margin)) {
    const StaticGeom& g = all_[i];
    if (g.geom == terrain_ || (ignore_entity >= 0 && g.entity == ignore_entity)) continue;
    if (detail::boxes_meet(g.aabb, box, margin)) return false;
  }
  return true;
}

RayHit RayScene::ode_nearest(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double limit_m,
                             int ignore_entity) const {
  RayHit best;
  double limit = limit_m;
  dContactGeom contacts[kMaxContacts];
  const Eigen::Vector3d end = origin + limit_m * dir;
  const double reach[6] = {std::min(origin.x(), end.x()), std::max(origin.x(), end.x()),
                           std::min(origin.y(), end.y()), std::max(origin.y(), end.y()),
                           std::min(origin.z(), end.z()), std::max(origin.z(), end.z())};
  for (std::uint32_t i : grid_.near(reach)) {
    const StaticGeom& g = all_[i];
    if (ignore_entity >= 0 && g.entity == ignore_entity) continue;
    if (!detail::segment_meets_box(origin, dir, limit, g.aabb)) continue;
    dGeomRaySetLength(ray_, limit);
    dGeomRaySet(ray_, origin.x(), origin.y(), origin.z(), dir.x(), dir.y(), dir.z());
    const int n = dCollide(ray_, g.geom, kMaxContacts, contacts, sizeof(dContactGeom));
    if (detail::take_nearest_contact(contacts, n, origin, dir, limit, g.entity, false, best)) limit = best.distance_m;
  }
  return best;
}

RayHit RayScene::nearest(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double limit_m,
                         int ignore_entity) const {
  BvhHit h;
  cast(&origin, true, &dir, 1, limit_m + float_slack_m(limit_m, origin.norm()), ignore_entity, &h);
  RayHit r;
  if (!std::isfinite(h.t)) return r;
  if (refine(origin, dir, limit_m, h, ignore_entity, r)) return r;
  // A float hit within rounding of the limit that lies beyond it in double: nothing nearer.
  if (h.t >= limit_m - float_slack_m(limit_m, origin.norm())) return r;
  // Embree struck an edge ODE misses: ask ODE outright.
  return ode_nearest(origin, dir, limit_m, ignore_entity);
}

}  // namespace sear
