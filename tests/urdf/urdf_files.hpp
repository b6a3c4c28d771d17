// Hand-made URDF test robots and the mesh files they name, written into a test's own folder:
// ASCII STL boxes in millimetres and a COLLADA box that states its unit.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include "scene/urdf_import.hpp"

namespace sear::test {

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

// The 1-based line of the first line of `text` that holds `needle`: where an error must point.
inline int line_of(const std::string& text, const std::string& needle) {
  const auto at = text.find(needle);
  if (at == std::string::npos) {
    ADD_FAILURE() << "'" << needle << "' is not in the text";
    return -1;
  }
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// A box of sides sx, sy, sz centred on the origin, each face split into n x n squares (2 n^2
// triangles a face), as ASCII STL.
inline std::string box_stl(double sx, double sy, double sz, int n = 1) {
  std::string out = "solid box\n";
  const auto corner = [&](int axis, double sign, double u, double v) {
    double p[3];
    p[axis] = sign * 0.5 * (axis == 0 ? sx : axis == 1 ? sy : sz);
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const double side[3] = {sx, sy, sz};
    p[a] = (u - 0.5) * side[a];
    p[b] = (v - 0.5) * side[b];
    return fmt::format("{:.6f} {:.6f} {:.6f}", p[0], p[1], p[2]);
  };
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0})
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const double u0 = double(i) / n, u1 = double(i + 1) / n, v0 = double(j) / n, v1 = double(j + 1) / n;
          for (const auto& t : {std::array<std::pair<double, double>, 3>{{{u0, v0}, {u1, v0}, {u1, v1}}},
                                std::array<std::pair<double, double>, 3>{{{u0, v0}, {u1, v1}, {u0, v1}}}}) {
            out += "facet normal 0 0 0\n outer loop\n";
            // Outward winding on the + faces; reversed on the - faces.
            for (int k = 0; k < 3; ++k) {
              const auto& uv = t[static_cast<std::size_t>(sign > 0 ? k : 2 - k)];
              out += "  vertex " + corner(axis, sign, uv.first, uv.second) + "\n";
            }
            out += " endloop\nendfacet\n";
          }
        }
  return out + "endsolid box\n";
}

// A regular octahedron with its corners on the axes at `r` from the centre, as ASCII STL: 8
// faces, 6 corners, volume 4/3 r^3.
inline std::string octahedron_stl(double r) {
  std::string out = "solid octahedron\n";
  for (double sx : {1.0, -1.0})
    for (double sy : {1.0, -1.0})
      for (double sz : {1.0, -1.0}) {
        std::array<std::array<double, 3>, 3> c = {{{sx * r, 0, 0}, {0, sy * r, 0}, {0, 0, sz * r}}};
        if (sx * sy * sz < 0) std::swap(c[1], c[2]);  // outward winding
        out += fmt::format("facet normal {} {} {}\n outer loop\n", sx, sy, sz);
        for (const auto& p : c) out += fmt::format("  vertex {:.6f} {:.6f} {:.6f}\n", p[0], p[1], p[2]);
        out += " endloop\nendfacet\n";
      }
  return out + "endsolid octahedron\n";
}

// The same box as COLLADA, in the unit `meter` metres per file unit, Z up.
inline std::string box_dae(double sx, double sy, double sz, double meter) {
  const std::string stl = box_stl(sx, sy, sz);
  std::string positions;
  std::size_t count = 0;
  for (std::size_t at = stl.find("vertex "); at != std::string::npos; at = stl.find("vertex ", at + 1)) {
    positions += stl.substr(at + 7, stl.find('\n', at) - at - 7) + " ";
    ++count;
  }
  std::string indices;
  for (std::size_t i = 0; i < count; ++i) indices += std::to_string(i) + " ";
  return fmt::format(R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="unit" meter="{}"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="box"><mesh>
    <source id="pos"><float_array id="pos-array" count="{}">{}</float_array>
      <technique_common><accessor source="#pos-array" count="{}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="vtx"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="{}"><input semantic="VERTEX" source="#vtx" offset="0"/><p>{}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="n"><instance_geometry url="#box"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)",
                     meter, 3 * count, positions, count, count / 3, indices);
}

