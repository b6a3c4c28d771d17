#include "scene/urdf_import.hpp"

#include <console_bridge/console.h>
#include <fmt/format.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <set>
#include <sstream>

#include "scene/convex_hull.hpp"
#include "scene/loader_parts.hpp"
#include "scene/mesh_loader.hpp"
#include "scene/nearest_name.hpp"
#include "scene/urdf_inertia.hpp"
#include "scene/urdf_joints.hpp"

namespace sear {
namespace {

namespace fs = std::filesystem;
using Iso = Eigen::Isometry3d;

// An rpy this close to a multiple of 90 degrees is taken as meaning it: "1.5708" is pi/2 written
// short, and left as it is it tilts a wheel axle by 4e-6 rad, enough to make it drift sideways.
constexpr double kSnap_rad = 1e-3;
// A wheel's joint axis must lie along the robot's y axis to this angle (after snapping).
constexpr double kAxleTolerance_rad = 1e-3;
// A body shape that reaches within this of the ground the wheels stand on touches it as soon as
// the tyres give a little under load: it drags.
constexpr double kDragClearance_m = 0.002;

int line_in(const std::string& text, std::size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

// urdfdom reports through console_bridge; its messages are kept for our own error line.
class CaptureLog : public console_bridge::OutputHandler {
 public:
  CaptureLog() { console_bridge::useOutputHandler(this); }
  ~CaptureLog() override { console_bridge::restorePreviousOutputHandler(); }
  CaptureLog(const CaptureLog&) = delete;
  CaptureLog& operator=(const CaptureLog&) = delete;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR && first_error.empty()) first_error = text;
  }
  std::string first_error;
};

// The elements of the URDF by name, for the lines urdfdom does not keep.
class UrdfLines {
 public:
  explicit UrdfLines(const tinyxml2::XMLElement* root) : root_(root) {
    for (auto* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const char* name = e->Attribute("name");
      if (!name) continue;
      if (std::string(e->Name()) == "link") links_[name] = e;
      if (std::string(e->Name()) == "joint") joints_[name] = e;
    }
  }
  int root() const { return root_->GetLineNum(); }
  const tinyxml2::XMLElement* link(const std::string& name) const {
    const auto it = links_.find(name);
    return it == links_.end() ? nullptr : it->second;
  }
  const tinyxml2::XMLElement* joint(const std::string& name) const {
    const auto it = joints_.find(name);
    return it == joints_.end() ? nullptr : it->second;
  }
  int link_line(const std::string& name) const { return line(link(name)); }
  int joint_line(const std::string& name) const { return line(joint(name)); }
  // The line of `path` (child names) below a link, or of the deepest part of it that exists.
  int below_link(const std::string& name, std::initializer_list<const char*> path, int index = 0) const {
    const tinyxml2::XMLElement* e = link(name);
    int at = line(e);
    bool first = true;
    for (const char* step : path) {
      if (!e) break;
      const tinyxml2::XMLElement* c = e->FirstChildElement(step);
      for (int k = 0; first && c && k < index; ++k) c = c->NextSiblingElement(step);
      first = false;
      if (!c) break;
      e = c;
      at = e->GetLineNum();
    }
    return at;
  }

 private:
  int line(const tinyxml2::XMLElement* e) const { return e ? e->GetLineNum() : root_->GetLineNum(); }
  const tinyxml2::XMLElement* root_;
  std::map<std::string, const tinyxml2::XMLElement*> links_, joints_;
};

Iso pose_of(const urdf::Pose& p) {
  Iso t = Iso::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).normalized().toRotationMatrix();
  return t;
}

