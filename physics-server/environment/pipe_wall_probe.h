// Where the environment's wall is along a ray from inside it: what a spring
// arm pressing a wheel (or a pad) outwards meets. Used by the wheel contacts
// (physics/wheels/wheel_contacts.h) every physics step, for every wheel.
//
//  * Analytic pipes: exactly, from the bore (pipe_path.h). The wall is where
//    the ray leaves the union of the pieces' bores: the first t at which
//    min over the pieces that own the point (pipe_piece_depth) of
//    (distance from the piece's axis - inner radius) reaches 0. A straight
//    piece is solved in closed form (a quadratic); a torus piece, or a ray
//    crossing into another piece, by regula falsi (Illinois) on that
//    function, bracketed by the ray's two ends, to 1e-7 m. A point no piece
//    owns (past an open end) is free space: a wheel beyond the pipe's exit
//    touches nothing. Tee openings are free space too (pipe_piece_depth).
//  * Every other environment geom (plane, terrain or mesh triangles, terrain
//    walls, mesh pipes): an ODE ray (dCreateRay, closest hit, no back-face
//    culling) collided with each geom; the nearest hit wins.
// Both kinds are tried and the nearer wall is returned. No allocation.
#pragma once

#include <ode/ode.h>

#include <Eigen/Core>

#include <vector>

#include "environment/pipe_path.h"

namespace chainsim {

struct WallHit {
  double t = 0;                                     // distance along the ray, m
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // on the wall, world frame
  // unit normal of the wall at the point, pointing away from the wall into
  // the free space (for a pipe: towards its axis)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  bool pipe = false;   // the wall is the analytic pipe's (else an ODE geom's)
};

class WallProbe {
 public:
  // layout: the analytic pipe (nullptr if none; it must outlive the probe);
  // geoms: the environment's geoms; those of the analytic pipe class are
  // skipped (the layout answers for them). ODE must be initialised.
  WallProbe(const PipeLayout* layout, const std::vector<dGeomID>& geoms);
  ~WallProbe();
  WallProbe(const WallProbe&) = delete;
  WallProbe& operator=(const WallProbe&) = delete;

  // The nearest wall along origin + t dir (dir unit), 0 < t <= max_t. false:
  // none within max_t, or the origin is not inside the free space of the
  // pipe. *piece_hint: the pipe piece the last hit was on (-1: unknown);
  // pieces near it are tried first and it is updated.
  bool cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_t,
            int* piece_hint, WallHit* hit) const;

  // there is an analytic pipe
  bool has_pipe() const { return layout_ && !layout_->pieces.empty(); }

  // A point x against the analytic pipe's wall: the gap (min over the
  // pieces that own x of its distance from their axis - the inner radius;
  // > 0: x is in the wall, < 0: in the bore), and in *hit the wall point
  // nearest to x (t = the gap, the normal into the free space, pipe = true).
  // -infinity (hit untouched) where no piece owns x (past an open end, or
  // no analytic pipe). *piece_hint as for cast.
  double pipe_wall_gap(const Eigen::Vector3d& x, int* piece_hint, WallHit* hit) const;

  // the analytic part alone (tests): false if no layout or no wall within max_t
  bool cast_pipe(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_t,
                 int* piece_hint, WallHit* hit) const;

 private:
  // min over owning pieces of (distance from axis - radius), -inf if none
  // owns x; *piece = the piece giving it, *out = its outward direction
  double bore_gap(const Eigen::Vector3d& x, int lo, int hi, int* piece,
                  Eigen::Vector3d* out) const;
  // bore_gap over the pieces near `hint` (every piece for a short pipe or no
  // hint), and over every piece if none of those owns x; *lo, *hi: the range
  // it ended with
  double bore_gap_near(const Eigen::Vector3d& x, int hint, int* lo, int* hi, int* piece,
                       Eigen::Vector3d* out) const;

  const PipeLayout* layout_;
  std::vector<dGeomID> others_;   // environment geoms answered by ODE rays
  dGeomID ray_ = nullptr;
};

}  // namespace chainsim
