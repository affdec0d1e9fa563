// Undulating terrain. See terrain.h.
#include "environment/terrain.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "model/units.h"

namespace chainsim {
namespace {
constexpr double kWallDepth = 0.02;  // walls reach this far below z = 0, m

double cell(const TerrainSpec& t) { return t.resolution_m > 0 ? t.resolution_m : t.wavelength_m / 24; }
}  // namespace

void validate_terrain(const TerrainSpec& t) {
  auto positive = [](const char* key, double v) {
    if (!(v > 0) || !std::isfinite(v)) {
      std::ostringstream s;
      s << key << " must be > 0 (is " << v << ")";
      throw std::invalid_argument(s.str());
    }
  };
  if (!(t.amplitude_m >= 0) || !std::isfinite(t.amplitude_m))
    throw std::invalid_argument("amplitude_m must be >= 0");
  positive("wavelength_m", t.wavelength_m);
  positive("width_m", t.width_m);
  positive("length_m", t.length_m);
  if (t.resolution_m < 0 || !std::isfinite(t.resolution_m))
    throw std::invalid_argument("resolution_m must be >= 0 (0 = automatic)");
  if (t.length_m / cell(t) > 200000) throw std::invalid_argument("resolution_m is too fine for length_m (> 200000 cells)");
  if (t.walls) {
    positive("wall_height_m", t.wall_height_m);
    positive("wall_thickness_m", t.wall_thickness_m);
  }
}

double terrain_height_m(const TerrainSpec& t, double x) {
  return t.amplitude_m * (1 - std::cos(2 * kPi * x / t.wavelength_m));
}

TriMesh terrain_mesh(const TerrainSpec& t) {
  validate_terrain(t);
  const int nx = std::max(1, static_cast<int>(std::ceil(t.length_m / cell(t))));
  const int ny = 4;
  TriMesh m;
  for (int i = 0; i <= nx; ++i) {
    const double x = -0.5 * t.length_m + t.length_m * i / nx;
    for (int j = 0; j <= ny; ++j) {
      const double y = -0.5 * t.width_m + t.width_m * j / ny;
      m.vertices.emplace_back(x, y, terrain_height_m(t, x));
    }
  }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(i * (ny + 1) + j); };
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      // counter-clockwise seen from above: normal up
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

std::vector<TerrainWall> terrain_walls(const TerrainSpec& t) {
  if (!t.walls) return {};
  const double top = 2 * t.amplitude_m + t.wall_height_m;
  const double h = top + kWallDepth;
  const double y = 0.5 * t.width_m + 0.5 * t.wall_thickness_m;
  const Eigen::Vector3d size(t.length_m, t.wall_thickness_m, h);
  return {{Eigen::Vector3d(0, y, top - 0.5 * h), size}, {Eigen::Vector3d(0, -y, top - 0.5 * h), size}};
}

}  // namespace chainsim