Eigen::Vector3d vec(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

// Every rpy within kSnap_rad of a right angle becomes that angle, in the document urdfdom reads.
void snap_angles(tinyxml2::XMLElement* element, const std::string& path,
                 std::vector<std::pair<SourceRef, std::string>>& warnings) {
  for (auto* e = element->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const char* rpy = e->Attribute("rpy");
    if (rpy && std::string(e->Name()) == "origin") {
      std::istringstream in(rpy);
      double v[3];
      bool changed = false;
      if (in >> v[0] >> v[1] >> v[2]) {
        for (double& a : v) {
          const double right = std::round(a / (M_PI / 2)) * (M_PI / 2);
          const double off = std::abs(a - right);
          if (off > 0 && off < kSnap_rad && off > 1e-12) {
            a = right;
            changed = true;
          }
        }
      }
      if (changed) {
        warnings.push_back({{path, e->GetLineNum()},
                            fmt::format("rpy=\"{}\" is within {} rad of right angles: taken as {:.17g} {:.17g} {:.17g}",
                                        rpy, kSnap_rad, v[0], v[1], v[2])});
        e->SetAttribute("rpy", fmt::format("{:.17g} {:.17g} {:.17g}", v[0], v[1], v[2]).c_str());
      }
    }
    snap_angles(e, path, warnings);
  }
}

// Where a mesh's file is: package://NAME/... through the mapping (or a folder NAME that holds
// the URDF), file:// and plain paths as they are, relative ones beside the URDF.
std::string resolve_mesh(const std::string& uri, const std::string& urdf_path, const UrdfMapping& mapping,
                         std::string& problem) {
  const std::string package = "package://";
  if (uri.rfind(package, 0) == 0) {
    const std::string rest = uri.substr(package.size());
    const auto slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string inside = slash == std::string::npos ? "" : rest.substr(slash + 1);
    const auto it = mapping.packages.find(name);
    if (it != mapping.packages.end()) return (fs::path(it->second) / inside).string();
    for (fs::path dir = fs::absolute(urdf_path).parent_path(); !dir.empty() && dir != dir.root_path();
         dir = dir.parent_path())
      if (dir.filename() == name) return (dir / inside).string();
    problem = fmt::format("mesh '{}' is in package '{}', which is not known: give <package name=\"{}\" dir=\"...\"/> "
                          "in the robot's mapping, or --package {}=DIR on the command line",
                          uri, name, name, name);
    return "";
  }
  if (uri.rfind("file://", 0) == 0) return uri.substr(7);
  return path_beside(urdf_path, uri);
}

// Points that bound a shape, in the frame `at` puts it in: corners, rims, mesh vertices.
void shape_points(const ShapeDesc& s, const Iso& at, std::vector<Eigen::Vector3d>& out) {
  const Iso t = at * Iso(Eigen::Translation3d(s.position_m)) * Iso(s.rotation);
  switch (s.kind) {
    case ShapeDesc::Kind::Box:
      for (int k = 0; k < 8; ++k)
        out.push_back(t * Eigen::Vector3d((k & 1 ? 0.5 : -0.5) * s.size_m.x(), (k & 2 ? 0.5 : -0.5) * s.size_m.y(),
                                          (k & 4 ? 0.5 : -0.5) * s.size_m.z()));
      break;
    case ShapeDesc::Kind::Cylinder:
      for (int k = 0; k < 64; ++k) {
        const double a = 2 * M_PI * (k / 2) / 32.0;
        out.push_back(t * Eigen::Vector3d(s.size_m.x() * std::cos(a), s.size_m.x() * std::sin(a),
                                          (k & 1 ? 0.5 : -0.5) * s.size_m.z()));
      }
      break;
    case ShapeDesc::Kind::Sphere:
      for (int k = 0; k < 6; ++k) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[k / 2] = (k & 1 ? 1 : -1) * s.size_m.x();
        out.push_back(t * d);
      }
      break;
    case ShapeDesc::Kind::Mesh:
      for (const auto& v : s.mesh.vertices) out.push_back(t * v.cast<double>());
      break;
  }
}

struct Bounds {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  void add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool empty() const { return !(lo.x() <= hi.x()); }
};

Bounds bounds_of(const std::vector<Eigen::Vector3d>& points) {
  Bounds b;
  for (const auto& p : points) b.add(p);
  return b;
}

// A shape placed in a body, with where it came from.
struct PlacedShape {
  ShapeDesc shape;  // position and rotation in the body's frame
  std::string link;
  int line = 0;
};

struct Body {
  Iso frame = Iso::Identity();  // in base_link's frame, at rest
  std::string joint;            // the moving joint it hangs on (empty: the chassis)
  std::string first_link;
  int wheel = -1;               // index into the mapping's wheels
  int live = -1;                // or into the robot's live joints (UrdfRobot::joints)
  MassProperties mass;
  std::vector<PlacedShape> collisions;
  std::vector<std::pair<PlacedShape, Eigen::Vector4d>> visuals;
};

class Importer {
 public:
  Importer(const std::string& path, const UrdfMapping& mapping, Diagnostics& diagnostics, UrdfRobot& robot,
           const urdf::ModelInterface& model, const UrdfLines& lines)
      : path_(path), mapping_(mapping), diagnostics_(diagnostics), robot_(robot), model_(model), lines_(lines) {}

  bool run();

 private:
  void error(int line, const std::string& message) { diagnostics_.error(path_, line, message); }
  void warn(int line, const std::string& message) { robot_.report.warnings.push_back({{path_, line}, message}); }
  std::optional<ShapeDesc> hull_of(const ShapeDesc& mesh, const std::string& link, int line, std::size_t triangles,
                                   std::size_t budget, UrdfImportDesc::Mesh& report);
  std::optional<ShapeDesc> shape_of(const urdf::Geometry& g, const std::string& link, const char* use, int index,
                                    const Iso& at, std::size_t* triangles);
  void visit(const urdf::Link& link, int body, const Iso& in_body, int caster);
  void add_link(const urdf::Link& link, int body, const Iso& in_body, int caster);
  double density_for(const std::string& link) const;
  const UrdfMapping::Collision* collision_rule(const std::string& link) const;
  void build_wheel(Body& body, const Iso& to_chassis_com);
  void build_live(const Body& body, const Iso& to_chassis_com);

  std::string path_;
  const UrdfMapping& mapping_;
  Diagnostics& diagnostics_;
  UrdfRobot& robot_;
  const urdf::ModelInterface& model_;
  const UrdfLines& lines_;
  std::vector<Body> bodies_;
  std::vector<std::vector<PlacedShape>> caster_shapes_;  // per mapped caster, in base_link's frame
  std::set<std::string> used_joints_;
};

double Importer::density_for(const std::string& link) const {
  double any = 0;
  for (const auto& d : mapping_.densities) {
    if (d.link == link) return d.kg_per_m3;
    if (d.link.empty()) any = d.kg_per_m3;
  }
  return any;
}

const UrdfMapping::Collision* Importer::collision_rule(const std::string& link) const {
  const UrdfMapping::Collision* any = nullptr;
  for (const auto& c : mapping_.collisions) {
    if (c.link == link) return &c;
    if (c.link.empty()) any = &c;
  }
  return any;
}

