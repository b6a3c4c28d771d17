// The viewer's "scene" message (tools/view/PROTOCOL.md section 2): the world as loaded and each
// robot's body, physics shapes, sensors (how to draw what they see) and MCUs, from a ProjectDesc.
#pragma once

#include <string>

#include "scene/description.hpp"

namespace sear {

// Most triangles sent for one mesh (an obstacle's, or a mesh terrain); a bigger mesh is thinned
// to every k-th triangle, which keeps its outline and extent for a picture at a bounded size.
constexpr std::size_t kSceneMaxMeshTriangles = 20000;

// How the page draws what a device sees.
enum class SensorView { None, Cone, Fan, Gps };
SensorView sensor_view(const DeviceDesc& device);

// The power-up fan of a SICK LMS2xx in the mount frame (degrees counter-clockwise from the mount's
// +x): 180 degrees at 0.5 degree, -90 .. +90, as the model starts (lms2xx_default_config).
constexpr double kLmsStartDeg = -90.0;
constexpr double kLmsStepDeg = 0.5;
constexpr int kLmsCount = 361;

// The whole "scene" message, compact JSON, no trailing newline.
std::string scene_json(const ProjectDesc& project);

}  // namespace sear
