#include "scene/mesh_loader.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <limits>

namespace sear {

MeshLoadResult load_mesh(const std::string& path, UpAxis up, double scale) {
  return load_mesh_scaled(path, up, Eigen::Vector3d::Constant(scale));
}

MeshLoadResult load_mesh_scaled(const std::string& path, UpAxis up, const Eigen::Vector3d& scale) {
  MeshLoadResult out;
  Assimp::Importer importer;
  // A COLLADA file states its own up axis; we take the user's word (up_axis attribute) for every
  // format alike, so assimp must not rotate COLLADA scenes on its own.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                aiProcess_SortByPType | aiProcess_FindDegenerates);
  if (!scene || !scene->mRootNode) {
    out.error = fmt::format("cannot load mesh: {}", importer.GetErrorString());
    return out;
  }
  // A COLLADA file's <unit> reaches the vertices through its root node's transform, which
  // aiProcess_PreTransformVertices applies; the per-axis scale (a URDF's) comes after it.
  const Eigen::Vector3f s = scale.cast<float>();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const auto base = static_cast<std::uint32_t>(out.mesh.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      // Y-up to Z-up is a +90 degree turn about X: (x, y, z) -> (x, -z, y); it keeps the winding.
      out.mesh.vertices.emplace_back((up == UpAxis::Z ? Eigen::Vector3f(p.x, p.y, p.z) : Eigen::Vector3f(p.x, -p.z, p.y))
                                         .cwiseProduct(s));
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      for (int k = 0; k < 3; ++k) out.mesh.indices.push_back(base + face.mIndices[k]);
    }
  }
  if (out.mesh.indices.empty()) out.error = "mesh has no triangles";
  return out;
}

void mesh_bounds(const TriangleMesh& mesh, Eigen::Vector3f& lo, Eigen::Vector3f& hi) {
  lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  for (const auto& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
}

}  // namespace sear