std::optional<ShapeDesc> Importer::shape_of(const urdf::Geometry& g, const std::string& link, const char* use,
                                            int index, const Iso& at, std::size_t* triangles) {
  ShapeDesc s;
  s.position_m = at.translation();
  s.rotation = at.linear();
  const int line = lines_.below_link(link, {use, "geometry"}, index);
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(g);
      s.kind = ShapeDesc::Kind::Box;
      s.size_m = vec(b.dim);
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      s.kind = ShapeDesc::Kind::Cylinder;
      s.size_m = {c.radius, c.radius, c.length};
      break;
    }
    case urdf::Geometry::SPHERE: {
      const auto& c = static_cast<const urdf::Sphere&>(g);
      s.kind = ShapeDesc::Kind::Sphere;
      s.size_m = Eigen::Vector3d::Constant(c.radius);
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      const int mesh_line = lines_.below_link(link, {use, "geometry", "mesh"}, index);
      std::string problem;
      const std::string file = resolve_mesh(m.filename, path_, mapping_, problem);
      if (!problem.empty()) {
        error(mesh_line, fmt::format("link '{}': {}", link, problem));
        return std::nullopt;
      }
      std::error_code ec;
      if (!fs::is_regular_file(file, ec)) {
        error(mesh_line, fmt::format("link '{}': mesh file '{}' not found ({})", link, m.filename, file));
        return std::nullopt;
      }
      MeshLoadResult loaded = load_mesh_scaled(file, UpAxis::Z, vec(m.scale));
      if (!loaded.error.empty()) {
        error(mesh_line, fmt::format("link '{}': mesh '{}': {}", link, m.filename, loaded.error));
        return std::nullopt;
      }
      s.kind = ShapeDesc::Kind::Mesh;
      s.mesh = std::move(loaded.mesh);
      Eigen::Vector3f lo, hi;
      mesh_bounds(s.mesh, lo, hi);
      UrdfImportDesc::Mesh report;
      report.link = link;
      report.use = use;
      report.file = m.filename;
      report.extent_m = (hi - lo).cast<double>();
      report.triangles = s.mesh.indices.size() / 3;
      if (triangles) *triangles = report.triangles;
      report.decision = std::string(use) == "visual" ? "drawn" : "trimesh";
      robot_.report.meshes.push_back(report);
      break;
    }
  }
  if (!(s.size_m.minCoeff() >= 0) || (s.kind != ShapeDesc::Kind::Mesh && !(s.size_m.minCoeff() > 0)))
    error(line, fmt::format("link '{}': a {} shape needs positive sizes", link, use));
  return s;
}

// A body mesh over its budget as its convex hull: the hull's faces fanned into triangles, a
// trimesh for ODE (docs/urdf.md says why not a dConvex), in the mesh's own frame.
std::optional<ShapeDesc> Importer::hull_of(const ShapeDesc& mesh, const std::string& link, int line,
                                           std::size_t triangles, std::size_t budget, UrdfImportDesc::Mesh& report) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.mesh.vertices.size());
  for (const auto& v : mesh.mesh.vertices) points.push_back(v.cast<double>());
  const ConvexHull hull = convex_hull(points);
  if (!hull.error.empty()) {
    error(line, fmt::format("link '{}': collision mesh '{}' has no convex hull ({}); it may be flat: use replace=\"box\" "
                            "or a mesh with volume",
                            link, report.file, hull.error));
    return std::nullopt;
  }
  ShapeDesc out = mesh;
  out.mesh = hull_triangles(hull);
  report.decision = fmt::format("convex hull, {} vertices, {} faces, {} triangles ({} triangles, over the budget of {})",
                                hull.vertices.size(), hull.faces.size(), out.mesh.indices.size() / 3, triangles, budget);
  return out;
}

