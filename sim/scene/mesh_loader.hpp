// Loads a triangle mesh for terrain, obstacles or a chassis with assimp (OBJ, STL, COLLADA,
// Ogre XML and every other format assimp reads), converted to SEAR's Z-up metres.
#pragma once

#include <string>

#include "scene/description.hpp"

namespace sear {

enum class UpAxis { Y, Z };

struct MeshLoadResult {
  TriangleMesh mesh;
  std::string error;  // empty on success
};

// `up` says which axis of the file points up; Y-up files are turned so that their Y becomes Z.
MeshLoadResult load_mesh(const std::string& path, UpAxis up, double scale);
// The same with a scale per axis (a URDF mesh's `scale`), applied after any unit the file states.
MeshLoadResult load_mesh_scaled(const std::string& path, UpAxis up, const Eigen::Vector3d& scale);

// Axis-aligned bounds of a loaded mesh.
void mesh_bounds(const TriangleMesh& mesh, Eigen::Vector3f& lo, Eigen::Vector3f& hi);

}  // namespace sear
