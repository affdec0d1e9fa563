// Meshes through assimp. See mesh_loader.h.
#include "environment/mesh_loader.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>

namespace chainsim {

void TriMesh::append(const TriMesh& other) {
  const uint32_t base = static_cast<uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.triangles) triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

Eigen::Vector3d TriMesh::min_corner() const {
  Eigen::Vector3d m = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  for (const auto& v : vertices) m = m.cwiseMin(v);
  return m;
}

Eigen::Vector3d TriMesh::max_corner() const {
  Eigen::Vector3d m = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  for (const auto& v : vertices) m = m.cwiseMax(v);
  return m;
}

namespace {

// appends the triangles of node and its children, with their accumulated transform
void collect(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, double scale,
             TriMesh* out) {
  const aiMatrix4x4 t = parent * node->mTransformation;
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* m = scene->mMeshes[node->mMeshes[k]];
    const uint32_t base = static_cast<uint32_t>(out->vertices.size());
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D p = t * m->mVertices[v];
      out->vertices.emplace_back(scale * p.x, scale * p.y, scale * p.z);
    }
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      out->triangles.push_back(
          {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(scene, node->mChildren[c], t, scale, out);
}

}  // namespace

TriMesh load_mesh_file(const std::string& path, double scale) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw MeshError("mesh file '" + path + "': no such file");
  if (std::filesystem::is_directory(path, ec))
    throw MeshError("mesh file '" + path + "': is a directory");
  // a FIFO would block the reader, a device never end
  if (!std::filesystem::is_regular_file(path, ec))
    throw MeshError("mesh file '" + path + "': not a regular file (a FIFO or device)");
  constexpr uintmax_t kMaxMeshBytes = 256u << 20;
  if (const auto size = std::filesystem::file_size(path, ec); !ec && size > kMaxMeshBytes)
    throw MeshError("mesh file '" + path + "': " + std::to_string(size) + " bytes, over the limit of " +
                    std::to_string(kMaxMeshBytes));
  Assimp::Importer importer;
  // degenerate triangles become lines and points, which SortByPType drops
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_FindDegenerates |
                aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
    const std::string why = importer.GetErrorString();
    throw MeshError("mesh file '" + path + "': assimp cannot read it: " +
                    (why.empty() ? "incomplete scene" : why));
  }
  TriMesh out;
  collect(scene, scene->mRootNode, aiMatrix4x4(), scale, &out);
  if (out.triangles.empty()) throw MeshError("mesh file '" + path + "': has no triangles");
  for (const auto& v : out.vertices)
    if (!v.allFinite()) throw MeshError("mesh file '" + path + "': has non-finite vertex coordinates");
  return out;
}

void transform_mesh(TriMesh* mesh, const Eigen::Vector3d& translation_m,
                    const Eigen::Vector3d& rpy_rad) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(rpy_rad.z(), Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(rpy_rad.y(), Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(rpy_rad.x(), Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  for (auto& v : mesh->vertices) v = r * v + translation_m;
}

void write_stl(const TriMesh& mesh, const std::string& path, const std::string& header) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw MeshError("cannot write '" + path + "'");
  char head[80] = {};
  header.copy(head, sizeof head);
  f.write(head, sizeof head);
  const uint32_t n = static_cast<uint32_t>(mesh.triangles.size());
  f.write(reinterpret_cast<const char*>(&n), 4);  // little-endian hosts only (x86, ARM)
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    const Eigen::Vector3d& b = mesh.vertices[t[1]];
    const Eigen::Vector3d& c = mesh.vertices[t[2]];
    const Eigen::Vector3d nrm = (b - a).cross(c - a).normalized();
    float rec[12];
    for (int i = 0; i < 3; ++i) {
      rec[i] = static_cast<float>(nrm[i]);
      rec[3 + i] = static_cast<float>(a[i]);
      rec[6 + i] = static_cast<float>(b[i]);
      rec[9 + i] = static_cast<float>(c[i]);
    }
    f.write(reinterpret_cast<const char*>(rec), sizeof rec);
    const uint16_t attr = 0;
    f.write(reinterpret_cast<const char*>(&attr), 2);
  }
  if (!f) throw MeshError("cannot write '" + path + "'");
}

void write_obj(const TriMesh& mesh, const std::string& path, const std::string& comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw MeshError("cannot write '" + path + "'");
  std::fprintf(f, "# %s\n", comment.c_str());
  for (const auto& v : mesh.vertices) std::fprintf(f, "v %.6f %.6f %.6f\n", v.x(), v.y(), v.z());
  for (const auto& t : mesh.triangles) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw MeshError("cannot write '" + path + "'");
}

}  // namespace chainsim
