#include "core/mesh_file.h"

#include <cmath>

#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include "core/errors.h"
#include "core/files.h"

namespace causticbench {

namespace {

// Refuses a mesh file with a vertex or normal that is not finite, or a vertex beyond kMaximumCoordinate,
// naming the scene line that names the file, the vertex and what was expected.
void check_mesh_vertices(const aiScene* scene, const std::string& path, const SourceLocation& where) {
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* part = scene->mMeshes[m];
    for (unsigned v = 0; v < part->mNumVertices; ++v) {
      const aiVector3D& p = part->mVertices[v];
      bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
      if (!finite || std::abs(p.x) > kMaximumCoordinate || std::abs(p.y) > kMaximumCoordinate ||
          std::abs(p.z) > kMaximumCoordinate) {
        throw InputError(fmt::format("{}: mesh '{}': vertex {} of part {} is ({}, {}, {}): expected finite coordinates "
                                     "within +-{:g} (single-precision geometry stops resolving the scene beyond that; "
                                     "fit_size cannot help, since normals are computed before it scales the mesh)",
                                     where.describe(), path, v, m, p.x, p.y, p.z, kMaximumCoordinate));
      }
      if (part->mNormals) {
        const aiVector3D& n = part->mNormals[v];
        if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) {
          throw InputError(fmt::format("{}: mesh '{}': the normal of vertex {} of part {} is ({}, {}, {}): expected "
                                       "finite numbers",
                                       where.describe(), path, v, m, n.x, n.y, n.z));
        }
      }
    }
  }
}

}  // namespace

std::shared_ptr<const TriangleMesh> load_mesh(const std::string& path, bool smooth_normals, double fit_size,
                                              const SourceLocation& where) {
  Assimp::Importer importer;
  {
    // The raw vertices first, in a read of their own: Assimp computes smooth normals in float on the
    // unscaled mesh within the read below (before it joins vertices, which keeps the normals the meshes
    // always had), so a NaN or a coordinate of 1e30 would poison them before fit_size could scale it.
    Assimp::Importer raw;
    if (const aiScene* unprocessed = raw.ReadFile(path, aiProcess_PreTransformVertices))
      check_mesh_vertices(unprocessed, path, where);
  }
  unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices;
  if (smooth_normals) flags |= aiProcess_GenSmoothNormals;
  const aiScene* scene = importer.ReadFile(path, flags);
  if (!scene || !scene->mRootNode || scene->mNumMeshes == 0) {
    std::string reason = importer.GetErrorString();
    if (reason.empty()) reason = "the file holds no mesh Assimp can read (no faces, or not a mesh format)";
    throw InputError(fmt::format("{}: cannot read mesh '{}': {}", where.describe(), path, reason));
  }

  auto mesh = std::make_shared<TriangleMesh>();
  mesh->smooth = smooth_normals;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* part = scene->mMeshes[m];
    uint32_t base = static_cast<uint32_t>(mesh->positions.size());
    for (unsigned v = 0; v < part->mNumVertices; ++v) {
      const aiVector3D& p = part->mVertices[v];
      mesh->positions.emplace_back(p.x, p.y, p.z);
      if (part->mNormals) {
        const aiVector3D& n = part->mNormals[v];
        mesh->normals.emplace_back(n.x, n.y, n.z);
      } else {
        mesh->normals.emplace_back(0.0f, 1.0f, 0.0f);
      }
    }
    for (unsigned f = 0; f < part->mNumFaces; ++f) {
      const aiFace& face = part->mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh->triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
    }
  }
  if (mesh->triangles.empty()) throw InputError(fmt::format("{}: mesh '{}' has no triangles", where.describe(), path));
  if (fit_size > 0.0) {
    // Scale the largest extent to fit_size, centre in x and z, and stand the mesh on y = 0.
    Vec3 lower(1e30f), upper(-1e30f);
    for (const Vec3& p : mesh->positions) {
      lower = glm::min(lower, p);
      upper = glm::max(upper, p);
    }
    Vec3 extent = upper - lower;
    float scale = static_cast<float>(fit_size) / std::max(1e-12f, max_component(extent));
    Vec3 offset(-(lower.x + upper.x) * 0.5f, -lower.y, -(lower.z + upper.z) * 0.5f);
    for (Vec3& p : mesh->positions) p = (p + offset) * scale;
  }
  if (!smooth_normals) mesh->compute_flat_normals();
  mesh->orient_by_normals();
  return mesh;
}

void write_mesh_ply(const TriangleMesh& mesh, const std::string& path) {
  // aiScene's destructor frees what it points to: everything below is allocated with new[] for it.
  aiScene scene;
  scene.mRootNode = new aiNode();
  scene.mRootNode->mNumMeshes = 1;
  scene.mRootNode->mMeshes = new unsigned[1]{0};
  scene.mNumMaterials = 1;
  scene.mMaterials = new aiMaterial*[1]{new aiMaterial()};
  auto* part = new aiMesh();
  scene.mNumMeshes = 1;
  scene.mMeshes = new aiMesh*[1]{part};
  part->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  part->mNumVertices = static_cast<unsigned>(mesh.positions.size());
  part->mVertices = new aiVector3D[mesh.positions.size()];
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    part->mVertices[v] = aiVector3D(mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z);
  if (mesh.normals.size() == mesh.positions.size()) {
    part->mNormals = new aiVector3D[mesh.normals.size()];
    for (size_t v = 0; v < mesh.normals.size(); ++v)
      part->mNormals[v] = aiVector3D(mesh.normals[v].x, mesh.normals[v].y, mesh.normals[v].z);
  }
  part->mNumFaces = static_cast<unsigned>(mesh.triangles.size());
  part->mFaces = new aiFace[mesh.triangles.size()];
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    part->mFaces[t].mNumIndices = 3;
    part->mFaces[t].mIndices = new unsigned[3]{mesh.triangles[t].x, mesh.triangles[t].y, mesh.triangles[t].z};
  }
  write_file_atomically_with(path, [&](const std::string& temporary) {
    Assimp::Exporter exporter;
    if (exporter.Export(&scene, "plyb", temporary) != aiReturn_SUCCESS)
      throw WriteError(fmt::format("{}: cannot write the mesh: {}", path, exporter.GetErrorString()));
  });
}

}  // namespace causticbench