void Importer::add_link(const urdf::Link& link, int body, const Iso& in_body, int caster) {
  Body& b = bodies_[static_cast<std::size_t>(body)];
  const Iso in_base = b.frame * in_body;
  robot_.links[link.name] = {in_base.translation(), in_base.linear(), body == 0};

  std::vector<ShapeDesc> own_collisions;
  for (std::size_t k = 0; k < link.collision_array.size(); ++k) {
    const auto& c = link.collision_array[k];
    if (!c->geometry) continue;
    std::size_t triangles = 0;
    auto s = shape_of(*c->geometry, link.name, "collision", static_cast<int>(k), pose_of(c->origin), &triangles);
    if (!s) continue;
    own_collisions.push_back(*s);
    PlacedShape placed{*s, link.name, lines_.below_link(link.name, {"collision"}, static_cast<int>(k))};
    placed.shape.position_m = in_body * s->position_m;
    placed.shape.rotation = in_body.linear() * s->rotation;
    if (caster >= 0) {
      placed.shape.position_m = in_base * s->position_m;
      placed.shape.rotation = in_base.linear() * s->rotation;
      caster_shapes_[static_cast<std::size_t>(caster)].push_back(placed);
      if (s->kind == ShapeDesc::Kind::Mesh) robot_.report.meshes.back().decision = "caster ball";
      continue;
    }
    if (b.wheel >= 0) {
      if (s->kind == ShapeDesc::Kind::Mesh) robot_.report.meshes.back().decision = "wheel cylinder";
    } else if (s->kind == ShapeDesc::Kind::Mesh) {
      const UrdfMapping::Collision* rule = collision_rule(link.name);
      const std::size_t budget = rule ? rule->max_triangles : 20000;
      auto& report = robot_.report.meshes.back();
      using Replace = UrdfMapping::Collision::Replace;
      if (triangles > budget && rule && rule->replace == Replace::Hull) {
        std::optional<ShapeDesc> hull = hull_of(*s, link.name, placed.line, triangles, budget, report);
        if (!hull) continue;
        placed.shape.mesh = std::move(hull->mesh);
      } else if (triangles > budget && rule && rule->replace == Replace::Box) {
        Eigen::Vector3f lo, hi;
        mesh_bounds(s->mesh, lo, hi);
        ShapeDesc box;
        box.kind = ShapeDesc::Kind::Box;
        box.size_m = (hi - lo).cast<double>();
        box.rotation = placed.shape.rotation;
        box.position_m = placed.shape.position_m + placed.shape.rotation * (0.5 * (hi + lo).cast<double>());
        placed.shape = box;
        report.decision = fmt::format("box {:.3g} x {:.3g} x {:.3g} m ({} triangles, over the budget of {})",
                                      box.size_m.x(), box.size_m.y(), box.size_m.z(), triangles, budget);
      } else if (triangles > budget) {
        warn(placed.line, fmt::format("link '{}': collision mesh '{}' has {} triangles, over the budget of {}: every "
                                      "contact test walks them; <collision link=\"{}\" replace=\"hull\"/> "
                                      "makes it its convex hull, replace=\"box\" its bounding box",
                                      link.name, report.file, triangles, budget, link.name));
        report.decision = fmt::format("trimesh ({} triangles, over the budget of {}, kept)", triangles, budget);
      } else {
        report.decision = fmt::format("trimesh ({} triangles, within the budget of {})", triangles, budget);
      }
    }
    b.collisions.push_back(placed);
  }

  std::vector<ShapeDesc> own_visuals;
  for (std::size_t k = 0; k < link.visual_array.size(); ++k) {
    const auto& v = link.visual_array[k];
    if (!v->geometry) continue;
    auto s = shape_of(*v->geometry, link.name, "visual", static_cast<int>(k), pose_of(v->origin), nullptr);
    if (!s) continue;
    PlacedShape placed{*s, link.name, lines_.below_link(link.name, {"visual"}, static_cast<int>(k))};
    placed.shape.position_m = in_body * s->position_m;
    placed.shape.rotation = in_body.linear() * s->rotation;
    Eigen::Vector4d rgba(0.7, 0.7, 0.7, 1.0);
    if (v->material) rgba = {v->material->color.r, v->material->color.g, v->material->color.b, v->material->color.a};
    b.visuals.push_back({placed, rgba});
    own_visuals.push_back(*s);
  }

  // The link's own mass: its <inertial>, checked, or one derived from a density. Its size, for
  // the radius of gyration, from its collision shapes or else its visuals.
  std::vector<Eigen::Vector3d> points;
  for (const auto& s : own_collisions.empty() ? own_visuals : own_collisions) shape_points(s, Iso::Identity(), points);
  const Bounds extent = bounds_of(points);
  const double size = extent.empty() ? 0.0 : (extent.hi - extent.lo).norm();
  const double density = density_for(link.name);
  std::string refused;
  int refused_line = lines_.link_line(link.name);
  MassProperties own;
  if (link.inertial) {
    const auto& in = *link.inertial;
    own.mass_kg = in.mass;
    own.inertia_kgm2 << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    own = place(own, pose_of(in.origin).translation(), pose_of(in.origin).linear());
    refused = non_physical_reason(own, size);
    refused_line = lines_.below_link(link.name, {"inertial", own.mass_kg > 0 ? "inertia" : "mass"});
  }
  if ((!refused.empty() || !link.inertial) && density > 0) {
    if (own_collisions.empty()) {
      error(lines_.link_line(link.name),
            fmt::format("link '{}': a density is given to derive its mass from, but it has no <collision> shape",
                        link.name));
      return;
    }
    own = MassProperties{};
    for (const auto& s : own_collisions) own = combine(own, place(solid_shape(s, density), s.position_m, s.rotation));
    warn(refused_line, fmt::format("link '{}': {}; mass and inertia derived from its collision shapes at {} kg/m^3: "
                                   "{:.4g} kg",
                                   link.name, link.inertial ? refused : "no <inertial>", density, own.mass_kg));
  } else if (!refused.empty()) {
    error(refused_line, fmt::format("link '{}': {}; fix the <inertial>, or give <density link=\"{}\" kg_per_m3=\"...\"/> "
                                    "to derive it from the collision shapes",
                                    link.name, refused, link.name));
    return;
  }
  if (own.mass_kg > 0) b.mass = combine(b.mass, place(own, in_body.translation(), in_body.linear()));
}

