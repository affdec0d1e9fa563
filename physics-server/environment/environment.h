// What the chain moves in: an open-air plane, an undulating terrain between
// two walls (paper Fig. 12), a pipe network, or any mesh. Pure data, filled by
// the scene loader (scene_environment.cpp, keys in docs/scene-reference.md);
// environment_geoms.h turns it into ODE geoms.
//
// Frames: world z up, SI units. Surfaces: every part of the environment has a
// surface name; contacts between a surface and the modules ("module") use the
// pair table `contacts`, else WorldConfig::ground (material.h).
#pragma once

#include <Eigen/Core>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "environment/material.h"

namespace chainsim {

struct TriMesh;

enum class EnvironmentType { Plane, Terrain, Pipe, Mesh };

// one piece of a pipe network; pieces are joined end to end, each starting
// where the previous one ends, tangent to it
struct PipeSegment {
  // Split: a bullhead tee with swept outlets (a twin elbow): the pipe ends
  // against a wall and divides into two elbows turning opposite ways; the
  // network goes on along the one towards direction_deg, the other ends open
  enum class Type { Straight, Elbow, Tee, Split };
  Type type = Type::Straight;
  // Straight: length of the axis, m
  double length_m = 0.0;
  // Straight, first segment only: slope of the axis above the horizontal,
  // degrees (-90..90); NaN = the pipe's slope_deg
  double slope_deg = std::numeric_limits<double>::quiet_NaN();
  // Elbow, Split: radius of the axis's arc, m (> the pipe's inner radius)
  double bend_radius_m = 0.0;
  // Elbow, Split: angle turned, degrees (0..180]
  double angle_deg = 90.0;
  // Elbow, Tee, Split: which way the bend (the branch, the outlet the
  // network follows) goes, degrees about the pipe
  // axis: 0 = the pipe's "up" side (towards +z for a pipe that is not
  // vertical), 90 = left, 180 = down, 270 = right
  double direction_deg = 0.0;
  // Tee: length of the straight run through the junction, m (> inner diameter);
  // the branch leaves from the middle of the run
  double run_length_m = 0.0;
  // Tee: length of the branch from the run's axis, m (> inner radius)
  double branch_length_m = 0.0;
  // Tee: the network continues along the branch (else along the run); the
  // other way is an open stub
  bool follow_branch = false;
};

enum class PipeCollider {
  Analytic,  // exact cylinder and torus interiors (pipe_geom.h)
  Mesh,      // a triangle mesh of the bore, tessellated from the same pieces
};

struct PipeSpec {
  double inner_diameter_m = 0.03;
  PipeCollider collider = PipeCollider::Analytic;
  Eigen::Vector3d entry_m = Eigen::Vector3d::Zero();  // centre of the entry opening
  double heading_deg = 0.0;   // entry axis direction: about z from +x
  double slope_deg = 0.0;     // entry axis: above the horizontal (-90..90)
  std::vector<PipeSegment> segments;
  int mesh_segments = 32;     // mesh collider: vertices around the bore
  std::string surface = "pipe";
};

// z(x, y) = amplitude (1 - cos(2 pi x / wavelength)) for |x| <= length / 2,
// |y| <= width / 2: valleys at z = 0 (x = 0 is one), crests at 2 amplitude.
// Walls: two boxes along x just outside |y| = width / 2.
struct TerrainSpec {
  double amplitude_m = 0.02;
  double wavelength_m = 0.25;
  double width_m = 0.3;
  double length_m = 2.0;
  double resolution_m = 0.0;   // mesh cell length along x; 0 = wavelength / 24
  bool walls = true;
  double wall_height_m = 0.05;      // above the crests
  double wall_thickness_m = 0.01;
  std::string surface = "ground";
  std::string wall_surface = "wall";
};

struct MeshSpec {
  std::string file;          // as resolved (relative to the scene file's directory)
  std::string file_as_given; // as written in the scene
  double scale = 1.0;        // file units -> m
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();  // roll, pitch, yaw: R = Rz Ry Rx
  std::string surface = "mesh";
  // the loaded mesh, world frame (scaled and placed); empty = the World loads `file`
  std::shared_ptr<const TriMesh> data;
};

struct EnvironmentConfig {
  EnvironmentType type = EnvironmentType::Plane;
  bool ground_plane = false;  // also a plane z = 0 with Terrain, Pipe, Mesh (Plane always has it)
  std::string ground_surface = "ground";
  PipeSpec pipe;
  TerrainSpec terrain;
  MeshSpec mesh;
  // per-pair contact parameters; pairs not listed: environment-module
  // contacts use WorldConfig::ground, module-module WorldConfig::module_contact
  std::vector<MaterialPair> contacts;
};

const char* environment_type_name(EnvironmentType t);

// surface names this environment uses, in a fixed order
std::vector<std::string> environment_surfaces(const EnvironmentConfig& env);

// the pair (a, b) of the table (either order), else fallback
Material contact_material(const EnvironmentConfig& env, const std::string& a,
                          const std::string& b, const Material& fallback);

// the environment's triangle mesh when it uses one (mesh, terrain surface, mesh
// pipe), world frame; loads a mesh file if MeshSpec::data is empty. Throws
// MeshError or std::invalid_argument.
std::shared_ptr<const TriMesh> environment_mesh(const EnvironmentConfig& env);

}  // namespace chainsim
