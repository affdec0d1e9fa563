// The geometry of a pipe network: its segments (environment.h) laid out end
// to end into pieces (straight cylinders and torus sections) in the world
// frame, and point queries against their bore, shared by the analytic
// collider (pipe_geom.h), the mesh tessellation (pipe_mesh.h) and the tests.
//
// Layout: a frame (point, tangent t, up n) starts at the entry: t from the
// pipe's heading and slope, n the unit vector perpendicular to t in the
// vertical plane through t, towards +z (for a vertical pipe: away from the
// heading). Left is n x t. A straight moves the point along t; an elbow bends
// towards cos(direction) n + sin(direction) left and turns the frame with it;
// a tee puts a run along t and a branch towards direction from the middle of
// the run, and continues along one of them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <stdexcept>
#include <vector>

#include "environment/environment.h"

namespace chainsim {

struct PipeFrame {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // on the axis, m
  Eigen::Vector3d tangent = Eigen::Vector3d::UnitX();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     // perpendicular to tangent
};

struct PipePiece {
  enum class Kind { Straight, Elbow };
  Kind kind = Kind::Straight;
  double radius_m = 0;         // inner radius
  int segment = -1;            // the PipeSpec segment it comes from
  PipeFrame start;             // frame at the start of the piece's axis
  // Straight: axis start.point + s start.tangent, 0 <= s <= length_m
  double length_m = 0;
  // Elbow: axis centre + bend_radius (cos a u + sin a v), 0 <= a <= angle_rad;
  // normal = u x v is the bend plane's normal
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double bend_radius_m = 0, angle_rad = 0;
  // pieces whose bore opens a hole in this piece's wall (the two pieces of a tee)
  int holes[2] = {-1, -1};
};

class PipeLayoutError : public std::invalid_argument {
 public:
  PipeLayoutError(int segment, const std::string& what)
      : std::invalid_argument(what), segment_(segment) {}
  int segment() const { return segment_; }  // -1: the pipe as a whole
 private:
  int segment_;
};

struct PipeLayout {
  double radius_m = 0;
  std::vector<PipePiece> pieces;
  PipeFrame entry;                   // tangent points into the pipe
  PipeFrame exit;                    // where the last segment ends, tangent pointing out
  double entry_straight_m = 0;       // straight axis from the entry (0 if it starts with a bend)
  std::vector<PipeFrame> open_ends;  // entry (tangent reversed), stubs and exit; tangents point out
};

// throws PipeLayoutError naming the segment
PipeLayout layout_pipe(const PipeSpec& spec);

// pipe_piece_depth's and pipe_depth's answer where no piece owns the point
inline constexpr double kNotOwned = -std::numeric_limits<double>::infinity();

// Depth of a sphere (centre p, radius r) into piece k's wall: distance of p
// from the piece's axis + r - inner radius; > 0 = penetrating. dir_out: unit
// vector from the axis towards p (the outward wall normal there). Returns
// kNotOwned (-infinity) where the piece does not own p: p beyond the piece's ends (open
// there or another piece's), farther than 2 inner radii from the axis, or
// the wall point lies in a hole. With a piece that opens a hole in this one:
// a sphere wholly inside its bore touches no wall (its negative depth
// there), and a sphere in both walls (the wedge between a split's outlets)
// belongs to the piece it is less deep into (kNotOwned here if that is
// the other).
double pipe_piece_depth(const PipeLayout& layout, int k, const Eigen::Vector3d& p, double r,
                        Eigen::Vector3d* dir_out);

// no point within rho_m of c can have a positive pipe_piece_depth (with r
// = 0) for piece p: the ball lies wholly inside the bore, wholly beyond one
// of the piece's ends, or wholly farther than 2 inner radii from its axis.
// Exact (distance from the axis changes by at most the distance moved), so
// a collider may skip such a ball without losing a contact.
bool pipe_piece_ball_clear(const PipePiece& p, const Eigen::Vector3d& c, double rho_m);

// the largest pipe_piece_depth over the pieces; kNotOwned if none owns p
double pipe_depth(const PipeLayout& layout, const Eigen::Vector3d& p, double r);

// x is strictly inside piece k's bore (by margin_m), within its ends
bool pipe_piece_bore_contains(const PipePiece& piece, const Eigen::Vector3d& x, double margin_m);

// axis point and frame of piece k at fraction f (0..1) along its axis
PipeFrame pipe_piece_frame(const PipePiece& piece, double f);

// length of piece k's axis, m
double pipe_piece_axis_length(const PipePiece& piece);

// The angle of a point about elbow e's centre, from u towards v, in
// [-1e-12, 2 pi - 1e-12); qp: the point from the centre, in the bend's plane.
double elbow_angle(const PipePiece& e, const Eigen::Vector3d& qp);
// elbow_angle(e, qp) > e.angle_rad + 1e-12 (the point lies past the elbow's
// end), the same answer without atan2 wherever atan2's rounding cannot
// change it: away from the ends of angles 0, 90 and 180 degrees (the wall
// probes of wheels in an elbow spent a third of their time in atan2).
bool elbow_past_end(const PipePiece& e, const Eigen::Vector3d& qp);

}  // namespace chainsim