void Importer::visit(const urdf::Link& link, int body, const Iso& in_body, int caster) {
  for (std::size_t k = 0; k < mapping_.casters.size(); ++k)
    if (mapping_.casters[k].link == link.name) caster = static_cast<int>(k);
  const Body& on = bodies_[static_cast<std::size_t>(body)];
  if (caster >= 0 && on.live >= 0 && mapping_.casters[static_cast<std::size_t>(caster)].link == link.name) {
    const auto& m = mapping_.casters[static_cast<std::size_t>(caster)];
    diagnostics_.error(m.source.file, m.source.line,
                       fmt::format("caster link '{}' moves with joint '{}': a caster rides on the chassis; make that "
                                   "joint fixed, or hold it with <freeze>",
                                   link.name, on.joint));
    return;
  }
  add_link(link, body, in_body, caster);
  for (const auto& joint : link.child_joints) {
    const auto child = model_.getLink(joint->child_link_name);
    if (!child) continue;
    const int line = lines_.joint_line(joint->name);
    const Iso at = in_body * pose_of(joint->parent_to_joint_origin_transform);
    int child_caster = caster;  // a caster's swivel is its own: held, and lumped into the chassis
    for (std::size_t k = 0; k < mapping_.casters.size(); ++k)
      if (mapping_.casters[k].link == child->name) child_caster = static_cast<int>(k);
    const Eigen::Vector3d axis = vec(joint->axis).normalized();
    const auto wheel = std::find_if(mapping_.wheels.begin(), mapping_.wheels.end(),
                                    [&](const UrdfMapping::Wheel& w) { return w.joint == joint->name; });
    const auto freeze = std::find_if(mapping_.freezes.begin(), mapping_.freezes.end(),
                                     [&](const UrdfMapping::Freeze& f) { return f.joint == joint->name; });
    used_joints_.insert(joint->name);
    switch (joint->type) {
      case urdf::Joint::FLOATING:
      case urdf::Joint::PLANAR:
        error(line, fmt::format("joint '{}' is {}: a SEAR robot is one vehicle whose links hang on fixed, revolute, "
                                "continuous or prismatic joints; make it fixed, or a robot of its own",
                                joint->name, joint->type == urdf::Joint::FLOATING ? "floating" : "planar"));
        continue;
      case urdf::Joint::FIXED:
        visit(*child, body, at, caster);
        continue;
      default:
        break;
    }
    const bool prismatic = joint->type == urdf::Joint::PRISMATIC;
    if (child_caster >= 0 || freeze != mapping_.freezes.end()) {
      // Held where the mapping says (a caster's swivel and roller at their zero): part of its parent.
      const double q = freeze != mapping_.freezes.end() ? freeze->position : 0.0;
      Iso motion = Iso::Identity();
      if (prismatic) motion.translation() = q * axis;
      else motion.linear() = Eigen::AngleAxisd(q, axis).toRotationMatrix();
      visit(*child, body, at * motion, child_caster);
      continue;
    }
    if (wheel == mapping_.wheels.end()) {
      // Neither a wheel nor held: a live joint, passive unless a servo names it. Its child and
      // everything fixed below it become a body of their own, hinged or sliding on its parent.
      const Body& parent = bodies_[static_cast<std::size_t>(body)];
      if (parent.wheel >= 0) {
        error(line, fmt::format("joint '{}' hangs from wheel '{}': SEAR's wheel carries nothing that moves; make it "
                                "fixed, or hold it with <freeze joint=\"{}\"/>",
                                joint->name, mapping_.wheels[static_cast<std::size_t>(parent.wheel)].name, joint->name));
        continue;
      }
      JointLinkDesc live;
      live.joint = joint->name;
      live.link = child->name;
      live.source = {path_, line};
      live.parent = parent.live;
      std::vector<std::string> notes;
      for (const auto& problem : read_joint_motion(*joint, live, notes))
        error(line, fmt::format("joint '{}': {}", joint->name, problem));
      for (const auto& note : notes) warn(line, note);
      Body b;
      b.frame = parent.frame * at;
      b.joint = joint->name;
      b.first_link = child->name;
      b.live = static_cast<int>(robot_.joints.size());
      robot_.joints.push_back(live);
      bodies_.push_back(b);
      visit(*child, static_cast<int>(bodies_.size() - 1), Iso::Identity(), caster);
      continue;
    }
    if (prismatic || body != 0) {
      error(line, fmt::format("joint '{}' is mapped as wheel '{}', but {}", joint->name, wheel->name,
                              prismatic ? "it is prismatic: a wheel turns" : "it does not hang from the chassis"));
      visit(*child, body, at, caster);
      continue;
    }
    if (joint->type == urdf::Joint::REVOLUTE && joint->limits &&
        joint->limits->upper - joint->limits->lower < 2 * M_PI)
      error(line, fmt::format("joint '{}' is revolute with limits {:.4g}..{:.4g} rad: a wheel turns without end; "
                              "make it continuous",
                              joint->name, joint->limits->lower, joint->limits->upper));
    Body b;
    b.frame = bodies_[static_cast<std::size_t>(body)].frame * at;
    b.joint = joint->name;
    b.first_link = child->name;
    b.wheel = static_cast<int>(wheel - mapping_.wheels.begin());
    bodies_.push_back(b);
    visit(*child, static_cast<int>(bodies_.size() - 1), Iso::Identity(), caster);
  }
}

