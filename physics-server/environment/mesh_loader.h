// Triangle meshes for environments: loaded from files through assimp (STL,
// OBJ, PLY, glTF and whatever else assimp reads) or generated (pipe_mesh.h,
// terrain.h), and written as STL or OBJ (the example meshes, the viewer).
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

// an indexed triangle mesh; a triangle's front side (its normal) is counter-
// clockwise: the side a body should stay on (a pipe's bore, a terrain's top)
struct TriMesh {
  std::vector<Eigen::Vector3d> vertices;        // m
  std::vector<std::array<uint32_t, 3>> triangles;  // vertex indices
  void append(const TriMesh& other);
  Eigen::Vector3d min_corner() const;
  Eigen::Vector3d max_corner() const;
};

class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// every mesh of the file's scene, node transforms applied, triangulated,
// points and lines dropped; times scale. Throws MeshError naming the file and
// assimp's reason (missing file, unknown format, broken data, no triangles),
// or the bound when it has more than max_triangles triangles.
constexpr size_t kMaxMeshTriangles = 4000000;  // a 256 MiB binary STL holds 5.6 million
TriMesh load_mesh_file(const std::string& path, double scale = 1.0, size_t max_triangles = kMaxMeshTriangles);

// v' = R(rpy) v + t, with R = Rz(yaw) Ry(pitch) Rx(roll) (radians)
void transform_mesh(TriMesh* mesh, const Eigen::Vector3d& translation_m,
                    const Eigen::Vector3d& rpy_rad);

// binary STL; throws MeshError if the file cannot be written
void write_stl(const TriMesh& mesh, const std::string& path, const std::string& header);
// Wavefront OBJ (vertices and faces only); throws MeshError if the file cannot be written
void write_obj(const TriMesh& mesh, const std::string& path, const std::string& comment);

}  // namespace chainsim
