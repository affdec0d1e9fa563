// The undulating terrain of the paper's Fig. 12 (TerrainSpec, environment.h):
// its height function and its triangle mesh. The walls are boxes (environment_geoms.cpp).
#pragma once

#include "environment/environment.h"
#include "environment/mesh_loader.h"

namespace chainsim {

// terrain surface height at x, m (constant across y)
double terrain_height_m(const TerrainSpec& t, double x);

// the surface as triangles facing up: cells of resolution_m along x (auto:
// wavelength / 24) and about 4 cells across
TriMesh terrain_mesh(const TerrainSpec& t);

// the two walls as (centre, full size) boxes; empty without walls
struct TerrainWall {
  Eigen::Vector3d centre_m, size_m;
};
std::vector<TerrainWall> terrain_walls(const TerrainSpec& t);

// throws std::invalid_argument naming the key of the first bad parameter
void validate_terrain(const TerrainSpec& t);

}  // namespace chainsim
