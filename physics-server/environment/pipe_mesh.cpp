// Pipe tessellation. See pipe_mesh.h.
#include "environment/pipe_mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "model/units.h"

namespace chainsim {
namespace {

int ring_count(const PipePiece& p, int around) {
  const double edge = 2 * kPi * p.radius_m / around;
  if (p.kind == PipePiece::Kind::Elbow)
    return std::max(2, static_cast<int>(std::ceil(p.angle_rad * (p.bend_radius_m + p.radius_m) / edge)));
  const bool tee = p.holes[0] >= 0 || p.holes[1] >= 0;
  return std::max(1, static_cast<int>(std::ceil(p.length_m / ((tee ? 1 : 4) * edge))));
}

Eigen::Vector3d ring_point(const PipeFrame& f, double radius, int j, int around) {
  const double a = 2 * kPi * j / around;
  const Eigen::Vector3d left = f.up.cross(f.tangent);
  return f.point + radius * (std::cos(a) * f.up + std::sin(a) * left);
}

// a tube of rings along piece p at radius; inward = triangles face the axis
TriMesh tube(const PipePiece& p, double radius, int around, bool inward) {
  TriMesh m;
  const int n = ring_count(p, around);
  for (int i = 0; i <= n; ++i) {
    const PipeFrame f = pipe_piece_frame(p, static_cast<double>(i) / n);
    for (int j = 0; j < around; ++j) m.vertices.push_back(ring_point(f, radius, j, around));
  }
  auto at = [&](int i, int j) { return static_cast<uint32_t>(i * around + (j % around)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < around; ++j) {
      const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
      // (a, b, c) faces outwards: (b - a) is along the axis, (c - b) around it
      if (inward) {
        m.triangles.push_back({a, c, b});
        m.triangles.push_back({a, d, c});
      } else {
        m.triangles.push_back({a, b, c});
        m.triangles.push_back({a, c, d});
      }
    }
  return m;
}

}  // namespace

TriMesh pipe_bore_mesh(const PipeLayout& layout, int around) {
  if (around < 3) throw std::invalid_argument("a pipe mesh needs at least 3 vertices around");
  TriMesh out;
  for (const PipePiece& p : layout.pieces) {
    TriMesh t = tube(p, p.radius_m, around, true);
    if (p.holes[0] >= 0 || p.holes[1] >= 0) {
      std::vector<std::array<uint32_t, 3>> kept;
      for (const auto& tri : t.triangles) {
        const Eigen::Vector3d c = (t.vertices[tri[0]] + t.vertices[tri[1]] + t.vertices[tri[2]]) / 3;
        bool open = false;
        for (int h : p.holes)
          if (h >= 0 && pipe_piece_bore_contains(layout.pieces[h], c, 0.0)) open = true;
        if (!open) kept.push_back(tri);
      }
      t.triangles = std::move(kept);
    }
    out.append(t);
  }
  return out;
}

TriMesh pipe_solid_mesh(const PipeLayout& layout, int around, double wall_m) {
  for (const PipePiece& p : layout.pieces)
    if (p.holes[0] >= 0 || p.holes[1] >= 0)
      throw std::invalid_argument("pipe_solid_mesh: tees are not supported");
  TriMesh out = pipe_bore_mesh(layout, around);
  for (const PipePiece& p : layout.pieces) out.append(tube(p, p.radius_m + wall_m, around, false));
  // flat rings at the entry and the exit, facing out of the pipe
  for (int e = 0; e < 2; ++e) {
    const bool at_entry = e == 0;
    const PipeFrame& end = at_entry ? layout.entry : layout.exit;
    TriMesh ring;
    for (int j = 0; j < around; ++j) {
      ring.vertices.push_back(ring_point(end, layout.radius_m, j, around));
      ring.vertices.push_back(ring_point(end, layout.radius_m + wall_m, j, around));
    }
    for (int j = 0; j < around; ++j) {
      const uint32_t a = 2 * j, b = 2 * j + 1, c = 2 * ((j + 1) % around) + 1,
                     d = 2 * ((j + 1) % around);
      // (a, b, c) faces against the tangent: out of the pipe at the entry
      if (!at_entry) {
        ring.triangles.push_back({a, c, b});
        ring.triangles.push_back({a, d, c});
      } else {
        ring.triangles.push_back({a, b, c});
        ring.triangles.push_back({a, c, d});
      }
    }
    out.append(ring);
  }
  return out;
}

}  // namespace chainsim
