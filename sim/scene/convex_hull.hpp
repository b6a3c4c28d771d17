// The convex hull of a mesh's points, by Debian's qhull (libqhull_r): a collision shape that
// stands in for a mesh of many triangles (a URDF mapping's replace="hull").
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/description.hpp"

namespace sear {

struct ConvexHull {
  std::vector<Eigen::Vector3d> vertices;  // the hull's corners, in the order of the points given
  struct Face {
    Eigen::Vector3d normal{0, 0, 1};      // unit, outward
    double offset = 0;                    // normal . x = offset on the face
    std::vector<std::uint32_t> corners;   // into `vertices`, counter-clockwise seen from outside
  };
  std::vector<Face> faces;                // coplanar facets merged: a cube has six
  std::string error;                      // empty on success (qhull's reason otherwise: flat, too few points)
};

ConvexHull convex_hull(const std::vector<Eigen::Vector3d>& points);

// The hull's faces fanned into triangles, outward wound, over its vertices.
TriangleMesh hull_triangles(const ConvexHull& hull);

// Its volume, from its faces (the divergence theorem over the fanned triangles).
double hull_volume(const ConvexHull& hull);

}  // namespace sear
