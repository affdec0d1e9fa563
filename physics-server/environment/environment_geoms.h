// The environment as static ODE geoms (no bodies): a plane, terrain and mesh
// triangles (dTriMesh), terrain walls (boxes), analytic pipe pieces
// (pipe_geom.h). Each geom's user data is its surface tag (surface_tag()), a
// negative number, so the World tells environment geoms (<= 0) from module
// bodies (> 0, 1 + body index) and finds each contact's material.
#pragma once

#include <ode/ode.h>

#include <memory>
#include <string>
#include <vector>

#include "environment/environment.h"
#include "environment/mesh_loader.h"
#include "environment/pipe_path.h"

namespace chainsim {

class EnvironmentGeoms {
 public:
  // Creates the geoms in space. Loads and lays out everything before it
  // creates the first geom, so a bad mesh file or pipe throws with nothing
  // to clean up. ODE must be initialised.
  EnvironmentGeoms(const EnvironmentConfig& cfg, dSpaceID space);
  // frees the triangle data: destroy the space (and with it the geoms) first
  ~EnvironmentGeoms();
  EnvironmentGeoms(const EnvironmentGeoms&) = delete;
  EnvironmentGeoms& operator=(const EnvironmentGeoms&) = delete;

  // surface names, index = surface_index(tag)
  const std::vector<std::string>& surfaces() const { return surfaces_; }
  static intptr_t surface_tag(int surface_index) { return -(surface_index + 1); }
  static int surface_index(intptr_t tag) { return static_cast<int>(-tag - 1); }
  // the pipe's layout (pipe environments), else nullptr
  const PipeLayout* pipe_layout() const { return pipe_.get(); }
  const std::vector<dGeomID>& geoms() const { return geoms_; }

 private:
  void add(dGeomID g, const std::string& surface);
  void warm_up(dGeomID mesh);

  std::vector<std::string> surfaces_;
  std::vector<dGeomID> geoms_;
  std::unique_ptr<PipeLayout> pipe_;
  std::shared_ptr<const TriMesh> mesh_;   // referenced by ODE's triangle data
  std::vector<int> mesh_index_;          // mesh_->triangles as ODE wants them (int)
  dTriMeshDataID tri_data_ = nullptr;
};

}  // namespace chainsim
