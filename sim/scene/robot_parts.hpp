// Readers of robot parts that SEAR's robot files and a URDF's mapping write alike (robot_loader.cpp),
// and the reader of a project's <robot urdf="..."> (urdf_mapping.cpp).
#pragma once

#include <string>

#include "scene/description.hpp"
#include "scene/element_reader.hpp"
#include "scene/urdf_overrides.hpp"

namespace tinyxml2 {
class XMLElement;
}

namespace sear {

// A part's `material` attribute, which must name one of the world's materials.
std::string read_robot_material(ElementReader& r, const WorldDesc& world, const Diagnostics& diagnostics);
MotorDesc read_robot_motor(ElementReader& r);
ServoDesc read_robot_servo(ElementReader& r);
void read_robot_pose(ElementReader& r, const WorldDesc& world, RobotDesc& robot);
// A robot's <material>: joins the world's unless the world names it already.
void add_robot_material(ElementReader& r, WorldDesc& world);

// A project's <robot urdf="...">: the URDF's links and joints, the mapping (in the element or in
// the file its `mapping` names, then `overrides`), pose, script and MCUs. False when the URDF could
// not be read.
bool read_urdf_robot(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                     WorldDesc& world, RobotDesc& robot, const UrdfOverrides& overrides);

}  // namespace sear
