// Triangle meshes of a pipe layout (pipe_path.h): the bore alone (what the
// mesh collider uses: triangles facing the axis) or a solid tube with a wall
// (what a CAD export looks like; the example meshes in scenes/meshes).
#pragma once

#include "environment/mesh_loader.h"
#include "environment/pipe_path.h"

namespace chainsim {

// the inner wall, `around` vertices per ring, triangles facing the axis.
// Rings: straight pieces every 4 (tees: 1) circumferential edge lengths,
// elbows every circumferential edge length on the outside of the bend. Tee
// openings: triangles whose centre is inside the other pipe's bore are left
// out (a jagged opening, one edge length).
TriMesh pipe_bore_mesh(const PipeLayout& layout, int around);

// the bore plus an outer wall wall_m thick and flat rings closing the open
// ends; layouts without tees only (throws std::invalid_argument)
TriMesh pipe_solid_mesh(const PipeLayout& layout, int around, double wall_m);

}  // namespace chainsim