bool Importer::run() {
  const std::size_t errors_before = diagnostics_.count();
  const auto root = model_.getRoot();
  robot_.name = model_.getName();
  // Mapped names must be in the URDF.
  std::vector<std::string> joint_names, link_names;
  for (const auto& [name, j] : model_.joints_) joint_names.push_back(name);
  for (const auto& [name, l] : model_.links_) link_names.push_back(name);
  const auto known = [&](const SourceRef& at, const std::string& kind, const std::string& name,
                         const std::vector<std::string>& names) {
    // An empty name was reported where it was (missing), and is no URDF's.
    if (name.empty() || std::find(names.begin(), names.end(), name) != names.end()) return;
    diagnostics_.error(at.file, at.line,
                       fmt::format("the URDF '{}' has no {} '{}'{}", fs::path(path_).filename().string(), kind, name,
                                   did_you_mean(diagnostics_, name, names)));
  };
  for (const auto& w : mapping_.wheels) known(w.source, "joint", w.joint, joint_names);
  for (const auto& f : mapping_.freezes) known(f.source, "joint", f.joint, joint_names);
  for (const auto& c : mapping_.casters) known(c.source, "link", c.link, link_names);
  for (const auto& d : mapping_.densities)
    if (!d.link.empty()) known(d.source, "link", d.link, link_names);
  for (const auto& c : mapping_.collisions)
    if (!c.link.empty()) known(c.source, "link", c.link, link_names);
  if (diagnostics_.count() != errors_before) return false;

  bodies_.emplace_back();
  bodies_[0].first_link = root->name;
  caster_shapes_.resize(mapping_.casters.size());
  visit(*root, 0, Iso::Identity(), -1);
  if (diagnostics_.count() != errors_before) return false;

  // Every body needs a mass: a moving link with no inertial anywhere in it has none.
  for (const auto& b : bodies_) {
    if (b.mass.mass_kg > 0) continue;
    if (b.joint.empty())
      error(lines_.link_line(b.first_link),
            fmt::format("link '{}' (the chassis) has no <inertial>, and no link fixed to it has one: give one, or "
                        "<density kg_per_m3=\"...\"/> to derive it from the collision shapes",
                        b.first_link));
    else
      error(lines_.link_line(b.first_link),
            fmt::format("link '{}' moves (joint '{}') but has no <inertial>, and no link fixed to it has one: give one, "
                        "or <density link=\"{}\" kg_per_m3=\"...\"/> to derive it from the collision shapes",
                        b.first_link, b.joint, b.first_link));
  }
  if (diagnostics_.count() != errors_before) return false;

  // The chassis body sits at its centre of mass (ODE wants it there): everything on it moves by -com.
  Body& base = bodies_[0];
  const Eigen::Vector3d com = base.mass.com_m;
  const Iso to_com = Iso(Eigen::Translation3d(-com));
  robot_.report.base_origin_m = -com;
  for (auto& [name, frame] : robot_.links) frame.position_m -= com;
  ChassisDesc& chassis = robot_.chassis;
  chassis.shape = ChassisDesc::Shape::Parts;
  chassis.mass_kg = base.mass.mass_kg;
  chassis.given_inertia = true;
  chassis.inertia_kgm2 = base.mass.inertia_kgm2;
  chassis.material = mapping_.chassis_material;
  std::vector<Eigen::Vector3d> points;
  for (auto& p : base.collisions) {
    p.shape.position_m -= com;
    chassis.parts.push_back(p.shape);
    shape_points(p.shape, Iso::Identity(), points);
  }

  for (std::size_t i = 1; i < bodies_.size(); ++i) {
    if (bodies_[i].wheel >= 0) build_wheel(bodies_[i], to_com);
    else build_live(bodies_[i], to_com);
  }
  if (diagnostics_.count() != errors_before) return false;
  std::sort(robot_.wheels.begin(), robot_.wheels.end(), [&](const WheelDesc& a, const WheelDesc& b) {
    const auto index = [&](const WheelDesc& w) {
      return std::find_if(mapping_.wheels.begin(), mapping_.wheels.end(),
                          [&](const UrdfMapping::Wheel& m) { return m.name == w.name; }) -
             mapping_.wheels.begin();
    };
    return index(a) < index(b);
  });
  double wheel_ground = std::numeric_limits<double>::infinity();
  for (const auto& w : robot_.wheels) {
    wheel_ground = std::min(wheel_ground, w.position_m.z() - w.radius_m);
    shape_points(ShapeDesc{ShapeDesc::Kind::Sphere, w.position_m, Eigen::Matrix3d::Identity(),
                           Eigen::Vector3d::Constant(w.radius_m), {}},
                 Iso::Identity(), points);
  }

  for (std::size_t k = 0; k < mapping_.casters.size(); ++k) {
    const auto& m = mapping_.casters[k];
    std::vector<Eigen::Vector3d> cp;
    for (const auto& s : caster_shapes_[k]) shape_points(s.shape, to_com, cp);
    if (cp.empty()) {
      const auto it = robot_.links.find(m.link);
      if (m.radius_m > 0 && it != robot_.links.end()) cp.push_back(it->second.position_m - Eigen::Vector3d(0, 0, m.radius_m));
      else {
        diagnostics_.error(m.source.file, m.source.line,
                           fmt::format("caster link '{}' has no <collision> shape to size its ball from; give 'radius'",
                                       m.link));
        continue;
      }
    }
    const Bounds b = bounds_of(cp);
    CasterDesc caster;
    caster.radius_m = m.radius_m > 0 ? m.radius_m : 0.5 * (b.hi.z() - b.lo.z());
    const Eigen::Vector3d centre = 0.5 * (b.lo + b.hi);
    // The ball's lowest point stays where the URDF's shape has its own.
    caster.position_m = {centre.x(), centre.y(), b.lo.z() + caster.radius_m};
    robot_.casters.push_back(caster);
    shape_points(ShapeDesc{ShapeDesc::Kind::Sphere, caster.position_m, Eigen::Matrix3d::Identity(),
                           Eigen::Vector3d::Constant(caster.radius_m), {}},
                 Iso::Identity(), points);
  }

  // A body shape down where the tyres meet the ground drags along it: a caster modelled as a box.
  if (!robot_.wheels.empty())
    for (const auto& p : base.collisions) {
      std::vector<Eigen::Vector3d> pp;
      shape_points(p.shape, Iso::Identity(), pp);
      if (bounds_of(pp).lo.z() <= wheel_ground + kDragClearance_m)
        warn(p.line, fmt::format("link '{}': its collision shape reaches down to the ground the wheels stand on "
                                 "({:.3g} m below base_link): it will slide over the floor, with friction; if it is "
                                 "a caster, <caster link=\"{}\"/> makes it a ball that rolls",
                                 p.link, -(bounds_of(pp).lo.z() - com.z()), p.link));
    }

  const Bounds all = bounds_of(points);
  if (all.empty()) {
    chassis.size_m = Eigen::Vector3d::Constant(0.1);
    chassis.bottom_z_m = -0.05;
  } else {
    chassis.size_m = (all.hi - all.lo).cwiseMax(Eigen::Vector3d::Constant(1e-3));
    std::vector<Eigen::Vector3d> hull;
    for (const auto& s : chassis.parts) shape_points(s, Iso::Identity(), hull);
    chassis.bottom_z_m = hull.empty() ? all.lo.z() : bounds_of(hull).lo.z();
  }

  // Visuals, each in the frame of the body that carries it in the simulation.
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Iso sim_frame = to_com;  // base_link -> the chassis body (at the centre of mass)
    if (bodies_[i].live >= 0) {
      // A live link's body has its link's axes, moved to its centre of mass (build_live).
      sim_frame = Iso(Eigen::Translation3d(-bodies_[i].mass.com_m));
    } else if (bodies_[i].wheel >= 0) {
      const auto& name = mapping_.wheels[static_cast<std::size_t>(bodies_[i].wheel)].name;
      const auto w = std::find_if(robot_.wheels.begin(), robot_.wheels.end(),
                                  [&](const WheelDesc& d) { return d.name == name; });
      if (w == robot_.wheels.end()) continue;
      // SEAR's wheel body: at the axle centre, its z along the robot's y (as physics/vehicle builds it).
      const Iso wheel_frame = Iso(Eigen::Translation3d(w->position_m)) *
                              Iso(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()));
      sim_frame = wheel_frame.inverse() * to_com * bodies_[i].frame;
    }
    for (const auto& [v, rgba] : bodies_[i].visuals) {
      UrdfImportDesc::Visual out;
      out.body = bodies_[i].wheel >= 0
                     ? static_cast<int>(std::find_if(robot_.wheels.begin(), robot_.wheels.end(),
                                                     [&](const WheelDesc& d) {
                                                       return d.name ==
                                                              mapping_.wheels[static_cast<std::size_t>(bodies_[i].wheel)]
                                                                  .name;
                                                     }) -
                                        robot_.wheels.begin())
                     : -1;
      out.joint = bodies_[i].live;
      out.link = v.link;
      out.shape = v.shape;
      out.shape.position_m = sim_frame * v.shape.position_m;
      out.shape.rotation = sim_frame.linear() * v.shape.rotation;
      out.rgba = rgba;
      robot_.report.visuals.push_back(std::move(out));
    }
  }
  return diagnostics_.count() == errors_before;
}

