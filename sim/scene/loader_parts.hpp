// Pieces of the project loader shared between its files: one reader per top-level element.
#pragma once

#include <optional>
#include <string>

#include "scene/description.hpp"
#include "scene/element_reader.hpp"
#include "scene/urdf_overrides.hpp"

namespace tinyxml2 {
class XMLDocument;
class XMLElement;
}

namespace sear {

// A path written in `file`, taken relative to that file's folder.
std::string path_beside(const std::string& file, const std::string& relative);

// A <material> element.
Material read_material_element(ElementReader& r);

// The mesh named by an element's `file`, `up_axis` and `scale` attributes; errors name the element.
// `bounds_min`/`bounds_max` receive its bounding box when given.
TriangleMesh read_mesh_file(ElementReader& r, Eigen::Vector3f* bounds_min = nullptr,
                            Eigen::Vector3f* bounds_max = nullptr);

// Names of robots and obstacles become file names and column names: letters, digits, '_' and '-',
// at most ranges::kMaxNameLength of them.
void check_name(ElementReader& r, const std::string& name);

// Free text that goes into the summary (a project's or a material's name): UTF-8 with no control
// characters, at most 200 bytes. The file is valid UTF-8 already, but character references
// (&#1;, &#xD800;) can still put control characters or invalid code points into a value.
void check_label(ElementReader& r, const char* attribute, const std::string& text);

// The byte offset of the first byte of `text` that is not part of valid UTF-8 (overlong forms,
// surrogates and code points beyond U+10FFFF included), or npos when it is all valid.
std::size_t first_invalid_utf8(const std::string& text);

// Parses a file's text, checked UTF-8 first, into `doc`; false, with the error at its line, when
// it is not well-formed XML.
bool parse_xml(const std::string& xml, const std::string& path, Diagnostics& diagnostics, tinyxml2::XMLDocument& doc);

// The whole of a file: false when it cannot be opened or read.
bool read_text_file(const std::string& path, std::string& text);

// The whole of a file the user named as `what` ("project file", "scenario file"); empty, with the
// error given, when it is missing or cannot be read.
std::optional<std::string> read_named_file(const std::string& path, const char* what, Diagnostics& diagnostics);

// Reports, at its line, the first byte of `text` (the contents of `file`) that is not UTF-8.
// Project and robot files are read as UTF-8, whatever their XML declaration says: a Latin-1 name
// would otherwise reach summary.json and file names as bytes no JSON reader accepts.
bool check_utf8(const std::string& text, const std::string& file, Diagnostics& diagnostics);

// Checks that `path`, which `r`'s attribute `attribute` names as `relative`, is a regular file
// that can be read; reports "not found", "is a folder", ... at the element. `what` names it in
// messages ("mesh file", "firmware source").
bool check_readable_file(ElementReader& r, const std::string& what, const std::string& relative,
                         const std::string& path);

// Reports a second `kind` child of `element`: some elements may appear only once.
void check_at_most_one(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                       std::initializer_list<const char*> kinds);

void read_world(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                WorldDesc& world);

// A <robot> element of a project: inline, or naming a robot file with file="...". Materials the
// robot declares join the world's. False when an included robot file could not be read.
bool read_project_robot(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                        WorldDesc& world, RobotDesc& robot, const UrdfOverrides& overrides = {});

void read_script(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics,
                 std::vector<ScriptCommand>& script);

// An <mcu> element of a project's robot.
void read_mcu(const tinyxml2::XMLElement& element, const std::string& file, Diagnostics& diagnostics, McuDesc& mcu);

// Cross-checks of a robot's MCUs against its parts: names, pins and channels used once.
void validate_mcus(const RobotDesc& robot, Diagnostics& diagnostics);

// Cross-checks of one robot once all its parts are read (wiring, drive layout, script names).
void validate_robot(const RobotDesc& robot, Diagnostics& diagnostics);

// How far the robot's body (chassis, wheels, casters) reaches from its origin, in metres.
double robot_reach_m(const RobotDesc& robot);

// Warns of each sensor placed far outside its robot (a position in centimetres written as metres).
void warn_misplaced_devices(const RobotDesc& robot, Diagnostics& diagnostics);

}  // namespace sear
