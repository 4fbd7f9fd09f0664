#include "aar_geometry/mesh_io.h"

#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "aar_geometry/load_error.h"
#include "mesh_check.h"

namespace aar_geometry {

namespace {

Eigen::Matrix4d ToEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d out;
  out << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return out;
}

std::string PartName(const aiScene& scene, const aiNode& node, unsigned mesh_index) {
  const aiMesh& mesh = *scene.mMeshes[mesh_index];
  std::string name = node.mName.length > 0 ? node.mName.C_Str() : "";
  if (name.empty() || &node == scene.mRootNode) {
    name = mesh.mName.length > 0 ? mesh.mName.C_Str() : "mesh" + std::to_string(mesh_index);
  }
  return name;
}

void AddNode(const aiScene& scene, const aiNode& node, const Eigen::Matrix4d& parent_transform,
             TriangleMesh& out) {
  const Eigen::Matrix4d transform = parent_transform * ToEigen(node.mTransformation);
  const Eigen::Matrix3d linear = transform.topLeftCorner<3, 3>();
  const bool mirrored = linear.determinant() < 0.0;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[i]];
    if (!(mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    const int part = out.AddPart(PartName(scene, node, node.mMeshes[i]));
    const int offset = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      out.vertices.push_back((transform * Eigen::Vector4d(p.x, p.y, p.z, 1.0)).head<3>());
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines left over from triangulation
      Eigen::Vector3i tri(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
      if (mirrored) std::swap(tri[1], tri[2]);
      out.triangles.push_back(tri.array() + offset);
      out.triangle_parts.push_back(part);
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    AddNode(scene, *node.mChildren[c], transform, out);
  }
}

}  // namespace

TriangleMesh LoadMesh(const std::string& path) {
  CheckReadableFile(path);
  CheckMeshStructure(path);

  Assimp::Importer importer;
  // Keep the file's axes: ROS models are authored z-up and must not be turned to y-up.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    throw LoadError(path, std::string("not a readable mesh: ") + importer.GetErrorString());
  }
  if (scene->mRootNode == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    throw LoadError(path, "mesh file is incomplete");
  }
  // Debian's assimp is built with assertions on, and its triangulation aborts the process on a
  // mesh whose primitive-type flags disagree with its faces (a truncated PLY makes one). Set the
  // flags from the faces themselves before triangulating.
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    aiMesh& mesh = *scene->mMeshes[m];
    unsigned types = 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const unsigned n = mesh.mFaces[f].mNumIndices;
      if (n == 0)
        throw LoadError(path, "mesh " + std::to_string(m) + " has a face with no vertices");
      types |= n == 1   ? aiPrimitiveType_POINT
               : n == 2 ? aiPrimitiveType_LINE
               : n == 3 ? aiPrimitiveType_TRIANGLE
                        : aiPrimitiveType_POLYGON;
    }
    mesh.mPrimitiveTypes = types;
  }
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
  if (scene == nullptr) {
    throw LoadError(path, std::string("cannot triangulate: ") + importer.GetErrorString());
  }

  TriangleMesh mesh;
  AddNode(*scene, *scene->mRootNode, Eigen::Matrix4d::Identity(), mesh);
  if (mesh.triangles.empty()) throw LoadError(path, "contains no triangles");
  try {
    mesh.Validate();
  } catch (const std::invalid_argument& e) {
    throw LoadError(path, e.what());
  }
  return mesh;
}

void WriteObj(const std::string& path, const TriangleMesh& mesh, const std::string& comment) {
  mesh.Validate();
  std::ofstream out(path);
  if (!out) throw LoadError(path, "cannot be written");
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  for (const auto& name : mesh.part_names) {
    if (name.empty() || name.find_first_of("\r\n") != std::string::npos) {
      throw LoadError(path, "part name '" + name + "' cannot be written as an OBJ object name");
    }
  }
  out << std::fixed << std::setprecision(6);
  for (const auto& v : mesh.vertices) out << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << "\n";
  // Faces grouped by part, parts in their order, so each part is one OBJ object.
  for (size_t p = 0; p < mesh.part_names.size(); ++p) {
    out << "o " << mesh.part_names[p] << "\n";
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      if (mesh.triangle_parts[t] != static_cast<int>(p)) continue;
      const auto& f = mesh.triangles[t];
      out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << "\n";
    }
  }
  if (!out) throw LoadError(path, "write failed");
}

}  // namespace aar_geometry