void Importer::build_live(const Body& body, const Iso& to_chassis_com) {
  JointLinkDesc& j = robot_.joints[static_cast<std::size_t>(body.live)];
  const auto joint = model_.getJoint(body.joint);
  // ODE wants the body's origin at its centre of mass: the link's axes, moved to it.
  const Iso link = to_chassis_com * body.frame;
  const Eigen::Vector3d com = body.mass.com_m;
  j.position_m = link * com;
  j.rotation = link.linear();
  j.anchor_m = link.translation();
  j.axis = (link.linear() * vec(joint->axis)).normalized();
  j.mass_kg = body.mass.mass_kg;
  j.inertia_kgm2 = body.mass.inertia_kgm2;
  j.material = mapping_.chassis_material;
  for (const auto& p : body.collisions) {
    ShapeDesc s = p.shape;
    s.position_m -= com;
    j.parts.push_back(s);
  }
}

void Importer::build_wheel(Body& body, const Iso& to_chassis_com) {
  const auto& m = mapping_.wheels[static_cast<std::size_t>(body.wheel)];
  const auto joint = model_.getJoint(body.joint);
  const int line = lines_.joint_line(body.joint);
  const Eigen::Vector3d axis = vec(joint->axis).normalized();  // in the joint's (the body's) frame
  const Eigen::Vector3d axis_chassis = body.frame.linear() * axis;
  if (std::abs(axis_chassis.y()) < std::cos(kAxleTolerance_rad)) {
    error(line, fmt::format("wheel joint '{}' turns about ({:.3g}, {:.3g}, {:.3g}) in the base frame; SEAR's wheels turn "
                            "about the robot's y axis (left), to within {} rad",
                            body.joint, axis_chassis.x(), axis_chassis.y(), axis_chassis.z(), kAxleTolerance_rad));
    return;
  }
  // Its rolling shape comes from its collision shapes (or, lacking those, its visuals): a mesh
  // tyre would not roll smoothly, so it becomes SEAR's cylinder of the same radius and width.
  std::vector<Eigen::Vector3d> points;
  for (const auto& s : body.collisions) shape_points(s.shape, Iso::Identity(), points);
  if (points.empty())
    for (const auto& [v, rgba] : body.visuals) shape_points(v.shape, Iso::Identity(), points);
  if (points.empty()) {
    error(lines_.link_line(body.first_link),
          fmt::format("wheel link '{}' has no <collision> or <visual> shape to take its radius and width from",
                      body.first_link));
    return;
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, radius = 0;
  for (const auto& p : points) {
    const double along = p.dot(axis);
    lo = std::min(lo, along);
    hi = std::max(hi, along);
    radius = std::max(radius, (p - along * axis).norm());
  }
  WheelDesc w;
  w.name = m.name;
  w.source = m.source;
  w.material = m.material;
  w.radius_m = radius;
  w.width_m = std::max(hi - lo, 1e-3);
  w.position_m = to_chassis_com * (body.frame * (0.5 * (lo + hi) * axis));
  w.mass_kg = body.mass.mass_kg;
  // The inertia about the axle centre, turned into the wheel body's frame (z along the robot's y).
  const Eigen::Vector3d offset = body.mass.com_m - 0.5 * (lo + hi) * axis;
  MassProperties about_axle = body.mass;
  about_axle.inertia_kgm2 += body.mass.mass_kg * (offset.squaredNorm() * Eigen::Matrix3d::Identity() -
                                                   offset * offset.transpose());
  const Eigen::Matrix3d to_wheel =
      Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix().transpose() * body.frame.linear();
  w.given_inertia = true;
  w.inertia_kgm2 = to_wheel * about_axle.inertia_kgm2 * to_wheel.transpose();
  if (joint->dynamics) {
    w.joint_friction_nm = std::max(0.0, joint->dynamics->friction);
    w.joint_damping_nmps = std::max(0.0, joint->dynamics->damping);
  }
  if (offset.norm() > 1e-3)
    warn(lines_.below_link(body.first_link, {"inertial", "origin"}),
         fmt::format("wheel link '{}': its centre of mass is {:.3g} m off the axle; SEAR's wheel keeps it on the "
                     "axle (the inertia about the axle includes it)",
                     body.first_link, offset.norm()));
  robot_.wheels.push_back(w);
}

}  // namespace

