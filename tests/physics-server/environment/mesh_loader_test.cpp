// Meshes through assimp: what we write (STL, OBJ) reads back the same; PLY
// and glTF read; missing and broken files give errors naming the file and
// assimp's reason; a mesh environment collides.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "environment/mesh_loader.h"
#include "environment/pipe_mesh.h"
#include "environment/pipe_path.h"
#include "physics/world.h"
#include "world_of.h"

namespace chainsim {
namespace {

// a directory of this test process, removed at exit
struct TempDir {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("chainsim_mesh_test_" + std::to_string(::getpid()));
  TempDir() { std::filesystem::create_directories(dir); }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

std::string temp_path(const std::string& name) {
  static TempDir temp;
  return (temp.dir / name).string();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
}

std::string error_of(const std::string& path) {
  try {
    load_mesh_file(path);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "(no error)";
}

PipeLayout small_pipe() {
  PipeSpec p;
  p.inner_diameter_m = 0.03;
  PipeSegment s;
  s.length_m = 0.1;
  p.segments = {s};
  return layout_pipe(p);
}

// a mesh over the triangle bound is refused with its count and the bound
TEST(MeshLoader, MeshOverTheTriangleBoundIsRefused) {
  const TriMesh m = pipe_solid_mesh(small_pipe(), 16, 0.002);
  const std::string path = temp_path("bound.stl");
  write_stl(m, path, "test");
  const size_t n = m.triangles.size();
  EXPECT_EQ(load_mesh_file(path, 1.0, n).triangles.size(), n);
  try {
    load_mesh_file(path, 1.0, n - 1);
    FAIL() << "no error";
  } catch (const MeshError& e) {
    EXPECT_EQ(std::string(e.what()), "mesh file '" + path + "': " + std::to_string(n) +
                                         " faces, over the limit of " + std::to_string(n - 1));
  }
}

TEST(MeshLoader, StlAndObjRoundTrip) {
  const TriMesh m = pipe_solid_mesh(small_pipe(), 16, 0.002);
  for (const std::string ext : {"stl", "obj"}) {
    const std::string path = temp_path("pipe." + ext);
    if (ext == "stl")
      write_stl(m, path, "test");
    else
      write_obj(m, path, "test");
    const TriMesh back = load_mesh_file(path, 2.0);
    EXPECT_EQ(back.triangles.size(), m.triangles.size()) << ext;
    EXPECT_NEAR((back.max_corner() - 2.0 * m.max_corner()).norm(), 0, 1e-6) << ext;
    EXPECT_NEAR((back.min_corner() - 2.0 * m.min_corner()).norm(), 0, 1e-6) << ext;
    // winding kept: the first triangle's normal is the same
    const auto& a = m.triangles[0];
    const auto& b = back.triangles[0];
    const Eigen::Vector3d na = (m.vertices[a[1]] - m.vertices[a[0]]).cross(m.vertices[a[2]] - m.vertices[a[0]]);
    const Eigen::Vector3d nb =
        (back.vertices[b[1]] - back.vertices[b[0]]).cross(back.vertices[b[2]] - back.vertices[b[0]]);
    EXPECT_GT(na.normalized().dot(nb.normalized()), 0.999) << ext;
  }
}

TEST(MeshLoader, PlyAndGltfRead) {
  const std::string ply = temp_path("tri.ply");
  write_text(ply,
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
             "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(load_mesh_file(ply).triangles.size(), 1u);
  // one triangle, positions in an embedded buffer (3 x vec3 float = 36 bytes)
  const std::string gltf = temp_path("tri.gltf");
  write_text(gltf, R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
 "nodes":[{"mesh":0,"translation":[0,0,1]}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}]})");
  const TriMesh g = load_mesh_file(gltf);
  ASSERT_EQ(g.triangles.size(), 1u);
  EXPECT_NEAR(g.min_corner().z(), 1.0, 1e-6);  // the node's translation applied
}

TEST(MeshLoader, MissingAndBrokenFilesAreNamedWithTheReason) {
  const std::string missing = temp_path("nope.stl");
  std::string e = error_of(missing);
  EXPECT_NE(e.find(missing), std::string::npos) << e;
  EXPECT_NE(e.find("no such file"), std::string::npos) << e;

  const std::string garbage = temp_path("garbage.stl");
  write_text(garbage, "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0\n");  // truncated ASCII STL
  e = error_of(garbage);
  EXPECT_NE(e.find(garbage), std::string::npos) << e;
  EXPECT_NE(e.find("assimp"), std::string::npos) << e;

  const std::string unknown = temp_path("what.xyzw");
  write_text(unknown, "\x01\x02\x03 not a mesh");
  e = error_of(unknown);
  EXPECT_NE(e.find(unknown), std::string::npos) << e;
  EXPECT_NE(e.find("assimp"), std::string::npos) << e;

  const std::string points = temp_path("points.obj");
  write_text(points, "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  e = error_of(points);
  EXPECT_NE(e.find(points), std::string::npos) << e;
}

// a mesh environment: a box-shaped floor read from an OBJ carries a module
TEST(MeshLoader, MeshEnvironmentCarriesAModule) {
  const std::string floor = temp_path("floor.obj");
  write_text(floor,
             "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n");
  WorldConfig c;
  c.environment.type = EnvironmentType::Mesh;
  c.environment.ground_plane = false;
  c.environment.mesh.file = floor;
  c.environment.mesh.position_m = Eigen::Vector3d(0, 0, 0.1);
  c.head_position = Eigen::Vector3d(0, 0, 0.125);
  World w = world_of(c, {"passive"});
  for (int k = 0; k < 1000; ++k) w.step();
  EXPECT_NEAR(w.body_state(0, 0).position.z(), 0.112, 0.001);  // resting on the mesh at z = 0.1

  c.environment.mesh.file = temp_path("nope.obj");
  try {
    World bad = world_of(c, {"passive"});
    FAIL() << "no error";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.obj"), std::string::npos);
  }
}

}  // namespace
}  // namespace chainsim