// A wheel link and its continuous joint on base_link, about y, with a cylinder tyre.
inline std::string wheel_xml(const std::string& name, double y, double radius = 0.045, double width = 0.025,
                             const std::string& inertial = R"(<inertial><mass value="0.06"/>
      <inertia ixx="3.35e-5" ixy="0" ixz="0" iyy="6.075e-5" iyz="0" izz="3.35e-5"/></inertial>)") {
  return fmt::format(R"(
  <link name="{0}_wheel">
    <collision><origin rpy="1.5707963267948966 0 0"/><geometry><cylinder radius="{2}" length="{3}"/></geometry></collision>
    {4}
  </link>
  <joint name="{0}_wheel_joint" type="continuous">
    <parent link="base_link"/><child link="{0}_wheel"/>
    <origin xyz="0 {1} 0"/><axis xyz="0 1 0"/>
  </joint>)",
                     name, y, radius, width, inertial);
}

// A 20 kg cart, so that a 0.2 kg link swinging on it barely moves it, on two free wheels and
// a ball caster at each end, with `extra` links and joints.
inline std::string rig_urdf(const std::string& extra) {
  return R"(<robot name="rig">
  <link name="base_link">
    <collision><geometry><box size="0.3 0.2 0.05"/></geometry></collision>
    <inertial><mass value="20"/><inertia ixx="0.0708" ixy="0" ixz="0" iyy="0.1542" iyz="0" izz="0.2167"/></inertial>
  </link>)" + wheel_xml("left", 0.12) + wheel_xml("right", -0.12) + R"(
  <link name="front_caster"><collision><geometry><sphere radius="0.0225"/></geometry></collision>
    <inertial><mass value="0.02"/><inertia ixx="4e-6" ixy="0" ixz="0" iyy="4e-6" iyz="0" izz="4e-6"/></inertial></link>
  <joint name="front_caster_joint" type="fixed"><parent link="base_link"/><child link="front_caster"/>
    <origin xyz="0.12 0 -0.0225"/></joint>
  <link name="rear_caster"><collision><geometry><sphere radius="0.0225"/></geometry></collision>
    <inertial><mass value="0.02"/><inertia ixx="4e-6" ixy="0" ixz="0" iyy="4e-6" iyz="0" izz="4e-6"/></inertial></link>
  <joint name="rear_caster_joint" type="fixed"><parent link="base_link"/><child link="rear_caster"/>
    <origin xyz="-0.12 0 -0.0225"/></joint>
)" + extra + "\n</robot>\n";
}

// Imports `text`, written as `name` in `dir`; the diagnostics say why when it fails.
struct Imported {
  bool ok = false;
  UrdfRobot robot;
  Diagnostics diagnostics;
  std::string path;
};

inline Imported import_text(const std::filesystem::path& dir, const std::string& text, const UrdfMapping& mapping = {},
                            const std::string& name = "robot.urdf") {
  Imported out;
  out.path = (dir / name).string();
  write_text(out.path, text);
  out.ok = import_urdf(out.path, mapping, out.diagnostics, out.robot);
  return out;
}

// The first diagnostic's "file:line: error: ..." text that holds `needle`, or "".
inline const Diagnostic* find_error(const Diagnostics& d, const std::string& needle) {
  for (const auto& e : d.all())
    if (e.message.find(needle) != std::string::npos) return &e;
  return nullptr;
}

inline const std::pair<SourceRef, std::string>* find_warning(const UrdfRobot& r, const std::string& needle) {
  for (const auto& w : r.report.warnings)
    if (w.second.find(needle) != std::string::npos) return &w;
  return nullptr;
}

}  // namespace sear::test