bool expand_urdf_text(std::string& text, const std::string& path, const std::map<std::string, std::string>& args,
                      Diagnostics& diagnostics) {
  // Plain names first: ${NAME} and $(arg NAME), as a launch file would pass them.
  for (const auto& [name, value] : args)
    for (const std::string& pattern : {"${" + name + "}", "$(arg " + name + ")"})
      for (std::size_t at = text.find(pattern); at != std::string::npos; at = text.find(pattern, at + value.size()))
        text.replace(at, pattern.size(), value);
  bool ok = true;
  std::size_t reported = 0;
  for (const char* mark : {"${", "$("}) {
    for (std::size_t at = text.find(mark); at != std::string::npos && reported < 10; at = text.find(mark, at + 2)) {
      const std::size_t end = text.find_first_of("}) \"\n", at + 2);
      const std::string expr = text.substr(at, end == std::string::npos ? 20 : end + 1 - at);
      diagnostics.error(path, line_in(text, at),
                        fmt::format("unexpanded xacro expression '{}': xacro is not available in Debian 12, so SEAR "
                                    "reads only expanded URDF; expand it where xacro is installed (xacro "
                                    "robot.urdf.xacro > robot.urdf), or, for a plain name, give <arg name=\"...\" "
                                    "value=\"...\"/> in the robot's mapping or --arg NAME=VALUE on the command line",
                                    expr));
      ok = false;
      ++reported;
    }
  }
  const auto macro = text.find("<xacro:");
  if (ok && macro != std::string::npos) {
    diagnostics.error(path, line_in(text, macro),
                      "a <xacro:...> element: xacro is not available in Debian 12, so SEAR reads only expanded URDF; "
                      "expand it where xacro is installed (xacro robot.urdf.xacro > robot.urdf)");
    ok = false;
  }
  return ok;
}

bool import_urdf(const std::string& path, const UrdfMapping& mapping, Diagnostics& diagnostics, UrdfRobot& robot) {
  std::string text;
  if (!read_text_file(path, text)) {
    diagnostics.error(path, 0, "the URDF cannot be read");
    return false;
  }
  if (!check_utf8(text, path, diagnostics) || !expand_urdf_text(text, path, mapping.args, diagnostics)) return false;
  tinyxml2::XMLDocument doc;
  if (!parse_xml(text, path, diagnostics, doc)) return false;
  tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "robot") {
    diagnostics.error(path, root ? root->GetLineNum() : 1, "a URDF must have <robot> as its root element");
    return false;
  }
  robot.report.file = path;
  snap_angles(root, path, robot.report.warnings);
  tinyxml2::XMLPrinter printer;
  doc.Print(&printer);

  urdf::ModelInterfaceSharedPtr model;
  {
    CaptureLog log;
    model = urdf::parseURDF(printer.CStr());
    if (!model) {
      diagnostics.error(path, root->GetLineNum(),
                        fmt::format("urdfdom cannot read this URDF: {}",
                                    log.first_error.empty() ? "no reason given" : log.first_error));
      return false;
    }
  }
  UrdfLines lines(root);
  Importer importer(path, mapping, diagnostics, robot, *model, lines);
  return importer.run();
}

}  // namespace sear
