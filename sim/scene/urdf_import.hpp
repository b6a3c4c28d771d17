// A URDF robot description turned into SEAR's chassis, wheels and casters: urdfdom reads the
// file, a SEAR mapping says what URDF cannot (which joints are wheels, which links are casters,
// frozen joints, densities, collision budgets), and every pitfall is a named error at its line.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "scene/description.hpp"
#include "scene/diagnostics.hpp"

namespace sear {

// What the project says about a URDF beyond the URDF itself.
struct UrdfMapping {
  std::map<std::string, std::string> packages;  // package:// name -> folder
  std::map<std::string, std::string> args;      // ${NAME} and $(arg NAME) -> text
  struct Wheel {
    SourceRef source;
    std::string name, joint, material = "default";
  };
  std::vector<Wheel> wheels;
  struct Caster {
    SourceRef source;
    std::string link;
    double radius_m = 0;  // 0: half the height of its collision shapes
  };
  std::vector<Caster> casters;
  struct Freeze {
    SourceRef source;
    std::string joint;
    double position = 0;  // rad or m
  };
  std::vector<Freeze> freezes;
  struct Density {
    SourceRef source;
    std::string link;  // empty: every link
    double kg_per_m3 = 0;
  };
  std::vector<Density> densities;
  // Body collision meshes with more triangles than the budget: kept (with a warning), boxed, or
  // replaced by their convex hull.
  struct Collision {
    enum class Replace { None, Box, Hull };
    SourceRef source;
    std::string link;  // empty: every link
    std::size_t max_triangles = 20000;
    Replace replace = Replace::None;
  };
  std::vector<Collision> collisions;
  std::string chassis_material = "default";
};

// A link's frame in the chassis frame, for mounting devices on it.
struct UrdfLinkFrame {
  Eigen::Vector3d position_m{0, 0, 0};
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  bool on_chassis = true;  // false: it moves with a wheel or a live joint
};

struct UrdfRobot {
  std::string name;
  ChassisDesc chassis;
  std::vector<WheelDesc> wheels;  // in the mapping's order
  std::vector<CasterDesc> casters;
  std::vector<JointLinkDesc> joints;  // moving joints that are no wheels, parents first
  std::map<std::string, UrdfLinkFrame> links;
  UrdfImportDesc report;
};

// The URDF text with the mapping's arguments substituted, or empty with an error when a xacro
// expression is left (xacro is not in Debian 12).
bool expand_urdf_text(std::string& text, const std::string& path, const std::map<std::string, std::string>& args,
                      Diagnostics& diagnostics);

// Reads `path`; false (with errors given) when it cannot become a SEAR robot.
bool import_urdf(const std::string& path, const UrdfMapping& mapping, Diagnostics& diagnostics, UrdfRobot& robot);

}  // namespace sear
