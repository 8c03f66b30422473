#include "cobra/planning/geometry.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <stdexcept>

namespace cobra::planning {

const char* toString(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::Box: return "box";
    case ShapeKind::Cylinder: return "cylinder";
    case ShapeKind::Capsule: return "capsule";
    case ShapeKind::Sphere: return "sphere";
    case ShapeKind::Mesh: return "mesh";
  }
  return "unknown";
}

namespace {

/// Appends every triangle of `node` and its children, in the scene's root frame.
void collectTriangles(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, double scale,
                      TriangleMesh& mesh) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    const aiMesh& part = *scene.mMeshes[node.mMeshes[i]];
    const std::size_t first_vertex = mesh.vertices.size();
    for (unsigned v = 0; v < part.mNumVertices; ++v) {
      const aiVector3D p = transform * part.mVertices[v];
      mesh.vertices.push_back({scale * p.x, scale * p.y, scale * p.z});
    }
    for (unsigned f = 0; f < part.mNumFaces; ++f) {
      const aiFace& face = part.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
      mesh.triangles.push_back({first_vertex + face.mIndices[0], first_vertex + face.mIndices[1],
                                first_vertex + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) collectTriangles(scene, *node.mChildren[c], transform, scale, mesh);
}

}  // namespace

TriangleMesh loadMesh(const std::filesystem::path& path, double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw std::invalid_argument("mesh '" + path.string() + "': scale must be a positive number (m per file unit)");
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw std::runtime_error("mesh file '" + path.string() +
                             "' not found: check the path (relative to the scene file)");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (scene == nullptr || scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0)
    throw std::runtime_error("mesh file '" + path.string() + "' could not be read as STL or OBJ: " +
                             importer.GetErrorString());
  TriangleMesh mesh;
  collectTriangles(*scene, *scene->mRootNode, aiMatrix4x4(), scale, mesh);
  if (mesh.triangles.empty())
    throw std::runtime_error("mesh file '" + path.string() + "' has no triangles: export the surface as a mesh");
  for (const auto& v : mesh.vertices)
    for (const double c : v)
      if (!std::isfinite(c)) throw std::runtime_error("mesh file '" + path.string() + "' has a non-finite vertex");
  return mesh;
}

}  // namespace cobra::planning
