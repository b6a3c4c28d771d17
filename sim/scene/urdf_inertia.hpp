// Mass properties of rigid links for the URDF import: lumping links that a fixed joint ties
// together into one body (parallel-axis theorem, rotated tensors), the checks that tell a real
// inertia from a placeholder, and the inertia of a uniform solid shape for a given density.
#pragma once

#include <Eigen/Core>
#include <string>

#include "scene/description.hpp"

namespace sear {

// A mass with its centre and its inertia tensor about that centre, both in one body's frame.
struct MassProperties {
  double mass_kg = 0;
  Eigen::Vector3d com_m{0, 0, 0};
  Eigen::Matrix3d inertia_kgm2 = Eigen::Matrix3d::Zero();
};

// `part` given in its own frame, which sits at `position` turned by `rotation` in the body frame.
MassProperties place(const MassProperties& part, const Eigen::Vector3d& position, const Eigen::Matrix3d& rotation);

// Two masses in one frame as one: the total about the joint centre of mass.
MassProperties combine(const MassProperties& a, const MassProperties& b);

// Why an inertia cannot belong to a real body, or empty when it can. `size_m` is the largest
// extent of the link's geometry (0: unknown, then the radius-of-gyration test is skipped).
std::string non_physical_reason(const MassProperties& m, double size_m);

// A uniform solid shape of `density_kg_m3`, about its centre in the shape's frame. A mesh is
// taken as its bounding box: meshes need not be closed, so their own volume is not reliable.
MassProperties solid_shape(const ShapeDesc& shape, double density_kg_m3);

}  // namespace sear
