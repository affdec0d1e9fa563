// Environment geoms. See environment_geoms.h.
#include "environment/environment_geoms.h"

#include <algorithm>
#include <stdexcept>

#include "environment/pipe_geom.h"
#include "environment/terrain.h"

namespace chainsim {

EnvironmentGeoms::EnvironmentGeoms(const EnvironmentConfig& cfg, dSpaceID space)
    : surfaces_(environment_surfaces(cfg)) {
  // everything that can fail, before the first geom
  if (cfg.type == EnvironmentType::Pipe) pipe_ = std::make_unique<PipeLayout>(layout_pipe(cfg.pipe));
  if (cfg.type == EnvironmentType::Terrain) validate_terrain(cfg.terrain);
  mesh_ = environment_mesh(cfg);
  if (mesh_) {
    mesh_index_.reserve(3 * mesh_->triangles.size());
    for (const auto& t : mesh_->triangles)
      for (uint32_t i : t) {
        if (i >= mesh_->vertices.size()) throw std::invalid_argument("mesh: vertex index out of range");
        mesh_index_.push_back(static_cast<int>(i));
      }
  }

  if (cfg.type == EnvironmentType::Plane || cfg.ground_plane)
    add(dCreatePlane(space, 0, 0, 1, 0), cfg.ground_surface);
  if (mesh_) {
    static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "packed vertices");
    tri_data_ = dGeomTriMeshDataCreate();
    dGeomTriMeshDataBuildDouble(tri_data_, mesh_->vertices.data(), sizeof(Eigen::Vector3d),
                                static_cast<int>(mesh_->vertices.size()), mesh_index_.data(),
                                static_cast<int>(mesh_index_.size()), 3 * sizeof(int));
    // edge flags for the capsule collider, so it does not push a body
    // sideways off a triangle into its concave neighbour (the inside of a pipe)
    dGeomTriMeshDataPreprocess2(tri_data_, 1U << dTRIDATAPREPROCESS_BUILD_CONCAVE_EDGES, nullptr);
    const std::string& surface = cfg.type == EnvironmentType::Terrain ? cfg.terrain.surface
                                 : cfg.type == EnvironmentType::Pipe  ? cfg.pipe.surface
                                                                      : cfg.mesh.surface;
    dGeomID mesh = dCreateTriMesh(space, tri_data_, nullptr, nullptr, nullptr);
    add(mesh, surface);
    warm_up(mesh);
  }
  if (cfg.type == EnvironmentType::Terrain)
    for (const TerrainWall& w : terrain_walls(cfg.terrain)) {
      dGeomID g = dCreateBox(space, w.size_m.x(), w.size_m.y(), w.size_m.z());
      dGeomSetPosition(g, w.centre_m.x(), w.centre_m.y(), w.centre_m.z());
      add(g, cfg.terrain.wall_surface);
    }
  if (pipe_ && cfg.pipe.collider == PipeCollider::Analytic)
    for (int k = 0; k < static_cast<int>(pipe_->pieces.size()); ++k)
      add(pipe_geom_create(space, pipe_.get(), k), cfg.pipe.surface);
}

// ODE's trimesh colliders (OPCODE) keep per-thread lists of the triangles a
// body overlaps and grow them when a collision needs more: collide a large
// probe of every shape once here, so that steps do not allocate later (when
// the World is stepped in the thread that built it)
void EnvironmentGeoms::warm_up(dGeomID mesh) {
  const Eigen::Vector3d lo = mesh_->min_corner(), hi = mesh_->max_corner();
  const double size = std::max(0.05, 0.25 * (hi - lo).norm());
  dGeomID probes[4] = {dCreateSphere(nullptr, size), dCreateCapsule(nullptr, size / 2, size),
                       dCreateCylinder(nullptr, size / 2, size), dCreateBox(nullptr, size, size, size)};
  dContactGeom contacts[64];
  for (dGeomID probe : probes) {
    for (const auto& v : {mesh_->vertices.front(), mesh_->vertices[mesh_->vertices.size() / 2],
                          mesh_->vertices.back()}) {
      dGeomSetPosition(probe, v.x(), v.y(), v.z());
      dCollide(probe, mesh, 64, contacts, sizeof(dContactGeom));
    }
    dGeomDestroy(probe);
  }
}

EnvironmentGeoms::~EnvironmentGeoms() {
  if (tri_data_) dGeomTriMeshDataDestroy(tri_data_);
}

void EnvironmentGeoms::add(dGeomID g, const std::string& surface) {
  const auto it = std::find(surfaces_.begin(), surfaces_.end(), surface);
  const int index = static_cast<int>(it - surfaces_.begin());
  if (it == surfaces_.end()) surfaces_.push_back(surface);
  dGeomSetData(g, reinterpret_cast<void*>(surface_tag(index)));
  geoms_.push_back(g);
}

}  // namespace chainsim
